//! Tabulated kinematics, as the right wing's kinematics (errors must say
//! `right_kinematics`): a table not monotonic in time or not periodic is rejected naming the
//! entry; smooth tables load and simulate; random tables never panic.

use proptest::prelude::*;

use crate::bases::bases_cached;
use crate::checks::{check_error, load_guarded, simulate_briefly};
use crate::toml_mutation::{Defect, config, put_table, table};

proptest! {
    #![proptest_config(config(400))]

    /// Not monotonic in time: names `right_kinematics.t_s[i]` and says "increase"; not
    /// periodic: names the stroke's last entry and says "periodic"; smooth tables load and
    /// simulate; random tables never panic.
    #[test]
    fn tabulated_kinematics_tables(
        t in table(6..50, 1e-4..1.0, 5.0..170.0, 0.0..0.01),
    ) {
        let mut v = bases_cached()[3].1.clone();
        put_table(&mut v["right_kinematics"], &t);
        let text = toml::to_string(&v).unwrap();
        let result = load_guarded(&text)?;
        let s = match &result {
            Err(e) => {
                check_error(e, &text)?;
                e.to_string()
            }
            Ok(_) => String::new(),
        };
        match t.defect {
            Defect::None => {
                prop_assert!(result.is_ok(), "smooth table rejected: {}", s);
                let r = simulate_briefly(result.unwrap(), 3);
                prop_assert!(r.is_ok(), "simulation panicked: {:?}", r);
            }
            Defect::NotMonotonic(i) => {
                let field = format!("field `right_kinematics.t_s[{i}]`");
                prop_assert!(s.contains(&field) && s.contains("increase"), "{}", s);
            }
            Defect::NotPeriodic => {
                let field =
                    format!("field `right_kinematics.stroke_deg[{}]`", t.stroke.len() - 1);
                prop_assert!(s.contains(&field) && s.contains("periodic"), "{}", s);
            }
            Defect::Random => {
                if let Ok(vehicle) = result {
                    let r = simulate_briefly(vehicle, 2);
                    prop_assert!(r.is_ok(), "simulation panicked: {:?}", r);
                }
            }
        }
    }
}
