"""Wind fields and the estimator from Python (issue #27): `Simulation.set_wind_model` and a
model's `[wind]` table, each wing's wind (`wing_winds_m_s`), and the Gym tasks observing the
estimate (`observe="estimate"`)."""

import math
import pathlib

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import flapwing
import flapwing.envs  # registers the environments

TURBULENCE = {
    "turbulence": {"intensity_m_s": [0.1, 0.1, 0.1], "length_scale_m": [0.5, 0.5, 0.5],
                   "seed": 7},
}


def _run(sim, steps):
    """The run's per-step numbers (time, state, loads) side by side, one row per step."""
    out = sim.run(steps)
    return np.column_stack([np.asarray(out[k], dtype=float).reshape(steps, -1)
                            for k in sorted(out) if k != "terms"])


def test_a_steady_wind_field_is_the_uniform_wind():
    """A steady wind given as a field (evaluated at each hinge) and the same wind given as
    the uniform `set_wind` move the air past the wings alike: the same per-step loads and
    states to rounding (the per-wing path evaluates each wing in its own air)."""
    wind = [0.3, -0.1, 0.05]
    a = flapwing.Simulation("drosophila")
    a.set_wind(wind)
    b = flapwing.Simulation("drosophila")
    b.set_wind_model({"steady_world_m_s": wind})
    ra, rb = _run(a, 300), _run(b, 300)
    assert np.allclose(ra, rb, rtol=1e-12, atol=1e-15)
    w = b.wing_winds_m_s
    assert w.shape == (2, 3)
    assert np.array_equal(w, np.array([wind, wind]))
    assert a.wing_winds_m_s.shape == (0, 3)


def test_turbulence_is_deterministic_per_seed_and_differs_between_wings(tmp_path):
    """Dryden turbulence from a seed: two simulations with the same field fly bit for bit
    the same; the two wings, centimetres apart across the wind, see different winds; a model
    file with the same `[wind]` table starts in that field; another seed differs."""
    runs = []
    for seed in (7, 7, 8):
        s = flapwing.Simulation("drosophila")
        s.set_wind_model({"turbulence": {**TURBULENCE["turbulence"], "seed": seed}})
        runs.append((_run(s, 200), s.wing_winds_m_s))
    assert np.array_equal(runs[0][0], runs[1][0])
    assert not np.array_equal(runs[0][0], runs[2][0])
    w = runs[0][1]
    assert np.all(np.isfinite(w)) and np.any(w != 0.0)
    text = (pathlib.Path(__file__).parents[2] / "models" / "drosophila.toml").read_text()
    path = tmp_path / "fly_turbulent.toml"
    path.write_text(text + "\n[wind.turbulence]\nintensity_m_s = [0.1, 0.1, 0.1]\n"
                    "length_scale_m = [0.5, 0.5, 0.5]\nseed = 7\n")
    f = flapwing.Simulation(str(path))
    assert np.array_equal(_run(f, 200), runs[0][0])
    f.set_wind_model(None)
    f.run(1)
    assert f.wing_winds_m_s.shape == (0, 3)


@pytest.mark.parametrize("table, needle", [
    ({"turbulence": {"intensity_m_s": [-0.1, 0.1, 0.1], "length_scale_m": [0.5, 0.5, 0.5]}},
     "intensity"),
    ({"turbulence": {"intensity_m_s": [0.1, 0.1, 0.1], "length_scale_m": [0.0, 0.5, 0.5]}},
     "length_scale"),
    ({"steady_world_m_s": [1.0, 2.0]}, "steady_world_m_s"),
    ({"gale": 3.0}, "gale"),
    ({"gusts": [{"amplitude_m_s": 1.0, "direction_world": [0, 0, 0], "start_s": 0.0,
                 "duration_s": 0.01}]}, "direction"),
])
def test_bad_wind_tables_are_value_errors_that_change_nothing(table, needle):
    s = flapwing.Simulation("drosophila")
    s.set_wind_model({"steady_world_m_s": [0.2, 0.0, 0.0]})
    with pytest.raises(ValueError, match=needle):
        s.set_wind_model(table)
    s.run(1)
    assert np.array_equal(s.wing_winds_m_s, np.array([[0.2, 0.0, 0.0]] * 2))


@pytest.mark.parametrize("env_id", ["flapwing/Hover-v0", "flapwing/Recover-v0"])
def test_tasks_can_observe_the_estimate(env_id):
    """`observe="estimate"`: the environment passes Gymnasium's checker, and the reset
    observation is the filter's state (position error, velocity, attitude error, rate), not
    the raw readings: on Recover-v0 its attitude error is the disturbance to within motion
    capture's 3.4 degree noise per frame (a 10 degree bound per axis, more than 2.5 sigma
    after the one frame of the pre-roll), while the raw observation's first six numbers are
    the IMU's."""
    env = gym.make(env_id, observe="estimate")
    check_env(env.unwrapped, skip_render_check=True)
    raw = gym.make(env_id)
    o, _ = env.reset(seed=5)
    r, _ = raw.reset(seed=5)
    assert o.shape == r.shape == (12,)
    assert not np.array_equal(o, r)
    # The estimate's attitude error against the raw motion-capture frame's (same seed,
    # same sensors: the filter fused that frame onto a 10 degree prior).
    assert np.all(np.abs(o[6:9] - r[9:12]) < math.radians(10.0)), (o, r)
    for _ in range(5):
        o, reward, term, trunc, _ = env.step(np.zeros(4))
        assert np.all(np.isfinite(o)) and math.isfinite(reward)
        if term or trunc:
            break


def test_observe_takes_only_sensors_or_estimate():
    with pytest.raises(ValueError, match="observe"):
        gym.make("flapwing/Hover-v0", observe="kalman")
    with pytest.raises(ValueError, match="observe"):
        flapwing.HoverTask("drosophila", "hover", None, observe=3)
