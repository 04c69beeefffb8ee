//! `flapwing envelope --plot`: three panels against forward speed (at the first climb rate
//! of the grid): the power required (mean, and positive work only), the trim angles (body
//! pitch, stroke plane) and the real parts of the averaged-model modes (the mode loci).

use std::path::Path;

use anyhow::Result;
use flapstudy::envelope::EnvelopeRow;
use plotters::prelude::*;

/// Draws the plot of `rows` to `path` (PNG by extension, else SVG).
pub fn plot(rows: &[EnvelopeRow], path: &Path, name: &str) -> Result<()> {
    crate::plot::render!(path, (900, 1000), draw(rows, name))
}

/// (speed, value) series of the trimmed points at the grid's first climb rate.
fn series(
    rows: &[EnvelopeRow],
    f: impl Fn(&flapstudy::envelope::EnvelopePoint) -> f64,
) -> Vec<(f64, f64)> {
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
    let (u_lo, u_hi) = range(rows.iter().map(|r| r.condition.forward_speed_m_s));
    let power = series(rows, |p| p.point.power.aero_w * 1e3);
    let positive = series(rows, |p| p.point.power.aero_positive_w * 1e3);
    let pitch = series(rows, |p| p.trim.pitch_rad.to_degrees());
    let plane = series(rows, |p| p.point.stroke_plane_angle_rad.to_degrees());
    // Each mode's real part at each speed: modes sorted by real part, k-th against speed.
    let n_lon = rows
        .iter()
        .filter_map(|r| r.point.as_ref())
        .map(|p| p.longitudinal_modes.len())
        .max()
        .unwrap_or(0);
    let n_lat = rows
        .iter()
        .filter_map(|r| r.point.as_ref())
        .map(|p| p.lateral_modes.len())
        .max()
        .unwrap_or(0);
    let lon: Vec<Vec<(f64, f64)>> = (0..n_lon)
        .map(|k| {
            series(rows, |p| {
                p.longitudinal_modes.get(k).map_or(f64::NAN, |m| m.re_per_s)
            })
        })
        .map(|s| s.into_iter().filter(|p| p.1.is_finite()).collect())
        .collect();
    let lat: Vec<Vec<(f64, f64)>> = (0..n_lat)
        .map(|k| {
            series(rows, |p| {
                p.lateral_modes.get(k).map_or(f64::NAN, |m| m.re_per_s)
            })
        })
        .map(|s| s.into_iter().filter(|p| p.1.is_finite()).collect())
        .collect();

    let (p_lo, p_hi) = range(power.iter().chain(&positive).map(|p| p.1).chain([0.0]));
    let mut chart = ChartBuilder::on(&panels[0])
        .margin(12)
        .x_label_area_size(35)
        .y_label_area_size(60)
        .build_cartesian_2d(u_lo..u_hi, p_lo..p_hi)
        .map_err(e)?;
    chart
        .configure_mesh()
        .x_desc("forward speed [m/s]")
        .y_desc("power required [mW]")
        .draw()
        .map_err(e)?;
    for (s, label, color) in [
        (&power, "aerodynamic (elastic storage)", BLUE),
        (&positive, "positive work only", RED),
    ] {
        chart
            .draw_series(LineSeries::new(s.iter().copied(), color.stroke_width(2)))
            .map_err(e)?
            .label(label)
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
            });
        chart
            .draw_series(s.iter().map(|&p| Circle::new(p, 3, color.filled())))
            .map_err(e)?;
    }
    chart
        .configure_series_labels()
        .border_style(BLACK)
        .background_style(WHITE.mix(0.8))
        .draw()
        .map_err(e)?;

    let (a_lo, a_hi) = range(pitch.iter().chain(&plane).map(|p| p.1));
    let mut chart = ChartBuilder::on(&panels[1])
        .margin(12)
        .x_label_area_size(35)
        .y_label_area_size(60)
        .build_cartesian_2d(u_lo..u_hi, a_lo..a_hi)
        .map_err(e)?;
    chart
        .configure_mesh()
        .x_desc("forward speed [m/s]")
        .y_desc("angle [deg]")
        .draw()
        .map_err(e)?;
    for (s, label, color) in [
        (&pitch, "body pitch", BLUE),
        (&plane, "stroke plane to horizontal", GREEN),
    ] {
        chart
            .draw_series(LineSeries::new(s.iter().copied(), color.stroke_width(2)))
            .map_err(e)?
            .label(label)
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
            });
    }
    chart
        .configure_series_labels()
        .border_style(BLACK)
        .background_style(WHITE.mix(0.8))
        .draw()
        .map_err(e)?;

    let (r_lo, r_hi) = range(lon.iter().chain(&lat).flatten().map(|p| p.1).chain([0.0]));
    let mut chart = ChartBuilder::on(&panels[2])
        .margin(12)
        .x_label_area_size(35)
        .y_label_area_size(60)
        .build_cartesian_2d(u_lo..u_hi, r_lo..r_hi)
        .map_err(e)?;
    chart
        .configure_mesh()
        .x_desc("forward speed [m/s]")
        .y_desc("mode real part [1/s] (> 0 unstable)")
        .draw()
        .map_err(e)?;
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
            vec![(u_lo, 0.0), (u_hi, 0.0)],
            BLACK.mix(0.5),
        )))
        .map_err(e)?;
    chart
        .configure_series_labels()
        .border_style(BLACK)
        .background_style(WHITE.mix(0.8))
        .draw()
        .map_err(e)?;
    area.present().map_err(e)?;
    Ok(())
}
