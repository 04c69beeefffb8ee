//! A C2 periodic cubic spline: how measured (tabulated) kinematics are interpolated.

/// A C2 periodic cubic spline on [0, 1) through (x_i, y_i), x_0 = 0, x_{n-1} = 1, y_0 = y_{n-1}.
#[derive(Debug, Clone, PartialEq)]
pub struct PeriodicSpline {
    x: Vec<f64>,
    y: Vec<f64>,
    /// Second derivatives at the knots.
    m: Vec<f64>,
}

impl PeriodicSpline {
    /// Fits the spline (solving the cyclic tridiagonal system for the knot curvatures).
    pub fn new(x: &[f64], y: &[f64]) -> Self {
        let n = x.len() - 1; // distinct knots
        let h: Vec<f64> = (0..n).map(|i| x[i + 1] - x[i]).collect();
        // Equations for m_i, i in 0..n (periodic: m_n = m_0):
        // h_{i-1} m_{i-1} + 2 (h_{i-1} + h_i) m_i + h_i m_{i+1} = 6 ((y_{i+1}-y_i)/h_i - (y_i-y_{i-1})/h_{i-1})
        let mut a = vec![0.0; n];
        let mut b = vec![0.0; n];
        let mut c = vec![0.0; n];
        let mut r = vec![0.0; n];
        for i in 0..n {
            let im = (i + n - 1) % n;
            let hm = h[im];
            let hi = h[i];
            let y_next = y[i + 1];
            let y_prev = if i == 0 { y[n - 1] } else { y[i - 1] };
            a[i] = hm;
            b[i] = 2.0 * (hm + hi);
            c[i] = hi;
            r[i] = 6.0 * ((y_next - y[i]) / hi - (y[i] - y_prev) / hm);
        }
        let m = solve_cyclic(&a, &b, &c, &r);
        let mut m_full = m.clone();
        m_full.push(m[0]);
        Self {
            x: x.to_vec(),
            y: y.to_vec(),
            m: m_full,
        }
    }

    fn segment(&self, t: f64) -> (usize, f64, f64) {
        let t = t - t.floor();
        let i = self
            .x
            .partition_point(|&xi| xi <= t)
            .saturating_sub(1)
            .min(self.x.len() - 2);
        (i, t - self.x[i], self.x[i + 1] - self.x[i])
    }

    /// Value at t (periodic).
    pub fn value(&self, t: f64) -> f64 {
        let (i, s, h) = self.segment(t);
        let (m0, m1) = (self.m[i], self.m[i + 1]);
        let (y0, y1) = (self.y[i], self.y[i + 1]);
        let u = h - s;
        m0 * u * u * u / (6.0 * h)
            + m1 * s * s * s / (6.0 * h)
            + (y0 / h - m0 * h / 6.0) * u
            + (y1 / h - m1 * h / 6.0) * s
    }

    /// First derivative at t.
    pub fn derivative(&self, t: f64) -> f64 {
        let (i, s, h) = self.segment(t);
        let (m0, m1) = (self.m[i], self.m[i + 1]);
        let (y0, y1) = (self.y[i], self.y[i + 1]);
        let u = h - s;
        -m0 * u * u / (2.0 * h) + m1 * s * s / (2.0 * h) - (y0 / h - m0 * h / 6.0)
            + (y1 / h - m1 * h / 6.0)
    }

    /// Second derivative at t.
    pub fn second_derivative(&self, t: f64) -> f64 {
        let (i, s, h) = self.segment(t);
        (self.m[i] * (h - s) + self.m[i + 1] * s) / h
    }
}

/// Solves a cyclic tridiagonal system (sub-diagonal a, diagonal b, super-diagonal c, with
/// a[0] and c[n-1] the corner entries) by Sherman-Morrison.
fn solve_cyclic(a: &[f64], b: &[f64], c: &[f64], r: &[f64]) -> Vec<f64> {
    let n = b.len();
    if n == 1 {
        return vec![r[0] / (a[0] + b[0] + c[0])];
    }
    let gamma = -b[0];
    let mut bb = b.to_vec();
    bb[0] = b[0] - gamma;
    bb[n - 1] = b[n - 1] - a[0] * c[n - 1] / gamma;
    let x = solve_tridiagonal(a, &bb, c, r);
    let mut u = vec![0.0; n];
    u[0] = gamma;
    u[n - 1] = c[n - 1];
    let z = solve_tridiagonal(a, &bb, c, &u);
    let fact = (x[0] + a[0] * x[n - 1] / gamma) / (1.0 + z[0] + a[0] * z[n - 1] / gamma);
    x.iter().zip(&z).map(|(xi, zi)| xi - fact * zi).collect()
}

fn solve_tridiagonal(a: &[f64], b: &[f64], c: &[f64], r: &[f64]) -> Vec<f64> {
    let n = b.len();
    let mut cp = vec![0.0; n];
    let mut dp = vec![0.0; n];
    cp[0] = c[0] / b[0];
    dp[0] = r[0] / b[0];
    for i in 1..n {
        let den = b[i] - a[i] * cp[i - 1];
        cp[i] = c[i] / den;
        dp[i] = (r[i] - a[i] * dp[i - 1]) / den;
    }
    let mut x = vec![0.0; n];
    x[n - 1] = dp[n - 1];
    for i in (0..n - 1).rev() {
        x[i] = dp[i] - cp[i] * x[i + 1];
    }
    x
}
