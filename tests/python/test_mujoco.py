"""flapwing inside MuJoCo (examples/python/mujoco_plugin.py): a MuJoCo free body with the
vehicle's mass and inertia, stepped at flapwing's step and fed flapwing's wing forces and
moments each step through ``xfrc_applied``, flies flapwing's open-loop climb-and-roll
manoeuvre the way flapwing's own rapier body does.

The bound, from the two integrators. Both are first-order semi-implicit (symplectic)
Euler at the same dt: v_{k+1} = v_k + dt a(x_k), x_{k+1} = x_k + dt v_{k+1}, and both
integrate the attitude with the exponential map of the new angular velocity, so with the
same loads at the same state they take the same step up to round-off. The one modelled
difference is the gyroscopic term -I^{-1}(w x I w) of Euler's equations: MuJoCo adds it
explicitly as a bias force at the start of the step, rapier3d-f64 treats it in its own
way (or not at all). Per step it changes the body rate by at most dt |I^{-1}(w x I w)|,
so the rate difference after k steps is at most B_w(k) = sum dt |I^{-1}(w_j x I w_j)|,
the attitude difference at most B_th = sum dt B_w, the velocity difference at most
sum dt (|F|/m) B_th (the wing force, of magnitude |F|, turned by that angle) and the
position difference at most B_p = sum dt B_v; to first order (the loads' own response to
the difference is neglected: the check's margin covers it). A round-off floor of 1e-6 of
the largest value so far covers the unstable hover's growth of round-off before the roll
begins (while w stays along a principal axis the gyroscopic term is exactly zero).
In a pure climb (no roll) the two trajectories agree to round-off, which is checked too.
"""

import importlib.util
import pathlib

import numpy as np
import pytest

mujoco = pytest.importorskip("mujoco")

ROOT = pathlib.Path(__file__).resolve().parents[2]
spec = importlib.util.spec_from_file_location(
    "mujoco_plugin", ROOT / "examples" / "python" / "mujoco_plugin.py")
plugin = importlib.util.module_from_spec(spec)
spec.loader.exec_module(plugin)


@pytest.fixture(scope="module")
def flight():
    return plugin.fly_both("drosophila", wingbeats=10)


def test_mujoco_flies_flapwing_manoeuvre_within_the_integrator_bound(flight):
    r = flight
    dw = np.linalg.norm(r["w_ref"] - r["w_mj"], axis=1)
    dp = np.linalg.norm(r["p_ref"] - r["p_mj"], axis=1)
    bw, bp = plugin.integrator_bound(r)
    assert np.all(dw <= bw), f"rate difference {dw.max():.3e} above bound"
    assert np.all(dp <= bp), f"position difference {dp.max():.3e} above bound"
    # The manoeuvre is a real one: the body climbs and rolls by a measurable amount.
    assert np.linalg.norm(r["p_ref"][-1]) > 0.1 * r["length_m"]
    assert np.linalg.norm(r["w_ref"], axis=1).max() > 1.0


def test_before_the_roll_the_trajectories_agree_to_round_off(flight):
    # Steps before wingbeat 4: w along the body y axis only (a principal axis), so the
    # gyroscopic term is zero and both integrators take identical steps.
    r = flight
    n = len(r["p_ref"]) // 10
    k = 4 * n
    dp = np.linalg.norm(r["p_ref"][:k] - r["p_mj"][:k], axis=1)
    scale = np.linalg.norm(r["p_ref"][:k], axis=1).max()
    assert dp.max() <= 1e-6 * scale
