//! The full second-order linear regression of the seed paper's eq 16, for any number of
//! factors: constant, linear terms, every pairwise interaction and every square,
//! `RESP = b0 + sum_i b_i x_i + sum_{i<j} b_ij x_i x_j + sum_i b_ii x_i^2`, in that order
//! (for the paper's three factors x = (ln Re, dtau_D, dtau_A) this is exactly eq 16's term
//! order b0..b9). Fitted by ordinary least squares with standard errors, t values and
//! p-values ([`super::stats::ols`]).

use nalgebra::DMatrix;

use super::error::StudyResult;
use super::stats::{LinearFit, ols};

/// One term of a polynomial model: the product of the listed factor indices (empty = 1).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Term(pub Vec<usize>);

impl Term {
    /// The term's name from the factor names, e.g. `x1*x2`, `x1^2`, `1`.
    pub fn name(&self, factors: &[String]) -> String {
        match self.0.as_slice() {
            [] => "1".to_owned(),
            [i] => factors[*i].clone(),
            [i, j] if i == j => format!("{}^2", factors[*i]),
            idx => idx
                .iter()
                .map(|&i| factors[i].as_str())
                .collect::<Vec<_>>()
                .join("*"),
        }
    }

    /// The term's value for one observation `x`.
    pub fn eval(&self, x: &[f64]) -> f64 {
        self.0.iter().map(|&i| x[i]).product()
    }
}

/// The terms of eq 16 for `k` factors: 1, x_i, x_i x_j (i < j), x_i^2.
pub fn full_quadratic_terms(k: usize) -> Vec<Term> {
    let mut terms = vec![Term(vec![])];
    terms.extend((0..k).map(|i| Term(vec![i])));
    for i in 0..k {
        for j in (i + 1)..k {
            terms.push(Term(vec![i, j]));
        }
    }
    terms.extend((0..k).map(|i| Term(vec![i, i])));
    terms
}

/// Fits `y` on the given terms of the factors; `x[f][i]` is factor f in observation i.
pub fn fit_terms(
    factor_names: &[String],
    terms: &[Term],
    x: &[Vec<f64>],
    y: &[f64],
) -> StudyResult<LinearFit> {
    let n = y.len();
    let design = DMatrix::from_fn(n, terms.len(), |i, j| {
        let obs: Vec<f64> = x.iter().map(|col| col[i]).collect();
        terms[j].eval(&obs)
    });
    let names = terms.iter().map(|t| t.name(factor_names)).collect();
    ols(names, &design, y)
}

/// The full second-order regression of eq 16 of `y` on the factors `x`.
pub fn fit_full_quadratic(
    factor_names: &[String],
    x: &[Vec<f64>],
    y: &[f64],
) -> StudyResult<LinearFit> {
    fit_terms(factor_names, &full_quadratic_terms(x.len()), x, y)
}
