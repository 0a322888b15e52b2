//! The orders of convergence the estimator assumes, measured: the tip error of a resolution
//! against a much finer solve of the same method, halving the resolution step.

use ccrkit::method::estimate::{RK4_ORDER, SUB_ARC_ORDER};
use ccrkit::prelude::*;

/// Observed order from tip errors at resolutions n and 2n against a fine solve.
fn observed(model: &Model, method: MethodKind, name: &str, ns: [usize; 3], fine: usize) -> f64 {
    let tip = |n: usize| {
        SolveRequest::new(method)
            .with_settings(Settings::new().with(name, n).with("bend-refine", "off"))
            .run(model)
            .expect("solves")
            .shape
            .tip()
    };
    let solve_with = |n: usize| {
        if method == MethodKind::Energy {
            SolveRequest::new(method)
                .with_settings(Settings::new().with(name, n))
                .run(model)
                .expect("solves")
                .shape
                .tip()
        } else {
            tip(n)
        }
    };
    let reference = solve_with(fine);
    let e: Vec<f64> = ns
        .iter()
        .map(|&n| (solve_with(n) - reference).norm())
        .collect();
    let p1 = (e[0] / e[1]).log2();
    let p2 = (e[1] / e[2]).log2();
    println!("{method} {name} {ns:?}: errors {e:?}, orders {p1:.2} {p2:.2}");
    // Below 1e-8 m the shooting tolerance, not the step, sets the error.
    if e[2] < 1e-8 {
        p1
    } else {
        0.5 * (p1 + p2)
    }
}

/// A soft rod with a helical cable and one tied half-way.
const SOFT_HELIX: &str = r#"
name = "soft-helix"
[robot]
sections = 12
section_length = 0.01
disk_radius = 0.004
disk_thickness = 0.001
backbone = { youngs_modulus = 3e6, poisson_ratio = 0.45, diameter = 0.004 }
[[cables]]
name = "A"
radius = 0.0025
angles = { helix = { start = 0.0, per_disk = 0.3 } }
tension = 0.3
[[cables]]
name = "B"
radius = 0.0025
angles = { straight = 2.0 }
ends_at = 6
tension = 0.2
"#;

#[test]
fn sub_arcs_converge_at_order_two_and_rk4_at_order_four() {
    // A helical cable and one tied half-way: the curvature varies along every section.
    let model = Model::from_toml_str(SOFT_HELIX).expect("model");
    let model3 = Model::from_file("models/paper/case3.toml").expect("case III");
    for m in [&model3, &model] {
        let p = observed(m, MethodKind::Energy, "sub-arcs", [4, 8, 16], 64);
        assert!((p - SUB_ARC_ORDER).abs() < 0.3, "energy order {p}");
        let p = observed(m, MethodKind::Cosserat, "rk4-steps", [2, 4, 8], 128);
        assert!((p - RK4_ORDER).abs() < 0.4, "rk4 order {p}");
    }
}

#[test]
fn the_adaptive_rods_error_follows_its_tolerance() {
    let model = Model::from_file("models/paper/case1.toml").expect("case I");
    let tip = |s: Settings| {
        SolveRequest::new(MethodKind::Cosserat)
            .with_settings(s)
            .run(&model)
            .expect("solves")
            .shape
            .tip()
    };
    let reference = tip(Settings::new().with("rk4-steps", 200));
    let e = |tol: f64| (tip(Settings::new().with("adaptive", tol)) - reference).norm();
    let (a, b) = (e(1e-4), e(1e-6));
    let p = (a / b).log10() / 2.0;
    println!("adaptive: errors {a:.3e} at 1e-4, {b:.3e} at 1e-6: order {p:.2}");
    assert!(
        (p - ccrkit::method::estimate::ADAPTIVE_ORDER).abs() < 0.25,
        "order {p}"
    );
}
