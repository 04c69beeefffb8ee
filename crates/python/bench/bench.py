"""Speed benchmarks of the Python package (the README's speed rows), interleaving A and B
in one run (this VM's speed drifts by up to 2x from minute to minute):

1. Python overhead: N free-flight steps of the trimmed fruit fly through one
   `Simulation.run(N, record=False)` call, against the same N steps in Rust
   (`cargo run --release -p flapsim --example step_timing`, timed in-process): the ratio of
   each pair, median and quartiles over the rounds.
2. `flapwing/Hover-v0` with a per-wingbeat action (a zero offset from the trim, through
   `env.step`): simulated wingbeats per wall-second, one core.

Run from the repository root: `python3 crates/python/bench/bench.py` (after
`pip install ./crates/python`; set CARGO_TARGET_DIR as for the build).
"""

import os
import subprocess
import time

import numpy as np

import flapwing
import flapwing.envs  # noqa: F401
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


def hover_wingbeats_per_s(env, wingbeats: int = 2000) -> float:
    env.reset(seed=0)
    a = np.zeros(4)
    n = 0
    t = time.perf_counter()
    while n < wingbeats:
        _, _, term, trunc, _ = env.step(a)
        n += 1
        if term or trunc:
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
    env = gym.make("flapwing/Hover-v0")
    rates = [hover_wingbeats_per_s(env) for _ in range(5)]
    q = np.percentile(rates, [25, 50, 75])
    print(f"Hover-v0, per-wingbeat action: median {q[1]:.0f} wingbeats/s "
          f"[quartiles {q[0]:.0f} {q[2]:.0f}]")


if __name__ == "__main__":
    main()
