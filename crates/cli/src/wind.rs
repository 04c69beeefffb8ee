//! The wind flags of `simulate` and `hover`: steady wind, Dryden turbulence and 1 - cosine
//! gusts on top of (or instead of) the model's `[wind]` (flapsim::wind).

use flapsim::wind::{GustSpec, TurbulenceSpec, Wind, WindSpec};
use nalgebra::Vector3;

use crate::error::input_error;

/// Length scale of flag-given turbulence when neither the flag nor the model gives one, m
/// (a room's eddies: see flapsim's wind documentation).
const DEFAULT_LENGTH_SCALE_M: f64 = 1.0;

/// Wind flags shared by the commands that fly a vehicle.
#[derive(Debug, Clone, Default, clap::Args)]
pub struct WindArgs {
    /// Steady wind, world frame, m/s: X,Y,Z (replaces the model's `[wind]` steady wind).
    #[arg(
        long = "wind-world-m-s",
        value_name = "X,Y,Z",
        allow_hyphen_values = true
    )]
    pub wind_world_m_s: Option<String>,
    /// Dryden turbulence RMS, m/s: one value for u, v and w, or U,V,W (replaces the model's).
    #[arg(
        long = "turbulence-intensity-m-s",
        value_name = "S|U,V,W",
        allow_hyphen_values = true
    )]
    pub turbulence_intensity_m_s: Option<String>,
    /// Dryden length scales, m: one value or LU,LV,LW (default the model's, else 1 m).
    #[arg(long = "turbulence-length-scale-m", value_name = "L|LU,LV,LW")]
    pub turbulence_length_scale_m: Option<String>,
    /// Seed of the turbulence (the same seed gives the same wind). Default the model's, else 0.
    #[arg(long = "wind-seed", value_name = "N")]
    pub wind_seed: Option<u64>,
    /// A 1 - cosine gust, repeatable: amplitude_m_s=A,direction=X:Y:Z,start_s=T0 and
    /// duration_s=T or length_m=L (added to the model's gusts).
    #[arg(long = "gust", value_name = "KEY=VALUE,...")]
    pub gust: Vec<String>,
    /// Still air: ignore the model's `[wind]`.
    #[arg(long = "no-wind", conflicts_with_all = ["wind_world_m_s", "turbulence_intensity_m_s", "turbulence_length_scale_m", "wind_seed", "gust"])]
    pub no_wind: bool,
}

fn numbers(
    flag: &str,
    s: &str,
    min_ok: impl Fn(f64) -> bool,
    allowed: &str,
) -> anyhow::Result<Vec<f64>> {
    s.split(',')
        .map(|p| {
            p.trim()
                .parse::<f64>()
                .ok()
                .filter(|x| x.is_finite() && min_ok(*x))
                .ok_or_else(|| {
                    input_error(format!(
                        "{flag} `{s}`: `{}` is not allowed: {allowed}",
                        p.trim()
                    ))
                })
        })
        .collect()
}

/// One value for all three components, or three.
fn triple(
    flag: &str,
    s: &str,
    min_ok: impl Fn(f64) -> bool,
    allowed: &str,
) -> anyhow::Result<[f64; 3]> {
    match numbers(flag, s, min_ok, allowed)?.as_slice() {
        [x] => Ok([*x; 3]),
        [x, y, z] => Ok([*x, *y, *z]),
        other => Err(input_error(format!(
            "{flag} `{s}`: {} values; allowed: one value or three (comma-separated)",
            other.len()
        ))),
    }
}

/// Parses one `--gust`.
pub fn parse_gust(s: &str) -> anyhow::Result<GustSpec> {
    let mut g = GustSpec {
        amplitude_m_s: f64::NAN,
        direction_world: [f64::NAN; 3],
        start_s: 0.0,
        duration_s: None,
        length_m: None,
    };
    let keys = "amplitude_m_s, direction (X:Y:Z), start_s, duration_s, length_m";
    for part in s.split(',').map(str::trim).filter(|p| !p.is_empty()) {
        let (k, v) = part
            .split_once('=')
            .ok_or_else(|| input_error(format!("--gust `{s}`: `{part}` is not key=value")))?;
        let num = |v: &str| -> anyhow::Result<f64> {
            v.trim()
                .parse::<f64>()
                .ok()
                .filter(|x| x.is_finite())
                .ok_or_else(|| {
                    input_error(format!("--gust `{s}`: {k} = `{v}` is not a finite number"))
                })
        };
        match k.trim() {
            "amplitude_m_s" => g.amplitude_m_s = num(v)?,
            "start_s" => g.start_s = num(v)?,
            "duration_s" => g.duration_s = Some(num(v)?),
            "length_m" => g.length_m = Some(num(v)?),
            "direction" => {
                let d: Vec<f64> = v.split(':').map(num).collect::<anyhow::Result<_>>()?;
                g.direction_world = d.try_into().map_err(|d: Vec<f64>| {
                    input_error(format!(
                        "--gust `{s}`: direction has {} components; allowed: X:Y:Z",
                        d.len()
                    ))
                })?;
            }
            other => {
                return Err(input_error(format!(
                    "--gust `{s}`: unknown key `{other}`; allowed: {keys}"
                )));
            }
        }
    }
    if g.amplitude_m_s.is_nan() || g.direction_world[0].is_nan() {
        return Err(input_error(format!(
            "--gust `{s}`: amplitude_m_s and direction are required; keys: {keys}"
        )));
    }
    Ok(g)
}

/// The run's `[wind]`: the model's, changed by the flags (`None`: still air).
pub fn spec(args: &WindArgs, vehicle: &flapsim::Vehicle) -> anyhow::Result<Option<WindSpec>> {
    if args.no_wind {
        return Ok(None);
    }
    let flags = args.wind_world_m_s.is_some()
        || args.turbulence_intensity_m_s.is_some()
        || args.turbulence_length_scale_m.is_some()
        || args.wind_seed.is_some()
        || !args.gust.is_empty();
    if !flags {
        return Ok(vehicle.wind.clone());
    }
    let mut w = vehicle.wind.clone().unwrap_or_default();
    if let Some(s) = &args.wind_world_m_s {
        w.steady_world_m_s =
            match numbers("--wind-world-m-s", s, |_| true, "a finite number")?.as_slice() {
                [x, y, z] => [*x, *y, *z],
                other => {
                    return Err(input_error(format!(
                        "--wind-world-m-s `{s}`: {} values; allowed: X,Y,Z",
                        other.len()
                    )));
                }
            };
    }
    let sigma = args
        .turbulence_intensity_m_s
        .as_deref()
        .map(|s| {
            triple(
                "--turbulence-intensity-m-s",
                s,
                |x| x >= 0.0,
                "a finite RMS >= 0 m/s",
            )
        })
        .transpose()?;
    let length = args
        .turbulence_length_scale_m
        .as_deref()
        .map(|s| {
            triple(
                "--turbulence-length-scale-m",
                s,
                |x| x > 0.0,
                "a finite length > 0 m",
            )
        })
        .transpose()?;
    if let Some(t) = &mut w.turbulence {
        if let Some(s) = sigma {
            t.intensity_m_s = s;
        }
        if let Some(l) = length {
            t.length_scale_m = l;
            t.sample_spacing_m = None;
        }
        if let Some(seed) = args.wind_seed {
            t.seed = seed;
        }
    } else if let Some(s) = sigma {
        w.turbulence = Some(TurbulenceSpec {
            intensity_m_s: s,
            length_scale_m: length.unwrap_or([DEFAULT_LENGTH_SCALE_M; 3]),
            seed: args.wind_seed.unwrap_or(0),
            sample_spacing_m: None,
        });
    } else if length.is_some() || args.wind_seed.is_some() {
        return Err(input_error(
            "--turbulence-length-scale-m and --wind-seed need turbulence: give --turbulence-intensity-m-s (or a model with [wind.turbulence])",
        ));
    }
    for g in &args.gust {
        w.gusts.push(parse_gust(g)?);
    }
    Ok(Some(w))
}

/// The run's wind field (reference point the vehicle's start), checked against the run's
/// duration (a gust must end within it).
pub fn start(
    args: &WindArgs,
    vehicle: &flapsim::Vehicle,
    origin: &str,
    duration_s: f64,
) -> anyhow::Result<Option<Wind>> {
    let Some(spec) = spec(args, vehicle)? else {
        return Ok(None);
    };
    let origin = format!("{origin} with the wind flags");
    let v = wingforce::Validator::new(&origin);
    let params = spec.build(&v, "wind").map_err(crate::vehicle::sim_error)?;
    params
        .check_run(&v, "wind", duration_s)
        .map_err(crate::vehicle::sim_error)?;
    Ok(Some(Wind::new(params, vehicle.initial_position_m)))
}

/// A one-line description of the run's wind for the text reports.
pub fn describe(w: &Wind) -> String {
    let p = w.params();
    let s: Vector3<f64> = p.steady_world_m_s;
    let mut d = format!("wind: steady [{:.3}, {:.3}, {:.3}] m/s", s.x, s.y, s.z);
    if let Some((t, _, seed)) = &p.turbulence {
        d += &format!(
            ", Dryden turbulence sigma u,v,w [{:.3}, {:.3}, {:.3}] m/s, L [{:.3}, {:.3}, {:.3}] m, seed {seed}, convected at {:.3} m/s",
            t.sigma_m_s[0],
            t.sigma_m_s[1],
            t.sigma_m_s[2],
            t.length_scale_m[0],
            t.length_scale_m[1],
            t.length_scale_m[2],
            p.convection_speed_m_s
        );
    }
    if !p.gusts.is_empty() {
        d += &format!(", {} 1-cosine gust(s)", p.gusts.len());
    }
    d
}
