"""Forward flight and climb from Python: `Vehicle.trim/trimmed/stability` at a flight
condition and `flapwing.envelope`, the same numbers as the Rust side (flapsim::flight)."""

import math

import pytest

import flapwing


def test_hover_is_the_default_condition_and_speed_lowers_the_nose():
    bee = flapwing.Vehicle("bumblebee")
    hover = bee.trim()
    assert hover == bee.trim(speed_m_s=0.0, climb_m_s=0.0)
    assert hover["condition"] == {"forward_speed_m_s": 0.0, "climb_rate_m_s": 0.0}
    fast = bee.trim(speed_m_s=2.5)
    assert fast["condition"]["forward_speed_m_s"] == 2.5
    # Dudley & Ellington 1990a's bee lowers its body with speed (flapsim's forward_flight
    # tests hold the published 2.5 m/s angle).
    assert fast["pitch_rad"] < hover["pitch_rad"] - math.radians(20)
    assert max(abs(fast[k]) for k in (
        "residual_fx_over_weight", "residual_fz_over_weight",
        "residual_my_over_weight_length")) < 1e-7


def test_the_trimmed_vehicle_flies_on_at_its_speed():
    bee = flapwing.Vehicle("bumblebee").trimmed(speed_m_s=2.5)
    sim = flapwing.Simulation(bee, mode="longitudinal")
    assert sim.state["velocity_m_s"][0] == pytest.approx(2.5)
    for _ in range(sim.steps_per_wingbeat):
        sim.step()
    # One wingbeat later it still flies at the trimmed speed (the trim is an equilibrium of
    # the averaged model; the wingbeat's oscillation is a few per cent at most).
    assert sim.state["velocity_m_s"][0] == pytest.approx(2.5, rel=0.03)


def test_stability_at_a_condition_and_the_envelope():
    bee = flapwing.Vehicle("bumblebee")
    low = bee.stability(floquet=False, speed_m_s=1.0)
    assert low["trim"]["condition"]["forward_speed_m_s"] == 1.0
    assert len(low["longitudinal_modes"]) == 3
    rows = flapwing.envelope(bee, [0.0, 2.0, 9.0])
    assert [r["condition"]["forward_speed_m_s"] for r in rows] == [0.0, 2.0, 9.0]
    assert rows[1]["point"]["trim"] == bee.trim(speed_m_s=2.0)
    assert rows[1]["point"]["point"]["power"]["aero_w"] > 0
    assert rows[2]["point"] is None and "no trim at 9.00 m/s" in rows[2]["no_trim_reason"]
    climbs = flapwing.envelope(bee, [0.0], climbs_m_s=[0.0, 0.5])
    assert [r["condition"]["climb_rate_m_s"] for r in climbs] == [0.0, 0.5]


@pytest.mark.parametrize("kwargs, says", [
    ({"speed_m_s": -1.0}, "[0, 100]"),
    ({"speed_m_s": math.nan}, "NaN"),
    ({"climb_m_s": math.inf}, "inf"),
])
def test_bad_conditions_raise_value_error_naming_the_value(kwargs, says):
    bee = flapwing.Vehicle("bumblebee")
    with pytest.raises(ValueError, match="speed_m_s / climb_m_s") as e:
        bee.trim(**kwargs)
    assert says in str(e.value)
    with pytest.raises(ValueError):
        bee.stability(floquet=False, **kwargs)


def test_bad_envelopes_and_unreachable_conditions():
    bee = flapwing.Vehicle("bumblebee")
    with pytest.raises(ValueError, match="empty"):
        flapwing.envelope(bee, [])
    with pytest.raises(ValueError, match="NaN"):
        flapwing.envelope(bee, [1.0, math.nan])
    with pytest.raises(ValueError, match="vortex-ring"):
        bee.trim(climb_m_s=-1.0)
    with pytest.raises(flapwing.AnalysisError, match="no trim at 8.00 m/s"):
        bee.trim(speed_m_s=8.0)
