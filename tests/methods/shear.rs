//! The energy model with shear (`shear = on`, `energy/shear.rs`) against the Cosserat rod it
//! discretizes: a soft rod under helical tendons, Timoshenko's cantilever in closed form,
//! and seeded random robots.

use ccrkit::prelude::*;
use ccrkit::study::random::random_model;

/// Energy with shear against the converged rod on soft rods (the target) \[m\].
const SOFT_BOUND: f64 = 0.05e-3;

/// The converged rod: 20 RK4 steps per section, shooting to the reference tolerance.
fn rod(model: &Model) -> Result<Shape, SolveError> {
    let reference = ccrkit::study::reference();
    SolveRequest::new(MethodKind::Cosserat)
        .with_settings(
            Settings::new()
                .with("rk4-steps", 20)
                .with("tolerance", reference.tolerance),
        )
        .run(model)
        .map(|s| s.shape)
}

fn energy(model: &Model, shear: &str) -> Result<Shape, SolveError> {
    SolveRequest::new(MethodKind::Energy)
        .with_settings(Settings::new().with("shear", shear))
        .run(model)
        .map(|s| s.shape)
}

/// The lung rod (E = 2 MPa, 6 mm, one straight and two helical tendons) at these tensions.
fn lung_rod(tensions: [f64; 3]) -> Model {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/models/soft/lung_rod.toml"
    ))
    .expect("lung rod");
    let mut it = tensions.iter();
    let text: String = text
        .lines()
        .map(|l| match (l.trim() == "tension = 0.0", l) {
            (true, _) => format!("tension = {}", it.next().expect("three cables")),
            (false, l) => l.to_string(),
        })
        .collect::<Vec<_>>()
        .join("\n");
    Model::from_toml_str(&text).expect("model")
}

/// A soft rod under tendon tensions: with shear the energy model meets the rod within
/// 0.05 mm; without it, it does not (so the check can fail).
#[test]
fn soft_rod_meets_the_cosserat_rod_with_shear() {
    let mut worst_off = 0.0f64;
    for t in [
        [0.8, 0.5, 0.0],
        [0.0, 1.0, 0.6],
        [0.5, 0.5, 0.5],
        [1.2, 0.0, 0.0],
        [0.0, 0.0, 1.5],
    ] {
        let m = lung_rod(t);
        let truth = rod(&m).expect("rod");
        let on = energy(&m, "on").expect("energy, shear on");
        let off = energy(&m, "off").expect("energy, shear off");
        let (d_on, d_off) = (on.tip_distance(&truth), off.tip_distance(&truth));
        eprintln!(
            "lung rod {t:?}: energy vs rod {:.4} mm with shear, {:.4} mm without",
            d_on * 1e3,
            d_off * 1e3
        );
        assert!(d_on <= SOFT_BOUND, "{t:?}: {d_on} m");
        worst_off = worst_off.max(d_off);
    }
    assert!(
        worst_off > SOFT_BOUND,
        "shear off never misses: {worst_off}"
    );
}

/// Timoshenko's cantilever: a short, thick soft rod under a small tip force deflects by
/// `F L³ / (3 EI) + F L / GA` (bending plus shear, shear coefficient 1 as the rod takes it);
/// the shear part is 12 % here, and the model with shear meets the sum within 0.5 %.
#[test]
fn cantilever_deflects_by_bending_plus_shear() {
    let (e, nu, d, l, f): (f64, f64, f64, f64, f64) = (2e6, 0.45, 0.01, 0.02, 0.01);
    let text = format!(
        r#"
name = "stub"
[robot]
sections = 4
section_length = {}
tendons = "inside"
spacer_disks = false
backbone = {{ youngs_modulus = {e}, poisson_ratio = {nu}, diameter = {d}, density = 0.0 }}
[[cables]]
name = "A"
radius = 0.002
angles = {{ straight = 0.0 }}
[loads]
tip_force = [{f}, 0.0, 0.0]
"#,
        l / 4.0
    );
    let m = Model::from_toml_str(&text).expect("model");
    let b = &m.robot.backbone;
    let bending = f * l.powi(3) / (3.0 * b.ei());
    let shear = f * l / b.ga();
    let on = energy(&m, "on").expect("shear on").tip().x;
    let off = energy(&m, "off").expect("shear off").tip().x;
    eprintln!(
        "cantilever: FL³/3EI {bending:.4e} + FL/GA {shear:.4e} m; with shear {on:.4e}, \
         without {off:.4e} m"
    );
    let exact = bending + shear;
    assert!(shear > 0.1 * exact, "the shear part is visible");
    assert!(((on - exact) / exact).abs() < 5e-3, "{on} vs {exact}");
    assert!(
        ((off - bending) / bending).abs() < 5e-3,
        "{off} vs {bending}"
    );
    let rod_tip = rod(&m).expect("rod").tip().x;
    assert!(((rod_tip - exact) / exact).abs() < 5e-3, "rod {rod_tip}");
}

/// Seeded random robots: energy (with and without shear, 4 and 8 sub-arcs) against the
/// converged rod (80 RK4 steps per section), median and worst over the robots where both
/// are stable (`cargo test --release --test methods shear::random -- --nocapture`); with
/// shear at the default 4 sub-arcs every one within 0.1 mm (the target).
#[test]
fn random_robots_energy_against_the_rod() {
    let variants: [&[(&str, &str)]; 4] = [
        &[("shear", "off")],
        &[("shear", "on")],
        &[("shear", "off"), ("sub-arcs", "8")],
        &[("shear", "on"), ("sub-arcs", "8")],
    ];
    let mut gaps: Vec<Vec<(u64, f64)>> = vec![vec![]; variants.len()];
    for seed in 0..60 {
        let model = random_model(seed).expect("valid");
        let reference = ccrkit::study::reference();
        let Ok(truth) = SolveRequest::new(MethodKind::Cosserat)
            .with_settings(
                Settings::new()
                    .with("rk4-steps", 80)
                    .with("tolerance", reference.tolerance),
            )
            .run(&model)
        else {
            continue;
        };
        if truth.shape.report.stable == Some(false) {
            continue;
        }
        let shapes: Vec<_> = variants
            .iter()
            .map(|pairs| {
                let mut s = Settings::new();
                for (k, v) in pairs.iter() {
                    s.push(*k, *v);
                }
                SolveRequest::new(MethodKind::Energy)
                    .with_settings(s)
                    .run(&model)
            })
            .collect();
        if shapes.iter().any(|s| {
            s.as_ref()
                .map_or(true, |s| s.shape.report.stable == Some(false))
        }) {
            continue;
        }
        for (g, s) in gaps.iter_mut().zip(&shapes) {
            let s = s.as_ref().expect("checked");
            g.push((seed, s.shape.tip_distance(&truth.shape)));
        }
    }
    assert!(gaps[1].len() >= 50, "only {} robots", gaps[1].len());
    for (pairs, g) in variants.iter().zip(&mut gaps) {
        g.sort_by(|a, b| a.1.total_cmp(&b.1));
        let (wseed, worst) = g.last().copied().unwrap_or_default();
        println!(
            "energy {pairs:?}: {} robots, median {:.4} mm, worst {:.4} mm (seed {wseed}), {} over 0.1 mm",
            g.len(),
            g[g.len() / 2].1 * 1e3,
            worst * 1e3,
            g.iter().filter(|x| x.1 > 1e-4).count()
        );
    }
    let worst = gaps[1].last().map_or(0.0, |x| x.1);
    assert!(worst <= 1e-4, "energy with shear {worst} m from the rod");
}
