//! `flapwing validate`'s vehicles section (issue 24): every built-in vehicle against measured
//! data, each row with its source, model and measured values, tolerance and a verdict that
//! follows from them; a miss carries its measured cause.

use serde_json::Value;

use super::{full_json, full_text};

/// The built-in vehicles (flapsim::builtin_model).
const VEHICLES: [&str; 6] = [
    "robobee",
    "hummingbird",
    "drosophila",
    "bumblebee",
    "robobee_kinematic",
    "dragonfly",
];

fn section() -> Value {
    full_json()["vehicles"].clone()
}

/// The verdict a row's numbers give under its check.
fn passes(row: &Value) -> bool {
    let model = row["model"].as_f64().unwrap_or(f64::NAN); // NaN is null in JSON
    let check = &row["check"];
    match check["kind"].as_str().unwrap() {
        "relative" => match row["measured"].as_f64() {
            Some(x) => (model / x - 1.0).abs() <= check["tolerance"].as_f64().unwrap(),
            None => false,
        },
        "within" => {
            check["lo"].as_f64().unwrap() <= model && model <= check["hi"].as_f64().unwrap()
        }
        "below" => model < check["bound"].as_f64().unwrap(),
        k => panic!("unknown check {k}"),
    }
}

#[test]
fn every_builtin_vehicle_has_rows_with_sources_and_consistent_verdicts() {
    let v = section();
    let rows = v["rows"].as_array().unwrap();
    for name in VEHICLES {
        let mine: Vec<&Value> = rows.iter().filter(|r| r["vehicle"] == name).collect();
        assert!(!mine.is_empty(), "no rows for {name}");
    }
    // The rows the issue names are there.
    let has = |vehicle: &str, needle: &str| {
        rows.iter()
            .any(|r| r["vehicle"] == vehicle && r["quantity"].as_str().unwrap().contains(needle))
    };
    for (vehicle, needle) in [
        ("robobee", "stroke peak-to-peak at 180 Vpp"),
        ("robobee", "pitch amplitude"),
        ("robobee", "pitch-stroke phase"),
        ("robobee", "mean lift"),
        ("robobee", "hover trim"),
        ("hummingbird", "pitch amplitude"),
        ("hummingbird", "hover trim"),
        ("drosophila", "weight support"),
        ("bumblebee", "oscillatory mode: period"),
        ("bumblebee", "slow subsidence"),
        ("dragonfly", "Azuma et al. 1985, climb: mean vertical force"),
        (
            "dragonfly",
            "Azuma et al. 1985, climb: mean horizontal force",
        ),
        (
            "dragonfly",
            "Azuma & Watanabe 1988, experiment 1: mean vertical force",
        ),
        (
            "dragonfly",
            "Azuma & Watanabe 1988, experiment 2: mean vertical force",
        ),
        (
            "dragonfly",
            "Azuma & Watanabe 1988, experiment 3: mean vertical force",
        ),
        (
            "dragonfly",
            "Azuma & Watanabe 1988, experiment 4: mean vertical force",
        ),
    ] {
        assert!(has(vehicle, needle), "{vehicle}: {needle}");
    }
    // Issue #38: every vehicle but robobee_kinematic (prescribed wings in still air) is shown under
    // another wake: the dynamic one for still air (actuated and four-winged) and the frozen
    // wake, the frozen one for a dynamic wake; its verdict follows its own number.
    for r in rows {
        let other = &r["other_wake"];
        if r["vehicle"] == "robobee_kinematic" {
            assert!(other.is_null(), "{r}");
            continue;
        }
        assert_eq!(other["inflow"], "dynamic", "{r}");
        let mut shown = r.clone();
        shown["model"] = other["model"].clone();
        assert_eq!(other["verdict"] == "pass", passes(&shown), "{r}");
        // A miss under the other wake carries its own cause, measured under that wake (the
        // bumblebee's slow subsidence passes frozen and misses dynamic).
        assert_eq!(
            other["verdict"] == "MISS",
            other["cause"].as_str().is_some_and(|c| !c.is_empty()),
            "{r}"
        );
    }
    // The dragonfly's induced-flow causes say which way the wakes modelled here push the row,
    // still air beside the dynamic wake, and where the paper's own calculation lies.
    for r in rows.iter().filter(|r| r["vehicle"] == "dragonfly") {
        for cause in [&r["cause"], &r["other_wake"]["cause"]] {
            if let Some(c) = cause.as_str() {
                assert!(
                    c.contains("the induced flow modelled here moves the row from ")
                        && c.contains("the paper's own calculation ("),
                    "{}: {c}",
                    r["quantity"]
                );
            }
        }
    }
    // A dragonfly row that misses names the pairs' share in its own quantity: the pairs
    // together under the dynamic wake are the row's dynamic-wake value (the horizontal row's
    // cause once gave the vertical split).
    for r in rows
        .iter()
        .filter(|r| r["vehicle"] == "dragonfly" && r["verdict"] == "MISS")
    {
        let Some(cause) = r["cause"].as_str() else {
            continue;
        };
        if let Some(dynamic) = r["other_wake"]["model"].as_f64() {
            assert!(
                cause.contains(&format!("together {dynamic:.3} (")),
                "{}: {cause}",
                r["quantity"]
            );
        }
        // A 1988 flight's vertical force names the wing's twist (Table 3's stations) and what
        // it measured the twist to do: the row's value less that of rigid wings feathering as
        // at 0.75R.
        let quantity = r["quantity"].as_str().unwrap_or_default();
        if quantity.contains("Azuma & Watanabe 1988") && quantity.contains("vertical") {
            let rigid = cause
                .split("rigid wings feathering as at 0.75R give ")
                .nth(1)
                .and_then(|t| t.split(',').next())
                .and_then(|x| x.parse::<f64>().ok())
                .unwrap_or_else(|| panic!("{quantity}: no twist in {cause}"));
            let model = r["model"].as_f64().unwrap();
            assert!(
                cause.contains(&format!("the twist moves it by {:+.3}", model - rigid)),
                "{quantity}: {cause}"
            );
        }
    }
    let (mut passed, mut missed) = (0, 0);
    for r in rows {
        let source = r["source"].as_str().unwrap();
        assert!(source.len() > 10, "{r}");
        let verdict = r["verdict"].as_str().unwrap();
        assert_eq!(verdict == "pass", passes(r), "verdict against numbers: {r}");
        match verdict {
            "pass" => {
                assert!(r["cause"].is_null(), "{r}");
                passed += 1;
            }
            "MISS" => {
                assert!(
                    r["cause"].as_str().unwrap().len() > 20,
                    "a miss says why: {r}"
                );
                missed += 1;
            }
            _ => panic!("{r}"),
        }
        // A row with no published value says so in its source.
        if r["measured"].is_null() && r["property"] == false {
            assert!(source.contains("NOT FOUND"), "{r}");
        }
    }
    let top = full_json();
    assert_eq!(top["vehicles_passed"], passed);
    assert_eq!(top["vehicles_missed"], missed);
    // The bumblebee's nine derivatives are compared term by term with Sun & Xiong's table.
    for d in [
        "X_u", "X_w", "X_q", "Z_u", "Z_w", "Z_q", "M_u", "M_w", "M_q",
    ] {
        assert!(has("bumblebee", &format!("derivative {d} ")), "{d}");
    }
    // What no source gave is said plainly, the bumblebee's trim angle and inertia among it.
    let nf = v["not_found"].as_array().unwrap();
    assert!(
        nf.iter()
            .any(|e| e[0] == "bumblebee" && e[1].as_str().unwrap().contains("I_y"))
    );
    assert!(
        nf.iter()
            .any(|e| e[0] == "robobee" && e[1].as_str().unwrap().contains("phase"))
    );
    // The RoboBee's pitch-stroke phase is compared with the lab's high-speed video (both
    // wings' mean, -2.5 and -18.1 deg: scripts/research/robobee3d_video.py) within the
    // issue's 20 deg.
    let phase = rows
        .iter()
        .find(|r| {
            r["vehicle"] == "robobee"
                && r["quantity"]
                    .as_str()
                    .unwrap()
                    .starts_with("pitch-stroke phase at 180 Vpp")
        })
        .expect("the RoboBee's phase row");
    assert!(
        (phase["measured"].as_f64().unwrap() + 10.3).abs() < 1e-9,
        "{phase}"
    );
    assert!(
        (phase["check"]["lo"].as_f64().unwrap() + 30.3).abs() < 1e-9,
        "{phase}"
    );
    assert!(
        (phase["check"]["hi"].as_f64().unwrap() - 9.7).abs() < 1e-9,
        "{phase}"
    );
    assert!(
        v["estimates"]
            .as_array()
            .unwrap()
            .iter()
            .any(|e| e["vehicle"] == "robobee")
    );
}

#[test]
fn added_mass_share_rows_exist_for_every_vehicle() {
    let v = section();
    let rows = v["rows"].as_array().unwrap();
    for name in VEHICLES {
        let r = rows
            .iter()
            .find(|r| {
                r["vehicle"] == name
                    && r["quantity"]
                        .as_str()
                        .unwrap()
                        .starts_with("added-mass share of the mean lift (impulse)")
            })
            .unwrap_or_else(|| panic!("no added-mass row for {name}"));
        assert_eq!(r["property"], true, "{r}");
        assert_eq!(r["check"]["lo"], -0.01);
        assert_eq!(r["check"]["hi"], 0.01);
        // The prescribed vehicles' impulse form averages to zero over their periodic
        // kinematics: below 1% of the lift (issue 24). (The actuated wings' rows are checked
        // for a consistent verdict above; the robobee's misses at the time of writing, its
        // cause measured in the row.)
        if ["drosophila", "bumblebee", "robobee_kinematic", "dragonfly"].contains(&name) {
            assert_eq!(r["verdict"], "pass", "{r}");
            assert!(r["model"].as_f64().unwrap().abs() < 0.01, "{r}");
        }
    }
}

#[test]
fn text_report_prints_the_section() {
    let out = &full_text().stdout;
    assert!(
        out.contains("built-in vehicles against measured data"),
        "{out}"
    );
    assert!(out.contains("NOT FOUND (bumblebee)"), "{out}");
    assert!(out.contains("vehicle rows pass"), "{out}");
    for name in VEHICLES {
        assert!(out.lines().any(|l| l.starts_with(name)), "{name}");
    }
    // A miss under the other wake names its cause, listed with the others: the bumblebee's
    // slow subsidence passes as the model stands (frozen) and misses under the dynamic wake.
    let row = out
        .lines()
        .find(|l| {
            l.starts_with("bumblebee") && l.contains("slow subsidence") && l.contains("dynamic")
        })
        .unwrap_or_else(|| panic!("{out}"));
    let n: usize = row
        .split("dynamic: cause ")
        .nth(1)
        .and_then(|t| t.trim().parse().ok())
        .unwrap_or_else(|| panic!("{row}"));
    assert!(out.contains(&format!("  cause {n}: ")), "{out}");
}
