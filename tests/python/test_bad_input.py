"""Bad input never kills or hangs the interpreter (issue 23).

A corpus of bad arguments across the whole API (Wing, Vehicle, HoverController, Simulation,
HoverTask, VecHoverTask and the Gymnasium environments), run in child Python processes with a
timeout. A case fails on a crash (the child dies: SIGABRT, SIGSEGV, ...), a hang (the timeout)
or a silent acceptance: it must raise the expected exception type with a message that names the
argument. A child runs a batch of cases one after another, each in a fresh namespace, and
reports each case as it finishes; a child that dies or hangs is charged to the case it was
running, and the rest of its batch goes on in a new child (so every case is still seen to end
in its own exception, and the corpus costs a few interpreter starts instead of one per case).
Long calls must stop on Ctrl-C: those cases start the call in a process, send SIGINT once it
runs and expect KeyboardInterrupt within a generous liveness bound. The batches run in
parallel (a thread pool of subprocesses). The harness is tests/python/badinput_harness.py.
"""

from __future__ import annotations

import signal
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor

import pytest

from badinput_harness import (PRELUDE, TIMEOUT_S, WORKERS, C, Case,
                              assert_raises_a_named_error, run_cases)

INTERRUPT_BOUND_S = 20  # liveness bound after SIGINT, not a timing assertion


SIM = "s = Simulation()"
TASK = "t = HoverTask()"
VEC = "v = VecHoverTask(2)"
ENV = "from flapwing.envs import FlapwingEnv, VecHoverEnv"

CASES = [
    # --- Wing: sizes (allocation before the check used to abort the process) ---
    C("wing-cycle-1e10", "Wing().evaluate_cycle(10**10)", "ValueError", "samples", "2982616"),
    C("wing-cycle-2**64", "Wing().evaluate_cycle(2**64)", "ValueError", "samples"),
    C("wing-cycle-0", "Wing().evaluate_cycle(0)", "ValueError", "samples"),
    C("wing-cycle-neg", "Wing().evaluate_cycle(-1)", "ValueError", "samples"),
    C("wing-cycle-float", "Wing().evaluate_cycle(1.5)", "TypeError", "samples"),
    C("wing-cycle-str", "Wing().evaluate_cycle('10')", "TypeError", "samples"),
    C("wing-cycle-bool", "Wing().evaluate_cycle(True)", "TypeError", "samples"),
    C("wing-cycle-npneg", "Wing().evaluate_cycle(np.int64(-3))", "ValueError", "samples"),
    C("wing-many-1e8", "Wing().evaluate_many(np.zeros(10**8))", "ValueError", "phases", "1073741824"),
    C("wing-many-broadcast-1e9", "Wing().evaluate_many(np.broadcast_to(0.0, (10**9,)))",
      "ValueError", "phases"),
    C("wing-many-2d", "Wing().evaluate_many([[0.1, 0.2]])", "ValueError", "phases"),
    C("wing-many-nan", "Wing().evaluate_many([0.1, float('nan')])", "ValueError", "phases"),
    C("wing-many-inf", "Wing().evaluate_many(np.array([0.1, np.inf]))", "ValueError", "phases"),
    C("wing-many-complex", "Wing().evaluate_many(np.array([0.1j]))", "TypeError", "phases"),
    C("wing-many-complex-list", "Wing().evaluate_many([0.1, 1j])", "TypeError", "phases"),
    C("wing-many-str", "Wing().evaluate_many(['a'])", "TypeError", "phases"),
    C("wing-many-ragged", "Wing().evaluate_many([0.1, [0.2, 0.3]])", "ValueError", "phases"),
    C("wing-many-none", "Wing().evaluate_many(None)", "TypeError", "phases"),
    C("wing-many-bool", "Wing().evaluate_many(np.array([True]))", "TypeError", "phases"),
    C("wing-many-datetime", "Wing().evaluate_many(np.array([np.datetime64('2020')]))",
      "TypeError", "phases"),
    C("wing-many-object", "Wing().evaluate_many([object()])", "TypeError", "phases"),
    C("wing-many-overflow", "Wing().evaluate_many([0.1, 0.2], velocity_m_s=[1e200, 0, 0])",
      "ValueError", "velocity_m_s"),
    C("wing-cycle-overflow", "Wing().evaluate_cycle(10, angular_velocity_rad_s=[0, 1e200, 0])",
      "ValueError", "angular_velocity_rad_s"),
    # --- Wing.evaluate: values ---
    C("wing-eval-v1e200", "Wing().evaluate(0.1, velocity_m_s=[1e200, 0, 0])", "ValueError",
      "velocity_m_s"),
    C("wing-eval-w1e200", "Wing().evaluate(0.1, angular_velocity_rad_s=[1e200, 0, 0])",
      "ValueError", "angular_velocity_rad_s"),
    C("wing-eval-nan", "Wing().evaluate(float('nan'))", "ValueError", "phase"),
    C("wing-eval-inf", "Wing().evaluate(float('-inf'))", "ValueError", "phase"),
    C("wing-eval-complex", "Wing().evaluate(1j)", "TypeError", "phase"),
    C("wing-eval-npcomplex", "Wing().evaluate(np.complex128(0.1 + 1j))", "TypeError", "phase"),
    C("wing-eval-str", "Wing().evaluate('0.1')", "TypeError", "phase"),
    C("wing-eval-array", "Wing().evaluate(np.zeros(2))", "ValueError", "phase"),
    C("wing-eval-v-len2", "Wing().evaluate(0.1, velocity_m_s=[1, 2])", "ValueError",
      "velocity_m_s"),
    C("wing-eval-v-complex", "Wing().evaluate(0.1, velocity_m_s=[1j, 0, 0])", "TypeError",
      "velocity_m_s"),
    C("wing-eval-v-nan", "Wing().evaluate(0.1, velocity_m_s=[np.nan, 0, 0])", "ValueError",
      "velocity_m_s"),
    C("wing-eval-v-2d", "Wing().evaluate(0.1, velocity_m_s=np.zeros((3, 1)))", "ValueError",
      "velocity_m_s"),
    C("wing-eval-v-str", "Wing().evaluate(0.1, velocity_m_s='abc')", "TypeError",
      "velocity_m_s"),
    C("wing-eval-w-scalar", "Wing().evaluate(0.1, angular_velocity_rad_s=1.0)", "ValueError",
      "angular_velocity_rad_s"),
    C("wing-side", "Wing(side='middle')", "ValueError", "side"),
    C("wing-model", "Wing('no_such_model')", "ValueError", "no_such_model"),
    C("wing-model-int", "Wing(model=3)", "TypeError", "model"),
    # --- Vehicle ---
    C("vehicle-model", "Vehicle('no_such_model')", "ValueError", "no_such_model"),
    C("vehicle-model-none-type", "Vehicle(model=1.5)", "TypeError", "model"),
    C("lqr-neg-weight", "Vehicle().lqr(position_body_lengths=-1.0)", "ValueError",
      "position_body_lengths"),
    C("lqr-zero-weight", "Vehicle().lqr(attitude_rad=0.0)", "ValueError", "attitude_rad"),
    C("lqr-nan-weight", "Vehicle().lqr(control_rad=float('nan'))", "ValueError", "control_rad"),
    C("lqr-inf-weight", "Vehicle().lqr(integral_time_s=float('inf'))", "ValueError",
      "integral_time_s"),
    C("lqr-tiny-weight", "Vehicle().lqr(control_rad=1e-200)", "ValueError", "control_rad"),
    C("lqr-complex-weight", "Vehicle().lqr(control_rad=1j)", "TypeError", "control_rad"),
    C("lqr-str-weight", "Vehicle().lqr(attitude_rad='x')", "TypeError", "attitude_rad"),
    C("lqr-unknown-weight", "Vehicle().lqr(no_such_weight=1.0)", "ValueError", "no_such_weight"),
    C("lqr-neg-delay", "Vehicle().lqr(delay_wingbeats=-1)", "ValueError", "delay_wingbeats"),
    C("lqr-float-delay", "Vehicle().lqr(delay_wingbeats=1.5)", "TypeError", "delay_wingbeats"),
    C("lqr-huge-delay", "Vehicle().lqr(delay_wingbeats=2**70)", "ValueError", "delay_wingbeats"),
    C("controls-unknown", "Vehicle().with_controls(no_such=1.0)", "ValueError", "no_such"),
    C("controls-nan", "Vehicle().with_controls(amplitude_rad=float('nan'))", "ValueError",
      "amplitude_rad"),
    C("controls-complex", "Vehicle().with_controls(amplitude_rad=1j)", "TypeError",
      "amplitude_rad"),
    C("controls-npcomplex", "Vehicle().with_controls(amplitude_rad=np.complex128(1j))",
      "TypeError", "amplitude_rad"),
    C("controls-str", "Vehicle().with_controls(amplitude_rad='x')", "TypeError",
      "amplitude_rad"),
    C("controls-array", "Vehicle().with_controls(amplitude_rad=[0.1, 0.2])", "ValueError",
      "amplitude_rad"),
    C("init-state-len", "Vehicle().with_initial_state({'position_m': [1, 2]})", "ValueError",
      "position_m"),
    C("init-state-key", "Vehicle().with_initial_state({'no_such': [0, 0, 0]})", "ValueError",
      "no_such"),
    C("init-state-zero-quat",
      "Vehicle().with_initial_state({'world_from_body_wxyz': [0, 0, 0, 0]})", "ValueError",
      "world_from_body_wxyz"),
    C("init-state-huge-quat",
      "Vehicle().with_initial_state({'world_from_body_wxyz': [1e200] * 4})", "ValueError",
      "world_from_body_wxyz"),
    C("init-state-complex", "Vehicle().with_initial_state({'velocity_m_s': [1j, 0, 0]})",
      "TypeError", "velocity_m_s"),
    C("init-state-nan", "Vehicle().with_initial_state({'position_m': np.array([np.nan, 0, 0])})",
      "ValueError", "position_m"),
    C("init-state-not-dict", "Vehicle().with_initial_state([1, 2, 3])", "TypeError", "state"),
    C("stability-floquet-str", "Vehicle().stability(floquet='yes')", "TypeError", "floquet"),
    C("controller-update-len", "c.update({'position_m': [0, 0]})", "ValueError", "position_m",
      setup="c = Vehicle().lqr()"),
    C("controller-error-state-complex", "c.error_state({'velocity_m_s': np.zeros(3, complex)})",
      "TypeError", "velocity_m_s", setup="c = Vehicle().lqr()"),
    # --- Simulation: sizes, counts ---
    C("sim-run-1e9", "s.run(10**9)", "ValueError", "steps", "record=False", setup=SIM),
    C("sim-run-neg", "s.run(-1)", "ValueError", "steps", setup=SIM),
    C("sim-run-2**64", "s.run(2**64)", "ValueError", "steps", setup=SIM),
    C("sim-run-float", "s.run(1.5)", "TypeError", "steps", setup=SIM),
    C("sim-run-str", "s.run('10')", "TypeError", "steps", setup=SIM),
    C("sim-run-none", "s.run(None)", "TypeError", "steps", setup=SIM),
    C("sim-run-npneg", "s.run(np.int64(-5), record=False)", "ValueError", "steps", setup=SIM),
    C("sim-wingbeats-wrap", "s.run_wingbeats(2**64 // s.steps_per_wingbeat + 1)", "ValueError",
      "wingbeats", setup=SIM),
    C("sim-wingbeats-wrap-norecord", "s.run_wingbeats(2**64 // s.steps_per_wingbeat + 1, record=False)",
      "ValueError", "wingbeats", setup=SIM),
    C("sim-wingbeats-1e7", "s.run_wingbeats(10**7)", "ValueError", "wingbeats", setup=SIM),
    C("sim-wingbeats-neg", "s.run_wingbeats(-1)", "ValueError", "wingbeats", setup=SIM),
    C("sim-wingbeats-float", "s.run_wingbeats(2.0)", "TypeError", "wingbeats", setup=SIM),
    # --- Simulation: construction ---
    C("sim-mcap-exists", "Simulation(mcap=p)", "FileExistsError", "mcap", "force=True",
      setup="import tempfile; p = tempfile.mkstemp(suffix='.mcap')[1]"),
    C("sim-mcap-dir", "Simulation(mcap=d)", "ValueError", "mcap",
      setup="import tempfile; d = tempfile.mkdtemp()"),
    C("sim-log-rate-zero", "Simulation(log_rate_hz=0)", "ValueError", "log_rate_hz"),
    C("sim-log-rate-neg", "Simulation(log_rate_hz=-5.0)", "ValueError", "log_rate_hz"),
    C("sim-log-rate-nan", "Simulation(log_rate_hz=float('nan'))", "ValueError", "log_rate_hz"),
    C("sim-log-rate-complex", "Simulation(log_rate_hz=1j)", "TypeError", "log_rate_hz"),
    C("sim-force-positional", "Simulation('drosophila', 'free', None, None, True)", "TypeError",
      "positional"),
    C("sim-mode", "Simulation(mode='flying')", "ValueError", "mode"),
    C("sim-vehicle-int", "Simulation(vehicle=3)", "ValueError", "vehicle"),
    C("sim-vehicle-name", "Simulation(vehicle='no_such_model')", "ValueError", "no_such_model"),
    # --- Simulation: controls, wind, state ---
    C("sim-channels-len", "s.set_control_channels([1, 2, 3])", "ValueError", "values", setup=SIM),
    C("sim-channels-2d", "s.set_control_channels([[1, 2], [3, 4]])", "ValueError", "values",
      setup=SIM),
    C("sim-channels-nan", "s.set_control_channels([np.nan, 0, 0, 0])", "ValueError", "values",
      setup=SIM),
    C("sim-channels-complex", "s.set_control_channels([1j, 0, 0, 0])", "TypeError", "values",
      setup=SIM),
    C("sim-channels-str", "s.set_control_channels('abcd')", "TypeError", "values", setup=SIM),
    C("sim-wind-len", "s.set_wind([1, 2])", "ValueError", "wind_world_m_s", setup=SIM),
    C("sim-wind-inf", "s.set_wind([np.inf, 0, 0])", "ValueError", "wind_world_m_s", setup=SIM),
    C("sim-wind-complex", "s.set_wind(np.array([1j, 0, 0]))", "TypeError", "wind_world_m_s",
      setup=SIM),
    C("sim-wind-str", "s.set_wind('xyz')", "TypeError", "wind_world_m_s", setup=SIM),
    C("sim-wind-none", "s.set_wind(None)", "TypeError", "wind_world_m_s", setup=SIM),
    C("sim-state-len", "s.set_state(position_m=[0, 0])", "ValueError", "position_m", setup=SIM),
    C("sim-state-key", "s.set_state(no_such=[0, 0, 0])", "ValueError", "no_such", setup=SIM),
    C("sim-state-zero-quat", "s.set_state(world_from_body_wxyz=[0, 0, 0, 0])", "ValueError",
      "world_from_body_wxyz", setup=SIM),
    C("sim-state-complex", "s.set_state(velocity_m_s=[1j, 0, 0])", "TypeError", "velocity_m_s",
      setup=SIM),
    C("sim-state-inf", "s.set_state(angular_velocity_body_rad_s=[0, np.inf, 0])", "ValueError",
      "angular_velocity_body_rad_s", setup=SIM),
    C("sim-state-huge-velocity", "s.set_state(velocity_m_s=[1e200, 0, 0]); s.run(5)",
      "DivergedError", "max_speed_m_s", setup=SIM),
    C("sim-huge-wind", "s.set_wind([1e200, 0, 0]); s.run(5)", "RuntimeError", "", setup=SIM),
    C("sim-controls-neg-freq", "s.set_controls(freq_hz=-1e300)", "RuntimeError", "frequency",
      setup=SIM),
    C("controls-huge-amplitude", "Vehicle().with_controls(amplitude_rad=1e300)", "RuntimeError",
      "amplitude"),
    C("trim-huge-freq", "Vehicle().with_controls(freq_hz=1e300).trim()", "AnalysisError",
      "frequency"),
    C("sim-controls-unknown", "s.set_controls(no_such=1.0)", "ValueError", "no_such", setup=SIM),
    C("sim-controls-nan", "s.set_controls(amplitude_rad=np.nan)", "ValueError", "amplitude_rad",
      setup=SIM),
    C("sim-controls-str", "s.set_controls(amplitude_rad='x')", "TypeError", "amplitude_rad",
      setup=SIM),
    C("sim-controls-complex", "s.set_controls(freq_hz=1j)", "TypeError", "freq_hz", setup=SIM),
    # --- HoverTask ---
    C("task-aw-2**62", "HoverTask(action_wingbeats=2**62)", "ValueError", "action_wingbeats"),
    C("task-aw-1e7", "HoverTask(action_wingbeats=10**7)", "ValueError", "action_wingbeats",
      "1000000"),
    C("task-aw-0", "HoverTask(action_wingbeats=0)", "ValueError", "action_wingbeats"),
    C("task-aw-neg", "HoverTask(action_wingbeats=-1)", "ValueError", "action_wingbeats"),
    C("task-aw-float", "HoverTask(action_wingbeats=1.5)", "TypeError", "action_wingbeats"),
    C("task-aw-str", "HoverTask(action_wingbeats='2')", "TypeError", "action_wingbeats"),
    C("task-duration-neg", "HoverTask(duration_s=-1.0)", "ValueError", "duration_s"),
    C("task-duration-nan", "HoverTask(duration_s=float('nan'))", "ValueError", "duration_s"),
    C("task-duration-complex", "HoverTask(duration_s=1j)", "TypeError", "duration_s"),
    C("task-disturbance-neg", "HoverTask('drosophila', 'recover', disturbance_deg=-5.0)",
      "ValueError", "disturbance_deg"),
    C("task-unknown-field", "HoverTask(no_such=1.0)", "ValueError", "no_such"),
    C("task-kind", "HoverTask(task='fly')", "ValueError", "task"),
    C("task-model", "HoverTask(model='no_such_model')", "ValueError", "no_such_model"),
    C("task-randomize-missing", "HoverTask(randomize='/no/such/file.toml')", "OSError",
      "randomize"),
    C("task-reset-neg", "t.reset(-1)", "ValueError", "seed", setup=TASK),
    C("task-reset-2**64", "t.reset(2**64)", "ValueError", "seed", setup=TASK),
    C("task-reset-float", "t.reset(1.5)", "TypeError", "seed", setup=TASK),
    C("task-step-len3", "t.step([0, 0, 0])", "ValueError", "action", setup=TASK),
    C("task-step-2x2", "t.step([[0, 0], [0, 0]])", "ValueError", "action", setup=TASK),
    C("task-step-complex-list", "t.step([1j, 0, 0, 0])", "TypeError", "action", setup=TASK),
    C("task-step-complex-array", "t.step(np.zeros(4, dtype=complex))", "TypeError", "action",
      setup=TASK),
    C("task-step-nan", "t.step([np.nan, 0, 0, 0])", "ValueError", "action", setup=TASK),
    C("task-step-huge", "t.step([1e9, 0, 0, 0])", "ValueError", "action[0]", setup=TASK),
    C("task-step-str", "t.step('abcd')", "TypeError", "action", setup=TASK),
    C("task-step-none", "t.step(None)", "TypeError", "action", setup=TASK),
    # --- VecHoverTask ---
    C("vec-num-1e5", "VecHoverTask(10**5)", "ValueError", "num", "4096"),
    C("vec-num-0", "VecHoverTask(0)", "ValueError", "num"),
    C("vec-num-neg", "VecHoverTask(-1)", "ValueError", "num"),
    C("vec-num-float", "VecHoverTask(2.5)", "TypeError", "num"),
    C("vec-aw-2**62", "VecHoverTask(2, action_wingbeats=2**62)", "ValueError", "action_wingbeats"),
    C("vec-step-4x2", "v.step(np.zeros((4, 2)))", "ValueError", "actions", "(2, 4)", setup=VEC),
    C("vec-step-flat8", "v.step(np.zeros(8))", "ValueError", "actions", setup=VEC),
    C("vec-step-1x4", "v.step(np.zeros((1, 4)))", "ValueError", "actions", setup=VEC),
    C("vec-step-2x4x1", "v.step(np.zeros((2, 4, 1)))", "ValueError", "actions", setup=VEC),
    C("vec-step-complex", "v.step(np.zeros((2, 4), dtype=complex))", "TypeError", "actions",
      setup=VEC),
    C("vec-step-nan", "v.step(np.full((2, 4), np.nan))", "ValueError", "actions", setup=VEC),
    C("vec-step-huge", "v.step([[0, 0, 0, 0], [1e9, 0, 0, 0]])", "ValueError", "actions[1, 0]",
      setup=VEC),
    C("vec-step-str", "v.step('ab')", "TypeError", "actions", setup=VEC),
    C("vec-resets-len", "v.step(np.zeros((2, 4)), reset_seeds=[None])", "ValueError",
      "reset_seeds", setup=VEC),
    C("vec-resets-neg", "v.step(np.zeros((2, 4)), reset_seeds=[-1, None])", "ValueError",
      "reset_seeds[0]", setup=VEC),
    C("vec-resets-str", "v.step(np.zeros((2, 4)), reset_seeds='ab')", "TypeError",
      "reset_seeds", setup=VEC),
    C("vec-resets-float", "v.step(np.zeros((2, 4)), reset_seeds=[None, 0.5])", "TypeError",
      "reset_seeds[1]", setup=VEC),
    C("vec-reset-len", "v.reset([1])", "ValueError", "seeds", setup=VEC),
    C("vec-reset-neg", "v.reset([-1, 2])", "ValueError", "seeds[0]", setup=VEC),
    C("vec-reset-float", "v.reset([1.5, 2])", "TypeError", "seeds[0]", setup=VEC),
    C("vec-reset-int", "v.reset(5)", "TypeError", "seeds", setup=VEC),
    C("vec-reset-none-item", "v.reset([None, 1])", "TypeError", "seeds[0]", setup=VEC),
    C("vec-reset-one-index", "v.reset_one(5, 0)", "ValueError", "`i`", setup=VEC),
    C("vec-reset-one-neg", "v.reset_one(-1, 0)", "ValueError", "`i`", setup=VEC),
    C("vec-reset-one-seed", "v.reset_one(0, -1)", "ValueError", "seed", setup=VEC),
    C("vec-draws-index", "v.draws(2)", "ValueError", "`i`", setup=VEC),
    C("vec-draws-neg", "v.draws(-1)", "ValueError", "`i`", setup=VEC),
    # --- Gymnasium environments ---
    C("env-vec-1e5", "VecHoverEnv(10**5)", "ValueError", "num", setup=ENV),
    C("env-vec-4x2", "e.step(np.zeros((4, 2)))", "ValueError", "actions",
      setup=ENV + "; e = VecHoverEnv(2); e.reset(seed=1)"),
    C("env-vec-flat8", "e.step(np.zeros(8))", "ValueError", "actions",
      setup=ENV + "; e = VecHoverEnv(2); e.reset(seed=1)"),
    C("env-vec-complex", "e.step(np.zeros((2, 4), dtype=complex))", "TypeError", "actions",
      setup=ENV + "; e = VecHoverEnv(2); e.reset(seed=1)"),
    C("env-2x2", "e.step(np.zeros((2, 2)))", "ValueError", "action",
      setup=ENV + "; e = FlapwingEnv(); e.reset(seed=1)"),
    C("env-complex", "e.step(np.zeros(4, dtype=complex))", "TypeError", "action",
      setup=ENV + "; e = FlapwingEnv(); e.reset(seed=1)"),
    C("env-list-complex", "e.step([0, 0, 0, 1j])", "TypeError", "action",
      setup=ENV + "; e = FlapwingEnv(); e.reset(seed=1)"),
    C("env-aw-2**62", "FlapwingEnv(action_wingbeats=2**62)", "ValueError", "action_wingbeats",
      setup=ENV),
    C("env-recover-aw-neg", "FlapwingEnv('recover', action_wingbeats=-3)", "ValueError",
      "action_wingbeats", setup=ENV),
]

# pyo3 names these (a str, bool or dict parameter given another type) in a note only.
NAMED_IN_A_NOTE = {"wing-model-int", "vehicle-model-none-type", "init-state-not-dict",
                   "stability-floquet-str"}

@pytest.fixture(scope="module")
def results() -> dict:
    return run_cases(CASES)


def test_the_corpus_is_large_and_unique():
    assert len(CASES) >= 100
    assert len({c.id for c in CASES}) == len(CASES)


@pytest.mark.parametrize("case", CASES, ids=[c.id for c in CASES])
def test_bad_input_raises_a_named_error(case: Case, results: dict):
    # No exception notes before 3.11.
    names_checked = case.id not in NAMED_IN_A_NOTE or sys.version_info >= (3, 11)
    assert_raises_a_named_error(case, results[case.id], names_checked)


# --- Ctrl-C: long calls stop with KeyboardInterrupt ---

INTERRUPTS = {
    "sim-run-record-false": ("s = Simulation()", "s.run(10**9, record=False)"),
    "sim-run-wingbeats": ("s = Simulation()", "s.run_wingbeats(10**8, record=False)"),
    # Recorded: room for 1e6 steps is reserved (360 MB, touched only as the run goes).
    "sim-run-recorded": ("s = Simulation()", "s.run(1_000_000)"),
    "task-step-long-action": ("t = HoverTask(action_wingbeats=10**6); t.reset(1)",
                              "t.step(np.zeros(4))"),
    "vec-step-long-action": ("v = VecHoverTask(2, action_wingbeats=10**6); v.reset([1, 2])",
                             "v.step(np.zeros((2, 4)))"),
    "env-step-long-action": (
        "from flapwing.envs import FlapwingEnv; e = FlapwingEnv(action_wingbeats=10**6); "
        "e.reset(seed=1)", "e.step(np.zeros(4))"),
    "vec-build-4096": ("", "VecHoverTask(4096)"),
    # ~3 s of phases on a fast machine; interrupted after ~1 s, little memory touched.
    "wing-evaluate-cycle": ("w = Wing()", "w.evaluate_cycle(2_900_000)"),
    "wing-evaluate-many": ("w = Wing(); p = np.linspace(0, 1, 2_900_000)",
                           "w.evaluate_many(p, velocity_m_s=[0.1, 0, 0])"),
}

# The child handles SIGINT as an interpreter started from a terminal does (KeyboardInterrupt):
# started from a non-interactive shell's background job it would inherit SIGINT ignored, and
# Python then installs no handler at all.
INTERRUPT_SCRIPT = PRELUDE + """
import signal
signal.signal(signal.SIGINT, signal.default_int_handler)
exec(compile({setup!r}, "setup", "exec"))
print("started", flush=True)
try:
    exec(compile({call!r}, "call", "exec"))
except KeyboardInterrupt:
    print("KeyboardInterrupt", flush=True)
    sys.exit(42)
print("finished", flush=True)
"""


def _interrupt(item) -> dict:
    key, (setup, call) = item
    proc = subprocess.Popen([sys.executable, "-c", INTERRUPT_SCRIPT.format(setup=setup, call=call)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        line = proc.stdout.readline()  # setup done (or the process died)
        if line.strip() != "started":
            proc.kill()
            _, err = proc.communicate()
            return {"error": f"did not start: {line!r} {err[-2000:]}"}
        time.sleep(1.0)
        proc.send_signal(signal.SIGINT)
        t0 = time.monotonic()
        try:
            out, err = proc.communicate(timeout=INTERRUPT_BOUND_S)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.communicate()
            return {"error": f"still running {INTERRUPT_BOUND_S} s after SIGINT (ignores Ctrl-C)"}
        return {"returncode": proc.returncode, "stdout": out, "stderr": err[-2000:],
                "after_sigint_s": time.monotonic() - t0}
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.communicate()


@pytest.fixture(scope="module")
def interrupted() -> dict:
    with ThreadPoolExecutor(WORKERS) as pool:
        return dict(zip(INTERRUPTS, pool.map(_interrupt, INTERRUPTS.items())))


@pytest.mark.parametrize("key", list(INTERRUPTS))
def test_ctrl_c_stops_long_calls(key: str, interrupted: dict):
    r = interrupted[key]
    assert "error" not in r, f"{INTERRUPTS[key][1]}: {r['error']}"
    assert r["returncode"] == 42 and "KeyboardInterrupt" in r["stdout"], (
        f"{INTERRUPTS[key][1]}: exit {r['returncode']}, stdout {r['stdout']!r}, "
        f"stderr {r['stderr']}")


# --- What the stubs promise is accepted: array-likes of any real dtype, numpy integers ---

ACCEPTED = """
import tempfile
w = Wing()
for phases in ([0.1, 0.2], (0, 1), np.array([0, 1], dtype=np.int32),
               np.array([0.1, 0.2], dtype=np.float32), np.arange(6.0)[::2]):
    assert w.evaluate_many(phases)["total"]["force_n"].shape == (len(phases), 3)
assert w.evaluate(np.float32(0.1), velocity_m_s=[0, 0, 1])["total"]["force_n"].shape == (3,)
assert w.evaluate(1, velocity_m_s=np.array([0, 0, 1], dtype=np.int64))["t_star"] == w.evaluate(1.0)["t_star"]
assert len(w.evaluate_cycle(np.int64(10))["phase"]) == 10
s = Simulation()
s.set_wind([0, 0, 0])
s.set_wind(np.zeros(3, dtype=np.float32))
s.set_control_channels(list(s.controls[k] for k in []) or [0, 0, 0, 0]) if False else None
s.set_state(position_m=(0, 0, 0), velocity_m_s=np.zeros(3, dtype=np.int16))
assert s.run(np.int64(3))["t_s"].shape == (3,)
assert s.run(2, record=False) is None
assert s.run_wingbeats(np.uint8(1), record=False) is None
assert s.run(0)["t_s"].shape == (0,)
p = tempfile.mkstemp(suffix=".mcap")[1]
sim = Simulation(mcap=p, force=True)
sim.run(3, record=False)
assert sim.close_log()["steps_seen"] == 3
v = VecHoverTask(2)
v.reset(np.array([1, 2], dtype=np.uint64))
v.step([[0, 0, 0, 0], [0, 0, 0, 0]])
v.step(np.zeros((2, 4), dtype=np.float32), reset_seeds=[None, np.int64(7)])
t = HoverTask()
t.reset(np.uint64(2**63))
t.step([0, 0, 0, 0])
t.step(np.zeros(4, dtype=np.int8))
c = Vehicle().lqr(delay_wingbeats=np.int64(1), attitude_rad=np.float32(0.05))
c.update({"position_m": [0, 0, 0], "velocity_m_s": (0, 0, 0)})
print("ok")
"""


def test_array_likes_and_numpy_scalars_are_accepted():
    proc = subprocess.run([sys.executable, "-c", PRELUDE + ACCEPTED], capture_output=True,
                          text=True, timeout=TIMEOUT_S)
    assert proc.returncode == 0 and proc.stdout.strip().endswith("ok"), proc.stderr[-3000:]
