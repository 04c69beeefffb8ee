//! A task's action box: the LQR design range cut to what the vehicle accepts about its trim.

use crate::error::{Error, Result};
use crate::model::Vehicle;
use crate::trim::Trim;

/// The action limits: `design` (three times the LQR design excursions) cut to what the
/// vehicle accepts about its trim `t`, so that every action in the box is controls its
/// actuators and kinematics take (an actuator's voltage limit, a stroke amplitude of at most
/// 180 deg, ...: [`Vehicle::apply_controls`]). Each channel is first cut alone (the largest
/// fraction of its design limit, both signs, found by bisection), then the box as a whole,
/// until each of its 16 corners is accepted (the limits are peaks and sums of the channels,
/// so the corners are the worst cases).
pub(super) fn admissible_limit(vehicle: &Vehicle, t: &Trim, design: [f64; 4]) -> Result<[f64; 4]> {
    let drive = vehicle.drive_controlled();
    let accepts = |u: &[f64; 4]| {
        let mut v = vehicle.clone();
        v.apply_controls(&t.controls.with_channels(drive, u))
            .is_ok()
    };
    // The largest s in [0, 1] with ok(s) (ok(0) holds), to 1e-4 of the design limit.
    let largest = |ok: &dyn Fn(f64) -> bool| {
        if ok(1.0) {
            return 1.0;
        }
        let (mut lo, mut hi) = (0.0, 1.0);
        while hi - lo > 1e-4 {
            let mid = 0.5 * (lo + hi);
            if ok(mid) { lo = mid } else { hi = mid }
        }
        lo
    };
    let corners = |lim: &[f64; 4]| {
        (0..16).all(|k: usize| {
            let u = std::array::from_fn(|j| if k >> j & 1 == 1 { lim[j] } else { -lim[j] });
            accepts(&u)
        })
    };
    if !corners(&[0.0; 4]) {
        return Err(Error::Analysis(format!(
            "{}: the vehicle refuses its own trim controls",
            vehicle.name
        )));
    }
    let mut lim = design;
    for j in 0..4 {
        let s = largest(&|s| {
            [1.0, -1.0].iter().all(|sign| {
                let mut u = [0.0; 4];
                u[j] = sign * s * design[j];
                accepts(&u)
            })
        });
        lim[j] = s * design[j];
    }
    let s = largest(&|s| corners(&lim.map(|l| s * l)));
    Ok(lim.map(|l| s * l))
}

#[cfg(test)]
mod tests {
    use crate::control::LqrWeights;
    use crate::task::{Task, TaskSpec};

    fn fly() -> &'static str {
        crate::builtin_model("drosophila").unwrap()
    }

    #[test]
    fn the_action_box_holds_controls_the_vehicle_accepts_at_every_corner() {
        // The fly trims at 147 deg of stroke: its design box (3x the LQR excursion on the
        // amplitude and its left-right difference) would reach past 180 deg.
        let t = Task::new(fly(), "fly", TaskSpec::hover(), None).unwrap();
        let design = LqrWeights::default()
            .control_max(t.vehicle())
            .map(|u| 3.0 * u);
        let lim = t.action_limit();
        assert!(lim.iter().zip(design).all(|(l, d)| *l > 0.0 && *l <= d));
        assert!(
            lim.iter().zip(design).any(|(l, d)| *l < d),
            "{lim:?} {design:?}"
        );
        for k in 0..16usize {
            let u: [f64; 4] =
                std::array::from_fn(|j| if k >> j & 1 == 1 { lim[j] } else { -lim[j] });
            let mut v = t.vehicle().clone();
            let c = t.trim().controls.with_channels(false, &u);
            assert!(v.apply_controls(&c).is_ok(), "corner {u:?}");
        }
    }
}
