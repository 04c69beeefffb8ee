//! `flapwing wake-capture`: the paper's wake-capture regressions (eq 17-19) at one point, as
//! the raw formula gives them (Table 5) and as the simulator uses them (inputs clamped into
//! the fitted range).

use std::fmt::Write;

use serde::Serialize;
use wingforce::WakeCaptureModel;
use wingforce::coefficients::FitRange;

use crate::cli::WakeCaptureArgs;
use crate::output::{fmt_sig, print_json, print_stdout};

/// One regression input against its fitted range.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct InputReport {
    /// The value given.
    pub value: f64,
    /// Lower end of the fitted range.
    pub fitted_min: f64,
    /// Upper end of the fitted range.
    pub fitted_max: f64,
    /// True when `value` lies in the fitted range.
    pub inside: bool,
    /// The value the simulator uses: `value` moved to the nearest end of the range.
    pub clamped_value: f64,
}

impl InputReport {
    fn new(value: f64, range: FitRange) -> Self {
        Self {
            value,
            fitted_min: range.min,
            fitted_max: range.max,
            inside: range.contains(value),
            clamped_value: range.clamp(value),
        }
    }
}

/// The three regression inputs.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Inputs {
    /// Reynolds number, Re = V_ref c_bar / nu.
    pub re: InputReport,
    /// Acceleration fraction dtau_A (enters mu*).
    pub dtau_a: InputReport,
    /// Deceleration fraction dtau_D (enters dCL_bar and dCD_bar).
    pub dtau_d: InputReport,
}

/// The three regression outputs.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Outputs {
    /// Mean lift-coefficient increment over the first 0.1 T of a half stroke (eq 17).
    pub dcl_bar: f64,
    /// Mean drag-coefficient increment (eq 18).
    pub dcd_bar: f64,
    /// Non-dimensional time of the peak (eq 19, plus sign).
    pub mu_star: f64,
}

impl From<wingforce::WakeCaptureParams> for Outputs {
    fn from(p: wingforce::WakeCaptureParams) -> Self {
        Self {
            dcl_bar: p.dcl_bar,
            dcd_bar: p.dcd_bar,
            mu_star: p.mu_star,
        }
    }
}

/// A wake-capture model evaluated at one point: the JSON of this command, also embedded in
/// `flapwing forces --json`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Report {
    /// Where the model's coefficients come from.
    pub model: String,
    /// The inputs and their fitted ranges.
    pub inputs: Inputs,
    /// The raw formula at the given inputs (reproduces Table 5, even outside the range).
    pub raw: Outputs,
    /// The formula at the clamped inputs: what the simulator uses.
    pub clamped: Outputs,
    /// True when any input was outside its fitted range.
    pub any_clamped: bool,
}

impl Report {
    /// Evaluates `model` at the given inputs.
    pub fn new(model: &WakeCaptureModel, re: f64, dtau_a: f64, dtau_d: f64) -> Self {
        let clamped = model.clamped(re, dtau_a, dtau_d);
        Self {
            model: model.source.clone(),
            inputs: Inputs {
                re: InputReport::new(re, model.re_range),
                dtau_a: InputReport::new(dtau_a, model.dtau_a_range),
                dtau_d: InputReport::new(dtau_d, model.dtau_d_range),
            },
            raw: model.raw(re, dtau_a, dtau_d).into(),
            clamped: clamped.into(),
            any_clamped: clamped.flags.any(),
        }
    }

    /// The inputs with their report names.
    pub fn named_inputs(&self) -> [(&'static str, &InputReport); 3] {
        [
            ("Re", &self.inputs.re),
            ("dtau_A", &self.inputs.dtau_a),
            ("dtau_D", &self.inputs.dtau_d),
        ]
    }

    /// The inputs that were clamped, as `name value -> clamped (fitted min-max)`.
    pub fn clamped_inputs(&self) -> Vec<String> {
        self.named_inputs()
            .into_iter()
            .filter(|(_, i)| !i.inside)
            .map(|(name, i)| {
                format!(
                    "{name} {} -> {} (fitted {}-{})",
                    fmt_sig(i.value, 6),
                    i.clamped_value,
                    i.fitted_min,
                    i.fitted_max
                )
            })
            .collect()
    }

    /// The text report: an input table and the raw and clamped outputs.
    pub fn write_text(&self, out: &mut String) -> std::fmt::Result {
        writeln!(
            out,
            "{:<9} {:>10}  {:>15}  {:<6}  {:>10}",
            "input", "value", "fitted range", "inside", "clamped to"
        )?;
        for (name, i) in self.named_inputs() {
            let range = format!("[{}, {}]", i.fitted_min, i.fitted_max);
            let inside = if i.inside { "yes" } else { "NO" };
            writeln!(
                out,
                "{name:<9} {:>10}  {range:>15}  {inside:<6}  {:>10}",
                fmt_sig(i.value, 6),
                fmt_sig(i.clamped_value, 6)
            )?;
        }
        writeln!(out)?;
        writeln!(
            out,
            "{:<9} {:>12}  {:>12}",
            "output", "raw formula", "clamped"
        )?;
        for (name, raw, used) in [
            ("dCL_bar", self.raw.dcl_bar, self.clamped.dcl_bar),
            ("dCD_bar", self.raw.dcd_bar, self.clamped.dcd_bar),
            ("mu*", self.raw.mu_star, self.clamped.mu_star),
        ] {
            writeln!(out, "{name:<9} {raw:>12.5}  {used:>12.5}")?;
        }
        Ok(())
    }
}

/// Runs the command.
pub fn run(args: WakeCaptureArgs) -> anyhow::Result<()> {
    // The flags were checked by clap (finite, Re > 0, dtau in (0, 0.5)).
    let report = Report::new(
        &WakeCaptureModel::paper(),
        args.re,
        args.dtau_a,
        args.dtau_d,
    );
    if args.json {
        return print_json(&report);
    }
    let mut text = String::new();
    writeln!(text, "wake capture: {}", report.model)?;
    writeln!(
        text,
        "Re = V_ref c_bar / nu (V_ref: peak stroke speed at R_g)"
    )?;
    writeln!(text)?;
    report.write_text(&mut text)?;
    writeln!(text)?;
    if report.any_clamped {
        writeln!(
            text,
            "outside the fitted range: {}; the simulator uses the clamped column",
            report.clamped_inputs().join(", ")
        )?;
    } else {
        writeln!(text, "all inputs inside the fitted range: raw = clamped")?;
    }
    print_stdout(&text)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn v2_row_is_clamped_on_dtau_d_only() {
        // Table 5 row V2: Re 408, dtau_A 0.12, dtau_D 0.03 (below the fitted 0.06).
        let r = Report::new(&WakeCaptureModel::paper(), 408.0, 0.12, 0.03);
        assert!(r.any_clamped);
        assert!(r.inputs.re.inside && r.inputs.dtau_a.inside && !r.inputs.dtau_d.inside);
        assert_eq!(r.inputs.dtau_d.clamped_value, 0.06);
        assert!((r.raw.dcl_bar - 0.65305).abs() < 5e-6);
        assert_eq!(r.raw.mu_star, r.clamped.mu_star);
        assert_ne!(r.raw.dcl_bar, r.clamped.dcl_bar);
        assert_eq!(
            r.clamped_inputs(),
            ["dtau_D 0.03 -> 0.06 (fitted 0.06-0.18)"]
        );
    }
}
