//! The body's rate damping, for a stable midpoint prediction of its rates
//! ([`LoadSampling::Midpoint`](crate::LoadSampling::Midpoint)).
//!
//! The midpoint state is predicted from the last two: omega_mid = omega_k + (dt/2) a, with
//! a = (omega_k - omega_{k-1})/dt. On a rate-damping mode omega' = -lambda omega that is the
//! two-step Adams-Bashforth method, stable only for dt lambda < 1, half forward Euler's
//! limit (the step-start sampling). Measured: the dragonfly, whose wings damp the roll of
//! its slender body within 0.3 ms, diverged at 100 steps per wingbeat and fewer under that
//! prediction (its open-loop run survives them under the step-start sampling).
//!
//! With the body's inertia I known (the host's model) and the wings' rate damping D =
//! -dM/domega (the cycle mean about the centre of mass, body frame, at rest in still air),
//! the damping part A = I^-1 D of the acceleration is taken implicitly:
//!
//!   omega_mid = (1 + dt/2 A)^-1 (omega_k + dt/2 (a + A omega_mid,prev)),
//!
//! where a + A omega_mid,prev is the last step's acceleration without its damping part. On
//! the damping mode this gives omega_{k+1} = (1 - dt/2 A)(1 + dt/2 A)^-1 omega_k, the
//! trapezoidal rule (A-stable, second order); elsewhere omega_mid = omega_k + (dt/2) a +
//! O(dt^2), the second-order prediction. The cycle-mean D stands for the damping that
//! varies over the wingbeat: the stiff mean is what the stability needs. Sets without an
//! inertia (built wing by wing, or actuated: their wings' damping is not the kinematics')
//! keep the explicit prediction.

use nalgebra::{Matrix3, Vector3};
use wingforce::BodyMotion;

use super::WingSet;

/// Wingbeat phases at which the cycle-mean damping is sampled.
const PHASES: usize = 64;

impl WingSet {
    /// The body's inertia about its centre of mass, body frame, kg m^2, which the midpoint
    /// prediction of the body's rates uses to stay stable on stiff rate damping (see the
    /// module documentation); `None` (the default) for the explicit prediction. flapsim's
    /// vehicles set their own. A matrix that is not symmetric positive definite is ignored.
    pub fn set_body_inertia_kg_m2(&mut self, inertia: Option<Matrix3<f64>>) {
        self.rate_damping = inertia.and_then(|i| {
            let inv = i.try_inverse()?;
            let sym = (i - i.transpose()).norm() <= 1e-12 * i.norm();
            let pd = i.symmetric_eigenvalues().iter().all(|&l| l > 0.0);
            if !(sym && pd && i.iter().all(|x| x.is_finite())) || self.dynamic.is_some() {
                return None;
            }
            Some(inv * self.cycle_mean_rate_damping())
        });
    }

    /// D = -dM/domega of the cycle-mean moment about the centre of mass at rest in still air,
    /// by central differences in each body rate.
    fn cycle_mean_rate_damping(&self) -> Matrix3<f64> {
        let f = self.freq_hz();
        let delta = 1e-3 * 2.0 * std::f64::consts::PI * f;
        let mean_moment = |w: Vector3<f64>| {
            let motion = BodyMotion {
                velocity_m_s: Vector3::zeros(),
                angular_velocity_rad_s: w,
            };
            let mut m = Vector3::zeros();
            for j in 0..PHASES {
                let phase = (j as f64 + 0.5) / PHASES as f64;
                for w in &self.wings {
                    let forces = w.evaluate(phase, &motion);
                    m += forces.total.moment_about_com_nm(&w.mount().hinge_in_body_m);
                }
            }
            m / PHASES as f64
        };
        let mut d = Matrix3::zeros();
        for j in 0..3 {
            let e = Vector3::ith(j, delta);
            let col = -(mean_moment(e) - mean_moment(-e)) / (2.0 * delta);
            d.set_column(j, &col);
        }
        d
    }

    /// The body rates at the step's midpoint from those at t_k (`rates`) and the last step's
    /// (`prev_rates`, and `prev_mid` the midpoint rates it used), see the module
    /// documentation.
    pub(super) fn midpoint_rates(
        &self,
        rates: &Vector3<f64>,
        prev_rates: &Vector3<f64>,
        prev_mid: &Vector3<f64>,
    ) -> Vector3<f64> {
        let half = 0.5 * self.dt_s;
        match &self.rate_damping {
            Some(a) => {
                let acc = (rates - prev_rates) / self.dt_s + a * prev_mid;
                let lhs = Matrix3::identity() + half * a;
                let rhs = rates + half * acc;
                lhs.lu().solve(&rhs).unwrap_or(rhs)
            }
            None => rates + 0.5 * (rates - prev_rates),
        }
    }
}
