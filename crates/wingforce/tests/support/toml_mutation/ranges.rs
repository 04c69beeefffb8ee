//! Targeted ranges: a field with its documented range, and values outside it (below or above
//! by a relative amount from 1e-6 to 1e6, or absolutely huge, the open bound itself, NaN or
//! +-inf); an out-of-range value of a field must be rejected naming exactly that field.

use proptest::prelude::*;

/// A field with its documented range.
#[derive(Debug, Clone, Copy)]
pub struct Range {
    /// Index into the including test's `bases()`.
    pub base: usize,
    /// Dotted path; list entries as `name.i`.
    pub path: &'static str,
    pub lo: f64,
    pub hi: f64,
    pub lo_open: bool,
    pub hi_open: bool,
    /// The field as the error names it (`name[i]` for list entries, `path` otherwise).
    pub field: &'static str,
}

pub const fn r(
    base: usize,
    path: &'static str,
    lo: f64,
    hi: f64,
    lo_open: bool,
    hi_open: bool,
) -> Range {
    Range {
        base,
        path,
        lo,
        hi,
        lo_open,
        hi_open,
        field: path,
    }
}

pub const INF: f64 = f64::INFINITY;

/// A value outside `[lo, hi]` (outside the open ends too): below or above by a relative
/// amount from 1e-6 to 1e6 (or absolute huge), the open bound itself, NaN or +-inf (an
/// infinite bound excludes its infinity only if it is closed).
pub fn outside(r: Range) -> BoxedStrategy<f64> {
    let mut s: Vec<BoxedStrategy<f64>> = vec![Just(f64::NAN).boxed()];
    if r.lo.is_finite() || r.lo_open {
        s.push(Just(f64::NEG_INFINITY).boxed());
    }
    if r.hi.is_finite() || r.hi_open {
        s.push(Just(f64::INFINITY).boxed());
    }
    let scale = |b: f64| b.abs().max(1.0);
    if r.lo.is_finite() {
        let lo = r.lo;
        s.push(
            (-6.0f64..6.0)
                .prop_map(move |e| lo - scale(lo) * 10f64.powf(e))
                .boxed(),
        );
        s.push(Just(lo - 1e300).boxed());
        if r.lo_open {
            s.push(Just(lo).boxed());
        }
    }
    if r.hi.is_finite() {
        let hi = r.hi;
        s.push(
            (-6.0f64..6.0)
                .prop_map(move |e| hi + scale(hi) * 10f64.powf(e))
                .boxed(),
        );
        s.push(Just(hi + 1e300).boxed());
        if r.hi_open {
            s.push(Just(hi).boxed());
        }
    }
    proptest::strategy::Union::new(s).boxed()
}

/// One of `ranges` and a value outside it.
pub fn range_and_value(ranges: &'static [Range]) -> impl Strategy<Value = (Range, f64)> {
    (0..ranges.len()).prop_flat_map(move |i| (Just(ranges[i]), outside(ranges[i])))
}
