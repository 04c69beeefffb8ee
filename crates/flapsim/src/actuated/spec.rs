//! The `[actuation]` section of a vehicle model file: wing mass properties, the pitch hinge,
//! the stroke's transmission and springs, one actuator (`[actuation.piezo]` or
//! `[actuation.dc_motor]`) and the drive. Degrees only at this edge; every value is
//! range-checked with an error naming the file, the field, the value and what is allowed.

use serde::{Deserialize, Serialize};
use wingforce::Validator;

use super::actuator::{Actuator, DcMotor, Piezo};
use super::drive::Drive;
use super::dynamics::{Hinge, Stroke, WingDynamics, WingInertia};
use crate::error::Result;

/// `[actuation.wing_inertia]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WingInertiaSpec {
    /// Wing mass, kg.
    pub mass_kg: f64,
    /// Inertia about the stroke axis with the wing normal to the stroke plane, kg m^2.
    pub stroke_inertia_kg_m2: f64,
    /// Inertia about the pitch axis, kg m^2.
    pub pitch_inertia_kg_m2: f64,
    /// Centre of mass from the stroke axis along the span, m.
    pub com_span_m: f64,
    /// Centre of mass from the pitch axis along the chord, positive towards the leading edge, m.
    pub com_chord_m: f64,
}

/// `[actuation.hinge]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HingeSpec {
    /// Torsional stiffness, N m/rad.
    pub stiffness_nm_rad: f64,
    /// Torsional damping, N m s/rad.
    #[serde(default)]
    pub damping_nm_s_rad: f64,
    /// Rest pitch angle theta_r, deg (90: wing normal to the stroke plane).
    #[serde(default = "default_rest_deg")]
    pub rest_deg: f64,
    /// Hinge stops: |theta - theta_r| past this ends a run with an error, deg.
    #[serde(default = "default_stop_deg")]
    pub stop_deg: f64,
}

fn default_rest_deg() -> f64 {
    90.0
}
fn default_stop_deg() -> f64 {
    85.0
}

/// `[actuation.stroke]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StrokeSpec {
    /// Transmission flexure or stroke spring stiffness about the stroke axis, N m/rad.
    pub flexure_nm_rad: f64,
    /// Extra viscous damping about the stroke axis, N m s/rad.
    #[serde(default)]
    pub damping_nm_s_rad: f64,
    /// Stroke angle where the springs are relaxed, deg.
    #[serde(default)]
    pub rest_deg: f64,
}

/// `[actuation.drive]`: the same waveform on both wings, with left-minus-right differences.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DriveSpec {
    /// Drive frequency, Hz.
    pub freq_hz: f64,
    /// Amplitude of the fundamental, V.
    pub amplitude_v: f64,
    /// DC bias, V.
    #[serde(default)]
    pub bias_v: f64,
    /// Second harmonic as a fraction of the fundamental.
    #[serde(default)]
    pub second_harmonic: f64,
    /// Phase of the second harmonic, deg.
    #[serde(default)]
    pub second_harmonic_phase_deg: f64,
    /// Left-minus-right amplitude, V (half added to the left wing, half taken from the right).
    #[serde(default)]
    pub diff_amplitude_v: f64,
    /// Left-minus-right bias, V.
    #[serde(default)]
    pub diff_bias_v: f64,
}

/// `[actuation]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ActuationSpec {
    /// Wing-dynamics sub-steps per body step.
    #[serde(default = "default_substeps")]
    pub substeps: usize,
    /// Drive periods run from rest, at a frozen body state, before the wings' periodic motion
    /// is averaged (trim, the averaged model, the start of a hover); the motion must then
    /// repeat to within [`super::periodic::PERIODIC_TOLERANCE_RAD`] or the analysis stops.
    #[serde(default = "default_settle_cycles")]
    pub settle_cycles: usize,
    /// Wing mass properties.
    pub wing_inertia: WingInertiaSpec,
    /// The pitch hinge.
    pub hinge: HingeSpec,
    /// Transmission and springs of the stroke.
    pub stroke: StrokeSpec,
    /// A piezoelectric bimorph (give this or `dc_motor`).
    #[serde(default)]
    pub piezo: Option<Piezo>,
    /// A DC motor with gearbox (give this or `piezo`).
    #[serde(default)]
    pub dc_motor: Option<DcMotor>,
    /// The drive.
    pub drive: DriveSpec,
}

fn default_settle_cycles() -> usize {
    40
}

fn default_substeps() -> usize {
    1
}

/// A validated actuation: the dynamic model (the same for both wings) and each wing's drive.
#[derive(Debug, Clone, PartialEq)]
pub struct Actuation {
    /// The wing's dynamic model.
    pub dynamics: WingDynamics,
    /// Left and right drives now (the model's drives with the controls applied).
    pub drives: [Drive; 2],
    /// Left and right drives of the model file (controls are offsets on these).
    pub base_drives: [Drive; 2],
    /// See [`ActuationSpec::settle_cycles`].
    pub settle_cycles: usize,
}

impl Actuation {
    /// The drives under drive controls `c` (offsets on the model's drives; left-minus-right
    /// differences split half and half), checked against the actuator's voltage limit.
    pub fn controlled_drives(&self, c: &crate::model::Controls) -> Result<[Drive; 2]> {
        let lim = self.dynamics.stroke.voltage_limit_v();
        let mut out = self.base_drives;
        for (i, d) in out.iter_mut().enumerate() {
            let half = if i == 0 { 0.5 } else { -0.5 };
            d.freq_hz += c.freq_hz;
            d.bias_v += c.bias_v + half * c.diff_bias_v;
            d.amplitude_v += c.amplitude_v + half * c.diff_amplitude_v;
            d.second_harmonic += half * c.diff_second_harmonic;
            let side = if i == 0 { "left" } else { "right" };
            if !(d.peak_bound_v() <= lim) || !(d.freq_hz > 0.0) {
                return Err(crate::Error::Analysis(format!(
                    "the drive controls (bias {:+.2} V, amplitude {:+.2} V, differences {:+.2} V amplitude, {:+.2} V bias, {:+.3} second harmonic, frequency {:+.2} Hz) give the {side} wing a peak |V| up to {:.1} V at {:.1} Hz; allowed: |V| <= {lim} V (the actuator's limit) and a frequency > 0",
                    c.bias_v,
                    c.amplitude_v,
                    c.diff_amplitude_v,
                    c.diff_bias_v,
                    c.diff_second_harmonic,
                    c.freq_hz,
                    d.peak_bound_v(),
                    d.freq_hz
                )));
            }
        }
        Ok(out)
    }
}

impl ActuationSpec {
    /// Validates the section (`field` is its dotted path, `actuation`).
    pub fn build(&self, v: &Validator<'_>, field: &str) -> Result<Actuation> {
        let f = |name: &str| format!("{field}.{name}");
        if !(1..=64).contains(&self.substeps) {
            return Err(v
                .invalid(&f("substeps"), self.substeps, "an integer in [1, 64]")
                .into());
        }
        let wi = &self.wing_inertia;
        let inertia = WingInertia {
            mass_kg: v.non_negative(&f("wing_inertia.mass_kg"), wi.mass_kg)?,
            stroke_inertia_kg_m2: v.positive(
                &f("wing_inertia.stroke_inertia_kg_m2"),
                wi.stroke_inertia_kg_m2,
            )?,
            pitch_inertia_kg_m2: v.positive(
                &f("wing_inertia.pitch_inertia_kg_m2"),
                wi.pitch_inertia_kg_m2,
            )?,
            com_span_m: v.within(&f("wing_inertia.com_span_m"), wi.com_span_m, 0.0, 1.0)?,
            com_chord_m: v.within(&f("wing_inertia.com_chord_m"), wi.com_chord_m, -1.0, 1.0)?,
        };
        // The mass matrix must stay positive definite at every pitch: B J > C^2.
        let c = inertia.product_kg_m2();
        if c * c >= inertia.pitch_inertia_kg_m2 * inertia.stroke_inertia_kg_m2 {
            return Err(v
                .invalid(
                    &f("wing_inertia"),
                    format!("m r_c x_c = {c:e} kg m^2"),
                    "a physical wing: (m r_c x_c)^2 < stroke_inertia * pitch_inertia",
                )
                .into());
        }
        let h = &self.hinge;
        let hinge = Hinge {
            stiffness_nm_rad: v.positive(&f("hinge.stiffness_nm_rad"), h.stiffness_nm_rad)?,
            damping_nm_s_rad: v.non_negative(&f("hinge.damping_nm_s_rad"), h.damping_nm_s_rad)?,
            rest_rad: v
                .within(&f("hinge.rest_deg"), h.rest_deg, 0.0, 180.0)?
                .to_radians(),
            stop_rad: v
                .within_open_low(&f("hinge.stop_deg"), h.stop_deg, 0.0, 180.0)?
                .to_radians(),
        };
        let actuator = match (&self.piezo, &self.dc_motor) {
            (Some(p), None) => {
                let g = |n: &str| f(&format!("piezo.{n}"));
                v.positive(&g("mass_kg"), p.mass_kg)?;
                v.non_negative(&g("stiffness_n_m"), p.stiffness_n_m)?;
                v.non_negative(&g("damping_n_s_m"), p.damping_n_s_m)?;
                v.positive(&g("force_per_volt_n_v"), p.force_per_volt_n_v)?;
                v.positive(&g("transmission_rad_m"), p.transmission_rad_m)?;
                v.positive(&g("voltage_limit_v"), p.voltage_limit_v)?;
                Actuator::Piezo(*p)
            }
            (None, Some(m)) => {
                let g = |n: &str| f(&format!("dc_motor.{n}"));
                v.positive(&g("resistance_ohm"), m.resistance_ohm)?;
                v.positive(&g("torque_constant_nm_a"), m.torque_constant_nm_a)?;
                v.positive(&g("back_emf_v_s_rad"), m.back_emf_v_s_rad)?;
                v.non_negative(&g("rotor_inertia_kg_m2"), m.rotor_inertia_kg_m2)?;
                v.non_negative(&g("shaft_damping_nm_s_rad"), m.shaft_damping_nm_s_rad)?;
                v.positive(&g("gear_ratio"), m.gear_ratio)?;
                v.within_open_low(&g("gear_efficiency"), m.gear_efficiency, 0.0, 1.0)?;
                v.positive(&g("voltage_limit_v"), m.voltage_limit_v)?;
                Actuator::DcMotor(*m)
            }
            (p, m) => {
                return Err(v
                    .invalid(
                        field,
                        format!(
                            "{} actuator sections",
                            usize::from(p.is_some()) + usize::from(m.is_some())
                        ),
                        "exactly one of [actuation.piezo] and [actuation.dc_motor]",
                    )
                    .into());
            }
        };
        let s = &self.stroke;
        let stroke = Stroke::Driven {
            actuator,
            flexure_nm_rad: v.non_negative(&f("stroke.flexure_nm_rad"), s.flexure_nm_rad)?,
            damping_nm_s_rad: v.non_negative(&f("stroke.damping_nm_s_rad"), s.damping_nm_s_rad)?,
            rest_rad: v
                .within(&f("stroke.rest_deg"), s.rest_deg, -90.0, 90.0)?
                .to_radians(),
        };
        let dynamics = WingDynamics {
            inertia,
            hinge,
            stroke,
            substeps: self.substeps,
            aero: true,
        };
        if !(dynamics.stroke_stiffness_nm_rad() > 0.0) {
            return Err(v
                .invalid(
                    &f("stroke.flexure_nm_rad"),
                    s.flexure_nm_rad,
                    "a stroke system with some stiffness (actuator or flexure > 0), so that it has a rest position",
                )
                .into());
        }
        let d = &self.drive;
        let freq = v.within_open_low(&f("drive.freq_hz"), d.freq_hz, 0.0, 1e4)?;
        let amp = v.finite(&f("drive.amplitude_v"), d.amplitude_v)?;
        let bias = v.finite(&f("drive.bias_v"), d.bias_v)?;
        let h2 = v.within(&f("drive.second_harmonic"), d.second_harmonic, -1.0, 1.0)?;
        let psi2 = v
            .within(
                &f("drive.second_harmonic_phase_deg"),
                d.second_harmonic_phase_deg,
                -360.0,
                360.0,
            )?
            .to_radians();
        let da = v.finite(&f("drive.diff_amplitude_v"), d.diff_amplitude_v)?;
        let db = v.finite(&f("drive.diff_bias_v"), d.diff_bias_v)?;
        let drive = |half: f64| Drive {
            freq_hz: freq,
            bias_v: bias + half * db,
            amplitude_v: amp + half * da,
            second_harmonic: h2,
            second_harmonic_phase_rad: psi2,
        };
        let drives = [drive(0.5), drive(-0.5)];
        let lim = actuator.voltage_limit_v();
        for (side, dr) in ["left", "right"].iter().zip(&drives) {
            if dr.peak_bound_v() > lim {
                return Err(v
                    .invalid(
                        &f("drive"),
                        format!(
                            "{side} wing peak |V| up to {:.1} V (bias {} V, amplitude {} V, second harmonic {})",
                            dr.peak_bound_v(),
                            dr.bias_v,
                            dr.amplitude_v,
                            dr.second_harmonic
                        ),
                        &format!("|bias| + |amplitude| (1 + |second_harmonic|) <= the {} limit of {lim} V", actuator.kind()),
                    )
                    .into());
            }
        }
        if !(1..=10_000).contains(&self.settle_cycles) {
            return Err(v
                .invalid(
                    &f("settle_cycles"),
                    self.settle_cycles,
                    "an integer in [1, 10000]",
                )
                .into());
        }
        Ok(Actuation {
            dynamics,
            drives,
            base_drives: drives,
            settle_cycles: self.settle_cycles,
        })
    }
}
