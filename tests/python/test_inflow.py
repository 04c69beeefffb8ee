"""The dynamic wake in Python (issue #38): `Vehicle.inflow_model`, `WingSet.inflow_states`.

A wing set whose model has `[aero] inflow = "dynamic"` carries each pair's inflow states and
steps them with its loads. It starts at momentum theory's hover downwash for the weight,
w_h = sqrt(m g / (2 rho A)) over the disc the pair sweeps, A = Phi R^2 (Ellington 1984c), and
then follows the pair's own thrust: at rest the wingbeat mean of the thrust balances
2 rho A <w0^2> (the mean state's momentum balance, whose rate has no mean over a periodic
motion; wingforce::inflow::dynamic).
"""

import math
import pathlib
import re

import numpy as np
import pytest

import flapwing

ROOT = pathlib.Path(__file__).resolve().parents[2]


def dynamic_fly(tmp_path):
    text = (ROOT / "models/drosophila.toml").read_text()
    assert 'inflow = "frozen"' in text
    path = tmp_path / "fly_dynamic.toml"
    text = text.replace('inflow = "frozen"', 'inflow = "dynamic"')
    # At 100 steps per wingbeat, where the momentum balance below was measured (1.1e-4; at the
    # fly's default 20 steps the step means' own error adds 2.6e-3).
    line = re.compile(r"^steps_per_wingbeat = \d+", re.M)
    path.write_text(line.sub("steps_per_wingbeat = 100", text, count=1))
    return str(path)


REST = dict(position_m=[0, 0, 0], world_from_body_wxyz=[1, 0, 0, 0], velocity_m_s=[0, 0, 0],
            angular_velocity_body_rad_s=[0, 0, 0])


def test_the_wake_is_named_and_its_states_follow_the_thrust(tmp_path):
    path = dynamic_fly(tmp_path)
    assert flapwing.Vehicle("drosophila").inflow_model == "frozen"
    assert flapwing.Vehicle("robobee").inflow_model == "off"
    assert flapwing.Vehicle(path).inflow_model == "dynamic"
    wings = flapwing.WingSet(path)
    [(w0, wx, wy)] = wings.inflow_states
    # The model's numbers: 1 mg, 140 deg of stroke, tip radius 2.39 + 0.3 mm, air 1.204.
    area = math.radians(140.0) * (2.39e-3 + 0.3e-3) ** 2
    w_h = math.sqrt(1.0e-6 * 9.81 / (2 * 1.204 * area))
    assert w0 == pytest.approx(w_h, rel=1e-12) and wx == 0.0 and wy == 0.0
    # Ten wingbeats at rest: the states move with the thrust; over the last the wingbeat mean
    # of the force (inertia and added mass average out) balances 2 rho A <w0^2>.
    steps = round(1.0 / (wings.dt_s * 218.0))
    means = []
    for beat in range(10):
        force, w2 = np.zeros(3), 0.0
        for _ in range(steps):
            force += wings.step(**REST)["force_body_n"] / steps
            w2 += wings.inflow_states[0][0] ** 2 / steps
        means.append((np.linalg.norm(force), w2))
    thrust, w2 = means[-1]
    assert 2 * 1.204 * area * w2 == pytest.approx(thrust, rel=1e-3), (thrust, w2)  # measured: 1.1e-4
    assert wings.inflow_states[0][0] != w0


def test_states_can_be_set_only_where_the_wake_answers(tmp_path):
    wings = flapwing.WingSet(dynamic_fly(tmp_path))
    wings.set_inflow_states([(0.5, 0.01, -0.02)])
    assert wings.inflow_states == [(0.5, 0.01, -0.02)] or wings.inflow_states == [[0.5, 0.01, -0.02]]
    with pytest.raises(ValueError, match="one per pair"):
        wings.set_inflow_states([(0.5, 0, 0), (0.5, 0, 0)])
    with pytest.raises(ValueError, match="finite"):
        wings.set_inflow_states([(float("nan"), 0, 0)])
    frozen = flapwing.WingSet("drosophila")
    assert frozen.inflow_states == []
    with pytest.raises(ValueError, match="no dynamic inflow"):
        frozen.set_inflow_states([(0.5, 0, 0)])


def test_a_python_run_logs_the_inflow_where_the_wake_answers(tmp_path):
    """`flapwing.Simulation(..., mcap=...)` writes `/inflow` for a dynamic-wake vehicle, as
    `flapwing simulate` does: each logged step's pair states, the ones its loads were taken
    at; a frozen-wake run has no such channel."""
    log = tmp_path / "dyn.mcap"
    sim = flapwing.Simulation(flapwing.Vehicle(dynamic_fly(tmp_path)), "free", mcap=str(log), log_rate_hz=None)
    sim.run(120, record=False)
    assert sim.close_log()["samples"] == 120
    tables = flapwing.read_log(str(log), pandas=False)
    inflow = tables["/inflow"]
    assert len(inflow["log_time_ns"]) == 120
    np.testing.assert_array_equal(inflow["log_time_ns"], tables["/vehicle/state"]["log_time_ns"])
    w0 = [c for c in inflow if c.endswith("mean_m_s")]
    assert w0 and np.all(inflow[w0[0]] > 0), list(inflow)
    frozen = tmp_path / "frozen.mcap"
    sim = flapwing.Simulation("drosophila", "free", mcap=str(frozen))
    sim.run(20, record=False)
    sim.close_log()
    assert "/inflow" not in flapwing.read_log(str(frozen), pandas=False)


def test_actuated_and_four_winged_sets_carry_every_pairs_states(tmp_path):
    """The dynamic wake on actuated wings (their disc the stroke they sweep) and on tandem
    pairs (each pair's states, crossing each other's discs): the Python wing set carries one
    state triple per pair, and the states move with the loads from the hover start."""
    for name, pairs in (("robobee", 1), ("dragonfly", 2)):
        text = (ROOT / f"models/{name}.toml").read_text()
        assert "[aero]" not in text  # still air, the files' default
        text += '\n[aero]\ninflow = "dynamic"\n'
        path = tmp_path / f"{name}_dynamic.toml"
        path.write_text(text)
        assert flapwing.Vehicle(str(path)).inflow_model == "dynamic"
        wings = flapwing.WingSet(str(path))
        start = [tuple(s) for s in wings.inflow_states]
        assert len(start) == pairs
        for _ in range(50):
            wings.step(**REST)
        now = [tuple(s) for s in wings.inflow_states]
        assert len(now) == pairs and all(a[0] != b[0] for a, b in zip(start, now)), (start, now)
