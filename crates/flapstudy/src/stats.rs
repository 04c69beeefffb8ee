//! Statistics for the study tools: the regularized incomplete beta function (by its
//! continued fraction), Student's t distribution, and ordinary least squares with
//! coefficient standard errors, t values and two-sided p-values.
//!
//! References: the continued fraction of I_x(a, b) and its evaluation by the modified Lentz
//! method are those of Press et al., *Numerical Recipes* (3rd ed., section 6.4); the t
//! distribution's CDF is F(t) = 1 - I_{nu/(nu+t^2)}(nu/2, 1/2) / 2 for t > 0 (Abramowitz and
//! Stegun 26.7.1 with 26.5.27); the regression statistics are the textbook ones (e.g.
//! Montgomery, Peck and Vining, *Introduction to Linear Regression Analysis*, ch. 3):
//! S^2 = SSE / (n - p), Cov(beta) = S^2 (X^T X)^-1, t_j = beta_j / SE_j.

use std::f64::consts::PI;

use nalgebra::{DMatrix, DVector};
use serde::Serialize;

use super::error::{StudyError, StudyResult};

/// ln Gamma(x) for x > 0: Lanczos' approximation with g = 7 and nine coefficients
/// (Godfrey's set; relative error below 1e-15 over the positive axis), with the reflection
/// formula below 0.5.
pub fn ln_gamma(x: f64) -> f64 {
    const G: f64 = 7.0;
    const C: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    if x < 0.5 {
        (PI / (PI * x).sin().abs()).ln() - ln_gamma(1.0 - x)
    } else {
        let x = x - 1.0;
        let t = x + G + 0.5;
        let mut a = C[0];
        for (i, c) in C.iter().enumerate().skip(1) {
            a += c / (x + i as f64);
        }
        0.5 * (2.0 * PI).ln() + (x + 0.5) * t.ln() - t + a.ln()
    }
}

/// The regularized incomplete beta function I_x(a, b) for a, b > 0 and x in [0, 1]: the
/// continued fraction of Numerical Recipes (eq 6.4.5) evaluated by the modified Lentz
/// method, applied directly for x < (a + 1)/(a + b + 2) and through
/// I_x(a, b) = 1 - I_{1-x}(b, a) otherwise, where it converges fast.
pub fn beta_inc_reg(a: f64, b: f64, x: f64) -> f64 {
    assert!(a > 0.0 && b > 0.0, "beta_inc_reg needs a, b > 0");
    if x.is_nan() {
        return f64::NAN;
    }
    if x <= 0.0 {
        return 0.0;
    }
    if x >= 1.0 {
        return 1.0;
    }
    let ln_front = ln_gamma(a + b) - ln_gamma(a) - ln_gamma(b) + a * x.ln() + b * (1.0 - x).ln();
    if x < (a + 1.0) / (a + b + 2.0) {
        ln_front.exp() * beta_cf(a, b, x) / a
    } else {
        1.0 - ln_front.exp() * beta_cf(b, a, 1.0 - x) / b
    }
}

fn beta_cf(a: f64, b: f64, x: f64) -> f64 {
    const TINY: f64 = 1e-300;
    const EPS: f64 = 1e-16;
    let fix = |v: f64| if v.abs() < TINY { TINY } else { v };
    let (qab, qap, qam) = (a + b, a + 1.0, a - 1.0);
    let mut c = 1.0;
    let mut d = 1.0 / fix(1.0 - qab * x / qap);
    let mut h = d;
    for m in 1..=10_000 {
        let m = m as f64;
        let m2 = 2.0 * m;
        let aa = m * (b - m) * x / ((qam + m2) * (a + m2));
        d = 1.0 / fix(1.0 + aa * d);
        c = fix(1.0 + aa / c);
        h *= d * c;
        let aa = -(a + m) * (qab + m) * x / ((a + m2) * (qap + m2));
        d = 1.0 / fix(1.0 + aa * d);
        c = fix(1.0 + aa / c);
        let del = d * c;
        h *= del;
        if (del - 1.0).abs() < EPS {
            break;
        }
    }
    h
}

/// The CDF of Student's t distribution with `nu` > 0 degrees of freedom.
pub fn student_t_cdf(t: f64, nu: f64) -> f64 {
    let tail = 0.5 * beta_inc_reg(0.5 * nu, 0.5, nu / (nu + t * t));
    if t > 0.0 { 1.0 - tail } else { tail }
}

/// The two-sided p-value P(|T| >= |t|) of Student's t with `nu` degrees of freedom.
pub fn student_t_two_sided_p(t: f64, nu: f64) -> f64 {
    beta_inc_reg(0.5 * nu, 0.5, nu / (nu + t * t))
}

/// Least squares of `x beta = y` through an SVD of the column-scaled design; returns the
/// coefficients and the scaled pseudo-inverse pieces needed for the covariance, or `None`
/// when the design is numerically rank deficient (a column is a combination of others).
pub(crate) struct Lstsq {
    pub beta: DVector<f64>,
    /// (X^T X)^-1 of the unscaled design.
    pub xtx_inv: DMatrix<f64>,
}

pub(crate) fn lstsq(x: &DMatrix<f64>, y: &DVector<f64>) -> Option<Lstsq> {
    let p = x.ncols();
    let norms: Vec<f64> = (0..p).map(|j| x.column(j).norm()).collect();
    if norms.iter().any(|&s| s == 0.0 || !s.is_finite()) {
        return None;
    }
    let mut xs = x.clone();
    for (j, s) in norms.iter().enumerate() {
        xs.column_mut(j).scale_mut(1.0 / s);
    }
    let svd = xs.svd(true, true);
    let sv = &svd.singular_values;
    let smax = sv.max();
    let smin = sv.min();
    if !(smin > smax * 1e-10) {
        return None;
    }
    let u = svd.u.as_ref()?;
    let vt = svd.v_t.as_ref()?;
    let uty = u.transpose() * y;
    let mut beta = DVector::zeros(p);
    let mut xtx_inv = DMatrix::zeros(p, p);
    for k in 0..p {
        let vk = vt.row(k).transpose();
        beta += &vk * (uty[k] / sv[k]);
        xtx_inv += &vk * vk.transpose() / (sv[k] * sv[k]);
    }
    for j in 0..p {
        beta[j] /= norms[j];
        for k in 0..p {
            xtx_inv[(j, k)] /= norms[j] * norms[k];
        }
    }
    Some(Lstsq { beta, xtx_inv })
}

/// An ordinary least-squares fit with its statistics.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LinearFit {
    /// Term names, in the order of the design's columns.
    pub names: Vec<String>,
    /// Coefficients.
    pub coefficients: Vec<f64>,
    /// Standard errors of the coefficients, sqrt(S^2 (X^T X)^-1_jj).
    pub std_errors: Vec<f64>,
    /// t values coefficient / standard error.
    pub t_values: Vec<f64>,
    /// Two-sided p-values of the t values with n - p degrees of freedom.
    pub p_values: Vec<f64>,
    /// Fitted values.
    pub fitted: Vec<f64>,
    /// Residuals y - fitted.
    pub residuals: Vec<f64>,
    /// Sum of squared residuals.
    pub sse: f64,
    /// Standard error of the regression S = sqrt(SSE / (n - p)).
    pub s: f64,
    /// Coefficient of determination 1 - SSE/SST (SST about the mean of y).
    pub r_squared: f64,
    /// Adjusted R^2 = 1 - (1 - R^2)(n - 1)/(n - p).
    pub adj_r_squared: f64,
    /// Number of observations n.
    pub n: usize,
    /// Residual degrees of freedom n - p.
    pub dof: usize,
}

/// Ordinary least squares of `y` on the columns of `x` (include a column of ones for a
/// constant). Needs n > p and a full-rank design.
pub fn ols(names: Vec<String>, x: &DMatrix<f64>, y: &[f64]) -> StudyResult<LinearFit> {
    let (n, p) = x.shape();
    assert_eq!(names.len(), p, "one name per design column");
    assert_eq!(y.len(), n, "one response per design row");
    if n <= p {
        return Err(StudyError::Fit(format!(
            "{n} observations cannot fit {p} coefficients with an error estimate: at least {} are needed",
            p + 1
        )));
    }
    let yv = DVector::from_column_slice(y);
    let sol = lstsq(x, &yv).ok_or_else(|| {
        StudyError::Fit(format!(
            "the design matrix of terms [{}] is rank deficient: some term is a linear combination of others for these data (too few distinct levels?)",
            names.join(", ")
        ))
    })?;
    let fitted = x * &sol.beta;
    let residuals = &yv - &fitted;
    let sse = residuals.norm_squared();
    let dof = n - p;
    let s2 = sse / dof as f64;
    let mean = yv.mean();
    let sst: f64 = yv.iter().map(|v| (v - mean) * (v - mean)).sum();
    let r_squared = if sst > 0.0 { 1.0 - sse / sst } else { f64::NAN };
    let adj_r_squared = 1.0 - (1.0 - r_squared) * (n as f64 - 1.0) / dof as f64;
    let std_errors: Vec<f64> = (0..p).map(|j| (s2 * sol.xtx_inv[(j, j)]).sqrt()).collect();
    let coefficients: Vec<f64> = sol.beta.iter().copied().collect();
    let t_values: Vec<f64> = coefficients
        .iter()
        .zip(&std_errors)
        .map(|(b, se)| b / se)
        .collect();
    let p_values = t_values
        .iter()
        .map(|&t| {
            if t.is_nan() {
                f64::NAN
            } else {
                student_t_two_sided_p(t, dof as f64)
            }
        })
        .collect();
    Ok(LinearFit {
        names,
        coefficients,
        std_errors,
        t_values,
        p_values,
        fitted: fitted.iter().copied().collect(),
        residuals: residuals.iter().copied().collect(),
        sse,
        s: s2.sqrt(),
        r_squared,
        adj_r_squared,
        n,
        dof,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gamma_values() {
        // Gamma(5) = 4! = 24, Gamma(1/2) = sqrt(pi), Gamma(1) = 1 (exact identities).
        assert!((ln_gamma(5.0) - 24f64.ln()).abs() < 1e-13);
        assert!((ln_gamma(0.5) - PI.sqrt().ln()).abs() < 1e-13);
        assert!(ln_gamma(1.0).abs() < 1e-14);
        assert!((ln_gamma(0.1) - 9.513_507_698_668_732f64.ln()).abs() < 1e-12);
    }

    #[test]
    fn incomplete_beta_closed_forms() {
        // I_x(a, 1) = x^a, I_x(1, b) = 1 - (1 - x)^b, I_x(a, b) = 1 - I_{1-x}(b, a), and
        // I_x(1/2, 1/2) = (2/pi) asin(sqrt(x)) (all from the integral's definition).
        for &x in &[0.01, 0.2, 0.5, 0.77, 0.999] {
            for &a in &[0.5, 1.0, 2.5, 7.0] {
                assert!((beta_inc_reg(a, 1.0, x) - x.powf(a)).abs() < 1e-13);
                assert!((beta_inc_reg(1.0, a, x) - (1.0 - (1.0 - x).powf(a))).abs() < 1e-13);
                let s = beta_inc_reg(a, 3.3, x) + beta_inc_reg(3.3, a, 1.0 - x);
                assert!((s - 1.0).abs() < 1e-13);
            }
            let arcsine = 2.0 / PI * x.sqrt().asin();
            assert!((beta_inc_reg(0.5, 0.5, x) - arcsine).abs() < 1e-13);
        }
    }

    #[test]
    fn student_t_known_values() {
        // nu = 1 is the Cauchy distribution, F = 1/2 + atan(t)/pi; nu = 2 has
        // F = 1/2 + t / (2 sqrt(2 + t^2)) (closed forms of the t CDF).
        for &t in &[-30.0, -2.0, -0.3, 0.0, 0.7, 4.0, 100.0] {
            let cauchy = 0.5 + f64::atan(t) / PI;
            assert!((student_t_cdf(t, 1.0) - cauchy).abs() < 1e-13, "{t}");
            let two = 0.5 + t / (2.0 * (2.0 + t * t).sqrt());
            assert!((student_t_cdf(t, 2.0) - two).abs() < 1e-13, "{t}");
        }
        // Printed critical values of t tables: t_{0.975, 10} = 2.228, t_{0.975, 30} = 2.042,
        // t_{0.995, 5} = 4.032 (three printed decimals).
        assert!((student_t_two_sided_p(2.228, 10.0) - 0.05).abs() < 1e-4);
        assert!((student_t_two_sided_p(2.042, 30.0) - 0.05).abs() < 1e-4);
        assert!((student_t_two_sided_p(4.032, 5.0) - 0.01).abs() < 1e-4);
    }

    #[test]
    fn ols_hand_computed_line() {
        // y = b0 + b1 x on x = 0..3, y = 1, 3, 2, 5. By hand: x_bar = 1.5, y_bar = 2.75,
        // Sxx = 5, Sxy = 5.5, b1 = 1.1, b0 = 1.1, residuals -0.1, 0.8, -1.3, 0.6, SSE = 2.7,
        // S^2 = 1.35, SE(b1) = sqrt(1.35/5), SE(b0) = sqrt(1.35 (1/4 + 1.5^2/5)),
        // SST = 8.75, R^2 = 1 - 2.7/8.75; with nu = 2 the two-sided p of t is
        // 1 - t/sqrt(2 + t^2).
        let x = DMatrix::from_row_slice(4, 2, &[1.0, 0.0, 1.0, 1.0, 1.0, 2.0, 1.0, 3.0]);
        let fit = ols(vec!["b0".into(), "b1".into()], &x, &[1.0, 3.0, 2.0, 5.0]).unwrap();
        assert!((fit.coefficients[0] - 1.1).abs() < 1e-14);
        assert!((fit.coefficients[1] - 1.1).abs() < 1e-14);
        for (r, e) in fit.residuals.iter().zip([-0.1, 0.8, -1.3, 0.6]) {
            assert!((r - e).abs() < 1e-14);
        }
        assert!((fit.sse - 2.7).abs() < 1e-13);
        assert!((fit.s - 1.35f64.sqrt()).abs() < 1e-14);
        assert!((fit.std_errors[1] - (1.35f64 / 5.0).sqrt()).abs() < 1e-14);
        assert!((fit.std_errors[0] - (1.35f64 * 0.7).sqrt()).abs() < 1e-14);
        assert!((fit.r_squared - (1.0 - 2.7 / 8.75)).abs() < 1e-14);
        let t = fit.t_values[1];
        assert!((t - 1.1 / 0.27f64.sqrt()).abs() < 1e-13);
        assert!((fit.p_values[1] - (1.0 - t / (2.0 + t * t).sqrt())).abs() < 1e-13);
        assert_eq!(fit.dof, 2);
    }

    #[test]
    fn ols_rejects_degenerate_designs() {
        let x = DMatrix::from_row_slice(3, 2, &[1.0, 2.0, 1.0, 2.0, 1.0, 2.0]);
        assert!(ols(vec!["a".into(), "b".into()], &x, &[1.0, 2.0, 3.0]).is_err());
        let x = DMatrix::from_row_slice(2, 2, &[1.0, 0.0, 1.0, 1.0]);
        assert!(ols(vec!["a".into(), "b".into()], &x, &[1.0, 2.0]).is_err());
    }
}
