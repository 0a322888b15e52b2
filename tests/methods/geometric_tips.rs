//! The literal method's answers, recorded, so that speed work cannot change them.
//! Tips (or the error kind) on the paper cases, case I in the wall and pillar scenes, and 340
//! seeded random robots, compared to `tests/data/geometric_tips.json` to 1e-9 m. Recorded from
//! the literal method's first bounded solver (with its stability report) with
//! `CCRKIT_RECORD_TIPS=1 cargo test --release --test methods geometric_tips::`.
//! Since then one entry was recorded again, `case1-pillar` (1.06e-6 m): its disk 6 touches
//! the pillar with its side, whose contact point was the rim point the sign of a ~5e-6 normal
//! component chose (±1 mm along the disk axis); the exact witness (`contact/sat.rs`) puts it
//! where the two sides cross (−0.40 mm), which moves the contact's lever and the tip.

use ccrkit::method::geometric::Geometric;
use ccrkit::{Method, Model, Scene};
use std::collections::BTreeMap;

const TIP_TOL: f64 = 1e-9;
const DATA: &str = "tests/data/geometric_tips.json";

/// A deterministic random robot (6 sections, 1–6 helical cables, shortenings −3..6 % or free).
fn random_model(seed: u64) -> String {
    let mut s = seed.wrapping_mul(0x9E3779B97F4A7C15) | 1;
    let mut rnd = move || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut t = String::from(
        "name = \"random\"\n[robot]\nsections = 6\nsection_length = 0.02\ndisk_radius = 0.012\ndisk_thickness = 0.002\nbackbone = { youngs_modulus = 1.1e9, poisson_ratio = 0.3, diameter = 0.003 }\n",
    );
    let n = 1 + (rnd() * 6.0) as usize;
    for k in 0..n {
        let start = rnd() * std::f64::consts::TAU;
        let per_disk = if rnd() < 0.5 { 0.0 } else { -0.6 + 1.2 * rnd() };
        let radius = 0.004 + 0.006 * rnd();
        t += &format!(
            "[[cables]]\nname = \"c{k}\"\nradius = {radius}\nangles = {{ helix = {{ start = {start}, per_disk = {per_disk} }} }}\n"
        );
        if rnd() < 0.3 {
            t += &format!("ends_at = {}\n", 1 + (rnd() * 6.0) as usize);
        }
        if rnd() < 0.8 {
            t += &format!("shorten_percent = {}\n", -3.0 + 9.0 * rnd());
        }
    }
    t
}

/// Tip [m] or the error kind of every case.
fn outcomes() -> BTreeMap<String, Result<[f64; 3], String>> {
    let mut cases: Vec<(String, Model, Scene)> = vec![];
    for c in 1..=3 {
        let m = Model::from_file(format!("models/paper/case{c}.toml")).expect("case");
        cases.push((format!("case{c}"), m, Scene::empty()));
    }
    for s in ["wall", "pillar"] {
        let m = Model::from_file("models/paper/case1.toml").expect("case I");
        let scene = Scene::from_file(format!("models/scenes/{s}.toml")).expect("scene");
        cases.push((format!("case1-{s}"), m, scene));
    }
    for k in 0..340u64 {
        let m = Model::from_toml_str(&random_model(k)).expect("valid by construction");
        cases.push((format!("random{k:03}"), m, Scene::empty()));
    }
    cases
        .into_iter()
        .map(|(name, m, scene)| {
            let r = Geometric::literal().solve(&m.robot, &m.actuation, &scene, None);
            let out = r
                .map(|s| {
                    let t = s.tip();
                    [t.x, t.y, t.z]
                })
                .map_err(|e| e.kind().to_string());
            (name, out)
        })
        .collect()
}

#[test]
fn tips_equal_the_recorded_ones() {
    let now = outcomes();
    if std::env::var("CCRKIT_RECORD_TIPS").is_ok() {
        std::fs::write(DATA, serde_json::to_string_pretty(&now).expect("json")).expect("write");
        return;
    }
    let text = std::fs::read_to_string(DATA).expect("recorded tips");
    let before: BTreeMap<String, Result<[f64; 3], String>> =
        serde_json::from_str(&text).expect("parses");
    assert_eq!(before.len(), now.len());
    let solved = before.values().filter(|r| r.is_ok()).count();
    // Recorded: 282 shapes (277 random robots and the 5 paper/scene cases), 63 errors
    // (61 not_converged, 2 infeasible); every outcome must stay the same.
    assert!(solved >= 282, "{solved} recorded shapes");
    for (name, b) in &before {
        match (b, &now[name]) {
            (Ok(b), Ok(n)) => {
                let d = (0..3).map(|i| (b[i] - n[i]).abs()).fold(0.0, f64::max);
                assert!(d <= TIP_TOL, "{name}: tip moved {d:e} m");
            }
            (b, n) => assert_eq!(b, n, "{name}"),
        }
    }
}
