//! The rod's unloaded path (`src/method/cosserat/unloaded.rs`: strains from the tendons'
//! balance, one Magnus integration, no shooting; under displacement control Newton on the
//! cables' tensions around it) against independent truths: the shooting rod converged (random
//! robots driven by tensions or by shortenings, the paper cases under displacement control,
//! the 24-section soft lung rod), the closed-form arc of a straight tendon, and its order of
//! convergence.

use crate::common::arc_point;
use ccrkit::method::cosserat::Cosserat;
use ccrkit::study::random::random_model;
use ccrkit::{Method, Model, Scene, Shape};
use ccrkit_test_support::soft::lung_rod_toml;

/// The converged reference: shooting, 64 RK4 steps per section, residual 1e-10 N.
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

fn took_unloaded_path(shape: &Shape) -> bool {
    shape
        .report
        .notes
        .iter()
        .any(|n| n.starts_with("unloaded:"))
}

/// Tip and every disk within 1 µm of the converged shooting rod, the reported shortenings
/// within 1 nm and tensions within 1e-6 (relative), stable (by convexity, and by the shooting
/// rod's focal-point test wherever it decides), on every
/// random robot driven by tensions or by shortenings (its cables' tensions then Newton's
/// unknowns) with no weights, for the full and the inextensible rod at their defaults.
#[test]
fn unloaded_path_meets_the_converged_shooting_rod_on_random_robots() {
    let (mut taken, mut shortened, mut decided) = (0, 0, 0);
    for seed in 0..120 {
        let model = random_model(seed).expect("random robot");
        for m in [Cosserat::full(), Cosserat::kirchhoff()] {
            let fast = solve(&m, &model);
            if !took_unloaded_path(&fast) {
                continue;
            }
            taken += 1;
            if fast
                .report
                .notes
                .iter()
                .any(|n| n.contains("Newton iterations on"))
            {
                shortened += 1;
            }
            let reference = solve(&converged(m.clone()), &model);
            assert!(!took_unloaded_path(&reference));
            let worst = fast
                .disks
                .iter()
                .zip(&reference.disks)
                .map(|(a, b)| (a.position - b.position).norm())
                .fold(0.0f64, f64::max);
            assert!(worst <= 1e-6, "seed {seed} {}: {worst:e} m", m.name());
            for (a, b) in fast.cables.iter().zip(&reference.cables) {
                let (da, db) = (a.shortening.unwrap(), b.shortening.unwrap());
                assert!((da - db).abs() <= 1e-9, "seed {seed}: {da} vs {db}");
                let (ta, tb) = (a.tension.unwrap(), b.tension.unwrap());
                assert!(
                    (ta - tb).abs() <= 1e-6 * (1.0 + tb.abs()),
                    "seed {seed}: {ta} vs {tb}"
                );
            }
            // Stable by convexity on the unloaded path, where shooting's focal-point test
            // (independent: Jacobi fields of its variational pass) decides it too.
            assert_eq!(fast.report.stable, Some(true), "seed {seed}");
            if reference.report.stable.is_some() {
                decided += 1;
                assert_eq!(reference.report.stable, Some(true), "seed {seed}");
            }
            let (wa, wb) = (
                fast.report.base_wrench.unwrap(),
                reference.report.base_wrench.unwrap(),
            );
            for i in 0..6 {
                assert!(
                    (wa[i] - wb[i]).abs() <= 1e-6 * (1.0 + wb[i].abs()),
                    "seed {seed}"
                );
            }
        }
    }
    assert!(taken >= 40, "only {taken} unloaded solves");
    assert!(decided >= 30, "the focal-point test decided only {decided}");
    assert!(
        shortened >= 20,
        "only {shortened} shortened unloaded solves"
    );
}

/// The paper cases under displacement control at the default resolution: the unloaded path
/// meets the converged shooting rod to 0.1 µm at the tip (shooting at the same default steps
/// misses it by up to 1.7 µm on case III), with the same tensions to 1e-6 relative, from a
/// cold start in at most four Newton iterations on the tensions.
#[test]
fn paper_cases_under_displacement_control_meet_the_converged_rod() {
    use ccrkit::actuation::Input;
    for n in 1..=3 {
        let path = format!("{}/models/paper/case{n}.toml", env!("CARGO_MANIFEST_DIR"));
        let model = Model::from_file(path).expect("paper case");
        for m in [Cosserat::full(), Cosserat::kirchhoff()] {
            let m = m.with_control(Input::Shortening);
            let fast = solve(&m, &model);
            assert!(took_unloaded_path(&fast), "case {n}");
            let reference = solve(&converged(m.clone()), &model);
            let err = fast.tip_distance(&reference);
            assert!(err <= 1e-7, "case {n} {}: {err:e} m", m.name());
            assert!(
                fast.report.iterations <= 4,
                "case {n}: {}",
                fast.report.iterations
            );
            for (a, b) in fast.cables.iter().zip(&reference.cables) {
                let (ta, tb) = (a.tension.unwrap(), b.tension.unwrap());
                assert!(
                    (ta - tb).abs() <= 1e-6 * (1.0 + tb.abs()),
                    "case {n}: {ta} vs {tb}"
                );
            }
        }
    }
}

/// A straight tendon bends the inextensible rod into the arc `κ = τ r / EI`; the strains are
/// then constant, which fourth-order Magnus integrates exactly: one step per section meets
/// the closed form to rounding.
#[test]
fn one_step_per_section_is_the_closed_form_arc() {
    let (e, d, r, tau): (f64, f64, f64, f64) = (1.1e9, 0.003, 0.008, 3.0);
    let text = format!(
        "name = \"arc\"\n[robot]\nsections = 9\nsection_length = 0.02\ndisk_radius = 0.012\n\
         disk_thickness = 0.002\nbackbone = {{ youngs_modulus = {e}, poisson_ratio = 0.3, \
         diameter = {d} }}\n[[cables]]\nname = \"A\"\nradius = {r}\nangles = {{ straight = 0.0 }}\n\
         tension = {tau}\n"
    );
    let model = Model::from_toml_str(&text).expect("arc model");
    let ei = e * std::f64::consts::PI * d.powi(4) / 64.0;
    let kappa = tau * r / ei;
    let shape = solve(&Cosserat::kirchhoff().with_steps(1), &model);
    assert!(took_unloaded_path(&shape));
    for disk in &shape.disks {
        let err = (disk.position - arc_point(kappa, disk.s)).norm();
        assert!(err <= 1e-14, "s = {}: {err:e} m", disk.s);
    }
}

/// The soft lung rod at 24 stations, three tendons pulled: the default resolution and even
/// one step per section meet the converged rod to 1 µm at the tip, and the error falls at
/// fourth order in the step (the estimator's `RK4_ORDER` holds for this path too).
#[test]
fn lung_rod_meets_the_converged_rod_and_converges_at_fourth_order() {
    let model = Model::from_toml_str(&lung_rod_toml(24, [1.5, 2.5, 0.7])).expect("lung rod");
    let reference = solve(&converged(Cosserat::full()), &model);
    let err = |steps: usize| {
        let shape = solve(&Cosserat::full().with_steps(steps), &model);
        assert!(took_unloaded_path(&shape));
        shape.tip_distance(&reference)
    };
    let (e1, e2, e3) = (err(1), err(2), err(3));
    assert!(e1 <= 1e-6 && e3 <= 1e-7, "{e1:e} {e3:e}");
    let order = (e1 / e2).log2();
    assert!(
        (3.5..=4.5).contains(&order),
        "order {order} ({e1:e} → {e2:e})"
    );
}
