//! The bumblebee's rows: its four longitudinal mode times against Sun & Xiong's (2005)
//! abstract, its nine non-dimensional longitudinal derivatives term by term against the
//! paper's CFD table ([`crate::sun_xiong`]), in the paper's axes, and its power at 4.5 m/s
//! against its hover power (Dudley & Ellington 1990b: independent of airspeed).
//!
//! A derivative that misses carries what was measured on the model: which of its force terms
//! sets the derivative (the value with only the translational term, without the hover
//! downwash, without Lee et al.'s f_AR f_Ro), and for the couplings through a moment arm
//! (X_q, M_u, M_w) the arm the model's and the CFD's derivatives imply.

use wingforce::{AddedMassForm, AeroOptions};

use super::rows::{Check, RowBuilder};
use crate::error::Result;
use crate::flight::{FlightCondition, trim_point};
use crate::model::Vehicle;
use crate::operating_points::{SUN_XIONG_SOURCE, bumblebee_pitch_modes_note};
use crate::stability::analyze;
use crate::sun_xiong::{self, Comparison, MODE_TIME_NAMES, MODE_TIMES_S, TABLE_SOURCE};
use crate::trim::{LiftVariable, trim_at};

/// The bound on every bumblebee row: issue 17's 30% for a quasi-steady averaged model beside
/// CFD, the mode times' bound used alike for the derivatives they come from.
const TOLERANCE: f64 = 0.30;

/// Pushes the bumblebee's rows.
pub(super) fn bumblebee_rows(b: &mut RowBuilder, bee: &Vehicle) -> Result<()> {
    let c = sun_xiong::compare(bee)?;
    let note = bumblebee_pitch_modes_note(&c);
    for i in 0..4 {
        let (computed, published) = (c.model_times_s[i], MODE_TIMES_S[i]);
        b.push(
            "bumblebee",
            MODE_TIME_NAMES[i],
            SUN_XIONG_SOURCE,
            computed,
            Some(published),
            Check::Relative {
                tolerance: TOLERANCE,
            },
            false,
            || format!("{:+.0}% off: {note}", 100.0 * (computed / published - 1.0)),
        );
    }

    let variants = Variants::measure(bee)?;
    for &(name, model) in &c.model_derivatives {
        let published = sun_xiong::published(name).unwrap_or(f64::NAN);
        b.push(
            "bumblebee",
            format!(
                "non-dimensional derivative {name} at hover trim (Sun & Xiong's axes: x forward, z down, q and M nose up)"
            ),
            TABLE_SOURCE,
            model,
            Some(published),
            Check::Relative {
                tolerance: TOLERANCE,
            },
            false,
            || derivative_cause(name, model, published, &c, &variants),
        );
    }
    power_row(b, bee)
}

/// Dudley & Ellington 1990b (J Exp Biol 148:53, abstract): "the power required to fly is
/// independent of airspeed over a range from hovering flight to an airspeed of 4.5 m/s".
const POWER_SOURCE: &str = "Dudley & Ellington 1990b";

/// The fastest airspeed of Dudley & Ellington's bumblebees, m/s.
const TOP_SPEED_M_S: f64 = 4.5;

/// The aerodynamic power at [`TOP_SPEED_M_S`] over the hover power, both trimmed on the
/// mid-stroke angle of attack with the stroke amplitude and the wingbeat frequency held: of
/// the filmed bees' kinematics, "body angle, stroke plane angle, geometrical angle of attack,
/// and rotational angles of the wings" varied consistently with airspeed (Dudley & Ellington
/// 1990a, J Exp Biol 148:19, abstract), amplitude and frequency not. The cause of a miss
/// gives the ratio trimmed on the amplitude (the model file's lift variable) beside it.
fn power_row(b: &mut RowBuilder, bee: &Vehicle) -> Result<()> {
    let ratio = |lift: LiftVariable| -> Result<f64> {
        let power = |u: f64| -> Result<f64> {
            let t = trim_at(bee, lift, &FlightCondition::new(u, 0.0)?)?;
            Ok(trim_point(bee, &t)?.power.aero_w)
        };
        Ok(power(TOP_SPEED_M_S)? / power(0.0)?)
    };
    let at_aoa = ratio(LiftVariable::AngleOfAttack)?;
    b.push(
        "bumblebee",
        "aerodynamic power at 4.5 m/s / hover power, angle-of-attack trim (amplitude and frequency held)",
        POWER_SOURCE,
        at_aoa,
        Some(1.0),
        Check::Relative { tolerance: 0.15 },
        false,
        || match ratio(LiftVariable::Amplitude) {
            Ok(r) => format!(
                "{:+.0}% off; trimmed on the stroke amplitude instead, {r:.3}",
                100.0 * (at_aoa - 1.0)
            ),
            Err(e) => format!("{:+.0}% off; the amplitude trim: {e}", 100.0 * (at_aoa - 1.0)),
        },
    );
    Ok(())
}

/// The model's derivatives (Sun & Xiong's axes) with parts of its aerodynamics switched off.
struct Variants {
    translational_only: Vec<(&'static str, f64)>,
    no_downwash: Vec<(&'static str, f64)>,
    no_ar_ro: Vec<(&'static str, f64)>,
}

impl Variants {
    fn measure(bee: &Vehicle) -> Result<Self> {
        let derivatives = |f: &dyn Fn(&mut AeroOptions)| -> Result<Vec<(&'static str, f64)>> {
            let mut v = bee.clone();
            for w in &mut v.wings {
                let mut o = w.options().clone();
                f(&mut o);
                w.set_options(o);
            }
            sun_xiong::model_derivatives(&analyze(&v, false)?)
        };
        Ok(Self {
            translational_only: derivatives(&|o| {
                o.rotational = false;
                o.wake_capture = None;
                o.added_mass = AddedMassForm::Off;
            })?,
            no_downwash: derivatives(&|o| o.induced_inflow = None)?,
            no_ar_ro: derivatives(&|o| o.ar_ro_corrections = false)?,
        })
    }
}

fn value(set: &[(&'static str, f64)], name: &str) -> f64 {
    set.iter()
        .find(|(n, _)| *n == name)
        .map_or(f64::NAN, |&(_, v)| v)
}

/// Why a derivative misses, measured on the model.
fn derivative_cause(
    name: &str,
    model: f64,
    published: f64,
    c: &Comparison,
    v: &Variants,
) -> String {
    let mut why = format!(
        "model/CFD {:.2}; with the translational term alone {:+.3}, without the hover downwash {:+.3}, without f_AR f_Ro {:+.3}",
        model / published,
        value(&v.translational_only, name),
        value(&v.no_downwash, name),
        value(&v.no_ar_ro, name),
    );
    let within = |x: f64| (x / published - 1.0).abs() <= TOLERANCE;
    if ![&v.translational_only, &v.no_downwash, &v.no_ar_ro]
        .iter()
        .any(|set| within(value(set, name)))
    {
        why += ": none of these comes within the tolerance, so the quasi-steady translational term's response to the body's motion sets the miss";
    }
    let m = |n: &str| value(&c.model_derivatives, n);
    let p = |n: &str| sun_xiong::published(n).unwrap_or(f64::NAN);
    let r = &c.report.nondimensional_reference;
    // Heights and lengths the couplings imply (z down: negative is above the centre of mass):
    // X_q / X_u and M_u / X_u are the height z at which the u-force acts, M_w / Z_w minus the
    // fore-aft distance at which the w-force acts.
    let chord_mm = 1e3 * r.chord_m;
    let beat_mm = 1e3 * r.speed_m_s / r.freq_hz;
    let paper_beat_mm = 1e3 * c.paper_reference.speed_m_s / c.paper_reference.freq_hz;
    match name {
        "X_q" => {
            why += &format!(
                "; X_q/X_u puts the u-force {:+.2} mm from the centre of mass in z (the wings' mean centre of pressure; z down), the CFD's {:+.2} mm",
                beat_mm * m("X_q") / m("X_u"),
                paper_beat_mm * p("X_q") / p("X_u")
            )
        }
        "M_u" => {
            why += &format!(
                "; M_u/X_u puts the u-force {:+.2} mm from the centre of mass in z (z down; the model's X_q/X_u gives the same height), the CFD's {:+.2} mm: the CFD's wings pitch the body up with u by more than their drag change at the wings' height",
                chord_mm * m("M_u") / m("X_u"),
                chord_mm * p("M_u") / p("X_u")
            )
        }
        "M_w" => {
            why += &format!(
                "; M_w/Z_w puts the w-force {:+.3} mm from the centre of mass in x (x forward; the trim puts the mean lift over it), the CFD's {:+.3} mm",
                -chord_mm * m("M_w") / m("Z_w"),
                -chord_mm * p("M_w") / p("Z_w")
            )
        }
        "X_w" | "Z_u" | "Z_q" => {
            why += &format!(
                "; the model's down- and upstrokes mirror each other (equal angles of attack, no deviation), which leaves no coupling of the fore-aft and vertical motions: {model:+.1e}, where the CFD's is {:.0}% of its diagonal derivatives",
                100.0 * published.abs() / p("X_u").abs().min(p("Z_w").abs())
            )
        }
        _ => {}
    }
    why
}
