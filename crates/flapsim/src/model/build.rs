//! Validation: a [`VehicleSpec`] (the file's tables) into a [`Vehicle`] (SI units, wings
//! prepared), every value range-checked with an error naming the file, the field, the value
//! and what is allowed.

use nalgebra::{Matrix3, UnitQuaternion, Vector3};
use wingforce::model::{build_fluid, build_geometry, parse_toml};
use wingforce::{Fluid, Kinematics, KinematicsSpec, Mount, Side, Validator, Wing};

use super::Vehicle;
use super::spec::{HingeSpec, PairSpec, VehicleSpec};
use crate::controls::Controls;
use crate::error::Result;

impl VehicleSpec {
    /// Parses TOML text; `origin` (the file path) appears in errors.
    pub fn from_toml(text: &str, origin: &str) -> Result<Self> {
        Ok(parse_toml(text, origin)?)
    }

    /// Validates everything and prepares the wings.
    pub fn build(&self, origin: &str) -> Result<Vehicle> {
        let v = Validator::new(origin);
        let mass = v.positive("body.mass_kg", self.body.mass_kg)?;
        let [ixx, iyy, izz] = self.body.inertia_diag_kg_m2;
        for (i, x) in [ixx, iyy, izz].into_iter().enumerate() {
            v.positive(&format!("body.inertia_diag_kg_m2[{i}]"), x)?;
        }
        let ixz = v.finite("body.inertia_xz_kg_m2", self.body.inertia_xz_kg_m2)?;
        // Positive definite and satisfying the triangle inequalities of a real body.
        if ixz * ixz >= ixx * izz || ixx + iyy < izz || iyy + izz < ixx || ixx + izz < iyy {
            return Err(v
                .invalid(
                    "body.inertia_diag_kg_m2",
                    format!("[{ixx}, {iyy}, {izz}] with Ixz {ixz}"),
                    "a physical inertia: each diagonal entry at most the sum of the other two, and Ixz^2 < Ixx Izz",
                )
                .into());
        }
        let length = v.positive("body.length_m", self.body.length_m)?;
        let drag_area = v.within("body.drag_area_m2", self.body.drag_area_m2, 0.0, 1.0)?;
        let g = v.within("gravity_m_s2", self.gravity_m_s2, 0.0, 100.0)?;
        let mut aero = self.aero.build(&v, "aero")?;
        if !self.pairs.is_empty() && self.actuation.is_some() {
            return Err(v
                .invalid(
                    "pairs",
                    format!("{} further pair(s)", self.pairs.len()),
                    "no [[pairs]] on an actuated vehicle (its drives and wing dynamics are one left/right pair)",
                )
                .into());
        }
        // A twist is a measured table's feathering along the span; an actuated wing's pitch is
        // an output of its hinge dynamics, which would leave the twist unused.
        if self.actuation.is_some() {
            for (field, k) in [
                ("kinematics", Some(&self.kinematics)),
                ("left_kinematics", self.left_kinematics.as_ref()),
                ("right_kinematics", self.right_kinematics.as_ref()),
            ] {
                if let Some(KinematicsSpec::Tabulated { twist: Some(_), .. }) = k {
                    return Err(v
                        .invalid(
                            &format!("{field}.twist"),
                            "a spanwise twist",
                            "no twist on an actuated vehicle (its pitch is an output of the hinge dynamics, not a measured table)",
                        )
                        .into());
                }
            }
        }
        let inflow = self.aero.inflow_model(&v)?;
        if inflow != wingforce::InflowModel::Off {
            if !self.pairs.is_empty() && inflow == wingforce::InflowModel::Frozen {
                return Err(v
                    .invalid(
                        "aero.inflow",
                        inflow,
                        "\"off\" or \"dynamic\" for a model with [[pairs]] (the frozen momentum-theory downwash is that of one pair's disc; tandem pairs share and overlap theirs, which the dynamic wake models: wingforce::inflow::interference)",
                    )
                    .into());
            }
            if self.actuation.is_some() && inflow == wingforce::InflowModel::Frozen {
                return Err(v
                    .invalid(
                        "aero.inflow",
                        inflow,
                        "\"off\" or \"dynamic\" for an actuated vehicle (a frozen wake's disc is a prescribed stroke; an actuated vehicle's stroke is an output of its wing dynamics, which the dynamic wake measures)",
                    )
                    .into());
            }
            // Hover: the wings carry the weight, each its share (wingforce::inflow); a
            // dynamic inflow starts there and then follows each pair's own loads.
            let wings = 2.0 * (1 + self.pairs.len()) as f64;
            let mut i = wingforce::InducedInflow::hover(mass * g / wings);
            i.dynamic = inflow == wingforce::InflowModel::Dynamic;
            aero.induced_inflow = Some(i);
        }
        let geometry = build_geometry(&self.wing, &v, "wing", &self.aero)?;
        let base = self
            .kinematics
            .build(&v, "kinematics", geometry.r_gyration_m)?;
        let left_k = match &self.left_kinematics {
            Some(k) => k.build(&v, "left_kinematics", geometry.r_gyration_m)?,
            None => base.clone(),
        };
        let right_k = match &self.right_kinematics {
            Some(k) => k.build(&v, "right_kinematics", geometry.r_gyration_m)?,
            None => base.clone(),
        };
        let fluid: Fluid = build_fluid(&self.fluid, &v, "fluid", &geometry, &base)?;
        let (hinge_left, tilt) = build_hinge(&v, "hinge", &self.hinge)?;
        let mut pairs = Vec::with_capacity(self.pairs.len());
        for (p, pair) in self.pairs.iter().enumerate() {
            pairs.push(self.build_pair(&v, p, pair, &geometry, [&left_k, &right_k])?);
        }
        let sim = &self.sim;
        if !(10..=100_000).contains(&sim.steps_per_wingbeat) {
            return Err(v
                .invalid(
                    "sim.steps_per_wingbeat",
                    sim.steps_per_wingbeat,
                    "an integer in [10, 100000] (at least the model's sim.accurate_steps_per_wingbeat recommended)",
                )
                .into());
        }
        if let Some(n) = sim.accurate_steps_per_wingbeat
            && !(10..=100_000).contains(&n)
        {
            return Err(v
                .invalid(
                    "sim.accurate_steps_per_wingbeat",
                    n,
                    "an integer in [10, 100000], like sim.steps_per_wingbeat",
                )
                .into());
        }
        if !(1..=16).contains(&sim.solver_iterations) {
            return Err(v
                .invalid(
                    "sim.solver_iterations",
                    sim.solver_iterations,
                    "an integer in [1, 16]",
                )
                .into());
        }
        v.non_negative("sim.wing_mass_kg", sim.wing_mass_kg)?;
        v.positive("sim.max_speed_m_s", sim.max_speed_m_s)?;
        v.positive("sim.max_angular_speed_rad_s", sim.max_angular_speed_rad_s)?;
        let c = &self.controls;
        let controls = Controls {
            mean_stroke_rad: v
                .within("controls.mean_stroke_deg", c.mean_stroke_deg, -60.0, 60.0)?
                .to_radians(),
            amplitude_rad: v
                .within("controls.amplitude_deg", c.amplitude_deg, -90.0, 90.0)?
                .to_radians(),
            pitch_bias_rad: v
                .within("controls.pitch_bias_deg", c.pitch_bias_deg, -30.0, 30.0)?
                .to_radians(),
            aoa_rad: v
                .within("controls.aoa_deg", c.aoa_deg, -60.0, 60.0)?
                .to_radians(),
            freq_hz: v.within("controls.freq_hz", c.freq_hz, -1e4, 1e4)?,
            diff_amplitude_rad: v
                .within(
                    "controls.diff_amplitude_deg",
                    c.diff_amplitude_deg,
                    -90.0,
                    90.0,
                )?
                .to_radians(),
            diff_pitch_bias_rad: v
                .within(
                    "controls.diff_pitch_bias_deg",
                    c.diff_pitch_bias_deg,
                    -30.0,
                    30.0,
                )?
                .to_radians(),
            diff_mean_stroke_rad: v
                .within(
                    "controls.diff_mean_stroke_deg",
                    c.diff_mean_stroke_deg,
                    -60.0,
                    60.0,
                )?
                .to_radians(),
            bias_v: v.finite("controls.bias_v", c.bias_v)?,
            amplitude_v: v.finite("controls.amplitude_v", c.amplitude_v)?,
            diff_amplitude_v: v.finite("controls.diff_amplitude_v", c.diff_amplitude_v)?,
            diff_bias_v: v.finite("controls.diff_bias_v", c.diff_bias_v)?,
            diff_second_harmonic: v.within(
                "controls.diff_second_harmonic",
                c.diff_second_harmonic,
                -1.0,
                1.0,
            )?,
        };
        let init = &self.initial;
        let vec = |name: &str, a: [f64; 3], lim: f64| -> Result<Vector3<f64>> {
            for (i, x) in a.into_iter().enumerate() {
                v.within(&format!("initial.{name}[{i}]"), x, -lim, lim)?;
            }
            Ok(Vector3::new(a[0], a[1], a[2]))
        };
        let pos = vec("position_m", init.position_m, 1e4)?;
        let att = vec("attitude_deg", init.attitude_deg, 180.0)?;
        let vel = vec("velocity_m_s", init.velocity_m_s, 100.0)?;
        let rate = vec("angular_velocity_deg_s", init.angular_velocity_deg_s, 1e5)?;
        let make = |geometry: &wingforce::Geometry,
                    hinge_left: Vector3<f64>,
                    tilt: f64,
                    side: Side,
                    k: &Kinematics| {
            Wing::builder(geometry.clone(), k.clone())
                .mount(mount(hinge_left, tilt, side))
                .fluid(fluid)
                .options(aero.clone())
                .build()
        };
        let mut wings = vec![
            make(&geometry, hinge_left, tilt, Side::Left, &left_k),
            make(&geometry, hinge_left, tilt, Side::Right, &right_k),
        ];
        let mut base_kinematics = vec![left_k, right_k];
        let mut pair_control_gains = vec![1.0];
        for pair in pairs {
            pair_control_gains.push(pair.control_gain);
            let [kl, kr] = pair.kinematics;
            for (side, k) in [(Side::Left, kl), (Side::Right, kr)] {
                wings.push(make(&pair.geometry, pair.hinge_left, pair.tilt, side, &k));
                base_kinematics.push(k);
            }
        }
        let mut vehicle = Vehicle {
            name: self.name.clone(),
            mass_kg: mass,
            inertia_kg_m2: Matrix3::new(ixx, 0.0, -ixz, 0.0, iyy, 0.0, -ixz, 0.0, izz),
            length_m: length,
            body_drag_area_m2: drag_area,
            gravity_m_s2: g,
            wings,
            base_kinematics,
            pair_control_gains,
            controls,
            sim: sim.clone(),
            initial_position_m: pos,
            initial_attitude: UnitQuaternion::from_euler_angles(
                att.x.to_radians(),
                -att.y.to_radians(),
                att.z.to_radians(),
            ),
            initial_velocity_m_s: vel,
            initial_angular_velocity_rad_s: rate.map(f64::to_radians),
            mirror_symmetric: false,
            actuation: self
                .actuation
                .as_ref()
                .map(|a| a.build(&v, "actuation"))
                .transpose()?,
            trim_lift: self.trim.lift_variable,
            sensors: self.sensors.as_ref().map(|x| x.build(&v)).transpose()?,
            wind: match &self.wind {
                Some(w) => {
                    w.build(&v, "wind")?;
                    Some(w.clone())
                }
                None => None,
            },
        };
        if vehicle.actuation.is_some()
            && vehicle.trim_lift != crate::trim::spec::LiftVariable::Amplitude
        {
            return Err(v
                .invalid(
                    "trim.lift_variable",
                    vehicle.trim_lift.name(),
                    "`amplitude` for an actuated vehicle (it trims its drive amplitude)",
                )
                .into());
        }
        // The controlled kinematics must stay valid (checked before applying them, so the
        // error names the controls field rather than a wing).
        for i in 0..vehicle.wings.len() {
            let k = vehicle.controlled_kinematics(i, &controls);
            let side = Vehicle::wing_name(i);
            v.within_open_low(
                &format!("controls (resulting {side} stroke amplitude, deg)"),
                k.amplitude_rad.to_degrees(),
                0.0,
                180.0,
            )?;
            v.within_open_low(
                &format!("controls (resulting {side} frequency, Hz)"),
                k.freq_hz,
                0.0,
                1e5,
            )?;
        }
        vehicle.apply_controls(&controls)?;
        check_wings(&v, &vehicle.wings)?;
        Ok(vehicle)
    }
}

/// A validated further pair: its geometry, left hinge, stroke-plane tilt (rad) and the
/// kinematics of its left and right wings (with the phase offset).
struct BuiltPair {
    geometry: wingforce::Geometry,
    hinge_left: Vector3<f64>,
    tilt: f64,
    kinematics: [Kinematics; 2],
    control_gain: f64,
}

impl VehicleSpec {
    /// Validates `[[pairs]]` entry `p`: its fields are named `pairs[p].…` in errors.
    fn build_pair(
        &self,
        v: &Validator<'_>,
        p: usize,
        pair: &PairSpec,
        first_geometry: &wingforce::Geometry,
        first_kinematics: [&Kinematics; 2],
    ) -> Result<BuiltPair> {
        let field = format!("pairs[{p}]");
        let allowed = "the pair's wingbeat lead over the first pair, deg: a finite number in [-360, 360] (required; 180 = half a wingbeat)";
        let offset_deg = match pair.phase_offset_deg {
            None => {
                return Err(v
                    .invalid(&format!("{field}.phase_offset_deg"), "missing", allowed)
                    .into());
            }
            Some(x) if !(x.is_finite() && (-360.0..=360.0).contains(&x)) => {
                return Err(v
                    .invalid(&format!("{field}.phase_offset_deg"), x, allowed)
                    .into());
            }
            Some(x) => x,
        };
        let (hinge_left, tilt) = build_hinge(v, &format!("{field}.hinge"), &pair.hinge)?;
        let geometry = match &pair.wing {
            Some(w) => build_geometry(w, v, &format!("{field}.wing"), &self.aero)?,
            None => first_geometry.clone(),
        };
        let mut kinematics = match &pair.kinematics {
            Some(k) => {
                let k = k.build(v, &format!("{field}.kinematics"), geometry.r_gyration_m)?;
                [k.clone(), k]
            }
            None => [first_kinematics[0].clone(), first_kinematics[1].clone()],
        };
        let f0 = first_kinematics[0].freq_hz;
        if kinematics[0].freq_hz != f0 {
            return Err(v
                .invalid(
                    &format!("{field}.kinematics (frequency, Hz)"),
                    kinematics[0].freq_hz,
                    &format!(
                        "the first pair's frequency, {f0} Hz: all wings flap at one frequency"
                    ),
                )
                .into());
        }
        for k in &mut kinematics {
            k.phase_offset = offset_deg / 360.0;
        }
        let control_gain = match pair.control_gain {
            None => 1.0,
            Some(g) => v.within(&format!("{field}.control_gain"), g, -2.0, 2.0)?,
        };
        Ok(BuiltPair {
            geometry,
            hinge_left,
            tilt,
            kinematics,
            control_gain,
        })
    }
}

/// A `[hinge]` table validated: the left hinge in the body, m, and the stroke-plane tilt, rad.
fn build_hinge(v: &Validator<'_>, field: &str, h: &HingeSpec) -> Result<(Vector3<f64>, f64)> {
    let [hx, hy, hz] = h.left_in_body_m;
    for (i, x) in [hx, hy, hz].into_iter().enumerate() {
        v.within(&format!("{field}.left_in_body_m[{i}]"), x, -1.0, 1.0)?;
    }
    let tilt = v
        .within(
            &format!("{field}.stroke_plane_tilt_deg"),
            h.stroke_plane_tilt_deg,
            -90.0,
            90.0,
        )?
        .to_radians();
    Ok((Vector3::new(hx, hy, hz), tilt))
}

/// The mount of the `side` wing of a pair whose left hinge is `hinge_left` (the right one
/// mirrors it in y).
fn mount(hinge_left: Vector3<f64>, tilt: f64, side: Side) -> Mount {
    Mount {
        side,
        hinge_in_body_m: if side == Side::Left {
            hinge_left
        } else {
            Vector3::new(hinge_left.x, -hinge_left.y, hinge_left.z)
        },
        stroke_plane_tilt_rad: tilt,
    }
}

/// Rejects models whose derived quantities or forces are not finite (extreme but finite
/// inputs such as a 1e300 m span), naming the part of the model at fault.
pub(crate) fn check_wings(v: &Validator<'_>, wings: &[Wing]) -> Result<()> {
    for w in wings {
        wingforce::model::check_wing(v, w)?;
    }
    Ok(())
}
