//! `energy` with `shear = on` next to obstacles (`src/method/energy/newton/shear_step.rs`)
//! against the Cosserat rod with contact (`src/method/cosserat/contact.rs`), whose strains
//! include the shear: the soft lung rod (2 MPa) bent onto a wall by its straight tendon.

use ccrkit::method::run::SolveRequest;
use ccrkit::method::{MethodKind, Settings};
use ccrkit::{Model, Scene, Shape, SolveError};
use ccrkit_test_support::soft::lung_rod_toml;

fn solve(m: &Model, scene: &Scene, kind: MethodKind, shear: &str) -> Result<Shape, SolveError> {
    let mut settings = Settings::new().with("control", "force");
    let mut request = SolveRequest::new(kind);
    if kind == MethodKind::Energy {
        settings = settings.with("shear", shear);
        // From the straight start in one step the soft rod's first Newton step lands deep in
        // the wall, where the iterations do not settle (shear on or off); two continuation
        // steps reach it, as the rod's own load steps do.
        request.steps = 2;
    }
    request
        .with_settings(settings)
        .solver()?
        .solve(&m.robot, &m.actuation, scene, None)
}

/// The lung rod (no spacer disks: the rod touches the world with a ball of its body radius at
/// each station, `energy` with its backbone capsules) pulled by its straight tendon towards a
/// wall that stops its tip short of its free place. Target: `energy` within
/// 0.05 mm of the rod on soft rods, now next to obstacles too.
#[test]
fn sheared_energy_meets_the_rod_on_a_soft_rod_pressed_on_a_wall() {
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
    let rod = solve(&m, &scene, MethodKind::Cosserat, "on").expect("rod");
    let sheared = solve(&m, &scene, MethodKind::Energy, "on").expect("energy, shear on");
    let plain = solve(&m, &scene, MethodKind::Energy, "off").expect("energy, shear off");
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
