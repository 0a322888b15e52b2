//! `ccrkit calibrate` without `--fit` is the library's choice on train only: it fits every
//! candidate of `calibrate::select::candidates`, chooses by `calibrate::select` (hold-out
//! `_same_` rows of train), reports the choice and writes the chosen set's fit on all of train —
//! the same model, to the bit, as the library call with the same options.

use crate::common::cli::{ccrkit_in, root, scratch};
use ccrkit::calibrate::data::{DataOptions, Dataset};
use ccrkit::calibrate::fit::{fitted_toml, FitOptions};
use ccrkit::calibrate::predict::{PredictOptions, DEFAULT_CHUNK};
use ccrkit::calibrate::select::{candidates, select, SelectOptions};
use ccrkit::method::run::SolveRequest;
use ccrkit::method::{MethodKind, Settings};
use ccrkit::Model;
use std::path::Path;

const MODEL: &str = "models/hardware/ftdcr_v4.toml";
const TRAIN: &str = "models/hardware/data/v4/tdcr_sysid_20260511-183002_train.csv";

/// Every 12th row of v4 train (135 rows, 40 of them `_same_`), written to `dir`.
fn small_train(dir: &Path) -> std::path::PathBuf {
    let text = std::fs::read_to_string(root().join(TRAIN)).expect("train data");
    let mut lines = text.lines();
    let mut out = vec![lines.next().expect("header")];
    out.extend(lines.step_by(12));
    let p = dir.join("train12.csv");
    std::fs::write(&p, out.join("\n") + "\n").expect("writes");
    p
}

/// The robot and hardware of a model file, as text (`Debug` prints each `f64` exactly).
fn fingerprint(path: &Path) -> String {
    let m = Model::from_file(path).expect("fitted model reads");
    format!("{:?}\n{:?}", m.robot, m.hardware)
}

#[test]
fn cli_default_is_the_library_selection() {
    let dir = scratch("calibrate-default");
    let data = small_train(&dir);
    let out = dir.join("cli.toml");
    let run = ccrkit_in(
        &dir,
        &[
            "calibrate",
            root().join(MODEL).to_str().expect("utf-8 path"),
            "--data",
            data.to_str().expect("utf-8 path"),
            "--out",
            out.to_str().expect("utf-8 path"),
            "--set",
            "sub-arcs=1",
            "--max-iterations",
            "2",
        ],
    );
    let stdout = String::from_utf8_lossy(&run.stdout).to_string();
    assert!(
        run.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&run.stderr)
    );

    // The library, with what the CLI's defaults mean (method energy, chunk, hold-out `_same_`).
    let model = Model::from_file(root().join(MODEL)).expect("model");
    let train = Dataset::from_file(&data, &DataOptions::default()).expect("data");
    let mut s = Settings::new();
    s.push("sub-arcs", "1");
    let mut fit = FitOptions::new(PredictOptions {
        request: SolveRequest::new(MethodKind::DEFAULT).with_settings(s),
        chunk: DEFAULT_CHUNK,
        progress: ccrkit::progress::ProgressHandle::none(),
    });
    fit.max_iterations = 2;
    let cands = candidates(&model.robot, false);
    let sel = select(&model, &train, &cands, &SelectOptions::new(fit)).expect("selects");
    let chosen = sel.chosen();

    // The report names every candidate and marks the library's choice.
    for c in &cands {
        assert!(
            stdout.contains(&c.label),
            "`{}` not reported:\n{stdout}",
            c.label
        );
    }
    let marked: Vec<&str> = stdout
        .lines()
        .filter(|l| l.ends_with("<- chosen"))
        .collect();
    assert_eq!(marked.len(), 1, "{stdout}");
    assert_eq!(
        marked[0].split_whitespace().next(),
        Some(chosen.candidate.label.as_str()),
        "{stdout}"
    );
    assert!(
        stdout.contains(&format!("`{}`", chosen.candidate.label)),
        "{stdout}"
    );

    // The written model is the chosen set's fit on all of train.
    let text = std::fs::read_to_string(root().join(MODEL)).expect("model text");
    let lib = dir.join("lib.toml");
    std::fs::write(
        &lib,
        fitted_toml(&text, &chosen.full.model, "library").expect("toml"),
    )
    .expect("writes");
    assert_eq!(fingerprint(&out), fingerprint(&lib));
    // … and not what the nominal model is (the fit moved something).
    assert_ne!(fingerprint(&out), fingerprint(&root().join(MODEL)));
}

/// Data without `pattern_label` has no hold-out to choose on: refused by name, with the way to
/// fit one set; `--fit default` fits the default set alone.
#[test]
fn cli_default_without_labels_names_the_column() {
    let dir = scratch("calibrate-nolabel");
    let text = std::fs::read_to_string(small_train(&dir)).expect("data");
    let header: Vec<&str> = text.lines().next().expect("header").split(',').collect();
    let k = header
        .iter()
        .position(|c| *c == "pattern_label")
        .expect("label column");
    let stripped: Vec<String> = text
        .lines()
        .take(40)
        .map(|l| {
            let mut c: Vec<&str> = l.split(',').collect();
            c.remove(k);
            c.join(",")
        })
        .collect();
    let data = dir.join("nolabel.csv");
    std::fs::write(&data, stripped.join("\n") + "\n").expect("writes");
    let model = root().join(MODEL);
    let args = |extra: &[&str]| {
        let mut a: Vec<String> = [
            "calibrate",
            model.to_str().expect("utf-8"),
            "--data",
            data.to_str().expect("utf-8"),
            "--out",
            "fit.toml",
            "--set",
            "sub-arcs=1",
            "--max-iterations",
            "1",
        ]
        .map(String::from)
        .to_vec();
        a.extend(extra.iter().map(|s| s.to_string()));
        a
    };
    let run = ccrkit_in(&dir, &args(&[]));
    let err = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(1), "{err}");
    assert!(
        err.contains("pattern_label") && err.contains("--fit default"),
        "{err}"
    );
    let run = ccrkit_in(&dir, &args(&["--fit", "default"]));
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let out = String::from_utf8_lossy(&run.stdout);
    assert!(
        !out.contains("<- chosen") && out.contains("gain.seg0"),
        "{out}"
    );
}
