//! The designs: the factor values of every case (full factorial, Taguchi arrays, Latin
//! hypercube) and the seeded generator behind the Latin hypercube.

use super::super::taguchi::OrthogonalArray;
use super::file::{DesignKind, MAX_CASES, StudySpec};
use super::study::Factor;

/// SplitMix64 (Steele, Lea and Flood 2014): a small, fast, well-mixed generator; the same
/// seed gives the same Latin hypercube on every platform.
#[derive(Debug, Clone)]
pub struct SplitMix64(u64);

impl SplitMix64 {
    /// A generator from a seed.
    pub fn new(seed: u64) -> Self {
        Self(seed)
    }
    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// A uniform number in [0, 1) with 53 random bits.
    pub fn next_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
    /// A uniform integer in [0, n) (n > 0), by rejection (no modulo bias).
    pub fn below(&mut self, n: u64) -> u64 {
        let zone = u64::MAX - u64::MAX % n;
        loop {
            let x = self.next_u64();
            if x < zone {
                return x % n;
            }
        }
    }
}

/// A Latin hypercube of `n` samples over the given ranges: in every factor each of the n
/// equal strata holds exactly one sample, placed uniformly inside it (McKay, Beckman and
/// Conover 1979).
pub fn latin_hypercube(ranges: &[(f64, f64)], n: usize, seed: u64) -> Vec<Vec<f64>> {
    let mut rng = SplitMix64::new(seed);
    let mut cols: Vec<Vec<f64>> = Vec::with_capacity(ranges.len());
    for &(lo, hi) in ranges {
        let mut perm: Vec<usize> = (0..n).collect();
        for i in (1..n).rev() {
            let j = rng.below(i as u64 + 1) as usize;
            perm.swap(i, j);
        }
        cols.push(
            perm.iter()
                .map(|&s| lo + (hi - lo) * (s as f64 + rng.next_f64()) / n as f64)
                .collect(),
        );
    }
    (0..n)
        .map(|i| cols.iter().map(|c| c[i]).collect())
        .collect()
}

pub(super) fn generate_cases(
    spec: &StudySpec,
    factors: &[Factor],
) -> Result<Vec<Vec<f64>>, String> {
    if spec.design != DesignKind::LatinHypercube && (spec.samples.is_some() || spec.seed.is_some())
    {
        return Err(format!(
            "`samples` and `seed` belong to latin_hypercube, not {}",
            spec.design.name()
        ));
    }
    let taguchi = |oa: OrthogonalArray| -> Result<Vec<Vec<f64>>, String> {
        let counts: Vec<usize> = factors.iter().map(|f| f.levels.len()).collect();
        let cols = oa.assign(&counts)?;
        Ok(oa
            .rows
            .iter()
            .map(|row| {
                factors
                    .iter()
                    .zip(&cols)
                    .map(|(f, &c)| f.levels[row[c] as usize - 1])
                    .collect()
            })
            .collect())
    };
    match spec.design {
        DesignKind::FullFactorial => {
            let total = factors
                .iter()
                .try_fold(1usize, |acc, f| acc.checked_mul(f.levels.len()))
                .filter(|&t| t <= MAX_CASES)
                .ok_or_else(|| format!("the full factorial has more than {MAX_CASES} cases"))?;
            Ok((0..total)
                .map(|mut i| {
                    let mut v = vec![0.0; factors.len()];
                    for (slot, f) in v.iter_mut().zip(factors).rev() {
                        *slot = f.levels[i % f.levels.len()];
                        i /= f.levels.len();
                    }
                    v
                })
                .collect())
        }
        DesignKind::LatinHypercube => {
            let n = spec
                .samples
                .ok_or("latin_hypercube needs `samples` (the number of cases)")?;
            if !(1..=MAX_CASES).contains(&n) {
                return Err(format!("`samples` = {n}: an integer in [1, {MAX_CASES}]"));
            }
            let ranges: Vec<(f64, f64)> = factors
                .iter()
                .map(|f| f.range.expect("latin hypercube factors have ranges"))
                .collect();
            Ok(latin_hypercube(&ranges, n, spec.seed.unwrap_or(0)))
        }
        DesignKind::TaguchiL9 => taguchi(OrthogonalArray::l9()),
        DesignKind::TaguchiL18 => taguchi(OrthogonalArray::l18()),
        DesignKind::TaguchiL27 => taguchi(OrthogonalArray::l27()),
    }
}
