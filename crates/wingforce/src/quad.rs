//! Numerical quadrature used for planform integrals (setup only, never per step).

/// 4-point Gauss-Legendre nodes on [-1, 1].
const GL4_X: [f64; 4] = [
    -0.861_136_311_594_052_6,
    -0.339_981_043_584_856_3,
    0.339_981_043_584_856_3,
    0.861_136_311_594_052_6,
];
/// 4-point Gauss-Legendre weights.
const GL4_W: [f64; 4] = [
    0.347_854_845_137_453_9,
    0.652_145_154_862_546_1,
    0.652_145_154_862_546_1,
    0.347_854_845_137_453_9,
];

/// Integrates `f` over `[a, b]` with `panels` equal panels of 4-point Gauss-Legendre.
///
/// Exact for polynomials up to degree 7 on each panel; the nodes never touch the ends, so
/// integrable end singularities (the Ellington beta planform's root and tip) are tolerated.
pub(crate) fn gauss_legendre(a: f64, b: f64, panels: usize, mut f: impl FnMut(f64) -> f64) -> f64 {
    let h = (b - a) / panels as f64;
    let mut sum = 0.0;
    for p in 0..panels {
        let mid = a + (p as f64 + 0.5) * h;
        for k in 0..4 {
            sum += GL4_W[k] * f(mid + 0.5 * h * GL4_X[k]);
        }
    }
    sum * 0.5 * h
}

/// Integrates over consecutive intervals `breaks[i]..breaks[i+1]`, `panels` panels each.
pub(crate) fn piecewise(breaks: &[f64], panels: usize, mut f: impl FnMut(f64) -> f64) -> f64 {
    breaks
        .windows(2)
        .map(|w| gauss_legendre(w[0], w[1], panels, &mut f))
        .sum()
}

/// The standard normal cumulative distribution, Phi(x), to about 1e-15 (via erfc).
pub fn normal_cdf(x: f64) -> f64 {
    0.5 * erfc(-x / std::f64::consts::SQRT_2)
}

/// Complementary error function: the Maclaurin series of erf for |x| < 2.5 and the Laplace
/// continued fraction (evaluated by Lentz's method) beyond, both accurate to about 1e-15.
pub fn erfc(x: f64) -> f64 {
    // Series for erf near zero, continued fraction for the tail: both converge fast and are
    // accurate to ~1e-15, which the wake-capture integral test needs.
    let ax = x.abs();
    let value = if ax < 2.5 {
        // erf(x) = 2/sqrt(pi) * sum_{n} (-1)^n x^(2n+1) / (n! (2n+1))
        let mut term = ax;
        let mut sum = ax;
        let x2 = ax * ax;
        let mut n = 0.0;
        loop {
            n += 1.0;
            term *= -x2 / n;
            let add = term / (2.0 * n + 1.0);
            sum += add;
            if add.abs() < 1e-17 * sum.abs() {
                break;
            }
        }
        1.0 - 2.0 / std::f64::consts::PI.sqrt() * sum
    } else {
        // Lentz continued fraction: erfc(x) = exp(-x^2)/sqrt(pi) * 1/(x + 1/2/(x + 1/(x + 3/2/(x + ...))))
        let mut f = ax;
        let tiny = 1e-300;
        let mut c = f;
        let mut d = 0.0;
        for k in 1..200 {
            let a = k as f64 * 0.5;
            d = ax + a * d;
            d = if d.abs() < tiny { tiny } else { d };
            d = 1.0 / d;
            c = ax + a / c;
            c = if c.abs() < tiny { tiny } else { c };
            let delta = c * d;
            f *= delta;
            if (delta - 1.0).abs() < 1e-16 {
                break;
            }
        }
        (-ax * ax).exp() / std::f64::consts::PI.sqrt() / f
    };
    if x >= 0.0 { value } else { 2.0 - value }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gauss_legendre_integrates_cubics_exactly() {
        // int_0^2 x^3 dx = 4 (analytic).
        let v = gauss_legendre(0.0, 2.0, 1, |x| x * x * x);
        assert!((v - 4.0).abs() < 1e-14);
    }

    #[test]
    fn normal_cdf_matches_tables() {
        // Phi(-3) = 0.0013498980316301 and Phi(1) = 0.8413447460685429 (Abramowitz & Stegun 26.2).
        assert!((normal_cdf(-3.0) - 0.001_349_898_031_630_1).abs() < 1e-13);
        assert!((normal_cdf(1.0) - 0.841_344_746_068_542_9).abs() < 1e-13);
        assert!((normal_cdf(3.2) - 0.999_312_862_062_084).abs() < 1e-13);
    }
}
