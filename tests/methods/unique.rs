//! `solve --check unique` (`ccrkit::method::unique`): whether an answer is the only equilibrium
//! found along other paths, and what the other model's answer 20 mm away means.

use crate::common::{ccrkit_json, cli, paper};
use ccrkit::prelude::*;
use ccrkit::study::compare::{compare, DISAGREE_TOL};
use ccrkit::Model;
use ccrkit_test_support::{port_robots::port_robot, rng::Rng};

/// Random robot 22 of the support crate's generator (port removed), every cable shortened by
/// a seeded 0–6 %: `energy` and the displacement-driven rod shooting at 3 RK4 steps per
/// section land 19.3 mm apart, both converged.
fn two_answers_robot() -> String {
    let seed = 22;
    let toml = port_robot(seed).toml;
    let body = toml
        .split("[port]")
        .next()
        .expect("the robot before its port");
    let mut r = Rng(seed * 7 + 3);
    let mut t = String::new();
    for line in body.lines() {
        t += line;
        t += "\n";
        if line.starts_with("ends_at") {
            t += &format!("shorten_percent = {}\n", r.range(0.0, 6.0));
        }
    }
    t
}

fn displacement(kind: MethodKind) -> SolveRequest {
    SolveRequest::new(kind).with_settings(Settings::new().with("control", "displacement"))
}

/// The rod always shooting (`solver = shooting`), under displacement control, `steps` RK4
/// steps per section.
fn shooting_rod(steps: usize) -> SolveRequest {
    SolveRequest::new(MethodKind::Cosserat).with_settings(
        Settings::new()
            .with("control", "displacement")
            .with("solver", "shooting")
            .with("rk4-steps", steps),
    )
}

/// What was two answers 19 mm apart (`energy` and the rod shooting at its default steps) is
/// one: `compare` still flags the pair with the rod shooting at 3 steps, but the unique check
/// of `energy`, whose other model is the rod at its default (the unloaded path), finds it in
/// agreement, and the shooting rod four times finer lands there too, so the 19 mm were the
/// shooting rod's resolution at 3 steps, not a second equilibrium.
#[test]
fn two_converged_answers_19_mm_apart_are_the_shooting_rods_resolution() {
    let model = Model::from_toml_str(&two_answers_robot()).expect("valid by construction");
    let plain = displacement(MethodKind::Energy)
        .run(&model)
        .expect("solves");
    assert!(plain.shape.report.converged && plain.shape.report.unique.is_none());
    let cmp = compare(
        &model,
        &[displacement(MethodKind::Energy), shooting_rod(3)],
        DISAGREE_TOL,
    )
    .expect("compares");
    assert!(cmp.to_json().any_disagreement && cmp.to_json().pairs[0].disagree);
    let coarse = shooting_rod(3).run(&model).expect("solves");
    let d = coarse.shape.tip_distance(&plain.shape);
    assert!((0.015..0.025).contains(&d), "the shooting rod {d} m away");
    let checked = displacement(MethodKind::Energy)
        .with_unique_check(true)
        .run(&model)
        .expect("solves");
    let u = checked.shape.report.unique.clone().expect("checked");
    let other = u.other_model.as_ref().expect("the rod answers too");
    let d = other.tip_distance_m.expect("the rod solved");
    assert!(d < 5e-4, "the rod at its default {d} m away");
    assert_eq!(other.verdict, "agrees");
    assert!(u.only && u.converged_tries >= 5, "{u:?}");
    assert!(u.solves >= 10 && u.time_s > 0.0);
    let fine = shooting_rod(12).run(&model).expect("solves");
    let gap = fine.shape.tip_distance(&checked.shape);
    assert!(gap < 5e-4, "rod at 12 RK4 steps {gap} m from energy");
}

/// A straight column pushed down at its tip by 3.3× its buckling load, one cable pulling a
/// little more than the opposite one: it buckles towards the stronger cable, and the mirror
/// image is an equilibrium too.
const BUCKLED: &str = r#"
name = "buckled column"
[robot]
sections = 10
section_length = 0.01
disk_radius = 0.008
disk_thickness = 0.001
backbone = { youngs_modulus = 5e10, poisson_ratio = 0.3, diameter = 0.001 }
[[cables]]
name = "a"
radius = 0.005
angles = { straight = 0.0 }
tension = 0.2
[[cables]]
name = "b"
radius = 0.005
angles = { straight = 3.141592653589793 }
tension = 0.1
[loads]
tip_force = [0.0, 0.0, -2.0]
"#;

#[test]
fn a_buckled_column_has_two_equilibria_and_the_check_finds_the_mirror_one() {
    let model = Model::from_toml_str(BUCKLED).expect("valid");
    let s = SolveRequest::new(MethodKind::Energy)
        .with_unique_check(true)
        .run(&model)
        .expect("solves")
        .shape;
    let tip = s.tip();
    assert!(tip.x > 0.05, "buckled towards cable a: {tip:?}");
    let u = s.report.unique.expect("checked");
    assert!(!u.only && u.equilibria == 2, "{u:?}");
    let other = u.tries.iter().find(|t| t.distinct).expect("a distinct try");
    let m = other.tip_m.expect("it converged");
    // The mirror image of the answer across the cables' plane, to within what the 0.1 N
    // difference of the cables moves it (a 5e-4 N m moment against the load's 0.14 N m).
    assert!(
        (m[0] + tip.x).abs() < 2e-3 && (m[2] - tip.z).abs() < 2e-3 && m[1].abs() < 1e-6,
        "{m:?} against {tip:?}"
    );
}

#[test]
fn a_paper_case_is_the_only_equilibrium_and_the_rod_agrees() {
    let s = SolveRequest::new(MethodKind::Energy)
        .with_unique_check(true)
        .run(&paper(2))
        .expect("solves")
        .shape;
    let u = s.report.unique.expect("checked");
    assert!(u.only && u.equilibria == 1, "{u:?}");
    assert_eq!(u.converged_tries, u.tries.len(), "{u:?}");
    let o = u.other_model.expect("the rod");
    assert!(o.tip_distance_m.expect("solved") < 1e-4 && o.verdict == "agrees");
}

#[test]
fn the_command_line_prints_and_writes_the_check() {
    let j = ccrkit_json(&[
        "solve",
        &cli::paper_path(1),
        "--check",
        "unique",
        "--json",
        "-",
    ]);
    assert_eq!(j["report"]["unique"]["only"], true, "{j}");
    let c = ccrkit_json(&[
        "compare",
        &cli::paper_path(1),
        "--methods",
        "energy,cosserat:control=displacement",
        "--json",
        "-",
    ]);
    assert_eq!(c["any_disagreement"], false, "{c}");
    assert_eq!(c["pairs"][0]["disagree"], false, "{c}");
}
