//! The recorder's warnings about wings whose wake-capture inputs lie outside the fitted
//! range of the paper's regressions (logged as `/events` warnings, once per wing until it
//! changes back).

use flapsim::Vehicle;

/// The warnings for wings whose wake-capture inputs lie outside the fitted range of the
/// regressions (once per wing until it changes back; `wake_warned` keeps track).
pub(super) fn wake_capture_warnings(vehicle: &Vehicle, wake_warned: &mut [bool]) -> Vec<String> {
    let mut out_messages = Vec::new();
    for i in 0..vehicle.wings.len().min(wake_warned.len()) {
        let flags = vehicle.wings[i]
            .wake_capture()
            .map(|p| p.flags)
            .unwrap_or_default();
        let out = flags.any();
        if out && !wake_warned[i] {
            let w = &vehicle.wings[i];
            let (da, dd) = w.kinematics().acceleration_fractions();
            let mut what = Vec::new();
            if flags.re_clamped {
                what.push(format!("Re = {:.0}", w.reynolds()));
            }
            if flags.dtau_a_clamped {
                what.push(format!("dtau_A = {da:.3}"));
            }
            if flags.dtau_d_clamped {
                what.push(format!("dtau_D = {dd:.3}"));
            }
            let side = Vehicle::wing_name(i);
            out_messages.push(format!(
                "{side} wing: wake-capture input outside its fitted range ({}); the regressions use the nearest fitted value",
                what.join(", ")
            ));
        }
        wake_warned[i] = out;
    }
    out_messages
}
