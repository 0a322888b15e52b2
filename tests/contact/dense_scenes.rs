//! Dense obstacle scenes (every run bounded): a scene of many obstacles within
//! reach of the robot either solves or ends in the named `contact budget exceeded` error,
//! decided by a count before any solving (`src/contact/broad.rs`, `MAX_PAIRS`); exact
//! duplicates are merged first, so 2000 copies of one box solve as one box, to the bit.
//!
//! Every run goes through the built binary under the adversarial harness's wall-time budget
//! (a hang guard, not a timing assertion).

use crate::common::adversarial_harness;
use crate::common::adversarial_harness::{root, run, run_all, scratch, Verdict};
use crate::common::rng::Rng;
use ccrkit::model::scene::Scene;
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::time::Duration;

const BUDGET: Duration = Duration::from_secs(30);

/// The box the dense scenes repeat: next to case I, across its whole height.
const BOX: &str =
    r#"{"shape": "box", "position": [0.055, 0.0, 0.10], "half_extents": [0.005, 0.15, 0.12]}"#;

fn case1() -> String {
    root().join("models/paper/case1.toml").display().to_string()
}

fn write_scene(dir: &Path, name: &str, obstacles: &[String]) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, format!(r#"{{"obstacles": [{}]}}"#, obstacles.join(","))).expect("write");
    p
}

fn args(a: &[&str]) -> Vec<String> {
    a.iter().map(|s| s.to_string()).collect()
}

/// `ccrkit solve case1 --method M --scene S --json J`: its verdict and, when solved, its JSON.
fn solve(dir: &Path, method: &str, scene: &Path, tag: &str) -> (Verdict, Option<Value>) {
    let json = dir.join(format!("{tag}-{method}.json"));
    let a = args(&[
        "solve",
        &case1(),
        "--method",
        method,
        "--scene",
        &scene.display().to_string(),
        "--json",
        &json.display().to_string(),
    ]);
    let v = run(dir, &a, BUDGET, Some(&json));
    let value = (v == Verdict::Solved)
        .then(|| std::fs::read_to_string(&json).ok())
        .flatten()
        .and_then(|t| serde_json::from_str(&t).ok());
    (v, value)
}

fn tip(v: &Value) -> [f64; 3] {
    let d = v["disks"].as_array().expect("disks");
    let p = &d[d.len() - 1]["position"];
    [0, 1, 2].map(|k| p[k].as_f64().expect("coordinate"))
}

/// 2000 copies of the box solve to the tip of one box (1e-12 m; it is the same solve, so in
/// fact to the bit) with both obstacle methods, and the report says they were merged.
/// Before: > 100 s each (200 copies: 18 s geometric, 3 s energy).
#[test]
fn identical_obstacles_solve_as_one() {
    let dir = scratch("dense-identical");
    let one = write_scene(&dir, "one.json", &[BOX.to_string()]);
    let many = write_scene(&dir, "many.json", &vec![BOX.to_string(); 2000]);
    for m in ["geometric", "energy"] {
        let (v1, j1) = solve(&dir, m, &one, "one");
        let (vn, jn) = solve(&dir, m, &many, "many");
        assert_eq!(v1, Verdict::Solved, "{m}: one box");
        assert_eq!(vn, Verdict::Solved, "{m}: 2000 boxes");
        let (j1, jn) = (j1.expect("json"), jn.expect("json"));
        let (t1, tn) = (tip(&j1), tip(&jn));
        let d = (0..3).map(|k| (t1[k] - tn[k]).abs()).fold(0.0, f64::max);
        assert!(d <= 1e-12, "{m}: tips {t1:?} and {tn:?} differ by {d:e} m");
        // It touches the box (else the test would not test contact).
        assert!(
            jn["contacts"].as_array().is_some_and(|c| !c.is_empty()),
            "{m}: no contact"
        );
        let notes = jn["report"]["notes"].to_string();
        assert!(
            notes.contains("1999 obstacles within reach are exact duplicates"),
            "{m}: {notes}"
        );
    }
}

/// Distinct, nearly coincident boxes (1e-9 m apart: nothing to merge, every pair near the
/// robot at every evaluation, the costliest scene per obstacle) beyond the limit end in the
/// named error with exit 1, before any solving; below it they solve or end named.
#[test]
fn distinct_obstacles_beyond_the_budget_are_refused_by_name() {
    let dir = scratch("dense-distinct");
    let near_box = |k: usize| {
        format!(
            r#"{{"shape": "box", "position": [{}, 0.0, 0.10], "half_extents": [0.005, 0.15, 0.12]}}"#,
            0.055 + 1e-9 * k as f64
        )
    };
    // Case I has 36 features: 114 obstacles give 4104 > 4096 pairs, 113 give 4068 (admitted;
    // the literal method spends ~15 s on them, so only the energy model runs that one here).
    let both = ["geometric", "energy"];
    for (n, refused, methods) in [
        (114usize, true, &both[..]),
        (2000, true, &both[..]),
        (113, false, &both[1..]),
        (3, false, &both[..]),
    ] {
        let obs: Vec<String> = (0..n).map(near_box).collect();
        let scene = write_scene(&dir, &format!("near{n}.json"), &obs);
        for &m in methods {
            let out = std::process::Command::new(adversarial_harness::bin())
                .args(["solve", &case1(), "--method", m, "--scene"])
                .arg(&scene)
                .output()
                .expect("runs");
            let err = String::from_utf8_lossy(&out.stderr);
            if refused {
                assert_eq!(out.status.code(), Some(1), "{m}, {n} boxes: {err}");
                let want = format!(
                    "contact budget exceeded: {n} distinct obstacles within reach of the robot × 36"
                );
                assert!(err.contains(&want), "{m}, {n} boxes: {err}");
                assert!(err.contains("the limit is 4096"), "{err}");
            } else {
                assert!(!err.contains("contact budget"), "{m}, {n} boxes: {err}");
                assert_ne!(out.status.code(), Some(101), "{m}: {err}");
            }
        }
    }
}

/// The merge is exact and only exact: a copy with another name merges, a copy moved by one ulp
/// or turned does not, the first of each group is kept in order, and a scene without
/// duplicates keeps every index in its order.
#[test]
fn only_exact_duplicates_merge() {
    let dir = scratch("dense-merge");
    let moved = BOX.replace(
        "0.055",
        &format!("{:?}", f64::from_bits(0.055f64.to_bits() + 1)),
    );
    let turned = BOX.replace(
        r#""half_extents""#,
        r#""rotation": {"rpy": [0.0, 0.0, 1e-12]}, "half_extents""#,
    );
    let named = BOX.replace('{', r#"{"name": "other", "#);
    let ball = r#"{"shape": "sphere", "position": [0.0, 0.05, 0.1], "radius": 0.01}"#;
    let obs = [
        BOX.to_string(),
        moved.clone(),
        ball.into(),
        named,
        turned,
        ball.into(),
        moved,
    ];
    let p = write_scene(&dir, "mixed.json", &obs);
    let scene = Scene::from_file(&p).expect("scene");
    assert_eq!(scene.distinct((0..7).collect()), vec![0, 1, 2, 4]);
    assert_eq!(scene.exact_duplicates(), 3);
    assert_eq!(scene.distinct(vec![4, 3, 0]), vec![4, 3]);
    let none = write_scene(&dir, "none.json", &obs[..3]);
    let scene = Scene::from_file(&none).expect("scene");
    assert_eq!(scene.distinct(vec![2, 0, 1]), vec![2, 0, 1]);
    assert_eq!(scene.exact_duplicates(), 0);
}

/// One random obstacle around case I's workspace (the robot reaches ~0.2 m up): a sphere, box
/// or capsule, sizes 2–40 mm, anywhere in a 0.3 m box over the base (some touch the robot,
/// some hold the base, some far).
fn random_obstacle(r: &mut Rng) -> String {
    let pos = [
        r.range(-0.12, 0.12),
        r.range(-0.12, 0.12),
        r.range(-0.02, 0.26),
    ];
    let rpy = [r.range(-3.0, 3.0), r.range(-3.0, 3.0), r.range(-3.0, 3.0)];
    let at = format!(
        r#""position": [{}, {}, {}], "rotation": {{"rpy": [{}, {}, {}]}}"#,
        pos[0], pos[1], pos[2], rpy[0], rpy[1], rpy[2]
    );
    let size = |r: &mut Rng| r.range(0.002, 0.04);
    match (r.next() * 3.0) as usize {
        0 => format!(r#"{{"shape": "sphere", {at}, "radius": {}}}"#, size(r)),
        1 => format!(
            r#"{{"shape": "box", {at}, "half_extents": [{}, {}, {}]}}"#,
            size(r),
            size(r),
            size(r)
        ),
        _ => format!(
            r#"{{"shape": "capsule", {at}, "radius": {}, "half_height": {}}}"#,
            size(r),
            size(r)
        ),
    }
}

/// Random dense scenes (1–40 obstacles, some repeated; and a few of 500–800, beyond the
/// budget: case I admits 113 distinct obstacles within reach) through `solve` with `geometric` and `energy`: every run ends solved or with a
/// named error under the wall-time budget — no panic, no hang, no non-finite number — and
/// every scene beyond the budget ends in the budget's error. `CCRKIT_DENSE_SCENES` sets the
/// number of scenes (default 12).
#[test]
fn random_dense_scenes_end_solved_or_named() {
    let dir = scratch("dense-random");
    let n: usize = std::env::var("CCRKIT_DENSE_SCENES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(12);
    let mut r = Rng(0x9e37_79b9_7f4a_7c15);
    let mut jobs = vec![];
    let mut over = vec![];
    for s in 0..n {
        let count = if s % 4 == 3 {
            500 + (r.next() * 300.0) as usize
        } else {
            1 + (r.next() * 40.0) as usize
        };
        let mut obs: Vec<String> = (0..count).map(|_| random_obstacle(&mut r)).collect();
        // Some scenes repeat obstacles (merged exactly).
        if s % 3 == 1 {
            let copies: Vec<String> = obs.iter().take(5).cloned().collect();
            obs.extend(copies.iter().cycle().take(50).cloned());
        }
        let p = write_scene(&dir, &format!("scene{s}.json"), &obs);
        for m in ["geometric", "energy"] {
            let json = dir.join(format!("scene{s}-{m}.json"));
            let a = args(&[
                "solve",
                &case1(),
                "--method",
                m,
                "--scene",
                &p.display().to_string(),
                "--json",
                &json.display().to_string(),
            ]);
            if count >= 500 {
                over.push(a.clone());
            }
            jobs.push((a, Some(json)));
        }
    }
    let t = run_all(&dir, jobs, BUDGET);
    t.report_and_assert("random dense scenes");
    assert!(t.solved > 0 && t.named > 0, "{t:?}");
    // Beyond the budget (of 500+ obstacles in that box far more than 113 lie within the
    // robot's reach): refused by name, by count, before the base disk is checked.
    for a in over {
        let out = std::process::Command::new(adversarial_harness::bin())
            .args(&a[..a.len() - 2])
            .output()
            .expect("runs");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains("contact budget exceeded"), "{err}");
    }
}
