//! The recorder writes MCAP files itself (see `mcap_write.rs`): the `mcap` crate's readers
//! accept them with every CRC checked, and the summary and indexes agree with the data.

use crate::common;

use flapsim::{Mode, Simulation, Vehicle};
use flightlog::{Level, LogOptions, Recorder, RunInfo, SimSettings};
use mcap::records::Record;
use mcap::sans_io::indexed_reader::{IndexedReadEvent, IndexedReader};
use mcap::sans_io::{LinearReader, LinearReaderOptions};

/// A full-rate drosophila run with events in the middle; the file's bytes and the message
/// count.
fn record(rate: Option<f64>) -> (Vec<u8>, u64) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("run.mcap");
    let vehicle = Vehicle::from_toml(flapsim::DROSOPHILA_TOML, common::ORIGIN).unwrap();
    let settings = SimSettings::new(Mode::Free, 0.02, rate, [0.0; 3]);
    let info = RunInfo::new(
        "simulate",
        "flapwing simulate",
        flapsim::DROSOPHILA_TOML,
        common::ORIGIN,
        settings.to_json(),
    );
    let opts = LogOptions {
        mcap: Some(path.clone()),
        log_rate_hz: rate,
        ..LogOptions::default()
    };
    let mut rec = Recorder::create(&opts, &info, &vehicle).unwrap();
    let mut sim = Simulation::new(vehicle, Mode::Free);
    for k in 0..900 {
        let out = sim.step().unwrap();
        rec.record(&out).unwrap();
        if k == 333 || k == 334 || k == 700 {
            rec.event(out.t_s, Level::Warning, "something \"odd\"")
                .unwrap();
        }
    }
    let stats = rec.finish().unwrap();
    (std::fs::read(&path).unwrap(), stats.mcap_messages)
}

/// Every record, read with every CRC (chunks, data section, summary section) checked.
fn records(bytes: &[u8]) -> Vec<Record<'static>> {
    let reader = LinearReader::new_with_options(
        LinearReaderOptions::default()
            .with_validate_chunk_crcs(true)
            .with_validate_data_section_crc(true)
            .with_validate_summary_section_crc(true)
            .with_emit_chunks(true)
            .with_check_finishes_after_end_magic(true),
    );
    flightlog::replay::linear_records(reader, bytes).unwrap()
}

fn check(rate: Option<f64>) {
    let (bytes, messages) = record(rate);
    let recs = records(&bytes);
    let chunks = recs
        .iter()
        .filter(|r| matches!(r, Record::Chunk { .. }))
        .count();
    assert!(chunks >= 3);

    // Every message, in file order, through the plain reader.
    let stream: Vec<(u16, u32, u64, Vec<u8>)> = mcap::MessageStream::new(&bytes)
        .unwrap()
        .map(|m| {
            let m = m.unwrap();
            (m.channel.id, m.sequence, m.log_time, m.data.into_owned())
        })
        .collect();
    assert_eq!(stream.len() as u64, messages);

    // The summary agrees.
    let summary = mcap::Summary::read(&bytes).unwrap().unwrap();
    let stats = summary.stats.as_ref().unwrap();
    assert_eq!(stats.message_count, messages);
    assert_eq!(stats.chunk_count as usize, chunks);
    assert_eq!(summary.chunk_indexes.len(), chunks);
    assert_eq!(
        stats.channel_count as usize,
        flightlog::schema::CHANNELS.len()
    );
    assert_eq!(summary.channels.len(), flightlog::schema::CHANNELS.len());
    assert_eq!(stats.schema_count as usize, summary.schemas.len());
    assert_eq!(stats.metadata_count, 2);
    assert_eq!(stats.attachment_count, 1);
    assert_eq!(stats.channel_message_counts.values().sum::<u64>(), messages);
    assert_eq!(stats.message_start_time, stream[0].2);
    assert_eq!(
        stats.message_end_time,
        stream.iter().map(|m| m.2).max().unwrap()
    );
    for (i, md) in summary.metadata_indexes.iter().enumerate() {
        let m = mcap::read::metadata(&bytes, md).unwrap();
        assert_eq!(m.name, md.name);
        assert_eq!(md.name, ["flapwing", "flapwing.end"][i]);
    }
    let att = &summary.attachment_indexes[0];
    let a = mcap::read::attachment(&bytes, att).unwrap();
    assert_eq!(a.data.as_ref(), flapsim::DROSOPHILA_TOML.as_bytes());

    // Indexed reading (what Foxglove does) finds the same messages.
    let mut reader = IndexedReader::new(&summary).unwrap();
    let mut indexed = Vec::new();
    while let Some(event) = reader.next_event() {
        match event.unwrap() {
            IndexedReadEvent::ReadChunkRequest { offset, length } => {
                let data = bytes[offset as usize..offset as usize + length].to_vec();
                reader.insert_chunk_record_data(offset, &data).unwrap();
            }
            IndexedReadEvent::Message { header, data } => indexed.push((
                header.channel_id,
                header.sequence,
                header.log_time,
                data.to_vec(),
            )),
        }
    }
    let mut a = stream.clone();
    let mut b = indexed;
    a.sort();
    b.sort();
    assert_eq!(a, b);
    // Sequence numbers count each channel's messages.
    for (id, n) in &stats.channel_message_counts {
        let seqs: Vec<u32> = stream.iter().filter(|m| m.0 == *id).map(|m| m.1).collect();
        assert_eq!(seqs, (0..*n as u32).collect::<Vec<_>>());
    }
}

#[test]
fn full_rate_logs_pass_every_mcap_check() {
    check(None);
}

#[test]
fn full_rate_logs_are_the_same_bytes_however_the_threads_run() {
    // Logging every step, the writer thread falls behind and the queue fills and empties
    // with thread timing; the bytes must not depend on it.
    let (a, _) = record(None);
    for _ in 0..3 {
        assert!(record(None).0 == a);
    }
}

#[test]
fn decimated_logs_pass_every_mcap_check() {
    check(Some(2000.0));
}
