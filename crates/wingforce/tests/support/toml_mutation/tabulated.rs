//! Tabulated kinematics: a smooth periodic table as TOML, putting a table into a kinematics
//! section, and random tables (smooth; one time moved back to or behind its predecessor; the
//! stroke's last value differing from the first; random), each saying what the generator did
//! to it and so which error must come first.

use std::ops::Range as Span;

use proptest::prelude::*;
use proptest::sample::Index;
use toml::Value;

use super::tree::list;

/// A smooth periodic table of `n` rows over `period_s` (one downstroke and one upstroke,
/// last row repeating the first): stroke -70 cos, pitch 90 - `pitch_amp_deg` sin, deviation
/// `deviation_amp_deg` sin 2x.
pub fn tabulated_kinematics_toml(
    n: usize,
    period_s: f64,
    pitch_amp_deg: f64,
    deviation_amp_deg: f64,
) -> String {
    let m = n - 1;
    let col = |f: &dyn Fn(f64) -> f64| {
        let v: Vec<String> = (0..n)
            .map(|i| {
                let p = (i % m) as f64 / m as f64 * std::f64::consts::TAU;
                format!("{:?}", f(p))
            })
            .collect();
        format!("[{}]", v.join(", "))
    };
    let t: Vec<String> = (0..n)
        .map(|i| format!("{:?}", period_s * i as f64 / m as f64))
        .collect();
    format!(
        "family = \"tabulated\"\nt_s = [{}]\nstroke_deg = {}\npitch_deg = {}\ndeviation_deg = {}\n",
        t.join(", "),
        col(&|p| -70.0 * p.cos()),
        col(&|p| 90.0 - pitch_amp_deg * p.sin()),
        col(&|p| deviation_amp_deg * (2.0 * p).sin()),
    )
}

/// Puts the table's times, stroke and pitch into a kinematics section (and drops its
/// deviation).
pub fn put_table(kinematics: &mut Value, t: &Table) {
    let k = kinematics.as_table_mut().unwrap();
    k.insert("t_s".into(), list(&t.t_s));
    k.insert("stroke_deg".into(), list(&t.stroke));
    k.insert("pitch_deg".into(), list(&t.pitch));
    k.remove("deviation_deg");
}

#[derive(Debug, Clone)]
pub struct Table {
    pub t_s: Vec<f64>,
    pub stroke: Vec<f64>,
    pub pitch: Vec<f64>,
    /// What the generator did to a valid table (and so which error must come first).
    pub defect: Defect,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Defect {
    None,
    /// t_s[i] <= t_s[i-1].
    NotMonotonic(usize),
    /// stroke's last value differs from the first.
    NotPeriodic,
    /// Values are random (any outcome, but no panic).
    Random,
}

/// Tabulated kinematics: smooth tables of `rows` rows over a period in `period_s` and a
/// stroke amplitude in `amplitude_deg`, the same with one time moved back to or behind its
/// predecessor, or with the stroke's last value differing from the first, and random tables
/// (times random, or cumulative steps, drawn from `random_time_s` or any float).
pub fn table(
    rows: Span<usize>,
    period_s: Span<f64>,
    amplitude_deg: Span<f64>,
    random_time_s: Span<f64>,
) -> impl Strategy<Value = Table> {
    let smooth =
        (rows, period_s, amplitude_deg, 0.0f64..1.0).prop_map(|(n, period, amp, phase0)| {
            let m = n - 1;
            let ang = |i: usize| ((i % m) as f64 / m as f64 + phase0) * std::f64::consts::TAU;
            Table {
                t_s: (0..n).map(|i| period * i as f64 / m as f64).collect(),
                stroke: (0..n).map(|i| -0.5 * amp * ang(i).cos()).collect(),
                pitch: (0..n).map(|i| 90.0 - 40.0 * ang(i).sin()).collect(),
                defect: Defect::None,
            }
        });
    prop_oneof![
        2 => smooth.clone(),
        3 => (smooth.clone(), any::<Index>(), 0.0f64..2.0).prop_map(|(mut t, i, back)| {
            // Move one time (after the first) back to or behind its predecessor.
            let k = 1 + i.index(t.t_s.len() - 1);
            let step = t.t_s[k] - t.t_s[k - 1];
            t.t_s[k] = t.t_s[k - 1] - back * step;
            t.defect = Defect::NotMonotonic(k);
            t
        }),
        3 => (smooth.clone(), prop_oneof![1e-5f64..100.0, -100.0f64..-1e-5]).prop_map(
            |(mut t, d)| {
                let n = t.stroke.len();
                t.stroke[n - 1] = t.stroke[0] + d;
                t.defect = Defect::NotPeriodic;
                t
            }
        ),
        3 => (
            prop::collection::vec(prop_oneof![random_time_s, Just(0.0), any::<f64>()], 0..30),
            prop::collection::vec(prop_oneof![-400.0f64..400.0, any::<f64>()], 0..30),
            prop::collection::vec(-400.0f64..400.0, 0..30),
            any::<bool>(),
        )
            .prop_map(|(mut t, stroke, pitch, cumulative)| {
                if cumulative {
                    // Increasing times from 0 with random (possibly tiny) steps.
                    let mut acc = 0.0;
                    for x in t.iter_mut() {
                        acc += x.abs().min(1e6);
                        *x = acc;
                    }
                    if let Some(first) = t.first_mut() {
                        *first = 0.0;
                    }
                }
                Table { t_s: t, stroke, pitch, defect: Defect::Random }
            }),
    ]
}
