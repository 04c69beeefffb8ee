//! flapwing's own protobuf messages: prost structs matching `proto/flapwing.proto`, whose
//! compiled descriptor set ([`FILE_DESCRIPTOR_SET`], built by build.rs with protox) every log
//! embeds as the schema of these messages. The Foxglove types (`PoseInFrame`,
//! `FrameTransform`, `Log`) are the foxglove crate's own (`foxglove::messages`).
//!
//! The structs are written out here rather than generated (prost-build would add a code
//! generator to the build for a dozen small messages); the unit test at the end checks them
//! against the compiled .proto: every field's name, number and type.

use foxglove::messages::Timestamp;

/// The `FileDescriptorSet` of proto/flapwing.proto and its import
/// (google/protobuf/timestamp.proto).
pub const FILE_DESCRIPTOR_SET: &[u8] = include_bytes!(concat!(env!("OUT_DIR"), "/flapwing.fds"));

#[derive(Clone, Copy, PartialEq, prost::Message)]
pub struct Vector3 {
    #[prost(double, tag = "1")]
    pub x: f64,
    #[prost(double, tag = "2")]
    pub y: f64,
    #[prost(double, tag = "3")]
    pub z: f64,
}

impl From<&nalgebra::Vector3<f64>> for Vector3 {
    fn from(v: &nalgebra::Vector3<f64>) -> Self {
        Self {
            x: v.x,
            y: v.y,
            z: v.z,
        }
    }
}

impl From<&nalgebra::UnitQuaternion<f64>> for Quaternion {
    fn from(q: &nalgebra::UnitQuaternion<f64>) -> Self {
        Self {
            x: q.i,
            y: q.j,
            z: q.k,
            w: q.w,
        }
    }
}

#[derive(Clone, Copy, PartialEq, prost::Message)]
pub struct Quaternion {
    #[prost(double, tag = "1")]
    pub x: f64,
    #[prost(double, tag = "2")]
    pub y: f64,
    #[prost(double, tag = "3")]
    pub z: f64,
    #[prost(double, tag = "4")]
    pub w: f64,
}

#[derive(Clone, Copy, PartialEq, prost::Message)]
pub struct Euler {
    #[prost(double, tag = "1")]
    pub roll: f64,
    #[prost(double, tag = "2")]
    pub pitch: f64,
    #[prost(double, tag = "3")]
    pub yaw: f64,
}

#[derive(Clone, Copy, PartialEq, prost::Message)]
pub struct WingAngles {
    #[prost(double, tag = "1")]
    pub phi: f64,
    #[prost(double, tag = "2")]
    pub theta: f64,
    #[prost(double, tag = "3")]
    pub eta: f64,
}

#[derive(Clone, Copy, PartialEq, prost::Message)]
pub struct VehicleState {
    #[prost(message, optional, tag = "1")]
    pub timestamp: Option<Timestamp>,
    #[prost(uint64, tag = "2")]
    pub step: u64,
    #[prost(double, tag = "3")]
    pub t_s: f64,
    #[prost(double, tag = "4")]
    pub phase: f64,
    #[prost(message, optional, tag = "5")]
    pub position_m: Option<Vector3>,
    #[prost(message, optional, tag = "6")]
    pub velocity_m_s: Option<Vector3>,
    #[prost(message, optional, tag = "7")]
    pub attitude: Option<Quaternion>,
    #[prost(message, optional, tag = "8")]
    pub euler_deg: Option<Euler>,
    #[prost(message, optional, tag = "9")]
    pub body_rates_rad_s: Option<Vector3>,
    #[prost(message, optional, tag = "10")]
    pub applied_force_body_n: Option<Vector3>,
    #[prost(message, optional, tag = "11")]
    pub applied_moment_body_nm: Option<Vector3>,
    #[prost(double, tag = "12")]
    pub lift_over_weight: f64,
    #[prost(message, optional, tag = "13")]
    pub memory: Option<StepMemory>,
}

#[derive(Clone, Copy, PartialEq, prost::Message)]
pub struct StepMemory {
    #[prost(uint64, tag = "1")]
    pub step: u64,
    #[prost(message, optional, tag = "2")]
    pub velocity_m_s: Option<Vector3>,
    #[prost(message, optional, tag = "3")]
    pub rates_rad_s: Option<Vector3>,
    #[prost(message, optional, tag = "4")]
    pub mid_rates_rad_s: Option<Vector3>,
    #[prost(message, optional, tag = "5")]
    pub world_from_body: Option<Quaternion>,
}

#[derive(Clone, Copy, PartialEq, prost::Message)]
pub struct Drive {
    #[prost(double, tag = "1")]
    pub bias_v: f64,
    #[prost(double, tag = "2")]
    pub amplitude_v: f64,
    #[prost(double, tag = "3")]
    pub diff_amplitude_v: f64,
    #[prost(double, tag = "4")]
    pub diff_bias_v: f64,
    #[prost(double, tag = "5")]
    pub diff_second_harmonic: f64,
}

#[derive(Clone, Copy, PartialEq, prost::Message)]
pub struct Controls {
    #[prost(message, optional, tag = "1")]
    pub timestamp: Option<Timestamp>,
    #[prost(uint64, tag = "2")]
    pub step: u64,
    #[prost(double, tag = "3")]
    pub t_s: f64,
    #[prost(double, tag = "4")]
    pub phase: f64,
    #[prost(double, tag = "5")]
    pub mean_stroke_deg: f64,
    #[prost(double, tag = "6")]
    pub amplitude_deg: f64,
    #[prost(double, tag = "7")]
    pub pitch_bias_deg: f64,
    #[prost(double, tag = "8")]
    pub freq_hz: f64,
    #[prost(double, tag = "9")]
    pub diff_amplitude_deg: f64,
    #[prost(double, tag = "10")]
    pub diff_pitch_bias_deg: f64,
    #[prost(double, tag = "11")]
    pub diff_mean_stroke_deg: f64,
    #[prost(message, optional, tag = "12")]
    pub drive: Option<Drive>,
}

#[derive(Clone, Copy, PartialEq, prost::Message)]
pub struct Actuation {
    #[prost(double, tag = "1")]
    pub hinge_moment_nm: f64,
    #[prost(double, tag = "2")]
    pub aero_pitch_moment_nm: f64,
    #[prost(double, tag = "3")]
    pub aero_stroke_moment_nm: f64,
    #[prost(double, tag = "4")]
    pub voltage_v: f64,
    #[prost(double, tag = "5")]
    pub displacement_m: f64,
    #[prost(double, tag = "6")]
    pub current_a: f64,
}

#[derive(Clone, Copy, PartialEq, prost::Message)]
pub struct WingKinematics {
    #[prost(message, optional, tag = "1")]
    pub timestamp: Option<Timestamp>,
    #[prost(uint64, tag = "2")]
    pub step: u64,
    #[prost(double, tag = "3")]
    pub t_s: f64,
    #[prost(double, tag = "4")]
    pub phase: f64,
    #[prost(message, optional, tag = "5")]
    pub angles_deg: Option<WingAngles>,
    #[prost(message, optional, tag = "6")]
    pub angles_rad: Option<WingAngles>,
    #[prost(message, optional, tag = "7")]
    pub rates_rad_s: Option<WingAngles>,
    #[prost(message, optional, tag = "8")]
    pub accelerations_rad_s2: Option<WingAngles>,
    #[prost(double, tag = "9")]
    pub t_star: f64,
    #[prost(int64, tag = "10")]
    pub half_stroke: i64,
    #[prost(bool, tag = "11")]
    pub downstroke: bool,
    #[prost(message, optional, tag = "12")]
    pub actuation: Option<Actuation>,
}

#[derive(Clone, Copy, PartialEq, prost::Message)]
pub struct ForceTerm {
    #[prost(message, optional, tag = "1")]
    pub force_n: Option<Vector3>,
    #[prost(message, optional, tag = "2")]
    pub moment_nm: Option<Vector3>,
    #[prost(double, tag = "3")]
    pub c_l: f64,
    #[prost(double, tag = "4")]
    pub c_d: f64,
}

#[derive(Clone, Copy, PartialEq, prost::Message)]
pub struct WingForces {
    #[prost(message, optional, tag = "1")]
    pub timestamp: Option<Timestamp>,
    #[prost(uint64, tag = "2")]
    pub step: u64,
    #[prost(double, tag = "3")]
    pub t_s: f64,
    #[prost(double, tag = "4")]
    pub phase: f64,
    #[prost(message, optional, tag = "5")]
    pub translational: Option<ForceTerm>,
    #[prost(message, optional, tag = "6")]
    pub rotational: Option<ForceTerm>,
    #[prost(message, optional, tag = "7")]
    pub added_mass: Option<ForceTerm>,
    #[prost(message, optional, tag = "8")]
    pub wake_capture: Option<ForceTerm>,
    #[prost(message, optional, tag = "9")]
    pub total: Option<ForceTerm>,
}

#[derive(Clone, Copy, PartialEq, prost::Message)]
pub struct ImuReading {
    #[prost(message, optional, tag = "1")]
    pub timestamp: Option<Timestamp>,
    #[prost(double, tag = "2")]
    pub t_sample_s: f64,
    #[prost(double, tag = "3")]
    pub t_delivered_s: f64,
    #[prost(message, optional, tag = "4")]
    pub gyro_rad_s: Option<Vector3>,
    #[prost(message, optional, tag = "5")]
    pub accel_m_s2: Option<Vector3>,
    #[prost(message, optional, tag = "6")]
    pub true_angular_velocity_rad_s: Option<Vector3>,
    #[prost(message, optional, tag = "7")]
    pub true_specific_force_m_s2: Option<Vector3>,
    #[prost(message, optional, tag = "8")]
    pub gyro_bias_rad_s: Option<Vector3>,
    #[prost(message, optional, tag = "9")]
    pub accel_bias_m_s2: Option<Vector3>,
}

#[derive(Clone, Copy, PartialEq, prost::Message)]
pub struct MocapReading {
    #[prost(message, optional, tag = "1")]
    pub timestamp: Option<Timestamp>,
    #[prost(double, tag = "2")]
    pub t_sample_s: f64,
    #[prost(double, tag = "3")]
    pub t_delivered_s: f64,
    #[prost(message, optional, tag = "4")]
    pub position_m: Option<Vector3>,
    #[prost(message, optional, tag = "5")]
    pub attitude: Option<Quaternion>,
    #[prost(message, optional, tag = "6")]
    pub euler_deg: Option<Euler>,
}

#[derive(Clone, PartialEq, prost::Message)]
pub struct Wind {
    #[prost(message, optional, tag = "1")]
    pub timestamp: Option<Timestamp>,
    #[prost(double, tag = "2")]
    pub t_s: f64,
    #[prost(message, repeated, tag = "3")]
    pub wing_winds_world_m_s: Vec<Vector3>,
    #[prost(message, optional, tag = "4")]
    pub uniform_world_m_s: Option<Vector3>,
}

#[derive(Clone, Copy, PartialEq, prost::Message)]
pub struct PairInflow {
    #[prost(double, tag = "1")]
    pub mean_m_s: f64,
    #[prost(double, tag = "2")]
    pub fore_m_s: f64,
    #[prost(double, tag = "3")]
    pub left_m_s: f64,
}

#[derive(Clone, PartialEq, prost::Message)]
pub struct Inflow {
    #[prost(message, optional, tag = "1")]
    pub timestamp: Option<Timestamp>,
    #[prost(double, tag = "2")]
    pub t_s: f64,
    #[prost(message, repeated, tag = "3")]
    pub pairs: Vec<PairInflow>,
}

#[derive(Clone, Copy, PartialEq, prost::Message)]
pub struct ErrorStd {
    #[prost(message, optional, tag = "1")]
    pub position_world_m: Option<Vector3>,
    #[prost(message, optional, tag = "2")]
    pub velocity_world_m_s: Option<Vector3>,
    #[prost(message, optional, tag = "3")]
    pub attitude_body_rad: Option<Vector3>,
    #[prost(message, optional, tag = "4")]
    pub accel_bias_body_m_s2: Option<Vector3>,
    #[prost(message, optional, tag = "5")]
    pub gyro_bias_body_rad_s: Option<Vector3>,
}

#[derive(Clone, Copy, PartialEq, prost::Message)]
pub struct EstimatedState {
    #[prost(message, optional, tag = "1")]
    pub position_world_m: Option<Vector3>,
    #[prost(message, optional, tag = "2")]
    pub velocity_world_m_s: Option<Vector3>,
    #[prost(message, optional, tag = "3")]
    pub attitude: Option<Quaternion>,
    #[prost(message, optional, tag = "4")]
    pub euler_deg: Option<Euler>,
    #[prost(message, optional, tag = "5")]
    pub body_rates_rad_s: Option<Vector3>,
}

#[derive(Clone, PartialEq, prost::Message)]
pub struct Estimate {
    #[prost(message, optional, tag = "1")]
    pub timestamp: Option<Timestamp>,
    #[prost(double, tag = "2")]
    pub t_s: f64,
    #[prost(uint64, tag = "3")]
    pub imu_samples: u64,
    #[prost(uint64, tag = "4")]
    pub mocap_frames: u64,
    #[prost(message, optional, tag = "5")]
    pub position_world_m: Option<Vector3>,
    #[prost(message, optional, tag = "6")]
    pub velocity_world_m_s: Option<Vector3>,
    #[prost(message, optional, tag = "7")]
    pub attitude: Option<Quaternion>,
    #[prost(message, optional, tag = "8")]
    pub euler_deg: Option<Euler>,
    #[prost(message, optional, tag = "9")]
    pub body_rates_rad_s: Option<Vector3>,
    #[prost(message, optional, tag = "10")]
    pub accel_bias_body_m_s2: Option<Vector3>,
    #[prost(message, optional, tag = "11")]
    pub gyro_bias_body_rad_s: Option<Vector3>,
    #[prost(message, optional, tag = "12")]
    pub std: Option<ErrorStd>,
    #[prost(double, repeated, tag = "13")]
    pub covariance: Vec<f64>,
    #[prost(message, optional, tag = "14")]
    pub feedback: Option<EstimatedState>,
}

#[cfg(test)]
mod tests {
    use super::*;
    use prost::Message;
    use prost_reflect::{DescriptorPool, DynamicMessage, Kind, MessageDescriptor, Value};

    /// Every field of `desc`, recursively, is set in `m` to a value other than its default,
    /// so a field the struct lacks or numbers differently shows up as missing or unknown.
    fn check_all_set(m: &DynamicMessage, desc: &MessageDescriptor, path: &str) {
        assert!(
            m.unknown_fields().next().is_none(),
            "{path}: the struct encodes a field the .proto lacks"
        );
        for f in desc.fields() {
            let p = format!("{path}.{}", f.name());
            assert!(
                m.has_field(&f),
                "{p}: not encoded (name, number or type differ)"
            );
            if let (Kind::Message(sub), Value::Message(v)) = (f.kind(), &*m.get_field(&f))
                && sub.full_name() != "google.protobuf.Timestamp"
            {
                check_all_set(v, &sub, &p);
            }
        }
    }

    fn roundtrip<M: Message>(name: &str, msg: &M) {
        let pool = DescriptorPool::decode(FILE_DESCRIPTOR_SET).unwrap();
        let desc = pool.get_message_by_name(name).unwrap();
        let dynamic = DynamicMessage::decode(desc.clone(), msg.encode_to_vec().as_slice()).unwrap();
        check_all_set(&dynamic, &desc, name);
    }

    #[test]
    fn structs_match_the_proto_file() {
        let t = Some(Timestamp::new(1, 2));
        let v = Some(Vector3 {
            x: 1.0,
            y: 2.0,
            z: 3.0,
        });
        let a = Some(WingAngles {
            phi: 1.0,
            theta: 2.0,
            eta: 3.0,
        });
        let term = Some(ForceTerm {
            force_n: v,
            moment_nm: v,
            c_l: 1.0,
            c_d: 2.0,
        });
        roundtrip(
            "flapwing.VehicleState",
            &VehicleState {
                timestamp: t,
                step: 1,
                t_s: 1.0,
                phase: 1.0,
                position_m: v,
                velocity_m_s: v,
                attitude: Some(Quaternion {
                    x: 1.0,
                    y: 2.0,
                    z: 3.0,
                    w: 4.0,
                }),
                euler_deg: Some(Euler {
                    roll: 1.0,
                    pitch: 2.0,
                    yaw: 3.0,
                }),
                body_rates_rad_s: v,
                applied_force_body_n: v,
                applied_moment_body_nm: v,
                lift_over_weight: 1.0,
                memory: Some(StepMemory {
                    step: 7,
                    velocity_m_s: v,
                    rates_rad_s: v,
                    mid_rates_rad_s: v,
                    world_from_body: Some(Quaternion {
                        x: 0.5,
                        y: 0.5,
                        z: 0.5,
                        w: 0.5,
                    }),
                }),
            },
        );
        roundtrip(
            "flapwing.Controls",
            &Controls {
                timestamp: t,
                step: 1,
                t_s: 1.0,
                phase: 1.0,
                mean_stroke_deg: 1.0,
                amplitude_deg: 1.0,
                pitch_bias_deg: 1.0,
                freq_hz: 1.0,
                diff_amplitude_deg: 1.0,
                diff_pitch_bias_deg: 1.0,
                diff_mean_stroke_deg: 1.0,
                drive: Some(Drive {
                    bias_v: 1.0,
                    amplitude_v: 1.0,
                    diff_amplitude_v: 1.0,
                    diff_bias_v: 1.0,
                    diff_second_harmonic: 1.0,
                }),
            },
        );
        roundtrip(
            "flapwing.WingKinematics",
            &WingKinematics {
                timestamp: t,
                step: 1,
                t_s: 1.0,
                phase: 1.0,
                angles_deg: a,
                angles_rad: a,
                rates_rad_s: a,
                accelerations_rad_s2: a,
                t_star: 1.0,
                half_stroke: 1,
                downstroke: true,
                actuation: Some(Actuation {
                    hinge_moment_nm: 1.0,
                    aero_pitch_moment_nm: 1.0,
                    aero_stroke_moment_nm: 1.0,
                    voltage_v: 1.0,
                    displacement_m: 1.0,
                    current_a: 1.0,
                }),
            },
        );
        roundtrip(
            "flapwing.WingForces",
            &WingForces {
                timestamp: t,
                step: 1,
                t_s: 1.0,
                phase: 1.0,
                translational: term,
                rotational: term,
                added_mass: term,
                wake_capture: term,
                total: term,
            },
        );
        roundtrip(
            "flapwing.ImuReading",
            &ImuReading {
                timestamp: t,
                t_sample_s: 1.0,
                t_delivered_s: 1.0,
                gyro_rad_s: v,
                accel_m_s2: v,
                true_angular_velocity_rad_s: v,
                true_specific_force_m_s2: v,
                gyro_bias_rad_s: v,
                accel_bias_m_s2: v,
            },
        );
        roundtrip(
            "flapwing.MocapReading",
            &MocapReading {
                timestamp: t,
                t_sample_s: 1.0,
                t_delivered_s: 1.0,
                position_m: v,
                attitude: Some(Quaternion {
                    x: 1.0,
                    y: 2.0,
                    z: 3.0,
                    w: 4.0,
                }),
                euler_deg: Some(Euler {
                    roll: 1.0,
                    pitch: 2.0,
                    yaw: 3.0,
                }),
            },
        );
        roundtrip(
            "flapwing.Inflow",
            &Inflow {
                timestamp: t,
                t_s: 1.0,
                pairs: vec![PairInflow {
                    mean_m_s: 1.0,
                    fore_m_s: 2.0,
                    left_m_s: 3.0,
                }],
            },
        );
        roundtrip(
            "flapwing.Wind",
            &Wind {
                timestamp: t,
                t_s: 1.0,
                wing_winds_world_m_s: vec![v.unwrap(), v.unwrap()],
                uniform_world_m_s: v,
            },
        );
        let q = Some(Quaternion {
            x: 1.0,
            y: 2.0,
            z: 3.0,
            w: 4.0,
        });
        let e = Some(Euler {
            roll: 1.0,
            pitch: 2.0,
            yaw: 3.0,
        });
        roundtrip(
            "flapwing.Estimate",
            &Estimate {
                timestamp: t,
                t_s: 1.0,
                imu_samples: 1,
                mocap_frames: 1,
                position_world_m: v,
                velocity_world_m_s: v,
                attitude: q,
                euler_deg: e,
                body_rates_rad_s: v,
                accel_bias_body_m_s2: v,
                gyro_bias_body_rad_s: v,
                std: Some(ErrorStd {
                    position_world_m: v,
                    velocity_world_m_s: v,
                    attitude_body_rad: v,
                    accel_bias_body_m_s2: v,
                    gyro_bias_body_rad_s: v,
                }),
                covariance: vec![1.0; 225],
                feedback: Some(EstimatedState {
                    position_world_m: v,
                    velocity_world_m_s: v,
                    attitude: q,
                    euler_deg: e,
                    body_rates_rad_s: v,
                }),
            },
        );
    }
}
