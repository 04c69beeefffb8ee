//! Recovery of known parameters from synthetic flights with sensor noise.

mod common;

use flapsim::control::Disturbance;
use flapwing_identify::{FitOptions, FlightData, Param, identify};

fn pitch(deg: f64) -> Disturbance {
    Disturbance {
        pitch_deg: deg,
        ..Disturbance::default()
    }
}

#[test]
fn experiment() {
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("hover.mcap");
    let t = std::time::Instant::now();
    common_log(&log, 1.0);
    eprintln!("log {:?}", t.elapsed());
    let data = FlightData::from_mcap(&log).unwrap();
    eprintln!(
        "read {:?} starts {} mocap {}",
        t.elapsed(),
        data.starts.len(),
        data.mocap.len()
    );
    let opts = FitOptions {
        params: Param::parse_list(&std::env::var("P").unwrap()).unwrap(),
        ..FitOptions::default()
    };
    let r = identify(&data, &opts, &mut |_| true).unwrap();
    eprintln!("{r}");
    eprintln!("{:?}", t.elapsed());
}

fn common_log(path: &std::path::Path, duration_s: f64) {
    flapwing_identify::synthetic::hover_log(
        &common::truth(),
        &if std::env::var_os("T").is_some() {
            common::truth()
        } else {
            common::nominal()
        },
        "nominal",
        path,
        &pitch(5.0),
        duration_s,
        Some(2000.0),
        7,
    )
    .unwrap();
}

#[test]
fn debug_replay() {
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("hover.mcap");
    flapwing_identify::synthetic::hover_log(
        &common::truth(),
        &common::truth(),
        "truth",
        &log,
        &pitch(5.0),
        0.2,
        None,
        7,
    )
    .unwrap();
    let data = FlightData::from_mcap(&log).unwrap();
    let v = flapsim::Vehicle::from_toml(&common::truth(), "t").unwrap();
    let st = data.starts[3];
    let mut v = v;
    v.apply_controls(&data.wingbeat_controls[st.wingbeat as usize].unwrap())
        .unwrap();
    let mut sim = flapsim::Simulation::try_new(v.clone(), flapsim::Mode::Free).unwrap();
    sim.start_at_step(st.wingbeat * 100).unwrap();
    sim.set_state(&st.state);
    let tbl = flightlog::replay::read_table(&log, "/vehicle/state").unwrap();
    let ci = |n: &str| tbl.columns.iter().position(|c| c == n).unwrap();
    for j in 0..300 {
        if j % 100 == 0 {
            sim.set_controls(data.wingbeat_controls[st.wingbeat as usize + j / 100].unwrap());
        }
        match sim.step() {
            Ok(o) => {
                if j % 50 == 49 {
                    let row = &tbl.rows[(st.wingbeat * 100) as usize + j];
                    let g =
                        |n: &str| -> f64 { row[ci(n)].as_deref().unwrap_or("0").parse().unwrap() };
                    let s = o.state;
                    eprintln!(
                        "{j} fz {:e} {:e} my {:e} {:e} ph {} {}",
                        o.total.force_n.z,
                        g("applied_force_body_n.z"),
                        o.total.moment_nm.y,
                        g("applied_moment_body_nm.y"),
                        o.phase,
                        g("phase")
                    );
                    eprintln!(
                        "{j} dz {:e} dvz {:e} dwy {:e} dvx {:e} qy {:e} {:e}",
                        s.position_m.z - g("position_m.z"),
                        s.velocity_m_s.z - g("velocity_m_s.z"),
                        s.angular_velocity_body_rad_s.y - g("body_rates_rad_s.y"),
                        s.velocity_m_s.x - g("velocity_m_s.x"),
                        s.world_from_body.j,
                        g("attitude.y")
                    );
                }
                if j % 50 == 0 || j < 3 {
                    let row = &tbl.rows[(st.wingbeat * 100) as usize + j];
                    let g =
                        |n: &str| -> f64 { row[ci(n)].as_deref().unwrap_or("0").parse().unwrap() };
                    eprintln!(
                        "{j} sim z {:e} log z {:e} step {} fz {:e} {:e} fx {:e} {:e} my {:e} {:e} ctl {:?}",
                        o.state.position_m.z,
                        g("position_m.z"),
                        g("step"),
                        o.total.force_n.z,
                        g("applied_force_body_n.z"),
                        o.total.force_n.x,
                        g("applied_force_body_n.x"),
                        o.total.moment_nm.y,
                        g("applied_moment_body_nm.y"),
                        o.controls.amplitude_rad
                    );
                }
            }
            Err(e) => {
                eprintln!("step {j}: {e}");
                break;
            }
        }
    }
}

#[test]
fn debug_inertia() {
    use flapsim::{Mode, Simulation, Vehicle};
    for diag in [
        "[8.1e-14, 4.3e-13, 3.53e-13]",
        "[4.3e-13, 1.1e-13, 3.53e-13]",
        "[4.3e-13, 8.1e-14, 3.53e-13]",
    ] {
        let t = common::replace_line(
            &common::nominal(),
            "inertia_diag_kg_m2 =",
            &format!("inertia_diag_kg_m2 = {diag}"),
        );
        let v = Vehicle::from_toml(&t, "x").unwrap();
        let mut sim = Simulation::new(v, Mode::Free);
        let mut w = None;
        for _ in 0..50 {
            w = Some(sim.step().unwrap().state.angular_velocity_body_rad_s);
        }
        eprintln!("{diag}: w after 50 steps {:?}", w.unwrap());
    }
}
