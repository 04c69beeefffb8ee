//! `--realtime FACTOR` paces a run to the wall clock, and `--foxglove --wait-for-client`
//! holds it until a Foxglove client has subscribed: the real binary serves a paced hover on
//! a loopback port, and a WebSocket client speaking `foxglove.sdk.v1` counts the messages
//! of one channel per wall-clock second. The live view serves the optional channels a run
//! logs too: a hover on the estimate through a gust serves `/estimate`, `/wind` and the
//! sensors.
//!
//! The bounds only ever ask for at least the paced wall time (pacing slows a run, it cannot
//! speed a slow machine up), so a busy machine cannot make them fail.

mod common;

use std::io::{BufRead, BufReader};
use std::net::{SocketAddr, TcpStream};
use std::process::{Child, Command, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use common::{argv, flapwing};

const BIN: &str = env!("CARGO_BIN_EXE_flapwing");
/// Nothing here may take longer (the test fails and kills the binary instead).
const LIMIT: Duration = Duration::from_secs(120);

/// Kills the binary if the test ends early (a failed assertion).
struct Guard(Child);

impl Drop for Guard {
    fn drop(&mut self) {
        if let Ok(None) = self.0.try_wait() {
            let _ = self.0.kill();
            let _ = self.0.wait();
        }
    }
}

/// Starts `flapwing args...` in a fresh directory; its stderr lines come through the
/// receiver (a thread reads them, so the binary never blocks on a full pipe).
fn spawn(args: &[&str]) -> (Guard, mpsc::Receiver<String>, tempfile::TempDir) {
    let dir = tempfile::tempdir().unwrap();
    let mut child = Command::new(BIN)
        .args(args)
        .current_dir(dir.path())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let stderr = child.stderr.take().unwrap();
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        for line in BufReader::new(stderr).lines().map_while(Result::ok) {
            if tx.send(line).is_err() {
                break;
            }
        }
    });
    (Guard(child), rx, dir)
}

/// Waits for the stderr line containing `needle` (all lines so far, for messages).
fn line_with(rx: &mpsc::Receiver<String>, needle: &str, seen: &mut Vec<String>) -> String {
    let start = Instant::now();
    loop {
        let left = LIMIT.saturating_sub(start.elapsed());
        match rx.recv_timeout(left) {
            Ok(line) => {
                seen.push(line.clone());
                if line.contains(needle) {
                    return line;
                }
            }
            Err(e) => panic!("no `{needle}` on stderr ({e}); got: {seen:#?}"),
        }
    }
}

/// Waits for the binary to exit (at most `LIMIT`); its exit code.
fn wait_exit(guard: &mut Guard) -> i32 {
    let start = Instant::now();
    loop {
        if let Some(status) = guard.0.try_wait().unwrap() {
            return status.code().expect("exit code (not killed by a signal)");
        }
        assert!(start.elapsed() < LIMIT, "the binary did not stop by itself");
        std::thread::sleep(Duration::from_millis(10));
    }
}

/// The `ws://127.0.0.1:PORT` URL at the end of a line.
fn ws_url(line: &str) -> String {
    let at = line
        .find("ws://")
        .unwrap_or_else(|| panic!("no URL in `{line}`"));
    line[at..]
        .split_whitespace()
        .next()
        .unwrap()
        .trim_end_matches([',', ';'])
        .to_owned()
}

/// Connects a `foxglove.sdk.v1` client to `url` (the server must accept that subprotocol);
/// the advertised channels (topic -> (id, schema name)).
fn connect(
    url: &str,
) -> (
    tungstenite::WebSocket<TcpStream>,
    std::collections::BTreeMap<String, (u64, String)>,
) {
    let addr: SocketAddr = url.trim_start_matches("ws://").parse().unwrap();
    let stream = TcpStream::connect_timeout(&addr, Duration::from_secs(10)).unwrap();
    stream
        .set_read_timeout(Some(Duration::from_secs(10)))
        .unwrap();
    let mut request = tungstenite::client::IntoClientRequest::into_client_request(url).unwrap();
    request.headers_mut().insert(
        "sec-websocket-protocol",
        tungstenite::http::HeaderValue::from_static("foxglove.sdk.v1"),
    );
    let (mut ws, response) = tungstenite::client(request, stream).unwrap();
    assert_eq!(
        response
            .headers()
            .get("sec-websocket-protocol")
            .and_then(|v| v.to_str().ok()),
        Some("foxglove.sdk.v1")
    );
    // serverInfo, then the advertisement of the run's channels.
    let channels = loop {
        match ws.read().unwrap() {
            tungstenite::Message::Text(text) => {
                let v: serde_json::Value = serde_json::from_str(text.as_str()).unwrap();
                if v["op"] == "advertise" {
                    break v["channels"]
                        .as_array()
                        .unwrap()
                        .iter()
                        .map(|c| {
                            (
                                c["topic"].as_str().unwrap().to_owned(),
                                (
                                    c["id"].as_u64().unwrap(),
                                    c["schemaName"].as_str().unwrap_or("").to_owned(),
                                ),
                            )
                        })
                        .collect();
                }
            }
            other => panic!("before the advertisement: {other:?}"),
        }
    };
    (ws, channels)
}

/// A run started by [`spawn_waiting`], waiting for a Foxglove client.
struct Waiting {
    guard: Guard,
    /// Its stderr lines.
    rx: mpsc::Receiver<String>,
    /// The stderr lines so far (for messages).
    seen: Vec<String>,
    /// Where the live view is served.
    url: String,
    _dir: tempfile::TempDir,
}

/// Starts `flapwing COMMAND --foxglove 127.0.0.1:0 --wait-for-client EXTRA... --no-log`
/// (`extra` split at white space) and waits for the line saying it waits for a client.
fn spawn_waiting(command: &str, extra: &str) -> Waiting {
    let mut args = vec![command, "--foxglove", "127.0.0.1:0", "--wait-for-client"];
    args.extend(argv(extra));
    args.push("--no-log");
    let (guard, rx, dir) = spawn(&args);
    let mut seen = Vec::new();
    let url = ws_url(&line_with(&rx, "waiting for a Foxglove client", &mut seen));
    Waiting {
        guard,
        rx,
        seen,
        url,
        _dir: dir,
    }
}

/// Sends a `subscribe` operation with `subscriptions` (a JSON array of `{id, channelId}`).
fn subscribe(ws: &mut tungstenite::WebSocket<TcpStream>, subscriptions: serde_json::Value) {
    ws.send(tungstenite::Message::Text(
        serde_json::json!({"op": "subscribe", "subscriptions": subscriptions})
            .to_string()
            .into(),
    ))
    .unwrap();
}

/// The subscription id and the log time (ns) of a binary message-data frame.
fn message_data(b: &[u8]) -> (u32, u64) {
    assert!(b.len() >= 13 && b[0] == 1, "not message data: {b:?}");
    (
        u32::from_le_bytes(b[1..5].try_into().unwrap()),
        u64::from_le_bytes(b[5..13].try_into().unwrap()),
    )
}

#[test]
fn the_live_view_serves_the_estimate_the_wind_and_the_sensors() {
    let (duration_s, gust_start_s, gust_end_s) = (0.06, 0.02, 0.04);
    // Paced (0.6 s of wall time): unpaced, the run outruns the socket and the server drops
    // what its client's queue cannot hold.
    let mut run = spawn_waiting(
        "hover",
        "--feedback estimated \
         --disturbance gust_x_m_s=0.2,gust_start_s=0.02,gust_duration_s=0.02 \
         --duration-s 0.06 --realtime 0.1",
    );
    let (mut ws, channels) = connect(&run.url);
    let topics = [
        ("/estimate", "flapwing.Estimate"),
        ("/wind", "flapwing.Wind"),
        ("/sensors/imu", "flapwing.ImuReading"),
        ("/sensors/mocap", "flapwing.MocapReading"),
    ];
    let mut subscriptions = Vec::new();
    for (k, (topic, schema)) in topics.iter().enumerate() {
        let (id, name) = channels
            .get(*topic)
            .unwrap_or_else(|| panic!("{topic} not advertised: {channels:?}"));
        assert_eq!(name, schema, "{topic}");
        subscriptions.push(serde_json::json!({"id": k, "channelId": id}));
    }
    subscribe(&mut ws, subscriptions.into());
    // Each subscription's messages: (log time, payload length).
    let mut got: Vec<Vec<(f64, usize)>> = vec![Vec::new(); topics.len()];
    let start = Instant::now();
    loop {
        assert!(start.elapsed() < LIMIT, "the run did not end");
        match ws.read() {
            Ok(tungstenite::Message::Binary(b)) => {
                let (k, t_ns) = message_data(&b);
                got[k as usize].push((t_ns as f64 * 1e-9, b.len() - 13));
            }
            Ok(tungstenite::Message::Close(_)) | Err(_) => break,
            Ok(_) => {}
        }
    }
    assert_eq!(wait_exit(&mut run.guard), 0, "{:#?}", run.seen);
    for ((topic, _), msgs) in topics.iter().zip(&got) {
        assert!(!msgs.is_empty(), "nothing on {topic}");
        assert!(
            msgs.iter()
                .all(|(t, len)| *t >= 0.0 && *t <= duration_s + 0.02 && *len > 0),
            "{topic}: {msgs:?}"
        );
    }
    // The estimate and the wind come with the logged samples (2000 per second: 120), the IMU
    // at its 1 kHz (60, after its 5 ms latency 55); at least half of each arrives (a server
    // drops what a slow client's queue cannot hold; paced, here none was dropped).
    eprintln!(
        "messages: {:?}",
        got.iter().map(Vec::len).collect::<Vec<_>>()
    );
    assert!(got[0].len() >= 60, "{} estimates", got[0].len());
    assert!(got[1].len() >= 60, "{} winds", got[1].len());
    assert!(got[2].len() >= 25, "{} IMU readings", got[2].len());
    // The wind message is longer while the gust blows (its vectors are no longer zero, and
    // protobuf leaves zeros out).
    let len_at = |t: f64| {
        got[1]
            .iter()
            .min_by(|a, b| (a.0 - t).abs().total_cmp(&(b.0 - t).abs()))
            .unwrap()
            .1
    };
    let (calm, gust) = (
        len_at(0.5 * gust_start_s),
        len_at(0.5 * (gust_start_s + gust_end_s)),
    );
    assert!(
        gust > calm,
        "wind message {calm} B calm, {gust} B in the gust"
    );
}

#[test]
fn a_run_without_an_estimator_advertises_no_estimate() {
    let mut run = spawn_waiting("hover", "--duration-s 0.01");
    let (mut ws, channels) = connect(&run.url);
    assert!(!channels.contains_key("/estimate"), "{channels:?}");
    assert!(!channels.contains_key("/wind"), "{channels:?}");
    // Subscribing releases the run.
    let (id, _) = channels
        .get("/vehicle/pose")
        .expect("/vehicle/pose advertised");
    subscribe(&mut ws, serde_json::json!([{"id": 1, "channelId": id}]));
    while let Ok(m) = ws.read() {
        if matches!(m, tungstenite::Message::Close(_)) {
            break;
        }
    }
    assert_eq!(wait_exit(&mut run.guard), 0, "{:#?}", run.seen);
}

#[test]
fn the_live_view_serves_every_wing_of_the_dragonfly() {
    let mut run = spawn_waiting(
        "simulate",
        "--model dragonfly --duration-s 0.01 --realtime 0.1",
    );
    let (mut ws, channels) = connect(&run.url);
    assert_eq!(
        channels.len(),
        21,
        "7 + 3 per wing + its 2 sensors: {channels:?}"
    );
    let watched = ["/tf/wing_pairs0_left", "/wing/pairs0_right/forces"];
    let mut subscriptions = Vec::new();
    for (k, topic) in watched.iter().enumerate() {
        let (id, _) = channels
            .get(*topic)
            .unwrap_or_else(|| panic!("{topic} not advertised: {channels:?}"));
        subscriptions.push(serde_json::json!({"id": k, "channelId": id}));
    }
    subscribe(&mut ws, subscriptions.into());
    let mut got = [0usize; 2];
    while let Ok(m) = ws.read() {
        match m {
            tungstenite::Message::Binary(b) if b.len() >= 13 && b[0] == 1 => {
                got[message_data(&b).0 as usize] += 1;
            }
            tungstenite::Message::Close(_) => break,
            _ => {}
        }
    }
    assert_eq!(wait_exit(&mut run.guard), 0, "{:#?}", run.seen);
    assert!(got.iter().all(|&n| n > 0), "messages per channel: {got:?}");
}

#[test]
fn paced_hover_is_watched_from_its_first_message() {
    // 0.3 simulated seconds at 0.1 simulated seconds per wall second: 3 s of wall time.
    let (duration_s, factor) = (0.3, 0.1);
    let expected_wall_s = duration_s / factor;
    let mut run = spawn_waiting("hover", "--realtime 0.1 --duration-s 0.3");
    let url = &run.url;
    assert!(url.starts_with("ws://127.0.0.1:"), "{url}");
    assert!(
        !url.ends_with(":0"),
        "the actual port must be printed: {url}"
    );

    // It waits: a second later nothing has run.
    std::thread::sleep(Duration::from_secs(1));
    assert!(
        run.guard.0.try_wait().unwrap().is_none(),
        "the run did not wait for a client"
    );

    let (mut ws, channels) = connect(url);
    let topic = "/vehicle/pose";
    let (channel_id, _) = channels
        .get(topic)
        .unwrap_or_else(|| panic!("{topic} not advertised: {channels:?}"));
    let subscribed_at = Instant::now();
    subscribe(
        &mut ws,
        serde_json::json!([{"id": 7, "channelId": channel_id}]),
    );
    line_with(&run.rx, "a Foxglove client subscribed", &mut run.seen);

    // Every message on the channel: its wall time since the subscription and its log time.
    let mut arrivals: Vec<(f64, u64)> = Vec::new();
    loop {
        assert!(subscribed_at.elapsed() < LIMIT, "the run did not end");
        match ws.read() {
            Ok(tungstenite::Message::Binary(b)) => {
                let (id, log_time_ns) = message_data(&b);
                assert_eq!(id, 7);
                arrivals.push((subscribed_at.elapsed().as_secs_f64(), log_time_ns));
            }
            Ok(tungstenite::Message::Close(_)) => break,
            Ok(_) => {}
            // The server stops at the end of the run (with or without a close frame).
            Err(_) => break,
        }
    }
    let code = wait_exit(&mut run.guard);
    let run_wall_s = subscribed_at.elapsed().as_secs_f64();
    assert_eq!(code, 0, "{:#?}", run.seen);

    // 2000 samples per simulated second on /vehicle/pose, the first one at the start.
    let n = arrivals.len();
    assert!(n >= 500, "{n} messages");
    let first_log_s = arrivals[0].1 as f64 * 1e-9;
    assert!(
        first_log_s < 0.01,
        "the first message is at {first_log_s} s"
    );
    let last_log_s = arrivals[n - 1].1 as f64 * 1e-9;
    assert!(last_log_s > 0.9 * duration_s, "the last at {last_log_s} s");

    // The run took the paced wall time, and the messages came spread over it.
    let span_s = arrivals[n - 1].0 - arrivals[0].0;
    let mut per_second = vec![0usize; arrivals[n - 1].0.ceil() as usize + 1];
    for (wall_s, _) in &arrivals {
        per_second[*wall_s as usize] += 1;
    }
    eprintln!(
        "{n} messages of {topic}; wall: run {run_wall_s:.3} s, messages over {span_s:.3} s \
         (expected {expected_wall_s:.1} s); per wall second since the subscription: {per_second:?}"
    );
    assert!(run_wall_s >= 0.9 * expected_wall_s, "{run_wall_s} s");
    assert!(span_s >= 0.9 * expected_wall_s, "{span_s} s");
    // The first wall second can hold the first 0.1 simulated seconds: a third.
    assert!(
        per_second[0] * 2 < n,
        "the first wall second held most messages: {per_second:?}"
    );
    // No message comes before its time on the schedule (1 ms early at most; 0.5 s for a
    // late delivery of the first message on a busy machine).
    let (w0, t0) = (arrivals[0].0, arrivals[0].1 as f64 * 1e-9);
    for &(w, t_ns) in &arrivals {
        let due = (t_ns as f64 * 1e-9 - t0) / factor;
        assert!(w - w0 >= due - 0.5, "message at {t_ns} ns arrived at {w} s");
    }
}

#[test]
fn paces_without_a_live_view() {
    // simulate, no logs, no viewer: 0.2 simulated seconds at factor 0.2 take 1 s.
    let start = Instant::now();
    let run = flapwing(&[
        "simulate",
        "--no-log",
        "--tethered",
        "--duration-s",
        "0.2",
        "--realtime",
        "0.2",
    ]);
    let wall_s = start.elapsed().as_secs_f64();
    assert_eq!(run.code, 0, "{run:?}");
    assert!(wall_s >= 0.9, "{wall_s} s");
}

#[test]
fn ctrl_c_stops_the_wait() {
    let mut run = spawn_waiting("hover", "");
    let status = Command::new("kill")
        .args(["-INT", &run.guard.0.id().to_string()])
        .status()
        .unwrap();
    assert!(status.success());
    let code = wait_exit(&mut run.guard);
    while let Ok(line) = run.rx.recv_timeout(Duration::from_secs(10)) {
        run.seen.push(line);
    }
    assert_eq!(code, 1, "{:#?}", run.seen);
    let text = run.seen.join("\n");
    assert!(
        text.contains("interrupted by Ctrl-C") && !text.contains("panicked"),
        "{text}"
    );
}

#[test]
fn wait_timeout_runs_anyway() {
    let (mut guard, rx, _dir) = spawn(&[
        "hover",
        "--foxglove",
        "127.0.0.1:0",
        "--wait-for-client",
        "--wait-timeout-s",
        "0.2",
        "--duration-s",
        "0.05",
        "--no-log",
    ]);
    let mut seen = Vec::new();
    line_with(&rx, "no Foxglove client subscribed within 0.2 s", &mut seen);
    assert_eq!(wait_exit(&mut guard), 0, "{seen:#?}");
}

#[test]
fn bad_pacing_flags_are_bad_input() {
    for (flags, needles) in [
        ("--realtime 0", &["--realtime 0", "> 0"][..]),
        ("--realtime=-1", &["--realtime -1", "> 0"]),
        ("--realtime nan", &["--realtime NaN", "finite"]),
        ("--realtime inf", &["--realtime inf", "finite"]),
        ("--wait-for-client", &["--foxglove"]),
        (
            "--foxglove 127.0.0.1:0 --wait-timeout-s 1",
            &["--wait-for-client"],
        ),
        (
            "--foxglove 127.0.0.1:0 --wait-for-client --wait-timeout-s=-1",
            &["--wait-timeout-s -1"],
        ),
    ] {
        for command in ["hover", "simulate"] {
            let mut args = vec![command, "--no-log", "--duration-s", "0.01"];
            args.extend(flags.split_whitespace());
            let run = flapwing(&args);
            run.assert_bad_input();
            for n in needles {
                assert!(run.stderr.contains(n), "`{n}` missing: {run:?}");
            }
        }
    }
}
