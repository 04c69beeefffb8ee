"""The FMU (crates/fmu): flapwing's wing set as an FMI 2.0 co-simulation FMU, built with
crates/fmu/build.sh from the C ABI's staticlib, validated and simulated by fmpy.

Reference numbers: `reference` (crates/fmu/reference.c, built by the same script) steps the
C ABI exactly as fmi2DoStep does, without FMI, and prints hex floats; the FMU's outputs must
equal them bit for bit (same library, same inputs, same arithmetic: nothing may differ).
flapwing's own tethered run (`flapwing simulate --tethered --json`) gives the cycle means:
the body-frame mean is the same sums in the same order as flapsim's SummaryBuilder, so it is
compared exactly too; the mean vertical force turns each step's force into the world with
numpy instead of nalgebra (a few ulp per step), so it is compared to 1e-9 relative.

Skipped (with the reason) only when gcc or the staticlib is missing: FLAPWING_STATICLIB, else
${CARGO_TARGET_DIR:-target}/release/libflapwing.a (`cargo build --release -p flapwing-ffi`).
"""

import json
import math
import os
import pathlib
import shutil
import subprocess
import sys

import fmpy
import numpy as np
import pytest
from fmpy.fmi1 import FMICallException
from fmpy.validation import validate_fmu

ROOT = pathlib.Path(__file__).resolve().parents[2]
FORCE = [f"force_body_n_{a}" for a in "xyz"]
MOMENT = [f"moment_body_nm_{a}" for a in "xyz"]
TETHERED_S = 0.1  # the CLI run: 21 complete wingbeats of the fruit fly's 218 Hz


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    if shutil.which(os.environ.get("CC", "gcc")) is None:
        pytest.skip("no C compiler (gcc, or CC) to build the FMU")
    target = pathlib.Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
    lib = pathlib.Path(os.environ.get("FLAPWING_STATICLIB", target / "release" / "libflapwing.a"))
    if not lib.is_file():
        pytest.skip(f"no C ABI staticlib at {lib}: build it with `cargo build --release -p flapwing-ffi`")
    out = tmp_path_factory.mktemp("fmu")
    env = dict(os.environ, FLAPWING_STATICLIB=str(lib), PYTHON=sys.executable)
    proc = subprocess.run(["bash", str(ROOT / "crates" / "fmu" / "build.sh"), str(out)],
                          capture_output=True, text=True, env=env)
    assert proc.returncode == 0, f"build.sh failed:\n{proc.stdout}\n{proc.stderr}"
    return {"fmu": str(out / "flapwing_wings.fmu"), "reference": out / "reference"}


def reference(built, steps_per_comm, n_comm, model="drosophila", dt_s=0.0, attitude=()):
    """The C ABI's mean wrench per communication step (rows of force xyz, moment xyz), the
    body at rest at `attitude` (w, x, y, z; default the model's initial attitude)."""
    proc = subprocess.run([str(built["reference"]), model, repr(dt_s), str(steps_per_comm), str(n_comm),
                           *map(repr, attitude)],
                          capture_output=True, text=True, check=True)
    lines = proc.stdout.splitlines()
    val = lambda s: float.fromhex(s)  # noqa: E731
    return {
        "dt_s": val(lines[0].split()[1]),
        "attitude": [val(s) for s in lines[1].split()[1:]],
        "weight_n": val(lines[2].split()[1]),
        "wrench": np.array([[val(s) for s in line.split()] for line in lines[3:]]),
    }


def tethered_start(ref, **extra):
    """Start values: the body at rest at the model's initial attitude (as `--tethered`)."""
    w, x, y, z = ref["attitude"]
    return {"world_from_body_w": w, "world_from_body_x": x, "world_from_body_y": y,
            "world_from_body_z": z, **extra}


def simulate(built, ref, steps_per_comm, n_comm, **kw):
    h = steps_per_comm * ref["dt_s"]
    return fmpy.simulate_fmu(built["fmu"], start_time=0.0, stop_time=n_comm * h, output_interval=h,
                             start_values=kw.pop("start_values", tethered_start(ref)),
                             output=FORCE + MOMENT + ["element_steps"] + kw.pop("output", []), **kw)


def wrench(result):
    """Outputs after each doStep (row 0 is the time-0 sample, before any step)."""
    return np.column_stack([result[n] for n in FORCE + MOMENT])[1:]


def test_fmpy_finds_no_problem(built):
    assert validate_fmu(built["fmu"]) == []
    md = fmpy.read_model_description(built["fmu"])
    assert md.fmiVersion == "2.0" and md.coSimulation.modelIdentifier == "flapwing_wings"
    # The default experiment steps the default model by its element step, 218 times.
    dt_s = reference(built, 1, 1)["dt_s"]
    assert float(md.defaultExperiment.stepSize) == dt_s
    result = fmpy.simulate_fmu(built["fmu"])  # fmpy's defaults: the default experiment
    assert list(result["element_steps"]) == list(range(219))


@pytest.mark.parametrize("steps_per_comm, n_comm", [(1, 250), (7, 40)])
def test_outputs_equal_the_c_abi_bit_for_bit(built, steps_per_comm, n_comm):
    ref = reference(built, steps_per_comm, n_comm)
    result = simulate(built, ref, steps_per_comm, n_comm)
    out = wrench(result)
    assert out.shape == ref["wrench"].shape
    # Bit for bit: the same library stepped from the same inputs in the same order.
    assert np.array_equal(out.view(np.uint64), ref["wrench"].view(np.uint64)), (
        f"first difference at row {np.argwhere(out != ref['wrench'])[0]}")
    assert list(result["element_steps"][1:]) == [steps_per_comm * (k + 1) for k in range(n_comm)]
    assert np.abs(out[:, 2]).max() > 1e-6  # the fly's wings do load the body (N)


@pytest.mark.parametrize("model, dt_s", [
    ("robobee", 0.0),          # actuated: the wings' stroke and pitch dynamics in the FMU
    ("drosophila", 1.0e-5),    # a host's step that does not divide the wingbeat
    # every other built-in vehicle at its own step: the stops of the hummingbird, the four
    # twisted wings of the dragonfly
    ("bumblebee", 0.0),
    ("robobee_kinematic", 0.0),
    ("dragonfly", 0.0),
    ("hummingbird", 0.0),
])
def test_other_models_and_steps_equal_the_c_abi_bit_for_bit(built, model, dt_s):
    ref = reference(built, 3, 60, model=model, dt_s=dt_s)
    assert dt_s == 0.0 or ref["dt_s"] == dt_s
    result = simulate(built, ref, 3, 60, start_values=tethered_start(ref, model=model, dt_s=dt_s))
    assert np.array_equal(wrench(result).view(np.uint64), ref["wrench"].view(np.uint64))


def test_cycle_means_equal_flapwings_tethered_run(built, run_flapwing, tmp_path):
    cli = json.loads(run_flapwing("simulate", "--model", "drosophila", "--tethered", "--json",
                                  "--duration-s", TETHERED_S, "--no-log", cwd=tmp_path).stdout)
    per_cycle = cli["steps_per_wingbeat"]
    cycles = cli["summary"]["wingbeats_averaged"]
    ref = reference(built, 1, 1)
    assert ref["dt_s"] == cli["dt_s"]
    out = wrench(simulate(built, ref, 1, cycles * per_cycle))

    # flapsim's SummaryBuilder: each wingbeat's sum from 0.0 in step order, weighted by
    # 1/steps and added up, then divided by the number of wingbeats.
    total = [0.0] * 6
    for c in range(cycles):
        s = [0.0] * 6
        for row in out[c * per_cycle:(c + 1) * per_cycle]:
            s = [a + float(b) for a, b in zip(s, row)]
        total = [t + (1.0 / per_cycle) * a for t, a in zip(total, s)]
    mean = [t / cycles for t in total]
    want = cli["summary"]["mean_total"]
    assert mean[:3] == want["force_n"] and mean[3:] == want["moment_nm"]

    # Mean vertical (world z) force: the body force turned by world_from_body.
    w, x, y, z = ref["attitude"]
    row_z = np.array([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)])
    vertical = (out[:, :3] @ row_z).reshape(cycles, per_cycle).mean(axis=1).mean()
    want_vertical = cli["summary"]["mean_lift_over_weight"] * cli["weight_n"]
    assert math.isclose(vertical, want_vertical, rel_tol=1e-9), (vertical, want_vertical)


def test_a_model_file_flies_like_its_built_in(built):
    ref = reference(built, 1, 100)
    result = simulate(built, ref, 1, 100, start_values=tethered_start(
        ref, model=str(ROOT / "models" / "drosophila.toml")))
    assert np.array_equal(wrench(result), ref["wrench"])


def test_the_amplitude_control_moves_the_lift(built):
    ref = reference(built, 1, 200)
    more = wrench(simulate(built, ref, 1, 200,
                           start_values=tethered_start(ref, control_amplitude_rad=0.1)))
    # A larger stroke amplitude lifts more: the mean body-z force over the two wingbeats grows.
    assert more[:, 2].mean() > 1.05 * ref["wrench"][:, 2].mean()


class Log:
    """An fmpy logger that keeps (status, message) pairs."""

    def __init__(self):
        self.messages = []

    def __call__(self, component, instance, status, category, message):
        self.messages.append((status, message.decode()))


def test_a_bad_model_name_is_an_fmi_error_with_the_c_abis_message(built):
    ref = reference(built, 1, 1)
    log = Log()
    with pytest.raises(FMICallException) as e:
        simulate(built, ref, 1, 10, start_values={"model": "no_such_fly"}, logger=log)
    assert e.value.function == "fmi2ExitInitializationMode" and e.value.status == 3  # fmi2Error
    errors = [m for s, m in log.messages if s == 3]
    assert errors and 'no built-in model named "no_such_fly"' in errors[0], log.messages
    assert "drosophila" in errors[0]  # names what is allowed


def test_a_nan_body_state_discards_the_step_and_ends_the_run(built):
    ref = reference(built, 1, 1)
    log = Log()
    result = simulate(built, ref, 1, 10, logger=log,
                      start_values=tethered_start(ref, velocity_world_m_s_z=float("nan")))
    # fmi2Discard, then fmi2Terminated: fmpy stops at the last good time, t = 0, no step taken.
    assert result["time"][-1] == 0.0 and result["element_steps"][-1] == 0
    assert [result[n][-1] for n in FORCE + MOMENT] == [0.0] * 6  # outputs before any step
    discards = [m for s, m in log.messages if s == 2]
    # The C ABI's message, passed on: which field, its value, what is allowed.
    assert discards and "velocity_world_m_s[2] = NaN" in discards[0], log.messages
    assert "allowed: finite numbers" in discards[0]


def test_a_step_that_is_no_whole_number_of_element_steps_is_an_error(built):
    ref = reference(built, 1, 1)
    log = Log()
    h = 1.5 * ref["dt_s"]
    with pytest.raises(FMICallException) as e:
        fmpy.simulate_fmu(built["fmu"], stop_time=4 * h, output_interval=h, logger=log)
    assert e.value.function == "fmi2DoStep" and e.value.status == 3
    assert any("not a whole number of element steps" in m for _, m in log.messages), log.messages


def test_a_c_host_runs_good_and_bad_instances_cleanly(built, tmp_path):
    """crates/fmu/tests/c_host.c loads the FMU's .so with dlopen, as a C master would: a good
    run (with an FMU state taken, set back and freed), a bad model and a NaN input in turn,
    each freed; under valgrind when the machine has it (no invalid access, no definite leak)."""
    fmi2 = pathlib.Path(fmpy.__file__).parent / "c-code"
    host = tmp_path / "c_host"
    subprocess.run([os.environ.get("CC", "gcc"), "-std=c11", "-Wall", "-Wextra", "-Werror",
                    f"-I{fmi2}", str(ROOT / "crates" / "fmu" / "tests" / "c_host.c"), "-o",
                    str(host), "-ldl"], check=True)
    so = pathlib.Path(built["fmu"]).parent / "fmu" / "binaries" / "linux64" / "flapwing_wings.so"
    guid = fmpy.read_model_description(built["fmu"]).guid
    valgrind = shutil.which("valgrind")
    wrap = [valgrind, "-q", "--leak-check=full", "--errors-for-leak-kinds=definite",
            "--error-exitcode=9"] if valgrind else []
    proc = subprocess.run([*wrap, str(host), str(so), guid], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    lines = proc.stdout.splitlines()
    good = [line for line in lines if line.startswith("run 0 steps")][0].split()
    assert good[3:6] == ["50", "status", "0"]  # fz printed with %.17g: exact
    assert float(good[-1]) == reference(built, 2, 50, attitude=(1.0, 0.0, 0.0, 0.0))["wrench"][-1, 2]
    # An FMU state taken halfway and set back repeats the second half: the same last force.
    assert "run 0 get 0" in lines and "run 0 set 0" in lines
    assert f"run 0 again status 0 fz {good[-1]}" in lines, lines
    assert "run 0 null get 3 set 3" in lines and "run 0 free 0 null" in lines
    assert "run 1 init 3" in lines and any('no built-in model named "no_such_fly"' in x for x in lines)
    assert "run 2 steps 0 status 2 fz 0" in lines
    assert any("velocity_world_m_s[2] = NaN" in x for x in lines)


TRIM = [f"trim_world_from_body_{a}" for a in "wxyz"] + [f"trim_velocity_world_m_s_{a}" for a in "xyz"]


@pytest.mark.parametrize("model, freq_hz, speed_m_s, climb_m_s, tol", [
    ("drosophila", 218.0, 0.0, 0.0, 1e-9), ("drosophila", 218.0, 1.0, 0.0, 1e-9),
    ("drosophila", 218.0, 0.0, 0.3, 1e-9), ("bumblebee", 155.0, 3.0, 0.0, 1e-9)])
def test_trimmed_wings_carry_the_weight_at_the_flight_condition(built, model, freq_hz, speed_m_s,
                                                                climb_m_s, tol):
    # With `trim`, the FMU trims the fruit fly at the condition (flapsim::flight: the
    # cycle-averaged wing loads balance the weight; the fly has no body drag) and reports the
    # attitude and velocity to hold. Held there, with zero control offsets, the wings' force
    # over each wingbeat, turned into the world, is the weight straight up and their moment
    # about the CoM zero. The FMU steps 200 element steps a wingbeat (not the model's 20), and
    # the trim balances the cycle mean of the host's own steps where they divide the wingbeat
    # (flapsim::trim::at_host_step), so the two are the same sums: within 1e-9 of the weight,
    # and of the weight times the body length (2.5 mm) for the moment (measured 2e-12; a trim
    # of other steps differs from the stepped wingbeat by the discretisation: 1.4e-5 of the
    # weight at hover and 5.6e-4 at 1 m/s between 100 and 200 steps a wingbeat).
    # The bumblebee at 3 m/s has a body drag (drag_area_m2), which its trim balances and the
    # FMU's force applies (docs/plugin.md, "Body drag"): the output is the weight straight up
    # there too (issue #40: it was pushed forward by 12% of its weight before).
    ref = reference(built, 1, 1, model=model)
    per = 200  # element steps a wingbeat: the steps the trim balances
    dt_s = 1.0 / (freq_hz * per)  # the model's wingbeat frequency (models/*.toml)
    ref = {**ref, "dt_s": dt_s}
    params = {"trim": True, "trim_forward_speed_m_s": speed_m_s, "trim_climb_rate_m_s": climb_m_s,
              "dt_s": dt_s, "model": model}
    first = simulate(built, ref, 1, 1, start_values=params, output=TRIM)
    trim = {n: first[n][0] for n in TRIM}
    assert all(math.isfinite(v) for v in trim.values()), trim
    assert trim["trim_velocity_world_m_s_x"] == pytest.approx(speed_m_s, abs=1e-12)
    assert trim["trim_velocity_world_m_s_z"] == pytest.approx(climb_m_s, abs=1e-12)
    held = {n.replace("trim_", ""): v for n, v in trim.items()}
    result = simulate(built, ref, per, 3, start_values={**params, **held})
    q = [held[f"world_from_body_{a}"] for a in "wxyz"]
    w, x, y, z = q
    world_from_body = np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
    ])
    weight = ref["weight_n"]
    rows = wrench(result)
    assert len(rows) >= 2
    for row in rows:
        force_world = world_from_body @ row[:3]
        assert np.allclose(force_world, [0.0, 0.0, weight], rtol=0, atol=tol * weight), force_world
        assert np.allclose(row[3:], 0.0, rtol=0, atol=tol * weight * 2.5e-3), row[3:]


def test_without_trim_the_trim_parameters_are_nan_and_a_bad_condition_is_an_fmi_error(built):
    ref = reference(built, 1, 1)
    plain = simulate(built, ref, 1, 1, output=TRIM)
    assert all(math.isnan(plain[n][0]) for n in TRIM)
    log = Log()
    with pytest.raises(FMICallException) as e:
        simulate(built, ref, 1, 1, logger=log,
                 start_values={"trim": True, "trim_climb_rate_m_s": -5.0})
    assert e.value.status == 3  # fmi2Error
    errors = [m for s, m in log.messages if s == 3]
    assert errors and "trim at 0 m/s forward, -5 m/s climb" in errors[0], log.messages


@pytest.mark.parametrize("model", ["drosophila", "hummingbird"])
def test_a_state_set_back_repeats_the_steps_that_followed_it(built, model):
    """fmi2GetFMUstate / fmi2SetFMUstate (canGetAndSetFMUstate): a master that steps back (a
    rejected step, a finite-difference linearisation, rollouts) gets the FMU as it was, wings
    included, and the steps that follow repeat bit for bit; also into an existing state (the
    wings saved into its copy), and after fmi2Reset rebuilt the wings (a copy of the state's
    replaces them). The hummingbird's wings strike their stops: their hinge states come back."""
    import ctypes

    from fmpy.fmi2 import FMU2Slave

    md = fmpy.read_model_description(built["fmu"])
    assert md.coSimulation.canGetAndSetFMUstate and not md.coSimulation.canSerializeFMUstate
    vr = {v.name: v.valueReference for v in md.modelVariables}
    slave = FMU2Slave(guid=md.guid, unzipDirectory=fmpy.extract(built["fmu"]),
                      modelIdentifier=md.coSimulation.modelIdentifier, instanceName="back")
    slave.instantiate()

    def start():
        slave.setupExperiment(startTime=0.0)
        slave.enterInitializationMode()
        slave.setString([vr["model"]], [model])
        slave.exitInitializationMode()
        return slave.getReal([vr["element_dt_s"]])[0]

    dt = start()
    out = [vr[n] for n in FORCE + MOMENT + ["element_steps"]]

    def run(k0, n):
        rows = []
        for k in range(k0, k0 + n):
            # The body moves: every state the wings keep (the step memory too) is exercised.
            slave.setReal([vr["velocity_world_m_s_x"], vr["angular_velocity_body_rad_s_y"]],
                          [0.1 * math.sin(0.1 * k), 2.0 * math.cos(0.07 * k)])
            slave.doStep(k * dt, dt)  # raises on an FMI error
            rows.append(slave.getReal(out))
        return np.array(rows)

    first_n = 230 if model == "hummingbird" else 30
    run(0, first_n)
    state = slave.getFMUstate()
    after = run(first_n, 200)
    slave.setFMUstate(state)
    assert np.array_equal(run(first_n, 200).view(np.uint64), after.view(np.uint64))
    # Into the existing state, then back to it after a branch with other inputs.
    state2 = slave.getFMUstate()
    run(first_n + 200, 3)
    slave.fmi2GetFMUstate(slave.component, ctypes.byref(state2))  # into the existing state
    branch_end = run(first_n + 203, 40)
    slave.setReal([vr["velocity_world_m_s_z"]], [0.3])
    run(first_n + 243, 17)
    slave.setFMUstate(state2)
    slave.setReal([vr["velocity_world_m_s_z"]], [0.0])
    assert np.array_equal(run(first_n + 203, 40).view(np.uint64), branch_end.view(np.uint64))
    # After a reset the wings are rebuilt (another build): the state's copy replaces them.
    slave.reset()
    start()
    slave.setFMUstate(state)
    assert np.array_equal(run(first_n, 200).view(np.uint64), after.view(np.uint64))
    slave.freeFMUstate(state)
    slave.freeFMUstate(state2)
    slave.terminate()
    slave.freeInstance()


def test_the_inflow_outputs_are_the_wing_sets_inflow_states(built, tmp_path):
    """Issue #38: the dynamic inflow states are states of the system in every host. The
    FMU's inflow outputs after each communication step are those of flapwing's WingSet after
    the same element steps (the body held, the same step), bit for bit; a model whose wake does
    not answer, and a pair the model does not have, output 0."""
    import flapwing

    text = (ROOT / "models/drosophila.toml").read_text().replace('inflow = "frozen"',
                                                                 'inflow = "dynamic"')
    path = tmp_path / "drosophila_dynamic.toml"
    path.write_text(text)
    ref = reference(built, 1, 1)
    inflow = [f"inflow_pair{p}_{k}_m_s" for p in (0, 1) for k in ("mean", "fore", "left")]
    result = simulate(built, ref, 1, 40, start_values=tethered_start(ref, model=str(path)),
                      output=inflow)
    wings = flapwing.WingSet(str(path), dt_s=ref["dt_s"])
    w, x, y, z = ref["attitude"]
    for k in range(40):
        wings.step([0.0, 0.0, 0.0], [w, x, y, z], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0])
        got = [result[n][k + 1] for n in inflow]
        assert got[:3] == list(wings.inflow_states[0]) and got[3:] == [0.0] * 3, k
    assert result["inflow_pair0_mean_m_s"][-1] > 0  # the air comes down through the disc
    frozen = simulate(built, ref, 1, 5, output=inflow)
    assert all((frozen[n] == 0).all() for n in inflow)
