//! Cutting a flight into the fit's segments: each wingbeat start with a known state begins
//! a segment of [`FitOptions::segment_wingbeats`] wingbeats (an actuated vehicle's runs on to
//! the next start, so that its wings chain), with the motion-capture frames and IMU samples
//! that fall due at its steps, the residuals' weights from the sensors' noise and the
//! start-state unknowns' scales (see the module documentation of [`crate::fit`]).

use flapsim::{Mode, Simulation, VehicleSpec};

use crate::data::{FlightData, controlled_wingbeats, timing};
use crate::error::{Error, Result};

use super::segments::{STATE_UNKNOWNS, Segment, Setup, Weights};
use super::types::FitOptions;

/// The resolution of a recorded stamp, s (ROS 2: whole nanoseconds).
const STAMP_QUANTUM_S: f64 = 1e-9;

/// The first step at or after `t_s` as flapsim's sensors pick it (a sample falls due at the
/// step whose time is within `tol_s` of it or after).
pub(super) fn step_at(t_s: f64, dt_s: f64, tol_s: f64) -> Option<u64> {
    let x = ((t_s - tol_s) / dt_s).ceil();
    if !(x.is_finite() && x > -1e15 && x < 1e15) {
        return None;
    }
    let mut s = x.max(0.0) as i64;
    while s > 0 && (s - 1) as f64 * dt_s >= t_s - tol_s {
        s -= 1;
    }
    while (s as f64) * dt_s < t_s - tol_s {
        s += 1;
    }
    Some(s as u64)
}

/// Builds the segments and weights of a fit.
pub(super) fn setup<'a>(data: &'a FlightData, opts: &FitOptions) -> Result<Setup<'a>> {
    setup_for(data, opts, false)
}

/// [`setup`], for a resimulation when `resim`: a flight with logged states is compared with
/// them, so its segments need no measurement and its model no sensors.
pub(super) fn setup_for<'a>(
    data: &'a FlightData,
    opts: &FitOptions,
    resim: bool,
) -> Result<Setup<'a>> {
    opts.check_settings()?;
    let against_states = resim && !data.logged_states.is_empty();
    let origin = &data.model_origin;
    let base = VehicleSpec::from_toml(&data.model_toml, origin)
        .map_err(|e| Error::Model(format!("`{origin}` does not load: {e}")))?;
    for p in &opts.params {
        p.check_model(&base, origin)?;
    }
    let vehicle = base
        .build(origin)
        .map_err(|e| Error::Model(format!("`{origin}` does not load: {e}")))?;
    // A resimulation against logged states weighs nothing: a model without sensors will do.
    let sensors = vehicle.sensors;
    if sensors.is_none() && !against_states {
        return Err(Error::Model(format!(
            "`{origin}` has no [sensors] table: the fit weighs each residual by the sensors' noise ([sensors.mocap] position_noise_m and attitude_noise_deg; see models/drosophila.toml)"
        )));
    }
    let mocap = sensors.and_then(|s| s.mocap);
    if mocap.is_none() && !against_states {
        return Err(Error::Model(format!(
            "`{origin}` has no [sensors.mocap] table: the fit weighs the motion-capture residuals by its position_noise_m and attitude_noise_deg"
        )));
    }
    let use_imu = opts.use_imu;
    if use_imu && data.imu.is_empty() {
        return Err(Error::Log {
            path: data.source.clone(),
            detail: "the IMU was asked for as a measurement but the data hold no IMU samples (`/sensors/imu` in a log, the gyro_*/accel_* columns of a CSV)".into(),
        });
    }
    if let Some(p) = opts.params.iter().find(|p| p.needs_imu())
        && !use_imu
    {
        return Err(Error::Setting(format!(
            "parameter `{}` is seen only by the IMU's samples: fit with the IMU (--imu)",
            p.name()
        )));
    }
    let (freq_hz, per) = timing(&vehicle);
    let dt_s = Simulation::try_new(vehicle.clone(), Mode::Free)
        .map_err(|e| Error::Model(format!("`{origin}`: {e}")))?
        .dt_s();
    let floor = 1e-12;
    let (pos, att, mocap_rate_hz) = mocap.map_or((1.0, 1.0, 1.0), |m| {
        (m.position_noise_m, m.attitude_noise_rad, m.rate_hz)
    });
    let (gyro, accel, imu_rate_hz) = sensors.map_or((1.0, 1.0, 1.0), |s| {
        let r = s.imu.rate_hz;
        (
            s.imu.gyro_noise_density * r.sqrt(),
            s.imu.accel_noise_density * r.sqrt(),
            r,
        )
    });
    let weights = Weights {
        pos: pos.max(floor),
        att: att.max(floor),
        gyro: gyro.max(floor),
        accel: accel.max(floor),
    };
    // A sample falls due at a step within a millionth of its period (flapsim's sensors), or
    // within a nanosecond: a ROS 2 bag's stamps are whole nanoseconds.
    let mocap_tol = (1e-6 / mocap_rate_hz).max(STAMP_QUANTUM_S);
    let imu_tol = (1e-6 / imu_rate_hz).max(STAMP_QUANTUM_S);
    let controls = controlled_wingbeats(data);
    let end_t = opts.max_duration_s.unwrap_or(f64::INFINITY);
    let k = u64::from(opts.segment_wingbeats);
    let mut segments = Vec::new();
    let mut next_free = 0u64;
    for start in &data.starts {
        let w0 = start.wingbeat;
        if w0 < next_free {
            continue;
        }
        // An actuated vehicle's wings chain from segment to segment (see `Setup::fly`): its
        // segment runs on to the next wingbeat start with a known state.
        let w_end = if vehicle.actuation.is_some() {
            data.starts
                .iter()
                .map(|s| s.wingbeat)
                .find(|&w| w >= w0 + k)
                .unwrap_or(w0 + k)
        } else {
            w0 + k
        };
        let mut ctl = Vec::new();
        for w in w0..w_end {
            let t_end = (w + 1) as f64 / freq_hz;
            match controls.get(&w) {
                Some(c) if t_end <= end_t + 1e-12 => ctl.push(*c),
                _ => break,
            }
        }
        if ctl.is_empty() {
            continue;
        }
        let step0 = w0 * per;
        let steps = ctl.len() * per as usize;
        let in_segment = |t: f64, tol: f64| -> Option<usize> {
            let s = step_at(t, dt_s, tol)?;
            (s >= step0 && s < step0 + steps as u64).then(|| (s - step0) as usize)
        };
        let t0 = step0 as f64 * dt_s;
        let t1 = (step0 + steps as u64) as f64 * dt_s;
        let lo = data.mocap.partition_point(|f| f.t_s < t0 - dt_s);
        let mut seg_mocap = Vec::new();
        for (i, f) in data.mocap.iter().enumerate().skip(lo) {
            if f.t_s > t1 + dt_s {
                break;
            }
            if let Some(j) = in_segment(f.t_s, mocap_tol) {
                seg_mocap.push((j, i));
            }
        }
        let mut seg_imu = Vec::new();
        if use_imu {
            let lo = data.imu.partition_point(|f| f.t_s < t0 - dt_s);
            for (i, f) in data.imu.iter().enumerate().skip(lo) {
                if f.t_s > t1 + dt_s {
                    break;
                }
                // The accelerometer needs the step before (the velocity change).
                if let Some(j) = in_segment(f.t_s, imu_tol).filter(|j| *j >= 1) {
                    seg_imu.push((j, i));
                }
            }
        }
        if seg_mocap.is_empty() && seg_imu.is_empty() && !against_states {
            continue;
        }
        segments.push(Segment {
            state: start.state,
            memory: start.memory,
            step0,
            controls: ctl,
            steps,
            mocap: seg_mocap,
            imu: seg_imu,
        });
        next_free = w_end;
    }
    if segments.is_empty() {
        return Err(Error::Data(format!(
            "`{}`: no segment to fit: {} wingbeat starts with a known state, {} wingbeats with controls, {} motion-capture frames; a segment needs a wingbeat start with a state (a `/vehicle/state` sample at the wingbeat's first step, or {} motion-capture frames on each side), the controls of its wingbeats and a measurement",
            data.source.display(),
            data.starts.len(),
            controls.len(),
            data.mocap.len(),
            crate::data::START_FIT_FRAMES
        )));
    }
    let m: usize = segments
        .iter()
        .map(|s| 6 * s.mocap.len() + 6 * s.imu.len())
        .sum();
    let scales: Vec<f64> = opts.params.iter().map(|p| p.scale(&base)).collect();
    if m <= opts.params.len() && !against_states {
        return Err(Error::Data(format!(
            "`{}`: {m} residuals cannot determine {} parameters (more measurements are needed)",
            data.source.display(),
            opts.params.len()
        )));
    }
    let fit_states = opts.start_states.fitted(data.start_source);
    let mut rows = Vec::with_capacity(segments.len());
    let mut at = 0;
    for seg in &segments {
        let len = 6 * seg.mocap.len() + 6 * seg.imu.len();
        rows.push(at..at + len);
        at += len;
    }
    let unknowns = opts.params.len()
        + if fit_states {
            STATE_UNKNOWNS * segments.len()
        } else {
            0
        };
    if m <= unknowns && !(against_states && unknowns == 0) {
        return Err(Error::Data(format!(
            "`{}`: {m} residuals cannot determine {} parameters and {} start-state unknowns (more measurements or longer segments are needed)",
            data.source.display(),
            opts.params.len(),
            unknowns - opts.params.len()
        )));
    }
    // A start-state correction's scale: the motion capture's noise in position and
    // attitude, and that noise over a tenth of a wingbeat in velocity and body rates (the
    // size of the errors of a quadratic through the frames around a wingbeat start).
    let (pos, att) = (weights.pos, weights.att);
    let rate = 10.0 * freq_hz;
    let mut state_scales = [0.0; STATE_UNKNOWNS];
    for (i, v) in [pos, att, pos * rate, att * rate].into_iter().enumerate() {
        state_scales[3 * i..3 * i + 3].fill(v);
    }
    Ok(Setup {
        data,
        base,
        params: opts.params.clone(),
        scales,
        segments,
        rows,
        fit_states,
        state_scales,
        weights,
        dt_s,
        fd_step: opts.fd_step.unwrap_or_else(|| {
            let stops = vehicle
                .actuation
                .as_ref()
                .is_some_and(|a| a.dynamics.hinge.contact.is_some());
            if stops {
                super::types::STOPS_FD_STEP
            } else {
                super::types::DEFAULT_FD_STEP
            }
        }),
        gravity_m_s2: vehicle.gravity_m_s2,
        m,
    })
}
