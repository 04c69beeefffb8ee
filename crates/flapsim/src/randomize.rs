//! Domain randomisation: per-episode draws of a vehicle model's parameters within ranges
//! given in a file. Each entry names a numeric field of the model file by its dotted path
//! (`body.mass_kg`, `wing.planform.span_m`, `hinge.left_in_body_m`,
//! `actuation.hinge.stiffness_nm_rad`, `sensors.imu.gyro_noise_density_deg_s_sqrt_hz`, ...)
//! and a range of scale factors; a draw multiplies the field (every element of an array) by
//! a factor uniform in the range. The drawn factors are returned so that runs log them.
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

fn scale(v: &mut toml::Value, k: f64) -> bool {
    match v {
        toml::Value::Float(x) => {
            *x *= k;
            true
        }
        toml::Value::Integer(i) => {
            *v = toml::Value::Float(*i as f64 * k);
            true
        }
        toml::Value::Array(a) => a.iter_mut().all(|x| scale(x, k)),
        _ => false,
    }
}

impl Randomization {
    /// Parses a randomisation file (`origin` names it in errors) and checks the ranges.
    pub fn from_toml(text: &str, origin: &str) -> Result<Self> {
        let r: Self = wingforce::model::parse_toml(text, origin)?;
        let v = wingforce::Validator::new(origin);
        for (i, p) in r.param.iter().enumerate() {
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

    /// Checks that every path names a numeric field of the model `text`.
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
        for p in &self.param {
            let [lo, hi] = p.scale;
            let k = lo + (hi - lo) * rng.uniform();
            let ok = find(&mut t, &p.path).is_some_and(|v| scale(v, k));
            if !ok {
                return Err(Error::Analysis(format!(
                    "randomisation: `{}` is not a numeric field of the model {origin}",
                    p.path
                )));
            }
            draws.push((p.path.clone(), k));
        }
        Ok((toml::to_string(&t).unwrap_or_default(), draws))
    }
}
