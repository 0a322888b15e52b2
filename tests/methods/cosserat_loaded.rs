//! The loaded rod shot on its external moment (`src/method/cosserat/loaded.rs`: strains from
//! the balance with the loads beyond each point, Newton on the base moment) against
//! independent truths: the converged rod shooting on Rucker–Webster's equations (the paper
//! cases under gravity and a tip force, and seeded random robots with loads), and the
//! stability verdict of that rod's own focal-point test.

use crate::common::paper;
use ccrkit::method::cosserat::Cosserat;
use ccrkit::study::random::random_model;
use ccrkit::{Method, Model, Scene, Shape};
use nalgebra::Vector3;

/// The converged reference: shooting on Rucker–Webster's equations, 64 RK4 steps per
/// section, residual 1e-10 N.
fn converged(m: Cosserat) -> Cosserat {
    Cosserat {
        tolerance: 1e-10,
        ..m.with_unloaded(false).with_steps(64)
    }
}

fn solve(m: &Cosserat, model: &Model) -> Shape {
    m.solve(&model.robot, &model.actuation, &Scene::empty(), None)
        .expect("solves")
}

fn took_loaded_path(shape: &Shape) -> bool {
    shape.report.notes.iter().any(|n| n.starts_with("loaded:"))
}

/// Lateral gravity on a nitinol backbone and a tip force, as `examples/rod_profile.rs`'s
/// `-loaded` cases.
fn load(model: &mut Model, gravity: [f64; 3], tip: [f64; 3]) {
    model.robot.backbone.density = 6450.0;
    model.robot.loads.gravity = Vector3::from(gravity);
    model.robot.loads.tip_force = Vector3::from(tip);
}

/// The largest distance between corresponding disks of two shapes \[m\].
fn worst_disk(a: &Shape, b: &Shape) -> f64 {
    a.disks
        .iter()
        .zip(&b.disks)
        .map(|(x, y)| (x.position - y.position).norm())
        .fold(0.0, f64::max)
}

/// The paper cases under lateral gravity and a tip force, force control, at the default
/// settings: every disk within 1 µm of the converged rod (shooting at the old default, 3 RK4
/// steps per section, missed case III's tip by 7.5 µm), for the full and the inextensible
/// rod, stable as the converged rod's focal-point test says, and every cable's shortening
/// within 1 µm of the converged rod's.
#[test]
fn loaded_paper_cases_meet_the_converged_rod_to_a_micrometre() {
    for n in 1..=3 {
        let mut model = paper(n);
        load(&mut model, [0.0, -9.81, 0.0], [0.05, 0.0, 0.0]);
        for m in [Cosserat::full(), Cosserat::kirchhoff()] {
            let fast = solve(&m, &model);
            assert!(took_loaded_path(&fast), "{:?}", fast.report.notes);
            let reference = solve(&converged(m.clone()), &model);
            assert!(!took_loaded_path(&reference));
            let worst = worst_disk(&fast, &reference);
            assert!(worst <= 1e-6, "case {n} {}: {worst:e} m", m.name());
            assert_eq!(fast.report.stable, reference.report.stable, "case {n}");
            // The shortenings reported: the loaded pass's rest lengths beside its lengths
            // against the reference's pass at zero load.
            for (a, b) in fast.cables.iter().zip(&reference.cables) {
                let (a, b) = (a.shortening.expect("path"), b.shortening.expect("path"));
                assert!(
                    (a - b).abs() <= 1e-6,
                    "case {n}: shortening {a} against {b}"
                );
            }
        }
    }
}

/// Seeded random robots (their own routes, tensions, disk masses) under gravity and a tip
/// force in random directions, each of a size that alone would bend the robot by up to about
/// 0.3 rad (as the generator's disk weights do), force control: every disk within 1 µm of
/// the converged rod shooting on Rucker–Webster's equations, and the same stability verdict
/// wherever that rod's focal-point test decides.
#[test]
fn loaded_path_meets_the_converged_rod_on_random_robots() {
    let mut rng = ccrkit_test_support::rng::Rng(7);
    let (mut taken, mut decided, mut largest) = (0, 0, 0.0f64);
    for seed in 0..40 {
        let mut model = random_model(seed).expect("random robot");
        let (ei, len) = (model.robot.backbone.ei(), model.robot.length());
        // Tip rotation F L²/(2 EI) and sag w L³/(6 EI) up to 0.3 (w = ρ A g).
        let force = 0.6 * ei / (len * len);
        let weight = 1.8 * ei / (len.powi(3) * 6450.0 * model.robot.backbone.area());
        let mut draw = |size: f64| [rng.range(-size, size), rng.range(-size, size), 0.0];
        let (g, f) = (draw(weight), draw(force));
        load(&mut model, g, f);
        for m in [Cosserat::full(), Cosserat::kirchhoff()] {
            let m = m.with_control(ccrkit::actuation::Input::Tension);
            let Ok(fast) = m.solve(&model.robot, &model.actuation, &Scene::empty(), None) else {
                continue;
            };
            if !took_loaded_path(&fast) {
                continue;
            }
            taken += 1;
            let reference = solve(&converged(m.clone()), &model);
            let worst = worst_disk(&fast, &reference);
            assert!(worst <= 1e-6, "seed {seed} {}: {worst:e} m", m.name());
            largest = largest.max(worst);
            if reference.report.stable.is_some() {
                decided += 1;
                assert_eq!(fast.report.stable, reference.report.stable, "seed {seed}");
            }
        }
    }
    eprintln!("{taken} loaded solves, largest disk error {largest:e} m, {decided} decided");
    assert!(taken >= 40, "only {taken} loaded solves");
    assert!(decided >= 10, "the focal-point test decided only {decided}");
}
