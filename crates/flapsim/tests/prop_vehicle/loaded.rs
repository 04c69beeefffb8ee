//! A vehicle that loads can be simulated: every numeric leaf of every base set to each
//! special value (exhaustive), and any numeric leaf set to a moderate value (random), either
//! fails to load with a proper error or loads and simulates its first steps without a panic
//! or a non-finite load or state.

use std::panic::{AssertUnwindSafe, catch_unwind};

use proptest::prelude::*;
use proptest::sample::Index;
use toml::Value;

use crate::bases::bases_cached;
use crate::checks::{check_error, load, load_guarded, simulate_briefly, unusable};
use crate::toml_mutation::{
    Seg, assert_special_values, config, get_mut, numeric_leaves, panic_message, path_str,
};

/// KNOWN BUG (issue 7, reported to the lead): these fields are checked only for sign and
/// finiteness, so finite but extreme values load without error and the first simulation step
/// then stops with "the aerodynamic load is not finite" / "the body state is not finite"
/// (`flapwing simulate` exits 1 "diverged" instead of 2 naming the field). Exactly these
/// (field, replacement) pairs are excluded from `loaded_vehicles_simulate`; remove each once
/// the loader rejects it. `Huge` = 1e300, `HugeInt` = i64::MAX, `Tiny` = 1e-300; `*` is any
/// list index.
const KNOWN_BUG_EXTREME: &[(&str, &[&str])] = &[];

/// Every numeric leaf of every base set to each special value (NaN, +-inf, 0, negated, -1,
/// +-1e300, 1e-300, i64::MAX): a vehicle that loads simulates three steps without a panic
/// or a non-finite load or state (exhaustive, not random).
#[test]
fn loaded_vehicles_simulate() {
    // List entries: the first two and the last stand for the rest (time budget).
    let some_numeric_leaves = |v0: &Value| {
        let mut probe = v0.clone();
        numeric_leaves(v0)
            .into_iter()
            .filter(|p| match p.last() {
                Some(Seg::Idx(i)) => {
                    let len = get_mut(&mut probe, &p[..p.len() - 1])
                        .as_array()
                        .unwrap()
                        .len();
                    *i < 2 || *i + 1 == len
                }
                _ => true,
            })
            .collect()
    };
    assert_special_values(
        "loaded_vehicles_simulate",
        bases_cached(),
        some_numeric_leaves,
        KNOWN_BUG_EXTREME,
        |text| match catch_unwind(AssertUnwindSafe(|| load(text))) {
            Err(p) => Some(format!(": loader PANICKED: {}", panic_message(p))),
            Ok(Ok(vehicle)) => unusable(vehicle).map(|why| format!(" loads but {why}")),
            Ok(Err(e)) => check_error(&e, text).err().map(|f| format!(": {f}")),
        },
    );
}

proptest! {
    #![proptest_config(config(400))]

    /// Any numeric leaf set to a moderate value (+-1e-6 .. 1e6): the vehicle either fails to
    /// load with a proper error, or loads and its simulation starts without a panic (a
    /// divergence is allowed: e.g. a huge initial velocity beyond sim.max_speed_m_s).
    #[test]
    fn moderate_values_load_and_simulate_or_fail_cleanly(
        base in any::<Index>(),
        leaf in any::<Index>(),
        exp in -6.0f64..6.0,
        negative in any::<bool>(),
    ) {
        let (_, v) = base.get(bases_cached());
        let mut v = v.clone();
        let p = leaf.get(&numeric_leaves(&v)).clone();
        let x = if negative { -1.0 } else { 1.0 } * 10f64.powf(exp);
        *get_mut(&mut v, &p) = Value::Float(x);
        let text = toml::to_string(&v).unwrap();
        match load_guarded(&text)? {
            Ok(vehicle) => {
                let r = simulate_briefly(vehicle, 2);
                prop_assert!(r.is_ok(), "{} = {:?}: simulation panicked: {:?}", path_str(&p), x, r);
            }
            Err(e) => check_error(&e, &text)?,
        }
    }
}
