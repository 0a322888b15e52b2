//! `energy` with its own sub-arc count in each section (`sub-arcs = 1,2,4`) and `auto`'s
//! refinement section by section where the a-priori estimate's part is large: against the
//! same model converged (32 sub-arcs in every section, the same shear setting).

use ccrkit::method::estimate::a_priori_discretization;
use ccrkit::prelude::*;
use ccrkit::study::random::random_model;
use ccrkit_test_support::rng::Rng;

/// `energy` at `sub_arcs` (a count or a list), displacement control as `auto` solves,
/// `shear` on or off; the shape and its settings.
fn energy(model: &Model, sub_arcs: &str, shear: bool) -> Option<(ccrkit::Shape, Settings)> {
    let s = Settings::new()
        .with("control", "displacement")
        .with("sub-arcs", sub_arcs)
        .with("shear", if shear { "on" } else { "off" });
    let solved = SolveRequest::new(MethodKind::Energy)
        .with_settings(s.clone())
        .run(model)
        .ok()?;
    Some((solved.shape, s))
}

/// One count in every section is the uniform discretization, bit for bit.
#[test]
fn equal_counts_per_section_are_the_uniform_discretization() {
    let model = Model::from_file("models/paper/case3.toml").expect("case III");
    let list = vec!["3"; model.robot.sections()].join(",");
    let (a, _) = energy(&model, "3", false).expect("solves");
    let (b, _) = energy(&model, &list, false).expect("solves");
    assert_eq!(a.disks, b.disks);
}

/// A list of the wrong length is refused by name.
#[test]
fn a_count_per_section_must_fit_the_robot() {
    let model = Model::from_file("models/paper/case3.toml").expect("case III");
    let err = SolveRequest::new(MethodKind::Energy)
        .with_settings(Settings::new().with("sub-arcs", "1,2"))
        .run(&model)
        .expect_err("two counts for nine sections");
    assert!(err.to_string().contains("sub-arcs"), "{err}");
}

/// Uneven counts (1–4, drawn per section) converge towards the same answer as even ones: the
/// a-priori estimate (safety factor included) bounds the distance to 32 sub-arcs, and doubling
/// every count shrinks it about fourfold (order 2).
#[test]
fn uneven_counts_are_bounded_by_their_estimate_and_converge_at_order_two() {
    let mut rng = Rng(77);
    let (mut checked, mut ratios) = (0, vec![]);
    for seed in 5000..5020 {
        let model = random_model(seed).expect("valid by construction");
        let Some((fine, _)) = energy(&model, "32", false) else {
            continue;
        };
        let n = model.robot.sections();
        let counts: Vec<usize> = (0..n).map(|_| 1 + (4.0 * rng.next()) as usize).collect();
        let list = |k: usize| {
            let c: Vec<String> = counts.iter().map(|m| (k * m).to_string()).collect();
            c.join(",")
        };
        let (Some((one, s)), Some((two, _))) = (
            energy(&model, &list(1), false),
            energy(&model, &list(2), false),
        ) else {
            continue;
        };
        let est =
            a_priori_discretization(MethodKind::Energy, &s, &model.robot, &one).expect("applies");
        let (e1, e2) = (one.tip_distance(&fine), two.tip_distance(&fine));
        assert!(
            e1 <= est + 1e-9,
            "seed {seed} {counts:?}: error {e1:.3e} above estimate {est:.3e}"
        );
        checked += 1;
        if e1 > 1e-7 {
            ratios.push(e1 / e2);
        }
    }
    assert!(checked >= 15, "only {checked} robots solved");
    ratios.sort_by(f64::total_cmp);
    let median = ratios[ratios.len() / 2];
    println!(
        "error(counts) / error(2 × counts): median {median:.2} of {}",
        ratios.len()
    );
    assert!((3.0..=5.5).contains(&median), "median ratio {median:.2}");
}

/// Sub-arcs solved in an `energy` answer (`sub-arcs=1,2,4` or `sub-arcs=4` over `n` sections).
fn total(setting: &str, n: usize) -> usize {
    let value = setting.trim_start_matches("sub-arcs=");
    let value = value.strip_suffix(", shear=on").unwrap_or(value);
    let counts: Vec<usize> = value
        .split(',')
        .map(|v| v.parse().expect("count"))
        .collect();
    if counts.len() == 1 {
        counts[0] * n
    } else {
        counts.iter().sum()
    }
}

/// Uniform refinement as `auto` walked it before it refined section by section: from one
/// sub-arc, the first ladder rung predicted (order 2) within 70 % of what the model part
/// leaves of `tol`, solved and estimated, until one meets `tol`; its count per section and
/// the solves it took.
fn uniform_walk(model: &Model, tol: f64, shear: bool, model_part: f64) -> Option<(usize, usize)> {
    let ladder = [1, 2, 3, 4, 6, 8, 12, 16];
    let (mut at, mut solves) = (0, 0);
    loop {
        let k = ladder[at];
        let (shape, set) = energy(model, &k.to_string(), shear)?;
        solves += 1;
        let d = a_priori_discretization(MethodKind::Energy, &set, &model.robot, &shape)?;
        if d + model_part <= tol || at + 1 == ladder.len() {
            return Some((k, solves));
        }
        let room = 0.7 * (tol - model_part);
        at = (at + 1..ladder.len())
            .find(|&j| d * (k as f64 / ladder[j] as f64).powi(2) <= room)
            .unwrap_or(ladder.len() - 1);
    }
}

/// `auto` on seeded random robots: where it answers with `energy`, that answer is within the
/// tolerance of the same model converged (32 sub-arcs, same shear) and its discretization
/// estimate bounds that distance; and its answer has no more sub-arcs in total over the
/// robots, in no more solves, than uniform refinement stopping at the same tolerance
/// ([`uniform_walk`]).
#[test]
fn auto_refines_where_the_estimate_says_so_and_solves_fewer_sub_arcs_than_uniform() {
    for tol in [1e-4, 1e-3] {
        let (mut adaptive, mut uniform, mut compared) = (0, 0, 0);
        let (mut solves, mut uniform_solves) = (0, 0);
        for seed in 6000..6025 {
            let model = random_model(seed).expect("valid by construction");
            let Ok(answer) = SolveRequest::auto(tol).run(&model) else {
                continue;
            };
            let a = answer.shape.report.auto.clone().expect("auto report");
            if a.method != "energy" {
                continue;
            }
            let shear = a.setting.ends_with("shear=on");
            let Some((fine, _)) = energy(&model, "32", shear) else {
                continue;
            };
            let est = answer
                .shape
                .report
                .error_estimate
                .clone()
                .expect("estimate");
            let truth = answer.shape.tip_distance(&fine);
            assert!(
                truth <= tol,
                "seed {seed} {}: {truth:.3e} m > {tol:e}",
                a.setting
            );
            let disc = est.discretization_m.expect("discretization part");
            assert!(
                truth <= disc + 1e-9,
                "seed {seed} {}: {truth:.3e} > estimate {disc:.3e}",
                a.setting
            );
            let n = model.robot.sections();
            let Some((k, walked)) = uniform_walk(&model, tol, shear, est.model_m.unwrap_or(0.0))
            else {
                continue;
            };
            let (mine, theirs) = (total(&a.setting, n), k * n);
            println!(
                "seed {seed} T {tol:e}: {} ({mine}) against sub-arcs={k} ({theirs})",
                a.setting
            );
            adaptive += mine;
            uniform += theirs;
            compared += 1;
            // The shear ladder's solves come after the unsheared one's: compare like with like.
            if !shear {
                solves += a.solves;
                uniform_solves += walked;
            }
        }
        println!(
            "T {tol:e}: {adaptive} sub-arcs against {uniform} uniform over {compared} answers; \
             {solves} solves against {uniform_solves}"
        );
        assert!(compared >= 15, "only {compared} energy answers");
        assert!(adaptive <= uniform, "{adaptive} > {uniform}");
        assert!(solves <= uniform_solves, "{solves} > {uniform_solves}");
    }
}
