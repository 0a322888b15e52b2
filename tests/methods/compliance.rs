//! Compliant cables (`stiffness`, `pretension` of a cable) in the energy model, against
//! independent truths: the series-spring relation (a compliant solve equals an inextensible
//! solve at the effective shortening `δ − T/k`), the closed-form tension of three symmetric
//! pretensioned cables on an axially soft backbone, and the tip Jacobian against central
//! differences of full solves; methods that cannot model compliance refuse it by name.

use ccrkit::actuation::{Actuation, Input};
use ccrkit::method::energy::Energy;
use ccrkit::method::run::SolveRequest;
use ccrkit::method::MethodKind;
use ccrkit::{Method, Model, Scene, Shape, SolveError};
use nalgebra::Vector3;

use crate::common::one_cable::V4_BEND;
use crate::common::one_cable::{
    assert_series_springs, compliant_v4, one_cable, tension, three_pretensioned,
};

fn solve(m: &Model, act: &Actuation) -> Shape {
    Energy::default()
        .solve(&m.robot, act, &Scene::empty(), None)
        .expect("solves")
}

/// Series springs: a cable of stiffness k shortened by δ (with pretension T₀) ends with
/// tension T; the inextensible cable shortened by δ + T₀/k − T/k gives the same shape and
/// tension (to 1e-9 m / 1e-6 relative). A rigid-ish backbone (E = 200 GPa) and a soft one.
#[test]
fn compliant_cable_equals_rigid_cable_at_the_effective_shortening() {
    assert_series_springs("energy", solve);
}

/// Three straight cables at 120° with pretension T₀ and no command: the robot stays straight,
/// the backbone shortens by ε = −3T/EA and each cable holds T = T₀ / (1 + 3 k L / EA)
/// (compatibility `L (1 + ε) − (L − T₀/k) = T/k`).
#[test]
fn symmetric_pretension_matches_the_closed_form() {
    let (k, t0, e) = (4000.0, 2.0, 2.5e8);
    let file = three_pretensioned(e, k, t0);
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
    let m = compliant_v4();
    let u = V4_BEND;
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

/// Methods without compliance refuse the file by name (the rods model it:
/// `tests/methods/cosserat_compliance.rs`); bad values are refused naming the field.
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
