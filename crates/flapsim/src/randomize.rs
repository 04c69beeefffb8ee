//! Domain randomisation: per-episode draws of a vehicle model's parameters within ranges
//! given in a file. Each entry names a numeric field of the model file by its dotted path
//! (`body.mass_kg`, `wing.planform.span_m`, `hinge.left_in_body_m`,
//! `actuation.hinge.stiffness_nm_rad`, `sensors.imu.gyro_noise_density_deg_s_sqrt_hz`, ...)
//! and a range of scale factors; a draw multiplies the field (every element of an array) by
//! a factor uniform in the range. The drawn factors are returned so that runs log them
//! (the tasks' `draws`, the Gymnasium environments' `info["draws"]`).
//!
//! Every real-valued field of the model file can be named, scalar or array; integer fields
//! (such as `sim.steps_per_wingbeat`), strings, booleans and tables are refused, and so are a
//! path named twice and a range outside 0 < low <= high. Errors name the randomisation
//! file, the entry's field, its value and what is allowed.
//!
//! ```toml
//! [[param]]
//! path = "body.mass_kg"
//! scale = [0.9, 1.1]
//! ```

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::sensors::Noise;

/// One randomised field.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Param {
    /// Dotted path of a numeric field (or array of numbers) in the model file.
    pub path: String,
    /// Lowest and highest scale factor.
    pub scale: [f64; 2],
}

/// A randomisation file: `[[param]]` entries.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Randomization {
    /// The randomised fields.
    pub param: Vec<Param>,
    /// Where the file came from (named in errors).
    #[serde(skip)]
    pub origin: String,
}

fn find<'a>(t: &'a mut toml::Table, path: &str) -> Option<&'a mut toml::Value> {
    let mut parts = path.split('.');
    let first = parts.next()?;
    let mut v = t.get_mut(first)?;
    for p in parts {
        v = v.as_table_mut()?.get_mut(p)?;
    }
    Some(v)
}

/// Whether `v` is a real number or a non-empty array of them, and if not, what it is.
fn real_valued(v: &toml::Value) -> std::result::Result<(), &'static str> {
    match v {
        toml::Value::Float(_) => Ok(()),
        toml::Value::Integer(_) => Err("an integer field"),
        toml::Value::Array(a) if a.is_empty() => Err("an empty array"),
        toml::Value::Array(a) => a.iter().try_for_each(real_valued),
        toml::Value::Table(_) => Err("a table"),
        _ => Err("not a number"),
    }
}

fn scale(v: &mut toml::Value, k: f64) {
    match v {
        toml::Value::Float(x) => *x *= k,
        toml::Value::Array(a) => a.iter_mut().for_each(|x| scale(x, k)),
        _ => {}
    }
}

impl Randomization {
    /// Parses a randomisation file (`origin` names it in errors) and checks the ranges.
    pub fn from_toml(text: &str, origin: &str) -> Result<Self> {
        let mut r: Self = wingforce::model::parse_toml(text, origin)?;
        r.origin = origin.to_owned();
        let v = wingforce::Validator::new(origin);
        for (i, p) in r.param.iter().enumerate() {
            if r.param[..i].iter().any(|q| q.path == p.path) {
                return Err(v
                    .invalid(
                        &format!("param[{i}].path"),
                        format!("\"{}\"", p.path),
                        "a field not named by an earlier entry (each field is drawn once)",
                    )
                    .into());
            }
            let [lo, hi] = p.scale;
            v.positive(&format!("param[{i}].scale[0] ({})", p.path), lo)?;
            if !(hi.is_finite() && hi >= lo) {
                return Err(v
                    .invalid(
                        &format!("param[{i}].scale ({})", p.path),
                        format!("[{lo}, {hi}]"),
                        "[low, high] with 0 < low <= high",
                    )
                    .into());
            }
        }
        Ok(r)
    }

    /// Checks that every path names a real-valued field of the model `text`.
    pub fn check(&self, text: &str, origin: &str) -> Result<()> {
        let mut rng = Noise::new(0);
        self.draw(text, origin, &mut rng).map(|_| ())
    }

    /// The model `text` with every field scaled by a factor drawn from `rng`, and the
    /// factors (path, factor).
    pub fn draw(
        &self,
        text: &str,
        origin: &str,
        rng: &mut Noise,
    ) -> Result<(String, Vec<(String, f64)>)> {
        let mut t: toml::Table = text.parse().map_err(|e: toml::de::Error| {
            Error::Model(wingforce::Error::Parse {
                origin: origin.to_owned(),
                message: e.to_string(),
            })
        })?;
        let mut draws = Vec::with_capacity(self.param.len());
        let v = wingforce::Validator::new(&self.origin);
        for (i, p) in self.param.iter().enumerate() {
            let [lo, hi] = p.scale;
            let k = lo + (hi - lo) * rng.uniform();
            let refused = match find(&mut t, &p.path) {
                Some(x) => real_valued(x).map(|()| scale(x, k)).err(),
                None => Some("no such field"),
            };
            if let Some(why) = refused {
                return Err(v
                    .invalid(
                        &format!("param[{i}].path"),
                        format!("\"{}\" ({why} in {origin})", p.path),
                        &format!(
                            "the dotted path of a real-valued field (a number or an array of numbers) of the model {origin}, e.g. \"body.mass_kg\""
                        ),
                    )
                    .into());
            }
            draws.push((p.path.clone(), k));
        }
        Ok((toml::to_string(&t).unwrap_or_default(), draws))
    }
}
