//! What the energy model's converged KKT system reports beyond the shape, against independent
//! truths: the tip Jacobian (implicit function theorem) against central differences of full
//! solves (paper cases, tension-driven, a wall contact), and the stability verdict against
//! Euler's buckling load of a cantilever, `P_cr = π² EI / (4 L²)`.

use crate::common;
use crate::common::paper;
use ccrkit::actuation::{Input, Shortening};
use ccrkit::method::energy::Energy;
use ccrkit::{Actuation, Method, Model, Scene, Shape};
use nalgebra::Vector3;

fn root() -> std::path::PathBuf {
    std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn run(set: &Energy, model: &Model, act: &Actuation, scene: &Scene) -> Shape {
    set.solve(&model.robot, act, scene, None).expect("solves")
}

fn tangent(s: &Shape) -> Vector3<f64> {
    s.disks[s.disks.len() - 1].rotation.column(2).into_owned()
}

/// Central differences of full solves in each driven input against `report.jacobian`:
/// the largest error relative to the largest Jacobian entry (position and tangent).
fn jacobian_error(set: &Energy, model: &Model, act: &Actuation, scene: &Scene, h: f64) -> f64 {
    let base = run(set, model, act, scene);
    let jac = base.report.jacobian.clone().expect("jacobian reported");
    let mut col = 0;
    let mut worst: f64 = 0.0;
    for c in 0..model.robot.cables.len() {
        let Some((name, input)) = jac.inputs.get(col).cloned() else {
            break;
        };
        if name != model.robot.cables[c].name {
            continue;
        }
        let (mut ap, mut am) = (act.clone(), act.clone());
        if input == Input::Shortening.name() {
            let d = act
                .shortening_length(&model.robot, c)
                .expect("driven by shortening");
            ap.cables[c].shorten = Some(Shortening::Length(d + h));
            am.cables[c].shorten = Some(Shortening::Length(d - h));
        } else {
            let t = act.tension(c).expect("driven by tension");
            ap.cables[c].tension = Some(t + h);
            am.cables[c].tension = Some(t - h);
        }
        let (sp, sm) = (run(set, model, &ap, scene), run(set, model, &am, scene));
        let dp = (sp.tip() - sm.tip()) / (2.0 * h);
        let dt = (tangent(&sp) - tangent(&sm)) / (2.0 * h);
        let jp = Vector3::from(jac.position[col]);
        let jt = Vector3::from(jac.tangent[col]);
        let scale = jp.norm().max(jt.norm()).max(1e-12);
        worst = worst
            .max((dp - jp).norm() / scale)
            .max((dt - jt).norm() / scale);
        col += 1;
    }
    assert_eq!(col, jac.inputs.len(), "every column checked");
    worst
}

#[test]
fn tip_jacobian_matches_central_differences_on_the_paper_cases() {
    let set = Energy::default();
    for n in 1..=3 {
        let m = paper(n);
        let e = jacobian_error(&set, &m, &m.actuation, &Scene::empty(), 1e-6);
        // Measured 1.4e-9 … 3.4e-9.
        println!("case {n}: relative error {e:.2e}");
        assert!(e < 1e-5, "case {n}: relative error {e:.2e}");
    }
}

#[test]
fn tip_jacobian_matches_central_differences_when_tension_driven() {
    let set = Energy {
        control: Input::Tension,
        ..Energy::default()
    };
    for n in 1..=3 {
        let m = paper(n);
        let e = jacobian_error(&set, &m, &m.actuation, &Scene::empty(), 1e-4);
        println!("case {n} (tension): relative error {e:.2e}");
        assert!(e < 1e-5, "case {n}: relative error {e:.2e}");
    }
}

#[test]
fn tip_jacobian_near_a_wall_matches_central_differences() {
    let m = paper(1);
    let scene = Scene::from_file(root().join("models/scenes/wall.toml")).expect("wall");
    let s = run(&Energy::default(), &m, &m.actuation, &scene);
    assert!(!s.contacts.is_empty(), "the wall is touched");
    assert!(
        s.report.jacobian.is_none() && s.report.stable.is_none(),
        "off by default"
    );
    let set = Energy {
        contact_sensitivity: true,
        ..Energy::default()
    };
    let e = jacobian_error(&set, &m, &m.actuation, &scene, 1e-6);
    println!("wall: relative error {e:.2e}");
    // Measured 2.2e-7 (h = 1e-6 m); without the contact curvature it was 1.6e-1.
    assert!(e < 1e-5, "wall: relative error {e:.2e}");
}

/// The paper robot with free cables and a compressive dead tip force `f` [N] along −z.
fn column(f: f64) -> Model {
    let path = root().join("models/paper/case1.toml");
    let text = std::fs::read_to_string(path).expect("case 1")
        + &format!("\n[loads]\ntip_force = [0.0, 0.0, {}]\n", -f);
    Model::from_toml_str(&text).expect("loaded model")
}

#[test]
fn a_straight_column_is_stable_below_euler_load_and_unstable_above() {
    let m = column(1.0);
    let l = m.robot.length();
    let p_cr = std::f64::consts::PI.powi(2) * m.robot.backbone.ei() / (4.0 * l * l);
    let set = Energy::default();
    for (factor, expect) in [(0.0, true), (0.9, true), (1.1, false), (2.0, false)] {
        let m = column(factor * p_cr);
        let act = Actuation::free(&m.robot);
        let s = run(&set, &m, &act, &Scene::empty());
        let bend = s.tip().x.hypot(s.tip().y);
        assert!(bend < 1e-12, "the column stays straight ({bend:e})");
        assert_eq!(
            s.report.stable,
            Some(expect),
            "{factor} × P_cr = {:.3} N",
            factor * p_cr
        );
    }
}

#[test]
fn the_paper_cases_are_stable() {
    for n in 1..=3 {
        let s = common::solve(&Energy::default(), &paper(n));
        assert_eq!(s.report.stable, Some(true), "case {n}");
    }
}
