//! `energy`'s a-priori discretization part (`energy/local_error.rs`, read from the answer
//! alone) against the discretization error it stands for: the same model at 32 sub-arcs.

use ccrkit::method::estimate::{a_priori_discretization, LOCAL_FACTOR, SAFETY};
use ccrkit::prelude::*;
use ccrkit::study::random::random_model;

/// The answer at `k` sub-arcs (displacement control, as `auto` solves), its settings.
fn at(model: &Model, k: usize) -> Option<(ccrkit::Shape, Settings)> {
    let s = Settings::new()
        .with("control", "displacement")
        .with("sub-arcs", k);
    let solved = SolveRequest::new(MethodKind::Energy)
        .with_settings(s.clone())
        .run(model)
        .ok()?;
    Some((solved.shape, s))
}

/// The leading term bounds the true discretization error on its own (before the safety
/// factor) on random robots it was not calibrated on, and is not loose (median ≤ 3×).
#[test]
fn the_leading_term_bounds_the_discretization_error_on_random_robots() {
    let mut ratios = vec![];
    for seed in 2000..2030 {
        let model = random_model(seed).expect("valid by construction");
        let Some((fine, _)) = at(&model, 32) else {
            continue;
        };
        for k in [1, 2] {
            let Some((shape, s)) = at(&model, k) else {
                continue;
            };
            let raw = a_priori_discretization(MethodKind::Energy, &s, &model.robot, &shape)
                .expect("applies: no obstacles, no port")
                / (SAFETY * LOCAL_FACTOR);
            let truth = shape.tip_distance(&fine);
            assert!(
                truth <= raw + 1e-9,
                "seed {seed}, {k} sub-arcs: error {truth:.3e} m above the leading term {raw:.3e} m"
            );
            if truth > 1e-8 {
                ratios.push(raw / truth);
            }
        }
    }
    ratios.sort_by(f64::total_cmp);
    assert!(ratios.len() >= 20, "only {} answers", ratios.len());
    let median = ratios[ratios.len() / 2];
    assert!(median <= 3.0, "leading term / error: median {median:.2}");
}

/// Straight cables tied at the tip without loads: constant strain per section is the rod's
/// exact answer, so one sub-arc is as good as 32 and the term is 0.
#[test]
fn straight_cables_without_loads_have_no_discretization_error() {
    let model = Model::from_file("models/paper/case1.toml").expect("case I");
    let (one, s) = at(&model, 1).expect("solves");
    let (fine, _) = at(&model, 32).expect("solves");
    let raw = a_priori_discretization(MethodKind::Energy, &s, &model.robot, &one).expect("applies");
    assert!(raw < 1e-9, "{raw:e}");
    assert!(
        one.tip_distance(&fine) < 1e-9,
        "{:e}",
        one.tip_distance(&fine)
    );
}
