"""flapwing's MuJoCo engine plugin `flapwing.wings` (crates/mujoco), built in a session fixture
with crates/mujoco/build.sh against the `mujoco` package from PyPI, flying the fruit fly of
examples/mujoco/fly.xml (examples/python/mujoco_plugin.py drives it); plus the Python-callback
fallback of that example (xfrc_applied), kept for control changes in flight.

Tolerances and where they come from:
- Tethered loads: the plugin hands flapwing the same body state (at rest at the initial pose)
  at the same step and phase as flapwing's tethered host, so the wrench is the same to
  round-off; what is checked is the wrench MuJoCo actually applied (qfrc_passive, rotated back
  to the body frame), cycle means to 1e-9 of the force's magnitude (the issue's bound).
- Open-loop free flight, Euler: both hosts take semi-implicit Euler steps with the exponential
  map for the attitude, so they differ by round-off, grown by the unstable free flight; measured
  2.6e-8 of the largest excursion over 0.1 s; checked against 1e-6 (the round-off floor the
  callback test below has used since it was written).
- RK4: a different scheme. With the loads held over the step, semi-implicit Euler moves the
  body by dt v + dt^2 a per step where the exact motion under constant a is dt v + dt^2 a / 2,
  so the positions part by at most sum dt^2/2 |a_k| = T dt/2 max|a| (first order; a from the
  reference's force and gravity). Measured: 1.7e-6 m against a bound of about 1e-5 m.
- Roll (diff_amplitude_deg = 2): the gyroscopic term, which the two engines integrate
  differently (rapier implicitly, MuJoCo explicitly), enters; the bound of the callback test
  (integrator_bound, derived there) applies.
"""

import importlib.util
import json
import math
import pathlib
import subprocess

import numpy as np
import pytest

import flapwing

mujoco = pytest.importorskip("mujoco", reason="the `mujoco` package (pip install mujoco) is not installed")

ROOT = pathlib.Path(__file__).resolve().parents[2]
spec = importlib.util.spec_from_file_location(
    "mujoco_plugin", ROOT / "examples" / "python" / "mujoco_plugin.py")
plugin = importlib.util.module_from_spec(spec)
spec.loader.exec_module(plugin)

STEPS = 2180  # 0.1 s at flapwing's drosophila step (flapwing simulate's default duration)
N = 100  # steps per wingbeat of examples/mujoco/fly.xml's timestep (the model states 20)


@pytest.fixture(scope="session")
def fly100(tmp_path_factory):
    """The fly stepped at fly.xml's 100 steps per wingbeat (its model file's default is the
    20 that hold its stated accuracy), so that flapwing's side steps what the plugin steps."""
    text = (ROOT / "models/drosophila.toml").read_text()
    assert "\nsteps_per_wingbeat = 20 " in text
    path = tmp_path_factory.mktemp("models") / "drosophila_100.toml"
    path.write_text(text.replace("\nsteps_per_wingbeat = 20 ", "\nsteps_per_wingbeat = 100 "))
    return str(path)


@pytest.fixture(scope="session")
def bee100(tmp_path_factory):
    """The bumblebee at 100 steps per wingbeat (its model file's default is 20), for the same
    reason as `fly100`."""
    text = (ROOT / "models/bumblebee.toml").read_text()
    assert "\nsteps_per_wingbeat = 20 " in text
    path = tmp_path_factory.mktemp("models") / "bumblebee_100.toml"
    path.write_text(text.replace("\nsteps_per_wingbeat = 20 ", "\nsteps_per_wingbeat = 100 "))
    return str(path)


@pytest.fixture(scope="session")
def step_start_fly(tmp_path_factory):
    """The fly with its loads taken at each step's start (`[sim] load_sampling`): MuJoCo's
    Euler and flapwing's rapier host then integrate the same loads the same way, to round-off.
    With the default midpoint sampling flapwing's own host moves rapier's pose to the
    trapezoidal rule and MuJoCo's Euler keeps its first-order pose (wingset::sampling), a
    difference of O(dt) by design; the plugin's wrench under the midpoint sampling is checked
    step by step in the tethered tests above this section."""
    text = (ROOT / "models/drosophila.toml").read_text()
    assert "\nsteps_per_wingbeat = 20 " in text
    path = tmp_path_factory.mktemp("models") / "drosophila_step_start.toml"
    path.write_text(text.replace("\nsteps_per_wingbeat = 20 ",
                                 '\nload_sampling = "step_start"\nsteps_per_wingbeat = 100 '))
    return str(path)


@pytest.fixture(scope="session")
def native():
    """Builds and loads libflapwing_mujoco.so (once per session)."""
    return plugin.build_plugin()


# ------------------------------------------------------------------ tethered cycle means

def tethered_mujoco(steps):
    """fly.xml held at its initial pose (gravity off, qpos/qvel restored after every step):
    the wrench MuJoCo applied in each step, body frame, from qfrc_passive (free joint: world
    force on dofs 0-2, body-frame moment on dofs 3-5; the CoM is the body origin)."""
    m = mujoco.MjModel.from_xml_path(str(plugin.FLY_XML))
    m.opt.gravity[:] = 0
    d = mujoco.MjData(m)
    qpos0 = d.qpos.copy()
    r = np.empty(9)
    f, mo = np.empty((steps, 3)), np.empty((steps, 3))
    for k in range(steps):
        mujoco.mj_step(m, d)
        mujoco.mju_quat2Mat(r, qpos0[3:7])
        f[k] = r.reshape(3, 3).T @ d.qfrc_passive[:3]
        mo[k] = d.qfrc_passive[3:6]
        d.qpos[:], d.qvel[:] = qpos0, 0
    return f, mo


def test_tethered_wrench_per_step_and_cycle_mean_equal_flapwing(native, fly100):
    import flapwing

    sim = flapwing.Simulation(flapwing.Vehicle(fly100), "tethered")
    ref = sim.run(N)
    f, mo = tethered_mujoco(N)
    fm_ref, fm = ref["force_n"].mean(axis=0), f.mean(axis=0)
    assert np.linalg.norm(fm - fm_ref) <= 1e-9 * np.linalg.norm(fm_ref), (fm, fm_ref)
    # The cycle-mean moment is zero by symmetry (round-off); scale: the mean |moment| per step.
    scale = np.linalg.norm(ref["moment_nm"], axis=1).mean()
    assert np.linalg.norm(mo.mean(axis=0) - ref["moment_nm"].mean(axis=0)) <= 1e-9 * scale
    # Each step's wrench, to 1e-12 of the wingbeat's largest (round-off of the rotation).
    assert np.abs(f - ref["force_n"]).max() <= 1e-12 * np.abs(ref["force_n"]).max()
    assert np.abs(mo - ref["moment_nm"]).max() <= 1e-12 * np.abs(ref["moment_nm"]).max()


def _with_model_body(xml, name):
    """fly.xml's body given the built-in model's mass and inertia, stepped at its own step."""
    import re

    v = flapwing.Vehicle(name)
    dt_s = flapwing.WingSet(v).dt_s
    inertia = np.diag(v.inertia_kg_m2) if np.ndim(v.inertia_kg_m2) == 2 else v.inertia_kg_m2
    xml = re.sub(r'timestep="[^"]*"', f'timestep="{dt_s!r}"', xml)
    return xml.replace('mass="1e-6" diaginertia="8.1e-14 3.53e-13 3.53e-13"',
                       f'mass="{v.mass_kg!r}" diaginertia="{" ".join(repr(float(i)) for i in inertia)}"')


@pytest.mark.parametrize("name", ["drosophila", "bumblebee", "robobee_kinematic", "dragonfly",
                                  "robobee", "hummingbird"])
def test_every_built_in_vehicle_applies_the_wing_sets_wrench(native, name):
    """Each built-in vehicle on a body with its mass and inertia, held at rest (tethered) at
    the model's own step for one wingbeat: the wrench the plugin applied in each step is the
    one flapwing's WingSet returns for the same body state, bit for bit (the actuated wings'
    dynamics and stops, the four twisted wings of the dragonfly included)."""
    v = flapwing.Vehicle(name)
    wings = flapwing.WingSet(v)
    m = mujoco.MjModel.from_xml_string(_with_model_body(plugin.fly_xml(model=name), name))
    m.opt.gravity[:] = 0
    d = mujoco.MjData(m)
    qpos0 = d.qpos.copy()
    mujoco.mj_forward(m, d)
    pos, quat = d.xipos[1].copy(), d.xquat[1].copy()
    for k in range(v.steps_per_wingbeat):
        mujoco.mj_step(m, d)
        got = d.plugin_state[:6].copy()
        d.qpos[:], d.qvel[:] = qpos0, 0
        want = wings.step(pos, quat, [0.0, 0.0, 0.0], [0.0, 0.0, 0.0])
        want = np.concatenate([want["force_body_n"], want["moment_body_nm"]])
        assert np.array_equal(got.view(np.uint64), want.view(np.uint64)), (k, got, want)
    assert np.abs(got[:3]).max() > 0


def test_tethered_mean_over_21_wingbeats_equals_the_cli(native, run_flapwing, fly100):
    out = run_flapwing("simulate", "--model", fly100, "--tethered", "--json", "--no-log")
    s = json.loads(out.stdout)
    assert s["steps_per_wingbeat"] == N and s["summary"]["wingbeats_averaged"] == 21
    ref = np.array(s["summary"]["mean_total"]["force_n"])
    f, _ = tethered_mujoco(21 * N)
    assert np.linalg.norm(f.mean(axis=0) - ref) <= 1e-9 * np.linalg.norm(ref), (f.mean(0), ref)


# ------------------------------------------------------------------ open-loop free flight

@pytest.fixture(scope="module")
def free_flapwing(step_start_fly):
    return plugin.fly_flapwing(STEPS, model=step_start_fly)


def test_free_flight_euler_follows_flapwing_to_round_off(native, free_flapwing, run_flapwing,
                                                         step_start_fly):
    mj, fw = plugin.fly_native(STEPS, model=step_start_fly), free_flapwing
    scale = np.linalg.norm(fw["position_m"], axis=1).max()
    assert scale > 1e-3  # a real flight: the untrimmed fly sinks and pitches by millimetres
    dp = np.linalg.norm(mj["position_m"] - fw["position_m"], axis=1)
    assert dp.max() <= 1e-6 * scale, f"{dp.max():.3e} m of {scale:.3e} m"
    dw = np.abs(mj["angular_velocity_body_rad_s"] - fw["angular_velocity_body_rad_s"])
    assert dw.max() <= 1e-6 * np.abs(fw["angular_velocity_body_rad_s"]).max()
    # The CLI's run ends where the Python package's does (same host, same model).
    out = run_flapwing("simulate", "--model", step_start_fly, "--duration-s", "0.1", "--json",
                       "--no-log")
    end = np.array(json.loads(out.stdout)["summary"]["final_state"]["position_m"])
    assert np.linalg.norm(mj["position_m"][-1] - end) <= 1e-6 * scale


def test_free_flight_rk4_within_the_first_order_integrator_bound(native, free_flapwing,
                                                                 step_start_fly):
    mj, fw = plugin.fly_native(STEPS, integrator="RK4", model=step_start_fly), free_flapwing
    dt = fw["dt_s"]
    # World acceleration of the reference: its body-frame force rotated, over m, plus gravity.
    acc = []
    for q, f in zip(fw["world_from_body_wxyz"], fw["force_n"]):
        r = np.empty(9)
        mujoco.mju_quat2Mat(r, q)
        acc.append(np.linalg.norm(r.reshape(3, 3) @ f / 1e-6 + [0, 0, -9.81]))
    bound = STEPS * dt * dt / 2 * max(acc)
    dp = np.linalg.norm(mj["position_m"] - fw["position_m"], axis=1)
    assert dp.max() <= bound, f"{dp.max():.3e} m, bound {bound:.3e} m"
    # RK4 is a different scheme: it parts from rapier by more than the Euler round-off floor.
    assert dp.max() > 1e-6 * np.linalg.norm(fw["position_m"], axis=1).max()


def test_controls_attribute_rolls_the_fly_within_the_gyroscopic_bound(native, step_start_fly):
    deg = 2.0
    mj = plugin.fly_native(STEPS, model=step_start_fly, diff_amplitude_deg=repr(deg))
    fw = plugin.fly_flapwing(STEPS, model=step_start_fly,
                             diff_amplitude_rad=deg * (math.pi / 180.0))
    w = fw["angular_velocity_body_rad_s"]
    assert np.abs(w[:, 0]).max() > 1.0  # it rolls
    r = {"dt_s": fw["dt_s"], "inertia_diag": np.array([8.1e-14, 3.53e-13, 3.53e-13]),
         "w_ref": w, "p_ref": fw["position_m"], "mass_kg": 1e-6,
         "force_n": np.linalg.norm(fw["force_n"], axis=1)}
    bw, bp = plugin.integrator_bound(r)
    dw = np.linalg.norm(mj["angular_velocity_body_rad_s"] - w, axis=1)
    dp = np.linalg.norm(mj["position_m"] - fw["position_m"], axis=1)
    assert np.all(dw <= bw), f"rate difference {dw.max():.3e} above bound"
    assert np.all(dp <= bp), f"position difference {dp.max():.3e} above bound"


def fly_roll(steps_per_wingbeat, wingbeats=10):
    """fly.xml (the model's step-mean sampling) at 1 / (218 Hz x steps_per_wingbeat), rolling
    and yawing under a 1 deg left-right amplitude difference: the final velocity and body
    rates."""
    xml = plugin.fly_xml("Euler", "drosophila", diff_amplitude_deg="1.0")
    old = 'timestep="4.587155963302752e-05"'
    assert old in xml
    xml = xml.replace(old, f'timestep="{1.0 / (218.0 * steps_per_wingbeat)!r}"')
    m = mujoco.MjModel.from_xml_string(xml)
    d = mujoco.MjData(m)
    for _ in range(wingbeats * steps_per_wingbeat):
        mujoco.mj_step(m, d)
    return d.qvel[:3].copy(), d.qvel[3:6].copy()


def test_a_rolling_fly_in_mujoco_converges_at_second_order(native):
    """MuJoCo's Euler takes the free body's gyroscopic term w x I w (its bias force) at the
    step's start; the plugin adds the wings' correction (`flapwing_wings_set_gyroscopic_host`), so that
    its update of the rates is the midpoint rule of Euler's equations and a fly turning about
    more than one principal axis stays second order (a one-step method of order p divides its
    error by 2^p per halved step; Hairer, Norsett & Wanner I, II.4). Measured against the
    plugin at 3200 steps per wingbeat, after 10 wingbeats at 200, 400, 800: velocity ratios
    3.96, 4.15, rate ratios 4.08, 4.22; before the correction 1.71, 2.00 and 3.70, 1.85."""
    v_ref, w_ref = fly_roll(3200)
    errors = []
    for n in (200, 400, 800):
        v, w = fly_roll(n)
        errors.append((np.linalg.norm(v - v_ref), np.linalg.norm(w - w_ref)))
    assert np.linalg.norm(w_ref[[0, 2]]) > 0.1  # it rolls and yaws
    ratios = [(a[0] / b[0], a[1] / b[1]) for a, b in zip(errors, errors[1:])]
    assert all(3.5 < r < 5.0 for pair in ratios for r in pair), (errors, ratios)


# ------------------------------------------------------------------ bad input

def load(**config):
    """fly.xml with the plugin's config replaced by `config` (no `model` unless given)."""
    xml = plugin.FLY_XML.read_text()
    cfg = "".join(f'<config key="{k}" value="{v}"/>' for k, v in config.items())
    return mujoco.MjModel.from_xml_string(
        xml.replace('<config key="model" value="drosophila"/>', cfg))


@pytest.mark.parametrize("config, names", [
    ({}, ["attribute `model` is missing", "allowed"]),
    ({"model": "no_such_fly"}, ["no_such_fly", "allowed: drosophila"]),
    ({"model": "/nonexistent/fly.toml"}, ["/nonexistent/fly.toml", "cannot read"]),
    ({"model": "drosophila", "amplitude_deg": "wide"}, ["amplitude_deg", "wide", "allowed"]),
    ({"model": "drosophila", "amplitude_deg": "500"}, ["amplitude", "allowed"]),
    ({"model": "drosophila", "wind": "1 2"}, ["wind", "1 2", "three finite numbers"]),
])
def test_bad_attribute_fails_the_load_naming_it(native, config, names):
    with pytest.raises(ValueError) as e:
        load(**config)
    for n in names:
        assert n in str(e.value), str(e.value)


def held_wingbeat_mean_force(m, pitch_rad, speed_m_s):
    """The wingbeat mean of the force the plugin applies to the free body of `m` held at
    `pitch_rad` and moving forward at `speed_m_s` (the state put back after every step)."""
    d = mujoco.MjData(m)  # the plugin's wings are built here, at m's step
    half = -0.5 * pitch_rad
    d.qpos[3:7] = [math.cos(half), 0.0, math.sin(half), 0.0]
    d.qvel[:] = 0
    d.qvel[0] = speed_m_s
    qpos0, qvel0 = d.qpos.copy(), d.qvel.copy()
    f = np.zeros(3)
    for _ in range(N):
        mujoco.mj_step(m, d)
        f += d.qfrc_passive[:3] / N  # free joint: world force on dofs 0-2
        d.qpos[:], d.qvel[:] = qpos0, qvel0
    return f


def test_trim_attribute_flies_the_flight_condition(native, fly100):
    """`trim="U W"` trims at load (flapwing_wings_trim): held at the trimmed attitude and
    velocity, the wings' cycle-mean force carries the weight (no body drag in the fly's
    model) as flapwing's trim says, to round-off: the trim balances the cycle mean of the
    plugin's own steps where they divide the wingbeat (flapsim::trim::at_host_step; here 100 a
    wingbeat, not the model's 20; the body held at the pitch of a trim of the model's 20 steps
    misses by the discretisation: the bumblebee's below by 1.8e-4 of its weight, measured)."""
    import flapwing

    fly = flapwing.Vehicle(fly100)  # the plugin's steps, so the same trim bit for bit
    t = fly.trim(speed_m_s=0.5)
    m = mujoco.MjModel.from_xml_string(plugin.fly_xml(trim="0.5 0"))
    m.opt.gravity[:] = 0
    f = held_wingbeat_mean_force(m, t["pitch_rad"], 0.5)
    weight = 1e-6 * 9.81
    assert abs(f[2] - weight) < 1e-9 * weight, (f, weight)
    assert abs(f[0]) < 1e-9 * weight, f
    with pytest.raises(ValueError, match="attribute `trim`"):
        load(model="drosophila", trim="0.5")
    with pytest.raises(ValueError, match="no trim at 50.00 m/s"):
        load(model="drosophila", trim="50 0")


def test_the_bumblebee_held_at_its_3_m_s_trim_feels_no_net_force(native, bee100):
    """The bumblebee has a body drag area (models/bumblebee.toml, drag_area_m2), which its
    trim at 3 m/s balances; the plugin applies that drag with the wings' wrench (docs/plugin.md,
    "Body drag"), so held at the trimmed attitude and velocity with gravity on, the wingbeat
    mean of the applied force plus gravity is zero to round-off (the trim balances the
    plugin's own steps, as above); issue #40 asks below 1% (it was 12% forward before the
    drag was applied). The MuJoCo step is the bumblebee's own, 1/(155 Hz x 100)."""
    import flapwing

    bee = flapwing.Vehicle(bee100)  # the plugin's steps, so the same trim bit for bit
    t = bee.trim(speed_m_s=3.0)
    xml = plugin.fly_xml(trim="3 0").replace('value="drosophila"', 'value="bumblebee"')
    m = mujoco.MjModel.from_xml_string(xml)
    m.opt.timestep = 1.0 / (155.0 * N)
    f = held_wingbeat_mean_force(m, t["pitch_rad"], 3.0)  # the wings built at m's step
    weight = bee.mass_kg * bee.gravity_m_s2
    net = f - [0.0, 0.0, weight]
    assert np.linalg.norm(net) < 1e-9 * weight, (net / weight)


def test_a_free_body_is_read_and_pushed_through_its_joint_as_mujocos_jacobian_would(native):
    """A body on one free joint takes the plugin's direct path (its state from qvel, the
    wrench into qfrc_passive on the joint's DOFs, issue #37); with the centre of mass off the
    body origin and the inertial frame rotated, and the body moving and spinning, it must give
    what the general path gives: the wrench of flapwing.WingSet at the state
    mj_objectVelocity reads (bit for bit: the same body state to round-off), and the
    generalised force mj_applyFT puts there (to round-off of the force, 1e-12)."""
    import flapwing

    xml = plugin.FLY_XML.read_text().replace(
        '<inertial pos="0 0 0"', '<inertial pos="0.0003 0.0001 -0.0002" quat="0.9 0.1 0.3 0.2"')
    m = mujoco.MjModel.from_xml_string(xml)
    d = mujoco.MjData(m)
    d.qvel[:] = [0.1, -0.05, 0.02, 3.0, -2.0, 1.0]
    mujoco.mj_forward(m, d)
    b, wrench = 1, d.plugin_state[:6].copy()
    r = d.xmat[b].reshape(3, 3)
    vel = np.zeros(6)
    mujoco.mj_objectVelocity(m, d, mujoco.mjtObj.mjOBJ_BODY, b, vel, 0)
    out = flapwing.WingSet("drosophila", dt_s=m.opt.timestep).step(
        d.xipos[b], d.xquat[b], vel[3:], r.T @ vel[:3])
    want = np.concatenate([out["force_body_n"], out["moment_body_nm"]])
    assert np.allclose(wrench, want, rtol=0, atol=1e-12 * np.abs(want).max()), (wrench, want)
    qfrc = np.zeros(m.nv)
    mujoco.mj_applyFT(m, d, r @ wrench[:3], r @ wrench[3:], d.xipos[b], b, qfrc)
    assert np.abs(qfrc).max() > 0
    assert np.allclose(d.qfrc_passive, qfrc, rtol=0, atol=1e-12 * np.abs(qfrc).max()), (
        d.qfrc_passive, qfrc)


def test_bad_model_file_fails_the_load_naming_it(native, tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text("[body]\nmass_kg = -1\n")
    with pytest.raises(ValueError) as e:
        load(model=str(bad))
    assert str(bad) in str(e.value)


def test_a_body_whose_mass_is_not_the_models_is_warned_about(native, capfd):
    # The wings' loads are the model's vehicle's; fly.xml's body is the fly's 1 mg.
    capfd.readouterr()
    mujoco.MjData(mujoco.MjModel.from_xml_string(plugin.fly_xml(model="drosophila")))
    assert "has a mass of" not in "".join(capfd.readouterr())
    mujoco.MjData(mujoco.MjModel.from_xml_string(plugin.fly_xml(model="bumblebee")))
    out = "".join(capfd.readouterr())
    assert ("body `fly` (with its subtree) has a mass of 1e-06 kg and the model `bumblebee` "
            "0.000175 kg") in out, out
    assert "accelerate this body 175 times as much" in out, out


def test_a_state_set_to_another_step_is_warned_about(native, capfd):
    """The plugin state carries the wing steps taken, so MuJoCo's state functions carry the
    wings' place in time; the wings cannot go back, so a host that sets the state to another
    step (mjd_transitionFD's perturbed steps restore the state each time) is warned: their
    phase no longer follows the body's time. Stepping, resetting and copying are not."""
    m = mujoco.MjModel.from_xml_path(str(plugin.FLY_XML))
    d = mujoco.MjData(m)
    capfd.readouterr()
    for _ in range(30):
        mujoco.mj_step(m, d)
    assert d.plugin_state[6] == 30
    mujoco.mj_copyData(mujoco.MjData(m), m, d)
    mujoco.mj_resetData(m, d)
    mujoco.mj_step(m, d)
    assert d.plugin_state[6] == 1
    assert "another step" not in "".join(capfd.readouterr())
    nx = 2 * m.nv + m.na
    mujoco.mjd_transitionFD(m, d, 1e-6, True, np.zeros((nx, nx)), np.zeros((nx, m.nu)), None,
                            None)
    out = "".join(capfd.readouterr())
    assert "the plugin state says wing step 1 and the wings are at step 2" in out, out
    assert out.count("another step") == 1 and 'rewind="true"' in out, out


def _fd_by_copies(m, d, eps):
    """d x_{k+1} / d x_k by forward differences of whole steps of copies of d (mj_copyData
    gives each copy the wings as they are: the plugin's `copy` callback), the columns in
    mjd_transitionFD's order (qpos tangent, qvel); d itself is not stepped."""
    nv = m.nv
    x_of = lambda x: np.concatenate([x.qpos.copy(), x.qvel.copy()])  # noqa: E731

    def after(perturb):
        c = mujoco.MjData(m)
        mujoco.mj_copyData(c, m, d)
        perturb(c)
        mujoco.mj_step(m, c)
        dq = np.empty(nv)
        mujoco.mj_differentiatePos(m, dq, 1.0, d_next.qpos, c.qpos)
        return np.concatenate([dq, c.qvel - d_next.qvel])

    d_next = mujoco.MjData(m)
    mujoco.mj_copyData(d_next, m, d)
    mujoco.mj_step(m, d_next)
    a = np.empty((2 * nv, 2 * nv))
    for j in range(nv):
        def pos(c, j=j):
            v = np.zeros(nv)
            v[j] = eps
            mujoco.mj_integratePos(m, c.qpos, v, 1.0)
        a[:, j] = after(pos) / eps
    for j in range(nv):
        def vel(c, j=j):
            c.qvel[j] += eps
        a[:, nv + j] = after(vel) / eps
    del x_of
    return a


@pytest.mark.parametrize("model", ["drosophila", "hummingbird", "dynamic wake"])
def test_rewind_gives_mujoco_s_own_linearisation_the_flight_s_derivatives(native, capfd, model,
                                                                           request):
    """With rewind="true" the plugin saves the wings before every step and puts them back
    when the host sets the state back a step, so mjd_transitionFD's perturbed steps are the
    same wing step as its nominal one: its A matrix equals the forward differences of whole
    steps of copies of the data (each copy with the source's wings, mj_copyData), and a run
    that linearises at every step flies bit for bit as one that never does. Without rewind
    the perturbed steps take the next wing step's loads, and A is off by their change over a
    step divided by the perturbation. The hummingbird's wings strike their stops: the save
    carries their hinge states; the fly with its wake answering, its inflow states."""
    if model == "dynamic wake":
        model = request.getfixturevalue("dynamic_fly")
    xml_on = plugin.fly_xml(model=model, rewind="true")
    xml_off = plugin.fly_xml(model=model)
    if model == "hummingbird":
        # The model's own mass, inertia and step on fly.xml's body.
        xml_on = _with_model_body(xml_on, model)
        xml_off = _with_model_body(xml_off, model)
    eps = 1e-6
    nx = 2 * 6
    results = {}
    for name, xml in (("on", xml_on), ("off", xml_off)):
        m = mujoco.MjModel.from_xml_string(xml)
        d = mujoco.MjData(m)
        for _ in range(37):
            mujoco.mj_step(m, d)
        capfd.readouterr()
        a = np.zeros((nx, nx))
        mujoco.mjd_transitionFD(m, d, eps, False, a, None, None, None)
        results[name] = (a, _fd_by_copies(m, d, eps), "".join(capfd.readouterr()))
    a_on, by_copies, out_on = results["on"]
    assert "another step" not in out_on and "flapwing" not in out_on, out_on
    scale = np.abs(by_copies).max()
    assert np.abs(a_on - by_copies).max() <= 1e-12 * scale, np.abs(a_on - by_copies).max() / scale
    a_off = results["off"][0]
    assert np.abs(a_off - by_copies).max() > 1e2 * scale, "without rewind A should be off"
    # MuJoCo's LQR tutorial calls mj_forward first (the wings then step with it): the same A.
    m = mujoco.MjModel.from_xml_string(xml_on)
    d = mujoco.MjData(m)
    for _ in range(37):
        mujoco.mj_step(m, d)
    mujoco.mj_forward(m, d)
    a = np.zeros((nx, nx))
    mujoco.mjd_transitionFD(m, d, eps, False, a, None, None, None)
    assert np.array_equal(a, a_on)

    # Linearising at every step changes nothing of the flight (bit for bit).
    m = mujoco.MjModel.from_xml_string(xml_on)
    plain, linearised = mujoco.MjData(m), mujoco.MjData(m)
    a = np.zeros((nx, nx))
    for _ in range(60):
        mujoco.mj_step(m, plain)
        mujoco.mjd_transitionFD(m, linearised, eps, True, a, None, None, None)
        mujoco.mj_step(m, linearised)
    assert np.array_equal(plain.qpos, linearised.qpos)
    assert np.array_equal(plain.qvel, linearised.qvel)
    assert np.array_equal(plain.plugin_state, linearised.plugin_state)


def test_rewind_reaches_back_one_step_and_says_so_beyond(native, capfd):
    m = mujoco.MjModel.from_xml_string(plugin.fly_xml(rewind="true"))
    d = mujoco.MjData(m)
    mujoco.mj_step(m, d)
    spec = mujoco.mjtState.mjSTATE_FULLPHYSICS
    back = np.empty(mujoco.mj_stateSize(m, spec))
    mujoco.mj_getState(m, d, back, spec)
    for _ in range(3):
        mujoco.mj_step(m, d)
    capfd.readouterr()
    mujoco.mj_setState(m, d, back, spec)
    mujoco.mj_step(m, d)
    out = "".join(capfd.readouterr())
    assert "more than the one step `rewind` keeps" in out, out
    for bad in ("yes", "1", "TRUE"):
        with pytest.raises(ValueError, match=f'attribute `rewind` = "{bad}"; allowed: "true"'):
            mujoco.MjModel.from_xml_string(plugin.fly_xml(rewind=bad))


def test_plugin_on_a_body_without_joints_fails_the_load(native):
    xml = plugin.FLY_XML.read_text().replace('<freejoint name="fly"/>', "")
    with pytest.raises(ValueError, match="no degrees of freedom"):
        mujoco.MjModel.from_xml_string(xml)


def test_nan_state_warns_applies_no_force_and_recovers(native, capfd):
    m = mujoco.MjModel.from_xml_path(str(plugin.FLY_XML))
    d = mujoco.MjData(m)
    mujoco.mj_step(m, d)
    capfd.readouterr()
    d.qvel[0] = np.nan
    mujoco.mj_forward(m, d)  # the plugin's step sees the NaN (mj_step would reset it first)
    err = capfd.readouterr().err
    assert "flapwing.wings" in err and "velocity_world_m_s[0] = NaN" in err, err
    assert np.all(d.qfrc_passive == 0) and np.all(d.plugin_state[:6] == 0)
    # mj_step: MuJoCo's own check resets the data; the plugin restarts its wings; no crash.
    mujoco.mj_step(m, d)
    assert np.all(np.isfinite(d.qpos)) and np.any(d.plugin_state[:6] != 0)


@pytest.mark.parametrize("config", [{}, {"trim": "0.3 0"}])
def test_reset_restarts_the_wings(native, config):
    # With `trim`, a reset clones the wings the load built and trimmed (it no longer trims
    # again: the hummingbird's trim alone takes seconds), and must restart them all the same.
    m = mujoco.MjModel.from_xml_string(plugin.fly_xml(**config))
    d = mujoco.MjData(m)
    first = []
    for _ in range(150):
        mujoco.mj_step(m, d)
        first.append(d.plugin_state.copy())
    mujoco.mj_resetData(m, d)
    for k in range(150):
        mujoco.mj_step(m, d)
        assert np.array_equal(d.plugin_state, first[k])


def test_a_copied_data_flies_on_as_the_original(native):
    """mj_copyData (and Python's copy.copy) gives the copy the source's wings as they are
    (the plugin's `copy` callback, flapwing_wings_clone), so stepped alike the two stay equal
    bit for bit. Before, the copy's wings kept their own phase: t = 0 for a fresh mjData, while
    its body was the source's, mid-wingbeat."""
    import copy

    m = mujoco.MjModel.from_xml_path(str(plugin.FLY_XML))
    d = mujoco.MjData(m)
    for _ in range(150):  # 1.5 wingbeats in
        mujoco.mj_step(m, d)
    c = mujoco.MjData(m)
    mujoco.mj_copyData(c, m, d)
    copies = [c, copy.copy(d)]
    for _ in range(100):
        for x in [d, *copies]:
            mujoco.mj_step(m, x)
        for x in copies:
            assert np.array_equal(x.plugin_state, d.plugin_state)
            assert np.array_equal(x.qpos, d.qpos) and np.array_equal(x.qvel, d.qvel)
    assert np.any(d.plugin_state[:6] != 0)


# ------------------------------------------------------------------ the callback fallback

@pytest.fixture(scope="module")
def flight(step_start_fly):
    return plugin.fly_with_callback(step_start_fly, wingbeats=10)


def test_callback_flies_flapwing_manoeuvre_within_the_integrator_bound(flight):
    r = flight
    dw = np.linalg.norm(r["w_ref"] - r["w_mj"], axis=1)
    dp = np.linalg.norm(r["p_ref"] - r["p_mj"], axis=1)
    bw, bp = plugin.integrator_bound(r)
    assert np.all(dw <= bw), f"rate difference {dw.max():.3e} above bound"
    assert np.all(dp <= bp), f"position difference {dp.max():.3e} above bound"
    # The manoeuvre is a real one: the body climbs and rolls by a measurable amount.
    assert np.linalg.norm(r["p_ref"][-1]) > 0.1 * r["length_m"]
    assert np.linalg.norm(r["w_ref"], axis=1).max() > 1.0


def test_callback_before_the_roll_the_trajectories_agree_to_round_off(flight):
    # Steps before wingbeat 4: w along the body y axis only (a principal axis), so the
    # gyroscopic term is zero and both integrators take identical steps.
    r = flight
    n = len(r["p_ref"]) // 10
    k = 4 * n
    dp = np.linalg.norm(r["p_ref"][:k] - r["p_mj"][:k], axis=1)
    scale = np.linalg.norm(r["p_ref"][:k], axis=1).max()
    assert dp.max() <= 1e-6 * scale


# ------------------------------------------------------------------ controls from actuators

def with_actuators(*names):
    """fly.xml with ctrl-only actuators (zero gear: they push nothing) of the given names."""
    xml = plugin.FLY_XML.read_text()
    acts = "".join(f'<motor name="{n}" joint="fly" gear="0 0 0 0 0 0"/>' for n in names)
    return mujoco.MjModel.from_xml_string(
        xml.replace("</worldbody>", f"</worldbody><actuator>{acts}</actuator>"))


def test_actuator_controls_drive_the_wings_as_flapwing_does(native):
    """An actuator `wings:diff_amplitude_rad` sets that control (SI) from its ctrl; the wings
    take it at the next wingbeat, exactly as flapwing.WingSet's set_controls does: the
    applied wrench equals the WingSet's bit for bit, step by step, across two changes."""
    import flapwing

    m = with_actuators("wings:diff_amplitude_rad")
    m.opt.gravity[:] = 0
    d = mujoco.MjData(m)
    mujoco.mj_kinematics(m, d)  # poses only: no force evaluation, so the wings do not step
    qpos0, quat, pos = d.qpos.copy(), d.xquat[1].copy(), d.xipos[1].copy()
    ref = flapwing.WingSet("drosophila", dt_s=m.opt.timestep)
    schedule = {0: 0.05, 150: -0.05}  # step -> ctrl (rad); the second mid-wingbeat
    got, want = [], []
    for k in range(3 * N):
        if k in schedule:
            d.ctrl[0] = schedule[k]
            ref.set_controls(diff_amplitude_rad=schedule[k])
        mujoco.mj_step(m, d)
        got.append(d.plugin_state[:6].copy())
        out = ref.step(pos, quat, [0, 0, 0], [0, 0, 0])
        want.append(np.concatenate([out["force_body_n"], out["moment_body_nm"]]))
        d.qpos[:], d.qvel[:] = qpos0, 0
    got, want = np.array(got), np.array(want)
    assert np.array_equal(got, want), np.abs(got - want).max()
    # The roll moment follows the differential amplitude: positive, then (from the third
    # wingbeat, the first after the change at step 150) negative on the wingbeat mean.
    roll = got[:, 3]
    assert roll[:N].mean() > 0 and roll[2 * N:].mean() < 0, (roll[:N].mean(), roll[2 * N:].mean())


def test_an_actuator_naming_no_control_fails_the_load(native):
    with pytest.raises(ValueError, match=r"wings:no_such.*allowed:.*wings:diff_amplitude_rad"):
        with_actuators("wings:no_such")


@pytest.fixture(scope="module")
def dynamic_fly(tmp_path_factory):
    """The fly with its wake answering (`[aero] inflow = "dynamic"`, issue #38)."""
    text = (ROOT / "models/drosophila.toml").read_text()
    assert 'inflow = "frozen"' in text
    path = tmp_path_factory.mktemp("models") / "drosophila_dynamic.toml"
    path.write_text(text.replace('inflow = "frozen"', 'inflow = "dynamic"'))
    return str(path)


def test_the_inflow_states_are_plugin_states(native, dynamic_fly):
    """Issue #38: the pair's dynamic inflow states are states of the system in every host.
    The plugin state holds them after its first 7 (3 per pair): after each step they are the
    states flapwing's WingSet has after the same step (tethered body, the same step), bit for
    bit; set through mj_setState they reach the wings, whose next wrench is WingSet's after
    set_inflow_states; with `trim` (which freezes the inflow) there are none."""
    m = mujoco.MjModel.from_xml_string(plugin.fly_xml(model=dynamic_fly))
    assert m.plugin_statenum[0] == 7 + 3
    m.opt.gravity[:] = 0
    d = mujoco.MjData(m)
    wings = flapwing.WingSet(dynamic_fly, dt_s=m.opt.timestep)
    assert np.array_equal(d.plugin_state[7:], np.array(wings.inflow_states[0]))
    qpos0 = d.qpos.copy()
    mujoco.mj_forward(m, d)
    pos, quat = d.xipos[1].copy(), d.xquat[1].copy()

    def both_step():
        mujoco.mj_step(m, d)
        d.qpos[:], d.qvel[:] = qpos0, 0
        out = wings.step(pos, quat, [0.0, 0.0, 0.0], [0.0, 0.0, 0.0])
        return np.concatenate([out["force_body_n"], out["moment_body_nm"]])

    for k in range(150):
        want = both_step()
        assert np.array_equal(d.plugin_state[:6], want), k
        assert np.array_equal(d.plugin_state[7:], np.array(wings.inflow_states[0])), k
    assert d.plugin_state[7] > 0  # the air comes down through the disc
    # A host that sets them: the wings take them at the next step.
    spec = mujoco.mjtState.mjSTATE_FULLPHYSICS
    x = np.empty(mujoco.mj_stateSize(m, spec))
    mujoco.mj_getState(m, d, x, spec)
    x[-3:] = [0.5, 0.01, -0.02]  # the plugin state comes last in mjSTATE_FULLPHYSICS
    mujoco.mj_setState(m, d, x, spec)
    wings.set_inflow_states([(0.5, 0.01, -0.02)])
    assert np.array_equal(both_step(), d.plugin_state[:6])
    m_trim = mujoco.MjModel.from_xml_string(plugin.fly_xml(model=dynamic_fly, trim="0 0"))
    assert m_trim.plugin_statenum[0] == 7
