//! The backbone's curvature stiffening `β` (`robot.backbone.stiffening`: bending energy
//! `½ EI κ² (1 + β κ²)` per length) in the energy model, against independent truths: the
//! closed-form arc of a tension-driven cable (`EI κ (1 + 2 β κ²) = T r`), the energy itself in
//! closed form, the tip Jacobian against central differences of full solves, a calibration
//! that recovers a known `β` from tips it generated; refused by name where not modelled,
//! validated by field, and `β = 0` the same to the bit as no field.

use ccrkit::calibrate::data::Dataset;
use ccrkit::calibrate::fit::{calibrate, fitted_toml, FitOptions};
use ccrkit::calibrate::predict::{predict, PredictOptions, DEFAULT_CHUNK};
use ccrkit::method::energy::{elastic_energy, Energy};
use ccrkit::method::run::SolveRequest;
use ccrkit::method::{MethodKind, Settings};
use ccrkit::{Method, Model, Scene, Shape, SolveError};
use nalgebra::Vector3;

use crate::common::one_cable::{compliant_v4, OneCable, V4_BEND};

/// The one-cable robot (10 × 10 mm, cable at 8 mm) on a backbone of `E = 5 GPa`, Ø 2 mm, with
/// stiffening `beta` (none written when `None`) and the cable lines `cable`.
fn robot(beta: Option<f64>, cable: &str) -> String {
    let body = OneCable::compliance(5e9).toml(cable);
    match beta {
        Some(b) => body.replace(
            "diameter = 0.002 }",
            &format!("diameter = 0.002, stiffening = {b:?} }}"),
        ),
        None => body,
    }
}

fn solve(m: &Model) -> Shape {
    Energy::default()
        .solve(&m.robot, &m.actuation, &Scene::empty(), None)
        .expect("solves")
}

/// A straight cable at radius `r` pulled with tension `T` and tied at the tip puts the pure
/// moment `T r` on every cross-section, and shortens the backbone by `ε = −T/EA`: the robot is
/// an arc of curvature `κ` (per undeformed length) with `EI κ (1 + 2 β κ²) = T r`, the cubic
/// solved here by Newton's method. Its tip turns by `θ = κ L` and sits at
/// `(1 + ε)/κ (1 − cos θ, 0, sin θ)` (the arc of length `L (1 + ε)`), to 1e-9 of the length.
/// `β = 0` gives `κ = T r / EI`; `β > 0` bends less.
#[test]
fn tension_driven_arc_matches_the_stiffened_closed_form() {
    let (e, d, r, l, t): (f64, f64, f64, f64, f64) = (5e9, 0.002, 0.008, 0.1, 4.0);
    let ei = e * std::f64::consts::PI * d.powi(4) / 64.0;
    let ea = e * std::f64::consts::PI * d * d / 4.0;
    let mut thetas = vec![];
    for beta in [0.0, 2e-3, 1e-2] {
        let m =
            Model::from_toml_str(&robot(Some(beta), &format!("tension = {t:?}\n"))).expect("model");
        let s = solve(&m);
        let mut k = t * r / ei;
        for _ in 0..60 {
            let f = ei * k * (1.0 + 2.0 * beta * k * k) - t * r;
            k -= f / (ei * (1.0 + 6.0 * beta * k * k));
        }
        let th = k * l;
        let eps = -t / ea;
        let tip = s.tip();
        // The cable at angle 0 pulls the tip toward +x; compare |x| (the sign is a convention).
        let want = Vector3::new(
            (1.0 + eps) / k * (1.0 - th.cos()),
            0.0,
            (1.0 + eps) / k * th.sin(),
        );
        let got = Vector3::new(tip.x.abs(), tip.y, tip.z);
        let rot = s.disks.last().expect("tip").rotation;
        let angle = rot[(0, 2)].abs().atan2(rot[(2, 2)]);
        println!("β = {beta}: κ = {k:.9} 1/m, θ = {th:.9} rad (solved {angle:.9}), tip {got:?}");
        assert!((angle - th).abs() < 1e-8, "β {beta}: θ {angle} vs {th}");
        assert!(
            (got - want).norm() < 1e-9 * l,
            "β {beta}: {got:?} vs {want:?}"
        );
        thetas.push(th);
    }
    assert!((thetas[0] - t * r * l / ei).abs() < 1e-12);
    assert!(thetas[0] > thetas[1] && thetas[1] > thetas[2] && thetas[2] > 0.3 * thetas[0]);
}

/// `elastic_energy` at given strains is `Σ_j ½ ℓ (EI κ² (1 + β κ²) + GJ τ² + EA ε²)`, written
/// out here for a 4-sub-arc-per-section robot and arbitrary strains.
#[test]
fn elastic_energy_matches_its_closed_form() {
    let beta = 3e-3;
    let m = Model::from_toml_str(&robot(Some(beta), "shorten = 0.0\n")).expect("model");
    let set = Energy::default();
    let (e, d, nu): (f64, f64, f64) = (5e9, 0.002, 0.3);
    let i = std::f64::consts::PI * d.powi(4) / 64.0;
    let (ei, gj, ea) = (
        e * i,
        e / (2.0 * (1.0 + nu)) * 2.0 * i,
        e * std::f64::consts::PI * d * d / 4.0,
    );
    let nsub = 10 * set.sub_arcs;
    let ell = 0.01 / set.sub_arcs as f64;
    let xi: Vec<f64> = (0..4 * nsub)
        .map(|k| ((k * 37 % 11) as f64 - 5.0) * 0.9)
        .collect();
    let mut want = 0.0;
    for j in 0..nsub {
        let (kx, ky, tau, eps) = (
            xi[4 * j],
            xi[4 * j + 1],
            xi[4 * j + 2],
            1e-3 * xi[4 * j + 3],
        );
        let k2 = kx * kx + ky * ky;
        want += 0.5 * ell * (ei * k2 * (1.0 + beta * k2) + gj * tau * tau + ea * eps * eps);
    }
    let mut x = xi.clone();
    for j in 0..nsub {
        x[4 * j + 3] *= 1e-3;
    }
    let got = elastic_energy(&m.robot, &set, &x).expect("energy");
    assert!((got - want).abs() < 1e-12 * want, "{got} vs {want}");
}

/// `report.jacobian` with `β > 0` equals central differences of full solves in each cable's
/// shortening (FTDCR v4 with compliant, pretensioned cables, a bending command): the
/// stiffening's Hessian block is exact.
#[test]
fn tip_jacobian_with_stiffening_matches_central_differences() {
    let mut m = compliant_v4();
    m.robot.backbone.stiffening = 2e-3;
    let set = Energy::default();
    let run = |v: &[f64]| {
        set.solve(&m.robot, &m.hardware.actuation(v), &Scene::empty(), None)
            .expect("solves")
    };
    let base = run(&V4_BEND);
    let jac = base.report.jacobian.clone().expect("jacobian");
    let h = 1e-7;
    let (mut worst, mut scale) = (0.0f64, 0.0f64);
    for (col, (name, _)) in jac.inputs.iter().enumerate() {
        let c = m.robot.cable_index(name).expect("cable");
        let (mut up, mut um) = (V4_BEND, V4_BEND);
        up[c] += h;
        um[c] -= h;
        let fd = (run(&up).tip() - run(&um).tip()) / (2.0 * h);
        let j = Vector3::from(jac.position[col]);
        worst = worst.max((fd - j).norm());
        scale = scale.max(j.norm());
    }
    println!("relative error {:.2e}", worst / scale);
    assert!(worst < 1e-5 * scale, "relative error {:.2e}", worst / scale);
    // And the stiffening moved the tip (it acts here).
    let mut plain = m.clone();
    plain.robot.backbone.stiffening = 0.0;
    let p = Energy::default()
        .solve(
            &plain.robot,
            &plain.hardware.actuation(&V4_BEND),
            &Scene::empty(),
            None,
        )
        .expect("solves");
    assert!((p.tip() - base.tip()).norm() > 1e-5);
}

/// Tips generated by FTDCR v4 (compliant cables) with `β* = 2·10⁻³ m²` on 120 train commands;
/// fitting `stiffening` alone from `β = 0` recovers `β*` (to 1 %), and the fitted model file
/// carries it (`fitted_toml`) and predicts the same tips when read back.
#[test]
fn calibration_recovers_a_known_stiffening() {
    let beta = 2e-3;
    let mut truth = compliant_v4();
    truth.robot.backbone.stiffening = beta;
    let file = format!(
        "{}/models/hardware/data/v4/tdcr_sysid_20260511-183002_train.csv",
        env!("CARGO_MANIFEST_DIR")
    );
    let all = Dataset::from_file(file, &Default::default()).expect("train");
    let idx: Vec<usize> = (0..all.len()).step_by(13).collect();
    let mut data = all.select(&idx);
    let mut s = Settings::new();
    s.push("sub-arcs", "1");
    let popts = PredictOptions {
        request: SolveRequest::new(MethodKind::Energy).with_settings(s),
        chunk: DEFAULT_CHUNK,
        progress: ccrkit::progress::ProgressHandle::none(),
    };
    let tips: Vec<Vector3<f64>> = predict(&truth, &data, &popts)
        .expect("predict")
        .into_iter()
        .map(|r| r.tip.expect("row solves"))
        .collect();
    data.tips = Some(tips.clone());
    let mut start = truth.clone();
    start.robot.backbone.stiffening = 0.0;
    let mut fo = FitOptions::new(popts.clone());
    fo.params = vec!["stiffening".into()];
    fo.tolerance = 1e-10;
    let rep = calibrate(&start, &data, &fo).expect("fits");
    let got = rep.params[0].value;
    println!(
        "β fitted {got:.6e} (truth {beta:e}), rmse {:.3e} m, {}",
        rep.after.rmse, rep.stop
    );
    assert!((got - beta).abs() < 1e-2 * beta, "β {got} vs {beta}");
    let text = std::fs::read_to_string(format!(
        "{}/models/hardware/ftdcr_v4.toml",
        env!("CARGO_MANIFEST_DIR")
    ))
    .expect("model text");
    let back = Model::from_toml_str(&fitted_toml(&text, &rep.model, "test").expect("toml"))
        .expect("fitted file reads");
    assert_eq!(back.robot.backbone.stiffening, got);
}

/// Methods that do not model the stiffening refuse the robot naming it; bad values are
/// refused naming the field; `stiffening = 0.0` is the linear backbone to the bit.
#[test]
fn stiffening_is_refused_validated_and_zero_is_the_linear_backbone() {
    let m = Model::from_toml_str(&robot(Some(1e-3), "shorten = 0.002\n")).expect("model");
    for kind in [
        MethodKind::Geometric,
        MethodKind::GeometricSquared,
        MethodKind::ConstantCurvature,
        MethodKind::Cosserat,
        MethodKind::Kirchhoff,
    ] {
        match SolveRequest::new(kind).run(&m) {
            Err(SolveError::Unsupported { reason, .. }) => {
                assert!(reason.contains("stiffening"), "{kind:?}: {reason}")
            }
            other => panic!("{kind:?}: {:?}", other.map(|_| ())),
        }
    }
    assert!(SolveRequest::new(MethodKind::Energy).run(&m).is_ok());
    for bad in ["-1e-3", "2.0", "nan"] {
        let text = robot(None, "shorten = 0.0\n").replace(
            "diameter = 0.002 }",
            &format!("diameter = 0.002, stiffening = {bad} }}"),
        );
        let err = Model::from_toml_str(&text).expect_err(bad).to_string();
        assert!(err.contains("robot.backbone.stiffening"), "{bad}: {err}");
    }
    let zero = Model::from_toml_str(&robot(Some(0.0), "shorten = 0.002\n")).expect("model");
    let none = Model::from_toml_str(&robot(None, "shorten = 0.002\n")).expect("model");
    let (a, b) = (solve(&zero), solve(&none));
    assert_eq!(a.tip(), b.tip());
    assert_eq!(a.report.jacobian, b.report.jacobian);
}
