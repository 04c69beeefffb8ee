//! The messages of `/wind` ([`crate::schema::WIND_CHANNEL`]), `/inflow`
//! ([`crate::schema::INFLOW_CHANNEL`]) and `/estimate` ([`crate::schema::ESTIMATE_CHANNEL`]):
//! each wing's wind from the simulation, each pair's dynamic inflow, and the state
//! estimator's newest estimate and covariance ([`flapsim::estimator::Estimator`]).

use flapsim::estimator::{Estimator, IAB, IP, ITH, IV, IWB, N_ERR};
use nalgebra::Vector3;

use crate::proto;
use crate::sample::timestamp;
use crate::sensor_msg::{euler_deg, quaternion};

fn v3(v: &Vector3<f64>) -> Option<proto::Vector3> {
    Some(v.into())
}

/// The `/wind` message of a step at log time `t_ns` (simulation time `t_s`).
pub(crate) fn wind(
    t_ns: u64,
    t_s: f64,
    uniform_world_m_s: &Vector3<f64>,
    wing_winds_world_m_s: &[Vector3<f64>],
) -> proto::Wind {
    proto::Wind {
        timestamp: Some(timestamp(t_ns)),
        t_s,
        wing_winds_world_m_s: wing_winds_world_m_s.iter().map(Into::into).collect(),
        uniform_world_m_s: v3(uniform_world_m_s),
    }
}

/// The `/inflow` message of a step at log time `t_ns` (simulation time `t_s`): each pair's
/// states the step's loads were taken at.
pub(crate) fn inflow(
    t_ns: u64,
    t_s: f64,
    pairs: &[wingforce::inflow::InflowState],
) -> proto::Inflow {
    proto::Inflow {
        timestamp: Some(timestamp(t_ns)),
        t_s,
        pairs: pairs
            .iter()
            .map(|p| proto::PairInflow {
                mean_m_s: p.mean_m_s,
                fore_m_s: p.gradient_m_s.x,
                left_m_s: p.gradient_m_s.y,
            })
            .collect(),
    }
}

/// The `/estimate` message of `filter` at log time `t_ns` (simulation time `t_s`, the time at
/// which [`Estimator::state_at`] gives the controller's view).
pub(crate) fn estimate(t_ns: u64, t_s: f64, filter: &Estimator) -> proto::Estimate {
    let (t_filter, x, p) = filter.latest();
    let stats = filter.stats();
    // At the filter's own time the state_at prediction is the nominal state itself, with
    // the angular rate of the newest gyroscope sample less the estimated bias.
    let rates = match t_filter {
        Some(t) => filter.state_at(t).angular_velocity_body_rad_s,
        None => Vector3::zeros(),
    };
    let std_at = |i: usize| {
        Some(proto::Vector3 {
            x: p[(i, i)].max(0.0).sqrt(),
            y: p[(i + 1, i + 1)].max(0.0).sqrt(),
            z: p[(i + 2, i + 2)].max(0.0).sqrt(),
        })
    };
    let mut covariance = Vec::with_capacity(N_ERR * N_ERR);
    for i in 0..N_ERR {
        for j in 0..N_ERR {
            covariance.push(p[(i, j)]);
        }
    }
    let fb = filter.state_at(t_s);
    proto::Estimate {
        timestamp: Some(timestamp(t_ns)),
        t_s: t_filter.unwrap_or(0.0),
        imu_samples: stats.imu_samples,
        mocap_frames: stats.mocap_frames,
        position_world_m: v3(&x.position_world_m),
        velocity_world_m_s: v3(&x.velocity_world_m_s),
        attitude: Some(quaternion(&x.world_from_body)),
        euler_deg: Some(euler_deg(&x.world_from_body)),
        body_rates_rad_s: v3(&rates),
        accel_bias_body_m_s2: v3(&x.accel_bias_body_m_s2),
        gyro_bias_body_rad_s: v3(&x.gyro_bias_body_rad_s),
        std: Some(proto::ErrorStd {
            position_world_m: std_at(IP),
            velocity_world_m_s: std_at(IV),
            attitude_body_rad: std_at(ITH),
            accel_bias_body_m_s2: std_at(IAB),
            gyro_bias_body_rad_s: std_at(IWB),
        }),
        covariance,
        feedback: Some(proto::EstimatedState {
            position_world_m: v3(&fb.position_m),
            velocity_world_m_s: v3(&fb.velocity_m_s),
            attitude: Some(quaternion(&fb.world_from_body)),
            euler_deg: Some(euler_deg(&fb.world_from_body)),
            body_rates_rad_s: v3(&fb.angular_velocity_body_rad_s),
        }),
    }
}

/// What the Rerun view shows of an estimate: the estimated pose against the truth (all
/// finite: non-finite numbers as 0).
#[derive(Debug, Clone, Copy, Default)]
#[cfg_attr(not(feature = "rerun"), allow(dead_code))]
pub(crate) struct EstimateView {
    pub t_ns: u64,
    /// World, m.
    pub position: [f64; 3],
    pub true_position: [f64; 3],
    /// world_from_body, x y z w.
    pub attitude: [f64; 4],
    /// Roll, pitch, yaw, deg.
    pub euler_deg: [f64; 3],
    pub true_euler_deg: [f64; 3],
    /// The position's standard deviation, world, m.
    pub position_std: [f64; 3],
}

#[cfg_attr(not(feature = "rerun"), allow(dead_code))]
fn fin(x: f64) -> f64 {
    if x.is_finite() { x } else { 0.0 }
}

#[cfg_attr(not(feature = "rerun"), allow(dead_code))]
impl EstimateView {
    /// The view of an `/estimate` message and the truth at its log time (position, world,
    /// m; roll, pitch, yaw, deg).
    pub fn of(m: &proto::Estimate, true_position: [f64; 3], true_euler_deg: [f64; 3]) -> Self {
        let p3 = |v: Option<proto::Vector3>| v.map_or([0.0; 3], |v| [fin(v.x), fin(v.y), fin(v.z)]);
        let q = m.attitude.map_or([0.0, 0.0, 0.0, 1.0], |q| {
            [fin(q.x), fin(q.y), fin(q.z), fin(q.w)]
        });
        let e = m
            .euler_deg
            .map_or([0.0; 3], |e| [fin(e.roll), fin(e.pitch), fin(e.yaw)]);
        Self {
            t_ns: m.timestamp.map_or(0, |t| {
                u64::from(t.sec()) * 1_000_000_000 + u64::from(t.nsec())
            }),
            position: p3(m.position_world_m),
            true_position: true_position.map(fin),
            attitude: q,
            euler_deg: e,
            true_euler_deg: true_euler_deg.map(fin),
            position_std: p3(m.std.and_then(|s| s.position_world_m)),
        }
    }
}
