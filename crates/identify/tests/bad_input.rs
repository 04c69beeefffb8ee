//! Bad input: clear errors naming the file, the field or column, the value and what is
//! allowed; never a panic.

mod common;

use flapwing_identify::{Error, FitOptions, FlightData, Param, identify};

fn csv_error(text: &str) -> String {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("f.csv");
    std::fs::write(&p, text).unwrap();
    let e = FlightData::from_csv(&p, &common::nominal(), "nominal").unwrap_err();
    assert!(matches!(e, Error::Csv { .. }), "{e}");
    e.to_string()
}

const HEADER: &str = "t_s,x_m,y_m,z_m,qw,qx,qy,qz,mean_stroke_rad,amplitude_rad,diff_amplitude_rad,diff_pitch_bias_rad";

#[test]
fn unsorted_csv_times_are_refused_with_the_line() {
    let e = csv_error(&format!(
        "{HEADER}\n0.002,0,0,0,1,0,0,0,0,0,0,0\n0.001,0,0,0,1,0,0,0,0,0,0,0\n"
    ));
    assert!(
        e.contains("line 3")
            && e.contains("t_s")
            && e.contains("0.001")
            && e.contains("increasing"),
        "{e}"
    );
}

#[test]
fn missing_csv_columns_are_named() {
    let e = csv_error("t_s,x_m,y_m,z_m,qw,qx,qy,qz\n0,0,0,0,1,0,0,0\n");
    assert!(
        e.contains("line 1") && e.contains("mean_stroke_rad") && e.contains("required"),
        "{e}"
    );
    let e = csv_error(&format!("{HEADER},wingspan\n"));
    assert!(e.contains("wingspan") && e.contains("allowed"), "{e}");
}

#[test]
fn bad_csv_values_are_named() {
    let e = csv_error(&format!("{HEADER}\n0,abc,0,0,1,0,0,0,0,0,0,0\n"));
    assert!(e.contains("line 2") && e.contains("`x_m` = `abc`"), "{e}");
    let e = csv_error(&format!("{HEADER}\n0,0,0,0,2,0,0,0,0,0,0,0\n"));
    assert!(e.contains("norm 2"), "{e}");
    let e = csv_error(&format!("{HEADER}\n0,0,0\n"));
    assert!(e.contains("3 fields") && e.contains("12 columns"), "{e}");
    let e = csv_error("");
    assert!(e.contains("no header"), "{e}");
}

/// A log without motion capture (a `simulate` run with --no-sensors): the error names the
/// missing channel and what writes it.
#[test]
fn a_log_without_the_measurements_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("plain.mcap");
    let toml = common::nominal();
    let vehicle = flapsim::Vehicle::from_toml(&toml, "nominal").unwrap();
    let settings = flightlog::SimSettings::new(flapsim::Mode::Free, 0.01, Some(2000.0), [0.0; 3]);
    let info = flightlog::RunInfo::new("simulate", "x", &toml, "nominal", settings.to_json());
    let opts = flightlog::LogOptions {
        mcap: Some(p.clone()),
        log_rate_hz: Some(2000.0),
        ..Default::default()
    };
    let mut rec = flightlog::Recorder::create(&opts, &info, &vehicle).unwrap();
    let mut sim = flapsim::Simulation::new(vehicle, flapsim::Mode::Free);
    for _ in 0..100 {
        let out = *sim.step().unwrap();
        rec.record(&out).unwrap();
    }
    rec.finish().unwrap();
    let e = FlightData::from_mcap(&p).unwrap_err().to_string();
    assert!(
        e.contains("/sensors/mocap")
            && e.contains("plain.mcap")
            && e.contains("channels in the log"),
        "{e}"
    );
    // Not a log at all.
    let q = dir.path().join("text.mcap");
    std::fs::write(&q, "hello").unwrap();
    assert!(FlightData::from_mcap(&q).is_err());
}

#[test]
fn unknown_parameters_and_settings_are_refused() {
    let e = Param::parse_list("inertia_yy_kg_m2,wing_colour")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("wing_colour") && e.contains("allowed") && e.contains("com_offset_x_m"),
        "{e}"
    );
    assert!(Param::parse_list("mass_kg,mass_kg").is_err());
    assert!(Param::parse_list("").is_err());
    let bad = FitOptions {
        segment_wingbeats: 0,
        ..FitOptions::default()
    };
    assert!(bad.check().unwrap_err().to_string().contains("[1, 1000]"));
}

/// The IMU biases need the IMU's samples in the fit.
#[test]
fn imu_parameters_need_the_imu() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("f.csv");
    std::fs::write(
        &p,
        format!("{HEADER}\n0,0,0,0,1,0,0,0,0,0,0,0\n0.001,0,0,0,1,0,0,0,0,0,0,0\n"),
    )
    .unwrap();
    let data = FlightData::from_csv(&p, &common::nominal(), "nominal").unwrap();
    let opts = FitOptions {
        params: Param::parse_list("gyro_bias_x_rad_s").unwrap(),
        ..FitOptions::default()
    };
    let e = identify(&data, &opts, &mut |_| true)
        .unwrap_err()
        .to_string();
    assert!(e.contains("--imu"), "{e}");
}

/// An actuated wing's parameter on a model without that part, and a stop restitution fitted
/// from the inelastic constraint (restitution 0, another contact law), are refused with the
/// table the parameter needs.
#[test]
fn actuated_parameters_need_their_part_of_the_model() {
    let check = |p: &str, toml: &str, origin: &str| {
        let spec = flapsim::VehicleSpec::from_toml(toml, origin).unwrap();
        Param::parse(p)
            .unwrap()
            .check_model(&spec, origin)
            .map_err(|e| e.to_string())
    };
    let e = check("force_per_volt_n_v", flapsim::DROSOPHILA_TOML, "drosophila").unwrap_err();
    assert!(
        e.contains("actuation.piezo.force_per_volt_n_v")
            && e.contains("no [actuation.piezo] table")
            && e.contains("prescribed kinematics"),
        "{e}"
    );
    let e = check("torque_constant_nm_a", flapsim::ROBOBEE_TOML, "robobee").unwrap_err();
    assert!(e.contains("no [actuation.dc_motor] table"), "{e}");
    let e = check("stop_restitution", flapsim::ROBOBEE_TOML, "robobee").unwrap_err();
    assert!(e.contains("no [actuation.hinge.stop] table"), "{e}");
    let e = check("stop_restitution", flapsim::HUMMINGBIRD_TOML, "hummingbird").unwrap_err();
    assert!(
        e.contains("restitution 0") && e.contains("[0.01, 1]"),
        "{e}"
    );
    check(
        "torque_constant_nm_a",
        flapsim::HUMMINGBIRD_TOML,
        "hummingbird",
    )
    .unwrap();
    check("hinge_stiffness_nm_rad", flapsim::ROBOBEE_TOML, "robobee").unwrap();
    check("inertia_yy_kg_m2", flapsim::DROSOPHILA_TOML, "drosophila").unwrap();
}
