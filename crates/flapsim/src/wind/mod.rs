//! Wind: steady wind, discrete 1 - cosine gusts and Dryden turbulence, evaluated at any world
//! point and time (each wing's hinge), deterministic for a seed.
//!
//! # The field
//!
//! The wind at a world point p and time t is
//! `steady + sum of gusts + u e_u + v e_v + w e_z`, with the turbulence (u, v, w) a frozen
//! field (Taylor's hypothesis) convected along the horizontal unit vector e_u at the speed
//! U_c: it depends on the single coordinate eta = U_c t - (p - p_0) . e_u, where p_0 is the
//! reference point (the vehicle's start). e_u is the horizontal direction of the steady wind
//! (world +x when it has none), e_v = e_z x e_u (lateral, horizontal), e_z world up. The
//! spectra, length scales and generation are MIL-F-8785C's Dryden forms ([`dryden`]); the
//! gusts ([`gust`]) are convected the same way.
//!
//! # Hover: the convection speed
//!
//! Dryden's spectra are spatial; a vehicle flying at airspeed V meets them at the time
//! frequency omega = V Omega. A hovering insect has V ~ 0, so the field is convected at
//! U_c = max(|steady horizontal wind|, `min_convection_speed_m_s`): the turbulence seen at a
//! point has the integral time scale L / U_c (first-order u: its correlation time). The
//! minimum (default 0.5 m/s, a typical indoor draft) therefore sets how fast still-air
//! turbulence changes; the vehicle's own motion moves it through the field on top (its
//! position enters eta), so a vehicle flying at V along e_u meets the field at V + U_c.
//!
//! # Per-wing wind and its limits
//!
//! Each wing sees the field at its hinge: [`crate::Simulation`] evaluates the wind at
//! body position + attitude * hinge_in_body_m and gives each wing its own air velocity
//! ([`crate::WingSet::set_wing_winds`]); the wind is uniform over one wing. The field is one
//! dimensional, as Dryden's model is: points displaced across the convection (e.g. the two
//! wings of a vehicle flying along e_u) see the same turbulence, points displaced along it
//! see it dx / U_c earlier or later. Real turbulence decorrelates across the span too; for
//! length scales of metres and a span of centimetres both effects are of order span / L
//! (about 1% of the gust velocity difference), which this model keeps only along e_u.
//!
//! # Scaling to an insect
//!
//! MIL-F-8785C's low-altitude model ([`dryden::DrydenParams::low_altitude`]) gives, at 1 m,
//! L_w = 1 m, L_u = L_v = 7.8 m and sigma_u = sigma_v = 2 sigma_w with sigma_w = 0.1 W20 (W20
//! the wind at 6 m); at 3 m, L_w = 3 m, L_u = L_v = 22.7 m. These fits were made above 10 ft
//! for aircraft; an insect's few metres are an extrapolation, and outdoors the length scales
//! are many body lengths, so turbulence acts as slowly varying wind. Indoors (a lab, a room)
//! the eddies are set by the room, the vents and the obstacles: choose L of the room's
//! smaller dimensions or the vent's size (0.2-1 m) and sigma from a measurement (hot-wire or
//! anemometer RMS; still rooms 0.02-0.05 m/s, ventilated ones 0.05-0.2 m/s), isotropic
//! (sigma_u = sigma_v = sigma_w, L_u = L_v = L_w) unless the flow has a direction.

pub mod dryden;
pub mod gust;

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};
use wingforce::Validator;

use crate::error::Result;
pub use dryden::{DrydenField, DrydenParams};
pub use gust::Gust;

/// `[wind]`: steady wind, turbulence and gusts.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WindSpec {
    /// Steady wind, world frame, m/s (the velocity of the air).
    #[serde(default)]
    pub steady_world_m_s: [f64; 3],
    /// Smallest speed at which turbulence and gusts given by length are convected past the
    /// vehicle, m/s (see the module documentation).
    #[serde(default = "default_min_convection")]
    pub min_convection_speed_m_s: f64,
    /// `[wind.turbulence]`: Dryden turbulence.
    #[serde(default)]
    pub turbulence: Option<TurbulenceSpec>,
    /// `[[wind.gusts]]`: 1 - cosine gusts.
    #[serde(default)]
    pub gusts: Vec<GustSpec>,
}

fn default_min_convection() -> f64 {
    0.5
}

impl Default for WindSpec {
    fn default() -> Self {
        Self {
            steady_world_m_s: [0.0; 3],
            min_convection_speed_m_s: default_min_convection(),
            turbulence: None,
            gusts: Vec::new(),
        }
    }
}

/// `[wind.turbulence]`: Dryden turbulence (MIL-F-8785C forms; see [`dryden`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TurbulenceSpec {
    /// RMS of the longitudinal, lateral and vertical components, m/s.
    pub intensity_m_s: [f64; 3],
    /// Length scales L_u, L_v, L_w, m: from [`MIN_LENGTH_SCALE_M`] (1 mm, the Kolmogorov
    /// microscale's order: Dryden's spectra end there) to 1e5.
    pub length_scale_m: [f64; 3],
    /// Seed of the random field: the same seed gives the same turbulence.
    #[serde(default)]
    pub seed: u64,
    /// Spacing of the generated samples along the convected coordinate, m (default the
    /// smallest length scale / 64; allowed 1e-4 to 1 times it, and at least
    /// [`MIN_SPACING_M`], 1e-5 m).
    #[serde(default)]
    pub sample_spacing_m: Option<f64>,
}

/// `[[wind.gusts]]`: one 1 - cosine gust (give `duration_s` or `length_m`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GustSpec {
    /// Peak speed, m/s.
    pub amplitude_m_s: f64,
    /// Direction the air moves, world frame (normalised).
    pub direction_world: [f64; 3],
    /// When the gust front reaches the vehicle's start point, s.
    pub start_s: f64,
    /// Duration, s.
    #[serde(default)]
    pub duration_s: Option<f64>,
    /// Length, m (duration = length / convection speed).
    #[serde(default)]
    pub length_m: Option<f64>,
}

/// A validated `[wind]`, SI units.
#[derive(Debug, Clone, PartialEq)]
pub struct WindParams {
    /// Steady wind, world, m/s.
    pub steady_world_m_s: Vector3<f64>,
    /// Convection direction e_u (horizontal, unit).
    pub convection_dir_world: Vector3<f64>,
    /// Convection speed U_c, m/s.
    pub convection_speed_m_s: f64,
    /// Turbulence: parameters, sample spacing (m) and seed.
    pub turbulence: Option<(DrydenParams, f64, u64)>,
    /// Gusts.
    pub gusts: Vec<Gust>,
}

const MAX_SPEED: f64 = 100.0;

/// The smallest Dryden length scale, m. Dryden's spectra describe the inertial range of
/// turbulence; eddies below the Kolmogorov microscale eta = (nu^3 / epsilon)^(1/4) are
/// damped by viscosity, and near the ground (nu = 1.5e-5 m^2/s, dissipation epsilon of
/// 1e-2 to 1e-1 m^2/s^3) eta is 0.4 to 0.8 mm. A length scale below 1 mm describes no air
/// (and with the default spacing L/64 a 1e-12 m scale asked for ~1e13 samples a metre).
pub const MIN_LENGTH_SCALE_M: f64 = 1e-3;

/// The finest sample spacing of the turbulence field, m: a run generates (convection speed
/// x duration) / spacing samples of 24 bytes, so 1e-5 m keeps a 1 s run at 1 m/s to 2.4 MB.
pub const MIN_SPACING_M: f64 = 1e-5;

impl WindSpec {
    /// Validates the table (`field` is its name in errors, e.g. `wind`).
    pub fn build(&self, v: &Validator<'_>, field: &str) -> Result<WindParams> {
        let steady = Vector3::from(checked3(
            &format!("{field}.steady_world_m_s"),
            self.steady_world_m_s,
            |f, x| v.within(f, x, -MAX_SPEED, MAX_SPEED),
        )?);
        let min_c = v.within_open_low(
            &format!("{field}.min_convection_speed_m_s"),
            self.min_convection_speed_m_s,
            0.0,
            MAX_SPEED,
        )?;
        let horizontal = Vector3::new(steady.x, steady.y, 0.0);
        let h = horizontal.norm();
        let dir = if h > 0.0 {
            horizontal / h
        } else {
            Vector3::x()
        };
        let u_c = h.max(min_c);
        let turbulence = match &self.turbulence {
            None => None,
            Some(t) => {
                let f = format!("{field}.turbulence");
                let p = DrydenParams {
                    sigma_m_s: checked3(&format!("{f}.intensity_m_s"), t.intensity_m_s, |f, x| {
                        v.within(f, x, 0.0, MAX_SPEED)
                    })?,
                    length_scale_m: checked3(
                        &format!("{f}.length_scale_m"),
                        t.length_scale_m,
                        |f, x| v.within(f, x, MIN_LENGTH_SCALE_M, 1e5),
                    )?,
                };
                let l_min = p
                    .length_scale_m
                    .iter()
                    .copied()
                    .fold(f64::INFINITY, f64::min);
                let spacing = match t.sample_spacing_m {
                    None => l_min / 64.0,
                    Some(h) => {
                        v.within_open_low(&format!("{f}.sample_spacing_m"), h, 0.0, l_min)?
                    }
                };
                // Finer spacings lose the reversed process's noise covariance to round-off
                // (its (1,1) entry is O((h/L)^3) of the stationary one), and below
                // MIN_SPACING_M the samples a run needs outgrow memory.
                if spacing < (l_min * 1e-4).max(MIN_SPACING_M) {
                    return Err(v
                        .invalid(
                            &format!("{f}.sample_spacing_m"),
                            spacing,
                            &format!(
                                "a spacing of at least 1e-4 of the smallest length scale ({l_min} m) and at least {MIN_SPACING_M} m"
                            ),
                        )
                        .into());
                }
                Some((p, spacing, t.seed))
            }
        };
        let mut gusts = Vec::with_capacity(self.gusts.len());
        for (i, g) in self.gusts.iter().enumerate() {
            let f = format!("{field}.gusts[{i}]");
            let amplitude_m_s = v.within(
                &format!("{f}.amplitude_m_s"),
                g.amplitude_m_s,
                0.0,
                MAX_SPEED,
            )?;
            let d = Vector3::from(checked3(
                &format!("{f}.direction_world"),
                g.direction_world,
                |f, x| v.finite(f, x),
            )?);
            let n = d.norm();
            if !(n > 0.0 && n.is_finite()) {
                return Err(v
                    .invalid(
                        &format!("{f}.direction_world"),
                        format!("{:?}", g.direction_world),
                        "a non-zero finite vector",
                    )
                    .into());
            }
            let start_s = v.within(&format!("{f}.start_s"), g.start_s, 0.0, 1e6)?;
            let duration_s = match (g.duration_s, g.length_m) {
                (Some(t), None) => v.within_open_low(&format!("{f}.duration_s"), t, 0.0, 1e6)?,
                (None, Some(l)) => v.within_open_low(&format!("{f}.length_m"), l, 0.0, 1e6)? / u_c,
                (a, b) => {
                    return Err(v
                        .invalid(
                            &f,
                            format!("duration_s = {a:?}, length_m = {b:?}"),
                            "exactly one of duration_s and length_m",
                        )
                        .into());
                }
            };
            gusts.push(Gust {
                amplitude_m_s,
                direction_world: d / n,
                start_s,
                duration_s,
            });
        }
        Ok(WindParams {
            steady_world_m_s: steady,
            convection_dir_world: dir,
            convection_speed_m_s: u_c,
            turbulence,
            gusts,
        })
    }
}

/// Each of three numbers checked under its name `field[i]`.
fn checked3(
    field: &str,
    x: [f64; 3],
    check: impl Fn(&str, f64) -> std::result::Result<f64, wingforce::Error>,
) -> Result<[f64; 3]> {
    let mut out = [0.0; 3];
    for (i, (o, x)) in out.iter_mut().zip(x).enumerate() {
        *o = check(&format!("{field}[{i}]"), x)?;
    }
    Ok(out)
}

impl WindParams {
    /// Rejects a gust that does not end within a run of `duration_s` (it would be cut off).
    pub fn check_run(&self, v: &Validator<'_>, field: &str, duration_s: f64) -> Result<()> {
        for (i, g) in self.gusts.iter().enumerate() {
            if g.end_s() > duration_s {
                return Err(v
                    .invalid(
                        &format!("{field}.gusts[{i}]"),
                        format!(
                            "start {} s + duration {} s = {} s",
                            g.start_s,
                            g.duration_s,
                            g.end_s()
                        ),
                        &format!("a gust that ends within the run ({duration_s} s)"),
                    )
                    .into());
            }
        }
        Ok(())
    }
}

/// The wind's parts at one point and time, world frame, m/s.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct WindSample {
    /// Steady wind.
    pub steady_m_s: Vector3<f64>,
    /// Sum of the gusts.
    pub gusts_m_s: Vector3<f64>,
    /// Turbulence.
    pub turbulence_m_s: Vector3<f64>,
}

impl WindSample {
    /// The air's velocity: the sum of the parts.
    pub fn total_m_s(&self) -> Vector3<f64> {
        self.steady_m_s + self.gusts_m_s + self.turbulence_m_s
    }
}

/// The wind field: see the module documentation.
#[derive(Debug, Clone)]
pub struct Wind {
    params: WindParams,
    reference_world_m: Vector3<f64>,
    lateral_dir_world: Vector3<f64>,
    field: Option<DrydenField>,
}

impl Wind {
    /// The field of validated parameters, with its reference point p_0 (world, m: where
    /// the turbulence's coordinate is zero at t = 0 and the gusts' times are counted).
    pub fn new(params: WindParams, reference_world_m: Vector3<f64>) -> Self {
        let field = params
            .turbulence
            .map(|(p, spacing, seed)| DrydenField::new(p, spacing, seed));
        let lateral_dir_world = Vector3::z().cross(&params.convection_dir_world);
        Self {
            params,
            reference_world_m,
            lateral_dir_world,
            field,
        }
    }

    /// A field from a `[wind]` table (errors name `origin` and the field).
    pub fn from_spec(
        spec: &WindSpec,
        origin: &str,
        reference_world_m: Vector3<f64>,
    ) -> Result<Self> {
        Ok(Self::new(
            spec.build(&Validator::new(origin), "wind")?,
            reference_world_m,
        ))
    }

    /// A steady, uniform wind (no turbulence, no gusts).
    pub fn steady(wind_world_m_s: Vector3<f64>) -> Self {
        let h = Vector3::new(wind_world_m_s.x, wind_world_m_s.y, 0.0);
        let n = h.norm();
        let params = WindParams {
            steady_world_m_s: wind_world_m_s,
            convection_dir_world: if n > 0.0 { h / n } else { Vector3::x() },
            convection_speed_m_s: n.max(default_min_convection()),
            turbulence: None,
            gusts: Vec::new(),
        };
        Self::new(params, Vector3::zeros())
    }

    /// The parameters.
    pub fn params(&self) -> &WindParams {
        &self.params
    }
    /// The turbulence field, if any.
    pub fn turbulence(&self) -> Option<&DrydenField> {
        self.field.as_ref()
    }

    /// The convected coordinate eta at a world point and time, m.
    pub fn eta_m(&self, point_world_m: &Vector3<f64>, t_s: f64) -> f64 {
        self.params.convection_speed_m_s * t_s
            - (point_world_m - self.reference_world_m).dot(&self.params.convection_dir_world)
    }

    /// The wind's parts at a world point and time.
    pub fn sample(&mut self, point_world_m: &Vector3<f64>, t_s: f64) -> WindSample {
        let eta = self.eta_m(point_world_m, t_s);
        let mut s = WindSample {
            steady_m_s: self.params.steady_world_m_s,
            ..WindSample::default()
        };
        if !self.params.gusts.is_empty() {
            // The time since the gust front passed the reference point, delayed by the
            // convection from it.
            let t_conv = eta / self.params.convection_speed_m_s;
            for g in &self.params.gusts {
                s.gusts_m_s += g.velocity_world_m_s(t_conv - g.start_s);
            }
        }
        if let Some(f) = &mut self.field {
            let [u, v, w] = f.at(eta);
            s.turbulence_m_s = u * self.params.convection_dir_world
                + v * self.lateral_dir_world
                + w * Vector3::z();
        }
        s
    }

    /// The air's velocity at a world point and time, world frame, m/s.
    pub fn velocity_world_m_s(&mut self, point_world_m: &Vector3<f64>, t_s: f64) -> Vector3<f64> {
        self.sample(point_world_m, t_s).total_m_s()
    }
}
