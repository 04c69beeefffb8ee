//! `flapwing frequency-response --plot FILE`: a Bode-style figure of the sweep: stroke and
//! pitch amplitude, the pitch-to-stroke phase and the stroke's lag behind the drive, and
//! the mean lift over the weight, against drive frequency, with the stroke's natural
//! frequency marked.

use std::path::Path;

use flapsim::actuated::FrequencyResponse;
use plotters::prelude::*;

/// Draws the figure (SVG, or PNG when the file name ends in `.png`).
pub fn plot(resp: &FrequencyResponse, path: &Path, title: &str) -> anyhow::Result<()> {
    crate::plot::render!(path, (900, 900), draw(resp, title))
}

type Series = Vec<(String, Vec<(f64, f64)>, RGBAColor)>;

fn draw<DB: DrawingBackend>(
    root: DrawingArea<DB, plotters::coord::Shift>,
    resp: &FrequencyResponse,
    title: &str,
) -> anyhow::Result<()>
where
    DB::ErrorType: 'static,
{
    let e = crate::plot::draw_error::<DB::ErrorType>;
    let root = crate::plot::titled_white(root, title, 20)?;
    let panels = root.split_evenly((3, 1));
    let mut volts: Vec<f64> = resp.points.iter().map(|p| p.amplitude_v).collect();
    volts.sort_by(f64::total_cmp);
    volts.dedup();
    let colors = [BLUE, RED, GREEN, MAGENTA, CYAN, BLACK];
    let series = |f: &dyn Fn(&flapsim::actuated::ResponsePoint) -> f64, what: &str| -> Series {
        volts
            .iter()
            .enumerate()
            .map(|(i, v)| {
                let pts = resp
                    .points
                    .iter()
                    .filter(|p| p.amplitude_v == *v && p.failed.is_none())
                    .map(|p| (p.freq_hz, f(p)))
                    .collect();
                (
                    format!("{what}, {v} V"),
                    pts,
                    colors[i % colors.len()].to_rgba(),
                )
            })
            .collect()
    };
    let mut amps = series(&|p| p.stroke_amplitude_deg, "stroke");
    amps.extend(
        series(&|p| p.pitch_amplitude_deg, "pitch")
            .into_iter()
            .map(|(l, p, c)| (l, p, c.mix(0.45))),
    );
    let mut phases = series(&|p| p.pitch_phase_deg, "pitch-stroke phase");
    phases.extend(series(&|p| p.stroke_lag_deg, "stroke lag behind drive"));
    let lift = series(&|p| p.lift_to_weight, "mean lift / weight");
    let (f0, f1) = resp
        .points
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
            (a.min(p.freq_hz), b.max(p.freq_hz))
        });
    let f1 = if f1 > f0 { f1 } else { f0 + 1.0 };
    for (area, (s, ylabel)) in panels.iter().zip([
        (&amps, "amplitude (deg)"),
        (&phases, "phase (deg)"),
        (&lift, "lift / weight"),
    ]) {
        let ys = s.iter().flat_map(|c| c.1.iter().map(|p| p.1));
        let (lo, hi) = ys.fold((0.0f64, 0.0f64), |(a, b), y| (a.min(y), b.max(y)));
        let pad = 0.05 * (hi - lo).max(1e-9);
        let mut chart = ChartBuilder::on(area)
            .margin(10)
            .x_label_area_size(35)
            .y_label_area_size(55)
            .build_cartesian_2d(f0..f1, (lo - pad)..(hi + pad))
            .map_err(e)?;
        chart
            .configure_mesh()
            .x_desc("drive frequency (Hz)")
            .y_desc(ylabel)
            .draw()
            .map_err(e)?;
        let f_n = resp.stroke_natural_freq_hz;
        if (f0..=f1).contains(&f_n) {
            chart
                .draw_series(LineSeries::new(
                    [(f_n, lo - pad), (f_n, hi + pad)],
                    BLACK.mix(0.4),
                ))
                .map_err(e)?
                .label(format!("stroke f_n {f_n:.1} Hz"))
                .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLACK.mix(0.4)));
        }
        for (label, pts, color) in s {
            let c = *color;
            chart
                .draw_series(LineSeries::new(pts.iter().copied(), c.stroke_width(2)))
                .map_err(e)?
                .label(label.as_str())
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], c.stroke_width(2))
                });
            chart
                .draw_series(pts.iter().map(|p| Circle::new(*p, 3, c.filled())))
                .map_err(e)?;
        }
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .draw()
            .map_err(e)?;
    }
    root.present().map_err(e)?;
    Ok(())
}
