"""Speed benchmarks of the Python package (the speed rows of docs/speed.md), interleaving A and B
in one run (this VM's speed drifts by up to 2x from minute to minute):

1. Python overhead: N free-flight steps of the trimmed fruit fly through one
   `Simulation.run(N, record=False)` call, against the same N steps in Rust
   (`cargo run --release -p flapsim --example step_timing`, timed in-process): the ratio of
   each pair, median and quartiles over the rounds.
2. `flapwing/Hover-v0` with a per-wingbeat action (a zero offset from the trim, through
   `env.step`; resets included): simulated wingbeats per wall-second, one core, each round
   interleaved with the Rust free-flight run of 1 (alternating which goes first), whose
   wingbeat rate gives a per-round ratio that the machine's load cancels out of; and the
   episode length the zero action reaches.
3. `WingSet.step` (the force element for a Python host: the body's state in as lists, the
   loads out as a dict of numpy arrays) and the lean `WingSet.step_wrench` (one state array
   in, the wrench into a preallocated array) from Python: seconds per call over N calls fed
   the trimmed fly's hovering state, against the Rust run of 1 per step (a whole
   `Simulation` step: the element, rapier and the summary), the three interleaved; the
   ratio of each pair.

Run from the repository root: `python3 crates/python/bench/bench.py` (after
`pip install ./crates/python`; set CARGO_TARGET_DIR as for the build).
"""

import os
import subprocess
import time

import numpy as np

import flapwing  # registers the Gymnasium environments
import gymnasium as gym

STEPS = 21_800  # 1 s of simulated fruit-fly flight, 100 steps per wingbeat
ROUNDS = 15


def rust_seconds(exe: str) -> float:
    out = subprocess.run([exe, "drosophila", str(STEPS), "1"], check=True,
                         capture_output=True, text=True).stdout
    return float(out.split()[0])


def python_seconds(v) -> float:
    sim = flapwing.Simulation(v, "free")
    t = time.perf_counter()
    sim.run(STEPS, record=False)
    return time.perf_counter() - t


def wingset_step_seconds(v, n: int = STEPS) -> float:
    """Seconds per `WingSet.step` call from Python, the body held at the trim state."""
    wings = flapwing.WingSet(v)
    s = flapwing.Simulation(v, "free").state
    p, q = list(s["position_m"]), list(s["world_from_body_wxyz"])
    u, w = list(s["velocity_m_s"]), list(s["angular_velocity_body_rad_s"])
    t = time.perf_counter()
    for _ in range(n):
        wings.step(p, q, u, w)
    return (time.perf_counter() - t) / n


def wingset_step_wrench_seconds(v, n: int = STEPS) -> float:
    """Seconds per `WingSet.step_wrench` call (the lean step: one state array in, the wrench
    into a preallocated array), the body held at the trim state."""
    wings = flapwing.WingSet(v)
    s = flapwing.Simulation(v, "free").state
    x = np.concatenate([s["position_m"], s["world_from_body_wxyz"], s["velocity_m_s"],
                        s["angular_velocity_body_rad_s"]]).astype(np.float64)
    out = np.zeros(6)
    t = time.perf_counter()
    for _ in range(n):
        wings.step_wrench(x, out)
    return (time.perf_counter() - t) / n


def hover_wingbeats_per_s(env, wingbeats: int = 2000, lengths: list | None = None) -> float:
    env.reset(seed=0)
    a = np.zeros(4)
    n = ep = 0
    t = time.perf_counter()
    while n < wingbeats:
        _, _, term, trunc, _ = env.step(a)
        n += 1
        ep += 1
        if term or trunc:
            if lengths is not None:
                lengths.append(ep)
            ep = 0
            env.reset()
    return n / (time.perf_counter() - t)


def main() -> None:
    target = os.environ.get("CARGO_TARGET_DIR", "target")
    subprocess.run(["cargo", "build", "--release", "-q", "-p", "flapsim", "--example",
                    "step_timing"], check=True)
    exe = os.path.join(target, "release", "examples", "step_timing")
    v = flapwing.Vehicle("drosophila").trimmed()
    python_seconds(v), rust_seconds(exe)  # warm up
    ratios = []
    for _ in range(ROUNDS):
        a = rust_seconds(exe)
        b = python_seconds(v)
        ratios.append(b / a)
    q = np.percentile(ratios, [25, 50, 75])
    print(f"Python run(N) / Rust, {STEPS} steps: median {q[1]:.3f}x [quartiles {q[0]:.3f} {q[2]:.3f}]")
    per_call, per_lean, per_step = [], [], []
    for k in range(ROUNDS):
        # The three in a rotating order, so that the machine's drift falls on each alike.
        runs = [lambda: per_call.append(wingset_step_seconds(v)),
                lambda: per_lean.append(wingset_step_wrench_seconds(v)),
                lambda: per_step.append(rust_seconds(exe) / STEPS)]
        for i in range(3):
            runs[(k + i) % 3]()
    for name, calls in [("WingSet.step", per_call), ("WingSet.step_wrench", per_lean)]:
        q = np.percentile(np.array(calls) / np.array(per_step), [25, 50, 75])
        print(f"{name} from Python: median {1e6 * np.median(calls):.2f} us per call; "
              f"the Rust Simulation step {1e6 * np.median(per_step):.2f} us; ratio median "
              f"{q[1]:.2f}x [quartiles {q[0]:.2f} {q[2]:.2f}]")
    env = gym.make("flapwing/Hover-v0")
    hover_wingbeats_per_s(env, 200)  # warm up
    wingbeats = STEPS / 100  # the Rust run's wingbeats (100 steps per wingbeat)
    rates, rust, lengths = [], [], []
    for k in range(ROUNDS):
        if k % 2 == 0:
            r = wingbeats / rust_seconds(exe)
            h = hover_wingbeats_per_s(env, lengths=lengths)
        else:
            h = hover_wingbeats_per_s(env, lengths=lengths)
            r = wingbeats / rust_seconds(exe)
        rates.append(h)
        rust.append(r)
    q = np.percentile(rates, [25, 50, 75])
    print(f"Hover-v0, per-wingbeat action: median {q[1]:.0f} wingbeats/s "
          f"[quartiles {q[0]:.0f} {q[2]:.0f}]")
    q = np.percentile(rust, [25, 50, 75])
    print(f"  Rust free flight in the same rounds: median {q[1]:.0f} wingbeats/s "
          f"[quartiles {q[0]:.0f} {q[2]:.0f}]")
    q = np.percentile(np.array(rates) / np.array(rust), [25, 50, 75])
    print(f"  Hover-v0 / Rust per round: median {q[1]:.3f} [quartiles {q[0]:.3f} {q[2]:.3f}]; "
          f"zero-action episodes: median {np.median(lengths):.0f} wingbeats")


if __name__ == "__main__":
    main()
