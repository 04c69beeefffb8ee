//! Record a short drosophila flight to MCAP and read everything back.

use crate::common;

use std::collections::BTreeMap;

use common::{ORIGIN, mcap_opts, record, wingbeats};
use flightlog::check::{CheckOutcome, check_log};
use flightlog::replay::{export_csv, read_summary};
use flightlog::schema::{self, CHANNELS};
use flightlog::{Decimator, SimSettings};
use nalgebra::{UnitQuaternion, Vector3};
use serde_json::Value;
use wingforce::wing::WingFrame;

fn close(a: f64, b: f64) -> bool {
    // Protobuf doubles are the bits themselves, but proto3 leaves zeros off the wire, so a
    // -0.0 reads back as 0.0.
    a.to_bits() == b.to_bits() || (a == 0.0 && b == 0.0)
}

fn assert_vec(v: &Value, expect: &Vector3<f64>, what: &str) {
    for (k, e) in ["x", "y", "z"].iter().zip(expect.iter()) {
        let got = v[k]
            .as_f64()
            .unwrap_or_else(|| panic!("{what}.{k} missing: {v}"));
        assert!(close(got, *e), "{what}.{k}: {got} vs {e}");
    }
}

#[test]
fn round_trip_full_rate() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("run.mcap");
    // 100 wingbeats at the fly's 20 steps per wingbeat.
    let duration = wingbeats(100.0);
    let run = record(&mcap_opts(&path, None), "simulate", duration);
    let n = run.outs.len() as u64;
    assert_eq!(n, 2000);
    assert_eq!(run.stats.samples, n);
    assert_eq!(run.stats.steps_seen, n);

    // The summary.
    let s = read_summary(&path).unwrap();
    assert!(s.complete, "{:?}", s.damage);
    assert_eq!(s.damage, None);
    assert_eq!(s.samples, n);
    assert_eq!(s.message_count, run.stats.mcap_messages);
    // The force arrows: at most FORCE_ARROWS_MAX_RATE_HZ per second (by log time).
    let mut arrow_decimator = Decimator::new(Some(schema::FORCE_ARROWS_MAX_RATE_HZ));
    let arrow_steps: BTreeMap<u64, usize> = run
        .outs
        .iter()
        .enumerate()
        .filter(|(_, o)| arrow_decimator.take(o.t_s))
        .map(|(k, o)| ((o.t_s * 1e9).round() as u64, k))
        .collect();
    // 2000 arrows a second against the fly's 4360 steps.
    let most = (duration * schema::FORCE_ARROWS_MAX_RATE_HZ).ceil() as usize + 1;
    assert!(arrow_steps.len() <= most && arrow_steps.len() < run.outs.len() / 2);
    let topics: Vec<&str> = s.channels.iter().map(|c| c.topic.as_str()).collect();
    assert_eq!(topics.len(), CHANNELS.len());
    for (topic, schema_name) in CHANNELS {
        let c = s.channels.iter().find(|c| c.topic == topic).unwrap();
        assert_eq!(c.schema_name, schema_name);
        assert_eq!(c.schema_encoding, "protobuf");
        assert_eq!(c.message_encoding, "protobuf");
        let expect = if topic == schema::TOPIC_EVENTS {
            run.stats.events
        } else if topic == schema::TOPIC_SCENE {
            1
        } else if topic == schema::TOPIC_SCENE_FORCES {
            arrow_steps.len() as u64
        } else {
            n
        };
        assert_eq!(c.message_count, expect, "{topic}");
    }
    // Metadata and attachment.
    let md = &s.metadata;
    assert_eq!(md["version"], env!("CARGO_PKG_VERSION"));
    assert_eq!(md["command"], "simulate");
    assert!(md["command_line"].starts_with("flapwing simulate"));
    assert_eq!(md["model_toml"], flapsim::DROSOPHILA_TOML);
    assert_eq!(md["model_origin"], ORIGIN);
    assert_eq!(
        SimSettings::from_json(&md["settings"]).unwrap(),
        run.settings
    );
    assert_eq!(s.settings(), Some(run.settings.clone()));
    let end = s.end_metadata.as_ref().expect("flapwing.end");
    assert_eq!(end["samples"], n.to_string());
    assert_eq!(s.attachments.len(), 1);
    assert_eq!(s.attachments[0].name, ORIGIN);
    assert_eq!(s.attachments[0].media_type, "application/toml");
    assert_eq!(
        s.attachments[0].bytes,
        flapsim::DROSOPHILA_TOML.len() as u64
    );
    // Times are simulation time.
    assert_eq!(s.start_s, 0.0);
    let last_t = run.outs.last().unwrap().t_s;
    assert!((s.end_s - last_t).abs() < 1e-9, "{} vs {last_t}", s.end_s);

    // Cycle means agree with flapsim's own summary (massless wings: total = aerodynamic).
    let cm = s.cycle_mean.as_ref().unwrap();
    assert_eq!(cm.wingbeats, run.summary.wingbeats_averaged);
    let scale = run.vehicle.weight_n();
    for k in 0..3 {
        let (a, b) = (cm.force_body_n[k], run.summary.mean_total.force_n[k]);
        assert!((a - b).abs() < 1e-9 * scale, "force[{k}] {a} vs {b}");
        let (a, b) = (cm.moment_body_nm[k], run.summary.mean_total.moment_nm[k]);
        assert!(
            (a - b).abs() < 1e-9 * scale * run.vehicle.length_m,
            "moment[{k}] {a} vs {b}"
        );
    }
    let lw = cm.lift_over_weight.unwrap();
    assert!(
        (lw - run.summary.mean_lift_over_weight).abs() < 1e-9,
        "{lw}"
    );
    let p0 = run.outs[0].state.position_m;
    let exc = run
        .outs
        .iter()
        .map(|o| (o.state.position_m - p0).norm())
        .fold(0.0, f64::max);
    assert!(
        (s.max_excursion_m - exc).abs() <= 1e-12 * exc.max(1e-9),
        "{}",
        s.max_excursion_m
    );

    // Every message, read with the mcap crate itself.
    let bytes = std::fs::read(&path).unwrap();
    let mut counts: BTreeMap<String, usize> = BTreeMap::new();
    let wings_static: Vec<_> = run
        .vehicle
        .wings
        .iter()
        .map(|w| {
            (
                w.mount().side,
                w.mount().hinge_in_body_m,
                *w.body_from_stroke(),
            )
        })
        .collect();
    for m in mcap::MessageStream::new(&bytes).unwrap() {
        let m = m.unwrap();
        let topic = m.channel.topic.clone();
        let v = common::decode(&m);
        assert_eq!(m.log_time, m.publish_time);
        // A scene update has its times in its entities.
        let ts = if topic == schema::TOPIC_SCENE || topic == schema::TOPIC_SCENE_FORCES {
            &v["entities"][0]["timestamp"]
        } else {
            &v["timestamp"]
        };
        assert_eq!(
            ts["seconds"].as_u64().unwrap() * 1_000_000_000 + ts["nanos"].as_u64().unwrap(),
            m.log_time
        );
        let i = counts.entry(topic.clone()).or_default();
        let k = *i;
        *i += 1;
        if topic == schema::TOPIC_EVENTS {
            assert_eq!(v["level"], 3, "{v}");
            continue;
        }
        if topic == schema::TOPIC_SCENE {
            // Once, with the first sample: each wing's planform, locked to its frame.
            assert_eq!(k, 0);
            assert_eq!(m.log_time, (run.outs[0].t_s * 1e9).round() as u64);
            let entities = v["entities"].as_array().unwrap();
            assert_eq!(entities.len(), 2);
            for (e, frame) in entities.iter().zip(["wing_left", "wing_right"]) {
                assert_eq!(e["frame_id"], frame);
                assert_eq!(e["frame_locked"], true);
                let points = e["triangles"][0]["points"].as_array().unwrap();
                assert!(points.len() >= 3 && points.len() % 3 == 0);
            }
            continue;
        }
        let out = if topic == schema::TOPIC_SCENE_FORCES {
            &run.outs[arrow_steps[&m.log_time]]
        } else {
            &run.outs[k]
        };
        assert_eq!(m.log_time, (out.t_s * 1e9).round() as u64);
        match topic.as_str() {
            "/vehicle/state" => {
                assert_eq!(v["step"], out.step);
                assert_vec(&v["position_m"], &out.state.position_m, "position");
                assert_vec(&v["velocity_m_s"], &out.state.velocity_m_s, "velocity");
                assert_vec(
                    &v["body_rates_rad_s"],
                    &out.state.angular_velocity_body_rad_s,
                    "rates",
                );
                assert_vec(&v["applied_force_body_n"], &out.total.force_n, "force");
                let q = &out.state.world_from_body;
                assert!(close(v["attitude"]["w"].as_f64().unwrap(), q.w));
                assert!(close(v["attitude"]["x"].as_f64().unwrap(), q.i));
            }
            "/vehicle/pose" => {
                assert_eq!(v["frame_id"], "world");
                assert_vec(&v["pose"]["position"], &out.state.position_m, "pose");
            }
            "/tf/base_link" => {
                assert_eq!(v["parent_frame_id"], "world");
                assert_eq!(v["child_frame_id"], "base_link");
                assert_vec(&v["translation"], &out.state.position_m, "tf");
            }
            "/tf/wing_left" | "/tf/wing_right" => {
                let w = usize::from(topic == "/tf/wing_right");
                let (side, hinge, bfs) = wings_static[w];
                assert_eq!(v["parent_frame_id"], "base_link");
                assert_eq!(v["child_frame_id"], ["wing_left", "wing_right"][w]);
                assert_vec(&v["translation"], &hinge, "hinge");
                let r = &v["rotation"];
                let q = UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(
                    r["w"].as_f64().unwrap(),
                    r["x"].as_f64().unwrap(),
                    r["y"].as_f64().unwrap(),
                    r["z"].as_f64().unwrap(),
                ));
                // The wing frame's axes: x = e_le, y = e_span (in the body frame).
                let fr = WingFrame::new(&out.wings[w].angles, side);
                let (le, span) = (bfs * fr.e_le, bfs * fr.e_span);
                assert!((q * Vector3::x() - le).norm() < 1e-12, "e_le");
                assert!((q * Vector3::y() - span).norm() < 1e-12, "e_span");
            }
            "/wing/left/kinematics" | "/wing/right/kinematics" => {
                let w = usize::from(topic.starts_with("/wing/right"));
                let a = &out.wings[w].angles;
                assert!(close(v["angles_rad"]["phi"].as_f64().unwrap(), a.phi));
                assert!(close(
                    v["rates_rad_s"]["theta"].as_f64().unwrap(),
                    a.theta_dot
                ));
                assert!(close(
                    v["angles_deg"]["theta"].as_f64().unwrap(),
                    a.theta.to_degrees()
                ));
                assert!(close(
                    v["t_star"].as_f64().unwrap(),
                    out.wings[w].phase.t_star
                ));
                assert_eq!(v["half_stroke"], out.wings[w].phase.half_stroke);
                assert_eq!(v["downstroke"], out.wings[w].phase.downstroke);
            }
            "/wing/left/forces" | "/wing/right/forces" => {
                let w = usize::from(topic.starts_with("/wing/right"));
                let f = &out.wings[w];
                let hinge = wings_static[w].1;
                for (j, part) in schema::FORCE_PARTS.iter().enumerate() {
                    let t = if j < 4 { &f.terms[j] } else { &f.total };
                    assert_vec(&v[part]["force_n"], &t.force_n, part);
                    assert_vec(&v[part]["moment_nm"], &t.moment_about_com_nm(&hinge), part);
                    assert!(close(v[part]["c_l"].as_f64().unwrap(), t.c_l), "{part}");
                    assert!(close(v[part]["c_d"].as_f64().unwrap(), t.c_d), "{part}");
                }
            }
            "/scene/forces" => {
                // The arrows are the wings' total forces: length |F| / weight * body length.
                let m_per_n = run.vehicle.length_m / run.vehicle.weight_n();
                for (w, e) in common::force_arrows(&v).iter().enumerate() {
                    assert_eq!(e.frame_id, "base_link");
                    assert_eq!(e.position, wings_static[w].1);
                    let f = out.wings[w].total.force_n;
                    assert!(
                        (e.vector / m_per_n - f).norm() <= 1e-12 * f.norm(),
                        "step {} wing {w}: arrow {} for {f}",
                        out.step,
                        e.vector / m_per_n
                    );
                }
            }
            "/vehicle/controls" => {
                assert!(close(
                    v["amplitude_deg"].as_f64().unwrap(),
                    out.controls.amplitude_rad.to_degrees()
                ));
            }
            other => panic!("unexpected topic {other}"),
        }
    }
    assert_eq!(
        counts.len(),
        CHANNELS.len() - usize::from(run.stats.events == 0)
    );

    // And the trajectory re-runs bit for bit.
    match check_log(&path).unwrap() {
        CheckOutcome::Match { samples, note } => {
            assert_eq!(samples, n);
            assert_eq!(note, None);
        }
        other => panic!("{other:?}"),
    }

    // CSV export: exact numbers, dotted columns.
    let csv = dir.path().join("state.csv");
    let st = export_csv(&path, "/vehicle/state", &csv).unwrap();
    assert_eq!(st.rows, n);
    assert_eq!(st.skipped, 0);
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    assert_eq!(header[0], "log_time_ns");
    assert!(header.contains(&"position_m.z") && header.contains(&"euler_deg.pitch"));
    let col = header.iter().position(|h| *h == "position_m.z").unwrap();
    for (k, line) in lines.enumerate() {
        let cells: Vec<&str> = line.split(',').collect();
        let z: f64 = cells[col].parse().unwrap();
        assert_eq!(z.to_bits(), run.outs[k].state.position_m.z.to_bits());
    }
    assert_eq!(st.columns as usize, header.len());
    let e = export_csv(&path, "/no/such", dir.path().join("x.csv")).unwrap_err();
    assert!(e.to_string().contains("/vehicle/state"), "{e}");
}

#[test]
fn decimation_keeps_about_the_rate() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("run.mcap");
    let duration = wingbeats(20.0);
    let run = record(&mcap_opts(&path, Some(2000.0)), "simulate", duration);
    let expect = (duration * 2000.0).ceil() as u64;
    assert!(
        run.stats.samples.abs_diff(expect) <= 1,
        "{} samples for {expect}",
        run.stats.samples
    );
    let s = read_summary(&path).unwrap();
    assert_eq!(s.samples, run.stats.samples);
    assert_eq!(s.metadata["log_rate_hz"], "2000");
    // Samples sit on the 0.5 ms grid, at most one step late.
    let dt = 1.0 / (run.vehicle.freq_hz() * run.vehicle.sim.steps_per_wingbeat as f64);
    let mut d = Decimator::new(Some(2000.0));
    let picked: Vec<f64> = run
        .outs
        .iter()
        .filter(|o| d.take(o.t_s))
        .map(|o| o.t_s)
        .collect();
    assert_eq!(picked.len() as u64, run.stats.samples);
    for t in &picked {
        let late = t - (t * 2000.0).floor() / 2000.0;
        assert!(late < dt + 1e-12, "{t}");
    }
    assert!(matches!(
        check_log(&path).unwrap(),
        CheckOutcome::Match { .. }
    ));
    // The cycle mean still exists and is close to the full-rate one (sampled coarsely).
    let cm = s.cycle_mean.unwrap();
    assert!(cm.wingbeats >= 19);
    let lw = cm.lift_over_weight.unwrap();
    assert!((lw - run.summary.mean_lift_over_weight).abs() < 0.2, "{lw}");
}

#[test]
fn wake_capture_outside_its_range_is_an_event() {
    // Drosophila flies below the wake-capture fit's Re range (136-6800) or not; either way
    // the recorder's event count matches the wings' flags.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("run.mcap");
    let run = record(&mcap_opts(&path, Some(2000.0)), "simulate", wingbeats(2.0));
    let flagged = run
        .vehicle
        .wings
        .iter()
        .filter(|w| w.wake_capture().is_some_and(|p| p.flags.any()))
        .count() as u64;
    assert_eq!(run.stats.events, flagged);
    let s = read_summary(&path).unwrap();
    assert_eq!(s.events.len() as u64, flagged);
    for e in &s.events {
        assert_eq!(e.level, "WARNING");
        assert!(e.message.contains("wake-capture"), "{}", e.message);
        assert_eq!(e.t_s, 0.0);
    }
}

#[test]
fn bad_options_fail_before_the_run() {
    let toml = flapsim::DROSOPHILA_TOML;
    let vehicle = flapsim::Vehicle::from_toml(toml, ORIGIN).unwrap();
    let info = flightlog::RunInfo::new("simulate", "x", toml, ORIGIN, "{}");
    let dir = tempfile::tempdir().unwrap();
    for rate in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        let e = flightlog::Recorder::create(
            &mcap_opts(&dir.path().join("a.mcap"), Some(rate)),
            &info,
            &vehicle,
        )
        .unwrap_err();
        assert!(e.is_bad_input(), "{e}");
    }
    let e = flightlog::Recorder::create(
        &mcap_opts(&dir.path().join("no/such/dir/a.mcap"), None),
        &info,
        &vehicle,
    )
    .unwrap_err();
    assert!(e.to_string().contains("cannot create"), "{e}");
    // Nothing asked for: a recorder that records nothing.
    let mut rec =
        flightlog::Recorder::create(&flightlog::LogOptions::default(), &info, &vehicle).unwrap();
    let mut sim = flapsim::Simulation::new(vehicle, flapsim::Mode::Free);
    rec.record(&sim.step().unwrap()).unwrap();
    assert_eq!(rec.finish().unwrap().mcap_messages, 0);
}

#[test]
fn dropped_recorder_still_finishes_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("dropped.mcap");
    let toml = flapsim::DROSOPHILA_TOML;
    let vehicle = flapsim::Vehicle::from_toml(toml, ORIGIN).unwrap();
    let info = flightlog::RunInfo::new("identify", "flapwing identify", toml, ORIGIN, "{}");
    {
        let mut rec =
            flightlog::Recorder::create(&mcap_opts(&path, None), &info, &vehicle).unwrap();
        let mut sim = flapsim::Simulation::new(vehicle, flapsim::Mode::Free);
        for _ in 0..50 {
            rec.record(&sim.step().unwrap()).unwrap();
        }
        rec.event(sim.time_s(), flightlog::Level::Error, "stopped by test")
            .unwrap();
    }
    let s = read_summary(&path).unwrap();
    assert!(s.complete);
    assert_eq!(s.samples, 50);
    assert!(s.end_metadata.is_some());
    assert_eq!(s.events.last().unwrap().level, "ERROR");
    assert!(matches!(
        check_log(&path).unwrap(),
        CheckOutcome::NotCheckable { .. }
    ));
}

#[test]
fn actuated_wings_log_their_hinge_and_actuator() {
    // The actuated RoboBee: its kinematics messages carry the dynamics' own angles and the
    // hinge and actuator state of the same step, equal to what the simulation produced.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("robobee.mcap");
    let run = common::record_model(
        &mcap_opts(&path, None),
        "simulate",
        2.0 / 160.0,
        flapsim::Mode::Tethered,
        flapsim::ROBOBEE_TOML,
        "robobee.toml",
    );
    let bytes = std::fs::read(&path).unwrap();
    let mut k = 0;
    for m in mcap::MessageStream::new(&bytes).unwrap() {
        let m = m.unwrap();
        if m.channel.topic != schema::TOPIC_KIN_RIGHT {
            continue;
        }
        let v = common::decode(&m);
        let out = &run.outs[k];
        let a = &out.actuated.as_ref().expect("actuated output")[1];
        let x = &v["actuation"];
        assert!(
            close(x["voltage_v"].as_f64().unwrap(), a.actuator.voltage_v),
            "{v}"
        );
        assert!(close(
            x["displacement_m"].as_f64().unwrap(),
            a.actuator.displacement_m
        ));
        assert!(close(
            x["hinge_moment_nm"].as_f64().unwrap(),
            a.hinge_moment_nm
        ));
        assert!(close(
            x["aero_pitch_moment_nm"].as_f64().unwrap(),
            a.aero_pitch_nm
        ));
        assert!(close(
            v["angles_rad"]["theta"].as_f64().unwrap(),
            a.angles.theta
        ));
        k += 1;
    }
    assert_eq!(k, run.outs.len());
    // The controls message carries the drive offsets (zero here: the model's own drive).
    let controls = mcap::MessageStream::new(&bytes)
        .unwrap()
        .map(|m| m.unwrap())
        .find(|m| m.channel.topic == schema::TOPIC_CONTROLS)
        .expect("a controls message");
    let v = common::decode(&controls);
    assert_eq!(v["drive"]["amplitude_v"], 0.0, "{v}");
    // The drive swings through its amplitude and the pitch moves off the hinge's rest.
    let volts = run
        .outs
        .iter()
        .map(|o| o.actuated.unwrap()[1].actuator.voltage_v.abs());
    // models/robobee.toml drives at 90 V amplitude.
    assert!(volts.fold(0.0, f64::max) > 85.0);
}
