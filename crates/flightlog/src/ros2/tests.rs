//! A ROS 2 bag written with the `mcap` crate, read whole, cut at every byte and with every
//! byte flipped: the reader and the summary never panic, and a cut bag keeps what came
//! before the cut.

use std::collections::BTreeMap;
use std::io::Cursor;
use std::path::Path;

use crate::ros2::bag::parse_bag;
use crate::ros2::summary::{read_topic_table, summarize};

const N: u32 = 40;

/// 40 messages of `p/msg/T` (`int32 a`, `float64 b`) at 100 Hz, in chunks of about 200 bytes.
fn bag() -> Vec<u8> {
    let mut out = Cursor::new(Vec::new());
    {
        let mut w = mcap::WriteOptions::new()
            .compression_threads(0)
            .compression(None)
            .chunk_size(Some(200))
            .library("test")
            .create(&mut out)
            .unwrap();
        let schema = w
            .add_schema("p/msg/T", "ros2msg", b"int32 a\nfloat64 b\n")
            .unwrap();
        let ch = w
            .add_channel(schema, "/t", "cdr", &BTreeMap::new())
            .unwrap();
        for i in 0..N {
            // Header, a at 0, 4 bytes of padding, b at 8 (little endian).
            let mut data = vec![0, 1, 0, 0];
            data.extend_from_slice(&(i as i32).to_le_bytes());
            data.extend_from_slice(&[0; 4]);
            data.extend_from_slice(&(f64::from(i) * 0.5).to_le_bytes());
            let header = mcap::records::MessageHeader {
                channel_id: ch,
                sequence: i,
                log_time: 1_000_000_000 + u64::from(i) * 10_000_000,
                publish_time: 0,
            };
            w.write_to_known_channel(&header, &data).unwrap();
        }
        w.finish().unwrap();
    }
    out.into_inner()
}

#[test]
fn whole_bag_summary() {
    let bytes = bag();
    let b = parse_bag(Path::new("b.mcap"), &bytes).unwrap();
    assert!(b.complete && b.damage.is_none() && b.has_ros2());
    let s = summarize(&b);
    let t = &s.topics[0];
    assert_eq!(
        (t.message_count, t.undecodable, t.problem.as_deref()),
        (40, 0, None)
    );
    assert_eq!(t.start_ns, Some(1_000_000_000));
    assert!((t.span_s - 0.39).abs() < 1e-12);
    assert!((t.rate_hz.unwrap() - 100.0).abs() < 1e-9);
    let table = read_topic_table(&b, "/t").unwrap();
    assert_eq!(table.columns, ["log_time_ns", "a", "b"]);
    assert_eq!(table.rows.len(), 40);
    let row: Vec<&str> = table.rows[3]
        .iter()
        .map(|c| c.as_deref().unwrap())
        .collect();
    assert_eq!(row, ["1030000000", "3", "1.5"]);
    let e = read_topic_table(&b, "/nope").unwrap_err().to_string();
    assert!(
        e.contains("has no channel `/nope`") && e.contains("/t"),
        "{e}"
    );
}

#[test]
fn cut_and_flipped_bags_never_panic() {
    let bytes = bag();
    let mut last = 0;
    for n in 8..bytes.len() {
        let b = parse_bag(Path::new("cut.mcap"), &bytes[..n]).unwrap();
        let got = b.messages.len();
        assert!(
            got >= last && got <= N as usize,
            "cut at {n}: {got} after {last}"
        );
        last = got;
        assert!(!b.complete);
        let d = b.damage.clone().unwrap();
        assert!(d.contains(&format!("{got} messages")), "{d}");
        let s = summarize(&b);
        assert_eq!(s.message_count, got as u64);
    }
    assert_eq!(last, N as usize);
    for i in 0..bytes.len() {
        let mut x = bytes.clone();
        x[i] ^= 0xff;
        if let Ok(b) = parse_bag(Path::new("flip.mcap"), &x) {
            let _ = summarize(&b).to_string();
        }
    }
}
