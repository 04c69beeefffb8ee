//! Wing planforms and the geometric quantities derived from them.
//!
//! Coordinates: `r` is the distance along the span axis from the stroke (hinge) axis, so the
//! wing occupies `r_root_m ..= r_tip_m`; `x` is chordwise, measured from the pitch axis and
//! positive towards the leading edge. A strip at `r` spans `x_le(r) - c(r) ..= x_le(r)`.

use serde::{Deserialize, Serialize};

use crate::error::{Result, Validator};
use crate::quad;

/// How a wing's chord varies along its span. Lengths in metres.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "shape", rename_all = "snake_case", deny_unknown_fields)]
pub enum PlanformSpec {
    /// Constant chord.
    Rectangular {
        /// Span b (root to tip), m.
        span_m: f64,
        /// Chord, m.
        chord_m: f64,
        /// Distance from the stroke axis to the wing root, m.
        #[serde(default)]
        root_offset_m: f64,
        /// Pitch axis position behind the leading edge, as a fraction of the local chord.
        #[serde(default = "default_pitch_axis")]
        pitch_axis_from_le_frac: f64,
    },
    /// Half-ellipse chord distribution `c = c_max sqrt(1 - (2 rho - 1)^2)`, rho = (r - r_root)/b.
    Elliptic {
        /// Span b, m.
        span_m: f64,
        /// Largest chord (at mid-span), m.
        max_chord_m: f64,
        /// Distance from the stroke axis to the wing root, m.
        #[serde(default)]
        root_offset_m: f64,
        /// Pitch axis position behind the leading edge, as a fraction of the local chord.
        #[serde(default = "default_pitch_axis")]
        pitch_axis_from_le_frac: f64,
    },
    /// Ellington's (1984) beta-distribution planform, set by the non-dimensional radius of
    /// the first moment of area `r1_hat` (second moment from his fit r2_hat = 0.929 r1_hat^0.732).
    EllingtonBeta {
        /// Span b, m.
        span_m: f64,
        /// Wing area S, m^2.
        area_m2: f64,
        /// Non-dimensional first moment of area, measured from the wing root.
        r1_hat: f64,
        /// Distance from the stroke axis to the wing root, m.
        #[serde(default)]
        root_offset_m: f64,
        /// Pitch axis position behind the leading edge, as a fraction of the local chord.
        #[serde(default = "default_pitch_axis")]
        pitch_axis_from_le_frac: f64,
    },
    /// Measured planform: stations along the span, linearly interpolated.
    Tabulated {
        /// Distance from the stroke axis to the wing root, m.
        #[serde(default)]
        root_offset_m: f64,
        /// Stations measured from the root, strictly increasing, starting at 0, m.
        r_from_root_m: Vec<f64>,
        /// Chord at each station, m (>= 0).
        chord_m: Vec<f64>,
        /// Leading edge ahead of the pitch axis at each station, m.
        le_offset_m: Vec<f64>,
    },
}

fn default_pitch_axis() -> f64 {
    0.25
}

/// Measured values that replace derived ones (only where a source measured them).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GeometryOverrides {
    /// Van Veen's pitch-stroke coupled moment sqrt(S_xx S_yy), m^4.
    pub sqrt_sxx_syy_m4: Option<f64>,
    /// Van Veen's asymmetric moment S_x|x|, m^4.
    pub sx_absx_m4: Option<f64>,
}

/// One blade-element strip.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Strip {
    /// Representative radius from the stroke axis: sqrt(int c r^2 dr / int c dr) over the strip,
    /// so that the strips' sum of area * r^2 is the wing's S R_g^2 exactly.
    pub r_m: f64,
    /// Strip area int c dr, m^2.
    pub area_m2: f64,
    /// Chordwise position of the translational centre of pressure (from the pitch axis,
    /// positive towards the leading edge), area-weighted over the strip, m.
    pub x_cp_m: f64,
}

/// Integrals of c^2 over the span used by the added-mass term (x is the mid-chord offset).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct AddedMassIntegrals {
    /// int c^2 dr, m^3.
    pub c2: f64,
    /// int c^2 r dr, m^4.
    pub c2_r: f64,
    /// int c^2 r^2 dr, m^5.
    pub c2_r2: f64,
    /// int c^2 x_mid dr, m^4.
    pub c2_x: f64,
    /// int c^2 r x_mid dr, m^5.
    pub c2_rx: f64,
    /// int c^2 x_mid^2 dr, m^5.
    pub c2_x2: f64,
    /// int c^4 dr, m^5 (the strips' rotational added inertia).
    pub c4: f64,
}

/// A planform with everything derived from it.
#[derive(Debug, Clone, PartialEq)]
pub struct Geometry {
    /// Distance from the stroke axis to the root, m.
    pub r_root_m: f64,
    /// Distance from the stroke axis to the tip (the paper's R), m.
    pub r_tip_m: f64,
    /// Span b = R - r_root, m.
    pub span_m: f64,
    /// Area S, m^2.
    pub area_m2: f64,
    /// Mean chord c_bar = S / b, m.
    pub mean_chord_m: f64,
    /// Aspect ratio AR = b^2 / S.
    pub aspect_ratio: f64,
    /// Radius of gyration R_g = sqrt(int r^2 c dr / S), from the stroke axis, m.
    pub r_gyration_m: f64,
    /// Rossby number Ro = R / c_bar.
    pub rossby: f64,
    /// S_xx = int x^2 dS, m^4 (derived).
    pub sxx_m4: f64,
    /// S_yy = int r^2 dS, m^4 (derived).
    pub syy_m4: f64,
    /// sqrt(S_xx S_yy), m^4 (derived, or a measured override).
    pub sqrt_sxx_syy_m4: f64,
    /// S_x|x| = int x|x| dS, m^4 (derived, or a measured override).
    pub sx_absx_m4: f64,
    /// S_|x|^3 = int |x|^3 dS, m^5 (derived): the pitch-only rotational term's moment about
    /// the pitch axis (see `Wing::kinematic_loads_in`).
    pub s_absx3_m5: f64,
    /// Blade-element strips, root to tip.
    pub strips: Vec<Strip>,
    /// Span integrals for the added-mass term.
    pub added_mass: AddedMassIntegrals,
}

/// Evaluates chord and leading-edge offset at a radius.
trait Shape {
    fn chord(&self, r: f64) -> f64;
    fn le_offset(&self, r: f64) -> f64;
}

struct Parametric<F: Fn(f64) -> f64> {
    chord: F,
    pitch_axis_frac: f64,
}

impl<F: Fn(f64) -> f64> Shape for Parametric<F> {
    fn chord(&self, r: f64) -> f64 {
        (self.chord)(r)
    }
    fn le_offset(&self, r: f64) -> f64 {
        self.pitch_axis_frac * (self.chord)(r)
    }
}

struct Table<'a> {
    r: Vec<f64>,
    chord: &'a [f64],
    le: &'a [f64],
}

impl Table<'_> {
    fn interp(&self, values: &[f64], r: f64) -> f64 {
        let i = match self.r.partition_point(|&ri| ri <= r) {
            0 => 0,
            n if n >= self.r.len() => self.r.len() - 2,
            n => n - 1,
        };
        let (r0, r1) = (self.r[i], self.r[i + 1]);
        let s = ((r - r0) / (r1 - r0)).clamp(0.0, 1.0);
        values[i] + s * (values[i + 1] - values[i])
    }
}

impl Shape for Table<'_> {
    fn chord(&self, r: f64) -> f64 {
        self.interp(self.chord, r)
    }
    fn le_offset(&self, r: f64) -> f64 {
        self.interp(self.le, r)
    }
}

/// Panels per strip for parametric planforms (Gauss-Legendre, 4 points each).
const PARAMETRIC_PANELS: usize = 64;
/// Panels per table interval (the integrands are polynomials there, so this is exact).
const TABLE_PANELS: usize = 2;

impl PlanformSpec {
    /// Validates the spec and derives the geometry with `n_strips` blade elements.
    ///
    /// `field` is the dotted path of this planform in its file (for error messages);
    /// `cp_chord_frac` places the translational centre of pressure behind the leading edge.
    pub fn build(
        &self,
        v: &Validator<'_>,
        field: &str,
        overrides: &GeometryOverrides,
        n_strips: usize,
        cp_chord_frac: f64,
    ) -> Result<Geometry> {
        let f = |name: &str| format!("{field}.{name}");
        match self {
            PlanformSpec::Rectangular {
                span_m,
                chord_m,
                root_offset_m,
                pitch_axis_from_le_frac,
            } => {
                let (b, r0, pa) =
                    spanwise(v, &f, *span_m, *root_offset_m, *pitch_axis_from_le_frac)?;
                let c = v.positive(&f("chord_m"), *chord_m)?;
                let shape = Parametric {
                    chord: move |_r: f64| c,
                    pitch_axis_frac: pa,
                };
                derive(
                    &shape,
                    &[r0, r0 + b],
                    PARAMETRIC_PANELS,
                    overrides,
                    n_strips,
                    cp_chord_frac,
                )
            }
            PlanformSpec::Elliptic {
                span_m,
                max_chord_m,
                root_offset_m,
                pitch_axis_from_le_frac,
            } => {
                let (b, r0, pa) =
                    spanwise(v, &f, *span_m, *root_offset_m, *pitch_axis_from_le_frac)?;
                let c = v.positive(&f("max_chord_m"), *max_chord_m)?;
                let shape = Parametric {
                    chord: move |r: f64| {
                        let s = 2.0 * (r - r0) / b - 1.0;
                        c * (1.0 - s * s).max(0.0).sqrt()
                    },
                    pitch_axis_frac: pa,
                };
                derive(
                    &shape,
                    &[r0, r0 + b],
                    PARAMETRIC_PANELS,
                    overrides,
                    n_strips,
                    cp_chord_frac,
                )
            }
            PlanformSpec::EllingtonBeta {
                span_m,
                area_m2,
                r1_hat,
                root_offset_m,
                pitch_axis_from_le_frac,
            } => {
                let (b, r0, pa) =
                    spanwise(v, &f, *span_m, *root_offset_m, *pitch_axis_from_le_frac)?;
                let s = v.positive(&f("area_m2"), *area_m2)?;
                // Ellington (1984) fitted r1_hat over 0.4-0.6 for insect wings; the beta shape
                // needs p, q > 0, which holds on this range.
                let r1 = v.within(&f("r1_hat"), *r1_hat, 0.4, 0.6)?;
                let (p, q) = ellington_beta_exponents(r1);
                let unit = move |r: f64| {
                    let x = ((r - r0) / b).clamp(0.0, 1.0);
                    x.powf(p - 1.0) * (1.0 - x).powf(q - 1.0)
                };
                let raw = quad::piecewise(
                    &fine_breaks(&[r0, r0 + b], n_strips),
                    PARAMETRIC_PANELS,
                    unit,
                );
                let k = s / raw;
                let shape = Parametric {
                    chord: move |r: f64| k * unit(r),
                    pitch_axis_frac: pa,
                };
                derive(
                    &shape,
                    &[r0, r0 + b],
                    PARAMETRIC_PANELS,
                    overrides,
                    n_strips,
                    cp_chord_frac,
                )
            }
            PlanformSpec::Tabulated {
                root_offset_m,
                r_from_root_m,
                chord_m,
                le_offset_m,
            } => {
                let r0 = v.non_negative(&f("root_offset_m"), *root_offset_m)?;
                if r_from_root_m.len() < 2 {
                    return Err(v.invalid(
                        &f("r_from_root_m"),
                        format!("{} stations", r_from_root_m.len()),
                        "at least 2 stations",
                    ));
                }
                for (name, list) in [("chord_m", chord_m), ("le_offset_m", le_offset_m)] {
                    if list.len() != r_from_root_m.len() {
                        return Err(v.invalid(
                            &f(name),
                            format!("{} values", list.len()),
                            &format!(
                                "exactly one value per station ({} stations in r_from_root_m)",
                                r_from_root_m.len()
                            ),
                        ));
                    }
                }
                if r_from_root_m[0] != 0.0 {
                    return Err(v.invalid(
                        &f("r_from_root_m[0]"),
                        r_from_root_m[0],
                        "0 (the first station is the wing root)",
                    ));
                }
                for i in 1..r_from_root_m.len() {
                    v.finite(&format!("{}[{i}]", f("r_from_root_m")), r_from_root_m[i])?;
                    if r_from_root_m[i] <= r_from_root_m[i - 1] {
                        return Err(v.invalid(
                            &format!("{}[{i}]", f("r_from_root_m")),
                            r_from_root_m[i],
                            &format!(
                                "strictly greater than the previous station ({})",
                                r_from_root_m[i - 1]
                            ),
                        ));
                    }
                }
                for (i, &c) in chord_m.iter().enumerate() {
                    v.non_negative(&format!("{}[{i}]", f("chord_m")), c)?;
                }
                for (i, &x) in le_offset_m.iter().enumerate() {
                    v.finite(&format!("{}[{i}]", f("le_offset_m")), x)?;
                }
                let r: Vec<f64> = r_from_root_m.iter().map(|x| x + r0).collect();
                let table = Table {
                    r: r.clone(),
                    chord: chord_m,
                    le: le_offset_m,
                };
                let geometry =
                    derive(&table, &r, TABLE_PANELS, overrides, n_strips, cp_chord_frac)?;
                if geometry.area_m2 <= 0.0 {
                    return Err(v.invalid(
                        &f("chord_m"),
                        "all zero",
                        "at least one chord > 0 (the wing needs area)",
                    ));
                }
                Ok(geometry)
            }
        }
        .and_then(|g| {
            if let Some(x) = overrides.sqrt_sxx_syy_m4 {
                v.positive("wing.overrides.sqrt_sxx_syy_m4", x)?;
            }
            if let Some(x) = overrides.sx_absx_m4 {
                v.finite("wing.overrides.sx_absx_m4", x)?;
            }
            Ok(g)
        })
    }
}

/// Validates the fields every parametric planform shares: (span, root offset, pitch axis).
fn spanwise(
    v: &Validator<'_>,
    f: &dyn Fn(&str) -> String,
    span_m: f64,
    root_offset_m: f64,
    pitch_axis: f64,
) -> Result<(f64, f64, f64)> {
    Ok((
        v.positive(&f("span_m"), span_m)?,
        v.non_negative(&f("root_offset_m"), root_offset_m)?,
        v.within(&f("pitch_axis_from_le_frac"), pitch_axis, 0.0, 1.0)?,
    ))
}

/// Ellington's beta-distribution exponents (p, q) for a given r1_hat, with
/// r2_hat = 0.929 r1_hat^0.732 (Ellington 1984, Phil Trans R Soc B 305:17, eq 37 and 40-41).
pub fn ellington_beta_exponents(r1_hat: f64) -> (f64, f64) {
    let r2 = 0.929 * r1_hat.powf(0.732);
    let common = r1_hat * (1.0 - r1_hat) / (r2 * r2 - r1_hat * r1_hat) - 1.0;
    (r1_hat * common, (1.0 - r1_hat) * common)
}

/// The union of the strip edges and the given breaks, sorted.
fn fine_breaks(breaks: &[f64], n_strips: usize) -> Vec<f64> {
    let (a, b) = (breaks[0], breaks[breaks.len() - 1]);
    let mut out: Vec<f64> = (0..=n_strips)
        .map(|i| a + (b - a) * i as f64 / n_strips as f64)
        .collect();
    out.extend(breaks.iter().copied().filter(|&x| x > a && x < b));
    out.sort_by(f64::total_cmp);
    out.dedup();
    out
}

/// Chordwise integrals over one strip cross-section between `x_te` and `x_le`: of x^2,
/// x|x| and |x|^3 (antiderivatives x^3/3, x^2|x|/3 and x^3|x|/4).
fn section_moments(x_le: f64, c: f64) -> (f64, f64, f64) {
    let x_te = x_le - c;
    let xx = (x_le.powi(3) - x_te.powi(3)) / 3.0;
    let x_absx = (x_le * x_le * x_le.abs() - x_te * x_te * x_te.abs()) / 3.0;
    let absx3 = (x_le.powi(3) * x_le.abs() - x_te.powi(3) * x_te.abs()) / 4.0;
    (xx, x_absx, absx3)
}

fn derive(
    shape: &dyn Shape,
    breaks: &[f64],
    panels: usize,
    overrides: &GeometryOverrides,
    n_strips: usize,
    cp_chord_frac: f64,
) -> Result<Geometry> {
    let r_root = breaks[0];
    let r_tip = *breaks.last().expect("at least two breaks");
    let span = r_tip - r_root;
    // Every integral uses the same subdivision (strip edges plus table stations), so the
    // strips' sums equal the whole-wing integrals to round-off.
    let fine = fine_breaks(breaks, n_strips);
    // The shape at each quadrature node, evaluated once: every whole-wing integral visits the
    // same nodes in the same order, and the shape's chord (a power law for the Ellington
    // beta planform) was 80 % of a model's build (callgrind: 40 M instructions of a fly).
    let mut nodes: Vec<(f64, f64, f64)> = Vec::new();
    quad::piecewise(&fine, panels, |r| {
        nodes.push((r, shape.le_offset(r), shape.chord(r)));
        0.0
    });
    let integ = |g: &dyn Fn(f64, f64, f64) -> f64| {
        let mut next = nodes.iter();
        quad::piecewise(&fine, panels, |_| {
            let &(r, le, c) = next.next().expect("the nodes visited in the same order");
            g(r, le, c)
        })
    };
    let sxx = integ(&|_, le, c| section_moments(le, c).0);
    let sx_absx = integ(&|_, le, c| section_moments(le, c).1);
    let s_absx3 = integ(&|_, le, c| section_moments(le, c).2);
    let x_mid = |le: f64, c: f64| le - 0.5 * c;
    let c2 = |c: f64| c.powi(2);
    let added_mass = AddedMassIntegrals {
        c2: integ(&|_, _, c| c2(c)),
        c2_r: integ(&|r, _, c| c2(c) * r),
        c2_r2: integ(&|r, _, c| c2(c) * r * r),
        c2_x: integ(&|_, le, c| c2(c) * x_mid(le, c)),
        c2_rx: integ(&|r, le, c| c2(c) * r * x_mid(le, c)),
        c2_x2: integ(&|_, le, c| c2(c) * x_mid(le, c) * x_mid(le, c)),
        c4: integ(&|_, _, c| c2(c) * c2(c)),
    };
    // Strips: equal widths; each strip's integrals use the same quadrature restricted to it,
    // with the table's breaks inside the strip kept so tabulated wings stay exact.
    let mut strips = Vec::with_capacity(n_strips);
    let dr = span / n_strips as f64;
    for i in 0..n_strips {
        let (a, b) = (r_root + i as f64 * dr, r_root + (i + 1) as f64 * dr);
        let mut sub: Vec<f64> = vec![a];
        sub.extend(breaks.iter().copied().filter(|&x| x > a && x < b));
        sub.push(b);
        let per = panels;
        let s_i = quad::piecewise(&sub, per, |r| shape.chord(r));
        let i2 = quad::piecewise(&sub, per, |r| shape.chord(r) * r * r);
        let xcp = quad::piecewise(&sub, per, |r| {
            shape.chord(r) * (shape.le_offset(r) - cp_chord_frac * shape.chord(r))
        });
        let (r_m, x_cp_m) = if s_i > 0.0 {
            ((i2 / s_i).sqrt(), xcp / s_i)
        } else {
            (0.5 * (a + b), 0.0)
        };
        strips.push(Strip {
            r_m,
            area_m2: s_i,
            x_cp_m,
        });
    }
    // Area and second moment are the sums over the strips, so that the strips reproduce
    // S and S R_g^2 exactly (the translational check of MODEL.md section 5 relies on it).
    let area: f64 = strips.iter().map(|s| s.area_m2).sum();
    let syy: f64 = strips.iter().map(|s| s.area_m2 * s.r_m * s.r_m).sum();
    let mean_chord = area / span;
    Ok(Geometry {
        r_root_m: r_root,
        r_tip_m: r_tip,
        span_m: span,
        area_m2: area,
        mean_chord_m: mean_chord,
        aspect_ratio: span * span / area,
        r_gyration_m: (syy / area).sqrt(),
        rossby: r_tip / mean_chord,
        sxx_m4: sxx,
        syy_m4: syy,
        sqrt_sxx_syy_m4: overrides.sqrt_sxx_syy_m4.unwrap_or((sxx * syy).sqrt()),
        sx_absx_m4: overrides.sx_absx_m4.unwrap_or(sx_absx),
        s_absx3_m5: s_absx3,
        strips,
        added_mass,
    })
}
