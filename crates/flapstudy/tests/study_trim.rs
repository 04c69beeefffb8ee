//! The `trim_feasible` response: 1 where a hover trim exists within the allowed range, 0
//! where it does not (here: a fly so heavy that no amplitude up to 180 deg lifts it).

use flapstudy::spec::StudySpec;

#[test]
fn trim_feasibility_follows_the_weight() {
    let text = r#"
name = "trim"
base_model = "drosophila"
design = "full_factorial"
responses = ["trim_feasible", "lift_over_weight"]

[[factor]]
path = "body.mass_kg"
levels = [1.0e-6, 1.0e-5]
"#;
    let spec = StudySpec::from_toml(text, "test.toml").unwrap();
    let study = spec
        .resolve(
            "test.toml",
            "test",
            flapsim::DROSOPHILA_TOML,
            &spec.base_model,
        )
        .unwrap();
    let rows = study.run(0..2, &|_| {}).unwrap();
    // 1 mg: lift/weight 1.01 at 140 deg, trims at about 139.5 deg. 10 mg: lift/weight below 0.1
    // (the downwash grows with the weight);
    // lift grows with amplitude squared at most, so even 180 deg cannot carry ten times more.
    assert_eq!(rows[0].responses[0], 1.0, "{:?}", rows[0].responses);
    assert_eq!(rows[1].responses[0], 0.0, "{:?}", rows[1].responses);
    assert!(rows[1].responses[1] < 0.2);
}
