//! Taguchi orthogonal arrays, signal-to-noise ratios (the seed paper's eq 15 and its two
//! companions) and main effects.
//!
//! Arrays (levels numbered from 1, as printed in the tables):
//! - L9(3^4): the standard array; column values (a, b, a + b, 2a + b) mod 3 + 1 over the
//!   nine (a, b) in GF(3)^2, row order a slowest.
//! - L18(6^1 x 3^6): the standard L18(2^1 x 3^7) with its two-level column and first
//!   three-level column merged into one six-level column (6-level = 3 (A - 1) + B). Its first
//!   three columns are exactly the seed paper's Table 2, L18(6^1 x 3^2) (Re, dtau_D, dtau_A).
//! - L27(3^13): the standard array; column j holds (u_j . (a, b, c)) mod 3 + 1 over the 27
//!   (a, b, c) in GF(3)^3 (row order a slowest, c fastest), with the 13 coefficient vectors
//!   u_j = (100, 010, 110, 210, 001, 101, 201, 011, 111, 211, 021, 121, 221) in Taguchi's
//!   column order: one vector for each of the 13 points of the projective plane PG(2, 3),
//!   so every pair of columns is linearly independent over GF(3) and hence balanced.
//!
//! SNR (in dB, n responses Y_j of one factor-level combination):
//! - larger-the-better, eq 15: SNR = -10 log10( (1/n) sum 1/Y_j^2 );
//! - smaller-the-better: SNR = -10 log10( (1/n) sum Y_j^2 );
//! - nominal-the-best: SNR = 10 log10( Ybar^2 / s^2 ) with s^2 the sample variance (n >= 2).
//!
//! (e.g. Phadke, *Quality Engineering Using Robust Design*, 1989, ch. 5.)

use serde::{Deserialize, Serialize};

use super::error::{StudyError, StudyResult};

/// The seed paper's Table 2, L18(6^1 x 3^2): the (Re, dtau_D, dtau_A) levels (numbered from
/// 1) of its CFD tests 1-18. Published data, for checking designs against the paper.
pub const SEED_PAPER_TABLE2: [[u8; 3]; 18] = [
    [1, 1, 1],
    [1, 2, 2],
    [1, 3, 3],
    [2, 1, 1],
    [2, 2, 2],
    [2, 3, 3],
    [3, 1, 2],
    [3, 2, 3],
    [3, 3, 1],
    [4, 1, 3],
    [4, 2, 1],
    [4, 3, 2],
    [5, 1, 2],
    [5, 2, 3],
    [5, 3, 1],
    [6, 1, 3],
    [6, 2, 1],
    [6, 3, 2],
];

/// An orthogonal array: `rows[i][j]` is the level (1-based) of column j in run i.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct OrthogonalArray {
    /// Name, e.g. `L18(6^1 x 3^6)`.
    pub name: &'static str,
    /// Number of levels of each column.
    pub levels: Vec<usize>,
    /// Runs x columns, levels from 1.
    pub rows: Vec<Vec<u8>>,
}

/// The standard L18(2^1 x 3^7) (Taguchi's table; e.g. Phadke 1989, appendix C).
const L18_2_3: [[u8; 8]; 18] = [
    [1, 1, 1, 1, 1, 1, 1, 1],
    [1, 1, 2, 2, 2, 2, 2, 2],
    [1, 1, 3, 3, 3, 3, 3, 3],
    [1, 2, 1, 1, 2, 2, 3, 3],
    [1, 2, 2, 2, 3, 3, 1, 1],
    [1, 2, 3, 3, 1, 1, 2, 2],
    [1, 3, 1, 2, 1, 3, 2, 3],
    [1, 3, 2, 3, 2, 1, 3, 1],
    [1, 3, 3, 1, 3, 2, 1, 2],
    [2, 1, 1, 3, 3, 2, 2, 1],
    [2, 1, 2, 1, 1, 3, 3, 2],
    [2, 1, 3, 2, 2, 1, 1, 3],
    [2, 2, 1, 2, 3, 1, 3, 2],
    [2, 2, 2, 3, 1, 2, 1, 3],
    [2, 2, 3, 1, 2, 3, 2, 1],
    [2, 3, 1, 3, 2, 3, 1, 2],
    [2, 3, 2, 1, 3, 1, 2, 3],
    [2, 3, 3, 2, 1, 2, 3, 1],
];

impl OrthogonalArray {
    /// L9(3^4).
    pub fn l9() -> Self {
        let cols: [[u8; 2]; 4] = [[1, 0], [0, 1], [1, 1], [2, 1]];
        let rows = (0..9u8)
            .map(|r| {
                let (a, b) = (r / 3, r % 3);
                cols.iter().map(|u| (u[0] * a + u[1] * b) % 3 + 1).collect()
            })
            .collect();
        Self {
            name: "L9(3^4)",
            levels: vec![3; 4],
            rows,
        }
    }

    /// L18(6^1 x 3^6); its first three columns are the seed paper's Table 2.
    pub fn l18() -> Self {
        let rows = L18_2_3
            .iter()
            .map(|r| {
                let mut row = vec![3 * (r[0] - 1) + r[1]];
                row.extend_from_slice(&r[2..]);
                row
            })
            .collect();
        let mut levels = vec![6];
        levels.extend([3; 6]);
        Self {
            name: "L18(6^1 x 3^6)",
            levels,
            rows,
        }
    }

    /// L27(3^13).
    pub fn l27() -> Self {
        let cols: [[u8; 3]; 13] = [
            [1, 0, 0],
            [0, 1, 0],
            [1, 1, 0],
            [2, 1, 0],
            [0, 0, 1],
            [1, 0, 1],
            [2, 0, 1],
            [0, 1, 1],
            [1, 1, 1],
            [2, 1, 1],
            [0, 2, 1],
            [1, 2, 1],
            [2, 2, 1],
        ];
        let rows = (0..27u8)
            .map(|r| {
                let (a, b, c) = (r / 9, (r / 3) % 3, r % 3);
                cols.iter()
                    .map(|u| (u[0] * a + u[1] * b + u[2] * c) % 3 + 1)
                    .collect()
            })
            .collect();
        Self {
            name: "L27(3^13)",
            levels: vec![3; 13],
            rows,
        }
    }

    /// Number of runs.
    pub fn runs(&self) -> usize {
        self.rows.len()
    }

    /// Number of columns.
    pub fn columns(&self) -> usize {
        self.levels.len()
    }

    /// True when every pair of columns is balanced: each pair of levels occurs equally often
    /// (the defining property of an orthogonal array of strength 2).
    pub fn is_balanced(&self) -> bool {
        let n = self.runs();
        for i in 0..self.columns() {
            for j in (i + 1)..self.columns() {
                let (li, lj) = (self.levels[i], self.levels[j]);
                if n % (li * lj) != 0 {
                    return false;
                }
                let mut counts = vec![0usize; li * lj];
                for row in &self.rows {
                    let (a, b) = (row[i] as usize, row[j] as usize);
                    if a == 0 || a > li || b == 0 || b > lj {
                        return false;
                    }
                    counts[(a - 1) * lj + (b - 1)] += 1;
                }
                if counts.iter().any(|&c| c != n / (li * lj)) {
                    return false;
                }
            }
        }
        true
    }

    /// Assigns factors with the given numbers of levels to columns: each factor, in order,
    /// takes the first unused column with its number of levels. Returns the column indices,
    /// or an error saying which factor does not fit.
    pub fn assign(&self, factor_levels: &[usize]) -> Result<Vec<usize>, String> {
        let mut used = vec![false; self.columns()];
        let mut out = Vec::with_capacity(factor_levels.len());
        for (f, &l) in factor_levels.iter().enumerate() {
            let Some(c) = (0..self.columns()).find(|&c| !used[c] && self.levels[c] == l) else {
                let avail: Vec<String> = (0..self.columns())
                    .filter(|&c| !used[c])
                    .map(|c| self.levels[c].to_string())
                    .collect();
                return Err(format!(
                    "factor {} has {l} levels, but {} has no free column with {l} levels (free columns have levels: [{}]; the columns are {:?})",
                    f + 1,
                    self.name,
                    avail.join(", "),
                    self.levels
                ));
            };
            used[c] = true;
            out.push(c);
        }
        Ok(out)
    }
}

/// Which SNR.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SnrKind {
    /// Larger the better (the seed paper's eq 15).
    LargerTheBetter,
    /// Smaller the better.
    SmallerTheBetter,
    /// Nominal the best (needs replicates).
    NominalTheBest,
}

impl SnrKind {
    /// Parses `larger`, `smaller` or `nominal` (or the full snake-case names).
    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "larger" | "larger_the_better" => Some(Self::LargerTheBetter),
            "smaller" | "smaller_the_better" => Some(Self::SmallerTheBetter),
            "nominal" | "nominal_the_best" => Some(Self::NominalTheBest),
            _ => None,
        }
    }
}

/// The SNR of the responses `ys` of one factor-level combination, dB.
pub fn snr(kind: SnrKind, ys: &[f64]) -> StudyResult<f64> {
    let n = ys.len() as f64;
    if ys.is_empty() {
        return Err(StudyError::Fit("SNR of no responses".to_owned()));
    }
    match kind {
        SnrKind::LargerTheBetter => {
            if ys.contains(&0.0) {
                return Err(StudyError::Fit(
                    "larger-the-better SNR (eq 15) is undefined for a response of 0".to_owned(),
                ));
            }
            Ok(-10.0 * (ys.iter().map(|y| 1.0 / (y * y)).sum::<f64>() / n).log10())
        }
        SnrKind::SmallerTheBetter => {
            Ok(-10.0 * (ys.iter().map(|y| y * y).sum::<f64>() / n).log10())
        }
        SnrKind::NominalTheBest => {
            if ys.len() < 2 {
                return Err(StudyError::Fit(
                    "nominal-the-best SNR needs at least 2 replicate responses per combination (10 log10(mean^2/variance))".to_owned(),
                ));
            }
            let mean = ys.iter().sum::<f64>() / n;
            let var = ys.iter().map(|y| (y - mean) * (y - mean)).sum::<f64>() / (n - 1.0);
            if var == 0.0 {
                return Err(StudyError::Fit(
                    "nominal-the-best SNR is undefined when the replicates do not vary".to_owned(),
                ));
            }
            Ok(10.0 * (mean * mean / var).log10())
        }
    }
}

/// The main effect of one factor: the mean of a value (an SNR or a response) at each level.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MainEffect {
    /// Factor name.
    pub factor: String,
    /// The distinct levels, ascending.
    pub levels: Vec<f64>,
    /// Mean of the value over the runs at each level.
    pub means: Vec<f64>,
    /// Number of runs at each level.
    pub counts: Vec<usize>,
    /// max(means) - min(means).
    pub delta: f64,
    /// Rank of delta among the factors (1 = largest effect).
    pub rank: usize,
}

/// Main effects of each factor on `values`: `settings[f][i]` is factor f's value in run i.
pub fn main_effects(names: &[String], settings: &[Vec<f64>], values: &[f64]) -> Vec<MainEffect> {
    let mut out: Vec<MainEffect> = names
        .iter()
        .zip(settings)
        .map(|(name, s)| {
            let mut levels: Vec<f64> = s.clone();
            levels.sort_by(f64::total_cmp);
            levels.dedup();
            let mut sums = vec![0.0; levels.len()];
            let mut counts = vec![0usize; levels.len()];
            for (x, v) in s.iter().zip(values) {
                let k = levels.partition_point(|l| l < x);
                sums[k] += v;
                counts[k] += 1;
            }
            let means: Vec<f64> = sums
                .iter()
                .zip(&counts)
                .map(|(s, &c)| s / c as f64)
                .collect();
            let hi = means.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            let lo = means.iter().copied().fold(f64::INFINITY, f64::min);
            MainEffect {
                factor: name.clone(),
                levels,
                means,
                counts,
                delta: hi - lo,
                rank: 0,
            }
        })
        .collect();
    let mut order: Vec<usize> = (0..out.len()).collect();
    order.sort_by(|&a, &b| out[b].delta.total_cmp(&out[a].delta));
    for (r, &i) in order.iter().enumerate() {
        out[i].rank = r + 1;
    }
    out
}
