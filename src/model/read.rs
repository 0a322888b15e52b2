//! Reading input files with a size cap, so a path such as `/dev/zero` or `/dev/urandom` (or a
//! mistyped multi-gigabyte file) ends in a named [`ModelError::Io`] instead of a hang or an
//! exhausted memory.
//!
//! The caps are far above any real input: a model with [`super::MAX_SECTIONS`] sections and a
//! per-disk radius and angle table for [`super::bounds::MAX_CABLES`] cables is under 64 MiB of
//! TOML; the committed vessel mesh is 0.2 MiB.

use crate::error::ModelError;
use std::io::Read;
use std::path::Path;

/// Largest model or scene file read \[bytes\] (64 MiB).
pub const MAX_TEXT_BYTES: u64 = 64 << 20;
/// Largest mesh file read \[bytes\] (256 MiB: about five million binary-STL triangles).
pub const MAX_MESH_BYTES: u64 = 256 << 20;

/// Largest actuation file read \[bytes\] (1 MiB: an actuation of 256 cables is about 20 kB;
/// a 37 MB goal file once took 794 MB of memory as a JSON tree).
pub const MAX_ACTUATION_BYTES: u64 = 1 << 20;

/// The bytes of `path`, or [`ModelError::Io`] when it cannot be read or holds more than
/// `limit` bytes (`what` names the kind of file in the message).
pub fn read_capped(path: &Path, limit: u64, what: &str) -> Result<Vec<u8>, ModelError> {
    let io = |reason: String| ModelError::Io {
        path: path.display().to_string(),
        reason,
    };
    let file = std::fs::File::open(path).map_err(|e| io(e.to_string()))?;
    let mut bytes = Vec::new();
    file.take(limit + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| io(e.to_string()))?;
    if bytes.len() as u64 > limit {
        return Err(io(format!(
            "larger than the {} limit for a {what} (is it a device or the wrong file?)",
            if limit >= 1 << 20 {
                format!("{} MiB", limit >> 20)
            } else {
                format!("{limit} byte")
            }
        )));
    }
    Ok(bytes)
}

/// The text of a model or scene file, capped at [`MAX_TEXT_BYTES`]; not UTF-8 is an
/// [`ModelError::Io`] naming the byte offset.
pub fn read_text(path: &Path, what: &str) -> Result<String, ModelError> {
    read_text_capped(path, MAX_TEXT_BYTES, what)
}

/// [`read_text`] with its own cap of `limit` bytes.
pub fn read_text_capped(path: &Path, limit: u64, what: &str) -> Result<String, ModelError> {
    let bytes = read_capped(path, limit, what)?;
    String::from_utf8(bytes).map_err(|e| ModelError::Io {
        path: path.display().to_string(),
        reason: format!(
            "not UTF-8 text (invalid byte at offset {}): not a {what}",
            e.utf8_error().valid_up_to()
        ),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn devices_end_in_a_named_size_error() {
        for dev in ["/dev/zero", "/dev/urandom"] {
            let p = Path::new(dev);
            if !p.exists() {
                continue;
            }
            let e = read_capped(p, 1 << 20, "model file").unwrap_err();
            match e {
                ModelError::Io { path, reason } => {
                    assert_eq!(path, dev);
                    assert!(reason.contains("1 MiB limit"), "{reason}");
                }
                other => panic!("{other:?}"),
            }
        }
    }

    #[test]
    fn a_small_file_reads_whole() {
        let dir = std::env::temp_dir().join(format!("ccrkit-read-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("x.toml");
        std::fs::write(&p, "name = \"x\"\n").unwrap();
        assert_eq!(read_text(&p, "model file").unwrap(), "name = \"x\"\n");
        std::fs::write(&p, [0xffu8, 0xfe]).unwrap();
        let e = read_text(&p, "model file").unwrap_err();
        assert!(e.to_string().contains("not UTF-8"), "{e}");
    }
}
