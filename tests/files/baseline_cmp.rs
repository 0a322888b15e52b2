//! `tests/scripts/cmp.py` on folders that do not match: a missing or empty folder is an error
//! that names it (it printed `differences: 0` for an empty one, and a traceback for a missing
//! one), and a file only in either folder counts as a difference (those only in AFTER were
//! not looked at). Skipped, saying so, where `python3` is not installed.

use std::path::{Path, PathBuf};
use std::process::Command;

fn cmp(a: &Path, b: &Path) -> Option<(bool, String)> {
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/scripts/cmp.py");
    let out = Command::new("python3")
        .arg(script)
        .arg(a)
        .arg(b)
        .output()
        .ok()?;
    let text =
        String::from_utf8_lossy(&out.stdout).to_string() + &String::from_utf8_lossy(&out.stderr);
    Some((out.status.success(), text))
}

fn folder(name: &str, files: &[(&str, &str)]) -> PathBuf {
    let d = std::env::temp_dir().join(format!("ccrkit-cmp-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("temp folder");
    for (f, text) in files {
        std::fs::write(d.join(f), text).expect("write");
    }
    d
}

#[test]
fn cmp_names_missing_and_unmatched_folders() {
    let full = folder(
        "full",
        &[("a.rc", "0\n"), ("a.json", "{\"x\": 1.0}"), ("b.rc", "1\n")],
    );
    let part = folder("part", &[("a.rc", "0\n"), ("a.json", "{\"x\": 1.0}")]);
    let empty = folder("empty", &[]);
    let missing = std::env::temp_dir().join("ccrkit-cmp-no-such-folder");
    let Some((ok, text)) = cmp(&full, &full) else {
        eprintln!("python3 not found: cmp.py not checked");
        return;
    };
    assert!(ok && text.contains("differences: 0"), "{text}");
    let (ok, text) = cmp(&missing, &full).expect("python3");
    assert!(
        !ok && text.contains("is not a folder") && !text.contains("Traceback"),
        "{text}"
    );
    let (ok, text) = cmp(&empty, &full).expect("python3");
    assert!(!ok && text.contains("holds no record.sh output"), "{text}");
    for (a, b) in [(&part, &full), (&full, &part)] {
        let (_, text) = cmp(a, b).expect("python3");
        assert!(text.contains("only in") && text.contains("b.rc"), "{text}");
        assert!(text.contains("differences: 1"), "{text}");
    }
    for d in [full, part, empty] {
        let _ = std::fs::remove_dir_all(d);
    }
}
