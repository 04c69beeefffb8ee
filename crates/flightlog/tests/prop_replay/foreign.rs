//! Foreign MCAP files: valid MCAP written with the `mcap` crate without flapwing metadata
//! (random channels, messages, metadata, attachments, chunking and compression).
//! `read_summary` and `check_log` say "not a flapwing log" naming the file; `export_csv`
//! never panics; cut in half, the same or an MCAP error naming the file.

use std::borrow::Cow;
use std::collections::BTreeMap;
use std::io::Cursor;

use flightlog::Error;
use flightlog::check::check_log;
use flightlog::replay::read_summary;
use proptest::prelude::*;
use proptest::sample::Index;

use crate::checks::{check_read_error, config, csv_of, guarded};

#[derive(Debug, Clone)]
struct Foreign {
    channels: Vec<(String, String, String)>,
    messages: Vec<(Index, u64, Vec<u8>)>,
    metadata: Vec<(String, BTreeMap<String, String>)>,
    attachments: Vec<(String, Vec<u8>)>,
    chunked: bool,
    compression: u8,
    chunk_size: u64,
}

fn foreign() -> impl Strategy<Value = Foreign> {
    let topic = prop_oneof![
        Just("/vehicle/state".to_owned()),
        Just("/events".to_owned()),
        Just("/wing/left/forces".to_owned()),
        "/[a-z/]{0,12}",
        ".{0,8}",
    ];
    let payload = prop_oneof![
        prop::collection::vec(any::<u8>(), 0..64),
        Just(br#"{"phase":0.5,"position_m":{"x":1,"y":2,"z":3},"total":{"force_n":{"x":1,"y":0,"z":2},"moment_nm":{"x":0,"y":0,"z":0}}}"#.to_vec()),
        Just(br#"{"level":4,"message":"boom"}"#.to_vec()),
        "[\\[\\]{}\":,0-9a-z.e+-]{0,40}".prop_map(String::into_bytes),
    ];
    let meta_name = prop_oneof![
        4 => "[a-z.]{0,10}".prop_filter("not flapwing", |s| s != "flapwing"),
        1 => Just("flapwing.end".to_owned()),
    ];
    (
        prop::collection::vec(
            (
                topic,
                "[a-z.]{0,10}",
                prop_oneof![Just("json".to_owned()), "[a-z]{0,5}"],
            ),
            0..5,
        ),
        prop::collection::vec((any::<Index>(), any::<u64>(), payload), 0..40),
        prop::collection::vec(
            (
                meta_name,
                prop::collection::btree_map(".{0,6}", ".{0,12}", 0..4),
            ),
            0..3,
        ),
        prop::collection::vec((".{0,10}", prop::collection::vec(any::<u8>(), 0..32)), 0..3),
        any::<bool>(),
        0u8..3,
        prop_oneof![Just(64u64), Just(1024), Just(1 << 20)],
    )
        .prop_map(
            |(channels, messages, metadata, attachments, chunked, compression, chunk_size)| {
                Foreign {
                    channels,
                    messages,
                    metadata,
                    attachments,
                    chunked,
                    compression,
                    chunk_size,
                }
            },
        )
}

fn write_foreign(f: &Foreign) -> Vec<u8> {
    let compression = match f.compression {
        0 => None,
        1 => Some(mcap::Compression::Zstd),
        _ => Some(mcap::Compression::Lz4),
    };
    let mut w = mcap::WriteOptions::new()
        .compression(compression)
        .compression_threads(0)
        .use_chunks(f.chunked)
        .chunk_size(Some(f.chunk_size))
        .library("someone-else")
        .create(Cursor::new(Vec::new()))
        .unwrap();
    let mut ids = Vec::new();
    for (topic, schema, encoding) in &f.channels {
        let s = w
            .add_schema(schema, "jsonschema", br#"{"type":"object"}"#)
            .unwrap();
        ids.push(w.add_channel(s, topic, encoding, &BTreeMap::new()).unwrap());
    }
    for (k, (ch, t, data)) in f.messages.iter().enumerate() {
        if ids.is_empty() {
            break;
        }
        w.write_to_known_channel(
            &mcap::records::MessageHeader {
                channel_id: *ch.get(&ids),
                sequence: k as u32,
                log_time: *t,
                publish_time: *t,
            },
            data,
        )
        .unwrap();
    }
    for (name, md) in &f.metadata {
        w.write_metadata(&mcap::records::Metadata {
            name: name.clone(),
            metadata: md.clone(),
        })
        .unwrap();
    }
    for (name, data) in &f.attachments {
        w.attach(&mcap::Attachment {
            log_time: 0,
            create_time: 0,
            name: name.clone(),
            media_type: "application/octet-stream".into(),
            data: Cow::Borrowed(data),
        })
        .unwrap();
    }
    w.finish().unwrap();
    w.into_inner().into_inner()
}

proptest! {
    #![proptest_config(config(100))]

    /// Valid MCAP files without a `flapwing` metadata record: read_summary and check_log
    /// say "not a flapwing log" naming the file; export_csv never panics. Cut in half, the
    /// same (or an MCAP/"not MCAP" error naming the file).
    #[test]
    fn foreign_mcap_files(f in foreign(), cut in any::<Index>()) {
        let bytes = write_foreign(&f);
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("other.mcap");
        std::fs::write(&path, &bytes).unwrap();
        let e = guarded("read_summary", || read_summary(&path))?
            .expect_err("a foreign MCAP file read as a flapwing log");
        check_read_error(&e, &path)?;
        prop_assert!(matches!(e, Error::NotFlapwing { .. }), "{e:?}");
        prop_assert!(e.to_string().contains("not a flapwing log"), "{e}");
        let e = guarded("check_log", || check_log(&path))?
            .expect_err("a foreign MCAP file checked");
        check_read_error(&e, &path)?;
        csv_of(&path, "/vehicle/state", &dir.path().join("s.csv"))?;
        // Truncated too.
        let short = dir.path().join("short.mcap");
        std::fs::write(&short, &bytes[..cut.index(bytes.len() + 1)]).unwrap();
        if let Err(e) = guarded("read_summary", || read_summary(&short))? {
            check_read_error(&e, &short)?;
        }
    }
}
