//! `flapwing sweep contour FILE.csv --x F1 --y F2 --response R --plot OUT.svg`: a response
//! over two factors of a sweep (like the seed paper's Fig 19-21), drawn as a colour map of
//! the grid cells, averaged over any other factors, with each cell's value written in it.

use std::collections::BTreeMap;
use std::path::PathBuf;

use clap::Args;
use flapstudy::table::Table;
use plotters::prelude::*;

use crate::error::{InputContext, input_error};
use crate::output::{create_output_file, print_stdout};

/// Arguments of `flapwing sweep contour`.
#[derive(Debug, Args)]
pub struct ContourArgs {
    /// A sweep CSV (`flapwing sweep` output, merged or not).
    #[arg(value_name = "FILE.csv")]
    pub file: PathBuf,
    /// Factor column on the horizontal axis.
    #[arg(long, value_name = "FACTOR")]
    pub x: String,
    /// Factor column on the vertical axis.
    #[arg(long, value_name = "FACTOR")]
    pub y: String,
    /// Response column to map.
    #[arg(long, value_name = "NAME")]
    pub response: String,
    /// Output file (.svg, or .png).
    #[arg(long, value_name = "FILE.svg")]
    pub plot: PathBuf,
    /// Replace the plot if it exists.
    #[arg(long)]
    pub force: bool,
}

/// Runs the command.
pub fn run(args: ContourArgs) -> anyhow::Result<()> {
    let origin = args.file.display().to_string();
    let text = std::fs::read_to_string(&args.file)
        .input_context(format!("cannot read sweep CSV `{origin}`"))?;
    let table = Table::parse(&text, &origin).map_err(|e| input_error(e.to_string()))?;
    let col = |name: &str| -> anyhow::Result<Vec<f64>> {
        let c = table
            .require(name)
            .map_err(|e| input_error(e.to_string()))?;
        table.numbers(c).map_err(|e| input_error(e.to_string()))
    };
    let (xs, ys, zs) = (col(&args.x)?, col(&args.y)?, col(&args.response)?);
    drop(create_output_file(&args.plot, args.force, "plot")?);
    // Mean response per (x, y) cell (other factors averaged out).
    let key = |v: f64| v.to_bits();
    let mut cells: BTreeMap<(u64, u64), (f64, f64, f64, usize)> = BTreeMap::new();
    for ((&x, &y), &z) in xs.iter().zip(&ys).zip(&zs) {
        let e = cells.entry((key(x), key(y))).or_insert((x, y, 0.0, 0));
        e.2 += z;
        e.3 += 1;
    }
    let sorted = |v: &[f64]| {
        let mut u: Vec<f64> = v.to_vec();
        u.sort_by(f64::total_cmp);
        u.dedup();
        u
    };
    let (ux, uy) = (sorted(&xs), sorted(&ys));
    if ux.len() < 2 || uy.len() < 2 {
        return Err(input_error(format!(
            "{origin}: `{}` and `{}` need at least 2 levels each for a map ({} and {})",
            args.x,
            args.y,
            ux.len(),
            uy.len()
        )));
    }
    let cells: Vec<(usize, usize, f64)> = cells
        .values()
        .map(|&(x, y, s, n)| {
            let i = ux.iter().position(|&u| u == x).unwrap_or(0);
            let j = uy.iter().position(|&u| u == y).unwrap_or(0);
            (i, j, s / n as f64)
        })
        .collect();
    let title = format!(
        "{}: {} over {} and {}",
        origin, args.response, args.x, args.y
    );
    let labels = (args.x.as_str(), args.y.as_str());
    crate::plot::render!(
        &args.plot,
        (900, 700),
        draw(&cells, &ux, &uy, labels, &title)
    )?;
    print_stdout(&format!(
        "wrote {} ({} cells)\n",
        args.plot.display(),
        cells.len()
    ))
}

fn draw<DB: DrawingBackend>(
    root: DrawingArea<DB, plotters::coord::Shift>,
    cells: &[(usize, usize, f64)],
    ux: &[f64],
    uy: &[f64],
    labels: (&str, &str),
    title: &str,
) -> anyhow::Result<()>
where
    DB::ErrorType: 'static,
{
    let e = crate::plot::draw_error::<DB::ErrorType>;
    let (lo, hi) = cells
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), c| {
            (a.min(c.2), b.max(c.2))
        });
    let span = (hi - lo).max(1e-300);
    root.fill(&WHITE).map_err(e)?;
    let (nx, ny) = (ux.len() as f64, uy.len() as f64);
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 16))
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(60)
        .build_cartesian_2d(-0.5..nx - 0.5, -0.5..ny - 0.5)
        .map_err(e)?;
    let fx = |v: &f64| {
        ux.get(v.round().max(0.0) as usize)
            .map(|u| format!("{u:.4}"))
            .unwrap_or_default()
    };
    let fy = |v: &f64| {
        uy.get(v.round().max(0.0) as usize)
            .map(|u| format!("{u:.4}"))
            .unwrap_or_default()
    };
    chart
        .configure_mesh()
        .disable_mesh()
        .x_labels(ux.len())
        .y_labels(uy.len())
        .x_label_formatter(&fx)
        .y_label_formatter(&fy)
        .x_desc(labels.0)
        .y_desc(labels.1)
        .draw()
        .map_err(e)?;
    chart
        .draw_series(cells.iter().map(|&(i, j, z)| {
            let t = (z - lo) / span;
            let c = HSLColor(0.66 * (1.0 - t), 0.75, 0.5);
            Rectangle::new(
                [
                    (i as f64 - 0.5, j as f64 - 0.5),
                    (i as f64 + 0.5, j as f64 + 0.5),
                ],
                c.filled(),
            )
        }))
        .map_err(e)?;
    chart
        .draw_series(cells.iter().map(|&(i, j, z)| {
            let color = &BLACK;
            Text::new(
                format!("{z:.4}"),
                (i as f64 - 0.3, j as f64),
                ("sans-serif", 14).into_font().color(color),
            )
        }))
        .map_err(e)?;
    root.present().map_err(e)?;
    Ok(())
}
