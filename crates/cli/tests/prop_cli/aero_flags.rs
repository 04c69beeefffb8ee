//! Random flags of the aerodynamics commands: `wake-capture` exits 0 exactly when every value
//! is valid (Re finite and > 0, dtau in (0, 0.5)), else 2; `forces` on the built-in robofly
//! exits 0, 1 (non-finite forces) or 2, always 2 for an invalid value (counts out of range
//! too); never a panic. A run is kept short (`forces` at most 3 x 40 steps), so the case
//! counts are small (48 and 24).

use proptest::prelude::*;

use crate::flag_values::{flag, number_text, valid_dtau, valid_re};
use crate::harness::{check_json, check_run, config, flapwing};

// ---------------------------------------------------------------------------------------------
// wake-capture.
// ---------------------------------------------------------------------------------------------

proptest! {
    #![proptest_config(config(48))]

    /// Random --re, --dtau-a, --dtau-d: exit 0 exactly when all three are valid (Re finite
    /// > 0, dtau in (0, 0.5)), else 2; never a panic.
    #[test]
    fn wake_capture_flags(
        re in number_text(),
        da in prop_oneof![number_text(), (0.0f64..0.6).prop_map(|x| format!("{x}"))],
        dd in prop_oneof![number_text(), (0.0f64..0.6).prop_map(|x| format!("{x}"))],
        joined in any::<[bool; 3]>(),
        json in any::<bool>(),
    ) {
        let dir = tempfile::tempdir().unwrap();
        let mut args = vec!["wake-capture".to_owned()];
        args.extend(flag("re", &re, joined[0]));
        args.extend(flag("dtau-a", &da, joined[1]));
        args.extend(flag("dtau-d", &dd, joined[2]));
        if json {
            args.push("--json".into());
        }
        let r = flapwing(dir.path(), &args);
        check_run(&r)?;
        check_json(&r, json)?;
        let valid = valid_re(&re, joined[0])
            && valid_dtau(&da, joined[1])
            && valid_dtau(&dd, joined[2]);
        prop_assert_eq!(r.code, if valid { 0 } else { 2 }, "{:?}\n{}", r.args, r.stderr);
    }
}

// ---------------------------------------------------------------------------------------------
// forces.
// ---------------------------------------------------------------------------------------------

/// An integer flag: `Ok` values are in range (and small, to keep runs short), `Err` are not.
fn int_text(lo: u64, small_hi: u64, hi: u64) -> impl Strategy<Value = (String, bool)> {
    prop_oneof![
        2 => (lo..=small_hi).prop_map(|n| (n.to_string(), true)),
        1 => prop::sample::select(vec![
            "0".to_owned(),
            "-1".to_owned(),
            format!("{}", hi + 1),
            "1.5".to_owned(),
            "1e3".to_owned(),
            "abc".to_owned(),
            "".to_owned(),
            "99999999999999999999999".to_owned(),
            format!("{}", lo.saturating_sub(1)),
        ])
        .prop_map(move |s| {
            let ok = s.parse::<u64>().is_ok_and(|n| (lo..=hi).contains(&n));
            (s, ok)
        }),
    ]
}

proptest! {
    #![proptest_config(config(24))]

    /// Random forces flags on the built-in robofly: exit 0, 1 (non-finite forces) or 2;
    /// always 2 when a flag value is invalid.
    #[test]
    fn forces_flags(
        re in prop::option::of(number_text()),
        da in prop::option::of(prop_oneof![number_text(), (0.0f64..0.6).prop_map(|x| format!("{x}"))]),
        dd in prop::option::of(prop_oneof![number_text(), (0.0f64..0.6).prop_map(|x| format!("{x}"))]),
        cycles in int_text(1, 3, 10_000),
        steps in int_text(2, 40, 10_000_000),
        no_wake in any::<bool>(),
        json in any::<bool>(),
    ) {
        let dir = tempfile::tempdir().unwrap();
        let mut args = vec!["forces".to_owned()];
        let mut valid = true;
        if let Some(re) = &re {
            args.extend(flag("re", re, true));
            valid &= valid_re(re, true);
        }
        if let Some(da) = &da {
            args.extend(flag("dtau-a", da, true));
            valid &= valid_dtau(da, true);
        }
        if let Some(dd) = &dd {
            args.extend(flag("dtau-d", dd, true));
            valid &= valid_dtau(dd, true);
        }
        args.extend(flag("cycles", &cycles.0, true));
        args.extend(flag("steps-per-cycle", &steps.0, true));
        valid &= cycles.1 && steps.1;
        if no_wake {
            args.push("--no-wake-capture".into());
        }
        if json {
            args.push("--json".into());
        }
        let r = flapwing(dir.path(), &args);
        check_run(&r)?;
        check_json(&r, json)?;
        if !valid {
            prop_assert_eq!(r.code, 2, "{:?}\n{}", r.args, r.stderr);
        }
    }
}
