//! Where a half stroke ends and what a drive period measured: the stroke reversals an
//! actuated wing tracks (the wake-capture term restarts at each, and the stroke phase
//! counts from the last), and the stroke reference each period's sampled stroke rate gives
//! (`wingforce::StrokeReference`, taken up from the next step on). Under the step mean a
//! sub-step is split at a reversal inside it (`reversal_within`), a reversal needs a half
//! stroke behind it, and a step ending within round-off of a period's end ends that period
//! (issue 37; the other samplings keep what their logs were written with).

use wingforce::{StrokePhase, StrokeReference, Wing};

use super::wing::{DynamicWing, WingState};
use crate::sampling::LoadSampling;

impl DynamicWing {
    /// Where a sub-step from t0 (stroke rate `pd0`) to (t0 + h, y) crosses a stroke reversal under the
    /// step mean: its offset from t0 (h when the rate reaches zero at the end), located as
    /// [`Self::track_reversal`] does (the rate linear over the sub-step, so within O(h^2)),
    /// and the stroke phase that starts there.
    ///
    /// Why the step is split there: the wake-capture term restarts at a reversal, so the
    /// loads jump; a Runge-Kutta step or a trapezoid across the jump carries an O(h) error
    /// in its mean once per half stroke, which makes the trajectory first order. Split
    /// there, each part is smooth.
    ///
    /// Why a reversal needs a half stroke behind it (its peak rate at least
    /// [`REVERSAL_MIN_PEAK_FRACTION`] of the wing's nominal peak stroke rate): a wing
    /// starting from rest dithers about zero rate in its first microseconds (the RoboBee:
    /// -0.0024 to +0.006 rad/s, 2e-6 of its peak rate, at 7 us), which a sub-step of 5 us
    /// resolves and one of 10 us does not; counted as reversals, those restart the wake
    /// capture and flip the half stroke, a difference of O(1) between step sizes (measured:
    /// the RoboBee's states after a quarter wingbeat at 800 and 1600 steps per wingbeat
    /// differed 40x more than at 400 and 800).
    pub(super) fn reversal_within(
        &self,
        wing: &Wing,
        pd0: f64,
        t0: f64,
        h: f64,
        y: &[f64; 4],
    ) -> Option<(f64, StrokePhase)> {
        let pd1 = self
            .angles_at(&WingState::from_y(y), t0 + h, [0.0; 2])
            .phi_dot;
        let crossed = (pd0 > 0.0 && pd1 <= 0.0) || (pd0 < 0.0 && pd1 >= 0.0);
        let stroked = self.half_stroke_peak_rate_rad_s.max(pd0.abs())
            >= REVERSAL_MIN_PEAK_FRACTION * wing.kinematics().peak_stroke_rate_rad_s();
        let frac = pd0 / (pd0 - pd1);
        (crossed && stroked && frac > 0.0 && frac <= 1.0).then(|| {
            (
                frac * h,
                StrokePhase {
                    half_stroke: self.half_stroke + 1,
                    t_star: 0.0,
                    downstroke: pd1 > 0.0,
                },
            )
        })
    }

    pub(super) fn track_reversal(&mut self, pd_old: f64, t0: f64, h: f64) {
        let pd = self.angles([0.0; 2]).phi_dot;
        let crossed = (pd_old > 0.0 && pd <= 0.0) || (pd_old < 0.0 && pd >= 0.0);
        if crossed {
            let frac = pd_old / (pd_old - pd);
            self.last_reversal_s = t0 + frac * h;
            self.half_stroke += 1;
            self.downstroke = pd > 0.0;
        }
    }

    /// Collects the stroke-rate profile of each drive period and, at its end, measures the
    /// stroke reference (peak rate, dtau_A, dtau_D by the half-peak rule) the wing takes up.
    /// `within`: (t, phi_dot) samples inside the step besides its end, in time order: both
    /// sides of a jump of the rate (an inelastic strike moves the stroke with the pitch) and
    /// of a stroke reversal the step was split at. Sampled at the steps' ends alone, a
    /// profile with a jump puts the half-peak crossing and the reversal anywhere within the
    /// step that holds it: an O(h) error in dtau_A and dtau_D, and so in the wake-capture
    /// term from the next period on (measured on the hummingbird: its tethered two-wingbeat
    /// mean force converged at first order, its one-wingbeat mean at second).
    pub(super) fn track_period(
        &mut self,
        wing: &Wing,
        within: &[(f64, f64)],
    ) -> Option<StrokeReference> {
        let f = self.drive.freq_hz;
        // Under the step mean, a step that ends within round-off of a period's end ends
        // that period, so that its stroke reference is taken up from the next step on,
        // exactly at the period's start (the wing set's steps divide the wingbeat, and
        // round-off in the accumulated time would otherwise move the take-up one step
        // later at some step counts and not others: an O(h) error whose sign alternated
        // with the count, measured on the RoboBee over three periods).
        let eps = match self.sampling {
            LoadSampling::StepMean => PERIOD_END_TOLERANCE,
            _ => 0.0,
        };
        let period = (self.t_s * f + eps).floor() as i64;
        let pd = self.angles([0.0; 2]).phi_dot;
        let mut reference = None;
        // The samples within the step that fall before the period's end belong to it.
        let before = within
            .iter()
            .take_while(|(t, _)| ((t * f + eps).floor() as i64) < period)
            .count();
        let (old, new) = match period != self.period_index {
            true => within.split_at(before),
            false => (within, &within[within.len()..]),
        };
        self.samples.extend_from_slice(old);
        if period != self.period_index {
            if self.model.aero {
                // Under the step mean, a sign change of the rate is a reversal only after a
                // half stroke (`reversal_within`); the other samplings count every one, as
                // their logs were written.
                let min_peak_rad_s = match self.sampling {
                    LoadSampling::StepMean => {
                        REVERSAL_MIN_PEAK_FRACTION * wing.kinematics().peak_stroke_rate_rad_s()
                    }
                    _ => 0.0,
                };
                reference = measure_reference(&self.samples, self.period_index, f, min_peak_rad_s);
            }
            self.samples.clear();
            self.period_index = period;
        }
        self.samples.extend_from_slice(new);
        self.samples.push((self.t_s, pd));
        reference
    }
}

/// The least peak stroke rate of a half stroke, as a fraction of the wing's nominal peak
/// stroke rate, for its end to count as a stroke reversal under the step mean
/// ([`DynamicWing::reversal_within`]). A numerical threshold, not a physical one: it only
/// has to lie between a start-up dither (2e-6 of the peak rate, measured on the RoboBee) and
/// a stroke (its peak rate, 1), and 0.01 leaves two orders of magnitude on either side.
const REVERSAL_MIN_PEAK_FRACTION: f64 = 0.01;

/// How close to a drive period's end, in periods, a step's end counts as that end (under the
/// step mean, `DynamicWing::track_period`): far above the round-off of the accumulated time
/// (1e-16 per step) and far below a step (1e-3 of a period at most).
const PERIOD_END_TOLERANCE: f64 = 1e-9;

/// The stroke reference of one drive period from its (t, phi_dot) samples: peak |phi_dot|,
/// and dtau_A, dtau_D by wingforce's half-peak rule on the linearly interpolated profile.
/// `None` when the period does not hold two stroke reversals.
fn measure_reference(
    samples: &[(f64, f64)],
    period: i64,
    freq_hz: f64,
    min_peak_rad_s: f64,
) -> Option<StrokeReference> {
    if samples.len() < 8 {
        return None;
    }
    let t0 = period as f64 / freq_hz;
    let phase: Vec<f64> = samples.iter().map(|(t, _)| (t - t0) * freq_hz).collect();
    let rate: Vec<f64> = samples.iter().map(|s| s.1).collect();
    let peak = rate.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let mut reversals = Vec::new();
    // The largest |rate| since the last reversal counted.
    let mut half_peak = rate[0].abs();
    for i in 1..rate.len() {
        let (a, b) = (rate[i - 1], rate[i]);
        half_peak = half_peak.max(a.abs());
        if ((a > 0.0 && b <= 0.0) || (a < 0.0 && b >= 0.0)) && half_peak >= min_peak_rad_s {
            half_peak = b.abs();
            let x = phase[i - 1] + (phase[i] - phase[i - 1]) * a / (a - b);
            reversals.push((x.rem_euclid(1.0), b > 0.0));
        }
    }
    if reversals.len() != 2 || !(peak > 0.0) {
        return None;
    }
    reversals.sort_by(|a, b| a.0.total_cmp(&b.0));
    let (dtau_a, dtau_d) = wingforce::kinematics::sampled_acceleration_fractions(
        &phase,
        &rate,
        [reversals[0], reversals[1]],
    );
    Some(StrokeReference {
        peak_stroke_rate_rad_s: peak,
        dtau_a,
        dtau_d,
    })
}
