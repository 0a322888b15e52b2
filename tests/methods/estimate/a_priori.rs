//! `energy`'s a-priori discretization part (`energy/local_error.rs`, read from the answer
//! alone) against the discretization error it stands for: the same model at 32 sub-arcs.

use ccrkit::method::estimate::{a_priori_discretization, LOCAL_FACTOR, SAFETY};
use ccrkit::prelude::*;
use ccrkit::study::random::random_model;
use ccrkit_test_support::{port_robots::port_robot, rng::Rng};

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

/// Over `models` (seed, model), the answers at 1 and 2 sub-arcs whose reference at 32 solves:
/// asserts the leading term (the estimate before its safety factor) is at least the distance to
/// the reference; returns how many answers were checked and the ratios term / error of those
/// whose error is above `floor` \[m\].
fn leading_term_ratios(
    models: impl Iterator<Item = (u64, Model)>,
    floor: f64,
) -> (usize, Vec<f64>) {
    let (mut checked, mut ratios) = (0, vec![]);
    for (seed, model) in models {
        let Some((fine, _)) = at(&model, 32) else {
            continue;
        };
        for k in [1, 2] {
            let Some((shape, s)) = at(&model, k) else {
                continue;
            };
            let raw = a_priori_discretization(MethodKind::Energy, &s, &model.robot, &shape)
                .expect("applies")
                / (SAFETY * LOCAL_FACTOR);
            let truth = shape.tip_distance(&fine);
            assert!(
                truth <= raw + 1e-9,
                "seed {seed}, {k} sub-arcs: error {truth:.3e} m above the leading term {raw:.3e} m"
            );
            checked += 1;
            if truth > floor {
                ratios.push(raw / truth);
            }
        }
    }
    ratios.sort_by(f64::total_cmp);
    (checked, ratios)
}

/// The leading term bounds the true discretization error on its own (before the safety
/// factor) on random robots it was not calibrated on, and is not loose (median ≤ 3×).
#[test]
fn the_leading_term_bounds_the_discretization_error_on_random_robots() {
    let models =
        (2000..2030).map(|seed| (seed, random_model(seed).expect("valid by construction")));
    let (_, ratios) = leading_term_ratios(models, 1e-8);
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

/// Random port robot `seed` of the support crate, every cable shortened by a seeded 0–4 %,
/// sagging under gravity across the port axis, the port turned by 0.9 rad.
fn port_model(seed: u64) -> Model {
    let mut r = Rng(seed * 11 + 5);
    let mut t = String::new();
    for line in port_robot(seed).toml.lines() {
        t += line;
        t += "\n";
        if line.starts_with("ends_at") {
            t += &format!("shorten_percent = {}\n", r.range(0.0, 4.0));
        }
        if line.starts_with("insertion") {
            t += "rotation = 0.9\n";
        }
    }
    t += "[loads]\ngravity = [0.0, 9.81, 0.0]\ndisk_mass = 0.002\n";
    Model::from_toml_str(&t).expect("valid by construction")
}

/// Through a port the leading term is that of the robot beyond it (its loads turned into its
/// frame): it bounds the distance to 32 sub-arcs on seeded random port robots as without one.
#[test]
fn the_leading_term_bounds_the_discretization_error_through_a_port() {
    let (checked, ratios) = leading_term_ratios((0..30).map(|seed| (seed, port_model(seed))), 1e-7);
    let median = ratios.get(ratios.len() / 2).copied().unwrap_or(f64::NAN);
    println!(
        "{checked} answers through a port, {} with an error above 0.1 µm: leading term / error median {median:.2}",
        ratios.len()
    );
    assert!(
        checked >= 40 && ratios.len() >= 20,
        "{checked} answers, {} with an error",
        ratios.len()
    );
    assert!(median <= 3.0, "leading term / error: median {median:.2}");
}
