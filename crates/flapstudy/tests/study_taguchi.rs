//! Taguchi arrays, SNR (eq 15) and main effects, and the full second-order regression
//! (eq 16) with its statistics.
//!
//! Sources: the seed paper (shared/seeds/000_94b36197bfdef766.txt) Table 2 (its L18 design),
//! eq 15 and section 7's reading of its Figures 12-14; the standard L9 and L27 tables
//! (Taguchi; e.g. Phadke, *Quality Engineering Using Robust Design*, 1989, appendix C);
//! regression identities from the normal equations.

use flapstudy::fit_wake::{PAPER_TABLE4_CSV, WakeCaptureData, fit_linear_ln};
use flapstudy::regression::{fit_full_quadratic, full_quadratic_terms};
use flapstudy::taguchi::{OrthogonalArray, SEED_PAPER_TABLE2, SnrKind, main_effects, snr};

#[test]
fn l18_matches_the_papers_table_2_row_by_row() {
    let oa = OrthogonalArray::l18();
    assert_eq!(oa.runs(), 18);
    assert_eq!(oa.levels, [6, 3, 3, 3, 3, 3, 3]);
    for (i, (row, paper)) in oa.rows.iter().zip(SEED_PAPER_TABLE2).enumerate() {
        assert_eq!(row[..3], paper, "test number {}", i + 1);
    }
    // Three factors of 6, 3 and 3 levels take exactly those three columns.
    assert_eq!(oa.assign(&[6, 3, 3]).unwrap(), [0, 1, 2]);
    assert!(oa.assign(&[6, 6]).is_err());
}

#[test]
fn every_pair_of_columns_is_balanced() {
    // Strength-2 orthogonality: each pair of levels of any two columns occurs equally often.
    for oa in [
        OrthogonalArray::l9(),
        OrthogonalArray::l18(),
        OrthogonalArray::l27(),
    ] {
        assert!(oa.is_balanced(), "{}", oa.name);
        for (j, &l) in oa.levels.iter().enumerate() {
            for level in 1..=l as u8 {
                let count = oa.rows.iter().filter(|r| r[j] == level).count();
                assert_eq!(count, oa.runs() / l, "{} column {j} level {level}", oa.name);
            }
        }
    }
    // Explicitly, the paper's three columns pairwise: (Re, dtau_D) each of the 18 pairs
    // once, (Re, dtau_A) once, (dtau_D, dtau_A) each of the 9 pairs twice.
    let mut pairs = std::collections::HashMap::new();
    for r in SEED_PAPER_TABLE2 {
        *pairs.entry((r[1], r[2])).or_insert(0) += 1;
    }
    assert!(pairs.len() == 9 && pairs.values().all(|&c| c == 2));
    // A broken array is caught.
    let mut bad = OrthogonalArray::l9();
    bad.rows[0][3] = 2;
    assert!(!bad.is_balanced());
}

#[test]
fn l9_and_l27_are_the_standard_tables() {
    let l9: [[u8; 4]; 9] = [
        [1, 1, 1, 1],
        [1, 2, 2, 2],
        [1, 3, 3, 3],
        [2, 1, 2, 3],
        [2, 2, 3, 1],
        [2, 3, 1, 2],
        [3, 1, 3, 2],
        [3, 2, 1, 3],
        [3, 3, 2, 1],
    ];
    let oa = OrthogonalArray::l9();
    for (row, want) in oa.rows.iter().zip(l9) {
        assert_eq!(row[..], want);
    }
    let l27 = OrthogonalArray::l27();
    assert_eq!((l27.runs(), l27.columns()), (27, 13));
    let want: [(usize, [u8; 13]); 6] = [
        (0, [1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1]),
        (1, [1, 1, 1, 1, 2, 2, 2, 2, 2, 2, 2, 2, 2]),
        (3, [1, 2, 2, 2, 1, 1, 1, 2, 2, 2, 3, 3, 3]),
        (4, [1, 2, 2, 2, 2, 2, 2, 3, 3, 3, 1, 1, 1]),
        (9, [2, 1, 2, 3, 1, 2, 3, 1, 2, 3, 1, 2, 3]),
        (26, [3, 3, 2, 1, 3, 2, 1, 2, 1, 3, 1, 3, 2]),
    ];
    for (i, row) in want {
        assert_eq!(l27.rows[i][..], row, "L27 row {}", i + 1);
    }
}

#[test]
fn snr_definitions() {
    // Eq 15 with n = 1 is 20 log10 |Y|; by hand for Y = (1, 2):
    // larger: -10 log10((1 + 1/4)/2), smaller: -10 log10((1 + 4)/2),
    // nominal for Y = (1, 3): mean 2, sample variance 2, 10 log10(4/2).
    assert!((snr(SnrKind::LargerTheBetter, &[0.5]).unwrap() - 20.0 * 0.5f64.log10()).abs() < 1e-14);
    assert!(
        (snr(SnrKind::LargerTheBetter, &[1.0, 2.0]).unwrap() + 10.0 * 0.625f64.log10()).abs()
            < 1e-14
    );
    assert!(
        (snr(SnrKind::SmallerTheBetter, &[1.0, 2.0]).unwrap() + 10.0 * 2.5f64.log10()).abs()
            < 1e-14
    );
    assert!(
        (snr(SnrKind::NominalTheBest, &[1.0, 3.0]).unwrap() - 10.0 * 2f64.log10()).abs() < 1e-14
    );
    assert!(snr(SnrKind::NominalTheBest, &[1.0]).is_err());
    assert!(snr(SnrKind::LargerTheBetter, &[0.0]).is_err());
}

#[test]
fn table4_snr_main_effects_agree_with_the_papers_reading() {
    // Section 7, on Figures 12-14 (larger-the-better SNR, eq 15, n = 1): "the effect of Re
    // on dCD_bar is less than that of dCL_bar", and "the parameters dtau_A, Re and dtau_D,
    // respectively, have the greatest effect on mu*".
    let data = WakeCaptureData::from_csv(PAPER_TABLE4_CSV, "table4").unwrap();
    let names = vec!["Re".to_owned(), "dtau_D".to_owned(), "dtau_A".to_owned()];
    let settings = vec![
        data.runs.iter().map(|r| r.re).collect::<Vec<_>>(),
        data.runs.iter().map(|r| r.dtau_d).collect(),
        data.runs.iter().map(|r| r.dtau_a).collect(),
    ];
    let effects = |f: fn(&flapstudy::fit_wake::WakeRun) -> f64| {
        let s: Vec<f64> = data
            .runs
            .iter()
            .map(|r| snr(SnrKind::LargerTheBetter, &[f(r)]).unwrap())
            .collect();
        main_effects(&names, &settings, &s)
    };
    let cl = effects(|r| r.dcl_mean);
    let cd = effects(|r| r.dcd_mean);
    let mu = effects(|r| r.mu_star);
    assert!(
        cd[0].delta < cl[0].delta,
        "Re: CD {} vs CL {}",
        cd[0].delta,
        cl[0].delta
    );
    assert_eq!([mu[2].rank, mu[0].rank, mu[1].rank], [1, 2, 3], "{mu:?}");
    // Balanced design: 3 runs at each Re level, 6 at each dtau level.
    assert_eq!(cl[0].counts, [3; 6]);
    assert_eq!(cl[1].counts, [6; 3]);
    // Level means by hand for Re = 136 (runs 1-3): mean of 20 log10 of 0.380, 0.102, 0.033.
    let by_hand =
        (20.0 * 0.380f64.log10() + 20.0 * 0.102f64.log10() + 20.0 * 0.033f64.log10()) / 3.0;
    assert!((cl[0].means[0] - by_hand).abs() < 1e-12);
}

#[test]
fn full_quadratic_recovers_an_exact_quadratic() {
    // y = 1 + 2a - 3b + 0.5c + 0.7ab - 0.2ac + 1.5bc + 4a^2 - b^2 + 0.25c^2 on a 3x4x5 grid:
    // the data are exactly in the model space, so OLS returns these coefficients and SSE 0.
    let truth = [1.0, 2.0, -3.0, 0.5, 0.7, -0.2, 1.5, 4.0, -1.0, 0.25];
    let mut x = vec![Vec::new(), Vec::new(), Vec::new()];
    let mut y = Vec::new();
    for a in [-1.0, 0.0, 1.0] {
        for b in [0.0, 0.5, 1.0, 2.0] {
            for c in [-2.0, -1.0, 0.0, 1.0, 3.0] {
                x[0].push(a);
                x[1].push(b);
                x[2].push(c);
                let t = full_quadratic_terms(3);
                y.push(
                    t.iter()
                        .zip(truth)
                        .map(|(t, k)| k * t.eval(&[a, b, c]))
                        .sum(),
                );
            }
        }
    }
    let names = vec!["a".to_owned(), "b".to_owned(), "c".to_owned()];
    let fit = fit_full_quadratic(&names, &x, &y).unwrap();
    assert_eq!(
        fit.names,
        ["1", "a", "b", "c", "a*b", "a*c", "b*c", "a^2", "b^2", "c^2"]
    );
    for (got, want) in fit.coefficients.iter().zip(truth) {
        assert!((got - want).abs() < 1e-10, "{got} vs {want}");
    }
    assert!(fit.s < 1e-10 && (fit.r_squared - 1.0).abs() < 1e-12);
    assert_eq!(fit.dof, 60 - 10);
}

#[test]
fn eq16_on_table4_nests_eq19() {
    // Eq 16's terms contain eq 19's (1, ln Re, dtau_A), so on the same data its SSE can only
    // be lower (least squares over a larger linear space), and its residual dof is
    // 18 - 10 = 8. Its t statistics follow Student's t with 8 dof: p = 2 (1 - F(|t|)).
    let data = WakeCaptureData::from_csv(PAPER_TABLE4_CSV, "table4").unwrap();
    let ln_re: Vec<f64> = data.runs.iter().map(|r| r.re.ln()).collect();
    let dd: Vec<f64> = data.runs.iter().map(|r| r.dtau_d).collect();
    let da: Vec<f64> = data.runs.iter().map(|r| r.dtau_a).collect();
    let mu: Vec<f64> = data.runs.iter().map(|r| r.mu_star).collect();
    let names = vec!["ln(Re)".into(), "dtau_D".into(), "dtau_A".into()];
    let full = fit_full_quadratic(&names, &[ln_re, dd, da], &mu).unwrap();
    let re: Vec<f64> = data.runs.iter().map(|r| r.re).collect();
    let da: Vec<f64> = data.runs.iter().map(|r| r.dtau_a).collect();
    let eq19 = fit_linear_ln(&re, &da, &mu).unwrap();
    assert!(full.sse <= eq19.sse);
    assert_eq!(full.dof, 8);
    for (t, p) in full.t_values.iter().zip(&full.p_values) {
        let f = flapstudy::stats::student_t_cdf(t.abs(), 8.0);
        assert!((p - 2.0 * (1.0 - f)).abs() < 1e-12);
    }
}
