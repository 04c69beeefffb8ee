//! The C ABI's types: term indices, the plain-data structs a host fills and reads, the
//! opaque handle, and their conversions to and from flapsim's types (SI units, body frame
//! x forward, y left, z up about the centre of mass; quaternions w, x, y, z).

use flapsim::{Controls, FromVehicle, State, Vehicle, WingSet, WingSetOutput};
use nalgebra::{Quaternion, UnitQuaternion, Vector3};

use crate::error::Failure;

/// Term index: the translational (quasi-steady circulatory) force.
pub const FLAPWING_TERM_TRANSLATIONAL: u32 = 0;
/// Term index: the rotational circulation.
pub const FLAPWING_TERM_ROTATIONAL: u32 = 1;
/// Term index: the added mass.
pub const FLAPWING_TERM_ADDED_MASS: u32 = 2;
/// Term index: the wake capture.
pub const FLAPWING_TERM_WAKE_CAPTURE: u32 = 3;

/// Largest deviation of the body quaternion's norm from 1 that a step accepts (the
/// quaternion is then normalised).
pub const FLAPWING_QUATERNION_NORM_TOLERANCE: f64 = 1e-6;

/// One wing set (opaque): the wings of a vehicle model, their state, and the model's body.
#[derive(Debug, Clone)]
pub struct FlapwingWings {
    pub(crate) set: WingSet,
    pub(crate) body: FlapwingBodyProperties,
    /// The host's inertia of the body when the host takes the gyroscopic term at the step's
    /// start (`flapwing_wings_set_gyroscopic_host`): each step's total then carries the
    /// correction.
    pub(crate) gyroscopic_host: Option<nalgebra::Matrix3<f64>>,
}

/// The body's state at t_k, from the host.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FlapwingBodyState {
    /// Position of the centre of mass, world, m.
    pub position_m: [f64; 3],
    /// Attitude, world_from_body, unit quaternion w, x, y, z.
    pub world_from_body_wxyz: [f64; 4],
    /// Velocity of the centre of mass, world, m/s.
    pub velocity_world_m_s: [f64; 3],
    /// Angular velocity, body frame, rad/s.
    pub angular_velocity_body_rad_s: [f64; 3],
}

/// Force and moment on the body.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FlapwingWrench {
    /// Force, body frame, N.
    pub force_body_n: [f64; 3],
    /// Moment about the centre of mass, body frame, N m.
    pub moment_body_nm: [f64; 3],
}

/// The model's body, for hosts that build it.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FlapwingBodyProperties {
    /// Mass, kg.
    pub mass_kg: f64,
    /// Inertia tensor about the centre of mass, body frame, row-major, kg m^2.
    pub inertia_body_kg_m2: [f64; 9],
    /// Gravitational acceleration, m/s^2 (along world -z).
    pub gravity_m_s2: f64,
    /// Initial position of the centre of mass, world, m.
    pub initial_position_m: [f64; 3],
    /// Initial attitude, world_from_body, w, x, y, z.
    pub initial_world_from_body_wxyz: [f64; 4],
}

/// Control inputs (flapsim::Controls), SI (rad, Hz, V): offsets on the model's kinematics
/// (prescribed wings) or on its drive (actuated wings).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FlapwingControls {
    /// Mean stroke angle offset, rad.
    pub mean_stroke_rad: f64,
    /// Stroke amplitude offset, rad.
    pub amplitude_rad: f64,
    /// Pitch bias offset, rad.
    pub pitch_bias_rad: f64,
    /// Mid-stroke angle-of-attack offset, rad.
    pub aoa_rad: f64,
    /// Wingbeat frequency offset, Hz.
    pub freq_hz: f64,
    /// Left-minus-right amplitude, rad.
    pub diff_amplitude_rad: f64,
    /// Left-minus-right pitch bias, rad.
    pub diff_pitch_bias_rad: f64,
    /// Left-minus-right mean stroke angle, rad.
    pub diff_mean_stroke_rad: f64,
    /// Drive bias offset, V (actuated wings).
    pub bias_v: f64,
    /// Drive amplitude offset, V (actuated wings).
    pub amplitude_v: f64,
    /// Left-minus-right drive amplitude, V (actuated wings).
    pub diff_amplitude_v: f64,
    /// Left-minus-right drive bias, V (actuated wings).
    pub diff_bias_v: f64,
    /// Left-minus-right second-harmonic fraction (actuated wings).
    pub diff_second_harmonic: f64,
}

/// One wing after the last step.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FlapwingWingState {
    /// Stroke angle phi, rad (wingforce WingAngles).
    pub stroke_rad: f64,
    /// Pitch angle theta, rad.
    pub pitch_rad: f64,
    /// Deviation angle eta, rad.
    pub deviation_rad: f64,
    /// d phi / dt, rad/s.
    pub stroke_rate_rad_s: f64,
    /// d theta / dt, rad/s.
    pub pitch_rate_rad_s: f64,
    /// d eta / dt, rad/s.
    pub deviation_rate_rad_s: f64,
    /// This wing's total aerodynamic force, body frame, N.
    pub force_body_n: [f64; 3],
    /// Hinge spring, damper and stop moment about the pitch axis, N m (actuated wings; 0
    /// otherwise).
    pub hinge_moment_nm: f64,
}

impl From<&FlapwingControls> for Controls {
    fn from(c: &FlapwingControls) -> Self {
        Controls {
            mean_stroke_rad: c.mean_stroke_rad,
            amplitude_rad: c.amplitude_rad,
            pitch_bias_rad: c.pitch_bias_rad,
            aoa_rad: c.aoa_rad,
            freq_hz: c.freq_hz,
            diff_amplitude_rad: c.diff_amplitude_rad,
            diff_pitch_bias_rad: c.diff_pitch_bias_rad,
            diff_mean_stroke_rad: c.diff_mean_stroke_rad,
            bias_v: c.bias_v,
            amplitude_v: c.amplitude_v,
            diff_amplitude_v: c.diff_amplitude_v,
            diff_bias_v: c.diff_bias_v,
            diff_second_harmonic: c.diff_second_harmonic,
        }
    }
}

impl From<&Controls> for FlapwingControls {
    fn from(c: &Controls) -> Self {
        FlapwingControls {
            mean_stroke_rad: c.mean_stroke_rad,
            amplitude_rad: c.amplitude_rad,
            pitch_bias_rad: c.pitch_bias_rad,
            aoa_rad: c.aoa_rad,
            freq_hz: c.freq_hz,
            diff_amplitude_rad: c.diff_amplitude_rad,
            diff_pitch_bias_rad: c.diff_pitch_bias_rad,
            diff_mean_stroke_rad: c.diff_mean_stroke_rad,
            bias_v: c.bias_v,
            amplitude_v: c.amplitude_v,
            diff_amplitude_v: c.diff_amplitude_v,
            diff_bias_v: c.diff_bias_v,
            diff_second_harmonic: c.diff_second_harmonic,
        }
    }
}

impl FlapwingControls {
    /// The name of the first field that is not finite, if any.
    pub(crate) fn first_non_finite(&self) -> Option<&'static str> {
        let fields = [
            ("mean_stroke_rad", self.mean_stroke_rad),
            ("amplitude_rad", self.amplitude_rad),
            ("pitch_bias_rad", self.pitch_bias_rad),
            ("aoa_rad", self.aoa_rad),
            ("freq_hz", self.freq_hz),
            ("diff_amplitude_rad", self.diff_amplitude_rad),
            ("diff_pitch_bias_rad", self.diff_pitch_bias_rad),
            ("diff_mean_stroke_rad", self.diff_mean_stroke_rad),
            ("bias_v", self.bias_v),
            ("amplitude_v", self.amplitude_v),
            ("diff_amplitude_v", self.diff_amplitude_v),
            ("diff_bias_v", self.diff_bias_v),
            ("diff_second_harmonic", self.diff_second_harmonic),
        ];
        fields
            .into_iter()
            .find(|(_, x)| !x.is_finite())
            .map(|(name, _)| name)
    }
}

impl FlapwingBodyState {
    /// The body state as flapsim's [`State`], or a message naming the first field that is not
    /// finite or a quaternion that is not of unit norm (within
    /// [`FLAPWING_QUATERNION_NORM_TOLERANCE`]; it is normalised).
    pub fn to_state(&self) -> Result<State, String> {
        let fields: [(&str, &[f64]); 4] = [
            ("position_m", &self.position_m),
            ("world_from_body_wxyz", &self.world_from_body_wxyz),
            ("velocity_world_m_s", &self.velocity_world_m_s),
            (
                "angular_velocity_body_rad_s",
                &self.angular_velocity_body_rad_s,
            ),
        ];
        for (name, v) in fields {
            if let Some(i) = v.iter().position(|x| !x.is_finite()) {
                return Err(format!(
                    "body state: {name}[{i}] = {}; allowed: finite numbers",
                    v[i]
                ));
            }
        }
        let [w, x, y, z] = self.world_from_body_wxyz;
        let q = Quaternion::new(w, x, y, z);
        let norm = q.norm();
        // NaN cannot reach here (the components are finite), but a norm that overflowed can.
        if (norm - 1.0).abs() > FLAPWING_QUATERNION_NORM_TOLERANCE || !norm.is_finite() {
            return Err(format!(
                "body state: world_from_body_wxyz = [{w}, {x}, {y}, {z}] has norm {norm}; allowed: a unit quaternion (norm within {FLAPWING_QUATERNION_NORM_TOLERANCE:e} of 1)"
            ));
        }
        Ok(State {
            position_m: Vector3::from(self.position_m),
            world_from_body: UnitQuaternion::from_quaternion(q),
            velocity_m_s: Vector3::from(self.velocity_world_m_s),
            angular_velocity_body_rad_s: Vector3::from(self.angular_velocity_body_rad_s),
        })
    }
}

impl From<&flapsim::BodyLoad> for FlapwingWrench {
    fn from(l: &flapsim::BodyLoad) -> Self {
        Self {
            force_body_n: l.force_n.into(),
            moment_body_nm: l.moment_nm.into(),
        }
    }
}

pub(crate) fn wxyz(q: &UnitQuaternion<f64>) -> [f64; 4] {
    [q.w, q.i, q.j, q.k]
}

/// The set with the vehicle's body drag turned on: the C ABI's hosts (MuJoCo, the FMU, a C
/// program) apply the wrench the set returns and nothing else, and the trims they fly at
/// balance that drag (docs/plugin.md).
pub(crate) fn with_body_drag(mut set: WingSet, v: &Vehicle) -> flapsim::Result<WingSet> {
    set.set_body_drag_area_m2(v.body_drag_area_m2)?;
    Ok(set)
}

pub(crate) fn body_properties(v: &Vehicle) -> FlapwingBodyProperties {
    let i = &v.inertia_kg_m2;
    let mut inertia = [0.0; 9];
    for r in 0..3 {
        for c in 0..3 {
            inertia[3 * r + c] = i[(r, c)];
        }
    }
    FlapwingBodyProperties {
        mass_kg: v.mass_kg,
        inertia_body_kg_m2: inertia,
        gravity_m_s2: v.gravity_m_s2,
        initial_position_m: v.initial_position_m.into(),
        initial_world_from_body_wxyz: wxyz(&v.initial_attitude),
    }
}

impl FlapwingWings {
    /// A handle from TOML text: `dt_s > 0` is the host's step (at most 1/10 of the wingbeat
    /// period, `wingset::check_dt`), `dt_s == 0` the model's own. The set applies the body's
    /// parasite drag (`[body] drag_area_m2`): a host applies the whole wrench it returns.
    pub(crate) fn from_toml(
        function: &str,
        text: &str,
        origin: &str,
        dt_s: f64,
    ) -> Result<Self, Failure> {
        if !(dt_s >= 0.0 && dt_s.is_finite()) {
            return Err(Failure::invalid(format!(
                "{function}: dt_s = {dt_s}; allowed: a finite step > 0 s of at most 1/10 of the wingbeat period, or 0 for the model's own step (1 / (f sim.steps_per_wingbeat))"
            )));
        }
        let vehicle = Vehicle::from_toml(text, origin).map_err(|e| Failure::sim(function, e))?;
        let set = if dt_s == 0.0 {
            WingSet::from_vehicle_sized(&vehicle)
        } else {
            WingSet::from_vehicle(&vehicle, dt_s)
        }
        .and_then(|s| with_body_drag(s, &vehicle))
        .map_err(|e| Failure::sim(function, e))?;
        Ok(Self {
            body: body_properties(&vehicle),
            set,
            gyroscopic_host: None,
        })
    }

    /// The wing set (for Rust callers and tests).
    pub fn wing_set(&self) -> &WingSet {
        &self.set
    }

    pub(crate) fn output(&self) -> &WingSetOutput {
        self.set.output()
    }
}
