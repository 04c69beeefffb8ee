//! `flapwing forces --plot FILE`: C_L(t*) and C_D(t*) of the whole wing over one wingbeat,
//! with and without the wake-capture term, like the seed paper's Fig 23-24.

use std::path::Path;

use plotters::prelude::*;
use wingforce::{BodyMotion, Term, TermForce, Wing, WingForces};

/// Samples per wingbeat drawn.
const SAMPLES: usize = 1000;

/// Draws the plot (SVG, or PNG when the file name ends in `.png`).
pub fn plot(wing: &Wing, path: &Path, title: &str) -> anyhow::Result<()> {
    let mut off = wing.clone();
    let mut options = wing.options().clone();
    options.wake_capture = None;
    off.set_options(options);
    let body = BodyMotion::default();
    // Phase over [0, 1): t* runs 0..0.5 in each half stroke; plot against phase (t/T).
    let series = |w: &Wing| -> Vec<(f64, TermForce)> {
        (0..SAMPLES)
            .map(|k| {
                let p = (k as f64 + 0.5) / SAMPLES as f64;
                (p, w.evaluate(p, &body).total)
            })
            .collect()
    };
    draw_series(&series(wing), &series(&off), path, title)
}

/// The same plot from a wing's forces at equal steps over one wingbeat (phase k / n): an
/// actuated wing's periodic motion. The curves without wake capture are the same motion's
/// totals less that term (the terms add); switching the term off would also change the
/// motion the drive gives the wing, so they are not a run without it.
pub fn plot_samples(samples: &[WingForces], path: &Path, title: &str) -> anyhow::Result<()> {
    let n = samples.len() as f64;
    let phase = |k: usize| k as f64 / n;
    let on: Vec<(f64, TermForce)> = samples
        .iter()
        .enumerate()
        .map(|(k, f)| (phase(k), f.total))
        .collect();
    let off: Vec<(f64, TermForce)> = samples
        .iter()
        .enumerate()
        .map(|(k, f)| {
            let wc = f.term(Term::WakeCapture);
            let mut t = f.total;
            t.c_l -= wc.c_l;
            t.c_d -= wc.c_d;
            (phase(k), t)
        })
        .collect();
    draw_series(&on, &off, path, title)
}

/// Draws C_L and C_D against the phase, with (`on`) and without (`off`) wake capture.
fn draw_series(
    on: &[(f64, TermForce)],
    off: &[(f64, TermForce)],
    path: &Path,
    title: &str,
) -> anyhow::Result<()> {
    let split = |s: &[(f64, TermForce)]| -> (Vec<(f64, f64)>, Vec<(f64, f64)>) {
        s.iter().map(|(p, f)| ((*p, f.c_l), (*p, f.c_d))).unzip()
    };
    let (cl_on, cd_on) = split(on);
    let (cl_off, cd_off) = split(off);
    let all = cl_on
        .iter()
        .chain(&cd_on)
        .chain(&cl_off)
        .chain(&cd_off)
        .map(|p| p.1);
    let (lo, hi) = all.fold((0.0f64, 0.0f64), |(a, b), y| (a.min(y), b.max(y)));
    let pad = 0.05 * (hi - lo).max(1e-9);
    let curves = [
        ("C_L with wake capture", cl_on, BLUE.mix(1.0)),
        ("C_L without", cl_off, BLUE.mix(0.4)),
        ("C_D with wake capture", cd_on, RED.mix(1.0)),
        ("C_D without", cd_off, RED.mix(0.4)),
    ];
    crate::plot::render!(path, (900, 550), draw(&curves, lo - pad, hi + pad, title))
}

fn draw<DB: DrawingBackend>(
    root: DrawingArea<DB, plotters::coord::Shift>,
    curves: &[(&'static str, Vec<(f64, f64)>, impl Into<RGBAColor> + Copy)],
    lo: f64,
    hi: f64,
    title: &str,
) -> anyhow::Result<()>
where
    DB::ErrorType: 'static,
{
    let e = crate::plot::draw_error::<DB::ErrorType>;
    root.fill(&WHITE).map_err(e)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 20))
        .margin(15)
        .x_label_area_size(40)
        .y_label_area_size(50)
        .build_cartesian_2d(0.0..1.0, lo..hi)
        .map_err(e)?;
    chart
        .configure_mesh()
        .x_desc("t / T (downstroke 0-0.5, upstroke 0.5-1)")
        .y_desc("coefficient")
        .draw()
        .map_err(e)?;
    for (label, pts, color) in curves {
        let c: RGBAColor = (*color).into();
        chart
            .draw_series(LineSeries::new(pts.iter().copied(), c.stroke_width(2)))
            .map_err(e)?
            .label(*label)
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], c.stroke_width(2)));
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()
        .map_err(e)?;
    root.present().map_err(e)?;
    Ok(())
}
