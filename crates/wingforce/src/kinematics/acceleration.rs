//! The half-peak rule: the acceleration and deceleration fractions (dtau_A, dtau_D) of any
//! stroke-rate profile, as a function of the phase or sampled.

/// The half-peak rule of [`crate::Kinematics::acceleration_fractions`], for any stroke-rate function
/// of the phase and its two reversals: the function sampled at 40,000 points over the period
/// from the first reversal, then [`sampled_acceleration_fractions`] on that profile.
pub fn measure_acceleration_fractions(
    rate: impl Fn(f64) -> f64,
    reversals: [(f64, bool); 2],
) -> (f64, f64) {
    let n = 40_000;
    let start = reversals[0].0;
    let phase: Vec<f64> = (0..n).map(|i| start + i as f64 / n as f64).collect();
    let samples: Vec<f64> = phase.iter().map(|&x| rate(x)).collect();
    sampled_acceleration_fractions(&phase, &samples, reversals)
}

/// The half-peak rule on a sampled periodic stroke-rate profile, linearly interpolated
/// between samples (`phase` increasing over one period, `rate` the stroke rate there) and
/// zero at the two `reversals`: in each half stroke, the acceleration fraction is twice the
/// time from the reversal to the first crossing of half the half stroke's peak rate, the
/// deceleration fraction twice the time from the last crossing to the next reversal (both in
/// periods), averaged over the two half strokes; the crossings are found exactly on the
/// interpolant. A dynamic wing calls it every wingbeat on its own 100 samples.
pub fn sampled_acceleration_fractions(
    phase: &[f64],
    rate: &[f64],
    reversals: [(f64, bool); 2],
) -> (f64, f64) {
    let mut sum_a = 0.0;
    let mut sum_d = 0.0;
    for k in 0..2 {
        let start = reversals[k].0;
        let end = if k == 0 {
            reversals[1].0
        } else {
            reversals[0].0 + 1.0
        };
        // The half stroke's points: the reversal, the samples inside (one period on), the
        // next reversal.
        let mut pts: Vec<(f64, f64)> = vec![(start, 0.0)];
        for shift in [0.0, 1.0] {
            pts.extend(
                phase
                    .iter()
                    .zip(rate)
                    .map(|(&x, &r)| (x + shift, r.abs()))
                    .filter(|&(x, _)| x > start && x < end),
            );
        }
        pts.sort_by(|a, b| a.0.total_cmp(&b.0));
        pts.push((end, 0.0));
        let half = 0.5 * pts.iter().fold(0.0f64, |m, p| m.max(p.1));
        let cross = |a: (f64, f64), b: (f64, f64)| {
            if b.1 == a.1 {
                a.0
            } else {
                a.0 + (half - a.1) / (b.1 - a.1) * (b.0 - a.0)
            }
        };
        let first = pts
            .windows(2)
            .find(|w| w[1].1 >= half)
            .map(|w| cross(w[0], w[1]))
            .unwrap_or(start);
        let last = pts
            .windows(2)
            .rev()
            .find(|w| w[0].1 >= half)
            .map(|w| cross(w[1], w[0]))
            .unwrap_or(end);
        sum_a += 2.0 * (first - start);
        sum_d += 2.0 * (end - last);
    }
    (0.5 * sum_a, 0.5 * sum_d)
}
