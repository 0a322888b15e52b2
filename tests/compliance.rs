//! Compliant cables (`stiffness`, `pretension` of a cable) in the energy model, against
//! independent truths: the series-spring relation (a compliant solve equals an inextensible
//! solve at the effective shortening `δ − T/k`), the closed-form tension of three symmetric
//! pretensioned cables on an axially soft backbone, and the tip Jacobian against central
//! differences of full solves; methods that cannot model compliance refuse it by name.

use ccrkit::actuation::{Actuation, Input, Shortening};
use ccrkit::method::energy::Energy;
use ccrkit::method::run::SolveRequest;
use ccrkit::method::MethodKind;
use ccrkit::{Method, Model, Scene, Shape, SolveError};
use nalgebra::Vector3;

/// A straight robot, 10 sections of 10 mm, one straight cable at offset 8 mm tied at the tip;
/// `extra` adds fields to the cable.
fn one_cable(e: f64, extra: &str) -> String {
    format!(
        "name = \"one\"\n[robot]\nsections = 10\nsection_length = 0.01\ndisk_radius = 0.012\n\
         disk_thickness = 0.002\nbackbone = {{ youngs_modulus = {e:e}, poisson_ratio = 0.3, diameter = 0.002 }}\n\
         [[cables]]\nname = \"A\"\nradius = 0.008\nangles = {{ straight = 0.0 }}\nshorten = 0.002\n{extra}\n"
    )
}

fn solve(m: &Model, act: &Actuation) -> Shape {
    Energy::default()
        .solve(&m.robot, act, &Scene::empty(), None)
        .expect("solves")
}

fn tension(s: &Shape, c: usize) -> f64 {
    s.cables[c].tension.expect("tension reported")
}

/// Series springs: a cable of stiffness k shortened by δ (with pretension T₀) ends with
/// tension T; the inextensible cable shortened by δ + T₀/k − T/k gives the same shape and
/// tension (to 1e-9 m / 1e-6 relative). A rigid-ish backbone (E = 200 GPa) and a soft one.
#[test]
fn compliant_cable_equals_rigid_cable_at_the_effective_shortening() {
    for (e, k, t0) in [(2e11, 2000.0, 0.0), (2e11, 500.0, 1.5), (5e9, 3000.0, 0.4)] {
        let extra = if t0 > 0.0 {
            format!("stiffness = {k}\npretension = {t0}")
        } else {
            format!("stiffness = {k}")
        };
        let soft = Model::from_toml_str(&one_cable(e, &extra)).expect("compliant model");
        let s = solve(&soft, &soft.actuation);
        let t = tension(&s, 0);
        assert!(t > 0.1, "the cable pulls: {t}");
        let rigid = Model::from_toml_str(&one_cable(e, "")).expect("rigid model");
        let mut act = rigid.actuation.clone();
        act.cables[0].shorten = Some(Shortening::Length(0.002 + t0 / k - t / k));
        let r = solve(&rigid, &act);
        let d = (s.tip() - r.tip()).norm();
        println!("E {e:e} k {k} T0 {t0}: T = {t:.6} N, tips differ by {d:.2e} m");
        assert!(d < 1e-9, "tips differ by {d:e} m");
        assert!(
            (tension(&r, 0) - t).abs() < 1e-6 * t,
            "{} vs {t}",
            tension(&r, 0)
        );
        if t0 == 0.0 {
            // Without pretension the compliant cable bends the robot less than the rigid one.
            let full = solve(&rigid, &rigid.actuation);
            assert!(full.tip().x.abs() > s.tip().x.abs() + 1e-4);
        }
    }
}

/// Three straight cables at 120° with pretension T₀ and no command: the robot stays straight,
/// the backbone shortens by ε = −3T/EA and each cable holds T = T₀ / (1 + 3 k L / EA)
/// (compatibility `L (1 + ε) − (L − T₀/k) = T/k`).
#[test]
fn symmetric_pretension_matches_the_closed_form() {
    let (k, t0, e) = (4000.0, 2.0, 2.5e8);
    let mut text = one_cable(e, "").replace("shorten = 0.002\n", "");
    text = text.replace("[[cables]]\nname = \"A\"", "[[cables]]\nname = \"C0\"");
    text = text.replace("angles = { straight = 0.0 }\n", "");
    let head = text.split("[[cables]]").next().expect("head").to_string();
    let mut file = head;
    for (i, a) in [0.0, 2.0943951023931953, 4.1887902047863905]
        .iter()
        .enumerate()
    {
        file.push_str(&format!(
            "[[cables]]\nname = \"C{i}\"\nradius = 0.008\nangles = {{ straight = {a} }}\n\
             shorten = 0.0\nstiffness = {k}\npretension = {t0}\n"
        ));
    }
    let m = Model::from_toml_str(&file).expect("model");
    let s = solve(&m, &m.actuation);
    let ea = e * std::f64::consts::PI * 0.001 * 0.001;
    let l = 0.1;
    let want = t0 / (1.0 + 3.0 * k * l / ea);
    for c in 0..3 {
        let t = tension(&s, c);
        assert!((t - want).abs() < 1e-9 * t0, "cable {c}: {t} vs {want}");
    }
    let tip = s.tip();
    let z = l * (1.0 - 3.0 * want / ea);
    assert!(
        (tip - Vector3::new(0.0, 0.0, z)).norm() < 1e-12,
        "{tip:?} vs z {z}"
    );
    println!("T = {want:.9} N (T0 = {t0} N), tip z = {z:.9} m");
}

/// `report.jacobian` with compliant cables equals central differences of full solves in each
/// cable's shortening (FTDCR v4, every cable compliant and pretensioned, a bending command).
#[test]
fn tip_jacobian_with_compliant_cables_matches_central_differences() {
    let path = format!(
        "{}/models/hardware/ftdcr_v4.toml",
        env!("CARGO_MANIFEST_DIR")
    );
    let mut m = Model::from_file(path).expect("v4");
    for (c, cable) in m.robot.cables.iter_mut().enumerate() {
        cable.stiffness = Some(3000.0 + 200.0 * c as f64);
        cable.pretension = 0.3;
    }
    let u = [4e-3, -2e-3, 0.0, -1e-3, 3e-3, 1e-3, 2e-3, -1e-3, 1.5e-3];
    let act = m.hardware.actuation(&u);
    let set = Energy::default();
    let base = solve(&m, &act);
    let jac = base.report.jacobian.clone().expect("jacobian");
    let slack = (0..9).filter(|&c| tension(&base, c) == 0.0).count();
    assert!(
        slack > 0 && slack < 9,
        "some cables slack, some taut: {slack}"
    );
    let h = 1e-7;
    let mut worst: f64 = 0.0;
    for (col, (name, input)) in jac.inputs.iter().enumerate() {
        assert_eq!(input, Input::Shortening.name());
        let c = m.robot.cable_index(name).expect("cable");
        let (mut up, mut um) = (u, u);
        up[c] += h;
        um[c] -= h;
        let run = |v: &[f64]| {
            set.solve(&m.robot, &m.hardware.actuation(v), &Scene::empty(), None)
                .expect("solves")
                .tip()
        };
        let fd = (run(&up) - run(&um)) / (2.0 * h);
        let j = Vector3::from(jac.position[col]);
        worst = worst.max((fd - j).norm());
    }
    let scale = jac
        .position
        .iter()
        .map(|p| Vector3::from(*p).norm())
        .fold(0.0, f64::max);
    println!("relative error {:.2e}", worst / scale);
    assert!(worst < 1e-5 * scale, "relative error {:.2e}", worst / scale);
}

/// Methods without compliance refuse the file by name (the rods model it since issue 15:
/// `tests/cosserat_compliance.rs`); bad values are refused naming the field.
#[test]
fn compliance_is_refused_or_validated_by_name() {
    let m = Model::from_toml_str(&one_cable(2e11, "stiffness = 2000.0")).expect("model");
    for kind in [
        MethodKind::Geometric,
        MethodKind::GeometricSquared,
        MethodKind::ConstantCurvature,
    ] {
        match SolveRequest::new(kind).run(&m) {
            Err(SolveError::Unsupported { reason, .. }) => {
                assert!(reason.contains("stiffness"), "{kind:?}: {reason}")
            }
            other => panic!("{kind:?}: {:?}", other.map(|_| ())),
        }
    }
    for (extra, field) in [
        ("stiffness = -1.0", "cables[0].stiffness"),
        ("stiffness = 0.0", "cables[0].stiffness"),
        ("pretension = 1.0", "cables[0].pretension"),
        (
            "stiffness = 10.0\npretension = -1.0",
            "cables[0].pretension",
        ),
        ("stiffness = 1.0\npretension = 1.0", "cables[0].pretension"),
    ] {
        let e = Model::from_toml_str(&one_cable(2e11, extra)).expect_err(extra);
        assert_eq!(e.field(), Some(field), "{extra}: {e}");
    }
}
