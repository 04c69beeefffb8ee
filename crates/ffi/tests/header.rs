//! The committed header `include/flapwing.h` is what cbindgen generates from the crate now.
//! `FLAPWING_BLESS=1 cargo test --release -p flapwing-ffi --test header` rewrites it.

use std::path::Path;

#[test]
fn header_is_current() {
    let crate_dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let config = cbindgen::Config::from_file(crate_dir.join("cbindgen.toml"))
        .expect("crates/ffi/cbindgen.toml");
    let mut generated = Vec::new();
    cbindgen::Builder::new()
        .with_crate(crate_dir)
        .with_config(config)
        .generate()
        .expect("cbindgen generates the header from crates/ffi/src")
        .write(&mut generated);
    let generated = String::from_utf8(generated).expect("the header is UTF-8");
    let path = crate_dir.join("include/flapwing.h");
    if std::env::var_os("FLAPWING_BLESS").is_some_and(|v| v == "1") {
        std::fs::write(&path, &generated).expect("write include/flapwing.h");
        return;
    }
    let committed = std::fs::read_to_string(&path).unwrap_or_default();
    if committed != generated {
        let line = committed
            .lines()
            .zip(generated.lines())
            .position(|(a, b)| a != b)
            .unwrap_or_else(|| committed.lines().count().min(generated.lines().count()));
        panic!(
            "{} is not what cbindgen generates from the crate now (first difference at line {}:\n  committed: {:?}\n  generated: {:?}).\nRegenerate it with: FLAPWING_BLESS=1 cargo test --release -p flapwing-ffi --test header",
            path.display(),
            line + 1,
            committed.lines().nth(line).unwrap_or("<end of file>"),
            generated.lines().nth(line).unwrap_or("<end of file>"),
        );
    }
}
