//! How often the estimate bounds the true error: seeded random robots, each method at a few
//! resolutions, the true error the tip distance to the converged rod (study::reference: 80
//! RK4 steps per section, shooting to 1e-11 N) driven by the same inputs.

use ccrkit::prelude::*;
use ccrkit::study::random::random_model;

const ROBOTS: u64 = 60;

#[test]
fn the_bound_holds_on_at_least_95_percent_of_random_answers() {
    let variants: [(MethodKind, &[(&str, &str)]); 7] = [
        (MethodKind::Energy, &[("sub-arcs", "1")]),
        (MethodKind::Energy, &[("sub-arcs", "2")]),
        (MethodKind::Energy, &[]),
        (MethodKind::Cosserat, &[("rk4-steps", "2")]),
        (MethodKind::Cosserat, &[]),
        (MethodKind::Cosserat, &[("adaptive", "1e-5")]),
        (MethodKind::Kirchhoff, &[]),
    ];
    let mut held = 0;
    let mut total = 0;
    let mut ratios = vec![];
    for seed in 0..ROBOTS {
        let model = random_model(seed).expect("valid by construction");
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
        for (kind, pairs) in &variants {
            let mut s = Settings::new();
            for (k, v) in pairs.iter() {
                s.push(*k, *v);
            }
            let Ok(solved) = SolveRequest::new(*kind)
                .with_settings(s)
                .with_estimate(true)
                .run(&model)
            else {
                continue;
            };
            let est = solved
                .shape
                .report
                .error_estimate
                .clone()
                .expect("asked for");
            let Some(bound) = est.bound_m else { continue };
            let err = solved.shape.tip_distance(&truth.shape);
            total += 1;
            if err <= bound.max(1e-9) {
                held += 1;
            } else {
                println!(
                    "seed {seed} {kind} {pairs:?}: error {err:.3e} m > bound {bound:.3e} (disc {:?}, model {:?})",
                    est.discretization_m, est.model_m
                );
            }
            ratios.push(bound / err.max(1e-12));
        }
    }
    ratios.sort_by(f64::total_cmp);
    let rate = held as f64 / total as f64;
    println!(
        "estimate bounds the true error in {held}/{total} = {:.1} % of answers; bound/error median {:.2}",
        100.0 * rate,
        ratios[ratios.len() / 2]
    );
    assert!(total >= 250, "only {total} answers");
    assert!(rate >= 0.95, "bound held in {:.1} %", 100.0 * rate);
}
