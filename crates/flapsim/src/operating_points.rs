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

use crate::averaged::{FrozenState, mean_loads};
use crate::error::{Error, Result};
use crate::model::Vehicle;
use crate::sun_xiong;

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
        limitation: ((bee_lw - 1.0).abs() > 0.15).then(|| format!(
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
    let (modes, note) = bumblebee_modes(&bee)?;
    let heave = bumblebee_heave_note(&bee, &sun_xiong::compare(&bee)?, None)?;
    for (i, (name, published, computed, limited)) in modes.into_iter().enumerate() {
        let limitation = match (limited, i, &heave) {
            (true, _, _) => Some(note.clone()),
            (false, 3, Some(h)) => Some(h.clone()),
            _ => None,
        };
        rows.push(OperatingPoint {
            name: name.to_owned(),
            source: SUN_XIONG_SOURCE,
            published,
            computed,
            relative_tolerance: 0.30,
            limitation,
        });
    }
    Ok(rows)
}

/// Where the bumblebee's mode times come from.
pub use crate::sun_xiong::MODES_SOURCE as SUN_XIONG_SOURCE;

/// The bumblebee's four longitudinal mode times from the averaged analysis beside Sun &
/// Xiong's (2005, abstract: period 0.32 s and doubling 0.1 s of the unstable oscillatory
/// mode, half times 0.024 s fast and 0.37 s slow subsidence): (what, published, computed,
/// known to miss (the pitch-dominated pair)), and why that pair misses
/// ([`bumblebee_pitch_modes_note`]).
pub fn bumblebee_modes(bee: &Vehicle) -> Result<([(&'static str, f64, f64, bool); 4], String)> {
    let c = sun_xiong::compare(bee)?;
    let known_to_miss = [true, false, true, false];
    let rows = std::array::from_fn(|i| {
        (
            sun_xiong::MODE_TIME_NAMES[i],
            sun_xiong::MODE_TIMES_S[i],
            c.model_times_s[i],
            known_to_miss[i],
        )
    });
    Ok((rows, bumblebee_pitch_modes_note(&c)))
}

/// Why the bumblebee's slow subsidence (the heave mode, whose rate is about Z_w / m) misses
/// Sun & Xiong's half time, measured on the model with its wake as it stands and under the
/// other wake ([`sun_xiong::Heave`]: both in N s/m beside the CFD's and momentum theory's);
/// `None` when it does not miss. `other`: the bumblebee's comparison under the other wake,
/// where already measured.
pub fn bumblebee_heave_note(
    bee: &Vehicle,
    c: &sun_xiong::Comparison,
    other: Option<&sun_xiong::Comparison>,
) -> Result<Option<String>> {
    let half_time = c.model_times_s[3];
    if (half_time / sun_xiong::MODE_TIMES_S[3] - 1.0).abs() <= 0.30 {
        return Ok(None);
    }
    let z_w = |c: &sun_xiong::Comparison| {
        c.model_derivatives
            .iter()
            .find(|(n, _)| *n == "Z_w")
            .map_or(f64::NAN, |&(_, v)| v)
    };
    let published = sun_xiong::published("Z_w").unwrap_or(f64::NAN);
    let measured;
    let other = match other {
        Some(o) => o,
        None => {
            measured = other_wake_comparison(bee)?;
            &measured
        }
    };
    let heave = bumblebee_heave(bee, c, other)?;
    let frozen = if bee.inflow_model() == wingforce::InflowModel::Dynamic {
        other
    } else {
        c
    };
    Ok(Some(format!(
        "the slow subsidence is the heave mode (rate about Z_w / m): the model's Z_w is {:.2} of the CFD's with its wake ({}), {:.2} with the wake frozen ({:.3} s half time); {}: the CFD's heave damping lies between the frozen and the responsive wake's (which part of its wake answers a heave is not in its stored text)",
        z_w(c) / published,
        bee.inflow_model(),
        z_w(frozen) / published,
        frozen.model_times_s[3],
        heave.describe(),
    )))
}

/// The bumblebee beside Sun & Xiong under the other wake: frozen for a dynamic one, dynamic
/// else.
pub fn other_wake_comparison(bee: &Vehicle) -> Result<sun_xiong::Comparison> {
    use wingforce::InflowModel::{Dynamic, Frozen};
    let wake = if bee.inflow_model() == Dynamic {
        Frozen
    } else {
        Dynamic
    };
    sun_xiong::compare(&bee.with_inflow_model(wake)?)
}

/// The bumblebee's heave damping under both wakes ([`sun_xiong::Heave`]), from its comparison
/// `c` as it stands and `other` under the other wake ([`other_wake_comparison`]).
pub fn bumblebee_heave(
    bee: &Vehicle,
    c: &sun_xiong::Comparison,
    other: &sun_xiong::Comparison,
) -> Result<sun_xiong::Heave> {
    use wingforce::InflowModel::{Dynamic, Frozen};
    let frozen_bee = bee.with_inflow_model(Frozen)?;
    match bee.inflow_model() {
        Dynamic => sun_xiong::Heave::measure(&frozen_bee, other, c),
        Frozen => sun_xiong::Heave::measure(&frozen_bee, c, other),
        off => Err(Error::Analysis(format!(
            "the heave damping under both wakes is measured on a bumblebee with an induced flow, not `{off}`"
        ))),
    }
}

/// Why the two pitch-dominated modes of the bumblebee miss Sun & Xiong's times (issue 17),
/// measured: the same mass, pitch inertia and gravity with the paper's own CFD derivatives in
/// place of the model's give the paper's times, so the miss lies in the quasi-steady
/// derivatives, not in the estimated inertia.
pub fn bumblebee_pitch_modes_note(c: &sun_xiong::Comparison) -> String {
    let t = c.published_derivative_times_s;
    let worst = (0..4)
        .map(|i| (t[i] / sun_xiong::MODE_TIMES_S[i] - 1.0).abs())
        .fold(0.0, f64::max);
    let ratio = |name: &str| {
        let model = c
            .model_derivatives
            .iter()
            .find(|(n, _)| *n == name)
            .map_or(f64::NAN, |&(_, v)| v);
        model / sun_xiong::published(name).unwrap_or(f64::NAN)
    };
    format!(
        "with Sun & Xiong's own CFD derivatives (their table) in place of the model's, the model's mass, I_y (an ellipsoid estimate) and gravity give a {:.3} s period, {:.3} s doubling, {:.4} s and {:.3} s half times, each within {:.0}% of the abstract: the pitch-dominated modes miss through the quasi-steady derivatives (M_u {:.2}, M_q {:.2} and X_u {:.2} times the CFD's; the derivative rows), not through I_y",
        t[0],
        t[1],
        t[2],
        t[3],
        100.0 * worst,
        ratio("M_u"),
        ratio("M_q"),
        ratio("X_u"),
    )
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
