//! The parameters a fit can vary, by name. Model parameters change the vehicle model file's
//! numbers (and the fitted model file gets their fitted values); measurement parameters
//! (sensor biases) belong to the flight, not the vehicle, and are reported only.
//!
//! | name | what | model field |
//! | --- | --- | --- |
//! | `inertia_xx_kg_m2`, `inertia_yy_kg_m2`, `inertia_zz_kg_m2` | body inertia about the CoM, body axes | `body.inertia_diag_kg_m2` |
//! | `mass_kg` | body mass (weight, and the induced inflow's thrust) | `body.mass_kg` |
//! | `com_offset_x_m`, `com_offset_z_m` | where the true centre of mass lies from the model's, body axes: every hinge moves by minus the offset relative to the CoM (a sideways offset would break the model's mirror symmetry) | `hinge.left_in_body_m` |
//! | `air_density_kg_m3` | a scale of every aerodynamic term at once (and of the Reynolds number) | `fluid.density_kg_m3` |
//! | `rotational_coefficient` | C_rot, the scale of the rotational-circulation term | `aero.c_rot` |
//! | `stroke_plane_tilt_rad` | stroke-plane tilt relative to the body (written in degrees) | `hinge.stroke_plane_tilt_deg` |
//! | `hinge_stiffness_nm_rad` | an actuated wing's pitch-hinge stiffness | `actuation.hinge.stiffness_nm_rad` |
//! | `hinge_damping_nm_s_rad` | an actuated wing's pitch-hinge damping | `actuation.hinge.damping_nm_s_rad` |
//! | `stroke_stiffness_nm_rad` | the stroke's torsional spring (the hummingbird's flexure) | `actuation.stroke.flexure_nm_rad` |
//! | `force_per_volt_n_v` | a piezo actuator's blocked force per volt | `actuation.piezo.force_per_volt_n_v` |
//! | `torque_constant_nm_a` | a DC motor's torque constant; its back-EMF constant scales with it (equal in SI for an ideal motor) | `actuation.dc_motor.torque_constant_nm_a`, `back_emf_v_s_rad` |
//! | `wing_stroke_inertia_kg_m2` | an actuated wing's inertia about the stroke axis | `actuation.wing_inertia.stroke_inertia_kg_m2` |
//! | `stop_restitution` | the pitch stops' coefficient of restitution | `actuation.hinge.stop.restitution` |
//! | `mocap_bias_x_m`, `mocap_bias_y_m`, `mocap_bias_z_m` | a constant offset of the motion capture's positions, world | (measurement) |
//! | `gyro_bias_x_rad_s`, `gyro_bias_y_rad_s`, `gyro_bias_z_rad_s` | the gyroscope's constant bias, body | (measurement) |
//! | `accel_bias_x_m_s2`, `accel_bias_y_m_s2`, `accel_bias_z_m_s2` | the accelerometer's constant bias, body | (measurement) |
//!
//! The fit works on each parameter divided by its scale ([`Param::scale`]): the nominal
//! value's magnitude, or for a parameter whose nominal value is 0 a typical size (1 % of the
//! body length for a CoM offset, the sensor's noise for a bias, 0.1 for a restitution, an
//! estimate of its size). An actuated wing's parameter needs a model with that part
//! ([`Param::check_model`]).

use flapsim::VehicleSpec;
use serde::Serialize;

use crate::error::{Error, Result};

/// A DC motor's back-EMF constant, V s/rad, when its torque constant is set to `kt_nm_a`:
/// scaled with it from `motor`'s (the two are equal in SI for an ideal motor), so the
/// motor's own ratio stays.
pub(crate) fn back_emf_scaled(motor: &flapsim::actuated::DcMotor, kt_nm_a: f64) -> f64 {
    motor.back_emf_v_s_rad / motor.torque_constant_nm_a * kt_nm_a
}

/// A parameter to fit.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(into = "String")]
pub enum Param {
    /// Ixx, kg m^2.
    InertiaXx,
    /// Iyy, kg m^2.
    InertiaYy,
    /// Izz, kg m^2.
    InertiaZz,
    /// Mass, kg.
    Mass,
    /// CoM offset along body x, m.
    ComOffsetX,
    /// CoM offset along body z, m.
    ComOffsetZ,
    /// Air density, kg/m^3.
    AirDensity,
    /// C_rot.
    RotationalCoefficient,
    /// Stroke-plane tilt, rad.
    StrokePlaneTilt,
    /// Pitch-hinge stiffness of an actuated wing, N m/rad.
    HingeStiffness,
    /// Pitch-hinge damping of an actuated wing, N m s/rad.
    HingeDamping,
    /// Stroke spring of an actuated wing, N m/rad.
    StrokeStiffness,
    /// Piezo force per volt, N/V.
    ForcePerVolt,
    /// DC motor torque constant, N m/A (the back-EMF constant scales with it).
    TorqueConstant,
    /// Wing inertia about the stroke axis, kg m^2.
    WingStrokeInertia,
    /// Pitch stops' coefficient of restitution.
    StopRestitution,
    /// Motion-capture position bias, world axis k, m.
    MocapBias(usize),
    /// Gyroscope bias, body axis k, rad/s.
    GyroBias(usize),
    /// Accelerometer bias, body axis k, m/s^2.
    AccelBias(usize),
}

impl From<Param> for String {
    fn from(p: Param) -> String {
        p.name()
    }
}

const AXES: [&str; 3] = ["x", "y", "z"];

impl Param {
    /// Every parameter, in the order of the docs.
    pub fn all() -> Vec<Param> {
        let mut v = vec![
            Param::InertiaXx,
            Param::InertiaYy,
            Param::InertiaZz,
            Param::Mass,
            Param::ComOffsetX,
            Param::ComOffsetZ,
            Param::AirDensity,
            Param::RotationalCoefficient,
            Param::StrokePlaneTilt,
            Param::HingeStiffness,
            Param::HingeDamping,
            Param::StrokeStiffness,
            Param::ForcePerVolt,
            Param::TorqueConstant,
            Param::WingStrokeInertia,
            Param::StopRestitution,
        ];
        v.extend((0..3).map(Param::MocapBias));
        v.extend((0..3).map(Param::GyroBias));
        v.extend((0..3).map(Param::AccelBias));
        v
    }

    /// The name, with its unit.
    pub fn name(self) -> String {
        match self {
            Param::InertiaXx => "inertia_xx_kg_m2".into(),
            Param::InertiaYy => "inertia_yy_kg_m2".into(),
            Param::InertiaZz => "inertia_zz_kg_m2".into(),
            Param::Mass => "mass_kg".into(),
            Param::ComOffsetX => "com_offset_x_m".into(),
            Param::ComOffsetZ => "com_offset_z_m".into(),
            Param::AirDensity => "air_density_kg_m3".into(),
            Param::RotationalCoefficient => "rotational_coefficient".into(),
            Param::StrokePlaneTilt => "stroke_plane_tilt_rad".into(),
            Param::HingeStiffness => "hinge_stiffness_nm_rad".into(),
            Param::HingeDamping => "hinge_damping_nm_s_rad".into(),
            Param::StrokeStiffness => "stroke_stiffness_nm_rad".into(),
            Param::ForcePerVolt => "force_per_volt_n_v".into(),
            Param::TorqueConstant => "torque_constant_nm_a".into(),
            Param::WingStrokeInertia => "wing_stroke_inertia_kg_m2".into(),
            Param::StopRestitution => "stop_restitution".into(),
            Param::MocapBias(k) => format!("mocap_bias_{}_m", AXES[k]),
            Param::GyroBias(k) => format!("gyro_bias_{}_rad_s", AXES[k]),
            Param::AccelBias(k) => format!("accel_bias_{}_m_s2", AXES[k]),
        }
    }

    /// A parameter by name; the error lists the allowed names.
    pub fn parse(name: &str) -> Result<Param> {
        Param::all()
            .into_iter()
            .find(|p| p.name() == name.trim())
            .ok_or_else(|| {
                Error::Setting(format!(
                    "unknown parameter `{name}`; allowed: {}",
                    Param::all()
                        .iter()
                        .map(|p| p.name())
                        .collect::<Vec<_>>()
                        .join(", ")
                ))
            })
    }

    /// Parses a comma-separated list (no repeats, at least one).
    pub fn parse_list(list: &str) -> Result<Vec<Param>> {
        let mut out: Vec<Param> = Vec::new();
        for n in list.split(',').map(str::trim).filter(|s| !s.is_empty()) {
            let p = Param::parse(n)?;
            if out.contains(&p) {
                return Err(Error::Setting(format!("parameter `{n}` is listed twice")));
            }
            out.push(p);
        }
        if out.is_empty() {
            return Err(Error::Setting(
                "no parameter to fit; name at least one (e.g. inertia_yy_kg_m2,com_offset_x_m)"
                    .into(),
            ));
        }
        Ok(out)
    }

    /// True for a parameter of the vehicle model (written to the fitted model file).
    pub fn in_model(self) -> bool {
        !matches!(
            self,
            Param::MocapBias(_) | Param::GyroBias(_) | Param::AccelBias(_)
        )
    }

    /// True for a parameter that only the IMU residuals see.
    pub fn needs_imu(self) -> bool {
        matches!(self, Param::GyroBias(_) | Param::AccelBias(_))
    }

    /// The value in the model `spec` (0 for a CoM offset or a bias: relative to the model).
    pub fn nominal(self, spec: &VehicleSpec) -> f64 {
        match self {
            Param::InertiaXx => spec.body.inertia_diag_kg_m2[0],
            Param::InertiaYy => spec.body.inertia_diag_kg_m2[1],
            Param::InertiaZz => spec.body.inertia_diag_kg_m2[2],
            Param::Mass => spec.body.mass_kg,
            Param::AirDensity => spec.fluid.density_kg_m3,
            Param::RotationalCoefficient => spec.aero.c_rot,
            Param::StrokePlaneTilt => spec.hinge.stroke_plane_tilt_deg.to_radians(),
            Param::HingeStiffness
            | Param::HingeDamping
            | Param::StrokeStiffness
            | Param::ForcePerVolt
            | Param::TorqueConstant
            | Param::WingStrokeInertia
            | Param::StopRestitution => self.actuation_value(spec).unwrap_or(0.0),
            Param::ComOffsetX
            | Param::ComOffsetZ
            | Param::MocapBias(_)
            | Param::GyroBias(_)
            | Param::AccelBias(_) => 0.0,
        }
    }

    /// Values the fit tries before it starts, for a parameter whose cost has several minima:
    /// it starts from the one of these and the model's value with the lowest cost (see
    /// [`crate::fit`]). `None`: the fit starts from the model's value.
    ///
    /// A stop's restitution changes which strikes a wing's periodic motion makes, and each
    /// change is a kink of the cost with a minimum on either side. Measured on the
    /// hummingbird (12 tethered wingbeats): the wing meets its stops once a wingbeat at
    /// restitution 0.10-0.15 and twice from 0.16; a 0.2 s synthetic hover with true
    /// restitution 0.3 has its lowest cost at 0.27 and a second minimum at 0.12 (the same
    /// under either load sampling), where a fit from 0.1 stopped under the step mean. The scan covers the compliant range
    /// [0.05, 0.95] in steps of 0.05, finer than the gap between the two minima.
    pub fn scan_values(self) -> Option<Vec<f64>> {
        match self {
            Param::StopRestitution => Some((1..=19).map(|k| 0.05 * f64::from(k)).collect()),
            _ => None,
        }
    }

    /// The scale the fit divides the parameter by (see the module docs).
    pub fn scale(self, spec: &VehicleSpec) -> f64 {
        let n = self.nominal(spec).abs();
        if n > 0.0 {
            return n;
        }
        let sensors = spec.sensors.as_ref();
        match self {
            Param::ComOffsetX | Param::ComOffsetZ => 0.01 * spec.body.length_m,
            Param::MocapBias(_) => sensors
                .and_then(|s| s.mocap)
                .map(|m| m.position_noise_m)
                .filter(|x| *x > 0.0)
                .unwrap_or(1e-3 * spec.body.length_m),
            Param::GyroBias(_) => sensors
                .map(|s| s.imu.gyro_bias_deg_s.to_radians())
                .filter(|x| *x > 0.0)
                .unwrap_or(1e-2),
            Param::AccelBias(_) => sensors
                .map(|s| s.imu.accel_bias_mg * 1e-3 * 9.80665)
                .filter(|x| *x > 0.0)
                .unwrap_or(0.1),
            Param::StopRestitution => 0.1,
            // A zero nominal value of a positive quantity: the build rejects it anyway.
            _ => 1.0,
        }
    }

    /// Sets the parameter's `value` in `spec` (measurement parameters leave it alone).
    /// `base` is the model the offsets are relative to.
    pub fn apply(self, spec: &mut VehicleSpec, base: &VehicleSpec, value: f64) {
        match self {
            Param::InertiaXx => spec.body.inertia_diag_kg_m2[0] = value,
            Param::InertiaYy => spec.body.inertia_diag_kg_m2[1] = value,
            Param::InertiaZz => spec.body.inertia_diag_kg_m2[2] = value,
            Param::Mass => spec.body.mass_kg = value,
            Param::AirDensity => spec.fluid.density_kg_m3 = value,
            Param::RotationalCoefficient => spec.aero.c_rot = value,
            Param::StrokePlaneTilt => spec.hinge.stroke_plane_tilt_deg = value.to_degrees(),
            Param::TorqueConstant => {
                if let Some(m) = spec.actuation.as_mut().and_then(|a| a.dc_motor.as_mut()) {
                    m.torque_constant_nm_a = value;
                    m.back_emf_v_s_rad = base
                        .actuation
                        .as_ref()
                        .and_then(|a| a.dc_motor)
                        .map_or(value, |b| back_emf_scaled(&b, value));
                }
            }
            Param::HingeStiffness
            | Param::HingeDamping
            | Param::StrokeStiffness
            | Param::ForcePerVolt
            | Param::WingStrokeInertia
            | Param::StopRestitution => {
                if let Some(x) = self.actuation_field(spec) {
                    *x = value;
                }
            }
            // The hinge moves by minus the CoM offset relative to the CoM.
            Param::ComOffsetX => {
                spec.hinge.left_in_body_m[0] = base.hinge.left_in_body_m[0] - value;
            }
            Param::ComOffsetZ => {
                spec.hinge.left_in_body_m[2] = base.hinge.left_in_body_m[2] - value;
            }
            Param::MocapBias(_) | Param::GyroBias(_) | Param::AccelBias(_) => {}
        }
    }

    /// The model field the parameter changes (`None` for a measurement parameter).
    pub fn model_field(self) -> Option<&'static str> {
        Some(match self {
            Param::InertiaXx | Param::InertiaYy | Param::InertiaZz => "body.inertia_diag_kg_m2",
            Param::Mass => "body.mass_kg",
            Param::AirDensity => "fluid.density_kg_m3",
            Param::RotationalCoefficient => "aero.c_rot",
            Param::StrokePlaneTilt => "hinge.stroke_plane_tilt_deg",
            Param::ComOffsetX | Param::ComOffsetZ => "hinge.left_in_body_m",
            Param::HingeStiffness => "actuation.hinge.stiffness_nm_rad",
            Param::HingeDamping => "actuation.hinge.damping_nm_s_rad",
            Param::StrokeStiffness => "actuation.stroke.flexure_nm_rad",
            Param::ForcePerVolt => "actuation.piezo.force_per_volt_n_v",
            Param::TorqueConstant => "actuation.dc_motor.torque_constant_nm_a",
            Param::WingStrokeInertia => "actuation.wing_inertia.stroke_inertia_kg_m2",
            Param::StopRestitution => "actuation.hinge.stop.restitution",
            _ => return None,
        })
    }

    /// An actuated wing's parameter in `spec`: the field, `None` when the model lacks the
    /// part (no `[actuation]`, another actuator, no stops) or for another parameter.
    fn actuation_field(self, spec: &mut VehicleSpec) -> Option<&mut f64> {
        let a = spec.actuation.as_mut()?;
        Some(match self {
            Param::HingeStiffness => &mut a.hinge.stiffness_nm_rad,
            Param::HingeDamping => &mut a.hinge.damping_nm_s_rad,
            Param::StrokeStiffness => &mut a.stroke.flexure_nm_rad,
            Param::ForcePerVolt => &mut a.piezo.as_mut()?.force_per_volt_n_v,
            Param::TorqueConstant => &mut a.dc_motor.as_mut()?.torque_constant_nm_a,
            Param::WingStrokeInertia => &mut a.wing_inertia.stroke_inertia_kg_m2,
            Param::StopRestitution => &mut a.hinge.stop.as_mut()?.restitution,
            _ => return None,
        })
    }

    /// [`Param::actuation_field`]'s value.
    fn actuation_value(self, spec: &VehicleSpec) -> Option<f64> {
        self.actuation_field(&mut spec.clone()).map(|x| *x)
    }

    /// Whether the model `spec` (from `origin`) has what the parameter changes: an actuated
    /// wing's parameter needs its part of `[actuation]`.
    pub fn check_model(self, spec: &VehicleSpec, origin: &str) -> Result<()> {
        // Restitution 0 is the inelastic constraint, another contact law: its neighbourhood
        // is not a compliant contact's, and the fit would see no effect there.
        if self == Param::StopRestitution && self.actuation_value(spec) == Some(0.0) {
            return Err(Error::Setting(format!(
                "parameter `stop_restitution` needs a compliant stop: `{origin}` has restitution 0, the perfectly inelastic constraint; start the fit from a restitution in [{}, 1] (actuation.hinge.stop.restitution)",
                flapsim::actuated::stop::RESTITUTION_FLOOR
            )));
        }
        if self.actuation_value(spec).is_some() || self.model_field().is_none() {
            return Ok(());
        }
        let Some(field) = self.model_field().filter(|f| f.starts_with("actuation.")) else {
            return Ok(());
        };
        let part = field.rsplit_once('.').map_or(field, |(t, _)| t);
        Err(Error::Setting(format!(
            "parameter `{}` changes `{field}`, but `{origin}` has no [{part}] table{}",
            self.name(),
            if spec.actuation.is_none() {
                " (its wings have prescribed kinematics)"
            } else {
                ""
            }
        )))
    }
}
