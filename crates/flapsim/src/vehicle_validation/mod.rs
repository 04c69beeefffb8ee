//! Every built-in vehicle against measured data (issue 24): the rows of `flapwing validate`'s
//! vehicles section, computed here (the command only prints them).
//!
//! Each row names the vehicle, what is compared, the source of the measured value, the
//! model's value, the measured value (`None` where no published value was found: the row
//! then checks what can be checked, e.g. the sign), the tolerance and its verdict: `pass` or
//! `MISS`. A miss carries its cause, measured on the model when the row is computed (never a
//! widened tolerance, never a hidden row). A miss is a finding about the model, reported
//! with its cause, not a failure of the command; the rows that check a property the model
//! must have by construction (the impulse form's zero cycle-mean added-mass force: its
//! share of the mean lift below 1%) are marked `property`, and the command names their
//! misses apart.
//!
//! Sources: docs/research/issue24-sources.md (the notes gathered for issue 24): RoboBee
//! bench data from the Harvard Microrobotics Lab's public robobee3d repository (section 1c),
//! Jafferis, Graule & Wood 2016 (1a), the Purdue hummingbird's `flappy` simulator (2b-c),
//! Sun & Xiong 2005 (3) and Fry, Sayaman & Dickinson 2005 (4).
//!
//! Tolerances: 15% on stroke and pitch amplitude, lift and drive (the bound issue 24 sets for
//! the RoboBee, used alike for the hummingbird's drive); 10% on the hummingbird's pitch
//! amplitude against its +-45 deg stops (a wing that strikes its stops every half stroke
//! swings to them: only the contact's give lies between); 15% on the fruit fly's weight
//! support (the quoted hover kinematics span 130-150 deg and 200-220 Hz, and a
//! quasi-steady lift goes as (amplitude x frequency)^2: (150/140)^2 = 1.15, (130/140)^2 =
//! 0.86); 30% on the bumblebee's mode times (issue 17's bound: a quasi-steady averaged model
//! beside modes from CFD derivatives); 1% on the added-mass share (issue 24); 15% on the
//! dragonfly's weight support in forward flight (the fruit fly's bound, used alike).

mod actuated;
mod bumblebee;
mod data;
pub mod dragonfly;
mod rows;

use nalgebra::Vector3;
use wingforce::Term;

use crate::averaged::{FrozenState, mean_loads};
use crate::error::Result;
use crate::model::Vehicle;
use crate::operating_points::{builtin, lift_over_weight};

use actuated::{hummingbird_rows, robobee_rows};
use bumblebee::bumblebee_rows;
pub use data::*;
use dragonfly::dragonfly_rows;
pub use rows::*;

/// Share of the mean lift (world z at the vehicle's initial attitude, body still) that the
/// added-mass term's cycle mean carries; for an actuated vehicle over its wings' periodic
/// motion. Returns (share, added-mass mean lift N, total aerodynamic mean lift N).
pub fn added_mass_lift_share(vehicle: &Vehicle) -> Result<(f64, f64, f64)> {
    let m = mean_loads(
        vehicle,
        &FrozenState {
            world_from_body: vehicle.initial_attitude,
            velocity_body_m_s: Vector3::zeros(),
            angular_velocity_body_rad_s: Vector3::zeros(),
        },
        200,
    )?;
    let q = vehicle.initial_attitude;
    let am = (q * m.terms[Term::AddedMass as usize].force_n).z;
    let total = (q * m.total.force_n).z;
    Ok((am / total, am, total))
}

/// Computes the vehicles section: every row as the built-in models stand, and for the
/// vehicles with an induced flow, beside it the same row under the other wake
/// ([`VehicleRow::other_wake`]; issue #38).
pub fn vehicle_section() -> Result<VehicleSection> {
    // The two passes are independent: side by side on the machine's cores.
    let (section, other) = rayon::join(
        || vehicle_section_with(false),
        || vehicle_section_with(true),
    );
    let (mut section, other) = (section?, other?);
    for (row, o) in section.rows.iter_mut().zip(other.rows) {
        if let Some(inflow) = builtin(row.vehicle).ok().and_then(|v| other_wake(&v)) {
            row.other_wake = Some(OtherWake {
                inflow,
                model: o.model,
                verdict: o.verdict,
                cause: o.cause,
            });
        }
    }
    Ok(section)
}

/// The section with every vehicle that has an induced flow under its other wake (`true`) or
/// as its model file says.
fn vehicle_section_with(other_wake: bool) -> Result<VehicleSection> {
    let mut b = RowBuilder {
        rows: Vec::new(),
        other_wake,
    };
    robobee_rows(&mut b)?;
    hummingbird_rows(&mut b)?;

    let fly = b.vehicle("drosophila")?;
    let fly_lw = lift_over_weight(&fly)?;
    b.push(
        "drosophila",
        "weight support: mean lift / weight at the model's hover kinematics (before trim)",
        "Fry, Sayaman & Dickinson 2005 (the fly hovers: lift = weight)",
        fly_lw,
        Some(1.0),
        Check::Relative { tolerance: 0.15 },
        false,
        || {
            format!(
                "L/W {fly_lw:.3} at the model's kinematics: the quoted hover kinematics span 130-150 deg and 200-220 Hz (notes 4), none from the 2005 table itself"
            )
        },
    );

    let bee = b.vehicle("bumblebee")?;
    bumblebee_rows(&mut b, &bee)?;

    dragonfly_rows(&mut b)?;

    for name in [
        "drosophila",
        "bumblebee",
        "robobee_kinematic",
        "dragonfly",
        "robobee",
        "hummingbird",
    ] {
        let v = b.vehicle(name)?;
        let form = v.wings[0].options().added_mass;
        let (share, am, total) = added_mass_lift_share(&v)?;
        b.push(
            name,
            format!(
                "added-mass share of the mean lift ({}), body at rest",
                form.name()
            ),
            "issue 24 / MODEL.md 4.3: an ideal-fluid added-mass force has no cycle mean",
            share,
            None,
            Check::Within {
                lo: -0.01,
                hi: 0.01,
            },
            true,
            || {
                let periodic = crate::actuated::periodic::settle_at_rest(&v)
                    .ok()
                    .flatten()
                    .map(|p| {
                        let peak = p
                            .samples
                            .iter()
                            .map(|w| {
                                (w[0].term(Term::AddedMass).force_n
                                    + w[1].term(Term::AddedMass).force_n)
                                    .z
                                    .abs()
                            })
                            .fold(0.0, f64::max);
                        format!(
                            "; over the wings' periodic motion (periodic to {:.1e} rad per period, {} steps) that mean is {:.2e} of the term's peak {peak:.3e} N, where a -dP/dt of a periodic impulse averages to zero (issue 24 asks 1e-9 of the peak): the term the actuated wing reports is not the whole derivative",
                            p.drift_rad,
                            p.samples.len(),
                            (am / peak).abs()
                        )
                    })
                    .unwrap_or_default();
                format!(
                    "the added-mass term ({}) carries {am:.3e} N of {total:.3e} N mean lift{periodic}",
                    form.describe()
                )
            },
        );
    }
    Ok(VehicleSection {
        rows: b.rows,
        not_found: NOT_FOUND.to_vec(),
        estimates: ESTIMATES.to_vec(),
    })
}

/// The built-in vehicles the section covers.
pub const VEHICLES: [&str; 6] = [
    "robobee",
    "hummingbird",
    "drosophila",
    "bumblebee",
    "robobee_kinematic",
    "dragonfly",
];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn checks_give_their_verdicts() {
        let row = |model, measured, check| VehicleRow {
            vehicle: "x",
            quantity: String::new(),
            source: String::new(),
            model,
            measured,
            check,
            verdict: Verdict::Miss,
            cause: None,
            property: false,
            other_wake: None,
        };
        let rel = Check::Relative { tolerance: 0.15 };
        assert!(row(1.15, Some(1.0), rel).passes());
        assert!(!row(1.16, Some(1.0), rel).passes());
        assert!(!row(f64::NAN, Some(1.0), rel).passes());
        assert!(!row(1.0, None, rel).passes());
        let below = Check::Below { bound: 0.0 };
        assert!(row(-1.0, None, below).passes() && !row(0.0, None, below).passes());
        let within = Check::Within { lo: 0.0, hi: 250.0 };
        assert!(row(250.0, None, within).passes() && !row(f64::NAN, None, within).passes());
    }

    #[test]
    fn every_estimate_names_a_key_of_its_model_file() {
        for e in ESTIMATES {
            let text = crate::builtin_model(e.vehicle).unwrap();
            let key = e.parameter.rsplit('.').next().unwrap();
            let section = &e.parameter[..e.parameter.len() - key.len() - 1];
            let at = text
                .find(&format!("\n[{section}]"))
                .unwrap_or_else(|| panic!("{e:?}: no section"));
            let body = &text[at + 1..];
            let end = body[1..].find("\n[").map_or(body.len(), |i| i + 1);
            assert!(
                body[..end]
                    .lines()
                    .any(|l| l.trim_start().starts_with(&format!("{key} "))
                        || l.trim_start().starts_with(&format!("{key}="))),
                "{e:?}"
            );
        }
    }
}
