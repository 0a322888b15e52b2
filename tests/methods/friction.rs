//! Capstan friction along the cables (`hardware.friction`, `energy/friction.rs`) against
//! independent truths: μ = 0 is today's model to the bit; a single planar cable follows the
//! capstan law `T(θ) = T_a e^{−aθ}` and the closed-form curvature `κ(s) = κ₀ / (1 + a κ₀ s)`;
//! the tip Jacobian equals central differences of full solves; methods that cannot model it
//! refuse it by name.

use ccrkit::actuation::{Actuation, Shortening};
use ccrkit::calibrate::data::{DataOptions, Dataset};
use ccrkit::calibrate::predict::{predict, PredictOptions};
use ccrkit::method::energy::Energy;
use ccrkit::method::run::SolveRequest;
use ccrkit::method::{MethodKind, Settings};
use ccrkit::{Method, Model, Scene, SolveError};
use nalgebra::Vector3;

fn root(rel: &str) -> String {
    format!("{}/{rel}", env!("CARGO_MANIFEST_DIR"))
}

/// One straight planar segment: 40 sections of 5 mm, one straight cable at 8 mm (angle 0)
/// tied at the tip, shortened by `d`.
fn planar(d: f64) -> Model {
    Model::from_toml_str(&format!(
        "name = \"capstan\"\n[robot]\nsections = 40\nsection_length = 0.005\ndisk_radius = 0.012\n\
         disk_thickness = 0.002\nbackbone = {{ youngs_modulus = 5e10, poisson_ratio = 0.3, diameter = 0.001 }}\n\
         [[cables]]\nname = \"A\"\nradius = 0.008\nangles = {{ straight = 0.0 }}\nshorten = {d}\n"
    ))
    .expect("model")
}

/// Bending angle of every section from the disk frames.
fn section_angles(shape: &ccrkit::Shape) -> Vec<f64> {
    shape
        .disks
        .windows(2)
        .map(|w| {
            let r = w[0].rotation.transpose() * w[1].rotation;
            ((r.trace() - 1.0) / 2.0).clamp(-1.0, 1.0).acos()
        })
        .collect()
}

/// The capstan law on one planar cable (pulled in, `a = μ = 0.3`): each section's curvature
/// is its mean tension times `r/EI`, and the tension read from it equals `T_a e^{−a θ}` at the
/// section's middle, `θ` the wrap angle measured on the output shape (to 1e-4 relative); the
/// curvature follows the closed form `κ(s) = κ₀ / (1 + a κ₀ s)`, `κ₀ = T_a r / EI` (to 1e-3);
/// the capstan ratio tip/base tension is `e^{−a θ_total}`. Paid out (`a = −0.3`) the tension
/// rises toward the tip. Without friction the curvature is constant.
#[test]
fn a_planar_cable_follows_the_capstan_law() {
    let m = planar(0.006);
    let set = Energy::default().with_sub_arcs(1);
    let ei = m.robot.backbone.ei();
    let r = 0.008;
    let l = 0.005;
    for a in [0.0, 0.3, -0.3] {
        let mut act = m.actuation.clone();
        act.cables[0].capstan = a;
        let s = set
            .solve(&m.robot, &act, &Scene::empty(), None)
            .expect("solves");
        let ta = s.cables[0].tension.expect("tension");
        assert!(ta > 0.1, "taut: {ta}");
        let th = section_angles(&s);
        let total: f64 = th.iter().sum();
        assert!(total > 0.5, "bent: {total} rad");
        let mut wrap = 0.0;
        let mut worst_law: f64 = 0.0;
        let mut worst_closed: f64 = 0.0;
        let k0 = ta * r / ei;
        for (j, &t) in th.iter().enumerate() {
            let kappa = t / l;
            let tension = ei * kappa / r;
            let law = ta * (-a * (wrap + 0.5 * t)).exp();
            worst_law = worst_law.max((tension / law - 1.0).abs());
            let sm = (j as f64 + 0.5) * l;
            let closed = k0 / (1.0 + a * k0 * sm);
            worst_closed = worst_closed.max((kappa / closed - 1.0).abs());
            wrap += t;
        }
        println!("a = {a}: T_a {ta:.4} N, wrap {total:.4} rad, law {worst_law:.2e}, closed form {worst_closed:.2e}");
        assert!(
            worst_law < 1e-4,
            "a = {a}: capstan law off by {worst_law:e}"
        );
        assert!(
            worst_closed < 1e-3,
            "a = {a}: closed form off by {worst_closed:e}"
        );
        // Capstan ratio: the tension at the tie (extrapolated from the last section's mean
        // by half its wrap) over the actuator's.
        let last = th[th.len() - 1];
        let t_end = ei * last / l / r * (-a * 0.5 * last).exp();
        let ratio = t_end / ta;
        assert!(
            (ratio / (-a * total).exp() - 1.0).abs() < 1e-4,
            "a = {a}: ratio {ratio} vs {}",
            (-a * total).exp()
        );
        if a > 0.0 {
            assert!(ratio < 0.9, "pulled in: tension falls toward the tip");
        } else if a < 0.0 {
            assert!(ratio > 1.1, "paid out: tension rises toward the tip");
        }
    }
}

fn v4() -> Model {
    Model::from_file(root("models/hardware/ftdcr_v4.toml")).expect("v4")
}

fn energy_opts(extra: &[(&str, &str)]) -> PredictOptions {
    let mut s = Settings::new();
    s.push("sub-arcs", "1");
    for (k, v) in extra {
        s.push(*k, *v);
    }
    PredictOptions {
        request: SolveRequest::new(MethodKind::Energy).with_settings(s),
        chunk: 16,
        progress: ccrkit::progress::ProgressHandle::none(),
    }
}

fn train_rows(step: usize) -> Dataset {
    let d = Dataset::from_file(
        root("models/hardware/data/v4/tdcr_sysid_20260511-183002_train.csv"),
        &DataOptions::default(),
    )
    .expect("data");
    let idx: Vec<usize> = (0..d.len()).step_by(step).collect();
    d.select(&idx)
}

/// μ = 0 is today's model to the bit: `hardware.friction = 0` predicts the same tips as no
/// friction field (v4, compliant tendons, every 20th train row); a friction coefficient on a single solve (no sequence, `s = 0`) changes
/// nothing; and friction does change a sequence (the test can fail).
#[test]
fn zero_friction_is_the_frictionless_model_to_the_bit() {
    let data = train_rows(20);
    // Compliant tendons as fitted (k ≈ 4.7 kN/m; README).
    let v4 = || {
        let mut m = v4();
        for cable in m.robot.cables.iter_mut() {
            cable.stiffness = Some(4000.0);
        }
        m
    };
    let plain = v4();
    let mut zero = v4();
    zero.hardware.friction = vec![0.0; 9];
    let a = predict(&plain, &data, &energy_opts(&[])).expect("predicts");
    let b = predict(&zero, &data, &energy_opts(&[])).expect("predicts");
    let tips = |p: &[ccrkit::calibrate::predict::RowPrediction]| -> Vec<Vector3<f64>> {
        p.iter().map(|r| *r.tip.as_ref().expect("solved")).collect()
    };
    assert_eq!(tips(&a), tips(&b));
    let mut rough = v4();
    rough.hardware.friction = vec![0.2; 9];
    let c = predict(&rough, &data, &energy_opts(&[])).expect("predicts");
    let moved = tips(&a)
        .iter()
        .zip(tips(&c))
        .map(|(x, y)| (x - y).norm())
        .fold(0.0, f64::max);
    assert!(moved > 1e-4, "friction moves some tip: {moved} m");
    // A single solve has no direction of motion: no friction.
    let u = [4e-3, -2e-3, 0.0, -1e-3, 3e-3, 1e-3, 2e-3, -1e-3, 1.5e-3];
    let act = rough.hardware.actuation(&u);
    assert!(act.cables.iter().all(|d| d.capstan == 0.0));
    let set = Energy::default();
    let s1 = set
        .solve(
            &plain.robot,
            &plain.hardware.actuation(&u),
            &Scene::empty(),
            None,
        )
        .expect("solves");
    let s2 = set
        .solve(&rough.robot, &act, &Scene::empty(), None)
        .expect("solves");
    assert_eq!(s1.tip(), s2.tip());
}

/// With friction the tip Jacobian (non-symmetric linearization) equals central differences of
/// full friction solves in each cable's shortening (v4, compliant cables, pulled and paid-out
/// cables with friction).
#[test]
fn tip_jacobian_with_friction_matches_central_differences() {
    let mut m = v4();
    for cable in m.robot.cables.iter_mut() {
        cable.stiffness = Some(4000.0);
    }
    let u = [4e-3, -2e-3, 0.0, -1e-3, 3e-3, 1e-3, 2e-3, -1e-3, 1.5e-3];
    let dir = [1.0, -1.0, 1.0, -1.0, 1.0, 1.0, 1.0, -1.0, -1.0];
    m.hardware.friction = vec![0.25; 9];
    let act = |v: &[f64]| -> Actuation { m.hardware.actuation_moving(v, &dir) };
    let set = Energy::default().with_sub_arcs(1);
    let solve = |a: &Actuation| {
        set.solve(&m.robot, a, &Scene::empty(), None)
            .expect("solves")
    };
    let base = solve(&act(&u));
    let jac = base
        .report
        .jacobian
        .clone()
        .expect("jacobian with friction");
    let h = 1e-7;
    let (mut worst, mut scale): (f64, f64) = (0.0, 0.0);
    for (col, (name, _)) in jac.inputs.iter().enumerate() {
        let c = m.robot.cable_index(name).expect("cable");
        let (mut up, mut um) = (act(&u), act(&u));
        let d = |x: &mut Actuation, e: f64| {
            if let Some(Shortening::Length(v)) = x.cables[c].shorten {
                x.cables[c].shorten = Some(Shortening::Length(v + e));
            }
        };
        d(&mut up, h);
        d(&mut um, -h);
        let fd = (solve(&up).tip() - solve(&um).tip()) / (2.0 * h);
        let j = Vector3::from(jac.position[col]);
        worst = worst.max((fd - j).norm());
        scale = scale.max(fd.norm());
    }
    println!("relative error {:.2e}", worst / scale);
    assert!(scale > 1.0, "the tip moves with the cables");
    assert!(worst < 1e-4 * scale, "relative error {:.2e}", worst / scale);
}

/// Methods without friction refuse a row with friction by name; the chord measure refuses it;
/// bad coefficients are refused naming the field.
#[test]
fn friction_is_refused_or_validated_by_name() {
    let m = planar(0.004);
    let mut act = m.actuation.clone();
    act.cables[0].capstan = 0.2;
    for kind in [
        MethodKind::Geometric,
        MethodKind::Cosserat,
        MethodKind::ConstantCurvature,
    ] {
        let e = kind
            .build(&Settings::new())
            .expect("builds")
            .solve(&m.robot, &act, &Scene::empty(), None)
            .expect_err("refused");
        assert!(matches!(e, SolveError::Unsupported { .. }), "{kind}: {e}");
        assert!(e.to_string().contains("`A`"), "{kind}: {e}");
        assert!(e.to_string().contains("friction"), "{kind}: {e}");
        // The method that models it is named from the registry (`capstan_friction`).
        assert!(
            e.to_string().contains("use `--method energy`"),
            "{kind}: {e}"
        );
    }
    let chord = Energy::default().with_cable_length(ccrkit::actuation::LengthMeasure::Chord);
    let e = chord
        .solve(&m.robot, &act, &Scene::empty(), None)
        .expect_err("refused");
    assert!(e.to_string().contains("path"), "{e}");
    let text = std::fs::read_to_string(root("models/hardware/ftdcr_v4.toml")).expect("file");
    for bad in ["-0.1", "3.0", "[0.1, 0.2]"] {
        let t = text.replacen(
            "\n[hardware]\n",
            &format!("\n[hardware]\nfriction = {bad}\n"),
            1,
        );
        let e =
            Model::from_toml_in(&t, std::path::Path::new(&root("models/hardware"))).expect_err(bad);
        assert!(e.to_string().contains("hardware.friction"), "{bad}: {e}");
    }
}
