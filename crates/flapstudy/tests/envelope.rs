//! The flight envelope (`flapstudy::envelope`): a grid of trims in parallel.
//!
//! The points are independent, so the parallel envelope must equal the points run one by one,
//! in the grid's order; a point beyond the vehicle's reach stays in the table with the reason;
//! a bad grid is refused naming the value and what is allowed.

use flapsim::Vehicle;
use flapsim::flight::FlightCondition;
use flapstudy::envelope::{CSV_HEADER, EnvelopeGrid, envelope, envelope_point, to_csv};

fn bumblebee() -> Vehicle {
    Vehicle::from_toml(flapsim::BUMBLEBEE_TOML, "models/bumblebee.toml").unwrap()
}

#[test]
fn the_parallel_envelope_is_its_points_in_grid_order() {
    let bee = bumblebee();
    let grid = EnvelopeGrid::new(vec![0.0, 1.5, 3.0, 9.0], vec![0.0, 0.3], "test").unwrap();
    let calls = std::sync::atomic::AtomicUsize::new(0);
    let rows = envelope(
        &bee,
        &grid,
        &|_| {
            calls.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        },
        &|| false,
    );
    assert_eq!(calls.into_inner(), 8);
    assert_eq!(rows.len(), 8);
    for (row, c) in rows.iter().zip(grid.conditions()) {
        assert_eq!(row.condition, c);
        assert_eq!(row, &envelope_point(&bee, &c));
    }
    // 9 m/s is beyond the bumblebee's stroke (180 deg): no trim, and why.
    let far = &rows[3];
    assert!(far.point.is_none());
    assert!(
        far.no_trim_reason.contains("no trim at 9.00 m/s") && far.no_trim_reason.contains("180"),
        "{}",
        far.no_trim_reason
    );
    // Every trimmed point balances (residuals at Newton's tolerance) and costs power.
    for r in rows.iter().filter_map(|r| r.point.as_ref()) {
        assert!(r.trim.max_residual() < 1e-7, "{:?}", r.trim);
        assert!(r.point.power.aero_w > 0.0);
        assert!(
            r.margin.fraction > 0.0 && r.margin.fraction < 1.0,
            "{:?}",
            r.margin
        );
    }
    let csv = to_csv(&rows);
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines[0], CSV_HEADER);
    assert_eq!(lines.len(), 9);
    let columns = CSV_HEADER.split(',').count();
    for l in &lines[1..] {
        // The reason is one quoted field (its commas inside the quotes).
        let unquoted = l.split('"').step_by(2).collect::<String>();
        assert_eq!(unquoted.split(',').count(), columns, "{l}");
    }
    assert!(lines[4].starts_with("9,0,0,"), "{}", lines[4]);
}

#[test]
fn a_stop_request_skips_the_points_not_started() {
    let bee = bumblebee();
    let grid = EnvelopeGrid::speeds(0.0, 2.0, 3, "test").unwrap();
    let rows = envelope(&bee, &grid, &|_| {}, &|| true);
    assert!(
        rows.iter()
            .all(|r| r.point.is_none() && r.no_trim_reason == flapstudy::envelope::INTERRUPTED)
    );
}

#[test]
fn bad_grids_say_what_is_allowed() {
    let e = EnvelopeGrid::new(vec![], vec![0.0], "--speeds-m-s")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("--speeds-m-s") && e.contains("empty") && e.contains("at least one"),
        "{e}"
    );
    let e = EnvelopeGrid::new(vec![1.0, f64::INFINITY], vec![0.0], "--speeds-m-s")
        .unwrap_err()
        .to_string();
    assert!(e.contains("inf") && e.contains("[0, 100]"), "{e}");
    let e = EnvelopeGrid::new(vec![1.0], vec![f64::NAN], "--climbs-m-s")
        .unwrap_err()
        .to_string();
    assert!(e.contains("NaN") && e.contains("climb"), "{e}");
    assert!(EnvelopeGrid::speeds(0.0, 1.0, 0, "n").is_err());
    assert_eq!(
        EnvelopeGrid::speeds(0.0, 4.5, 10, "n")
            .unwrap()
            .conditions()[9],
        FlightCondition::new(4.5, 0.0).unwrap()
    );
}
