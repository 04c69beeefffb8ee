//! The `[actuation]` section of a vehicle model file: wing mass properties, the pitch hinge,
//! the stroke's transmission and springs, one actuator (`[actuation.piezo]` or
//! `[actuation.dc_motor]`) and the drive. Degrees only at this edge; every value is
//! range-checked with an error naming the file, the field, the value and what is allowed.

use serde::{Deserialize, Serialize};
use wingforce::Validator;

use crate::error::Result;
use wingset::actuated::actuator::{Actuator, DcMotor, Piezo};
use wingset::actuated::drive::Drive;
use wingset::actuated::dynamics::{Hinge, Stroke, WingDynamics, WingInertia};
use wingset::actuated::stop::StopContact;

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

/// `[actuation.hinge]`: the passive pitch hinge.
///
/// A flexure hinge (the RoboBee's) is a torsional spring that breaks past a limit:
/// `stiffness_nm_rad`, `damping_nm_s_rad`, `rest_deg` and `break_deg` (its older name
/// `stop_deg` keeps its meaning: past it a run ends with an error). A hinge with mechanical
/// stops (the Purdue hummingbird robot's) adds `[actuation.hinge.stop]` ([`StopSpec`]): the
/// wing strikes the stops as a stiff unilateral contact (see [`super::stop`]); its spring
/// may then be zero, and it has no break limit unless `break_deg` gives one.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HingeSpec {
    /// Torsional stiffness, N m/rad (0 only with contact stops: a free wing between them).
    pub stiffness_nm_rad: f64,
    /// Torsional damping, N m s/rad.
    #[serde(default)]
    pub damping_nm_s_rad: f64,
    /// Rest pitch angle theta_r, deg (90: wing normal to the stroke plane); the stops sit
    /// symmetrically about it.
    #[serde(default = "default_rest_deg")]
    pub rest_deg: f64,
    /// Where the hinge breaks: |theta - theta_r| past this ends a run with an error, deg.
    /// Default: 85 without contact stops, none with them.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub break_deg: Option<f64>,
    /// The older name of `break_deg`, with the same meaning (give at most one of the two).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stop_deg: Option<f64>,
    /// `[actuation.hinge.stop]`: mechanical stops the wing strikes.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stop: Option<StopSpec>,
}

/// `[actuation.hinge.stop]`: hinge stops as a stiff unilateral contact with damping
/// ([`super::stop`]), symmetric about the hinge's rest angle.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StopSpec {
    /// Angle from the rest angle where the wing touches a stop, both ways, deg.
    pub angle_deg: f64,
    /// Coefficient of restitution of a strike, in [0, 1]: 0 is the perfectly inelastic stop,
    /// a constraint without contact law (no contact time or stiffness then); from 0.01 to 1 a
    /// compliant contact (between 0 and 0.01 realised as 0.01).
    pub restitution: f64,
    /// Contact time t_c, s: the contact stiffness is B (pi / t_c)^2 with B the wing's pitch
    /// inertia. A numerical parameter, not physics: short against the wingbeat. Give this or
    /// `stiffness_nm_rad`; default: 1/100 of the drive period.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub contact_time_s: Option<f64>,
    /// Contact stiffness, N m/rad, instead of `contact_time_s`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stiffness_nm_rad: Option<f64>,
}

fn default_rest_deg() -> f64 {
    90.0
}

/// The break limit of a hinge without contact stops when the file gives none, deg.
const DEFAULT_BREAK_DEG: f64 = 85.0;

impl HingeSpec {
    /// Validates the hinge (`field`: its dotted path; `drive_freq_hz` sets the default
    /// contact time).
    fn build(
        &self,
        v: &Validator<'_>,
        field: &str,
        pitch_inertia_kg_m2: f64,
        drive_freq_hz: f64,
    ) -> Result<Hinge> {
        let f = |name: &str| format!("{field}.{name}");
        let rest_rad = v
            .within(&f("rest_deg"), self.rest_deg, 0.0, 180.0)?
            .to_radians();
        let damping = v.non_negative(&f("damping_nm_s_rad"), self.damping_nm_s_rad)?;
        let contact = match &self.stop {
            None => None,
            Some(s) => {
                let g = |name: &str| f(&format!("stop.{name}"));
                let angle = v
                    .within_open_low(&g("angle_deg"), s.angle_deg, 0.0, 179.0)?
                    .to_radians();
                let e = v.within(&g("restitution"), s.restitution, 0.0, 1.0)?;
                // A compliant contact cannot restitute less than the floor (the stop
                // module's doc): a smaller value would be realised as the floor.
                if e > 0.0 && e < wingset::actuated::stop::RESTITUTION_FLOOR {
                    return Err(v
                        .invalid(
                            &g("restitution"),
                            e,
                            &format!(
                                "0 (the perfectly inelastic stop, a constraint) or a number in [{}, 1] (a compliant contact: one without memory cannot restitute less)",
                                wingset::actuated::stop::RESTITUTION_FLOOR
                            ),
                        )
                        .into());
                }
                if e == 0.0 {
                    // The perfectly inelastic stop is a constraint: it has no contact law.
                    for (name, given) in [
                        ("contact_time_s", s.contact_time_s),
                        ("stiffness_nm_rad", s.stiffness_nm_rad),
                    ] {
                        if let Some(x) = given {
                            return Err(v
                                .invalid(
                                    &g(name),
                                    &format!("{x} with restitution = 0"),
                                    "no contact time or stiffness with restitution 0 (a perfectly inelastic stop is a constraint, with no contact law), or a restitution from 0.01 to 1 for a compliant contact",
                                )
                                .into());
                        }
                    }
                    Some(StopContact::inelastic(angle))
                } else {
                    let k = match (s.contact_time_s, s.stiffness_nm_rad) {
                        (Some(_), Some(_)) => {
                            return Err(v
                                .invalid(
                                    &g("stiffness_nm_rad"),
                                    "both contact_time_s and stiffness_nm_rad",
                                    "one of the two (the stiffness follows from the contact time)",
                                )
                                .into());
                        }
                        (None, Some(k)) => v.positive(&g("stiffness_nm_rad"), k)?,
                        (t, None) => {
                            let t = match t {
                                Some(t) => v.within_open_low(&g("contact_time_s"), t, 0.0, 1.0)?,
                                None => 0.01 / drive_freq_hz,
                            };
                            StopContact::stiffness_for_contact_time(pitch_inertia_kg_m2, t)
                        }
                    };
                    Some(StopContact::new(angle, e, k))
                }
            }
        };
        let stiffness = if contact.is_some() {
            v.non_negative(&f("stiffness_nm_rad"), self.stiffness_nm_rad)?
        } else {
            if self.stiffness_nm_rad == 0.0 {
                return Err(v
                    .invalid(
                        &f("stiffness_nm_rad"),
                        self.stiffness_nm_rad,
                        "a finite number > 0, or 0 with contact stops ([actuation.hinge.stop]) to hold the wing",
                    )
                    .into());
            }
            v.positive(&f("stiffness_nm_rad"), self.stiffness_nm_rad)?
        };
        let (break_name, break_deg) = match (self.break_deg, self.stop_deg) {
            (Some(_), Some(_)) => {
                return Err(v
                    .invalid(
                        &f("stop_deg"),
                        "both break_deg and stop_deg",
                        "one of the two (stop_deg is the older name of break_deg)",
                    )
                    .into());
            }
            (Some(b), None) => ("break_deg", Some(b)),
            (None, Some(b)) => ("stop_deg", Some(b)),
            (None, None) => ("break_deg", contact.is_none().then_some(DEFAULT_BREAK_DEG)),
        };
        let break_rad = match break_deg {
            None => f64::INFINITY,
            Some(b_deg) => {
                let b = v
                    .within_open_low(&f(break_name), b_deg, 0.0, 180.0)?
                    .to_radians();
                if let Some(c) = &contact
                    && b <= c.angle_rad
                {
                    return Err(v
                        .invalid(
                            &f(break_name),
                            b_deg,
                            &format!(
                                "an angle past the contact stops at {} deg (the wing strikes the stops before the hinge can break)",
                                self.stop.as_ref().map_or(0.0, |s| s.angle_deg)
                            ),
                        )
                        .into());
                }
                b
            }
        };
        Ok(Hinge {
            stiffness_nm_rad: stiffness,
            damping_nm_s_rad: damping,
            rest_rad,
            break_rad,
            contact,
        })
    }
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
    pub fn controlled_drives(&self, c: &crate::controls::Controls) -> Result<[Drive; 2]> {
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
                return Err(crate::error::Error::Analysis(format!(
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
        let hinge = self.hinge.build(
            v,
            &f("hinge"),
            inertia.pitch_inertia_kg_m2,
            self.drive.freq_hz,
        )?;
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
