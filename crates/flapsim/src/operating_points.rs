//! The built-in insects at their published operating points, set beside the published
//! figures: mean vertical force over weight at the published hover kinematics (before any
//! trim), and Sun & Xiong's (2005) four longitudinal mode times against the averaged
//! analysis of the trimmed bumblebee. `flapwing validate` prints these rows after the seed
//! paper's.
//!
//! Tolerances (the bounds issue 17 set): weight support within 15%, since the models are
//! built from published means over individuals, not one animal measured for both morphology
//! and kinematics; mode times within 30%, since the comparison sets a quasi-steady model's
//! averaged modes beside modes from CFD derivatives.
//!
//! A row that flapwing's model is known to miss carries the reason (`limitation`), with the
//! evidence measured here ([`added_mass_share`]); such a row is reported, not hidden, and a
//! test checks that it still misses, so the note is dropped when the model improves.

use nalgebra::Vector3;
use wingforce::Term;

use crate::Vehicle;
use crate::averaged::{FrozenState, mean_loads};
use crate::error::{Error, Result};
use crate::stability::{ModeKind, analyze};

/// One comparison with a published figure.
#[derive(Debug, Clone, PartialEq)]
pub struct OperatingPoint {
    /// What is compared, with units.
    pub name: String,
    /// Where the published figure comes from.
    pub source: &'static str,
    /// The published figure.
    pub published: f64,
    /// flapwing's figure.
    pub computed: f64,
    /// Largest accepted |computed / published - 1|.
    pub relative_tolerance: f64,
    /// Why flapwing's quasi-steady model is known to fall outside the tolerance here, with the
    /// evidence; `None` where it is expected to agree.
    pub limitation: Option<String>,
}

impl OperatingPoint {
    /// computed / published - 1.
    pub fn relative_error(&self) -> f64 {
        self.computed / self.published - 1.0
    }

    /// True when within the tolerance (false for NaN).
    pub fn within(&self) -> bool {
        self.relative_error().abs() <= self.relative_tolerance
    }

    /// The verdict: within and unnoted, or outside with its known limitation; anything else
    /// (outside without a note, or a note on a row that now agrees) is a failure.
    pub fn verdict(&self) -> Verdict {
        match (self.within(), self.limitation.is_some()) {
            (true, false) => Verdict::Pass,
            (false, true) => Verdict::KnownLimitation,
            (false, false) => Verdict::Fail,
            (true, true) => Verdict::StaleNote,
        }
    }
}

/// See [`OperatingPoint::verdict`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Verdict {
    /// Within the tolerance.
    Pass,
    /// Outside, for the documented reason.
    KnownLimitation,
    /// Outside with no documented reason.
    Fail,
    /// Inside although documented as outside: the note must go.
    StaleNote,
}

/// Share of the weight that the cycle mean of the added-mass term carries, at the vehicle's
/// initial (published) attitude and kinematics. An ideal-fluid added-mass force is the time
/// derivative of the fluid impulse, which is periodic in a periodic wingbeat in still air, so
/// its cycle mean is zero; the per-strip quasi-steady form (MODEL.md 4.3, -m_a a_n along the
/// rotating normal) leaves the term -m_a v_n dn/dt, which is not a derivative and has a mean
/// wherever the wing pitches while it moves.
pub fn added_mass_share(vehicle: &Vehicle) -> Result<f64> {
    let m = mean_loads(vehicle, &still(vehicle), 200)?;
    let f = vehicle.initial_attitude * m.terms[Term::AddedMass as usize].force_n;
    Ok(f.z / vehicle.weight_n())
}

/// Mean vertical force over weight at the vehicle's initial attitude and base kinematics.
pub fn lift_over_weight(vehicle: &Vehicle) -> Result<f64> {
    let m = mean_loads(vehicle, &still(vehicle), 200)?;
    Ok((vehicle.initial_attitude * m.total.force_n).z / vehicle.weight_n())
}

fn still(vehicle: &Vehicle) -> FrozenState {
    FrozenState {
        world_from_body: vehicle.initial_attitude,
        velocity_body_m_s: Vector3::zeros(),
        angular_velocity_body_rad_s: Vector3::zeros(),
    }
}

/// The rows for the built-in bumblebee (Sun & Xiong 2005) and fruit fly (Fry et al. 2005).
pub fn operating_points() -> Result<Vec<OperatingPoint>> {
    let bee = builtin("bumblebee")?;
    let fly = builtin("drosophila")?;
    let mut rows = Vec::new();
    // With the induced inflow of hover (`[aero] induced_inflow`, wingforce::inflow) the fly
    // carries its weight within the tolerance. The bumblebee still makes too much lift at the
    // estimated 40 deg angle of attack; its note gives the measured shares and where a trim on
    // Sun & Xiong's own variable lands.
    let bee_lw = lift_over_weight(&bee)?;
    let bee_am = added_mass_share(&bee)?;
    let bee_aoa_deg = trimmed_angle_of_attack_deg(&bee)?;
    rows.push(OperatingPoint {
        name: "bumblebee L/W at 116 deg, 155 Hz (before trim)".to_owned(),
        source: "Sun & Xiong 2005 (hovers at these)",
        published: 1.0,
        computed: bee_lw,
        relative_tolerance: 0.15,
        limitation: Some(format!(
            "at 40 deg angle of attack (an estimate: Sun & Xiong's trimmed angles are not in the stored sources) the translational and wake-capture terms at Lee et al. 2016's coefficients carry {:.2} W with the hover downwash and the added-mass term's cycle mean ({}) {bee_am:.2} W (an ideal-fluid added-mass force has none); a trim on their variable, the angle of attack, lands at {bee_aoa_deg:.1} deg",
            bee_lw - bee_am,
            bee.wings[0].options().added_mass.describe()
        )),
    });
    rows.push(OperatingPoint {
        name: "fruit fly L/W at 140 deg, 218 Hz (before trim)".to_owned(),
        source: "Fry et al. 2005 (QS ~ all force)",
        published: 1.0,
        computed: lift_over_weight(&fly)?,
        relative_tolerance: 0.15,
        limitation: None,
    });
    let note = bumblebee_pitch_modes_note(&bee)?;
    for (name, published, computed, limited) in bumblebee_mode_times(&bee)? {
        rows.push(OperatingPoint {
            name: name.to_owned(),
            source: SUN_XIONG_SOURCE,
            published,
            computed,
            relative_tolerance: 0.30,
            limitation: limited.then(|| note.clone()),
        });
    }
    Ok(rows)
}

/// Where the bumblebee's mode times come from.
pub const SUN_XIONG_SOURCE: &str = "Sun & Xiong 2005, abstract";

/// Why the two pitch-dominated modes of the bumblebee miss Sun & Xiong's times (issue 17),
/// measured here: the same analysis with 30% less pitch inertia, and how far the other two
/// modes are off.
pub fn bumblebee_pitch_modes_note(bee: &Vehicle) -> Result<String> {
    let times = bumblebee_mode_times(bee)?;
    let mut light = bee.clone();
    light.inertia_kg_m2[(1, 1)] *= 0.7;
    let light_times = bumblebee_mode_times(&light)?;
    let off = |i: usize| (100.0 * (times[i].2 / times[i].1 - 1.0)).abs();
    Ok(format!(
        "the two pitch-dominated modes scale with M_u, M_q and I_y over the body; I_y is an ellipsoid estimate, and 30% less of it (the least the inertia's triangle inequality allows) brings them to {:.2} s and {:.3} s: the rest lies in the quasi-steady M_u and M_q (the derivative table of `stability`), while the same model puts the doubling and slow-subsidence times {:.0}% and {:.0}% off",
        light_times[0].2,
        light_times[2].2,
        off(1),
        off(3)
    ))
}

/// The bumblebee's four longitudinal mode times from the averaged analysis beside Sun &
/// Xiong's (2005, abstract: period 0.32 s and doubling 0.1 s of the unstable oscillatory
/// mode, half times 0.024 s fast and 0.37 s slow subsidence): (what, published, computed,
/// known to miss (the pitch-dominated pair)).
pub fn bumblebee_mode_times(bee: &Vehicle) -> Result<[(&'static str, f64, f64, bool); 4]> {
    let report = analyze(bee, false)?;
    let modes = &report.longitudinal_modes;
    let osc = modes
        .iter()
        .find(|m| m.kind == ModeKind::Oscillatory)
        .ok_or_else(|| {
            Error::Analysis("the bumblebee has no oscillatory longitudinal mode".into())
        })?;
    let mut halves: Vec<f64> = modes
        .iter()
        .filter(|m| m.kind == ModeKind::Real && m.stable)
        .filter_map(|m| m.time_to_half_or_double_s)
        .collect();
    halves.sort_by(f64::total_cmp);
    if halves.len() != 2 {
        return Err(Error::Analysis(format!(
            "the bumblebee has {} stable real longitudinal modes, Sun & Xiong 2005 found 2",
            halves.len()
        )));
    }
    Ok([
        (
            "bumblebee unstable oscillatory mode: period, s",
            0.32,
            osc.period_s.unwrap_or(f64::NAN),
            true,
        ),
        (
            "bumblebee unstable oscillatory mode: doubling time, s",
            0.1,
            osc.time_to_half_or_double_s.unwrap_or(f64::NAN),
            false,
        ),
        (
            "bumblebee fast subsidence: half time, s",
            0.024,
            halves[0],
            true,
        ),
        (
            "bumblebee slow subsidence: half time, s",
            0.37,
            halves[1],
            false,
        ),
    ])
}

/// The mid-stroke angle of attack, deg, at which a hover trim on the angle of attack (Sun &
/// Xiong's trim variable) carries the weight at the published stroke.
pub fn trimmed_angle_of_attack_deg(vehicle: &Vehicle) -> Result<f64> {
    let t = crate::trim::trim_on(vehicle, crate::trim::LiftVariable::AngleOfAttack)?;
    let (down_rad, _) = vehicle.base_kinematics[0]
        .mid_stroke_aoa_rad()
        .ok_or_else(|| {
            Error::Analysis(format!("{}: no mid-stroke angle of attack", vehicle.name))
        })?;
    Ok((down_rad + t.controls.aoa_rad).to_degrees())
}

pub(crate) fn builtin(name: &str) -> Result<Vehicle> {
    let text = crate::builtin_model(name)
        .ok_or_else(|| Error::Analysis(format!("no built-in model `{name}`")))?;
    Vehicle::from_toml(text, name)
}
