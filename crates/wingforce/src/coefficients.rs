//! Force-coefficient models: translational (Lee et al. 2016 or Dickinson et al. 1999) and the
//! seed paper's wake-capture regression (eq 17-19, 23-24).

use serde::{Deserialize, Serialize};

/// Lee et al. (2016) translational coefficients at Reynolds number `re`, eq 3-4 of the seed
/// paper: returns (K_l, C_d0, K_d) so that C_l = K_l sin 2 alpha and
/// C_d = C_d0 + K_d (1 - cos 2 alpha).
// 3.14 is the paper's fitted coefficient of K_d, not an approximation of pi.
#[allow(clippy::approx_constant)]
pub fn lee2016_factors(re: f64) -> (f64, f64, f64) {
    (
        1.966 - 3.95 * re.powf(-0.429),
        0.031 + 10.48 * re.powf(-0.764),
        1.873 - 3.14 * re.powf(-0.369),
    )
}

/// Lee et al. (2016) C_l(alpha) and C_d(alpha) (alpha in rad), eq 3-4.
pub fn lee2016(alpha_rad: f64, re: f64) -> (f64, f64) {
    let (kl, cd0, kd) = lee2016_factors(re);
    (
        kl * (2.0 * alpha_rad).sin(),
        cd0 + kd * (1.0 - (2.0 * alpha_rad).cos()),
    )
}

/// Aspect-ratio correction f_AR = 32.9 - 32.0 AR^-0.00361 (eq 5).
pub fn f_ar(aspect_ratio: f64) -> f64 {
    32.9 - 32.0 * aspect_ratio.powf(-0.00361)
}

/// Rossby-number correction f_Ro = -0.205 atan(0.587 (Ro - 3.105)) + 0.870 (eq 6).
pub fn f_ro(rossby: f64) -> f64 {
    -0.205 * (0.587 * (rossby - 3.105)).atan() + 0.870
}

/// Dickinson, Lehmann and Sane (1999) robofly fits, alpha in degrees (0 to 90):
/// C_L = 0.225 + 1.58 sin(2.13 alpha - 7.2), C_D = 1.92 - 1.55 cos(2.04 alpha - 9.82).
pub fn dickinson1999_deg(alpha_deg: f64) -> (f64, f64) {
    (
        0.225 + 1.58 * (2.13 * alpha_deg - 7.2).to_radians().sin(),
        1.92 - 1.55 * (2.04 * alpha_deg - 9.82).to_radians().cos(),
    )
}

/// Which translational model a wing uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum TranslationalModel {
    /// Lee et al. 2016 (the seed paper's eq 3-6), Reynolds-number dependent.
    #[default]
    Lee2016,
    /// Dickinson et al. 1999 robofly fits (Re about 100-200), independent of Re.
    Dickinson1999,
}

/// `c0 + c1 exp(c2 Re) + c3 dtau_D + c4 dtau_D^2`: the form of eq 17 and 18.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ExpQuadratic {
    /// Constant.
    pub c0: f64,
    /// Coefficient of the exponential.
    pub c1: f64,
    /// Rate of the exponential in Re.
    pub c2: f64,
    /// Linear coefficient of dtau_D.
    pub c3: f64,
    /// Quadratic coefficient of dtau_D.
    pub c4: f64,
}

impl ExpQuadratic {
    /// Evaluates the form.
    pub fn eval(&self, re: f64, dtau_d: f64) -> f64 {
        self.c0 + self.c1 * (self.c2 * re).exp() + self.c3 * dtau_d + self.c4 * dtau_d * dtau_d
    }
}

/// `m0 + m1 ln Re + m2 dtau_A`: the form of eq 19.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LinearLn {
    /// Constant.
    pub m0: f64,
    /// Coefficient of ln Re.
    pub m1: f64,
    /// Coefficient of dtau_A.
    pub m2: f64,
}

impl LinearLn {
    /// Evaluates the form.
    pub fn eval(&self, re: f64, dtau_a: f64) -> f64 {
        self.m0 + self.m1 * re.ln() + self.m2 * dtau_a
    }
}

/// The closed range a regression was fitted on.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FitRange {
    /// Lower end.
    pub min: f64,
    /// Upper end.
    pub max: f64,
}

impl FitRange {
    /// True when `x` is inside the range.
    pub fn contains(&self, x: f64) -> bool {
        x >= self.min && x <= self.max
    }
    /// `x` moved to the nearest end when outside.
    pub fn clamp(&self, x: f64) -> f64 {
        x.clamp(self.min, self.max)
    }
}

/// A wake-capture model: the paper's regressions, or a user's refit of the same forms.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WakeCaptureModel {
    /// Where the coefficients come from (shown in reports and logs).
    pub source: String,
    /// Cycle-mean lift increment over the first 0.1 T of a half stroke (eq 17 form).
    pub dcl: ExpQuadratic,
    /// Cycle-mean drag increment (eq 18 form).
    pub dcd: ExpQuadratic,
    /// Non-dimensional time of the peak (eq 19 form).
    pub mu_star: LinearLn,
    /// Fitted Reynolds-number range.
    pub re_range: FitRange,
    /// Fitted dtau_A range.
    pub dtau_a_range: FitRange,
    /// Fitted dtau_D range.
    pub dtau_d_range: FitRange,
}

impl Default for WakeCaptureModel {
    fn default() -> Self {
        Self::paper()
    }
}

/// Which inputs of a wake-capture evaluation were outside the fitted range (and clamped).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct RangeFlags {
    /// Re was outside the range.
    pub re_clamped: bool,
    /// dtau_A was outside the range.
    pub dtau_a_clamped: bool,
    /// dtau_D was outside the range.
    pub dtau_d_clamped: bool,
}

impl RangeFlags {
    /// True when any input was clamped.
    pub fn any(&self) -> bool {
        self.re_clamped || self.dtau_a_clamped || self.dtau_d_clamped
    }
}

/// The three regression outputs of a wake-capture model.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct WakeCaptureParams {
    /// Mean lift-coefficient increment over 0.1 T, dCL_bar.
    pub dcl_bar: f64,
    /// Mean drag-coefficient increment over 0.1 T, dCD_bar.
    pub dcd_bar: f64,
    /// Non-dimensional time of the peak, mu*.
    pub mu_star: f64,
    /// Inputs that were clamped to the fitted range before evaluating.
    pub flags: RangeFlags,
}

impl WakeCaptureModel {
    /// The seed paper's eq 17-19 (eq 19 with the plus sign of its Table 5 and second
    /// printing, per MODEL.md section 4), fitted on Re 136-6800 and dtau 0.06-0.18.
    pub fn paper() -> Self {
        Self {
            source: "seed paper eq 17-19 (plus sign in eq 19)".to_owned(),
            dcl: ExpQuadratic {
                c0: 0.94839,
                c1: -0.195478,
                c2: -0.00234646,
                c3: -7.9318,
                c4: 19.6205,
            },
            dcd: ExpQuadratic {
                c0: 0.903189,
                c1: -0.0356281,
                c2: -0.00027928,
                c3: -7.18999,
                c4: 17.7339,
            },
            mu_star: LinearLn {
                m0: 0.04195,
                m1: -0.002684,
                m2: 0.2236,
            },
            re_range: FitRange {
                min: 136.0,
                max: 6800.0,
            },
            dtau_a_range: FitRange {
                min: 0.06,
                max: 0.18,
            },
            dtau_d_range: FitRange {
                min: 0.06,
                max: 0.18,
            },
        }
    }

    /// The raw regressions at the given inputs, without clamping (reproduces Table 5 even at
    /// dtau_D = 0.03, outside the fitted range).
    pub fn raw(&self, re: f64, dtau_a: f64, dtau_d: f64) -> WakeCaptureParams {
        WakeCaptureParams {
            dcl_bar: self.dcl.eval(re, dtau_d),
            dcd_bar: self.dcd.eval(re, dtau_d),
            mu_star: self.mu_star.eval(re, dtau_a),
            flags: RangeFlags::default(),
        }
    }

    /// The regressions with inputs clamped into the fitted range; the flags say which were.
    pub fn clamped(&self, re: f64, dtau_a: f64, dtau_d: f64) -> WakeCaptureParams {
        let flags = RangeFlags {
            re_clamped: !self.re_range.contains(re),
            dtau_a_clamped: !self.dtau_a_range.contains(dtau_a),
            dtau_d_clamped: !self.dtau_d_range.contains(dtau_d),
        };
        let mut p = self.raw(
            self.re_range.clamp(re),
            self.dtau_a_range.clamp(dtau_a),
            self.dtau_d_range.clamp(dtau_d),
        );
        p.flags = flags;
        p
    }
}

impl WakeCaptureParams {
    /// Instantaneous (C_L,WC, C_D,WC) at t* (eq 23-24): a Gaussian of standard deviation
    /// mu*/3 centred at mu* holding 0.1 dC_bar of area.
    pub fn coefficients(&self, t_star: f64) -> (f64, f64) {
        let g = self.shape(t_star);
        (self.dcl_bar * g, self.dcd_bar * g)
    }

    /// The common factor 0.3 / (mu* sqrt(2 pi)) exp(-0.5 (3 (t* - mu*)/mu*)^2).
    #[inline]
    pub fn shape(&self, t_star: f64) -> f64 {
        let mu = self.mu_star;
        let z = 3.0 * (t_star - mu) / mu;
        0.3 / (mu * (2.0 * std::f64::consts::PI).sqrt()) * (-0.5 * z * z).exp()
    }
}
