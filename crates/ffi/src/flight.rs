//! Trim at a flight condition through the C ABI: `flapwing_wings_trim`.

use flapsim::flight::{FlightCondition, trim_point};
use flapsim::trim::{trim_at, trimmed_vehicle};
use flapsim::{FromVehicle, WingSet};

use crate::args::{handle, put};
use crate::error::{Failure, FlapwingStatus, guard};
use crate::types::{
    FlapwingControls, FlapwingWings, FlapwingWrench, body_properties, with_body_drag, wxyz,
};

/// A trim: what `flapwing_wings_trim` found and set.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FlapwingTrim {
    /// The trimmed controls (now in force on the handle; `flapwing_wings_controls` reads them).
    pub controls: FlapwingControls,
    /// Body pitch at trim, rad (nose up).
    pub pitch_rad: f64,
    /// The body's attitude at trim, world_from_body, w x y z.
    pub world_from_body_wxyz: [f64; 4],
    /// The body's velocity at trim, world, m/s (the flight condition's).
    pub velocity_world_m_s: [f64; 3],
    /// The first stroke plane's angle to the horizontal, rad (its normal tilted forward > 0).
    pub stroke_plane_angle_rad: f64,
    /// The wings' cycle-mean aerodynamic power at trim, W.
    pub aero_power_w: f64,
}

/// Trims the handle's vehicle at a flight condition (forward speed along world x and climb
/// rate, m/s, through still air; 0 and 0 is hover) and sets the handle to fly there: the
/// trimmed controls in force and the induced inflow frozen at the condition, the body
/// properties' initial attitude at the trim. Only before the first step (the handle's wing
/// set is rebuilt at the trim); afterwards, or for a bad condition, FLAPWING_INVALID_ARGUMENT
/// naming the value and what is allowed; no trim found: FLAPWING_INVALID_ARGUMENT with the
/// reason, and the handle unchanged. `out` may be NULL when only the setting is wanted.
///
/// # Safety
/// `wings` is NULL or a live handle; `out` is NULL or valid for a write.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn flapwing_wings_trim(
    wings: *mut FlapwingWings,
    forward_speed_m_s: f64,
    climb_rate_m_s: f64,
    out: *mut FlapwingTrim,
) -> FlapwingStatus {
    const F: &str = "flapwing_wings_trim";
    guard(F, || {
        // SAFETY: NULL or a live handle used by one thread at a time (the caller's contract).
        let w = unsafe { wings.as_mut() }.ok_or_else(|| Failure::null(F, "wings"))?;
        if w.set.steps() > 0 {
            return Err(Failure::invalid(format!(
                "{F}: the handle has taken {} steps; allowed: trim before the first step (create a new handle to trim again)",
                w.set.steps()
            )));
        }
        let condition = FlightCondition::new(forward_speed_m_s, climb_rate_m_s)
            .map_err(|e| Failure::sim(F, e))?;
        let vehicle = w.set.vehicle().ok_or_else(|| {
            Failure::invalid(format!("{F}: the handle has no vehicle model to trim"))
        })?;
        // The trim balances the loads of the handle's own steps where they divide the wingbeat.
        let vehicle = &flapsim::trim::at_host_step(vehicle, w.set.dt_s());
        let t = trim_at(vehicle, vehicle.trim_lift, &condition).map_err(|e| Failure::sim(F, e))?;
        let point = trim_point(vehicle, &t).map_err(|e| Failure::sim(F, e))?;
        let trimmed = trimmed_vehicle(vehicle, &t).map_err(|e| Failure::sim(F, e))?;
        let set = WingSet::from_vehicle(&trimmed, w.set.dt_s())
            .and_then(|s| with_body_drag(s, &trimmed))
            .map_err(|e| Failure::sim(F, e))?;
        let result = FlapwingTrim {
            controls: FlapwingControls::from(&t.controls),
            pitch_rad: t.pitch_rad,
            world_from_body_wxyz: wxyz(&t.attitude()),
            velocity_world_m_s: condition.velocity_world_m_s().into(),
            stroke_plane_angle_rad: point.stroke_plane_angle_rad,
            aero_power_w: point.power.aero_w,
        };
        w.set = set;
        w.body = body_properties(&trimmed);
        if !out.is_null() {
            // SAFETY: non-null and valid for a write (the caller's contract).
            unsafe { out.write(result) };
        }
        Ok(())
    })
}

/// After a step: the body's parasite drag, 0.5 rho |V| V C_D S against its velocity V through
/// the air (the model's `[body] drag_area_m2`; the wind is the air's velocity), body frame, at
/// the centre of mass (no moment). It is part of the total `flapwing_wings_step` returns: the
/// trims of `flapwing_wings_trim` balance it, and a host applies the total and nothing else.
/// Zeros before the first step and for a model without a drag area.
///
/// # Safety
/// `wings` is NULL or a live handle; `out` is NULL or valid for a write.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn flapwing_wings_body_drag(
    wings: *const FlapwingWings,
    out: *mut FlapwingWrench,
) -> FlapwingStatus {
    const F: &str = "flapwing_wings_body_drag";
    guard(F, || {
        // SAFETY: forwarded from this function's contract.
        let w = unsafe { handle(F, wings) }?;
        // SAFETY: forwarded from this function's contract.
        unsafe { put(F, out, FlapwingWrench::from(&w.output().body_drag)) }
    })
}
