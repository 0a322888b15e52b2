//! The geometric section solver against independent truths: closed-form geometry (circle),
//! invariants (constraint residuals, rotation equivariance) and recorded regressions.

use ccrkit::method::geometric::Geometric;
use ccrkit::{Method, Model, Scene, Shape, SolveError};
use nalgebra::{Rotation3, Vector3};

/// Constraint residual a solved shape must meet [m].
const CONSTRAINT_TOL: f64 = 1e-9;

fn robot_toml(cables: &str) -> String {
    format!(
        r#"
name = "test"
[robot]
sections = 9
section_length = 0.020
disk_radius = 0.012
disk_thickness = 0.002
backbone = {{ youngs_modulus = 1.1e9, poisson_ratio = 0.3, diameter = 0.003 }}
{cables}
"#
    )
}

fn solve(model: &Model) -> Shape {
    Geometric::literal()
        .solve(&model.robot, &model.actuation, &Scene::empty(), None)
        .expect("solve")
}

/// Every constraint of eq. 2 recomputed from the output shape: segment lengths l0, hole radii
/// (rigid disks), taut cable segments at (1 − Δ) × undeformed chord, slack ones no longer.
fn assert_constraints(model: &Model, shape: &Shape) {
    let robot = &model.robot;
    for i in 1..=robot.sections() {
        let seg = (shape.disks[i].position - shape.disks[i - 1].position).norm();
        assert!(
            (seg - robot.section_length(i)).abs() < CONSTRAINT_TOL,
            "l0 in section {i}"
        );
    }
    for (c, cable) in robot.cables.iter().enumerate() {
        let path = &shape.cables[c];
        for k in 0..=cable.ends_at {
            let r = (path.points[k] - shape.disks[k].position).norm();
            assert!(
                (r - cable.radius[k]).abs() < CONSTRAINT_TOL,
                "hole radius {c} {k}"
            );
        }
        let Some(f) = model.actuation.shortening_fraction(robot, c) else {
            continue;
        };
        for i in 1..=cable.ends_at {
            let chord = (path.points[i] - path.points[i - 1]).norm();
            let target = (1.0 - f) * robot.undeformed_chord(c, i);
            if path.slack_sections.contains(&i) {
                assert!(
                    chord <= target + CONSTRAINT_TOL,
                    "slack cable {c} too long in {i}"
                );
            } else {
                assert!(
                    (chord - target).abs() < CONSTRAINT_TOL,
                    "cable {c} section {i}: {chord} vs {target}"
                );
            }
        }
    }
}

#[test]
fn one_straight_cable_bends_every_section_alike_on_a_planar_circle() {
    let m = Model::from_toml_str(&robot_toml(
        r#"[[cables]]
name = "A"
radius = 0.008
angles = { straight = 0.0 }
shorten_percent = 3.0"#,
    ))
    .unwrap();
    let s = solve(&m);
    assert_constraints(&m, &s);
    // Same relative pose in every section.
    let rel = |i: usize| {
        let (a, b) = (&s.disks[i - 1], &s.disks[i]);
        (
            a.rotation.transpose() * (b.position - a.position),
            a.rotation.transpose() * b.rotation,
        )
    };
    let (p1, q1) = rel(1);
    for i in 2..=9 {
        let (p, q) = rel(i);
        assert!(
            (p - p1).norm() < 1e-10 && (q - q1).norm() < 1e-10,
            "section {i} differs"
        );
    }
    // In the x–z plane (the plane of the cable), bending towards the cable.
    for d in &s.disks {
        assert!(d.position.y.abs() < 1e-10);
    }
    assert!(s.tip().x > 0.0);
    // On a circle: all disks equidistant from the centre through three of them.
    let (a, b, c) = (
        s.disks[0].position,
        s.disks[4].position,
        s.disks[9].position,
    );
    let (ab, ac) = (b - a, c - a);
    let n = ab.cross(&ac);
    let center = a
        + (n.cross(&ab) * ac.norm_squared() + ac.cross(&n) * ab.norm_squared())
            / (2.0 * n.norm_squared());
    let radius = (a - center).norm();
    for d in &s.disks {
        assert!(((d.position - center).norm() - radius).abs() < 1e-10);
    }
}

#[test]
fn rotating_the_routing_rotates_the_shape() {
    let base = Model::from_file("models/paper/case2.toml").unwrap();
    let alpha = 0.7;
    let mut rotated = base.clone();
    for c in &mut rotated.robot.cables {
        for a in &mut c.angle {
            *a += alpha;
        }
    }
    let (s0, s1) = (solve(&base), solve(&rotated));
    let rz = Rotation3::from_axis_angle(&Vector3::z_axis(), alpha);
    for (a, b) in s0.disks.iter().zip(&s1.disks) {
        assert!((rz * a.position - b.position).norm() < 1e-9);
    }
}

#[test]
fn paper_cases_meet_their_constraints_and_recorded_tips() {
    // Regression values recorded from this solver (mm); they guard against silent changes.
    let expected = [
        ("models/paper/case1.toml", [59.904, 86.278, 123.159]),
        ("models/paper/case2.toml", [-14.789, 50.031, 167.864]),
        ("models/paper/case3.toml", [-30.567, 45.913, 165.103]),
    ];
    for (file, tip) in expected {
        let m = Model::from_file(file).unwrap();
        let s = solve(&m);
        assert_constraints(&m, &s);
        assert!(s.report.converged && s.report.residual < CONSTRAINT_TOL);
        let t = s.tip() * 1000.0;
        for k in 0..3 {
            assert!((t[k] - tip[k]).abs() < 1e-3, "{file}: tip {t:?} vs {tip:?}");
        }
    }
}

#[test]
fn case_three_shares_holes_and_reports_the_slack_cable() {
    let m = Model::from_file("models/paper/case3.toml").unwrap();
    let s = solve(&m);
    let b = &s.cables[1];
    assert!(b.slack && b.slack_sections.contains(&8) && b.slack_sections.contains(&9));
    // At disks 7–9 the two cables pass the same hole.
    for k in 7..=9 {
        assert!((s.cables[0].points[k] - b.points[k]).norm() < 1e-12);
    }
}

#[test]
fn zero_terms_are_reported_and_every_section_certified() {
    let m = Model::from_file("models/paper/case1.toml").unwrap();
    let s = solve(&m);
    assert_eq!(s.report.sections.len(), 9);
    for sec in &s.report.sections {
        assert!(
            !sec.zero_terms.is_empty(),
            "the literal optimum sits on a kink"
        );
        assert!(sec.candidates >= 1);
    }
}

#[test]
fn three_four_and_six_cables_and_an_inner_end() {
    for (count, shortened) in [(3usize, vec![0usize]), (4, vec![0, 1]), (6, vec![0, 1, 5])] {
        let mut cables = String::new();
        for k in 0..count {
            let ang = k as f64 * std::f64::consts::TAU / count as f64;
            let ends = if k == 1 { "ends_at = 5\n" } else { "" };
            let sh = if shortened.contains(&k) {
                "shorten_percent = 2.0\n"
            } else {
                ""
            };
            cables += &format!(
                "[[cables]]\nname = \"c{k}\"\nradius = 0.008\nangles = {{ helix = {{ start = {ang}, per_disk = 0.1 }} }}\n{ends}{sh}\n"
            );
        }
        let m = Model::from_toml_str(&robot_toml(&cables)).unwrap();
        let s = solve(&m);
        assert_constraints(&m, &s);
        assert_eq!(
            s.cables[1].points.len(),
            6,
            "cable ending at disk 5 passes disks 0..=5"
        );
    }
}

#[test]
fn a_paid_out_cable_is_slack_and_leaves_the_robot_straight() {
    let m = Model::from_toml_str(&robot_toml(
        r#"[[cables]]
name = "A"
radius = 0.008
angles = { straight = 0.0 }
shorten_percent = -1.0"#,
    ))
    .unwrap();
    let s = solve(&m);
    assert!(s.cables[0].slack);
    assert!((s.tip() - Vector3::new(0.0, 0.0, 0.18)).norm() < 1e-12);
}

#[test]
fn antagonistic_cables_both_shortened_are_infeasible_for_an_incompressible_backbone() {
    // Opposite holes ±d: |p + d|² + |p − d|² = 2 l0² + 2 |d|², so both chords cannot be shorter
    // than l0 while the backbone segment keeps l0. A named error, not a wrong shape.
    let m = Model::from_toml_str(&robot_toml(
        r#"[[cables]]
name = "A"
radius = 0.008
angles = { straight = 0.0 }
shorten_percent = 3.0
[[cables]]
name = "B"
radius = 0.008
angles = { straight = 3.141592653589793 }
shorten_percent = 0.5"#,
    ))
    .unwrap();
    match Geometric::literal().solve(&m.robot, &m.actuation, &Scene::empty(), None) {
        Err(SolveError::Infeasible { cable, section, .. }) => {
            assert!(cable == "A" || cable == "B", "names one of the antagonists");
            assert_eq!(section, 1);
        }
        other => panic!("expected Infeasible, got {other:?}"),
    }
}

#[test]
fn an_antagonist_paid_out_far_enough_goes_slack() {
    let m = Model::from_toml_str(&robot_toml(
        r#"[[cables]]
name = "A"
radius = 0.008
angles = { straight = 0.0 }
shorten_percent = 3.0
[[cables]]
name = "B"
radius = 0.008
angles = { straight = 3.141592653589793 }
shorten_percent = -5.0"#,
    ))
    .unwrap();
    let s = solve(&m);
    assert_constraints(&m, &s);
    assert!(s.cables[1].slack && !s.cables[0].slack);
    assert_eq!(s.cables[1].slack_sections, (1..=9).collect::<Vec<_>>());
}

#[test]
fn unreachable_shortening_is_a_named_error() {
    let m = Model::from_toml_str(&robot_toml(
        r#"[[cables]]
name = "A"
radius = 0.008
angles = { straight = 0.0 }
shorten_percent = 95.0"#,
    ))
    .unwrap();
    match Geometric::literal().solve(&m.robot, &m.actuation, &Scene::empty(), None) {
        Err(SolveError::Infeasible { cable, section, .. }) => {
            assert_eq!(cable, "A");
            assert_eq!(section, 1);
        }
        other => panic!("expected Infeasible, got {other:?}"),
    }
}

#[test]
fn squared_variant_meets_the_same_constraints() {
    let m = Model::from_file("models/paper/case2.toml").unwrap();
    let s = Geometric::squared()
        .solve(&m.robot, &m.actuation, &Scene::empty(), None)
        .unwrap();
    assert_constraints(&m, &s);
    assert_eq!(s.method, "geometric-squared");
}

#[test]
fn json_has_the_promised_fields() {
    let m = Model::from_file("models/paper/case1.toml").unwrap();
    let v: serde_json::Value = serde_json::from_str(&solve(&m).to_json_string()).unwrap();
    assert_eq!(v["method"], "geometric");
    assert_eq!(v["disks"].as_array().unwrap().len(), 10);
    assert_eq!(v["disks"][3]["rotation"].as_array().unwrap().len(), 3);
    assert_eq!(v["disks"][3]["position"].as_array().unwrap().len(), 3);
    assert!(v["disks"][3]["s"].is_number());
    assert_eq!(v["cables"][0]["name"], "A");
    assert_eq!(v["cables"][0]["points"].as_array().unwrap().len(), 10);
    assert!(v["cables"][0]["slack"].is_boolean());
    for key in ["converged", "iterations", "residual", "solve_time_s"] {
        assert!(!v["report"][key].is_null(), "report.{key}");
    }
}
