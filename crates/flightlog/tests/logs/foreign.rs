//! Files that are not flapwing logs give clear errors, never a panic.

use std::borrow::Cow;
use std::collections::BTreeMap;
use std::io::BufWriter;

use flightlog::Error;
use flightlog::check::check_log;
use flightlog::replay::{export_csv, read_summary};

#[test]
fn not_mcap() {
    let dir = tempfile::tempdir().unwrap();
    let text = dir.path().join("notes.mcap");
    std::fs::write(&text, "name = \"drosophila\"\n").unwrap();
    let e = read_summary(&text).unwrap_err();
    assert!(matches!(e, Error::NotMcap { .. }), "{e}");
    assert!(e.to_string().contains("not an MCAP file"), "{e}");
    assert!(e.is_bad_input());
    let empty = dir.path().join("empty.mcap");
    std::fs::write(&empty, "").unwrap();
    let e = read_summary(&empty).unwrap_err();
    assert!(e.to_string().contains("empty"), "{e}");
    let e = check_log(&empty).unwrap_err();
    assert!(matches!(e, Error::NotMcap { .. }), "{e}");
    let missing = dir.path().join("missing.mcap");
    let e = read_summary(&missing).unwrap_err();
    assert!(matches!(e, Error::Io { .. }), "{e}");
    assert!(e.is_bad_input());
    assert!(e.to_string().contains("missing.mcap"), "{e}");
}

#[test]
fn foreign_mcap() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("other.mcap");
    {
        let mut w = mcap::WriteOptions::new()
            .compression_threads(0)
            .library("someone-else")
            .create(BufWriter::new(std::fs::File::create(&path).unwrap()))
            .unwrap();
        let schema = w
            .add_schema("foxglove.Log", "jsonschema", br#"{"type":"object"}"#)
            .unwrap();
        let ch = w
            .add_channel(schema, "/log", "json", &BTreeMap::new())
            .unwrap();
        for i in 0..10u32 {
            w.write_to_known_channel(
                &mcap::records::MessageHeader {
                    channel_id: ch,
                    sequence: i,
                    log_time: u64::from(i),
                    publish_time: u64::from(i),
                },
                br#"{"message":"hi"}"#,
            )
            .unwrap();
        }
        w.write_metadata(&mcap::records::Metadata {
            name: "robot".into(),
            metadata: BTreeMap::from([("a".into(), "b".into())]),
        })
        .unwrap();
        w.attach(&mcap::Attachment {
            log_time: 0,
            create_time: 0,
            name: "x.toml".into(),
            media_type: "application/toml".into(),
            data: Cow::Borrowed(b"a = 1"),
        })
        .unwrap();
        w.finish().unwrap();
    }
    let e = read_summary(&path).unwrap_err();
    assert!(matches!(e, Error::NotFlapwing { .. }), "{e}");
    let msg = e.to_string();
    assert!(msg.contains("not a flapwing log"), "{msg}");
    assert!(msg.contains("someone-else"), "{msg}");
    assert!(e.is_bad_input());
    let e = export_csv(&path, "/log", dir.path().join("x.csv")).unwrap_err();
    assert!(matches!(e, Error::NotFlapwing { .. }), "{e}");
    let e = check_log(&path).unwrap_err();
    assert!(matches!(e, Error::NotFlapwing { .. }), "{e}");
}
