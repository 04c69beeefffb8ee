//! Control offsets each within their own range whose sum with the base kinematics is out of
//! range (a wing's amplitude outside (0, 180] deg, or a frequency not > 0): loading fails
//! with a value error on a `controls` field; otherwise the vehicle loads and simulates.

use flapsim::Error;
use proptest::prelude::*;
use toml::Value;

use crate::bases::bases_cached;
use crate::checks::{KNOWN_BUG_CONTROLS, check_error, load_guarded, unusable};
use crate::toml_mutation::config;

proptest! {
    #![proptest_config(config(200))]

    /// Controls each within their own range: when the resulting amplitude of either wing
    /// leaves (0, 180] deg or the frequency is not > 0, loading fails with a value error on a
    /// `controls` field; otherwise the vehicle loads and simulates.
    #[test]
    fn controls_that_break_the_kinematics_name_controls(
        amp in -90.0f64..=90.0,
        diff_amp in -90.0f64..=90.0,
        freq in prop_oneof![-1e3f64..1e3, -300.0f64..-100.0],
    ) {
        // drosophila-full: left harmonic and right tabulated wings, both 140 deg and 218 Hz.
        let (left, right) = (140.0 + amp + 0.5 * diff_amp, 140.0 + amp - 0.5 * diff_amp);
        let f = 218.0 + freq;
        // Stay clear of the boundaries (the library sums in radians).
        for x in [left, right, left - 180.0, right - 180.0, f] {
            prop_assume!(x.abs() > 1e-6);
        }
        let bad = !(left > 0.0 && left <= 180.0 && right > 0.0 && right <= 180.0 && f > 0.0);
        let mut v = bases_cached()[3].1.clone();
        let c = v["controls"].as_table_mut().unwrap();
        c.insert("amplitude_deg".into(), Value::Float(amp));
        c.insert("diff_amplitude_deg".into(), Value::Float(diff_amp));
        c.insert("freq_hz".into(), Value::Float(freq));
        let text = toml::to_string(&v).unwrap();
        let result = load_guarded(&text)?;
        if bad {
            let e = result.expect_err("out-of-range resulting kinematics accepted");
            if KNOWN_BUG_CONTROLS {
                return Ok(());
            }
            check_error(&e, &text)?;
            match &e {
                Error::Model(wingforce::Error::Invalid { field, .. }) => {
                    prop_assert!(field.starts_with("controls"), "{}", e)
                }
                _ => prop_assert!(false, "not a value error: {}", e),
            }
        } else {
            let vehicle = result.map_err(|e| TestCaseError::fail(format!("rejected: {e}")))?;
            prop_assert_eq!(unusable(vehicle), None);
        }
    }
}
