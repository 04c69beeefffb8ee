//! The check that a test binary built from many files leaves none out: with `autotests = false`
//! (or in a folder of modules) cargo does not find a new file by itself, and a file that is
//! not declared is never compiled or run. Included by path from each such binary's root.

use std::collections::HashSet;
use std::path::Path;

/// Every `.rs` file in `dir` other than `root_file` is exactly one of: a module of the root
/// (`mod NAME;`, or a `#[path = "FILE"]` line naming it, in `root`) or a test target of the
/// package (an uncommented `path = "tests/FILE"` line in `manifest`, when given). Every folder
/// with a `main.rs` is a test target (when `manifest` is given; without it cargo finds it).
/// Lines are read one at a time, commented ones skipped, so CRLF and comments do not fool it.
pub fn assert_every_test_file_runs(
    dir: &Path,
    root_file: &str,
    root: &str,
    manifest: Option<&str>,
) {
    let code = |text: &str| -> Vec<String> {
        text.lines()
            .map(|l| l.trim().to_owned())
            .filter(|l| !l.starts_with("//") && !l.starts_with('#') || l.starts_with("#["))
            .collect()
    };
    let root_lines = code(root);
    let modules: HashSet<String> = root_lines
        .iter()
        .filter_map(|l| l.strip_prefix("mod ")?.strip_suffix(';').map(str::to_owned))
        .collect();
    let path_attrs: HashSet<String> = root_lines
        .iter()
        .filter_map(|l| {
            let rest = l.strip_prefix("#[path = \"")?;
            Some(rest.split('"').next()?.to_owned())
        })
        .collect();
    let targets: HashSet<String> = manifest
        .map(|m| {
            code(m)
                .iter()
                .filter_map(|l| {
                    let rest = l.strip_prefix("path = \"tests/")?;
                    Some(rest.split('"').next()?.to_owned())
                })
                .collect()
        })
        .unwrap_or_default();
    let mut entries: Vec<_> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .collect();
    entries.sort();
    for path in entries {
        let name = path.file_name().unwrap().to_str().unwrap().to_owned();
        if let Some(stem) = name.strip_suffix(".rs") {
            if name == root_file {
                continue;
            }
            let module = modules.contains(stem) || path_attrs.contains(&name);
            let target = targets.contains(&name);
            assert!(
                module ^ target,
                "{}: {}",
                path.display(),
                if module {
                    "both a module of the test root and a [[test]] target (it would run twice)"
                } else {
                    "neither a module of the test root nor a [[test]] target (it would never run)"
                }
            );
        } else if manifest.is_some() && path.join("main.rs").is_file() {
            assert!(
                targets.contains(&format!("{name}/main.rs")),
                "{}/main.rs is not a [[test]] target in Cargo.toml",
                path.display()
            );
        }
    }
}
