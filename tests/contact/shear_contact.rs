//! `energy` with `shear = on` next to obstacles (`src/method/energy/newton/shear_step.rs`)
//! against the Cosserat rod with contact (`src/method/cosserat/contact.rs`), whose strains
//! include the shear: the soft lung rod (2 MPa) bent onto a wall by its straight tendon.

use ccrkit::method::run::SolveRequest;
use ccrkit::method::{MethodKind, Settings};
use ccrkit::{Model, Scene, Shape, SolveError};
use ccrkit_test_support::soft::lung_rod_toml;

fn solve(m: &Model, scene: &Scene, kind: MethodKind, shear: &str) -> Result<Shape, SolveError> {
    solve_in(m, scene, kind, shear, 1)
}

/// [`solve`] in `steps` continuation steps (`energy`; the rod takes its own load steps).
fn solve_in(
    m: &Model,
    scene: &Scene,
    kind: MethodKind,
    shear: &str,
    steps: usize,
) -> Result<Shape, SolveError> {
    let mut settings = Settings::new().with("control", "force");
    let mut request = SolveRequest::new(kind);
    if kind == MethodKind::Energy {
        settings = settings.with("shear", shear);
        request.steps = steps;
    }
    request
        .with_settings(settings)
        .solver()?
        .solve(&m.robot, &m.actuation, scene, None)
}

/// The lung rod pulled by its straight tendon and the scene of a 20 mm wall whose near face
/// stops its tip at 0.7 of its free reach (`x`).
fn rod_and_wall() -> (Model, Scene) {
    let text = lung_rod_toml(12, [TENSION, 0.0, 0.0]);
    let m = Model::from_toml_str(&text).expect("lung rod");
    let free = solve(&m, &Scene::default(), MethodKind::Cosserat, "on").expect("free");
    let face = 0.7 * free.tip().x;
    let wall = format!(
        "{text}[[obstacles]]\nname = \"wall\"\nshape = \"box\"\n\
         position = [{}, 0.0, 0.1]\nhalf_extents = [0.01, 0.1, 0.1]\n",
        face + 0.01
    );
    let scene = Model::from_toml_str(&wall).expect("wall").scene;
    (m, scene)
}

/// `energy` cold in one step on the soft rod beside the wall. Its first Newton step put the
/// backbone 13.5 mm into the 20 mm wall, past its middle, and the line search took it (the
/// merit sees a feature inside a convex obstacle): the iterations never settled, 60 of them
/// ending 13.5 mm inside (shear on or off), and this scene needed two continuation steps. The
/// line search now halves a trial that goes deeper than the iterate by more than a quarter of
/// the longest section (`energy/newton/line_search.rs` `depth_allowed`): both converge in a
/// few iterations to the rod with contact (within 0.1 mm; shear on within 0.05 mm), clear of
/// the wall.
#[test]
fn cold_energy_in_one_step_meets_the_rod_beside_a_wall() {
    let (m, scene) = rod_and_wall();
    let rod = solve(&m, &scene, MethodKind::Cosserat, "on").expect("rod");
    let face = scene.obstacles[0].aabb.0.x;
    for (shear, tol) in [("on", 5e-5), ("off", 1e-4)] {
        let e = solve_in(&m, &scene, MethodKind::Energy, shear, 1).expect("energy, cold");
        let d = (e.tip() - rod.tip()).norm();
        eprintln!(
            "shear {shear}: {} iterations, tip {:.4} mm from the rod",
            e.report.iterations,
            d * 1e3
        );
        assert!(e.report.converged && !e.contacts.is_empty());
        assert!(d < tol, "shear {shear}: {d:e} m from the rod");
        // Each station's ball of the body radius stays on the near side of the face.
        let r = m.robot.body_radius();
        let deepest = e
            .disks
            .iter()
            .map(|k| k.position.x + r)
            .fold(f64::MIN, f64::max);
        assert!(
            deepest < face + 1e-6,
            "a station reaches x = {deepest}, the face is at {face}"
        );
    }
}

/// The lung rod (no spacer disks: the rod touches the world with a ball of its body radius at
/// each station, `energy` with its backbone capsules) pulled by its straight tendon towards a
/// wall that stops its tip short of its free place. Target: `energy` within
/// 0.05 mm of the rod on soft rods, now next to obstacles too.
#[test]
fn sheared_energy_meets_the_rod_on_a_soft_rod_pressed_on_a_wall() {
    let (m, scene) = rod_and_wall();
    let free = solve(&m, &Scene::default(), MethodKind::Cosserat, "on").expect("free");
    let face = scene.obstacles[0].aabb.0.x;
    let rod = solve(&m, &scene, MethodKind::Cosserat, "on").expect("rod");
    // In two continuation steps (the way this scene was first solved).
    let sheared = solve_in(&m, &scene, MethodKind::Energy, "on", 2).expect("energy, shear on");
    let plain = solve_in(&m, &scene, MethodKind::Energy, "off", 2).expect("energy, shear off");
    let reaction = |s: &Shape| s.contacts.iter().map(|c| c.multiplier).sum::<f64>();
    let (d_on, d_off) = (
        (sheared.tip() - rod.tip()).norm(),
        (plain.tip() - rod.tip()).norm(),
    );
    eprintln!(
        "free tip x {:.3} mm, wall at {:.3} mm; tip vs rod: shear on {:.4} mm, off {:.4} mm; \
         reactions rod {:.5} N, energy on {:.5} N, off {:.5} N; contacts {} / {}",
        free.tip().x * 1e3,
        face * 1e3,
        d_on * 1e3,
        d_off * 1e3,
        reaction(&rod),
        reaction(&sheared),
        reaction(&plain),
        rod.contacts.len(),
        sheared.contacts.len()
    );
    assert!(!rod.contacts.is_empty() && !sheared.contacts.is_empty());
    assert!(d_on < 5e-5, "shear on: {d_on:e} m from the rod");
    assert!(d_on < d_off, "the shear brings energy closer to the rod");
    let (r, e) = (reaction(&rod), reaction(&sheared));
    assert!((r - e).abs() < 1e-2 * r, "reactions {r} vs {e} N");
}

/// The straight tendon's tension \[N\].
const TENSION: f64 = 0.4;
