//! Convergence of the SQP loop next to obstacles: with the contact curvature in the Hessian
//! the residual falls superlinearly.

use crate::method::energy::Energy;
use crate::model::scene::Scene;
use crate::model::Model;

/// The residual history of the energy solve of case I in `scene`.
fn history(scene: &str) -> Vec<f64> {
    let dir = env!("CARGO_MANIFEST_DIR");
    let mut model = Model::from_file(format!("{dir}/models/paper/case1.toml")).expect("case 1");
    model.scene = Scene::from_file(format!("{dir}/models/scenes/{scene}.toml")).expect("scene");
    let set = Energy::default();
    let prob = set
        .setup(&model.robot, &model.actuation, &model.scene)
        .expect("problem");
    let sol = set.newton(&prob, None).expect("converges");
    assert!(!sol.contacts.is_empty(), "{scene}: no contact");
    sol.history
}

/// Steps from `r_k` to `r_{k+1}` with `r_{k+1} ≤ r_k^1.5` (superlinear; a linear rate would
/// need `r_{k+1} ≤ c r_k`) over the final iterations: after the last residual above `from`,
/// while above `floor`. Returns how many steps were checked.
fn assert_superlinear(h: &[f64], from: f64, floor: f64) -> usize {
    let start = h.iter().rposition(|&r| r >= from).map_or(0, |i| i + 1);
    let mut steps = 0;
    for w in h[start..].windows(2) {
        if w[0] > floor {
            assert!(w[1] <= w[0].powf(1.5), "{:e} → {:e} in {h:?}", w[0], w[1]);
            steps += 1;
        }
    }
    steps
}

/// The wall: a disk rim against a box face; quadratic to round-off.
#[test]
fn wall_converges_superlinearly() {
    let h = history("wall");
    assert!(assert_superlinear(&h, 1e-2, 0.0) >= 3, "{h:?}");
    assert!(*h.last().expect("iterations") <= 1e-10, "{h:?}");
    assert!(h.len() <= 10, "{} iterations: {h:?}", h.len());
}

/// The pillar: two disk rims against a cylinder; superlinear, and to ~1e-12 (issue 16) since a
/// pair near touching is queried from its old normal (no EPA answer, whose normal was off by
/// ~1e-5 rad: the old floor of a few 1e-10).
#[test]
fn pillar_converges_superlinearly() {
    let h = history("pillar");
    assert!(assert_superlinear(&h, 1e-1, 1e-5) >= 2, "{h:?}");
    assert!(*h.last().expect("iterations") <= 1e-12, "{h:?}");
    assert!(h.len() <= 8, "{} iterations: {h:?}", h.len());
}
