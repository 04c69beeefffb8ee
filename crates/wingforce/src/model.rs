//! Model files: the TOML text a user writes for one wing (planform, kinematics, fluid and
//! aerodynamic options) and its validation into a ready [`Wing`].
//!
//! Degrees appear only in field names ending in `_deg`; everything built from a spec is SI
//! and radians. Unknown fields are errors, and every error names the file, the field, the
//! value and what is allowed.

use serde::{Deserialize, Serialize};

use crate::added_mass::AddedMassForm;
use crate::coefficients::{TranslationalModel, WakeCaptureModel};
use crate::error::{Error, Result, Validator};
use crate::inflow::InflowModel;
use crate::kinematics::{Kinematics, KinematicsSpec};
use crate::mount::{Fluid, Mount};
use crate::planform::{Geometry, GeometryOverrides, PlanformSpec};
use crate::wing::{AeroOptions, Wing};

/// A planform with its measured overrides.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WingSpec {
    /// The planform.
    pub planform: PlanformSpec,
    /// Measured values that replace derived ones.
    #[serde(default)]
    pub overrides: GeometryOverrides,
}

/// The fluid as written: density, and either the kinematic viscosity or the paper's Re.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FluidSpec {
    /// Density, kg/m^3.
    pub density_kg_m3: f64,
    /// Kinematic viscosity, m^2/s.
    pub kinematic_viscosity_m2_s: Option<f64>,
    /// Reynolds number Re = V_ref c_bar / nu (sets nu from the wing's kinematics).
    pub reynolds: Option<f64>,
}

impl Default for FluidSpec {
    fn default() -> Self {
        Self {
            density_kg_m3: Fluid::AIR_20C.density_kg_m3,
            kinematic_viscosity_m2_s: Some(Fluid::AIR_20C.kinematic_viscosity_m2_s),
            reynolds: None,
        }
    }
}

/// Aerodynamic options as written.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct AeroSpec {
    /// `lee2016` (default) or `dickinson1999`.
    pub translational: TranslationalModel,
    /// Apply Lee et al.'s f_AR and f_Ro corrections.
    pub ar_ro_corrections: bool,
    /// Include the rotational term.
    pub rotational: bool,
    /// The added-mass term's form: `"impulse"`, `"paper"` (eq 7-8) or `"off"`; `true` reads
    /// as `"paper"`, `false` as `"off"`.
    pub added_mass: AddedMassForm,
    /// Include the wake-capture term.
    pub wake_capture: bool,
    /// A refitted wake-capture model (e.g. written by `flapwing fit-wake`); the paper's if absent.
    pub wake_capture_model: Option<WakeCaptureModel>,
    /// Van Veen et al.'s C_rot.
    pub c_rot: f64,
    /// Number of blade-element strips per wing.
    pub strips: usize,
    /// Translational centre of pressure behind the leading edge, fraction of the chord.
    pub cp_chord_frac: f64,
    /// The induced inflow of a hovering vehicle through its stroke plane (momentum theory
    /// with the weight as thrust; [`crate::inflow`]). Only a vehicle, which has a weight, can
    /// switch it on; its builder sets [`AeroOptions::induced_inflow`]. The older spelling
    /// of `inflow = "frozen"`.
    pub induced_inflow: bool,
    /// The induced flow a vehicle's wings meet: `"off"` (still air), `"frozen"` (the hover
    /// downwash held at the flight condition) or `"dynamic"` (each pair's wake follows its
    /// loads: [`crate::inflow::dynamic`]). Absent: `induced_inflow` decides (frozen or off).
    pub inflow: Option<InflowModel>,
}

impl Default for AeroSpec {
    fn default() -> Self {
        let o = AeroOptions::default();
        Self {
            translational: o.translational,
            ar_ro_corrections: o.ar_ro_corrections,
            rotational: o.rotational,
            added_mass: o.added_mass,
            wake_capture: o.wake_capture.is_some(),
            wake_capture_model: None,
            c_rot: o.c_rot,
            strips: 20,
            cp_chord_frac: 0.25,
            induced_inflow: false,
            inflow: None,
        }
    }
}

impl AeroSpec {
    /// The induced-flow model the file asks for (`inflow`, or the older `induced_inflow`);
    /// an error when the two disagree.
    pub fn inflow_model(&self, v: &Validator<'_>) -> Result<InflowModel> {
        match (self.inflow, self.induced_inflow) {
            (Some(m), false) => Ok(m),
            (Some(InflowModel::Frozen), true) | (None, true) => Ok(InflowModel::Frozen),
            (None, false) => Ok(InflowModel::Off),
            (Some(m), true) => Err(v.invalid(
                "aero.inflow",
                m,
                "the model `induced_inflow = true` (its older spelling) also names, \"frozen\"; write only `inflow`",
            )),
        }
    }

    /// Validated options.
    pub fn build(&self, v: &Validator<'_>, field: &str) -> Result<AeroOptions> {
        v.positive(&format!("{field}.c_rot"), self.c_rot)?;
        if !(1..=1000).contains(&self.strips) {
            return Err(v.invalid(
                &format!("{field}.strips"),
                self.strips,
                "an integer in [1, 1000]",
            ));
        }
        v.within(
            &format!("{field}.cp_chord_frac"),
            self.cp_chord_frac,
            0.0,
            1.0,
        )?;
        if let Some(m) = &self.wake_capture_model {
            let f = |name: &str| format!("{field}.wake_capture_model.{name}");
            let coeffs = [
                ("dcl.c0", m.dcl.c0),
                ("dcl.c1", m.dcl.c1),
                ("dcl.c2", m.dcl.c2),
                ("dcl.c3", m.dcl.c3),
                ("dcl.c4", m.dcl.c4),
                ("dcd.c0", m.dcd.c0),
                ("dcd.c1", m.dcd.c1),
                ("dcd.c2", m.dcd.c2),
                ("dcd.c3", m.dcd.c3),
                ("dcd.c4", m.dcd.c4),
                ("mu_star.m0", m.mu_star.m0),
                ("mu_star.m1", m.mu_star.m1),
                ("mu_star.m2", m.mu_star.m2),
            ];
            for (name, x) in coeffs {
                v.finite(&f(name), x)?;
            }
            // dCL and dCD must be finite over the fitted range (an exponential rate such as
            // c2 = 1 overflows at ordinary Re).
            for re in [m.re_range.min, m.re_range.max] {
                for dd in [m.dtau_d_range.min, m.dtau_d_range.max] {
                    for (name, form) in [("dcl", &m.dcl), ("dcd", &m.dcd)] {
                        let x = form.eval(re, dd);
                        if !x.is_finite() {
                            return Err(v.invalid(
                                &f(name),
                                format!("{name} = {x} at Re = {re}, dtau_D = {dd}"),
                                "coefficients giving finite values over the model's fitted range",
                            ));
                        }
                    }
                }
            }
            // mu* sets the Gaussian's centre and width: it must be positive over the whole
            // fitted range (it is linear in ln Re and dtau_A, so the corners suffice).
            for re in [m.re_range.min, m.re_range.max] {
                for da in [m.dtau_a_range.min, m.dtau_a_range.max] {
                    let mu = m.mu_star.eval(re, da);
                    if !(mu > 0.0 && re > 0.0) {
                        return Err(v.invalid(
                            &f("mu_star"),
                            format!("mu* = {mu} at Re = {re}, dtau_A = {da}"),
                            "a model with mu* > 0 (and Re > 0) everywhere in its fitted range",
                        ));
                    }
                }
            }
            for (name, r) in [
                ("re_range", m.re_range),
                ("dtau_a_range", m.dtau_a_range),
                ("dtau_d_range", m.dtau_d_range),
            ] {
                if !(r.min.is_finite() && r.max.is_finite() && r.min < r.max) {
                    return Err(v.invalid(
                        &format!("{field}.wake_capture_model.{name}"),
                        format!("[{}, {}]", r.min, r.max),
                        "finite bounds with min < max",
                    ));
                }
            }
        }
        Ok(AeroOptions {
            translational: self.translational,
            ar_ro_corrections: self.ar_ro_corrections,
            rotational: self.rotational,
            added_mass: self.added_mass,
            wake_capture: if self.wake_capture {
                Some(
                    self.wake_capture_model
                        .clone()
                        .unwrap_or_else(WakeCaptureModel::paper),
                )
            } else {
                None
            },
            c_rot: self.c_rot,
            induced_inflow: None,
        })
    }
}

/// A wing on a fixed mount (a robotic wing in a tank): the file format of `models/robofly.toml`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WingModelSpec {
    /// A name for reports.
    #[serde(default)]
    pub name: String,
    /// The fluid.
    #[serde(default)]
    pub fluid: FluidSpec,
    /// The wing.
    pub wing: WingSpec,
    /// The kinematics.
    pub kinematics: KinematicsSpec,
    /// Aerodynamic options.
    #[serde(default)]
    pub aero: AeroSpec,
}

/// Parses TOML text, naming `origin` in errors.
pub fn parse_toml<T: serde::de::DeserializeOwned>(text: &str, origin: &str) -> Result<T> {
    toml::from_str(text).map_err(|e| Error::Parse {
        origin: origin.to_owned(),
        message: e.to_string().trim_end().to_owned(),
    })
}

impl WingModelSpec {
    /// Parses a wing model from TOML text (`origin` names the file in errors).
    pub fn from_toml(text: &str, origin: &str) -> Result<Self> {
        parse_toml(text, origin)
    }

    /// Validates and builds the wing on a fixed left mount at the origin.
    pub fn build(&self, origin: &str) -> Result<Wing> {
        let v = Validator::new(origin);
        let aero = &self.aero;
        let options = aero.build(&v, "aero")?;
        if aero.inflow_model(&v)? != InflowModel::Off {
            return Err(v.invalid(
                "aero.inflow",
                aero.inflow_model(&v)?,
                "\"off\" for a wing on a fixed mount: still fluid, as the seed paper's robofly (the induced flow is the downwash that carries a vehicle's weight; a vehicle model switches it on)",
            ));
        }
        let geometry = build_geometry(&self.wing, &v, "wing", aero)?;
        let kinematics =
            Kinematics::from_spec(&self.kinematics, &v, "kinematics", geometry.r_gyration_m)?;
        let fluid = build_fluid(&self.fluid, &v, "fluid", &geometry, &kinematics)?;
        let wing = Wing::builder(geometry, kinematics)
            .fluid(fluid)
            .options(options)
            .mount(Mount::fixed(crate::mount::Side::Left))
            .build();
        check_wing(&v, &wing)?;
        Ok(wing)
    }
}

/// Rejects a wing whose derived quantities or forces are not finite. The validator checks
/// each field's sign and finiteness; extreme but finite values (a 1e300 m span, a 1e-300 deg
/// amplitude) can still overflow what is derived from them, and must not reach a run as NaN.
pub fn check_wing(v: &Validator<'_>, wing: &Wing) -> Result<()> {
    let g = wing.geometry();
    let geometry = [
        ("area_m2", g.area_m2),
        ("span_m", g.span_m),
        ("mean_chord_m", g.mean_chord_m),
        ("r_gyration_m", g.r_gyration_m),
        ("aspect_ratio", g.aspect_ratio),
        ("rossby", g.rossby),
        ("sqrt_sxx_syy_m4", g.sqrt_sxx_syy_m4),
    ];
    for (name, x) in geometry {
        if !(x.is_finite() && x > 0.0) {
            return Err(v.invalid(
                "wing.planform",
                format!("a planform whose derived {name} is {x}"),
                "lengths and areas of a physical wing (the derived quantities must be finite and > 0)",
            ));
        }
    }
    let k = wing.kinematics();
    let derived = [
        ("frequency (Hz)", k.freq_hz),
        ("V_ref (m/s)", wing.v_ref_m_s()),
        ("Re", wing.reynolds()),
        (
            "reference force 0.5 rho V_ref^2 S (N)",
            wing.reference_force_n(),
        ),
    ];
    for (name, x) in derived {
        if !(x.is_finite() && x > 0.0) {
            return Err(v.invalid(
                "kinematics",
                format!("kinematics giving {name} = {x}"),
                "kinematics with a finite, positive frequency, reference speed and Reynolds number",
            ));
        }
    }
    let body = crate::mount::BodyMotion::default();
    for i in 0..16 {
        let f = wing.evaluate(i as f64 / 16.0 + 0.01, &body);
        let values = f
            .total
            .force_n
            .iter()
            .chain(f.total.moment_hinge_nm.iter())
            .chain([&f.total.c_l, &f.total.c_d]);
        if !values.into_iter().all(|x| x.is_finite()) {
            return Err(v.invalid(
                "kinematics",
                format!("a model whose forces are not finite at phase {:.3}", i as f64 / 16.0 + 0.01),
                "magnitudes a float can carry through the force model (check extreme lengths, frequencies and wake-capture coefficients)",
            ));
        }
    }
    Ok(())
}

/// Builds a planform's geometry with the strips and centre of pressure of `aero`.
pub fn build_geometry(
    spec: &WingSpec,
    v: &Validator<'_>,
    field: &str,
    aero: &AeroSpec,
) -> Result<Geometry> {
    spec.planform.build(
        v,
        &format!("{field}.planform"),
        &spec.overrides,
        aero.strips,
        aero.cp_chord_frac,
    )
}

/// Resolves a fluid spec (a given Re sets nu from the wing's V_ref and c_bar).
pub fn build_fluid(
    spec: &FluidSpec,
    v: &Validator<'_>,
    field: &str,
    g: &Geometry,
    k: &Kinematics,
) -> Result<Fluid> {
    let rho = v.positive(&format!("{field}.density_kg_m3"), spec.density_kg_m3)?;
    let nu = match (spec.kinematic_viscosity_m2_s, spec.reynolds) {
        (Some(nu), None) => v.positive(&format!("{field}.kinematic_viscosity_m2_s"), nu)?,
        (None, Some(re)) => {
            let re = v.positive(&format!("{field}.reynolds"), re)?;
            k.peak_stroke_rate_rad_s() * g.r_gyration_m * g.mean_chord_m / re
        }
        (None, None) => Fluid::AIR_20C.kinematic_viscosity_m2_s,
        (Some(nu), Some(re)) => {
            return Err(v.invalid(
                &format!("{field}.reynolds"),
                format!("{re} together with kinematic_viscosity_m2_s = {nu}"),
                "only one of kinematic_viscosity_m2_s and reynolds",
            ));
        }
    };
    Ok(Fluid {
        density_kg_m3: rho,
        kinematic_viscosity_m2_s: nu,
    })
}
