//! The error-state Kalman filter's algebra: one prediction from an IMU sample and one
//! motion-capture pose update with its reset (equations in the [module documentation of
//! `estimator`](super)).

use nalgebra::{Matrix3, SMatrix, SVector, UnitQuaternion, Vector3};

/// Dimension of the error state: position, velocity, attitude, accelerometer bias, gyro bias.
pub const N_ERR: usize = 15;
/// Offset of the position error in the error state.
pub const IP: usize = 0;
/// Offset of the velocity error.
pub const IV: usize = 3;
/// Offset of the attitude error (a body-frame rotation vector, `q_true = q (x) Exp(dtheta)`).
pub const ITH: usize = 6;
/// Offset of the accelerometer-bias error.
pub const IAB: usize = 9;
/// Offset of the gyroscope-bias error.
pub const IWB: usize = 12;

/// The error-state covariance, 15 x 15.
pub type Covariance = SMatrix<f64, N_ERR, N_ERR>;
/// An error-state vector.
pub type ErrorState = SVector<f64, N_ERR>;

/// The nominal state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Nominal {
    /// Body origin (centre of mass), world, m.
    pub position_world_m: Vector3<f64>,
    /// Its velocity, world, m/s.
    pub velocity_world_m_s: Vector3<f64>,
    /// Attitude.
    pub world_from_body: UnitQuaternion<f64>,
    /// Accelerometer bias, body, m/s^2.
    pub accel_bias_body_m_s2: Vector3<f64>,
    /// Gyroscope bias, body, rad/s.
    pub gyro_bias_body_rad_s: Vector3<f64>,
}

/// The IMU's noise as the filter models it (from the model's `[sensors.imu]`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImuNoise {
    /// Per-sample gyroscope white-noise standard deviation, rad/s (density x sqrt(rate)).
    pub gyro_noise_std_rad_s: f64,
    /// Per-sample accelerometer white-noise standard deviation, m/s^2.
    pub accel_noise_std_m_s2: f64,
    /// Gyroscope bias random walk, rad/s/sqrt(s).
    pub gyro_bias_walk_rad_s_sqrt_s: f64,
    /// Accelerometer bias random walk, m/s^2/sqrt(s).
    pub accel_bias_walk_m_s2_sqrt_s: f64,
    /// Gravity, m/s^2 (world z up, g = (0, 0, -g)).
    pub gravity_m_s2: f64,
}

/// The skew-symmetric matrix of `v` ([v]x w = v x w).
pub fn skew(v: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -v.z, v.y, v.z, 0.0, -v.x, -v.y, v.x, 0.0)
}

fn block3(m: &mut Covariance, r: usize, c: usize, b: &Matrix3<f64>) {
    m.fixed_view_mut::<3, 3>(r, c).copy_from(b);
}

/// The nominal state moved over `dt_s` by one IMU sample (`gyro_rad_s`, `accel_m_s2`, body)
/// taken at the end of the interval: rotation first, then velocity with the new attitude,
/// then position with the new velocity (semi-implicit Euler).
pub fn propagate(
    x: &Nominal,
    gyro_rad_s: &Vector3<f64>,
    accel_m_s2: &Vector3<f64>,
    dt_s: f64,
    gravity_m_s2: f64,
) -> Nominal {
    let w = gyro_rad_s - x.gyro_bias_body_rad_s;
    let a = accel_m_s2 - x.accel_bias_body_m_s2;
    let q = x.world_from_body * UnitQuaternion::from_scaled_axis(w * dt_s);
    let g = Vector3::new(0.0, 0.0, -gravity_m_s2);
    let v = x.velocity_world_m_s + (q * a + g) * dt_s;
    Nominal {
        position_world_m: x.position_world_m + v * dt_s,
        velocity_world_m_s: v,
        world_from_body: q,
        ..*x
    }
}

/// One prediction: the nominal state by [`propagate`] and the covariance by the error-state
/// transition of the same three sub-steps, P <- F3 (F2 (F1 P F1' + Q1) F2' + Q2) F3' + Qb.
pub fn predict(
    x: &Nominal,
    p: &Covariance,
    gyro_rad_s: &Vector3<f64>,
    accel_m_s2: &Vector3<f64>,
    dt_s: f64,
    noise: &ImuNoise,
) -> (Nominal, Covariance) {
    let next = propagate(x, gyro_rad_s, accel_m_s2, dt_s, noise.gravity_m_s2);
    let i3 = Matrix3::identity();
    let w = gyro_rad_s - x.gyro_bias_body_rad_s;
    let a = accel_m_s2 - x.accel_bias_body_m_s2;
    // 1: attitude, dtheta+ = Exp(w dt)' dtheta - dt dbg - dt n_g.
    let mut f1 = Covariance::identity();
    let e = UnitQuaternion::from_scaled_axis(w * dt_s).to_rotation_matrix();
    block3(&mut f1, ITH, ITH, &e.matrix().transpose());
    block3(&mut f1, ITH, IWB, &(-i3 * dt_s));
    let mut p1 = f1 * p * f1.transpose();
    let qg = (noise.gyro_noise_std_rad_s * dt_s).powi(2);
    for k in 0..3 {
        p1[(ITH + k, ITH + k)] += qg;
    }
    // 2: velocity, dv+ = dv - R+ [a]x dt dtheta+ - R+ dt dba - R+ dt n_a.
    let r = next.world_from_body.to_rotation_matrix().into_inner();
    let mut f2 = Covariance::identity();
    block3(&mut f2, IV, ITH, &(-r * skew(&a) * dt_s));
    block3(&mut f2, IV, IAB, &(-r * dt_s));
    let mut p2 = f2 * p1 * f2.transpose();
    let qa = (noise.accel_noise_std_m_s2 * dt_s).powi(2);
    for k in 0..3 {
        p2[(IV + k, IV + k)] += qa; // R (s^2 I) R' = s^2 I
    }
    // 3: position, dp+ = dp + dt dv+.
    let mut f3 = Covariance::identity();
    block3(&mut f3, IP, IV, &(i3 * dt_s));
    let mut p3 = f3 * p2 * f3.transpose();
    // Bias random walks over the interval.
    let qwb = noise.gyro_bias_walk_rad_s_sqrt_s.powi(2) * dt_s;
    let qab = noise.accel_bias_walk_m_s2_sqrt_s.powi(2) * dt_s;
    for k in 0..3 {
        p3[(IWB + k, IWB + k)] += qwb;
        p3[(IAB + k, IAB + k)] += qab;
    }
    (next, symmetric(&p3))
}

fn symmetric(p: &Covariance) -> Covariance {
    (p + p.transpose()) * 0.5
}

/// What a pose update did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PoseUpdate {
    /// Innovation: position (world, m) then attitude (body rotation vector, rad).
    pub innovation: [f64; 6],
    /// Normalised innovation squared, y' S^-1 y (chi-square with 6 degrees of freedom for a
    /// consistent filter).
    pub nis: f64,
}

/// A motion-capture pose update of `(x, p)`: measured position (world, m) with noise
/// standard deviation `position_std_m` per axis, measured attitude with a body-frame
/// rotation-vector noise of `attitude_std_rad` per axis; Joseph-form covariance update,
/// injection of the error into the nominal state and the reset of the covariance.
pub fn update_pose(
    x: &mut Nominal,
    p: &mut Covariance,
    position_world_m: &Vector3<f64>,
    world_from_body: &UnitQuaternion<f64>,
    position_std_m: f64,
    attitude_std_rad: f64,
) -> PoseUpdate {
    let yp = position_world_m - x.position_world_m;
    let yth = (x.world_from_body.inverse() * world_from_body).scaled_axis();
    let y = SVector::<f64, 6>::new(yp.x, yp.y, yp.z, yth.x, yth.y, yth.z);
    let mut h = SMatrix::<f64, 6, N_ERR>::zeros();
    for k in 0..3 {
        h[(k, IP + k)] = 1.0;
        h[(3 + k, ITH + k)] = 1.0;
    }
    let mut rm = SMatrix::<f64, 6, 6>::zeros();
    for k in 0..3 {
        rm[(k, k)] = position_std_m * position_std_m;
        rm[(3 + k, 3 + k)] = attitude_std_rad * attitude_std_rad;
    }
    let pht = *p * h.transpose();
    let s = h * pht + rm;
    let s = (s + s.transpose()) * 0.5;
    let s_inv = inverse_psd(&s);
    let k = pht * s_inv;
    let dx: ErrorState = k * y;
    let ikh = Covariance::identity() - k * h;
    let joseph = ikh * *p * ikh.transpose() + k * rm * k.transpose();
    let nis = (y.transpose() * s_inv * y)[(0, 0)];
    inject(x, &dx);
    // Reset: P <- G P G', G = blockdiag(I, I, I - [dtheta/2]x, I, I) (Sola 2017, eq. 287).
    let mut g = Covariance::identity();
    let dth = Vector3::new(dx[ITH], dx[ITH + 1], dx[ITH + 2]);
    block3(
        &mut g,
        ITH,
        ITH,
        &(Matrix3::identity() - skew(&(dth * 0.5))),
    );
    *p = symmetric(&(g * joseph * g.transpose()));
    PoseUpdate {
        innovation: [y[0], y[1], y[2], y[3], y[4], y[5]],
        nis,
    }
}

/// The inverse of a symmetric positive semi-definite S: by Cholesky when it is positive
/// definite. S is singular only when a measured quantity is known exactly and measured
/// exactly (zero prior and process noise on it and R = 0); S + eps I (eps = 1e-12 of its
/// largest diagonal entry) is then inverted instead: the columns of P H' that belong to
/// such a quantity are zero, so its gain stays zero, and the other gains change by a
/// relative 1e-12 at most.
fn inverse_psd(s: &SMatrix<f64, 6, 6>) -> SMatrix<f64, 6, 6> {
    if let Some(c) = s.cholesky() {
        return c.inverse();
    }
    let eps = 1e-12 * s.diagonal().max();
    if eps.is_finite()
        && eps > 0.0
        && let Some(c) = (s + SMatrix::<f64, 6, 6>::identity() * eps).cholesky()
    {
        return c.inverse();
    }
    SMatrix::zeros()
}

/// Adds the error state `dx` to the nominal state (`q <- q (x) Exp(dtheta)`).
pub fn inject(x: &mut Nominal, dx: &ErrorState) {
    let v3 = |i: usize| Vector3::new(dx[i], dx[i + 1], dx[i + 2]);
    x.position_world_m += v3(IP);
    x.velocity_world_m_s += v3(IV);
    x.world_from_body *= UnitQuaternion::from_scaled_axis(v3(ITH));
    x.accel_bias_body_m_s2 += v3(IAB);
    x.gyro_bias_body_rad_s += v3(IWB);
}
