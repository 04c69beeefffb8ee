//! Models for the synthetic flights of the tests.
#![allow(dead_code)]

/// The fruit fly with a motion-capture system of 1 kHz, 20 um and 0.5 deg noise (a
/// high-speed insect-tracking rig rather than a room system; the built-in model's 200 Hz,
/// 0.15 mm and 3.4 deg would need seconds of flight to pin the inertia).
pub fn nominal() -> String {
    let t = flapsim::DROSOPHILA_TOML;
    let t = replace_line(t, "rate_hz = 200.0", "rate_hz = 1000.0");
    let t = replace_line(&t, "position_noise_m = 1.5e-4", "position_noise_m = 2.0e-5");
    replace_line(&t, "attitude_noise_deg = 3.4", "attitude_noise_deg = 0.5")
}

/// Replaces the line starting with `start` (after indentation) by `with`.
pub fn replace_line(text: &str, start: &str, with: &str) -> String {
    let mut found = false;
    let out: Vec<String> = text
        .lines()
        .map(|l| {
            if !found && l.trim_start().starts_with(start) {
                found = true;
                with.to_owned()
            } else {
                l.to_owned()
            }
        })
        .collect();
    assert!(found, "no line starting with `{start}`");
    out.join("\n") + "\n"
}

/// The true inertia factor of Iyy and CoM offsets (x, z) of the synthetic vehicle, m.
pub const IYY_FACTOR: f64 = 1.2;
pub const COM_X_M: f64 = 3.0e-5;
pub const COM_Z_M: f64 = -2.0e-5;

/// The nominal model with Iyy x [`IYY_FACTOR`] and the centre of mass moved by
/// ([`COM_X_M`], 0, [`COM_Z_M`]): the hinges, relative to it, by minus that.
pub fn truth() -> String {
    let t = nominal();
    let t = replace_line(
        &t,
        "inertia_diag_kg_m2 =",
        &format!(
            "inertia_diag_kg_m2 = [8.1e-14, {:e}, 3.53e-13]",
            3.53e-13 * IYY_FACTOR
        ),
    );
    replace_line(
        &t,
        "left_in_body_m =",
        &format!(
            "left_in_body_m = [{:e}, 0.45e-3, {:e}]",
            0.28e-3 - COM_X_M,
            0.28e-3 - COM_Z_M
        ),
    )
}

/// The synthetic vehicle's true Iyy, CoM x and CoM z, in the order the tests fit them.
pub fn true_iyy_com() -> [f64; 3] {
    [3.53e-13 * IYY_FACTOR, COM_X_M, COM_Z_M]
}

/// Each fitted parameter is identifiable and its 95 % interval, widened by `slack`, holds
/// the true value: `expected` is (true value, slack) per parameter, in the fit's order.
pub fn assert_truth_inside(r: &flapwing_identify::FitReport, expected: &[(f64, f64)]) {
    assert_eq!(r.params.len(), expected.len());
    for (p, &(truth, slack)) in r.params.iter().zip(expected) {
        assert!(p.identifiable, "{}: {:?}", p.name, p.reason);
        assert!(
            p.ci95[0] - slack <= truth && truth <= p.ci95[1] + slack,
            "{}: true {truth:e} outside [{:e}, {:e}] (+- {slack:e})",
            p.name,
            p.ci95[0],
            p.ci95[1]
        );
    }
}
