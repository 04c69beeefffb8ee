"""flapwing.envs: the Gymnasium environments on flapsim's tasks, seeding, the vectorised
form and domain randomisation."""

import pathlib

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import flapwing
import flapwing.envs  # registers the environments

ROOT = pathlib.Path(__file__).resolve().parents[2]
RANDOMIZE = ROOT / "examples" / "python" / "randomize.toml"


@pytest.mark.parametrize("env_id", ["flapwing/Hover-v0", "flapwing/Recover-v0"])
def test_passes_gymnasium_env_checker(env_id):
    env = gym.make(env_id)
    check_env(env.unwrapped, skip_render_check=True)
    assert env.action_space.shape == (4,)
    assert env.observation_space.shape == (12,)


def _episode(env, seed, actions):
    obs, _ = env.reset(seed=seed)
    out = [obs]
    for a in actions:
        obs, r, term, trunc, _ = env.step(a)
        out.append(np.append(obs, r))
        if term or trunc:
            break
    return np.concatenate(out)


def test_seeding_makes_episodes_reproducible():
    env = gym.make("flapwing/Recover-v0")
    rng = np.random.default_rng(0)
    acts = [env.action_space.sample() * 0.1 for _ in range(8)]
    a = _episode(env, 123, acts)
    b = _episode(env, 123, acts)
    c = _episode(env, 124, acts)
    np.testing.assert_array_equal(a, b)
    assert not np.array_equal(a, c)
    del rng


def test_trim_action_hovers_at_first_and_the_sensors_see_the_body():
    env = gym.make("flapwing/Hover-v0", action_wingbeats=1)
    env.reset(seed=5)
    task = env.unwrapped.task
    limit = task.action_limit
    assert np.all(limit > 0)
    obs, r, term, trunc, info = env.step(np.zeros(4))
    # One wingbeat from the trim: the body barely moves, but rocks by 1-1.5 deg within the
    # wingbeat (README, `flapwing hover`): reward 1 - (1.5/10)^2 = 0.9775 or more.
    assert 0.975 < r <= 1.0 and not term
    for _ in range(3):
        obs, *_ = env.step(np.zeros(4))
    # The gyro reads the true body rate of 5 ms ago plus bias and noise. In symmetric hover
    # the true roll and yaw rates are zero (the pitch rate rocks at the wingbeat), so the
    # roll and yaw readings are bias + noise: the bias drawn with sigma 1 deg/s (ICM-20602
    # ZRO tolerance), the noise 4 mdps/sqrt(Hz) x sqrt(1 kHz); within 6 sigma of their sum.
    true_w = task.state["angular_velocity_body_rad_s"]
    assert abs(true_w[0]) < 1e-9 and abs(true_w[2]) < 1e-9
    sigma = np.radians(1.0) + np.radians(0.004) * np.sqrt(1000.0)
    assert abs(obs[0]) < 6 * sigma and abs(obs[2]) < 6 * sigma
    assert obs[0] != 0.0  # the bias and noise are there
    # Motion capture: position within 6 sigma of the 0.15 mm noise plus the motion in
    # its 6.5 ms delay.
    p = task.state["position_m"]
    v = np.linalg.norm(task.state["velocity_m_s"])
    assert np.all(np.abs(obs[6:9] - p) < 6 * 1.5e-4 + v * 0.0115)


def test_out_of_range_action_is_an_error_not_a_clamp():
    env = gym.make("flapwing/Hover-v0")
    env.reset(seed=0)
    lim = env.unwrapped.task.action_limit
    with pytest.raises(ValueError, match="outside the allowed"):
        env.step(np.array([2 * lim[0], 0.0, 0.0, 0.0]))


def test_episode_ends_and_must_be_reset():
    env = flapwing.envs.FlapwingEnv(duration_s=3 / 218.0)
    env.reset(seed=1)
    for k in range(3):
        *_, term, trunc, _ = env.step(np.zeros(4))
    assert trunc and not term
    with pytest.raises(ValueError, match="reset"):
        env.step(np.zeros(4))


def test_vectorised_tasks_equal_single_tasks():
    vec = flapwing.VecHoverTask(3, "drosophila", "recover")
    singles = [flapwing.HoverTask("drosophila", "recover") for _ in range(3)]
    seeds = [11, 12, 13]
    o = vec.reset(seeds)
    for s, t, row in zip(seeds, singles, o):
        np.testing.assert_array_equal(t.reset(s), row)
    acts = np.array([[0.0, 0.01, 0.0, 0.0], [0.0, -0.01, 0.0, 0.0], [0.01, 0.0, 0.0, 0.0]])
    for _ in range(4):
        obs, rew, term, trunc = vec.step(acts)
        for i, t in enumerate(singles):
            o1, r1, te1, tr1, _ = t.step(acts[i])
            np.testing.assert_array_equal(obs[i], o1)
            assert rew[i] == r1 and term[i] == te1 and trunc[i] == tr1


def test_vector_env_autoresets_on_the_next_step():
    env = flapwing.envs.VecHoverEnv(2, duration_s=2 / 218.0)
    obs, _ = env.reset(seed=3)
    assert obs.shape == (2, 12)
    z = np.zeros((2, 4))
    env.step(z)
    _, _, term, trunc, _ = env.step(z)
    assert np.all(trunc)
    obs, rew, term, trunc, _ = env.step(z)  # the reset step
    assert np.all(rew == 0.0) and not term.any() and not trunc.any()


def test_domain_randomisation_draws_within_ranges_and_logs_them():
    env = gym.make("flapwing/Hover-v0", randomize=str(RANDOMIZE))
    _, info = env.reset(seed=1)
    d1 = info["draws"]
    assert set(d1) == {"body.mass_kg", "body.inertia_diag_kg_m2", "wing.planform.span_m",
                       "hinge.left_in_body_m", "sensors.imu.gyro_noise_density_deg_s_sqrt_hz",
                       "sensors.imu.accel_noise_density_ug_sqrt_hz"}
    # Every draw within its entry's range (examples/python/randomize.toml).
    tomllib = pytest.importorskip("tomllib")  # Python 3.11+
    ranges = {p["path"]: p["scale"] for p in tomllib.loads(RANDOMIZE.read_text())["param"]}
    for path, k in d1.items():
        lo, hi = ranges[path]
        assert lo <= k <= hi, (path, k)
    task = env.unwrapped.task
    trim1 = task.trim["controls"]["amplitude_rad"]
    _, info = env.reset(seed=2)
    assert info["draws"] != d1
    # A heavier or lighter fly needs another stroke amplitude to hover.
    assert task.trim["controls"]["amplitude_rad"] != trim1
    _, info = env.reset(seed=1)
    assert info["draws"] == d1


def test_randomising_an_actuated_vehicle_and_bad_files(tmp_path):
    t = flapwing.HoverTask("drosophila", "hover",
                           str(ROOT / "examples" / "python" / "randomize.toml"))
    assert t.observation_len == 12
    bad = tmp_path / "r.toml"
    bad.write_text('[[param]]\npath = "body.no_such"\nscale = [0.9, 1.1]\n')
    # A path the model lacks: ValueError naming the file, the entry and the path.
    with pytest.raises(ValueError, match=r"r\.toml: field `param\[0\]\.path` = \"body\.no_such\""):
        flapwing.HoverTask("drosophila", "hover", str(bad))
    bad.write_text('[[param]]\npath = "body.mass_kg"\nscale = [1.1, 0.9]\n')
    with pytest.raises(ValueError, match="scale"):
        flapwing.HoverTask("drosophila", "hover", str(bad))
    # A model without a [sensors] table (every built-in vehicle has one): the drosophila's
    # file without it. AnalysisError naming the file and the table.
    fly = (ROOT / "models" / "drosophila.toml").read_text()
    head, tail = fly.split("# Sensors (flapsim::sensors)", 1)
    bare = tmp_path / "bare.toml"
    bare.write_text(head + tail[tail.index("[sim]"):])
    with pytest.raises(flapwing.AnalysisError, match=r"bare\.toml.*\[sensors\]"):
        flapwing.HoverTask(str(bare))


@pytest.mark.parametrize("model", flapwing.builtin_models())
@pytest.mark.parametrize("env_id", ["flapwing/Hover-v0", "flapwing/Recover-v0"])
def test_every_builtin_vehicle_runs_in_every_task_or_is_refused_as_the_table_says(env_id, model):
    table = (ROOT / "docs" / "python.md").read_text()
    row = next(line for line in table.splitlines() if line.strip().startswith(f"| `{model}` |"))
    supported = row.split("|")[2].strip() == "yes"
    assert supported == (model not in flapwing.envs.UNSUPPORTED), row
    if not supported:
        # gym.make says why, naming the table, and the task really cannot fly it: the
        # RoboBee (rebuilt from its published parameters, issue #24) lifts 0.95 W at its
        # drive's 100 V limit.
        with pytest.raises(ValueError, match="Gym tasks by vehicle") as e:
            gym.make(env_id, model=model)
        assert flapwing.envs.UNSUPPORTED[model] in str(e.value)
        kind = "hover" if env_id == "flapwing/Hover-v0" else "recover"
        why = {"robobee": "needs a drive peaking at 101.9 V"}
        with pytest.raises(flapwing.AnalysisError, match=why[model]):
            flapwing.HoverTask(model, kind)
        return
    env = gym.make(env_id, model=model)
    obs, _ = env.reset(seed=7)
    assert obs.shape == env.observation_space.shape == (12,)
    assert np.all(np.isfinite(obs)) and np.any(obs != 0.0)
    for _ in range(3):
        obs, r, term, trunc, _ = env.step(np.zeros(4))
        assert np.all(np.isfinite(obs)) and np.isfinite(r)
        if term or trunc:
            break


@pytest.mark.parametrize("model", ["hummingbird", "drosophila"])
def test_random_actions_of_the_action_space_fly_their_first_step(model):
    # The box is bounded by what the vehicle accepts about its trim (the hummingbird's
    # 21.5 V actuators, the fly's 180 deg stroke): its corners, the worst cases, are
    # accepted controls, and 200 sampled actions each fly a first step from a fresh episode
    # without terminating (before the bound: 171 of 200 for the hummingbird).
    env = flapwing.envs.FlapwingEnv(model=model)
    v = flapwing.Vehicle(model)
    trim = env.task.trim["controls"]
    lim = env.action_space.high
    assert np.all(lim > 0) and np.all(env.action_space.low == -lim)
    channels = env.control_channels
    for k in range(16):
        corner = np.where([(k >> j) & 1 for j in range(4)], lim, -lim)
        v.with_controls(**{c: trim[c] + u for c, u in zip(channels, corner)})
    env.action_space.seed(0)
    ended = []
    for i in range(200):
        env.reset(seed=i)
        a = env.action_space.sample()
        _, _, term, _, info = env.step(a)
        if term:
            ended.append((a, info.get("reason")))
    assert not ended, f"{len(ended)} of 200 random actions ended the episode: {ended[:3]}"


def test_recover_reset_observation_shows_the_disturbance():
    # The IMU's 5 ms latency exceeds a 4.6 ms wingbeat; the sensors run for their longest
    # latency (6.5 ms, motion capture) before the release, the body held at its disturbed
    # initial state, so the first observation is a reading of that state, not zeros.
    env = gym.make("flapwing/Recover-v0")
    task = env.unwrapped.task
    rows, truth = [], []
    for seed in range(40):
        obs, _ = env.reset(seed=seed)
        assert task.time_s == 0.0
        rows.append(obs)
        truth.append(_attitude_error(task))
    obs, truth = np.array(rows), np.array(truth)
    assert np.all(obs[:, 9:12] != 0.0) and np.all(obs[:, 3:6] != 0.0)
    # Motion capture's attitude error is the disturbance plus 3.4 deg of noise per axis
    # (models/drosophila.toml) against a uniform +-10 deg disturbance (std 5.8 deg).
    for axis in (0, 1):
        c = np.corrcoef(obs[:, 9 + axis], truth[:, axis])[0, 1]
        assert c > 0.7, (axis, c)
    # The accelerometer, held, reads gravity in the tilted body frame: its change from the
    # trim's reading is about g times the tilt (up to 1.7 m/s^2 here), far above its 25 mg
    # (0.25 m/s^2) turn-on bias and 3 mg noise.
    tilt = np.linalg.norm(truth[:, :2], axis=1)
    c = np.corrcoef(np.linalg.norm(obs[:, 3:6], axis=1), 9.81 * tilt)[0, 1]
    assert c > 0.7, c


def _qmul(a, b):
    w1, x1, y1, z1 = a
    w2, x2, y2, z2 = b
    return np.array([w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2,
                     w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
                     w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2,
                     w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2])


def _attitude_error(task):
    """The true attitude error from the trim attitude (flapsim::trim::attitude_for_pitch: a
    rotation of -pitch_rad about body y) as a rotation vector, rad."""
    p = task.trim["pitch_rad"]
    q_trim_inv = np.array([np.cos(-p / 2), 0.0, -np.sin(-p / 2), 0.0])
    q = _qmul(q_trim_inv, task.state["world_from_body_wxyz"])
    if q[0] < 0:
        q = -q
    angle = 2 * np.arctan2(np.linalg.norm(q[1:]), q[0])
    n = np.linalg.norm(q[1:])
    return q[1:] / n * angle if n > 0 else np.zeros(3)


def test_a_dynamic_wake_model_flies_the_tasks_and_resets_its_inflow(tmp_path):
    """Issue #38: the inflow states are states of the task. A model with the wake that answers
    (`[aero] inflow = "dynamic"`) trims with its wake, so the trim action holds it for the first
    wingbeat as it holds the frozen-wake fly (reward 0.975 or more: 1 - (1.5/10)^2 for the
    1-1.5 deg a wingbeat rocks the body); an episode after another one on the same environment
    repeats the first bit for bit (the pair's inflow starts again, nothing is carried over);
    and the wake changes the flight from the frozen one's."""
    text = (ROOT / "models/drosophila.toml").read_text()
    assert 'inflow = "frozen"' in text
    dynamic = tmp_path / "fly_dynamic.toml"
    dynamic.write_text(text.replace('inflow = "frozen"', 'inflow = "dynamic"'))
    zeros = [np.zeros(4)] * 4

    env = gym.make("flapwing/Hover-v0", model=str(dynamic), action_wingbeats=1)
    first = _episode(env, 5, zeros)
    assert first[12 + 12] >= 0.975, first  # the first step's reward, after its observation
    _episode(env, 9, zeros)
    np.testing.assert_array_equal(_episode(env, 5, zeros), first)

    frozen = gym.make("flapwing/Hover-v0", model=str(ROOT / "models/drosophila.toml"),
                      action_wingbeats=1)
    assert np.abs(_episode(frozen, 5, zeros) - first).max() > 1e-3
