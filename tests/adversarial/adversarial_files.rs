//! Adversarial model and scene files: every number of every committed model and
//! scene replaced by absurd values (zero, negative, NaN, infinities, 1e308, 1e-300, strings,
//! booleans, arrays), every line deleted and every line duplicated; each mutant solved by the
//! built binary (methods taken in turn from `MethodKind::ALL`) under a wall-time budget and
//! judged by `adversarial_harness`. A library-level proptest feeds random numbers into the
//! same fields and checks that validation never panics and names the field it refuses.

use crate::common::adversarial_harness::{methods, root, run_all, scratch};
use ccrkit::method::MethodKind;
use ccrkit::{Model, ModelError};
use proptest::prelude::*;
use std::path::{Path, PathBuf};
use std::time::Duration;

const BUDGET: Duration = Duration::from_secs(30);

const VALUES: &[&str] = &[
    "0", "-1", "1e308", "-1e308", "nan", "inf", "-inf", "1e-300", "3e20", "\"x\"", "true", "[]",
    "1e5", "-0.0",
];

/// Byte ranges of the numeric literals outside comments (`= 1.5`, `[0.1, -2e-3]`, `{ a = 3 }`).
fn numbers(text: &str) -> Vec<(usize, usize)> {
    numbers_after(text, &['=', '[', ',', '{'])
}

/// Byte ranges of the numeric literals that follow one of `seps` (JSON: `:`, `[`, `,`).
fn numbers_after(text: &str, seps: &[char]) -> Vec<(usize, usize)> {
    let mut out = vec![];
    let mut line_start = 0;
    for line in text.split_inclusive('\n') {
        let code = line.split('#').next().unwrap_or("");
        let b = code.as_bytes();
        let mut i = 0;
        while i < b.len() {
            let starts = (b[i].is_ascii_digit()
                || (b[i] == b'-' && b.get(i + 1).is_some_and(u8::is_ascii_digit)))
                && code[..i].trim_end().ends_with(seps);
            if starts {
                let mut j = i + 1;
                while j < b.len() && (b[j].is_ascii_alphanumeric() || b"+-.".contains(&b[j])) {
                    j += 1;
                }
                out.push((line_start + i, line_start + j));
                i = j;
            } else {
                i += 1;
            }
        }
        line_start += line.len();
    }
    out
}

/// Every mutant of `text`: each number replaced by each value, each code line deleted, each
/// code line duplicated.
fn mutants(text: &str) -> Vec<String> {
    let mut out = vec![];
    for (a, b) in numbers(text) {
        for v in VALUES {
            out.push(format!("{}{}{}", &text[..a], v, &text[b..]));
        }
    }
    out.extend(line_mutants(text, |l| {
        !(l.trim().is_empty() || l.trim_start().starts_with('#'))
    }));
    out
}

/// Each line of `text` that `keep` selects deleted, then duplicated (one mutant each).
fn line_mutants(text: &str, keep: impl Fn(&str) -> bool) -> Vec<String> {
    let lines: Vec<&str> = text.lines().collect();
    let mut out = vec![];
    for (k, l) in lines.iter().enumerate() {
        if keep(l) {
            let mut del = lines.clone();
            del.remove(k);
            out.push(del.join("\n"));
            let mut dup = lines.clone();
            dup.insert(k, l);
            out.push(dup.join("\n"));
        }
    }
    out
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).expect("write mutant");
    p
}

#[test]
fn mutated_models_and_scenes_end_named_and_bounded() {
    let dir = scratch("files");
    for sub in ["paper", "scenes", "json"] {
        std::fs::create_dir_all(dir.join(sub)).expect("mkdir");
    }
    #[cfg(unix)]
    {
        let _ = std::os::unix::fs::symlink(root().join("models/meshes"), dir.join("meshes"));
    }
    let ms = methods();
    let case1 = root().join("models/paper/case1.toml").display().to_string();
    let mut jobs = vec![];
    let mut k = 0usize;
    let mut job = |file: String, scene: Option<String>, jobs: &mut Vec<_>| {
        let json = dir.join("json").join(format!("{k}.json"));
        let mut a = vec![
            "solve".to_string(),
            file,
            "--method".into(),
            ms[k % ms.len()].clone(),
            "--json".into(),
            json.display().to_string(),
        ];
        if let Some(s) = scene {
            a.extend(["--scene".to_string(), s]);
        }
        jobs.push((a, Some(json)));
        k += 1;
    };
    for n in 1..=3 {
        let text = std::fs::read_to_string(root().join(format!("models/paper/case{n}.toml")))
            .expect("paper case");
        for (j, m) in mutants(&text).iter().enumerate() {
            let p = write(&dir.join("paper"), &format!("case{n}_{j}.toml"), m);
            job(p.display().to_string(), None, &mut jobs);
        }
    }
    let first_scene = jobs.len();
    for s in ["wall", "pillar", "vessel"] {
        let text =
            std::fs::read_to_string(root().join(format!("models/scenes/{s}.toml"))).expect("scene");
        for (j, m) in mutants(&text).iter().enumerate() {
            let p = write(&dir.join("scenes"), &format!("{s}_{j}.toml"), m);
            job(case1.clone(), Some(p.display().to_string()), &mut jobs);
        }
    }
    // Solving inside the vessel mesh takes seconds per run (README, obstacles), so its mutants
    // (pushed last) are read, validated and refused by the methods without obstacle support:
    // the file's validation is what a mutant tests.
    let no_obstacles: Vec<String> = MethodKind::ALL
        .iter()
        .filter(|k| !k.info().obstacles)
        .map(|k| k.name().to_string())
        .collect();
    let first_vessel = jobs.len()
        - mutants(
            &std::fs::read_to_string(root().join("models/scenes/vessel.toml")).expect("scene"),
        )
        .len();
    for (j, (a, _)) in jobs[first_vessel..].iter_mut().enumerate() {
        a[3] = no_obstacles[j % no_obstacles.len()].clone();
    }
    // The wall's and the pillar's mutants go to the methods that read an obstacle's geometry
    // (a box of zero, negative or huge half extent reaches the closed-form box distance of
    // both obstacle methods, not a refusal by a method without obstacles).
    let with_obstacles: Vec<String> = MethodKind::ALL
        .iter()
        .filter(|k| k.info().obstacles)
        .map(|k| k.name().to_string())
        .collect();
    for (j, (a, _)) in jobs[first_scene..first_vessel].iter_mut().enumerate() {
        a[3] = with_obstacles[j % with_obstacles.len()].clone();
    }
    assert!(jobs.len() > 500, "{} mutants", jobs.len());
    let t = run_all(&dir, jobs, BUDGET);
    t.report_and_assert("mutated files");
}

fn any_number() -> impl Strategy<Value = f64> {
    prop_oneof![
        Just(f64::NAN),
        Just(f64::INFINITY),
        Just(f64::NEG_INFINITY),
        Just(f64::MAX),
        Just(f64::MIN_POSITIVE),
        Just(0.0),
        Just(-0.0),
        -1e3..1e3f64,
        -1.0..1.0f64,
        any::<f64>(),
    ]
}

fn toml_number(x: f64) -> String {
    if x.is_nan() {
        "nan".into()
    } else if x == f64::INFINITY {
        "inf".into()
    } else if x == f64::NEG_INFINITY {
        "-inf".into()
    } else {
        format!("{x:e}")
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 400, failure_persistence: None, ..ProptestConfig::default() })]

    /// Any number in any field of case III: validation never panics; what it refuses it
    /// refuses by naming a field of the model.
    #[test]
    fn any_number_in_any_field_is_validated_by_name(idx in 0usize..64, x in any_number()) {
        let text = std::fs::read_to_string(root().join("models/paper/case3.toml")).expect("case");
        let nums = numbers(&text);
        let (a, b) = nums[idx % nums.len()];
        let m = format!("{}{}{}", &text[..a], toml_number(x), &text[b..]);
        match Model::from_toml_str(&m) {
            Ok(model) => {
                // Accepted values are finite and inside the documented ranges.
                let r = &model.robot;
                prop_assert!(r.length().is_finite() && r.length() <= 100.0);
                prop_assert!(r.backbone.youngs_modulus.is_finite());
            }
            Err(ModelError::Invalid { field, reason }) => {
                // A value may be refused where it clashes with another field (a tiny disk
                // radius refuses the backbone diameter): the error names a real field.
                prop_assert!(!reason.is_empty());
                prop_assert!(
                    ["name", "robot.", "cables", "loads", "scene", "obstacles", "clearance"]
                        .iter().any(|p| field.starts_with(p)),
                    "field `{}` is not a model field ({})", field, reason);
            }
            Err(ModelError::Parse { reason, .. }) => prop_assert!(!reason.is_empty()),
            Err(e) => prop_assert!(false, "unexpected {e:?}"),
        }
    }
}

/// JSON values that replace each number of a JSON scene (`NaN` and `1e999` are not JSON).
const JSON_VALUES: &[&str] = &[
    "0", "-1", "1e308", "-1e308", "1e-300", "1e999", "NaN", "\"x\"", "true", "[]", "null", "{}",
    "-0.0",
];

/// Every mutant of a JSON scene: each number replaced, each line deleted or duplicated, the
/// text truncated at twenty points, wrong types for whole fields, huge arrays, devices.
fn json_scene_mutants(text: &str, dir: &Path) -> Vec<String> {
    let mut out = vec![];
    for (a, b) in numbers_after(text, &[':', '[', ',']) {
        for v in JSON_VALUES {
            out.push(format!("{}{}{}", &text[..a], v, &text[b..]));
        }
    }
    let lines: Vec<&str> = text.lines().collect();
    for k in 0..lines.len() {
        let mut del = lines.clone();
        del.remove(k);
        out.push(del.join("\n"));
        let mut dup = lines.clone();
        dup.insert(k, lines[k]);
        out.push(dup.join("\n"));
    }
    let step = (text.len() / 20).max(1);
    for k in (0..text.len()).step_by(step) {
        out.push(text[..k].to_string());
    }
    let box_ =
        r#"{"shape": "box", "position": [0.055, 0.0, 0.10], "half_extents": [0.005, 0.15, 0.12]}"#;
    // 2000 copies of one box: merged exactly before solving (distinct obstacles beyond the
    // contact budget are refused by name: `tests/contact/dense_scenes.rs`).
    let many = vec![box_; 2000].join(",");
    let long = vec!["0.1"; 100_000].join(",");
    let zero_mesh = r#"{"obstacles": [{"shape": "mesh", "path": "/dev/zero"}]}"#;
    out.extend([
        String::new(),
        "[]".into(),
        "null".into(),
        "{}".into(),
        r#"{"obstacles": {}}"#.into(),
        r#"{"obstacles": "wall"}"#.into(),
        r#"{"obstacles": [], "clearance": "0"}"#.into(),
        r#"{"obstacles": [], "clearance": -1}"#.into(),
        r#"{"obstacles": [{"shape": "sphere"}]}"#.into(),
        r#"{"obstacles": [{"shape": "box", "position": [0, 0], "half_extents": [1, 1, 1]}]}"#.into(),
        format!(r#"{{"obstacles": [{box_}], "obstacles": []}}"#),
        format!(r#"{{"obstacles": [{many}]}}"#),
        format!(r#"{{"obstacles": [{{"shape": "box", "position": [{long}], "half_extents": [1, 1, 1]}}]}}"#),
        zero_mesh.into(),
        zero_mesh.replace("/dev/zero", &dir.join("no-such.stl").display().to_string()),
        "{".repeat(100_000),
    ]);
    out
}

/// `case` with `extra` (e.g. `stiffness = 1e4`) added to every cable table.
fn with_cable_fields(case: &str, extra: &str) -> String {
    case.replace("[[cables]]\n", &format!("[[cables]]\n{extra}\n"))
}

/// The same for the inputs that landed later: mutated JSON scenes (truncated, wrong types,
/// absurd and huge numbers, huge arrays, `/dev/zero`) and absurd cable `stiffness` and
/// `pretension` on every method.
#[test]
fn json_scenes_and_cable_compliance_end_named_and_bounded() {
    let dir = scratch("json-compliance");
    let ms = methods();
    let case1 = root().join("models/paper/case1.toml").display().to_string();
    let mut jobs = vec![];
    let mut k = 0usize;
    let mut job = |a: Vec<String>, jobs: &mut Vec<_>| {
        let json = dir.join(format!("out{k}.json"));
        let mut a = a;
        a.extend(["--json".to_string(), json.display().to_string()]);
        jobs.push((a, Some(json)));
        k += 1;
    };
    let wall = std::fs::read_to_string(root().join("models/scenes/wall.json")).expect("scene");
    let mut scenes = vec![];
    for (j, m) in json_scene_mutants(&wall, &dir).iter().enumerate() {
        scenes.push(write(&dir, &format!("wall_{j}.json"), m));
    }
    #[cfg(unix)]
    {
        let z = dir.join("zero.json");
        let _ = std::os::unix::fs::symlink("/dev/zero", &z);
        scenes.push(z);
    }
    let n_scenes = scenes.len();
    for (j, p) in scenes.into_iter().enumerate() {
        let m = ms[j % ms.len()].clone();
        let a = vec![
            "solve".into(),
            case1.clone(),
            "--method".into(),
            m,
            "--scene".into(),
        ];
        let mut a: Vec<String> = a;
        a.push(p.display().to_string());
        job(a, &mut jobs);
    }
    let stiffness = [
        "0", "-1", "1e308", "\"nan\"", "nan", "inf", "1e-300", "1e5", "-0.0", "\"x\"",
    ];
    let pretension = ["0", "-1", "1e308", "\"nan\"", "nan", "1e5", "1", "-inf"];
    let mut extras: Vec<String> = stiffness
        .iter()
        .map(|v| format!("stiffness = {v}"))
        .collect();
    extras.extend(
        pretension
            .iter()
            .map(|v| format!("stiffness = 1e4\npretension = {v}")),
    );
    extras.push("pretension = 1".into());
    for n in 1..=2 {
        let text = std::fs::read_to_string(root().join(format!("models/paper/case{n}.toml")))
            .expect("paper case");
        for (e, extra) in extras.iter().enumerate() {
            let p = write(
                &dir,
                &format!("case{n}_k{e}.toml"),
                &with_cable_fields(&text, extra),
            );
            for m in &ms {
                job(
                    vec![
                        "solve".into(),
                        p.display().to_string(),
                        "--method".into(),
                        m.clone(),
                    ],
                    &mut jobs,
                );
            }
        }
    }
    println!(
        "{n_scenes} JSON scenes, {} compliance runs",
        jobs.len() - n_scenes
    );
    let t = run_all(&dir, jobs, BUDGET);
    t.report_and_assert("JSON scenes and cable compliance");
}

// Dense scenes (thousands of obstacles within reach; the finding that was
// `many_obstacles_solve_within_the_budget`): `tests/contact/dense_scenes.rs`.

/// The fields of a real robot's model that the paper cases do not have: every number of the
/// `[hardware]` table (gain, offset, base pose, marker, backlash, capstan friction) and of the
/// backbone (with its curvature stiffening) replaced by each absurd value, each of those lines
/// deleted and duplicated; each mutant predicts 12 measured rows (a sequence: backlash and
/// friction act) with the energy model, and the unmutated model with every method (the
/// methods without capstan friction refuse it by name).
#[test]
fn hardware_models_end_named_and_bounded() {
    let dir = scratch("hardware");
    let text = std::fs::read_to_string(root().join("models/hardware/ftdcr_v4.toml"))
        .expect("hardware model")
        .replace(
            "marker = [0.0, 0.0, 0.008]\n",
            "marker = [0.0, 0.0, 0.008]\nbacklash = 1e-4\nfriction = 0.2\n",
        )
        .replace(
            "diameter = 0.001 }",
            "diameter = 0.001, stiffening = 1e-5 }",
        );
    assert!(text.contains("friction = 0.2") && text.contains("stiffening"));
    let data = std::fs::read_to_string(
        root().join("models/hardware/data/v4/tdcr_sysid_20260511-183002_val.csv"),
    )
    .expect("hardware data");
    let rows: Vec<&str> = data.lines().take(13).collect();
    let data = write(&dir, "rows.csv", &rows.join("\n"));
    let fields = [
        "gain", "offset", "base_", "marker", "backlash", "friction", "backbone",
    ];
    let line_of = |at: usize| text[..at].rsplit('\n').next().unwrap_or("").trim_start();
    let mut files = vec![];
    for (a, b) in numbers(&text) {
        if fields.iter().any(|f| line_of(a).starts_with(f)) {
            for v in VALUES {
                files.push(format!("{}{}{}", &text[..a], v, &text[b..]));
            }
        }
    }
    files.extend(line_mutants(&text, |l| {
        fields.iter().any(|f| l.starts_with(f))
    }));
    assert!(files.len() > 150, "{} mutants", files.len());
    let predict = |file: &Path, method: &str, k: usize| {
        let out = dir.join(format!("out{k}.csv")).display().to_string();
        let a = [
            "predict",
            &file.display().to_string(),
            "--data",
            &data.display().to_string(),
            "--out",
            &out,
            "--method",
            method,
        ];
        (a.iter().map(|s| s.to_string()).collect::<Vec<_>>(), None)
    };
    let mut jobs = vec![];
    for (k, m) in files.iter().enumerate() {
        jobs.push(predict(&write(&dir, &format!("m{k}.toml"), m), "energy", k));
    }
    let plain = write(&dir, "plain.toml", &text);
    for (j, m) in methods().iter().enumerate() {
        jobs.push(predict(&plain, m, files.len() + j));
    }
    let t = run_all(&dir, jobs, BUDGET);
    t.report_and_assert("hardware models");
}
