//! Actuation files that lie about what they were made for: a reach answer (`reach --json`)
//! names its robot and actuation space (`made_for`), and reading it back (`plan
//! --from-actuation`/`--to-actuation`, [`ccrkit::plan::read_actuation_file`]) with another
//! robot (holes at 4.0 mm instead of 4.5), other limits, or in tension space is refused by
//! name; a file without `made_for` (hand-written, or older) is read by cable name with a
//! warning. Mutants of a reach answer, fed to `plan`, end in a plan or a named error.

use crate::common::adversarial_harness::cli::ccrkit_in;
use crate::common::adversarial_harness::{args, root, run_all, scratch};
use ccrkit::fingerprint::MadeFor;
use ccrkit::method::run::SolveRequest;
use ccrkit::method::{MethodKind, Settings};
use ccrkit::plan::{read_actuation_file, read_actuation_in};
use ccrkit::reach::Space;
use ccrkit::{Model, ModelError};
use std::path::{Path, PathBuf};
use std::time::Duration;

const TWO_SEGMENT: &str = "models/plan/two_segment.toml";

fn model_text() -> String {
    std::fs::read_to_string(root().join(TWO_SEGMENT)).expect("model")
}

/// The two-segment robot with `from` replaced by `to` in its file.
fn variant(from: &str, to: &str) -> Model {
    let text = model_text();
    assert!(text.contains(from), "{from}");
    Model::from_toml_str(&text.replacen(from, to, 1)).expect("variant parses")
}

fn space(model: &Model, request: &SolveRequest) -> Space {
    Space::new(model, request, false).expect("space")
}

fn shortening() -> SolveRequest {
    SolveRequest::new(MethodKind::DEFAULT)
}

/// A reach-style answer of the two-segment robot: every cable shortened by `x`, what it was
/// made for given (`made_for`: its JSON, or none), in `space_name` space.
fn answer(dir: &Path, name: &str, x: f64, made_for: Option<&MadeFor>, space_name: &str) -> PathBuf {
    let cables = ["s0t0", "s0t1", "s0t2", "s1t0", "s1t1", "s1t2"];
    let list: Vec<serde_json::Value> = cables
        .iter()
        .map(|c| serde_json::json!({"cable": c, "shorten": x, "tension": 1.0}))
        .collect();
    let mut v = serde_json::json!({"actuation": list, "space": space_name});
    if let Some(m) = made_for {
        v["made_for"] = serde_json::to_value(m).expect("made_for");
    }
    let path = dir.join(name);
    std::fs::write(&path, v.to_string()).expect("write");
    path
}

fn refused(r: Result<impl std::fmt::Debug, ModelError>, field: &str, says: &str) {
    match r {
        Err(ModelError::Invalid { field: f, reason }) => {
            assert_eq!(f, field, "{reason}");
            assert!(reason.contains(says), "{reason}");
        }
        other => panic!("expected `{field}` refused, got {other:?}"),
    }
}

/// Read for the robot and space it was made for, the answer is believed (its point, its
/// `made_for` kept); made for another robot — one hole radius 4.0 mm instead of 4.5, cable
/// names and limits the same — or another space — one cable's limits changed, or tensions
/// instead of shortenings — it is refused by the field that differs.
#[test]
fn an_actuation_made_for_another_robot_or_space_is_refused_by_name() {
    let dir = scratch("actuation-made-for");
    let model = Model::from_file(root().join(TWO_SEGMENT)).expect("model");
    let own = space(&model, &shortening());
    let made = MadeFor::of_space(&own);
    let ok = answer(&dir, "ok.json", 0.001, Some(&made), "shortening");
    let read = read_actuation_file(&ok, &model, &own).expect("its own robot and space");
    assert_eq!(read.point, vec![0.001; 6]);
    assert_eq!(read.made_for.as_ref(), Some(&made));
    assert!(read.warning(&ok).is_none());

    let holes = variant("radius = 0.0045", "radius = 0.004");
    let other_robot = space(&holes, &shortening());
    refused(
        read_actuation_file(&ok, &holes, &other_robot),
        "made_for.robot_fingerprint",
        "made for robot `two-segment`",
    );
    // The reader without a space still checks the robot.
    refused(
        read_actuation_in(&ok, &holes, ccrkit::model::actuation::Input::Shortening),
        "made_for.robot_fingerprint",
        "ok.json",
    );

    let narrow = variant(
        "[limits.s0t0]\nshorten = [-0.004, 0.004]",
        "[limits.s0t0]\nshorten = [-0.002, 0.002]",
    );
    let narrow_space = space(&narrow, &shortening());
    refused(
        read_actuation_file(&ok, &narrow, &narrow_space),
        "made_for.space_fingerprint",
        "this request's shortening space",
    );

    let mut force = Settings::new();
    force.push("control", "force");
    let tension = SolveRequest::new(MethodKind::Energy).with_settings(force);
    let limited = model_text()
        .lines()
        .map(|l| match l.starts_with("shorten = [") {
            true => format!("{l}\ntension = [0.0, 20.0]"),
            false => l.to_string(),
        })
        .collect::<Vec<_>>()
        .join("\n");
    let limited = Model::from_toml_str(&limited).expect("tension limits parse");
    let tension_space = space(&limited, &tension);
    refused(
        read_actuation_file(&ok, &limited, &tension_space),
        "space",
        "written in shortening space",
    );
    // Without the `space` key, the fingerprint still tells the spaces apart.
    let unnamed = answer(&dir, "unnamed.json", 1.0, Some(&made), "tension");
    let mut v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&unnamed).expect("read")).expect("json");
    v.as_object_mut().expect("object").remove("space");
    std::fs::write(&unnamed, v.to_string()).expect("write");
    refused(
        read_actuation_file(&unnamed, &limited, &tension_space),
        "made_for.space_fingerprint",
        "this request's tension space",
    );
}

/// A file without `made_for` (hand-written, or written before ccrkit recorded it) is read by
/// cable name with a warning naming it; a `made_for` that is not what ccrkit writes, or that
/// lacks the space, is refused by name.
#[test]
fn an_actuation_without_made_for_is_read_with_a_warning_and_a_broken_one_refused() {
    let dir = scratch("actuation-no-made-for");
    let model = Model::from_file(root().join(TWO_SEGMENT)).expect("model");
    let own = space(&model, &shortening());
    let old = answer(&dir, "old.json", -0.001, None, "shortening");
    let read = read_actuation_file(&old, &model, &own).expect("read by cable name");
    assert_eq!(read.point, vec![-0.001; 6]);
    let w = read.warning(&old).expect("a warning");
    assert!(w.contains("old.json") && w.contains("made_for"), "{w}");

    let broken = answer(&dir, "broken.json", 0.0, None, "shortening");
    let text = std::fs::read_to_string(&broken).expect("read");
    std::fs::write(&broken, text.replacen('{', "{\"made_for\": 3, ", 1)).expect("write");
    refused(
        read_actuation_file(&broken, &model, &own),
        "made_for",
        "not what ccrkit writes",
    );
    let plan_like = MadeFor::new(&model.robot, &model.scene, 0.0, &shortening());
    let no_space = answer(&dir, "no_space.json", 0.0, Some(&plan_like), "shortening");
    refused(
        read_actuation_file(&no_space, &model, &own),
        "made_for.space_fingerprint",
        "(none)",
    );
}

/// The command line: `reach --json` writes `made_for`; `plan --to-actuation` takes it for
/// its robot, refuses it by name for the robot with 4.0 mm holes, and reads a file without
/// `made_for` with a `warning:` line.
#[test]
fn reach_answers_round_trip_through_plan_and_are_refused_for_another_robot() {
    let dir = scratch("actuation-cli");
    std::fs::copy(root().join(TWO_SEGMENT), dir.join("m.toml")).expect("copy");
    std::fs::write(
        dir.join("holes.toml"),
        model_text().replacen("radius = 0.0045", "radius = 0.004", 1),
    )
    .expect("variant");
    let out = ccrkit_in(
        &dir,
        &[
            "reach",
            "m.toml",
            "--tip",
            "0.01,0,0.12",
            "--json",
            "r.json",
        ],
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let r: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("r.json")).expect("r"))
            .expect("json");
    assert_eq!(r["space"], "shortening");
    assert_eq!(r["made_for"]["robot"], "two-segment");
    assert!(
        r["made_for"]["space_fingerprint"].is_string(),
        "{}",
        r["made_for"]
    );

    let plan = ccrkit_in(&dir, &["plan", "m.toml", "--to-actuation", "r.json"]);
    let err = String::from_utf8_lossy(&plan.stderr);
    assert!(plan.status.success() && !err.contains("warning"), "{err}");

    let other = ccrkit_in(
        &dir,
        &[
            "plan",
            "holes.toml",
            "--from-actuation",
            "r.json",
            "--to-tip",
            "0,0,0.12",
        ],
    );
    let err = String::from_utf8_lossy(&other.stderr);
    assert_eq!(other.status.code(), Some(1), "{err}");
    assert!(
        err.contains("`made_for.robot_fingerprint`") && err.contains("r.json"),
        "{err}"
    );

    let mut old = r.clone();
    old.as_object_mut().expect("object").remove("made_for");
    std::fs::write(dir.join("old.json"), old.to_string()).expect("old");
    let warned = ccrkit_in(&dir, &["plan", "m.toml", "--to-actuation", "old.json"]);
    let err = String::from_utf8_lossy(&warned.stderr);
    assert!(warned.status.success(), "{err}");
    assert!(
        err.contains("warning: `old.json` names no `made_for`"),
        "{err}"
    );
}

/// Every field of a reach answer replaced by absurd values (its fingerprints flipped or
/// emptied, `made_for` and its parts of the wrong type, entries renamed, repeated, dropped or
/// multiplied to 20 000, shortenings of ±1e308, strings, `null`), each fed to `plan
/// --to-actuation` under a budget: a plan or a named error, never a panic, a hang or a
/// non-finite number.
#[test]
fn mutated_reach_answers_end_in_a_plan_or_a_named_error() {
    let dir = scratch("actuation-mutants");
    std::fs::copy(root().join(TWO_SEGMENT), dir.join("m.toml")).expect("copy");
    let model = Model::from_file(root().join(TWO_SEGMENT)).expect("model");
    let made = MadeFor::of_space(&space(&model, &shortening()));
    let base = answer(&dir, "base.json", 0.0005, Some(&made), "shortening");
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&base).expect("read")).expect("json");
    let mut files = Vec::new();
    let absurd = [
        serde_json::json!(null),
        serde_json::json!(-1e308),
        serde_json::json!(1e308),
        serde_json::json!("x"),
        serde_json::json!([]),
        serde_json::json!({}),
        serde_json::json!(true),
    ];
    let mut set = |path: &[&str], val: serde_json::Value| {
        let mut m = v.clone();
        let mut at = &mut m;
        for p in path {
            at = match p.parse::<usize>() {
                Ok(k) => &mut at[k],
                Err(_) => &mut at[*p],
            };
        }
        *at = val;
        files.push(m);
    };
    for key in [
        "robot",
        "robot_fingerprint",
        "space_fingerprint",
        "scene_fingerprint",
        "margin_m",
        "method",
        "settings",
    ] {
        for val in &absurd {
            set(&["made_for", key], val.clone());
        }
        set(&["made_for", key], serde_json::json!("0000000000000000"));
    }
    for val in &absurd {
        set(&["made_for"], val.clone());
        set(&["space"], val.clone());
        set(&["actuation"], val.clone());
        for k in [0, 5] {
            set(&["actuation", &k.to_string(), "shorten"], val.clone());
            set(&["actuation", &k.to_string(), "cable"], val.clone());
            set(&["actuation", &k.to_string()], val.clone());
        }
    }
    set(&["actuation", "2", "cable"], serde_json::json!("zzz"));
    set(&["actuation", "2", "cable"], serde_json::json!("s0t0"));
    let entries = v["actuation"].as_array().expect("list").clone();
    set(&["actuation"], serde_json::json!(entries[..5]));
    let many: Vec<serde_json::Value> = entries.iter().cycle().take(20_000).cloned().collect();
    set(&["actuation"], serde_json::json!(many));
    let mut jobs = Vec::new();
    for (k, f) in files.iter().enumerate() {
        let name = format!("m{k}.json");
        std::fs::write(dir.join(&name), f.to_string()).expect("write");
        jobs.push((
            args(&[
                "plan",
                "m.toml",
                "--to-actuation",
                &name,
                "--json",
                &format!("p{k}.json"),
            ]),
            Some(dir.join(format!("p{k}.json"))),
        ));
    }
    let n = jobs.len();
    let t = run_all(&dir, jobs, Duration::from_secs(60));
    t.report_and_assert("actuation_files");
    assert_eq!(t.runs, n);
    assert!(t.named > n / 2, "most mutants are refused: {t:?}");
}
