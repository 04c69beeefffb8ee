//! Physics invariants of flapsim's sensors (crates/flapsim/src/sensors.rs).

use flapsim::sensors::{Imu, ImuParams, Mocap, MocapParams, Sensors};
use flapsim::{Mode, Simulation, State, Vehicle};
use nalgebra::{UnitQuaternion, Vector3};

const G: f64 = 9.81;

fn quiet(rate_hz: f64, latency_s: f64) -> ImuParams {
    ImuParams {
        rate_hz,
        latency_s,
        gyro_noise_density: 0.0,
        gyro_bias_rad_s: 0.0,
        gyro_bias_walk: 0.0,
        accel_noise_density: 0.0,
        accel_bias_m_s2: 0.0,
        accel_bias_walk: 0.0,
    }
}

fn at_rest(q: UnitQuaternion<f64>) -> State {
    State {
        position_m: Vector3::zeros(),
        world_from_body: q,
        velocity_m_s: Vector3::zeros(),
        angular_velocity_body_rad_s: Vector3::zeros(),
    }
}

fn std(xs: &[f64]) -> (f64, f64) {
    let n = xs.len() as f64;
    let m = xs.iter().sum::<f64>() / n;
    let v = xs.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / (n - 1.0);
    (m, v.sqrt())
}

#[test]
fn noiseless_imu_at_rest_reads_plus_g_on_z_and_no_rotation() {
    // A level body at rest: specific force = R^T (a - g_world) = (0, 0, +g) exactly.
    let mut imu = Imu::new(quiet(1000.0, 0.0), G, 1);
    imu.observe(0.0, &at_rest(UnitQuaternion::identity()), &Vector3::zeros());
    let s = imu
        .read(0.0)
        .expect("the sample at t = 0 is delivered at once");
    assert_eq!(s.accel_m_s2, Vector3::new(0.0, 0.0, G));
    assert_eq!(s.gyro_rad_s, Vector3::zeros());
}

#[test]
fn tethered_vehicle_reads_gravity_in_its_body_frame_and_free_fall_reads_zero() {
    let params = quiet(1000.0, 0.0);
    let v = Vehicle::from_toml(flapsim::DROSOPHILA_TOML, "drosophila.toml").unwrap();
    // Tethered at the model's 45 deg pitch, wings still: the tether holds the weight, so
    // the accelerometer reads the reaction, R^T (0, 0, g), magnitude g.
    let mut sim = Simulation::new(v.clone(), Mode::Tethered);
    sim.set_wings_still(true);
    let mut sensors = Sensors::new(
        &flapsim::sensors::SensorParams {
            imu: params,
            mocap: None,
        },
        G,
        7,
    );
    for _ in 0..200 {
        sim.step().unwrap();
        sensors.observe(sim.time_s(), &sim.state());
    }
    let s = sensors.imu.read(sim.time_s()).unwrap();
    let expect = sim.state().world_from_body.inverse() * Vector3::new(0.0, 0.0, G);
    assert!(
        (s.accel_m_s2 - expect).norm() < 1e-12 * G,
        "{:?}",
        s.accel_m_s2
    );
    assert!((s.accel_m_s2.norm() - G).abs() < 1e-12 * G);
    // Free fall with the wings still: no specific force at all (the equivalence principle),
    // up to rapier's round-off in the velocity.
    let mut sim = Simulation::new(v, Mode::Free);
    sim.set_wings_still(true);
    let mut sensors = Sensors::new(
        &flapsim::sensors::SensorParams {
            imu: params,
            mocap: None,
        },
        G,
        7,
    );
    for _ in 0..200 {
        sim.step().unwrap();
        sensors.observe(sim.time_s(), &sim.state());
    }
    let s = sensors.imu.read(sim.time_s()).unwrap();
    assert!(s.accel_m_s2.norm() < 1e-9 * G, "{:?}", s.accel_m_s2);
}

#[test]
fn white_noise_std_is_density_times_sqrt_rate() {
    // sigma = n sqrt(rate) (IEEE Std 952's discrete white noise). 20,000 samples per axis:
    // the sample std's relative standard error is 1/sqrt(2 N) = 0.5%, so 3% is 6 sigma.
    let rate = 1000.0;
    let mut p = quiet(rate, 0.0);
    p.gyro_noise_density = 0.004f64.to_radians(); // ICM-20602, 4 mdps/sqrt(Hz)
    p.accel_noise_density = 100e-6 * 9.80665; // ICM-20602, 100 ug/sqrt(Hz)
    let mut imu = Imu::new(p, G, 42);
    let rest = at_rest(UnitQuaternion::identity());
    let (mut gx, mut az) = (Vec::new(), Vec::new());
    for k in 0..20_000 {
        let t = k as f64 / rate;
        imu.observe(t, &rest, &Vector3::zeros());
        let s = imu.read(t).unwrap();
        assert!((s.t_s - t).abs() < 1e-12);
        gx.push(s.gyro_rad_s.x);
        az.push(s.accel_m_s2.z);
    }
    let (mg, sg) = std(&gx);
    let (ma, sa) = std(&az);
    let want_g = p.gyro_noise_density * rate.sqrt();
    let want_a = p.accel_noise_density * rate.sqrt();
    assert!(
        (sg / want_g - 1.0).abs() < 0.03,
        "gyro std {sg} vs {want_g}"
    );
    assert!(
        (sa / want_a - 1.0).abs() < 0.03,
        "accel std {sa} vs {want_a}"
    );
    // Zero-mean noise: means within 6 standard errors of 0 and of +g.
    assert!(mg.abs() < 6.0 * want_g / (20_000f64).sqrt());
    assert!((ma - G).abs() < 6.0 * want_a / (20_000f64).sqrt());
}

#[test]
fn latency_delays_by_whole_samples() {
    // Rate 1 kHz, latency 3 ms: at time t the newest sample is the one taken at t - 3 ms.
    let rate = 1000.0;
    let mut imu = Imu::new(quiet(rate, 3e-3), G, 3);
    for k in 0..50u32 {
        let t = f64::from(k) / rate;
        // The body's roll rate equals the sample index: the reading names its sample.
        let mut s = at_rest(UnitQuaternion::identity());
        s.angular_velocity_body_rad_s.x = f64::from(k);
        imu.observe(t, &s, &Vector3::zeros());
        let r = imu.read(t);
        if k < 3 {
            assert!(
                r.is_none(),
                "nothing is delivered before the latency at k = {k}"
            );
        } else {
            let r = r.unwrap();
            assert_eq!(r.gyro_rad_s.x, f64::from(k - 3));
            assert!((r.t_s - (t - 3e-3)).abs() < 1e-12);
        }
    }
}

#[test]
fn bias_walk_grows_as_sqrt_time_and_seeds_reproduce() {
    // A random walk of coefficient b moves by b sqrt(T) (1 sigma) in T: over 400 IMUs the
    // std of the bias after 1 s is b within the 400-sample std's error (3.5%, 5 sigma 18%).
    let b = 0.0012f64.to_radians();
    let mut p = quiet(1000.0, 0.0);
    p.gyro_bias_walk = b;
    let rest = at_rest(UnitQuaternion::identity());
    let mut end = Vec::new();
    for seed in 0..400 {
        let mut imu = Imu::new(p, G, seed);
        for k in 0..1000 {
            imu.observe(k as f64 / 1000.0, &rest, &Vector3::zeros());
        }
        end.push(imu.biases().0.y);
    }
    let (_, s) = std(&end);
    assert!((s / b - 1.0).abs() < 0.18, "bias after 1 s: std {s} vs {b}");
    // Same seed, same samples; another seed, other samples.
    let mut q = p;
    q.gyro_noise_density = 1e-3;
    let run = |seed| {
        let mut imu = Imu::new(q, G, seed);
        (0..100)
            .map(|k| {
                let t = k as f64 / 1000.0;
                imu.observe(t, &rest, &Vector3::zeros());
                imu.read(t).unwrap().gyro_rad_s
            })
            .collect::<Vec<_>>()
    };
    assert_eq!(run(5), run(5));
    assert_ne!(run(5), run(6));
}

#[test]
fn mocap_noise_and_delay() {
    let p = MocapParams {
        rate_hz: 200.0,
        latency_s: 10e-3,
        position_noise_m: 1.5e-4,
        attitude_noise_rad: 0.0,
    };
    let mut m = Mocap::new(p, 9);
    let mut xs = Vec::new();
    for k in 0..4000 {
        let t = k as f64 / 200.0;
        m.observe(t, &at_rest(UnitQuaternion::identity()));
        let r = m.read(t);
        if k < 2 {
            assert!(r.is_none());
        } else {
            let r = r.unwrap();
            assert!((r.t_s - (t - 10e-3)).abs() < 1e-12);
            xs.push(r.position_m.x);
        }
    }
    let (_, s) = std(&xs);
    assert!((s / 1.5e-4 - 1.0).abs() < 0.1, "position noise std {s}");
}

#[test]
fn the_default_model_carries_its_sensors() {
    let v = Vehicle::from_toml(flapsim::DROSOPHILA_TOML, "drosophila.toml").unwrap();
    let s = v.sensors.expect("drosophila.toml has [sensors]");
    assert_eq!(s.imu.rate_hz, 1000.0);
    assert!((s.imu.gyro_noise_density - 0.004f64.to_radians()).abs() < 1e-15);
    let bad = flapsim::DROSOPHILA_TOML.replace("rate_hz = 1000.0", "rate_hz = -1.0");
    let e = Vehicle::from_toml(&bad, "bad.toml")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("bad.toml") && e.contains("sensors.imu.rate_hz"),
        "{e}"
    );
}
