//! Actuator models, each reduced to what it does to the stroke angle: a reflected inertia,
//! stiffness, damping and a torque per volt about the stroke axis, plus its own state
//! (piezo tip displacement, motor current) recovered from the stroke.
//!
//! Piezoelectric bimorph through a linear transmission (RoboBee; Jafferis et al. 2016, the
//! lumped model of Steinmeyer et al. 2019): the tip displacement x drives the stroke as
//! phi = T x. With effective mass m_a, stiffness k_a, damping b_a and force per volt d_v
//! (blocked force over drive voltage), virtual work F dx = (F / T) dphi gives about the
//! stroke axis J_a = m_a / T^2, k = k_a / T^2, c = b_a / T^2 and torque per volt d_v / T.
//!
//! DC motor with a gearbox and a torsional stroke spring (Purdue's hummingbird robot; the
//! open-source `flappy` simulator's configuration): armature resistance R, torque constant
//! K_t, back-EMF constant K_e, rotor inertia J_r, gear ratio G, gear efficiency eta, viscous
//! friction b_m on the motor shaft. The shaft turns at G phi_dot; with the inductance
//! neglected (its electrical time constant L/R is far below the wingbeat period) the current
//! is i = (V - K_e G phi_dot) / R and the stroke torque eta G K_t i, so about the stroke axis
//! J = G^2 J_r, c = G^2 (b_m + eta K_t K_e / R) and torque per volt eta G K_t / R.

use serde::{Deserialize, Serialize};

/// A piezoelectric bimorph through a linear transmission.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Piezo {
    /// Effective mass m_a, kg.
    pub mass_kg: f64,
    /// Stiffness k_a, N/m.
    pub stiffness_n_m: f64,
    /// Damping b_a, N s/m.
    #[serde(default)]
    pub damping_n_s_m: f64,
    /// Force per volt d_v (blocked force over voltage), N/V.
    pub force_per_volt_n_v: f64,
    /// Transmission ratio T from tip displacement to stroke angle, rad/m.
    pub transmission_rad_m: f64,
    /// Largest drive voltage magnitude, V.
    pub voltage_limit_v: f64,
}

/// A DC motor driving the stroke through a gearbox, with a torsional stroke spring.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DcMotor {
    /// Armature resistance R, ohm.
    pub resistance_ohm: f64,
    /// Torque constant K_t, N m/A.
    pub torque_constant_nm_a: f64,
    /// Back-EMF constant K_e, V s/rad.
    pub back_emf_v_s_rad: f64,
    /// Rotor inertia J_r, kg m^2.
    pub rotor_inertia_kg_m2: f64,
    /// Viscous friction on the motor shaft b_m, N m s/rad.
    #[serde(default)]
    pub shaft_damping_nm_s_rad: f64,
    /// Gear ratio G (motor turns per stroke turn).
    pub gear_ratio: f64,
    /// Gear efficiency eta, in (0, 1].
    pub gear_efficiency: f64,
    /// Largest drive voltage magnitude, V.
    pub voltage_limit_v: f64,
}

impl DcMotor {
    /// Stall torque at the motor shaft for voltage `v`: K_t V / R, N m.
    pub fn stall_torque_nm(&self, v: f64) -> f64 {
        self.torque_constant_nm_a * v / self.resistance_ohm
    }

    /// No-load shaft speed for voltage `v` (no friction): V / K_e, rad/s.
    pub fn no_load_speed_rad_s(&self, v: f64) -> f64 {
        v / self.back_emf_v_s_rad
    }

    /// Shaft torque at shaft speed `omega` and voltage `v`: K_t (V - K_e omega) / R, N m.
    pub fn shaft_torque_nm(&self, v: f64, omega_rad_s: f64) -> f64 {
        self.torque_constant_nm_a * self.current_a(v, omega_rad_s)
    }

    /// Armature current at shaft speed `omega` and voltage `v`, A.
    pub fn current_a(&self, v: f64, omega_rad_s: f64) -> f64 {
        (v - self.back_emf_v_s_rad * omega_rad_s) / self.resistance_ohm
    }
}

/// Which actuator drives the stroke.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Actuator {
    /// Piezoelectric bimorph (RoboBee).
    Piezo(Piezo),
    /// DC motor and gearbox (hummingbird robot).
    DcMotor(DcMotor),
}

/// An actuator as seen from the stroke axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Reflected {
    /// Inertia added to the stroke axis, kg m^2.
    pub inertia_kg_m2: f64,
    /// Stiffness added to the stroke axis, N m/rad.
    pub stiffness_nm_rad: f64,
    /// Damping added to the stroke axis, N m s/rad.
    pub damping_nm_s_rad: f64,
    /// Stroke torque per drive volt, N m/V.
    pub torque_per_volt_nm_v: f64,
}

/// The actuator's own state, recovered from the stroke (for logs and reports).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct ActuatorState {
    /// Drive voltage, V.
    pub voltage_v: f64,
    /// Piezo tip displacement phi / T, m (zero for a motor).
    pub displacement_m: f64,
    /// Motor current, A (zero for a piezo).
    pub current_a: f64,
}

impl Actuator {
    /// The actuator reflected to the stroke axis (see the module doc).
    pub fn reflected(&self) -> Reflected {
        match self {
            Actuator::Piezo(p) => {
                let t = p.transmission_rad_m;
                Reflected {
                    inertia_kg_m2: p.mass_kg / (t * t),
                    stiffness_nm_rad: p.stiffness_n_m / (t * t),
                    damping_nm_s_rad: p.damping_n_s_m / (t * t),
                    torque_per_volt_nm_v: p.force_per_volt_n_v / t,
                }
            }
            Actuator::DcMotor(m) => {
                let g = m.gear_ratio;
                Reflected {
                    inertia_kg_m2: g * g * m.rotor_inertia_kg_m2,
                    stiffness_nm_rad: 0.0,
                    damping_nm_s_rad: g
                        * g
                        * (m.shaft_damping_nm_s_rad
                            + m.gear_efficiency * m.torque_constant_nm_a * m.back_emf_v_s_rad
                                / m.resistance_ohm),
                    torque_per_volt_nm_v: m.gear_efficiency * g * m.torque_constant_nm_a
                        / m.resistance_ohm,
                }
            }
        }
    }

    /// Largest drive voltage magnitude, V.
    pub fn voltage_limit_v(&self) -> f64 {
        match self {
            Actuator::Piezo(p) => p.voltage_limit_v,
            Actuator::DcMotor(m) => m.voltage_limit_v,
        }
    }

    /// The actuator's state at stroke angle `phi` (from rest), stroke rate `phi_dot` and
    /// voltage `v`.
    pub fn state(&self, phi_rad: f64, phi_dot_rad_s: f64, v: f64) -> ActuatorState {
        match self {
            Actuator::Piezo(p) => ActuatorState {
                voltage_v: v,
                displacement_m: phi_rad / p.transmission_rad_m,
                current_a: 0.0,
            },
            Actuator::DcMotor(m) => ActuatorState {
                voltage_v: v,
                displacement_m: 0.0,
                current_a: m.current_a(v, m.gear_ratio * phi_dot_rad_s),
            },
        }
    }

    /// "piezo" or "dc_motor".
    pub fn kind(&self) -> &'static str {
        match self {
            Actuator::Piezo(_) => "piezo",
            Actuator::DcMotor(_) => "dc_motor",
        }
    }
}
