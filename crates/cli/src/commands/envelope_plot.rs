//! `flapwing envelope --plot`: three panels against forward speed (at the first climb rate
//! of the grid): the power required (mean, and positive work only), the trim angles (body
//! pitch, stroke plane) and the real parts of the averaged-model modes (the mode loci).

use std::path::Path;

use anyhow::Result;
use flapsim::stability::ModeInfo;
use flapstudy::envelope::{EnvelopePoint, EnvelopeRow};
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;

/// Draws the plot of `rows` to `path` (PNG by extension, else SVG).
pub fn plot(rows: &[EnvelopeRow], path: &Path, name: &str) -> Result<()> {
    crate::plot::render!(path, (900, 1000), draw(rows, name))
}

/// (speed, value) series of the trimmed points at the grid's first climb rate.
fn series(rows: &[EnvelopeRow], f: impl Fn(&EnvelopePoint) -> f64) -> Vec<(f64, f64)> {
    let w0 = rows.first().map_or(0.0, |r| r.condition.climb_rate_m_s);
    rows.iter()
        .filter(|r| r.condition.climb_rate_m_s == w0)
        .filter_map(|r| {
            r.point
                .as_ref()
                .map(|p| (r.condition.forward_speed_m_s, f(p)))
        })
        .collect()
}

fn range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
        (lo.min(v), hi.max(v))
    });
    if !lo.is_finite() {
        return (0.0, 1.0);
    }
    let pad = 0.08 * (hi - lo).max(1e-12 * hi.abs().max(1.0));
    (lo - pad, hi + pad)
}

/// Each mode's real part against speed: the k-th mode (sorted by real part) of every point.
fn mode_loci(
    rows: &[EnvelopeRow],
    modes: impl Fn(&EnvelopePoint) -> &[ModeInfo],
) -> Vec<Vec<(f64, f64)>> {
    let n = rows
        .iter()
        .filter_map(|r| r.point.as_ref())
        .map(|p| modes(p).len())
        .max()
        .unwrap_or(0);
    (0..n)
        .map(|k| {
            series(rows, |p| modes(p).get(k).map_or(f64::NAN, |m| m.re_per_s))
                .into_iter()
                .filter(|p| p.1.is_finite())
                .collect()
        })
        .collect()
}

type SpeedChart<'a, DB> = ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// A panel with forward speed on x (`u`) and `y_desc` on y over `y`.
fn speed_chart<'a, DB: DrawingBackend>(
    area: &'a DrawingArea<DB, plotters::coord::Shift>,
    u: (f64, f64),
    y: (f64, f64),
    y_desc: &str,
) -> Result<SpeedChart<'a, DB>>
where
    DB::ErrorType: 'static,
{
    let e = crate::plot::draw_error::<DB::ErrorType>;
    let mut chart = ChartBuilder::on(area)
        .margin(12)
        .x_label_area_size(35)
        .y_label_area_size(60)
        .build_cartesian_2d(u.0..u.1, y.0..y.1)
        .map_err(e)?;
    chart
        .configure_mesh()
        .x_desc("forward speed [m/s]")
        .y_desc(y_desc)
        .draw()
        .map_err(e)?;
    Ok(chart)
}

/// Lines (with `dots`, also the points) of `lines`, each labelled, then the legend.
fn draw_lines<'a, DB: DrawingBackend + 'a>(
    chart: &mut SpeedChart<'a, DB>,
    lines: [(&Vec<(f64, f64)>, &str, RGBColor); 2],
    dots: bool,
) -> Result<()>
where
    DB::ErrorType: 'static,
{
    let e = crate::plot::draw_error::<DB::ErrorType>;
    for (s, label, color) in lines {
        chart
            .draw_series(LineSeries::new(s.iter().copied(), color.stroke_width(2)))
            .map_err(e)?
            .label(label)
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
            });
        if dots {
            chart
                .draw_series(s.iter().map(|&p| Circle::new(p, 3, color.filled())))
                .map_err(e)?;
        }
    }
    legend(chart)
}

fn legend<'a, DB: DrawingBackend + 'a>(chart: &mut SpeedChart<'a, DB>) -> Result<()>
where
    DB::ErrorType: 'static,
{
    chart
        .configure_series_labels()
        .border_style(BLACK)
        .background_style(WHITE.mix(0.8))
        .draw()
        .map_err(crate::plot::draw_error::<DB::ErrorType>)
}

fn draw<DB: DrawingBackend>(
    root: DrawingArea<DB, plotters::coord::Shift>,
    rows: &[EnvelopeRow],
    name: &str,
) -> Result<()>
where
    DB::ErrorType: 'static,
{
    let e = crate::plot::draw_error::<DB::ErrorType>;
    let area = crate::plot::titled_white(root, &format!("{name}: flight envelope"), 22)?;
    let panels = area.split_evenly((3, 1));
    let u = range(rows.iter().map(|r| r.condition.forward_speed_m_s));
    let power = series(rows, |p| p.point.power.aero_w * 1e3);
    let positive = series(rows, |p| p.point.power.aero_positive_w * 1e3);
    let pitch = series(rows, |p| p.trim.pitch_rad.to_degrees());
    let plane = series(rows, |p| p.point.stroke_plane_angle_rad.to_degrees());
    let lon = mode_loci(rows, |p| &p.longitudinal_modes);
    let lat = mode_loci(rows, |p| &p.lateral_modes);

    let y = range(power.iter().chain(&positive).map(|p| p.1).chain([0.0]));
    let mut chart = speed_chart(&panels[0], u, y, "power required [mW]")?;
    draw_lines(
        &mut chart,
        [
            (&power, "aerodynamic (elastic storage)", BLUE),
            (&positive, "positive work only", RED),
        ],
        true,
    )?;

    let y = range(pitch.iter().chain(&plane).map(|p| p.1));
    let mut chart = speed_chart(&panels[1], u, y, "angle [deg]")?;
    draw_lines(
        &mut chart,
        [
            (&pitch, "body pitch", BLUE),
            (&plane, "stroke plane to horizontal", GREEN),
        ],
        false,
    )?;

    let y = range(lon.iter().chain(&lat).flatten().map(|p| p.1).chain([0.0]));
    let mut chart = speed_chart(&panels[2], u, y, "mode real part [1/s] (> 0 unstable)")?;
    for (group, label, color) in [
        (&lon, "longitudinal modes", BLUE),
        (&lat, "lateral modes", GREEN),
    ] {
        for (k, s) in group.iter().enumerate() {
            let drawn = chart
                .draw_series(s.iter().map(|&p| Circle::new(p, 3, color.filled())))
                .map_err(e)?;
            if k == 0 {
                drawn
                    .label(label)
                    .legend(move |(x, y)| Circle::new((x + 10, y), 3, color.filled()));
            }
        }
    }
    chart
        .draw_series(std::iter::once(PathElement::new(
            vec![(u.0, 0.0), (u.1, 0.0)],
            BLACK.mix(0.5),
        )))
        .map_err(e)?;
    legend(&mut chart)?;
    area.present().map_err(e)?;
    Ok(())
}
