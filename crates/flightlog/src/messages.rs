//! The JSON messages, built from a step's output. Field lists match [`crate::schema`].

use flapsim::StepOutput;
use nalgebra::{Matrix3, Rotation3, UnitQuaternion, Vector3};
use serde::Serialize;
use wingforce::wing::WingFrame;
use wingforce::{Side, TermForce};

/// Replaces non-finite numbers by 0 and remembers that it did.
#[derive(Debug, Default)]
pub(crate) struct Fin {
    pub nonfinite: bool,
}

impl Fin {
    pub fn f(&mut self, x: f64) -> f64 {
        if x.is_finite() {
            x
        } else {
            self.nonfinite = true;
            0.0
        }
    }
    pub fn v(&mut self, v: &Vector3<f64>) -> Vec3 {
        Vec3 {
            x: self.f(v.x),
            y: self.f(v.y),
            z: self.f(v.z),
        }
    }
    pub fn q(&mut self, q: &UnitQuaternion<f64>) -> Quat {
        Quat {
            x: self.f(q.i),
            y: self.f(q.j),
            z: self.f(q.k),
            w: self.f(q.w),
        }
    }
}

/// `{sec, nsec}` (Foxglove's time).
#[derive(Debug, Clone, Copy, Serialize)]
pub(crate) struct Time {
    pub sec: u64,
    pub nsec: u32,
}

impl Time {
    pub fn from_ns(ns: u64) -> Self {
        Self {
            sec: ns / 1_000_000_000,
            nsec: (ns % 1_000_000_000) as u32,
        }
    }
}

/// Simulation time in integer nanoseconds (0 for negative or non-finite times).
pub(crate) fn time_ns(t_s: f64) -> u64 {
    let ns = (t_s * 1e9).round();
    if ns.is_finite() && ns > 0.0 {
        if ns >= u64::MAX as f64 {
            u64::MAX
        } else {
            ns as u64
        }
    } else {
        0
    }
}

#[derive(Debug, Clone, Copy, Serialize)]
pub(crate) struct Vec3 {
    pub x: f64,
    pub y: f64,
    pub z: f64,
}

#[derive(Debug, Clone, Copy, Serialize)]
pub(crate) struct Quat {
    pub x: f64,
    pub y: f64,
    pub z: f64,
    pub w: f64,
}

#[derive(Debug, Serialize)]
pub(crate) struct Pose {
    pub position: Vec3,
    pub orientation: Quat,
}

#[derive(Debug, Serialize)]
pub(crate) struct PoseInFrame<'a> {
    pub timestamp: Time,
    pub frame_id: &'a str,
    pub pose: Pose,
}

#[derive(Debug, Serialize)]
pub(crate) struct FrameTransform<'a> {
    pub timestamp: Time,
    pub parent_frame_id: &'a str,
    pub child_frame_id: &'a str,
    pub translation: Vec3,
    pub rotation: Quat,
}

#[derive(Debug, Serialize)]
pub(crate) struct Log<'a> {
    pub timestamp: Time,
    pub level: u8,
    pub message: &'a str,
    pub name: &'a str,
    pub file: &'a str,
    pub line: u32,
}

#[derive(Debug, Serialize)]
pub(crate) struct Euler {
    pub roll: f64,
    pub pitch: f64,
    pub yaw: f64,
}

#[derive(Debug, Serialize)]
pub(crate) struct VehicleState {
    pub timestamp: Time,
    pub step: u64,
    pub t_s: f64,
    pub phase: f64,
    pub position_m: Vec3,
    pub velocity_m_s: Vec3,
    pub attitude: Quat,
    pub euler_deg: Euler,
    pub body_rates_rad_s: Vec3,
    pub applied_force_body_n: Vec3,
    pub applied_moment_body_nm: Vec3,
    pub lift_over_weight: f64,
    pub nonfinite: bool,
}

#[derive(Debug, Serialize)]
pub(crate) struct Controls {
    pub timestamp: Time,
    pub step: u64,
    pub t_s: f64,
    pub phase: f64,
    pub mean_stroke_deg: f64,
    pub amplitude_deg: f64,
    pub pitch_bias_deg: f64,
    pub freq_hz: f64,
    pub diff_amplitude_deg: f64,
    pub diff_pitch_bias_deg: f64,
    pub diff_mean_stroke_deg: f64,
    pub nonfinite: bool,
}

#[derive(Debug, Serialize)]
pub(crate) struct Angles3 {
    pub phi: f64,
    pub theta: f64,
    pub eta: f64,
}

#[derive(Debug, Serialize)]
pub(crate) struct WingKinematics {
    pub timestamp: Time,
    pub step: u64,
    pub t_s: f64,
    pub phase: f64,
    pub angles_deg: Angles3,
    pub angles_rad: Angles3,
    pub rates_rad_s: Angles3,
    pub accelerations_rad_s2: Angles3,
    pub t_star: f64,
    pub half_stroke: i64,
    pub downstroke: bool,
    pub nonfinite: bool,
}

#[derive(Debug, Clone, Copy, Serialize)]
pub(crate) struct Part {
    pub force_n: Vec3,
    pub moment_nm: Vec3,
    pub c_l: f64,
    pub c_d: f64,
}

#[derive(Debug, Serialize)]
pub(crate) struct WingForces {
    pub timestamp: Time,
    pub step: u64,
    pub t_s: f64,
    pub phase: f64,
    pub translational: Part,
    pub rotational: Part,
    pub added_mass: Part,
    pub wake_capture: Part,
    pub total: Part,
    pub nonfinite: bool,
}

/// What the recorder knows about each wing that does not change during a run.
#[derive(Debug, Clone, Copy)]
pub(crate) struct WingStatic {
    pub side: Side,
    pub hinge_in_body_m: Vector3<f64>,
    pub body_from_stroke: Matrix3<f64>,
}

/// The rotation base_link_from_wing of a wing frame (see [`crate::schema::wing_frame_doc`]).
pub(crate) fn wing_rotation(w: &WingStatic, angles: &wingforce::WingAngles) -> UnitQuaternion<f64> {
    let fr = WingFrame::new(angles, w.side);
    let z = fr.e_le.cross(&fr.e_span);
    let m = w.body_from_stroke * Matrix3::from_columns(&[fr.e_le, fr.e_span, z]);
    UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(m))
}

/// Every message of one sample, serialized, in channel order of [`crate::schema::CHANNELS`]
/// (events excluded), plus the numbers the Rerun sink needs.
#[derive(Debug)]
pub(crate) struct Sample {
    pub t_ns: u64,
    /// JSON bytes per channel index 0..10 (index of [`crate::schema::CHANNELS`]).
    pub messages: Vec<(usize, Vec<u8>)>,
    #[cfg_attr(not(feature = "rerun"), allow(dead_code))]
    pub frame: FrameData,
}

/// The numbers a 3D view needs for one sample (all finite: sanitized).
#[derive(Debug, Clone, Copy, Default)]
#[cfg_attr(not(feature = "rerun"), allow(dead_code))]
pub(crate) struct FrameData {
    pub t_ns: u64,
    pub position: [f64; 3],
    /// world_from_body, x y z w.
    pub attitude: [f64; 4],
    pub euler_deg: [f64; 3],
    pub lift_over_weight: f64,
    /// Per wing: hinge (body frame), base_link_from_wing (x y z w).
    pub wing_hinge: [[f64; 3]; 2],
    pub wing_rotation: [[f64; 4]; 2],
    /// Per wing, per part (4 terms and total): force (body frame, N), C_L, C_D.
    pub force_n: [[[f64; 3]; 5]; 2],
    pub c_l: [[f64; 5]; 2],
    pub c_d: [[f64; 5]; 2],
}

fn arr(v: &Vec3) -> [f64; 3] {
    [v.x, v.y, v.z]
}
fn arr4(q: &Quat) -> [f64; 4] {
    [q.x, q.y, q.z, q.w]
}

fn part(fin: &mut Fin, t: &TermForce, hinge: &Vector3<f64>) -> Part {
    Part {
        force_n: fin.v(&t.force_n),
        moment_nm: fin.v(&t.moment_about_com_nm(hinge)),
        c_l: fin.f(t.c_l),
        c_d: fin.f(t.c_d),
    }
}

/// Builds every message of one step's output.
pub(crate) fn sample(
    out: &StepOutput,
    wings: &[WingStatic; 2],
    weight_n: f64,
) -> serde_json::Result<Sample> {
    let t_ns = time_ns(out.t_s);
    let ts = Time::from_ns(t_ns);
    let s = &out.state;
    let mut frame = FrameData {
        t_ns,
        ..FrameData::default()
    };
    let mut messages = Vec::with_capacity(10);

    // Vehicle state.
    let time_bad = !(out.t_s.is_finite() && out.phase.is_finite());
    let mut fin = Fin::default();
    let t_s = fin.f(out.t_s);
    let phase = fin.f(out.phase);
    let (roll, pitch, yaw) = s.euler_rad();
    let vertical = (s.world_from_body * out.total.force_n).z;
    let state = VehicleState {
        timestamp: ts,
        step: out.step,
        t_s,
        phase,
        position_m: fin.v(&s.position_m),
        velocity_m_s: fin.v(&s.velocity_m_s),
        attitude: fin.q(&s.world_from_body),
        euler_deg: Euler {
            roll: fin.f(roll.to_degrees()),
            pitch: fin.f(pitch.to_degrees()),
            yaw: fin.f(yaw.to_degrees()),
        },
        body_rates_rad_s: fin.v(&s.angular_velocity_body_rad_s),
        applied_force_body_n: fin.v(&out.total.force_n),
        applied_moment_body_nm: fin.v(&out.total.moment_nm),
        lift_over_weight: fin.f(vertical / weight_n),
        nonfinite: false,
    };
    let state = VehicleState {
        nonfinite: fin.nonfinite,
        ..state
    };
    frame.position = arr(&state.position_m);
    frame.attitude = arr4(&state.attitude);
    frame.euler_deg = [
        state.euler_deg.roll,
        state.euler_deg.pitch,
        state.euler_deg.yaw,
    ];
    frame.lift_over_weight = state.lift_over_weight;

    // Foxglove pose and body transform (sanitized the same way; the flag is on the state).
    let pose = PoseInFrame {
        timestamp: ts,
        frame_id: crate::schema::FRAME_WORLD,
        pose: Pose {
            position: state.position_m,
            orientation: state.attitude,
        },
    };
    messages.push((0, serde_json::to_vec(&pose)?));
    let tf = FrameTransform {
        timestamp: ts,
        parent_frame_id: crate::schema::FRAME_WORLD,
        child_frame_id: crate::schema::FRAME_BODY,
        translation: state.position_m,
        rotation: state.attitude,
    };
    messages.push((1, serde_json::to_vec(&tf)?));

    // Wing transforms.
    for (i, w) in wings.iter().enumerate() {
        let mut f = Fin::default();
        let q = wing_rotation(w, &out.wings[i].angles);
        let tf = FrameTransform {
            timestamp: ts,
            parent_frame_id: crate::schema::FRAME_BODY,
            child_frame_id: if i == 0 {
                crate::schema::FRAME_WING_LEFT
            } else {
                crate::schema::FRAME_WING_RIGHT
            },
            translation: f.v(&w.hinge_in_body_m),
            rotation: f.q(&q),
        };
        frame.wing_hinge[i] = arr(&tf.translation);
        frame.wing_rotation[i] = arr4(&tf.rotation);
        messages.push((2 + i, serde_json::to_vec(&tf)?));
    }
    messages.push((4, serde_json::to_vec(&state)?));

    // Controls.
    let c = &out.controls;
    let mut f = Fin::default();
    let controls = Controls {
        timestamp: ts,
        step: out.step,
        t_s,
        phase,
        mean_stroke_deg: f.f(c.mean_stroke_rad.to_degrees()),
        amplitude_deg: f.f(c.amplitude_rad.to_degrees()),
        pitch_bias_deg: f.f(c.pitch_bias_rad.to_degrees()),
        freq_hz: f.f(c.freq_hz),
        diff_amplitude_deg: f.f(c.diff_amplitude_rad.to_degrees()),
        diff_pitch_bias_deg: f.f(c.diff_pitch_bias_rad.to_degrees()),
        diff_mean_stroke_deg: f.f(c.diff_mean_stroke_rad.to_degrees()),
        nonfinite: false,
    };
    let controls = Controls {
        nonfinite: f.nonfinite || time_bad,
        ..controls
    };
    messages.push((5, serde_json::to_vec(&controls)?));

    // Kinematics per wing.
    for (i, wf) in out.wings.iter().enumerate() {
        let a = &wf.angles;
        let mut f = Fin::default();
        let k = WingKinematics {
            timestamp: ts,
            step: out.step,
            t_s,
            phase,
            angles_deg: Angles3 {
                phi: f.f(a.phi.to_degrees()),
                theta: f.f(a.theta.to_degrees()),
                eta: f.f(a.eta.to_degrees()),
            },
            angles_rad: Angles3 {
                phi: f.f(a.phi),
                theta: f.f(a.theta),
                eta: f.f(a.eta),
            },
            rates_rad_s: Angles3 {
                phi: f.f(a.phi_dot),
                theta: f.f(a.theta_dot),
                eta: f.f(a.eta_dot),
            },
            accelerations_rad_s2: Angles3 {
                phi: f.f(a.phi_ddot),
                theta: f.f(a.theta_ddot),
                eta: f.f(a.eta_ddot),
            },
            t_star: f.f(wf.phase.t_star),
            half_stroke: wf.phase.half_stroke,
            downstroke: wf.phase.downstroke,
            nonfinite: false,
        };
        let k = WingKinematics {
            nonfinite: f.nonfinite || time_bad,
            ..k
        };
        messages.push((6 + i, serde_json::to_vec(&k)?));
    }

    // Forces per wing.
    for (i, wf) in out.wings.iter().enumerate() {
        let hinge = &wings[i].hinge_in_body_m;
        let mut f = Fin::default();
        let parts = [
            part(&mut f, &wf.terms[0], hinge),
            part(&mut f, &wf.terms[1], hinge),
            part(&mut f, &wf.terms[2], hinge),
            part(&mut f, &wf.terms[3], hinge),
            part(&mut f, &wf.total, hinge),
        ];
        for (j, p) in parts.iter().enumerate() {
            frame.force_n[i][j] = arr(&p.force_n);
            frame.c_l[i][j] = p.c_l;
            frame.c_d[i][j] = p.c_d;
        }
        let m = WingForces {
            timestamp: ts,
            step: out.step,
            t_s,
            phase,
            translational: parts[0],
            rotational: parts[1],
            added_mass: parts[2],
            wake_capture: parts[3],
            total: parts[4],
            nonfinite: f.nonfinite || time_bad,
        };
        messages.push((8 + i, serde_json::to_vec(&m)?));
    }
    Ok(Sample {
        t_ns,
        messages,
        frame,
    })
}

/// A `foxglove.Log` message.
pub(crate) fn log_message(t_ns: u64, level: u8, message: &str) -> serde_json::Result<Vec<u8>> {
    serde_json::to_vec(&Log {
        timestamp: Time::from_ns(t_ns),
        level,
        message,
        name: "flapwing",
        file: "",
        line: 0,
    })
}
