//! Reading a model file from disk, bounded: the one reader of vehicle model files (and of
//! the other small TOML inputs: randomisation and study files) for the CLI and the Python
//! bindings. A model file is a few kB of TOML (the
//! built-in ones are 4-10 kB); a path to something else (a FIFO with no writer, `/dev/zero`,
//! a multi-GB file named by mistake) would block or read until memory runs out, so only
//! regular files of at most [`MAX_MODEL_FILE_BYTES`] are read.

use std::io::Read;
use std::path::Path;

/// The largest model file read, bytes (1 MiB: over a hundred times the largest built-in
/// model).
pub const MAX_MODEL_FILE_BYTES: u64 = 1 << 20;

/// The text of the model file at `path`. Refused, with an error naming the file: anything
/// but a regular file (after following symlinks; checked before opening, so a FIFO does not
/// block), a file above [`MAX_MODEL_FILE_BYTES`] (its size and the limit), text that is not
/// UTF-8, and the I/O errors of reading it.
pub fn read_model_file(path: &Path) -> std::io::Result<String> {
    read_bounded_text(path, "model file")
}

/// [`read_model_file`] for another small TOML input of a model (`what`: "randomisation
/// file", ...), under the same limit and with the same errors.
pub fn read_bounded_text(path: &Path, what: &str) -> std::io::Result<String> {
    use std::io::{Error, ErrorKind};
    let shown = path.display();
    let meta = std::fs::metadata(path)
        .map_err(|e| Error::new(e.kind(), format!("cannot read {what} {shown}: {e}")))?;
    if !meta.is_file() {
        return Err(Error::new(
            ErrorKind::InvalidInput,
            format!(
                "{what} {shown} is not a regular file ({}): only a regular (TOML) file is read",
                kind_of(&meta.file_type())
            ),
        ));
    }
    let too_big = |size: u64| {
        Error::new(
            ErrorKind::InvalidInput,
            format!(
                "{what} {shown} is {size} bytes, above the limit of {MAX_MODEL_FILE_BYTES} bytes (1 MiB) for a {what}"
            ),
        )
    };
    if meta.len() > MAX_MODEL_FILE_BYTES {
        return Err(too_big(meta.len()));
    }
    let file = std::fs::File::open(path)
        .map_err(|e| Error::new(e.kind(), format!("cannot read {what} {shown}: {e}")))?;
    // Bounded again while reading: the file may grow between the check and the read.
    let mut bytes = Vec::new();
    file.take(MAX_MODEL_FILE_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| Error::new(e.kind(), format!("cannot read {what} {shown}: {e}")))?;
    if bytes.len() as u64 > MAX_MODEL_FILE_BYTES {
        return Err(too_big(bytes.len() as u64));
    }
    String::from_utf8(bytes).map_err(|e| {
        Error::new(
            ErrorKind::InvalidData,
            format!("{what} {shown} is not UTF-8 text: {e}"),
        )
    })
}

/// A file type in words.
fn kind_of(t: &std::fs::FileType) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if t.is_fifo() {
            return "a FIFO";
        }
        if t.is_char_device() {
            return "a character device";
        }
        if t.is_block_device() {
            return "a block device";
        }
        if t.is_socket() {
            return "a socket";
        }
    }
    if t.is_dir() {
        "a directory"
    } else {
        "not a regular file"
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_a_model_and_refuses_devices_directories_and_large_files() {
        let dir = tempfile::tempdir().unwrap();
        let ok = dir.path().join("m.toml");
        std::fs::write(&ok, "name = \"x\"\n").unwrap();
        assert_eq!(read_model_file(&ok).unwrap(), "name = \"x\"\n");
        let big = dir.path().join("big.toml");
        std::fs::write(&big, vec![b'#'; MAX_MODEL_FILE_BYTES as usize + 1]).unwrap();
        let e = read_model_file(&big).unwrap_err().to_string();
        assert!(
            e.contains("big.toml") && e.contains("1048577 bytes") && e.contains("1048576"),
            "{e}"
        );
        let e = read_model_file(dir.path()).unwrap_err().to_string();
        assert!(e.contains("a directory"), "{e}");
        #[cfg(unix)]
        {
            let e = read_model_file(Path::new("/dev/zero"))
                .unwrap_err()
                .to_string();
            assert!(
                e.contains("/dev/zero") && e.contains("character device"),
                "{e}"
            );
        }
    }
}
