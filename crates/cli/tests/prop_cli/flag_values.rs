//! Flag values as typed on a command line, shared by the flag properties: numbers of every
//! size and sign, NaN and infinity spellings and garbage; a flag given as `--name=value` or
//! `--name value`; and which values of `--re` and `--dtau-*` the command must accept.

use proptest::prelude::*;

/// A flag value as typed: numbers of every size and sign, NaN/inf spellings, garbage.
pub(crate) fn number_text() -> impl Strategy<Value = String> {
    prop_oneof![
        3 => any::<f64>().prop_map(|x| format!("{x}")),
        3 => (-2.0f64..2.0).prop_map(|x| format!("{x}")),
        2 => (1.0f64..1e5).prop_map(|x| format!("{x:e}")),
        3 => prop::sample::select(vec![
            "nan", "NaN", "-nan", "inf", "-inf", "infinity", "-Infinity", "1e300", "-1e300",
            "1e-300", "1e309", "0", "-0", "0.0", "", " ", " 1", "1 ", "0x10", "1,5", "5e", "+3",
            "--", "-", "1e-320", "4.9e-324",
        ])
        .prop_map(str::to_owned),
        1 => "[a-zA-Z%$#@!=,._-]{1,10}",
        1 => any::<String>().prop_map(|s| s.replace('\0', "")),
    ]
}

/// `--name=value` (clap takes the value verbatim) or `--name value` (a value starting with
/// `-` is then taken for a flag: also a bad-input exit).
pub(crate) fn flag(name: &str, value: &str, joined: bool) -> Vec<String> {
    if joined {
        vec![format!("--{name}={value}")]
    } else {
        vec![format!("--{name}"), value.to_owned()]
    }
}

/// clap passes the value verbatim; `parse_reynolds` and `parse_dtau` trim and parse.
pub(crate) fn valid_re(s: &str, joined: bool) -> bool {
    (joined || !s.starts_with('-'))
        && s.trim()
            .parse::<f64>()
            .is_ok_and(|x| x.is_finite() && x > 0.0)
}

pub(crate) fn valid_dtau(s: &str, joined: bool) -> bool {
    (joined || !s.starts_with('-'))
        && s.trim()
            .parse::<f64>()
            .is_ok_and(|x| x.is_finite() && x > 0.0 && x < 0.5)
}
