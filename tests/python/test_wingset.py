"""flapwing.WingSet: the wings as a force element for a Python host.

Physics: the wing set's loads depend on the body's states and the wings' own state alone, so
fed the states of flapwing's own Simulation it returns the Simulation's loads (to round-off:
the quaternion round trip); and a
host that integrates the body with the same scheme (semi-implicit Euler, rapier's) follows the
Simulation to the difference of the two attitude updates, first order in the step.
"""

import importlib.util
import pathlib

import numpy as np
import pytest

import flapwing

EXAMPLE = pathlib.Path(__file__).resolve().parents[2] / "examples/python/wings_in_your_loop.py"


def test_loads_equal_the_simulations_step_by_step():
    sim = flapwing.Simulation("drosophila", mode="free")
    wings = flapwing.WingSet("drosophila")
    assert wings.dt_s == sim.dt_s and len(wings) == 2
    for _ in range(2 * sim.steps_per_wingbeat):
        s = sim.state
        mine = wings.step(s["position_m"], s["world_from_body_wxyz"], s["velocity_m_s"],
                          s["angular_velocity_body_rad_s"])
        theirs = sim.step()
        # To round-off: the set integrates the body's attitude from the quaternions it is
        # given (midpoint sampling, wingset::sampling), and Python's w, x, y, z quaternion
        # is normalised again on the way in.
        f_ref, m_ref = theirs["total"]["force_n"], theirs["total"]["moment_nm"]
        assert np.allclose(mine["force_body_n"], f_ref, rtol=0, atol=1e-12 * np.abs(f_ref).max())
        assert np.allclose(mine["moment_body_nm"], m_ref, rtol=0, atol=1e-12 * np.abs(m_ref).max())
        assert mine["t_s"] == theirs["t_s"] and mine["phase"] == theirs["phase"]
    assert mine["wing_forces_body_n"].shape == (2, 3)
    assert set(mine["terms"]) == {"translational", "rotational", "added_mass", "wake_capture"}


def test_the_example_loop_follows_the_simulation():
    spec = importlib.util.spec_from_file_location("wings_in_your_loop", EXAMPLE)
    ex = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(ex)
    p, q, v, w = ex.fly(wingbeats=10)
    sim = flapwing.Simulation("drosophila", mode="free")
    p0 = np.asarray(sim.state["position_m"])
    sim.run_wingbeats(10, record=False)
    s = sim.state
    excursion = np.linalg.norm(np.asarray(s["position_m"]) - p0)
    # First order in the step: the two attitude updates differ by O(|w| dt) per step, so
    # over the run the paths differ by a few per cent of dt * f = 1/steps_per_wingbeat of
    # the excursion at most.
    bound = excursion / sim.steps_per_wingbeat
    assert np.linalg.norm(p - np.asarray(s["position_m"])) < bound, (p, s["position_m"], bound)


def test_bad_input_is_a_value_error_naming_it():
    wings = flapwing.WingSet()
    good = dict(position_m=[0, 0, 0], world_from_body_wxyz=[1, 0, 0, 0], velocity_m_s=[0, 0, 0],
                angular_velocity_body_rad_s=[0, 0, 0])
    with pytest.raises(ValueError, match=r"velocity_m_s\[1\]"):
        wings.step(**{**good, "velocity_m_s": [0, float("nan"), 0]})
    with pytest.raises(ValueError, match="unit quaternion"):
        wings.step(**{**good, "world_from_body_wxyz": [2, 0, 0, 0]})
    with pytest.raises(ValueError, match="position_m"):
        wings.step(**{**good, "position_m": [0, 0]})
    assert wings.steps == 0
    with pytest.raises(ValueError, match="dt_s"):
        flapwing.WingSet("drosophila", dt_s=-1.0)
    with pytest.raises(ValueError, match="no_such_field"):
        wings.set_controls(no_such_field=1.0)
    # Controls the model refuses: as Simulation.set_controls, an AnalysisError naming them.
    with pytest.raises(flapwing.AnalysisError, match="amplitude"):
        wings.set_controls(amplitude_rad=-10.0)
    out = wings.step(**good)
    assert np.all(np.isfinite(out["force_body_n"])) and wings.steps == 1


def test_the_lean_step_writes_the_same_wrench_and_checks_its_arrays():
    """`WingSet.step_wrench(state13, out6)` writes the total `step` returns, bit for bit, on
    two sets fed the same states; bad arrays are ValueErrors naming the argument."""
    import numpy as np

    a, b = flapwing.WingSet("drosophila"), flapwing.WingSet("drosophila")
    s = flapwing.Simulation("drosophila", "free").state
    x = np.concatenate([s["position_m"], s["world_from_body_wxyz"], s["velocity_m_s"],
                        s["angular_velocity_body_rad_s"]])
    out = np.zeros(6)
    for k in range(30):
        x[7] = 0.01 * k  # a changing forward velocity
        r = a.step(x[0:3], x[3:7], x[7:10], x[10:13])
        assert b.step_wrench(x, out) is None
        np.testing.assert_array_equal(out[:3], r["force_body_n"])
        np.testing.assert_array_equal(out[3:], r["moment_body_nm"])
    assert a.steps == b.steps == 30
    for state, o, needle in [(x[:12], out, "`state` has 12 values"), (x, np.zeros(5), "`out` has 5 values"),
                             (np.where(np.arange(13) == 8, np.nan, x), out, "`velocity_m_s[1]` must be finite"),
                             (np.where(np.arange(13) == 3, 2.0, x), out, "unit quaternion")]:
        with pytest.raises(ValueError, match=needle.replace("[", r"\[").replace("]", r"\]")):
            b.step_wrench(state, o)
    assert b.steps == 30, "a refused step is not taken"
    with pytest.raises(TypeError):
        b.step_wrench(x.astype(np.float32), out)


@pytest.mark.parametrize("name", ["drosophila", "hummingbird"])
def test_a_copy_and_a_restored_state_step_as_the_original(name):
    """copy.copy gives a set that steps as the original would, bit for bit; save_state into
    that copy and restore_state from it take a host back a step (finite differences): the
    step after the restore equals the one a run that never went back takes. The hummingbird's
    wings strike their stops: their hinge states come back."""
    import copy

    def body(k):
        return ([0.0, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0], [0.05 * np.sin(0.1 * k), 0.0, 0.01],
                [0.0, 0.5 * np.cos(0.05 * k), 0.0])

    def wrench(out):
        return np.concatenate([out["force_body_n"], out["moment_body_nm"]]).view(np.uint64)

    wings = flapwing.WingSet(name)
    n = 440 if name == "hummingbird" else 60  # the hummingbird strikes twice a wingbeat
    reference = flapwing.WingSet(name)
    steps = [wrench(reference.step(*body(k))) for k in range(n)]
    saved = copy.copy(wings)
    for k in range(n):
        wings.save_state(saved)
        pos, quat, vel, rates = body(k)
        wings.step(pos, quat, [vel[0], vel[1], vel[2] + 0.05], rates)  # a perturbed step
        wings.restore_state(saved)
        assert np.array_equal(wrench(wings.step(*body(k))), steps[k]), k
    twin = copy.deepcopy(wings)
    assert np.array_equal(wrench(twin.step(*body(n))), wrench(wings.step(*body(n))))
    with pytest.raises(ValueError, match="not a copy of this one"):
        wings.save_state(flapwing.WingSet(name))
    wings.save_state(wings)  # itself: nothing to do (not a borrow error)
    wings.restore_state(wings)
    with pytest.raises(TypeError):
        wings.save_state("a set")
