//! The benchmark protocol (data README §8): the choice among candidate parameter sets is made
//! on train only. `calibrate::select` takes one dataset and nothing else; these tests pin its
//! signature and show that its outcome does not move when a val file beside the train file is
//! present, absent or garbage, while it does use the hold-out rows it names.

use ccrkit::calibrate::data::{DataOptions, Dataset};
use ccrkit::calibrate::fit::FitOptions;
use ccrkit::calibrate::predict::{PredictOptions, DEFAULT_CHUNK};
use ccrkit::calibrate::select::{select, Candidate, SelectOptions, Selection};
use ccrkit::method::run::SolveRequest;
use ccrkit::method::{MethodKind, Settings};
use ccrkit::{Model, SolveError};
use std::path::{Path, PathBuf};

const STEM: &str = "tdcr_sysid_20260511-183002";

fn root(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(rel)
}

fn options() -> SelectOptions {
    let mut s = Settings::new();
    s.push("sub-arcs", "1");
    let mut fit = FitOptions::new(PredictOptions {
        request: SolveRequest::new(MethodKind::Energy).with_settings(s),
        chunk: DEFAULT_CHUNK,
        progress: ccrkit::progress::ProgressHandle::none(),
    });
    fit.max_iterations = 4;
    SelectOptions::new(fit)
}

fn candidates() -> Vec<Candidate> {
    let base: Vec<String> = ["gain", "offset", "compliance", "marker.z"]
        .map(String::from)
        .to_vec();
    let mut plus = base.clone();
    plus.push("backlash".into());
    vec![
        Candidate {
            label: "small".into(),
            params: base,
        },
        Candidate {
            label: "small+backlash".into(),
            params: plus,
        },
    ]
}

/// Every 12th row of the train file in `dir` (135 rows, 40 of them `_same_`).
fn train_in(dir: &Path) -> Dataset {
    let d = Dataset::from_file(
        dir.join(format!("{STEM}_train.csv")),
        &DataOptions::default(),
    )
    .expect("train reads");
    let idx: Vec<usize> = (0..d.len()).step_by(12).collect();
    d.select(&idx)
}

/// The selection as bits: the choice, the held-out rows, every score and fitted value.
fn fingerprint(s: &Selection) -> (usize, Vec<usize>, Vec<u64>) {
    let mut bits = vec![];
    for c in &s.scored {
        bits.push(c.holdout_rmse.to_bits());
        for p in c.full.params.iter().chain(&c.reduced.params) {
            bits.push(p.value.to_bits());
        }
    }
    (s.best, s.holdout_rows.clone(), bits)
}

/// `select` has no input but the model, train, the candidates and the options (this line does
/// not compile if a val argument is added), and its outcome is the same to the bit whether the
/// train file's directory also holds the real val file, a garbage val file or none.
#[test]
fn selection_is_blind_to_val() {
    let _signature: fn(
        &Model,
        &Dataset,
        &[Candidate],
        &SelectOptions,
    ) -> Result<Selection, SolveError> = select;
    let model = Model::from_file(root("models/hardware/ftdcr_v4.toml")).expect("model");
    let data = root("models/hardware/data/v4");
    let tmp = std::env::temp_dir().join(format!("ccrkit_select_{}", std::process::id()));
    let mut prints = vec![];
    for (case, val) in [
        ("none", None),
        (
            "real",
            Some(std::fs::read(data.join(format!("{STEM}_val.csv"))).expect("val")),
        ),
        ("garbage", Some(b"not,a\ncsv \xff at all\n".to_vec())),
    ] {
        let dir = tmp.join(case);
        std::fs::create_dir_all(&dir).expect("tmp dir");
        let name = format!("{STEM}_train.csv");
        std::fs::copy(data.join(&name), dir.join(&name)).expect("copy train");
        if let Some(v) = val {
            std::fs::write(dir.join(format!("{STEM}_val.csv")), v).expect("write val");
        }
        let sel = select(&model, &train_in(&dir), &candidates(), &options()).expect("selects");
        prints.push((case, fingerprint(&sel)));
    }
    let _ = std::fs::remove_dir_all(&tmp);
    for (case, p) in &prints[1..] {
        assert_eq!(p, &prints[0].1, "val file {case} changed the selection");
    }
}

/// The hold-out split is what the module docs say: the held-out rows are exactly the `_same_`
/// rows of train, the reduced fits see only the others, the full fits all rows; and the score
/// reads the held-out tips (moving them moves the score: the test can fail).
#[test]
fn holdout_is_the_same_patterns_of_train() {
    let model = Model::from_file(root("models/hardware/ftdcr_v4.toml")).expect("model");
    let train = train_in(&root("models/hardware/data/v4"));
    let labels = train.labels.clone().expect("labels");
    let opts = options();
    let cands = &candidates()[..1];
    let sel = select(&model, &train, cands, &opts).expect("selects");
    let same: Vec<usize> = (0..train.len())
        .filter(|&i| labels[i].contains("_same_"))
        .collect();
    assert!(!same.is_empty() && same.len() < train.len());
    assert_eq!(sel.holdout_rows, same);
    let c = &sel.scored[0];
    assert_eq!(c.full.rows_used + c.full.rows_excluded, train.len());
    assert_eq!(
        c.reduced.rows_used + c.reduced.rows_excluded,
        train.len() - same.len()
    );
    assert!(c.holdout_rmse > 0.0 && c.holdout_rmse < 0.05);
    // Shift one held-out tip by 10 mm: the reduced fit is unchanged, the score is not.
    let mut moved = train.clone();
    if let Some(t) = moved.tips.as_mut() {
        t[same[0]].x += 0.01;
    }
    let sel2 = select(&model, &moved, cands, &opts).expect("selects");
    let c2 = &sel2.scored[0];
    for (a, b) in c.reduced.params.iter().zip(&c2.reduced.params) {
        assert_eq!(a.value.to_bits(), b.value.to_bits(), "{}", a.name);
    }
    assert!(
        c2.holdout_rmse > c.holdout_rmse,
        "{} vs {}",
        c2.holdout_rmse,
        c.holdout_rmse
    );
}

/// Bad requests are refused by field: no candidate, no labels, a hold-out that holds out
/// nothing.
#[test]
fn selection_refuses_bad_requests_by_name() {
    let model = Model::from_file(root("models/hardware/ftdcr_v4.toml")).expect("model");
    let train = train_in(&root("models/hardware/data/v4"));
    let field = |r: Result<Selection, SolveError>| match r {
        Err(SolveError::InvalidInput { field, .. }) => field,
        other => panic!("expected a refusal, got {:?}", other.map(|s| s.best)),
    };
    assert_eq!(field(select(&model, &train, &[], &options())), "candidates");
    let mut unlabelled = train.clone();
    unlabelled.labels = None;
    assert_eq!(
        field(select(&model, &unlabelled, &candidates(), &options())),
        "holdout"
    );
    let mut o = options();
    o.holdout = "no_such_pattern".into();
    assert_eq!(field(select(&model, &train, &candidates(), &o)), "holdout");
}
