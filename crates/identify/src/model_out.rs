//! Writing the fitted model: the data's model file with each fitted model parameter's value
//! replaced, edited in place (toml_edit keeps every other line and comment), each changed
//! key preceded by a comment naming the fit, the value before it and its interval, and a
//! header saying where the file came from. Measurement parameters (sensor biases) are not
//! model numbers and are left out (the header lists them).

use toml_edit::{DocumentMut, Item, Table, Value};

use crate::error::{Error, Result};
use crate::fit::FitReport;
use crate::params::Param;

/// The table at the dotted path `name` (e.g. `actuation.hinge`), made where missing.
fn table<'d>(doc: &'d mut DocumentMut, name: &str) -> Result<&'d mut Table> {
    let not_table = || Error::Model(format!("`{name}` in the model file is not a table"));
    let mut t = doc.as_table_mut();
    for part in name.split('.') {
        if t.get(part).is_none() {
            let mut sub = Table::new();
            sub.set_implicit(true);
            t.insert(part, Item::Table(sub));
        }
        t = t
            .get_mut(part)
            .and_then(Item::as_table_mut)
            .ok_or_else(not_table)?;
    }
    Ok(t)
}

fn set_comment(t: &mut Table, key: &str, comment: &str) {
    if let Some(mut k) = t.key_mut(key) {
        let old = k
            .leaf_decor()
            .prefix()
            .and_then(|p| p.as_str())
            .unwrap_or("")
            .to_owned();
        k.leaf_decor_mut().set_prefix(format!("{old}{comment}"));
    }
}

/// Replaces `key` (or element `index` of the array `key`) of table `t` with `value`,
/// keeping the value's own decoration (its source comment).
fn set_number(t: &mut Table, key: &str, index: Option<usize>, value: f64) -> Result<()> {
    match index {
        None => {
            let decor = t
                .get(key)
                .and_then(Item::as_value)
                .map(|v| v.decor().clone());
            let mut v = Value::from(value);
            if let Some(d) = decor {
                *v.decor_mut() = d;
            }
            t.insert(key, Item::Value(v));
        }
        Some(i) => {
            let arr = t
                .get_mut(key)
                .and_then(Item::as_array_mut)
                .filter(|a| a.len() > i)
                .ok_or_else(|| {
                    Error::Model(format!(
                        "`{key}` in the model file is not an array of {} numbers",
                        i + 1
                    ))
                })?;
            let decor = arr.get(i).map(|v| v.decor().clone());
            let mut v = Value::from(value);
            if let Some(d) = decor {
                *v.decor_mut() = d;
            }
            arr.replace(i, v);
        }
    }
    Ok(())
}

/// The model text of `model_toml` with the fitted values of `report`'s model parameters;
/// `log` names the data in the comments.
pub fn fitted_model_toml(model_toml: &str, report: &FitReport, command: &str) -> Result<String> {
    let mut doc: DocumentMut = model_toml
        .parse()
        .map_err(|e| Error::Model(format!("the model text does not parse as TOML: {e}")))?;
    let spec = flapsim::VehicleSpec::from_toml(model_toml, "model")
        .map_err(|e| Error::Model(e.to_string()))?;
    let fit_name = format!(
        "`{command}` on {} ({} segments, chi-square {:.4e} -> {:.4e}, {})",
        report.source, report.segments, report.cost_before, report.cost_after, report.termination
    );
    let mut skipped = Vec::new();
    for p in &report.params {
        let param = Param::parse(&p.name)?;
        let note = |field: &str, written: String| {
            format!(
                "# FITTED {field} by {fit_name}: {} = {:.6e} +- {:.3e} (95 % CI [{:.6e}, {:.6e}]{}), was {:.6e}; the comment after the value gives the source of the value before the fit\n",
                p.name,
                p.fitted,
                p.std_error,
                p.ci95[0],
                p.ci95[1],
                if p.identifiable {
                    ""
                } else {
                    ", NOT IDENTIFIABLE"
                },
                p.start
            ) + &written
        };
        match param {
            Param::InertiaXx | Param::InertiaYy | Param::InertiaZz => {
                let i = match param {
                    Param::InertiaXx => 0,
                    Param::InertiaYy => 1,
                    _ => 2,
                };
                let t = table(&mut doc, "body")?;
                set_number(t, "inertia_diag_kg_m2", Some(i), p.fitted)?;
                set_comment(
                    t,
                    "inertia_diag_kg_m2",
                    &note(&format!("body.inertia_diag_kg_m2[{i}]"), String::new()),
                );
            }
            Param::Mass
            | Param::AirDensity
            | Param::RotationalCoefficient
            | Param::HingeStiffness
            | Param::HingeDamping
            | Param::StrokeStiffness
            | Param::ForcePerVolt
            | Param::TorqueConstant
            | Param::WingStrokeInertia
            | Param::StopRestitution => {
                let field = param.model_field().unwrap_or_default();
                let (path, key) = field.rsplit_once('.').unwrap_or(("", field));
                let mut extra = String::new();
                if param == Param::TorqueConstant
                    && let Some(m) = spec.actuation.as_ref().and_then(|a| a.dc_motor)
                {
                    let ke = crate::params::back_emf_scaled(&m, p.fitted);
                    set_number(table(&mut doc, path)?, "back_emf_v_s_rad", None, ke)?;
                    extra = format!(
                        "# (back_emf_v_s_rad scaled with it to {ke:.6e} V s/rad: equal in SI for an ideal DC motor)\n"
                    );
                }
                let t = table(&mut doc, path)?;
                set_number(t, key, None, p.fitted)?;
                set_comment(t, key, &note(field, extra));
            }
            Param::StrokePlaneTilt => {
                let t = table(&mut doc, "hinge")?;
                let deg = p.fitted.to_degrees();
                set_number(t, "stroke_plane_tilt_deg", None, deg)?;
                set_comment(
                    t,
                    "stroke_plane_tilt_deg",
                    &note(
                        "hinge.stroke_plane_tilt_deg",
                        format!("# (written in degrees: {deg:.6} deg)\n"),
                    ),
                );
            }
            Param::ComOffsetX | Param::ComOffsetZ => {
                let i = if param == Param::ComOffsetX { 0 } else { 2 };
                let h = spec.hinge.left_in_body_m[i] - p.fitted;
                let t = table(&mut doc, "hinge")?;
                set_number(t, "left_in_body_m", Some(i), h)?;
                set_comment(
                    t,
                    "left_in_body_m",
                    &note(
                        &format!("hinge.left_in_body_m[{i}]"),
                        format!(
                            "# (the centre of mass moved by {:.6e} m, so the hinge, relative to it, by minus that: {h:.6e} m)\n",
                            p.fitted
                        ),
                    ),
                );
            }
            Param::MocapBias(_) | Param::GyroBias(_) | Param::AccelBias(_) => {
                skipped.push(format!(
                    "{} = {:.6e} +- {:.3e}",
                    p.name, p.fitted, p.std_error
                ));
            }
        }
    }
    let mut header = format!(
        "# Fitted model written by {fit_name}.\n# The keys marked FITTED below hold fitted values; every other number is the original model's ({}), with its source.\n",
        report.model
    );
    if !skipped.is_empty() {
        header.push_str(&format!(
            "# Measurement parameters fitted too (not model numbers, not written): {}\n",
            skipped.join("; ")
        ));
    }
    let text = format!("{header}{doc}");
    // The written model must load.
    flapsim::Vehicle::from_toml(&text, "fitted model")
        .map_err(|e| Error::Model(format!("the fitted model does not load: {e}")))?;
    Ok(text)
}
