//! Random robots × every registered method: proptest draws robots (sections,
//! lengths, disks, backbone, 1–6 cables with straight, helical or per-disk routing, ends
//! anywhere, shortenings from a payout to 99.99 %, tensions, optional loads and obstacles) and
//! solves each with every method of `MethodKind::ALL` through the built binary under a
//! wall-time budget. Judged by `adversarial_harness`: no panic, no hang, no exit 0 with a
//! non-finite number, every failure named. Set `CCRKIT_ADVERSARIAL_CASES` for more robots.

use crate::common::adversarial_harness::{methods, run_all, scratch, Tally};
use nalgebra::{Isometry3, Matrix3, Translation3, UnitQuaternion, Vector3};
use parry3d::math::Pose;
use parry3d::shape::{Ball, Cylinder};
use proptest::prelude::*;
use proptest::strategy::ValueTree;
use proptest::test_runner::{Config, TestRunner};
use std::fmt::Write as _;
use std::time::Duration;

const BUDGET: Duration = Duration::from_secs(40);

#[derive(Debug, Clone)]
struct CableSpec {
    radius_frac: f64,
    angle: f64,
    helix: Option<f64>,
    per_disk_jitter: Option<f64>,
    ends_frac: f64,
    shorten_percent: Option<f64>,
    tension: Option<f64>,
}

#[derive(Debug, Clone)]
struct RobotSpec {
    sections: usize,
    section_length: f64,
    disk_radius: f64,
    thickness_frac: f64,
    youngs: f64,
    diameter_frac: f64,
    cables: Vec<CableSpec>,
    gravity: Option<f64>,
    tip_moment: Option<f64>,
    sphere: Option<(f64, f64)>,
}

fn cable() -> impl Strategy<Value = CableSpec> {
    (
        0.3..0.95f64,
        -7.0..7.0f64,
        prop::option::weighted(0.3, -1.0..1.0f64),
        prop::option::weighted(0.2, 0.0..0.3f64),
        0.0..1.0f64,
        prop::option::weighted(
            0.8,
            prop_oneof![
                4 => -5.0..8.0f64,
                1 => Just(0.0),
                1 => 8.0..99.0f64,
                1 => Just(99.99),
            ],
        ),
        prop::option::weighted(
            0.6,
            prop_oneof![4 => 0.0..10.0f64, 1 => Just(0.0), 1 => 10.0..500.0f64],
        ),
    )
        .prop_map(
            |(radius_frac, angle, helix, per_disk_jitter, ends_frac, shorten_percent, tension)| {
                CableSpec {
                    radius_frac,
                    angle,
                    helix,
                    per_disk_jitter,
                    ends_frac,
                    shorten_percent,
                    tension,
                }
            },
        )
}

fn robot() -> impl Strategy<Value = RobotSpec> {
    (
        (1usize..10, 0.005..0.06f64, 0.003..0.03f64, 0.01..0.3f64),
        (
            prop_oneof![Just(1.1e9), 1e6..2e11f64],
            0.05..0.5f64,
            prop::collection::vec(cable(), 1..6),
        ),
        (
            prop::option::weighted(0.15, -20.0..20.0f64),
            prop::option::weighted(0.1, -0.5..0.5f64),
            prop::option::weighted(0.15, (0.005..0.05f64, 0.0..1.0f64)),
        ),
    )
        .prop_map(|(a, b, c)| RobotSpec {
            sections: a.0,
            section_length: a.1,
            disk_radius: a.2,
            thickness_frac: a.3,
            youngs: b.0,
            diameter_frac: b.1,
            cables: b.2,
            gravity: c.0,
            tip_moment: c.1,
            sphere: c.2,
        })
}

/// How many robots `CCRKIT_ADVERSARIAL_CASES` asks for (unset: the test's own times
/// `CCRKIT_CASES_SCALE`, `crate::common::case_scale`); a value that is not a whole number stops
/// the run naming it.
fn env_cases() -> Option<u32> {
    match std::env::var("CCRKIT_ADVERSARIAL_CASES") {
        Ok(v) => Some(v.trim().parse().unwrap_or_else(|_| {
            panic!("CCRKIT_ADVERSARIAL_CASES must be a whole number, got `{v}`")
        })),
        Err(_) => None,
    }
}

/// The test's own count of robots, times `CCRKIT_CASES_SCALE`, unless `CCRKIT_ADVERSARIAL_CASES`
/// names one.
fn robots(own: u32) -> u32 {
    env_cases().unwrap_or_else(|| own.saturating_mul(crate::common::case_scale()))
}

/// `cases` robots drawn from [`robot`] (proptest's runner with the suites' fixed seed, or
/// `PROPTEST_RNG_SEED`'s: `crate::common::fixed_seed`), each written to `dir/robot<k>.toml`.
fn draw_robots(dir: &std::path::Path, cases: u32) -> Vec<(RobotSpec, std::path::PathBuf)> {
    let mut runner = TestRunner::new(crate::common::fixed_seed(Config {
        cases,
        failure_persistence: None,
        ..Config::default()
    }));
    (0..cases)
        .map(|k| {
            let spec = robot()
                .new_tree(&mut runner)
                .expect("strategy draws")
                .current();
            let file = dir.join(format!("robot{k}.toml"));
            std::fs::write(&file, toml(&spec)).expect("write");
            (spec, file)
        })
        .collect()
}

/// The model file of a spec (valid by construction, except what the methods must judge).
fn toml(r: &RobotSpec) -> String {
    let n = r.sections;
    let mut t = String::new();
    let d = 2.0 * r.disk_radius * r.diameter_frac * 0.5;
    let _ = writeln!(t, "name = \"random\"\n[robot]\nsections = {n}");
    let _ = writeln!(t, "section_length = {:e}", r.section_length);
    let _ = writeln!(t, "disk_radius = {:e}", r.disk_radius);
    let _ = writeln!(
        t,
        "disk_thickness = {:e}",
        r.section_length * r.thickness_frac
    );
    let _ = writeln!(
        t,
        "backbone = {{ youngs_modulus = {:e}, poisson_ratio = 0.3, diameter = {d:e} }}",
        r.youngs
    );
    for (k, c) in r.cables.iter().enumerate() {
        let ends = 1 + ((n - 1) as f64 * c.ends_frac).round() as usize;
        let rad = d / 2.0 + (r.disk_radius - d / 2.0) * c.radius_frac;
        let _ = writeln!(
            t,
            "[[cables]]\nname = \"c{k}\"\nradius = {rad:e}\nends_at = {ends}"
        );
        match (c.helix, c.per_disk_jitter) {
            (Some(h), _) => {
                let _ = writeln!(
                    t,
                    "angles = {{ helix = {{ start = {:e}, per_disk = {h:e} }} }}",
                    c.angle
                );
            }
            (None, Some(j)) => {
                let a: Vec<String> = (0..=ends)
                    .map(|i| format!("{:e}", c.angle + j * ((i * 7919) % 13) as f64 / 13.0))
                    .collect();
                let _ = writeln!(t, "angles = [{}]", a.join(", "));
            }
            (None, None) => {
                let _ = writeln!(t, "angles = {{ straight = {:e} }}", c.angle);
            }
        }
        if let Some(p) = c.shorten_percent {
            let _ = writeln!(t, "shorten_percent = {p:e}");
        }
        if let Some(f) = c.tension {
            let _ = writeln!(t, "tension = {f:e}");
        }
    }
    if r.gravity.is_some() || r.tip_moment.is_some() {
        let _ = writeln!(t, "[loads]");
        if let Some(g) = r.gravity {
            let _ = writeln!(t, "gravity = [0.0, {g:e}, -9.81]\ndisk_mass = 0.002");
        }
        if let Some(m) = r.tip_moment {
            let _ = writeln!(t, "tip_moment = [{m:e}, 0.0, 0.0]");
        }
    }
    if let Some((rad, h)) = r.sphere {
        let len = n as f64 * r.section_length;
        let _ = writeln!(
            t,
            "[[obstacles]]\nname = \"ball\"\nshape = \"sphere\"\nradius = {rad:e}\nposition = [{:e}, 0.0, {:e}]",
            r.disk_radius + rad + 0.002,
            h * len
        );
    }
    t
}

#[test]
fn random_robots_with_every_method_end_named_and_bounded() {
    let dir = scratch("robots");
    let drawn = draw_robots(&dir, robots(40));
    let ms = methods();
    let mut jobs = vec![];
    for (k, (_, file)) in drawn.iter().enumerate() {
        for (j, m) in ms.iter().enumerate() {
            let json = dir.join(format!("robot{k}_{j}.json"));
            let args: Vec<String> = [
                "solve",
                &file.display().to_string(),
                "--method",
                m,
                "--json",
                &json.display().to_string(),
            ]
            .iter()
            .map(|s| s.to_string())
            .collect();
            jobs.push((args, Some(json)));
        }
    }
    let t: Tally = run_all(&dir, jobs, BUDGET);
    t.report_and_assert("random robots × methods");
    // Every solved shape with the ball obstacle keeps its disks out of the ball, checked from
    // the JSON alone with parry3d (independent of the methods' own contact code).
    let mut checked = 0;
    for (k, (spec, _)) in drawn.iter().enumerate() {
        let Some((rad, h)) = spec.sphere else {
            continue;
        };
        let centre = Vector3::new(
            spec.disk_radius + rad + 0.002,
            0.0,
            h * spec.sections as f64 * spec.section_length,
        );
        for (j, m) in ms.iter().enumerate() {
            let json = dir.join(format!("robot{k}_{j}.json"));
            let Ok(text) = std::fs::read_to_string(&json) else {
                continue;
            };
            let v: serde_json::Value = serde_json::from_str(&text).expect("JSON of a solve");
            let depth = deepest_disk_in_ball(&v, spec, centre, rad);
            // Contact tolerances of the methods are far below 1 µm.
            assert!(
                depth < 1e-6,
                "{m} robot{k}: a disk is {depth:e} m inside the ball"
            );
            checked += 1;
        }
    }
    println!("random robots: {checked} solved shapes with an obstacle checked for penetration");
}

/// Largest penetration of a disk (a cylinder at its solved frame) into the ball \[m\].
fn deepest_disk_in_ball(v: &serde_json::Value, spec: &RobotSpec, c: Vector3<f64>, rad: f64) -> f64 {
    let thickness = spec.section_length * spec.thickness_frac;
    let disk = Cylinder::new(thickness / 2.0, spec.disk_radius);
    let ball = Ball::new(rad);
    let ball_pose: Pose = Isometry3::translation(c.x, c.y, c.z).into();
    let num = |x: &serde_json::Value| x.as_f64().expect("a number");
    let mut worst = f64::NEG_INFINITY;
    for d in v["disks"].as_array().expect("disks") {
        let p: Vec<f64> = d["position"]
            .as_array()
            .expect("position")
            .iter()
            .map(num)
            .collect();
        let r: Vec<Vec<f64>> = d["rotation"]
            .as_array()
            .expect("rotation")
            .iter()
            .map(|row| row.as_array().expect("row").iter().map(num).collect())
            .collect();
        let rot = Matrix3::from_fn(|i, j| r[i][j]);
        // Parry's cylinder axis is y; the disk normal is the frame's z.
        let y_to_z = Matrix3::new(1.0, 0.0, 0.0, 0.0, 0.0, -1.0, 0.0, 1.0, 0.0);
        let q = UnitQuaternion::from_matrix(&(rot * y_to_z));
        let pose: Pose = Isometry3::from_parts(Translation3::new(p[0], p[1], p[2]), q).into();
        let gap = parry3d::query::distance(&pose, &disk, &ball_pose, &ball)
            .expect("convex")
            .distance;
        let depth = if gap > 0.0 {
            -gap
        } else {
            parry3d::query::contact(&pose, &disk, &ball_pose, &ball, 0.0)
                .ok()
                .flatten()
                .map_or(0.0, |ct| -ct.dist)
        };
        worst = worst.max(depth);
    }
    worst
}

/// Every number in `v` finite (`null` only where `allowed` says so for its path).
fn finite_numbers(
    v: &serde_json::Value,
    path: &str,
    allowed: &dyn Fn(&str) -> bool,
) -> Option<String> {
    match v {
        serde_json::Value::Null if !allowed(path) => Some(format!("{path} is null")),
        serde_json::Value::Number(n) if n.as_f64().is_none_or(|x| !x.is_finite()) => {
            Some(format!("{path} = {n}"))
        }
        serde_json::Value::Array(a) => a
            .iter()
            .enumerate()
            .find_map(|(k, x)| finite_numbers(x, &format!("{path}[{k}]"), allowed)),
        serde_json::Value::Object(m) => m
            .iter()
            .find_map(|(k, x)| finite_numbers(x, &format!("{path}.{k}"), allowed)),
        _ => None,
    }
}

/// What `report.unique` says holds together, read from the JSON alone: the equilibria are the
/// answer and each try marked distinct (each farther than the tolerance); the converged tries
/// are those with a tip; `only` is one equilibrium and at least one converged try; a try
/// without a tip names its error.
fn unique_consistent(u: &serde_json::Value) -> Result<(), String> {
    let tries = u["tries"].as_array().ok_or("no tries")?;
    let tol = u["tolerance_m"].as_f64().ok_or("no tolerance")?;
    let mut converged = 0;
    let mut distinct = 0;
    for t in tries {
        match (t["tip_distance_m"].as_f64(), t["tip_m"].is_array()) {
            (Some(d), true) => {
                converged += 1;
                if t["distinct"] == true {
                    distinct += 1;
                    if d <= tol {
                        return Err(format!("distinct at {d} ≤ {tol}: {t}"));
                    }
                }
            }
            (None, false) if t["error"].as_str().is_some_and(|e| !e.is_empty()) => {}
            _ => return Err(format!("a try neither converged nor named its error: {t}")),
        }
    }
    let equilibria = u["equilibria"].as_u64().ok_or("no equilibria")? as usize;
    let claimed = u["converged_tries"].as_u64().ok_or("no converged_tries")? as usize;
    if equilibria != 1 + distinct || claimed != converged {
        return Err(format!("{equilibria} equilibria, {claimed} converged: {u}"));
    }
    if u["only"] != (equilibria == 1 && converged > 0) {
        return Err(format!("`only` disagrees with its counts: {u}"));
    }
    Ok(())
}

/// Multiplicity: random robots solved by every method with `--check unique`, and compared
/// (`compare --json`), under the budget: no panic, hang or unnamed failure; every number
/// finite (a `null` only where a try, the other model or a compared row did not solve);
/// `report.unique`
/// consistent with its own tries; the comparison's `any_disagreement` and each pair's
/// `disagree` what its distances and inputs say.
#[test]
fn random_robots_checked_for_other_equilibria_report_consistently() {
    let dir = scratch("multiplicity");
    let drawn = draw_robots(&dir, env_cases().map_or(robots(12), |c| c.div_ceil(3)));
    let ms = methods();
    let mut jobs = vec![];
    let mut files = vec![];
    for (k, (_, file)) in drawn.iter().enumerate() {
        let f = file.display().to_string();
        for (j, m) in ms.iter().enumerate() {
            let json = dir.join(format!("u{k}_{j}.json"));
            let j = json.display().to_string();
            let a = [
                "solve", &f, "--method", m, "--check", "unique", "--json", &j,
            ];
            jobs.push((a.iter().map(|s| s.to_string()).collect(), None));
            files.push(json);
        }
        let json = dir.join(format!("c{k}.json"));
        let a = ["compare", &f, "--json", &json.display().to_string()];
        jobs.push((a.iter().map(|s| s.to_string()).collect(), None));
        files.push(json);
    }
    let t: Tally = run_all(&dir, jobs, BUDGET);
    t.report_and_assert("multiplicity (--check unique, compare)");
    let unconverged = |p: &str| {
        [
            ".tip_distance_m",
            ".tip_m",
            ".stable",
            ".tension",
            ".time_s",
        ]
        .iter()
        .any(|s| p.ends_with(s))
    };
    let (mut checked, mut several) = (0, 0);
    for f in &files {
        let Ok(text) = std::fs::read_to_string(f) else {
            continue;
        };
        let v: serde_json::Value = serde_json::from_str(&text).expect("JSON");
        if let Some(bad) = finite_numbers(&v, "", &unconverged) {
            panic!("{}: {bad}", f.display());
        }
        if let Some(u) = v.pointer("/report/unique") {
            unique_consistent(u).unwrap_or_else(|e| panic!("{}: {e}", f.display()));
            several += usize::from(u["equilibria"].as_u64() > Some(1));
        } else {
            // A row that did not solve has no tip, stability or time, and names its error.
            for r in v["rows"].as_array().expect("rows") {
                let ok = r["status"] == "ok";
                assert_eq!(ok, r["tip_m"].is_array(), "{r}");
                assert_eq!(ok, r["time_s"].is_number(), "{r}");
                assert!(ok || r["error"].is_string(), "{r}");
            }
            let tol = v["tolerance_m"].as_f64().expect("tolerance");
            let pairs = v["pairs"].as_array().expect("pairs");
            for p in pairs {
                let d = p["tip_m"].as_f64().expect("tip distance");
                assert_eq!(p["disagree"], p["same_input"] == true && d > tol, "{p}");
            }
            let any = pairs.iter().any(|p| p["disagree"] == true);
            assert_eq!(v["any_disagreement"], any, "{}", f.display());
        }
        checked += 1;
    }
    assert!(
        checked > files.len() / 3,
        "{checked} of {} answered",
        files.len()
    );
    println!("multiplicity: {checked} answers checked, {several} with more than one equilibrium");
}

/// A drawn robot (`PROPTEST_RNG_SEED=230542268`, robot 62 of 200, its ball left out) whose
/// cable `c1` is shortened by 99.99 %: `energy`'s KKT step left the finite numbers after some
/// fifty iterations, a step length of zero still moved the iterate by `0 · NaN`, and the run
/// ended "infeasible: axial stretch 1+ε = NaN". Now the run ends on its last finite iterate,
/// and the error names a finite stretch (or a residual said in words), never `NaN`.
#[test]
fn a_step_that_leaves_the_finite_numbers_ends_on_the_last_finite_iterate() {
    let toml = r#"name = "random"
[robot]
sections = 2
section_length = 5.161105315732944e-2
disk_radius = 2.3933632344559603e-2
disk_thickness = 1.3476482149063437e-2
backbone = { youngs_modulus = 1.1e9, poisson_ratio = 0.3, diameter = 8.731342962173712e-3 }
[[cables]]
name = "c0"
radius = 1.2469984261485004e-2
ends_at = 1
angles = { helix = { start = -6.768612524157321e-1, per_disk = -9.545375246075412e-1 } }
shorten_percent = 8.96795095391081e1
[[cables]]
name = "c1"
radius = 1.6920970273478667e-2
ends_at = 1
angles = { helix = { start = 6.1878079746188135e0, per_disk = 7.859146294282829e-1 } }
shorten_percent = 9.999e1
[[cables]]
name = "c2"
radius = 1.6258790618528127e-2
ends_at = 1
angles = { helix = { start = 4.454795675662674e0, per_disk = -1.1524633930914763e-1 } }
shorten_percent = -4.953266048112315e0
tension = 7.294986288157921e0
[[cables]]
name = "c3"
radius = 1.6907771731288712e-2
ends_at = 1
angles = [-1.9044062340441128e0, -1.8734708387637309e0]
shorten_percent = -3.4094174388039025e0
tension = 2.2669599805429668e0
[[cables]]
name = "c4"
radius = 1.8641375020497345e-2
ends_at = 1
angles = { straight = 6.076985508985371e0 }
tension = 5.080729865129206e0
"#;
    let model = ccrkit::Model::from_toml_str(toml).expect("the drawn robot is valid");
    let e =
        match ccrkit::prelude::SolveRequest::new(ccrkit::prelude::MethodKind::Energy).run(&model) {
            Ok(s) => panic!(
                "a cable shortened by 99.99 % solved: tip {:?}",
                s.shape.tip()
            ),
            Err(e) => e,
        };
    let msg = e.to_string();
    let non_finite = msg
        .split(|c: char| !c.is_alphanumeric())
        .any(|w| matches!(w.to_lowercase().as_str(), "nan" | "inf" | "infinity"));
    assert!(!non_finite, "a non-finite number in `{msg}`");
    match e {
        ccrkit::SolveError::Infeasible { reason, .. } => {
            // The stretch it names is a number below the floor of 0.5.
            let s: f64 = reason
                .split("1+ε = ")
                .nth(1)
                .and_then(|r| r.split(' ').next())
                .and_then(|x| x.parse().ok())
                .unwrap_or_else(|| panic!("no stretch in `{reason}`"));
            assert!(s.is_finite() && s < 0.5, "{reason}");
        }
        ccrkit::SolveError::NotConverged { .. } => {}
        other => panic!("unexpected {other:?}"),
    }
}
