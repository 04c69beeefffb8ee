//! Shards of a sweep: the study content hash, the shard header, atomic writes, completeness,
//! and the merge of a directory (refusals and the missing-shard report), plus the job-array
//! script.

use flapstudy::Study;
use flapstudy::shard::{
    Expected, ShardError, ShardHeader, ShardState, merge_group, parse_shard_file_name, scan_dir,
    shard_file_name, shard_state, study_hash, write_atomic,
};
use flapstudy::slurm::{JobArray, collapse_ranges, parse_time_limit, sbatch_line};
use flapstudy::spec::StudySpec;

const FACTORIAL: &str = r#"
name = "grid"
base_model = "drosophila"
design = "full_factorial"
responses = ["lift_over_weight", "aero_power_w"]
[[factor]]
path = "kinematics.amplitude_deg"
levels = [120.0, 140.0, 160.0]
[[factor]]
path = "kinematics.mid_stroke_aoa_deg"
range = [35.0, 45.0]
count = 2
"#;

fn study_from(text: &str, origin: &str, base: &str) -> Study {
    let spec = StudySpec::from_toml(text, origin).expect("study parses");
    spec.resolve(origin, "grid", base, "base")
        .expect("study resolves")
}

fn study(text: &str) -> Study {
    study_from(
        text,
        "test.toml",
        flapsim::builtin_model("drosophila").unwrap(),
    )
}

/// The text of shard k of n as `flapwing sweep --shard` writes it.
fn shard_text(s: &Study, k: usize, n: usize, file: &str) -> String {
    let h = ShardHeader::new(s, &study_hash(s), k, n, file);
    let results = s.run(h.cases.clone(), &|_| ()).unwrap();
    format!("{}\n{}", h.line(), s.csv(&results))
}

#[test]
fn hash_covers_the_table_inputs_only() {
    let s = study(FACTORIAL);
    let h = study_hash(&s);
    assert_eq!(h.len(), 64);
    assert!(
        h.bytes()
            .all(|b| b.is_ascii_hexdigit() && !b.is_ascii_uppercase())
    );
    // The same content from another path, or with other comments and layout: the same hash.
    let moved = study_from(
        &format!("# a comment\n{FACTORIAL}"),
        "/elsewhere/copy.toml",
        flapsim::builtin_model("drosophila").unwrap(),
    );
    assert_eq!(study_hash(&moved), h);
    // Anything that changes the table changes the hash.
    let changed = [
        FACTORIAL.replace("160.0]", "160.5]"),
        FACTORIAL.replace("count = 2", "count = 3"),
        FACTORIAL.replace("\"aero_power_w\"", "\"cl_mean_total\""),
        FACTORIAL.replace("name = \"grid\"", "name = \"grid2\""),
        FACTORIAL.replace("mid_stroke_aoa_deg", "mean_stroke_deg"),
    ];
    for text in &changed {
        assert_ne!(study_hash(&study(text)), h, "{text}");
    }
    // So does the base model's content (a study whose base_model is an edited file).
    let base = flapsim::builtin_model("drosophila").unwrap();
    assert!(base.contains("mass_kg = 1.0e-6"));
    let heavier = base.replacen("mass_kg = 1.0e-6", "mass_kg = 1.1e-6", 1);
    assert_ne!(study_hash(&study_from(FACTORIAL, "t", &heavier)), h);
    assert_eq!(study_hash(&study_from(FACTORIAL, "t", base)), h);
}

#[test]
fn header_line_round_trips_and_names_parse() {
    let s = study(FACTORIAL);
    let h = ShardHeader::new(&s, &study_hash(&s), 2, 4, "/data/my study.toml");
    assert_eq!(h.cases, 1..3);
    let line = h.line();
    assert!(line.starts_with("# flapwing study "), "{line}");
    assert!(
        line.ends_with(" shard 2/4 cases 1..3 from /data/my study.toml"),
        "{line}"
    );
    assert_eq!(ShardHeader::parse(&line), Some(h));
    for bad in [
        "# flapwing study abc shard 1/2 cases 0..3 from x",
        "case,a,b",
        "",
        &line.replace("shard 2/4", "shard 5/4"),
    ] {
        assert_eq!(ShardHeader::parse(bad), None, "{bad}");
    }
    assert_eq!(shard_file_name("grid", 3, 8), "grid-shard-3-of-8.csv");
    assert_eq!(
        parse_shard_file_name("my-grid-shard-3-of-8.csv"),
        Some(("my-grid".to_owned(), 3, 8))
    );
    assert_eq!(parse_shard_file_name(".grid-shard-3-of-8.csv.tmp-77"), None);
    assert_eq!(parse_shard_file_name("grid-shard-9-of-8.csv"), None);
}

#[test]
fn a_cut_short_shard_is_never_complete() {
    let s = study(FACTORIAL);
    let text = shard_text(&s, 1, 2, "/s.toml");
    assert!(matches!(shard_state(&text, "f"), ShardState::Complete(_)));
    // Every prefix of the file (a task killed mid-write without the atomic rename) is
    // incomplete or not a shard at all.
    for cut in 0..text.len() {
        let state = shard_state(&text[..cut], "f");
        assert!(
            !matches!(state, ShardState::Complete(_)),
            "cut at byte {cut}: {state:?}"
        );
    }
    // A row removed from the middle, or rows swapped, are caught too.
    let mut lines: Vec<&str> = text.lines().collect();
    lines.swap(2, 3);
    let swapped = lines.join("\n") + "\n";
    assert!(
        matches!(shard_state(&swapped, "f"), ShardState::Incomplete(_, ref w) if w.contains("out of order"))
    );
    assert!(matches!(
        shard_state("case,x\n0,1\n", "f"),
        ShardState::Foreign(_)
    ));
}

#[test]
fn atomic_write_replaces_whole_files_and_temp_files_are_ignored() {
    let dir = tempfile::tempdir().unwrap();
    let s = study(FACTORIAL);
    let path = dir.path().join(shard_file_name("grid", 1, 2));
    write_atomic(&path, b"old\n").unwrap();
    let text = shard_text(&s, 1, 2, "/s.toml");
    write_atomic(&path, text.as_bytes()).unwrap();
    assert_eq!(std::fs::read_to_string(&path).unwrap(), text);
    // No temporary file is left behind.
    let names: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names, [shard_file_name("grid", 1, 2)]);
    // A killed task's leftover temporary file (a half shard) is not taken for shard 2.
    let half = &shard_text(&s, 2, 2, "/s.toml")[..40];
    std::fs::write(dir.path().join(".grid-shard-2-of-2.csv.tmp-4242"), half).unwrap();
    let groups = scan_dir(dir.path()).unwrap();
    assert_eq!(groups.len(), 1);
    assert_eq!(groups[0].files.keys().copied().collect::<Vec<_>>(), [1]);
    // Writing into a missing directory is an error naming the file, not a panic.
    let e = write_atomic(&dir.path().join("no/such/x.csv"), b"x").unwrap_err();
    assert!(e.to_string().contains("x.csv"), "{e}");
}

#[test]
fn merge_refuses_other_studies_and_lists_missing_shards() {
    let dir = tempfile::tempdir().unwrap();
    let s = study(FACTORIAL);
    let whole = s.csv(&s.run(0..s.case_count(), &|_| ()).unwrap());
    let n = 4;
    for k in [1, 2, 4] {
        let path = dir.path().join(shard_file_name("grid", k, n));
        write_atomic(&path, shard_text(&s, k, n, "/data/grid.toml").as_bytes()).unwrap();
    }
    let shown = dir.path().display().to_string();
    let group = |d: &std::path::Path| scan_dir(d).unwrap().remove(0);
    let e = merge_group(&group(dir.path()), None, "/out").unwrap_err();
    let ShardError::NotComplete { missing, .. } = &e else {
        panic!("{e}")
    };
    assert_eq!(missing, &[3]);
    assert_eq!(
        e.to_string(),
        "study `grid` has 3 of 4 shards complete; missing shard(s) 3\nresubmit just those with:\n  flapwing submit /data/grid.toml --out /out --shards 4 --only 3"
    );

    // Shard 3 cut short: incomplete, listed with the reason, and resubmitted.
    let text3 = shard_text(&s, 3, n, "/data/grid.toml");
    let cut = text3.len() - text3.lines().last().unwrap().len() - 1;
    std::fs::write(
        dir.path().join(shard_file_name("grid", 3, n)),
        &text3[..cut],
    )
    .unwrap();
    let e = merge_group(&group(dir.path()), None, "/o u t")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("incomplete shard(s) 3 (0 of 1 case rows)"),
        "{e}"
    );
    assert!(e.ends_with("--out '/o u t' --shards 4 --only 3"), "{e}");

    // Complete: byte for byte the unsharded table.
    write_atomic(
        &dir.path().join(shard_file_name("grid", 3, n)),
        text3.as_bytes(),
    )
    .unwrap();
    assert_eq!(
        merge_group(&group(dir.path()), None, &shown).unwrap(),
        whole
    );

    // A shard of another study is refused, naming the file and both hashes.
    let other = study(&FACTORIAL.replace("160.0]", "161.0]"));
    let foreign = shard_text(&other, 2, n, "/data/grid.toml");
    let f2 = dir.path().join(shard_file_name("grid", 2, n));
    std::fs::write(&f2, foreign).unwrap();
    let e = merge_group(&group(dir.path()), None, &shown)
        .unwrap_err()
        .to_string();
    assert!(e.contains(&f2.display().to_string()), "{e}");
    assert!(
        e.contains(&study_hash(&other)) && e.contains(&study_hash(&s)),
        "{e}"
    );
    // Against a manifest's hash, even shard 1 may be the foreign one.
    let expected = Expected {
        hash: study_hash(&other),
        why: "the manifest".to_owned(),
        study_file: "/data/grid.toml".to_owned(),
    };
    let e = merge_group(&group(dir.path()), Some(&expected), &shown)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("grid-shard-1-of-4.csv") && e.contains("the manifest"),
        "{e}"
    );
}

#[test]
fn job_array_script() {
    let job = JobArray {
        study: "grid".into(),
        hash: "ab".repeat(32),
        flapwing: "/opt/flap wing/flapwing".into(),
        study_file: "/data/grid.toml".into(),
        out_dir: "/scratch/out".into(),
        shards: 8,
        only: vec![2, 3, 4, 7],
        throttle: Some(2),
        partition: Some("short".into()),
        time_limit: Some("00:30:00".into()),
        cpus_per_task: 4,
        extra_lines: vec!["#SBATCH --mem=2G".into()],
        force: false,
    };
    assert_eq!(job.array_spec(), "2-4,7%2");
    let s = job.script();
    for line in [
        "#SBATCH --array=2-4,7%2",
        "#SBATCH --cpus-per-task=4",
        "#SBATCH --time=00:30:00",
        "#SBATCH --partition=short",
        "#SBATCH --mem=2G",
        "#SBATCH --output=/scratch/out/slurm/grid-%A_%a.out",
        "exec '/opt/flap wing/flapwing' sweep /data/grid.toml --out /scratch/out --shard \"${SLURM_ARRAY_TASK_ID}/8\" --jobs \"${SLURM_CPUS_PER_TASK:-4}\"",
    ] {
        assert!(s.lines().any(|l| l == line), "no line `{line}` in\n{s}");
    }
    assert!(s.starts_with("#!/bin/bash\n"));
    // Every #SBATCH line comes before the first command (sbatch stops reading there).
    let first_cmd = s.lines().position(|l| !l.starts_with('#')).unwrap();
    assert!(s.lines().skip(first_cmd).all(|l| !l.starts_with("#SBATCH")));
    assert_eq!(collapse_ranges(&[1, 2, 3, 5, 7, 8]), "1-3,5,7-8");
    assert_eq!(collapse_ranges(&[4]), "4");

    assert!(parse_time_limit("00:30:00").is_ok());
    assert!(parse_time_limit("2-12:00:00").is_ok());
    for bad in [
        "30",
        "00:60:00",
        "1:2",
        "00:00:00",
        "x-01:00:00",
        "1-24:00:00",
        "",
    ] {
        assert!(parse_time_limit(bad).is_err(), "{bad}");
    }
    assert_eq!(sbatch_line("--mem=2G").unwrap(), "#SBATCH --mem=2G");
    assert_eq!(
        sbatch_line("#SBATCH --qos=short").unwrap(),
        "#SBATCH --qos=short"
    );
    for bad in ["rm -rf /", "--mem=1\nrm x", "mem=2G", "--"] {
        assert!(sbatch_line(bad).is_err(), "{bad}");
    }
}
