"""The flapwing Python package: wing forces, vehicles, simulation, analyses and errors.

Numbers are checked against the Rust side's own published checks (the same model and
formulas), analytic identities, or each other (one-call vs step-by-step)."""

import math

import numpy as np
import pytest

import flapwing

TERMS = ("translational", "rotational", "added_mass", "wake_capture")


def test_builtin_models_are_the_vehicles_and_builtin_wings_the_wings():
    assert set(flapwing.builtin_models()) == {
        "drosophila", "bumblebee", "robobee_kinematic", "robobee", "hummingbird", "dragonfly"}
    assert flapwing.builtin_wings() == ["robofly"]
    for name in flapwing.builtin_models():  # every name listed loads as what it is listed as
        vehicle = flapwing.Vehicle(name)
        assert vehicle.name == name
        if vehicle.actuated:
            # Its [kinematics] is only nominal: a Wing of it would evaluate a motion the
            # vehicle never makes, so it is refused, naming where the real motion is.
            with pytest.raises(ValueError, match="has actuated wings.*flapwing forces --model"):
                flapwing.Wing(name)
        else:
            flapwing.Wing(name)  # a vehicle's wing
    for name in flapwing.builtin_wings():
        flapwing.Wing(name)
        with pytest.raises(ValueError):
            flapwing.Vehicle(name)


def test_version_is_the_installed_distributions():
    import importlib.metadata

    assert flapwing.__version__ == importlib.metadata.version("flapwing")
    assert all(p.isdigit() for p in flapwing.__version__.split(".")[:3])


@pytest.mark.parametrize("first", ["flapwing", "gymnasium"])
def test_import_flapwing_alone_registers_the_gymnasium_environments(first):
    # A fresh interpreter: the README's first lines, without importing flapwing.envs, with
    # Gymnasium imported after flapwing (registered lazily, on Gymnasium's import) or before.
    import subprocess
    import sys

    imports = {
        "flapwing": (
            "import flapwing, sys\n"
            "assert 'gymnasium' not in sys.modules and 'numpy' not in sys.modules  # cheap\n"
            "import gymnasium as gym\n"
        ),
        "gymnasium": "import gymnasium as gym\nimport flapwing, sys\n",
    }[first]
    code = imports + (
        "assert 'flapwing.envs' not in sys.modules  # registered, not loaded\n"
        "env = gym.make('flapwing/Recover-v0')\n"
        "obs, _ = env.reset(seed=0)\n"
        "print(obs.shape, type(env.unwrapped).__name__)\n"
    )
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert r.stdout.strip() == "(12,) FlapwingEnv"


def test_wing_terms_sum_to_total_and_match_model_md():
    w = flapwing.Wing("robofly")
    f = w.evaluate(0.25)  # mid-downstroke
    total = sum(f[t]["force_n"] for t in TERMS)
    np.testing.assert_allclose(total, f["total"]["force_n"], rtol=1e-12, atol=1e-15)
    # MODEL.md 5 / `flapwing validate`: C_L,trans of the robofly wing mid-downstroke is
    # 1.38562 (tolerance 2e-5 as in validate's table).
    assert f["translational"]["c_l"] == pytest.approx(1.38562, abs=2e-5)
    assert w.reynolds == pytest.approx(1360.0)  # Table 5, run V3
    # The robofly reproduces the paper's BET, so its added mass is the paper's eq 7-8.
    assert w.added_mass_form == "paper"
    assert flapwing.Vehicle("drosophila").added_mass_form == "impulse"  # the default


def test_whole_cycle_in_one_call_matches_single_evaluations():
    w = flapwing.Wing("robofly")
    c = w.evaluate_cycle(200)
    assert c["total"]["force_n"].shape == (200, 3)
    assert c["phase"].shape == (200,)
    for k in (0, 37, 150):
        one = w.evaluate(float(c["phase"][k]))
        for t in TERMS + ("total",):
            np.testing.assert_array_equal(c[t]["force_n"][k], one[t]["force_n"])
    many = w.evaluate_many(np.array([0.1, 0.6]), velocity_m_s=np.array([0.01, 0.0, 0.0]))
    one = w.evaluate(0.6, velocity_m_s=np.array([0.01, 0.0, 0.0]))
    np.testing.assert_array_equal(many["total"]["force_n"][1], one["total"]["force_n"])


def test_cycle_mean_matches_the_cli_forces_table():
    # `flapwing forces` (README): mean total C_L over a wingbeat of the robofly, run V3, is
    # 1.10817 at 1000 steps per wingbeat (the wake-capture term needs the previous half
    # stroke, which the CLI's third wingbeat has; compare the translational term, which
    # does not: 0.96866).
    c = flapwing.Wing("robofly").evaluate_cycle(1000)
    assert c["translational"]["c_l"].mean() == pytest.approx(0.96866, abs=5e-5)


def test_vehicle_wing_on_its_hinge():
    w = flapwing.Wing("drosophila", side="right")
    assert w.freq_hz == pytest.approx(218.0)  # drosophila.toml, Fry et al. 2005
    with pytest.raises(ValueError, match="side"):
        flapwing.Wing("drosophila", side="middle")


def test_vehicle_properties():
    v = flapwing.Vehicle("drosophila")
    assert v.mass_kg == 1.0e-6
    assert v.weight_n == pytest.approx(9.81e-6)
    np.testing.assert_allclose(np.diag(v.inertia_kg_m2), [8.1e-14, 3.53e-13, 3.53e-13])
    assert v.control_channels == [
        "mean_stroke_rad", "amplitude_rad", "diff_amplitude_rad", "diff_pitch_bias_rad"]
    assert not v.actuated


def test_errors_are_python_exceptions_with_flapwing_messages(tmp_path):
    with pytest.raises(ValueError, match="neither a built-in name"):
        flapwing.Vehicle("no_such_model")
    bad = tmp_path / "bad.toml"
    bad.write_text(flapwing.Vehicle("drosophila").model_toml.replace(
        "mass_kg = 1.0e-6", "mass_kg = -1.0"))
    with pytest.raises(ValueError, match=r"bad\.toml.*body\.mass_kg"):
        flapwing.Vehicle(str(bad))
    with pytest.raises(ValueError, match="mode"):
        flapwing.Simulation("drosophila", mode="sideways")
    sim = flapwing.Simulation("drosophila")
    with pytest.raises(ValueError, match="no field `amplitude_deg`"):
        sim.set_controls(amplitude_deg=3.0)
    with pytest.raises(ValueError, match="3 components"):
        sim.set_wind(np.zeros(2))
    with pytest.raises(ValueError, match="finite"):
        sim.set_state(position_m=[float("nan"), 0.0, 0.0])
    # A run that leaves the envelope raises DivergedError, and the interpreter lives on.
    fast = sim.vehicle.with_initial_state({"velocity_m_s": [0.0, 0.0, 0.0]})
    s = flapwing.Simulation(fast, "free")
    s.set_state(velocity_m_s=[1e3, 0.0, 0.0])
    with pytest.raises(flapwing.DivergedError, match="max_speed_m_s"):
        s.run(10)
    assert issubclass(flapwing.DivergedError, RuntimeError)


def test_tethered_cycle_means_match_the_cli():
    # README, `flapwing simulate --tethered --duration-s 0.05`: mean lift/weight 0.8802 over
    # the complete wingbeats of 1090 steps.
    sim = flapwing.Simulation("drosophila", "tethered")
    tr = sim.run(1090)
    assert tr["force_n"].shape == (1090, 3)
    assert tr["term_force_n"].shape == (1090, 4, 3)
    assert sim.summary()["mean_lift_over_weight"] == pytest.approx(0.8802, abs=1e-4)
    np.testing.assert_allclose(tr["term_force_n"].sum(axis=1) + 0.0, tr["force_n"] - 0.0,
                               rtol=1e-9, atol=1e-18)


def test_n_steps_in_one_call_equal_n_single_steps():
    a = flapwing.Simulation("drosophila", "free")
    b = flapwing.Simulation("drosophila", "free")
    tr = a.run(250)
    for k in range(250):
        out = b.step()
        np.testing.assert_array_equal(out["state"]["position_m"], tr["position_m"][k])
        np.testing.assert_array_equal(out["total"]["force_n"], tr["force_n"][k])
    np.testing.assert_array_equal(a.state["position_m"], b.state["position_m"])
    assert a.steps == b.steps == 250 and a.time_s == pytest.approx(250 * a.dt_s)
    assert a.run(10, record=False) is None


def test_longitudinal_mode_keeps_lateral_states_zero():
    sim = flapwing.Simulation("drosophila", "longitudinal")
    tr = sim.run_wingbeats(5)
    assert np.all(tr["position_m"][:, 1] == 0.0)
    assert sim.mode == "longitudinal"


def test_free_fall_with_controls_and_state():
    # set_state then the first step: gravity only if the wings produce nothing; instead
    # check set_controls takes effect at the next wingbeat and is reported by the step.
    sim = flapwing.Simulation("drosophila", "tethered")
    sim.run(3)
    sim.set_controls(amplitude_rad=0.1)
    assert sim.controls["amplitude_rad"] == 0.0  # not before the next wingbeat
    sim.run(sim.steps_per_wingbeat)
    assert sim.controls["amplitude_rad"] == 0.1
    sim.set_control_channels(np.array([0.0, 0.2, 0.0, 0.0]))
    sim.run(sim.steps_per_wingbeat)
    assert sim.controls["amplitude_rad"] == pytest.approx(0.2)


def test_trim_stability_and_lqr():
    v = flapwing.Vehicle("drosophila")
    t = v.trim()
    # README: trim body pitch 45.00 deg, stroke amplitude 147.115 deg (+7.115 offset; the trim
    # of the fly's own 20 steps a wingbeat, +7.1162 on 200 phases).
    assert math.degrees(t["pitch_rad"]) == pytest.approx(45.0, abs=0.01)
    assert math.degrees(t["controls"]["amplitude_rad"]) == pytest.approx(7.1147, abs=1e-4)
    r = v.stability(floquet=False)
    a = r["a_longitudinal"]
    assert a.shape == (len(r["longitudinal_states"]),) * 2
    ev = r["eigenvalues_longitudinal"]
    np.testing.assert_allclose(np.sort_complex(ev), np.sort_complex(np.linalg.eigvals(a)),
                               rtol=1e-8, atol=1e-8)
    # Each reported mode is an eigenvalue of the matrix.
    for m in r["longitudinal_modes"]:
        lam = complex(m["re_per_s"], m["im_rad_s"])
        assert np.min(np.abs(ev - lam)) < 1e-6 * max(1.0, abs(lam))
    c = v.lqr()
    assert c.gain.shape == (4, 15)
    # Zero error state gives the trim controls.
    trimmed = v.trimmed()
    u = c.update({"position_m": np.zeros(3),
                  "world_from_body_wxyz": np.array([math.cos(t["pitch_rad"] / 2), 0.0,
                                                    math.sin(t["pitch_rad"] / 2), 0.0]),
                  "velocity_m_s": np.zeros(3), "angular_velocity_body_rad_s": np.zeros(3)})
    assert u["amplitude_rad"] == pytest.approx(t["controls"]["amplitude_rad"], abs=1e-9)
    assert trimmed.controls["amplitude_rad"] == pytest.approx(t["controls"]["amplitude_rad"])


def test_closed_loop_hover_through_the_bindings():
    # The LQR flown from Python, one update per wingbeat, recovers a 5 deg pitch error as
    # `flapwing hover` does (README: within 1 body length, final attitude error ~1 deg).
    v = flapwing.Vehicle("drosophila")
    c = v.lqr()
    t = c.trim
    p = t["pitch_rad"] - math.radians(5.0)
    start = v.trimmed().with_initial_state(
        {"world_from_body_wxyz": [math.cos(p / 2), 0.0, math.sin(p / 2), 0.0]})
    sim = flapwing.Simulation(start, "free")
    for _ in range(109):  # 0.5 s
        sim.set_controls(**c.update(sim.state))
        sim.run(sim.steps_per_wingbeat, record=False)
    err = np.linalg.norm(sim.state["position_m"])
    assert err < v.length_m
    assert abs(sim.state["euler_rad"][1] - t["pitch_rad"]) < math.radians(3.0)


def test_floquet_results():
    r = flapwing.Vehicle("drosophila").stability(floquet=True)
    mu = r["floquet_multipliers"]
    assert mu.dtype == np.complex128 and len(mu) == 4
    # exponent = ln(mu) * f (the wingbeat frequency): check the modulus relation.
    np.testing.assert_allclose(np.real(r["floquet_exponents"]),
                               np.log(np.abs(mu)) * 218.0, rtol=1e-6, atol=1e-6)
    # The monodromy matrix and its eigenvectors (flapsim::stability::floquet_analysis).
    phi = r["floquet_monodromy"]
    vecs = r["floquet_eigenvectors"]
    states = r["floquet_states"]
    assert states == ["vx_m_s", "vz_m_s", "pitch_err_rad", "q_rad_s"]
    assert phi.shape == (4, 4) and phi.dtype == np.float64
    assert vecs.shape == (4, 4) and vecs.dtype == np.complex128
    T = r["floquet_period_s"]
    assert T == pytest.approx(1.0 / 218.0, rel=1e-12)
    # Floquet theory: mu = exp(exponent T), the principal branch of the logarithm
    # (|Im(exponent) T| <= pi).
    exps = r["floquet_exponents"]
    np.testing.assert_allclose(np.exp(exps * T), mu, rtol=1e-12, atol=1e-14)
    assert np.all(np.abs(np.imag(exps) * T) <= math.pi + 1e-12)
    # The multipliers are the eigenvalues of Phi (numpy's LAPACK against nalgebra's Schur
    # form, agreeing to round-off of the matrix's size).
    scale = np.linalg.norm(phi, 2)
    for m in np.linalg.eigvals(phi):
        assert np.min(np.abs(mu - m)) < 1e-9 * scale
    # Each eigenvector: Phi v = mu v, unit 2-norm, largest entry real and positive. The SVD
    # null vector leaves a residual at round-off of Phi times its conditioning.
    for k in range(len(mu)):
        v = vecs[:, k]
        assert np.linalg.norm(v) == pytest.approx(1.0, abs=1e-12)
        big = v[np.argmax(np.abs(v))]
        assert big.real > 0 and abs(big.imag) < 1e-12
        assert np.linalg.norm(phi @ v - mu[k] * v) < 1e-8 * scale
        # The per-mode dicts carry the same vector.
        mode = r["floquet_longitudinal"][k]
        np.testing.assert_array_equal([complex(*c) for c in mode["eigenvector"]], v)
    # Without floquet, the Floquet fields are empty.
    r0 = flapwing.Vehicle("drosophila").stability(floquet=False)
    assert r0["floquet_monodromy"].shape == (0, 0) and r0["floquet_eigenvectors"].size == 0
    assert r0["floquet_period_s"] is None


@pytest.mark.parametrize("model", ["robobee", "hummingbird"])
def test_actuated_vehicles_work_the_same_way(model):
    v = flapwing.Vehicle(model)
    assert v.actuated
    assert v.control_channels == [
        "bias_v", "amplitude_v", "diff_amplitude_v", "diff_second_harmonic"]
    sim = flapwing.Simulation(v, "tethered")
    tr = sim.run_wingbeats(3)
    assert np.all(np.isfinite(tr["force_n"]))
    assert sim.summary()["mean_lift_over_weight"] > 0.0
    sim.set_controls(amplitude_v=1.0)
    sim.run_wingbeats(2, record=False)
    assert sim.controls["amplitude_v"] == 1.0


@pytest.mark.parametrize("model", ["robobee", "hummingbird"])
def test_actuated_summary_reports_the_wing_motion(model):
    # The summary carries the wing motion flapsim measured (flapsim::actuated::motion, the
    # measurement `simulate` prints and the frequency response uses): both wings over the
    # last complete drive period. Prescribed kinematics have none.
    v = flapwing.Vehicle(model)
    sim = flapwing.Simulation(v, "tethered")
    sim.run_wingbeats(4, record=False)
    m = sim.summary()["wing_motion"]
    left, right = m["wings"]
    for w in (left, right):
        for key in ("stroke_amplitude_deg", "pitch_amplitude_deg", "pitch_phase_deg",
                    "mid_stroke_aoa_deg", "drive_amplitude_v", "drive_bias_v", "freq_hz"):
            assert math.isfinite(w[key]), key
        assert 0.0 < w["stroke_amplitude_deg"] < 180.0
        assert -180.0 <= w["pitch_phase_deg"] <= 180.0
        assert w["cycles"] == pytest.approx(1.0)
    # The drive it measured is the model file's [actuation.drive] (no controls set): a sine
    # without bias.
    model_drive_v = {"robobee": 90.0, "hummingbird": 9.3}[model]
    assert left["drive_amplitude_v"] == pytest.approx(model_drive_v, rel=1e-6)
    assert left["drive_bias_v"] == pytest.approx(0.0, abs=1e-9 * left["drive_amplitude_v"])
    assert left["stroke_amplitude_deg"] == pytest.approx(right["stroke_amplitude_deg"])
    assert math.isfinite(m["amplitude_change_deg"])
    sim_p = flapwing.Simulation(flapwing.Vehicle("drosophila"), "tethered")
    sim_p.run_wingbeats(2, record=False)
    assert "wing_motion" not in sim_p.summary()
