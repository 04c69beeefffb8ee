//! The kinematics family of Sun's group's CFD studies (Sun & Tang 2002; Sun & Lan 2004,
//! J. Exp. Biol. 207:1887, eq. 1-2; Sun & Xiong 2005, J. Exp. Biol. 208:447, for the
//! hovering bumblebee): a simple-harmonic stroke, a constant angle of attack in the middle of
//! each half stroke (alpha_d in the downstroke, alpha_u in the upstroke), and a pitch flip at
//! each stroke reversal whose angular velocity rises and falls as 0.5 w0 (1 - cos(2 pi s/D))
//! over the flip duration D, starting at a chosen time relative to the reversal (the
//! rotation timing: advanced, symmetric or delayed).
//!
//! Phases are in wingbeats (tau in [0, 1)); the downstroke runs from tau = 0 to 0.5 (the
//! stroke angle rising), as in every family of [`crate::kinematics`]. The pitch angle theta
//! is alpha_d in the downstroke and pi - alpha_u in the upstroke.

use std::f64::consts::PI;

/// Shape of the pitch-flip family (angles in radians, times as fractions of the period).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FlipShape {
    /// Angle of attack held in the middle of the downstroke, rad.
    pub downstroke_aoa_rad: f64,
    /// Angle of attack held in the middle of the upstroke, rad.
    pub upstroke_aoa_rad: f64,
    /// Flip duration D as a fraction of the period, in [0.01, 0.5].
    pub flip_duration: f64,
    /// Offset of the flip's midpoint from the stroke reversal, fraction of the period
    /// (0 symmetric rotation, negative advanced, positive delayed).
    pub flip_offset: f64,
}

impl FlipShape {
    /// Stroke profile per unit amplitude about the mean: (value, d/dtau, d2/dtau2), the
    /// simple harmonic -cos(2 pi tau)/2 (reversals at tau = 0 and 0.5).
    pub fn stroke(tau: f64) -> (f64, f64, f64) {
        let w = 2.0 * PI;
        let (s, c) = (w * tau).sin_cos();
        (-0.5 * c, 0.5 * w * s, 0.5 * w * w * c)
    }

    /// Pitch angle theta and its first and second derivatives in tau.
    pub fn pitch(&self, tau: f64) -> (f64, f64, f64) {
        let d = self.flip_duration;
        let down = self.downstroke_aoa_rad;
        let up = PI - self.upstroke_aoa_rad;
        // Phase relative to the flip midpoints (which sit at 0.5 and 1.0 after the shift).
        let t = (tau - self.flip_offset).rem_euclid(1.0);
        let half = 0.5 * d;
        // The flip from `from` to `to`, s in [0, d] since it began: theta' follows
        // (to - from)/d (1 - cos(2 pi s/d)), so theta sweeps exactly to - from over the flip.
        let flip = |s: f64, from: f64, to: f64| {
            let delta = to - from;
            let k = 2.0 * PI / d;
            let (sn, cs) = (k * s).sin_cos();
            (
                from + delta * (s / d - sn / (2.0 * PI)),
                delta / d * (1.0 - cs),
                delta / d * k * sn,
            )
        };
        if t < half {
            flip(t + half, up, down)
        } else if t < 0.5 - half {
            (down, 0.0, 0.0)
        } else if t < 0.5 + half {
            flip(t - (0.5 - half), down, up)
        } else if t < 1.0 - half {
            (up, 0.0, 0.0)
        } else {
            flip(t - (1.0 - half), up, down)
        }
    }

    /// The same shape with both mid-stroke angles of attack moved by `delta_rad`.
    pub fn with_aoa_offset(&self, delta_rad: f64) -> FlipShape {
        FlipShape {
            downstroke_aoa_rad: self.downstroke_aoa_rad + delta_rad,
            upstroke_aoa_rad: self.upstroke_aoa_rad + delta_rad,
            ..*self
        }
    }
}

#[cfg(test)]
mod tests {
    //! Analytic properties of the family: the flip sweeps exactly from one held angle to the
    //! other, its rate peaks at 2 (to - from)/D mid-flip (the mean of 1 - cos is 1), and the
    //! profile is C2 (rate and acceleration vanish at the flip's ends).
    use super::*;

    fn shape(offset: f64) -> FlipShape {
        FlipShape {
            downstroke_aoa_rad: 40f64.to_radians(),
            upstroke_aoa_rad: 30f64.to_radians(),
            flip_duration: 0.2,
            flip_offset: offset,
        }
    }

    #[test]
    fn holds_the_mid_stroke_angles_and_flips_between_them() {
        let s = shape(0.0);
        assert!((s.pitch(0.25).0 - 40f64.to_radians()).abs() < 1e-15);
        assert!((s.pitch(0.75).0 - (PI - 30f64.to_radians())).abs() < 1e-15);
        // Symmetric rotation: mid-flip (at the reversal) lies half-way between the two.
        let mid = 0.5 * (40f64.to_radians() + PI - 30f64.to_radians());
        assert!((s.pitch(0.5).0 - mid).abs() < 1e-12);
        let peak = 2.0 * (PI - 30f64.to_radians() - 40f64.to_radians()) / 0.2;
        assert!((s.pitch(0.5).1 - peak).abs() < 1e-9);
    }

    #[test]
    fn profile_is_continuous_with_its_derivatives() {
        for offset in [-0.05, 0.0, 0.04] {
            let s = shape(offset);
            let h = 1e-7;
            for i in 0..2000 {
                let tau = i as f64 / 2000.0;
                let (a, da, dda) = s.pitch(tau);
                let (b, db, _) = s.pitch(tau + h);
                assert!((b - a).abs() < 1e-5, "theta jumps at {tau}");
                assert!(
                    ((b - a) / h - da).abs() < 1e-3 * (1.0 + da.abs()),
                    "theta' at {tau}"
                );
                assert!(
                    ((db - da) / h - dda).abs() < 1e-2 * (1.0 + dda.abs()),
                    "theta'' at {tau}"
                );
            }
        }
    }

    #[test]
    fn offset_moves_the_flip_in_time() {
        let advanced = shape(-0.05);
        let symmetric = shape(0.0);
        // Advanced rotation reaches the midpoint 0.05 of a period before the reversal.
        assert!((advanced.pitch(0.45).0 - symmetric.pitch(0.5).0).abs() < 1e-12);
    }
}
