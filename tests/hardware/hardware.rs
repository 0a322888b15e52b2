//! The FTDCR hardware models (`models/hardware/`) and the hardware features, against the
//! measured data in `models/hardware/data/` and closed forms.

use ccrkit::actuation::Shortening;
use ccrkit::method::energy::Energy;
use ccrkit::{Method, Model, Scene};
use std::f64::consts::PI;

fn root(rel: &str) -> String {
    format!("{}/{rel}", env!("CARGO_MANIFEST_DIR"))
}

fn model(v: &str) -> Model {
    Model::from_file(root(&format!("models/hardware/ftdcr_{v}.toml"))).expect("model loads")
}

/// Rows `(label, servo mm ×9, tip mm)` of a data CSV (plain parsing, independent of ccrkit).
fn rows(rel: &str) -> Vec<(String, Vec<f64>, [f64; 3])> {
    let text = std::fs::read_to_string(root(rel)).expect("data file");
    text.lines()
        .skip(1)
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            let x: Vec<f64> = f[2..].iter().map(|s| s.parse().expect("number")).collect();
            (f[1].to_string(), x[..9].to_vec(), [x[9], x[10], x[11]])
        })
        .collect()
}

fn wrap(a: f64) -> f64 {
    (a + PI).rem_euclid(2.0 * PI) - PI
}

/// Both models load, and a single-tendon pull from the data solves with the energy model:
/// the tendon's own segment bends in the tendon's plane, so the tip's azimuth equals the
/// tendon's angle (an exact property of the pull-only, straight-tendon model), and it agrees
/// with the measured tip motion of that row within 15°.
#[test]
fn hardware_models_load_and_solve_a_tendon_pull() {
    for (v, file) in [
        (
            "v4",
            "models/hardware/data/v4/tdcr_sysid_20260511-183002_train.csv",
        ),
        (
            "v6",
            "models/hardware/data/v6/tdcrv6_sysid_20260406-181730_train.csv",
        ),
    ] {
        let m = model(v);
        assert_eq!(m.robot.cables.len(), 9, "{v}");
        let data = rows(file);
        let neutral = data[0].2;
        for c in [0usize, 4] {
            // The row of this tendon's pull pattern where it is pulled most.
            let (_, u, tip) = data
                .iter()
                .filter(|r| r.0.contains(&format!("tendon{c}_")) && r.0.ends_with("_pull"))
                .max_by(|a, b| a.1[c].total_cmp(&b.1[c]))
                .expect("pull rows");
            assert!(u[c] > 2.0, "{v} cable {c} pulled {} mm", u[c]);
            let mut act = m.actuation.clone();
            for (k, d) in act.cables.iter_mut().enumerate() {
                d.shorten = Some(Shortening::Length(u[k] * 1e-3));
            }
            let shape = Energy::default()
                .solve(&m.robot, &act, &Scene::empty(), None)
                .expect("solves");
            assert!(shape.report.converged, "{v}");
            let p = shape.tip();
            let beta = m.robot.cables[c].angle[0];
            let az = p.y.atan2(p.x);
            assert!(p.x.hypot(p.y) > 5e-3, "{v} cable {c}: tip moved {p:?}");
            assert!(
                wrap(az - beta).abs() < 1e-6,
                "{v} cable {c}: azimuth {az} vs {beta}"
            );
            let meas = (tip[1] - neutral[1]).atan2(tip[0] - neutral[0]);
            assert!(
                wrap(meas - beta).abs() < 15f64.to_radians(),
                "{v} cable {c}: measured azimuth {} deg vs tendon {} deg",
                meas.to_degrees(),
                beta.to_degrees()
            );
            // Only the pulled cable carries tension.
            for (k, cp) in shape.cables.iter().enumerate() {
                let t = cp.tension.unwrap_or(0.0);
                assert_eq!(t > 1e-9, k == c, "{v} cable {k} tension {t}");
            }
        }
    }
}

use crate::common::one_cable;

/// A straight robot of 4 sections of 20 mm (disks of 10 mm, E = 5 GPa), one straight cable
/// `A` at 6 mm; its cable table is open for the drive and the tables after it.
fn small_one_cable() -> String {
    one_cable::OneCable {
        sections: 4,
        section_length: 0.02,
        disk_radius: 0.01,
        youngs_modulus: 5e9,
        cable_radius: 0.006,
    }
    .toml("")
}

/// Gain and offset reach every displacement-driven method exactly as `δ = g·u − o`: the
/// hardware model with command `u` gives the same shape as the plain model with shortening δ.
#[test]
fn gain_and_offset_drive_the_model_by_their_definition() {
    let (u, g, o) = (0.004, 0.83, 0.0007);
    let one = small_one_cable();
    let hw = Model::from_toml_str(&format!(
        "{one}shorten = {u}\n[hardware]\ngain = {g}\noffset = {o}\n"
    ))
    .expect("hardware model");
    let plain = Model::from_toml_str(&format!("{one}shorten = {}\n", g * u - o)).expect("plain");
    for m in [
        Box::new(Energy::default()) as Box<dyn Method>,
        ccrkit::method_by_name("geometric").expect("geometric"),
    ] {
        let a = m
            .solve(&hw.robot, &hw.actuation, &Scene::empty(), None)
            .expect("hw");
        let b = m
            .solve(&plain.robot, &plain.actuation, &Scene::empty(), None)
            .expect("plain");
        assert!(
            a.tip_distance(&b) < 1e-12,
            "{}: {}",
            m.name(),
            a.tip_distance(&b)
        );
        // And the shape really moved: the gain is not ignored.
        assert!(a.tip().x.abs() > 1e-3, "{}", m.name());
    }
    // Through `Hardware::actuation` (what predict uses) too.
    let act = hw.hardware.actuation(&[u]);
    let s = Energy::default()
        .solve(&hw.robot, &act, &Scene::empty(), None)
        .expect("act");
    let p = Energy::default()
        .solve(&plain.robot, &plain.actuation, &Scene::empty(), None)
        .expect("p");
    assert!(s.tip_distance(&p) < 1e-12);
}

/// The measured tip of a straight robot under a base pose and marker, in closed form:
/// base turned +90° about x maps z to −y.
#[test]
fn measured_tip_applies_base_pose_and_marker() {
    let m = Model::from_toml_str(&format!(
        "{}shorten = 0.0\n[hardware]\nbase_position = [0.1, 0.2, 0.3]\n\
         base_rotation = [{}, 0.0, 0.0]\nmarker = [0.0, 0.001, 0.01]\n",
        small_one_cable(),
        PI / 2.0
    ))
    .expect("model");
    let s = Energy::default()
        .solve(&m.robot, &m.actuation, &Scene::empty(), None)
        .expect("solves");
    let t = m.hardware.measured_tip(&s);
    // Tip + marker in the base frame: (0, 0.001, 0.08 + 0.01); rotated: (0, −0.09, 0.001).
    let want = nalgebra::Vector3::new(0.1, 0.2 - 0.09, 0.3 + 0.001);
    assert!((t - want).norm() < 1e-12, "{t:?} vs {want:?}");
}

/// Bad `[hardware]` values are refused naming the field.
#[test]
fn bad_hardware_is_refused_by_name() {
    let cases = [
        (
            "shorten = 0.0\n[hardware]\ngain = 0.0\n",
            "hardware.gain[0]",
        ),
        (
            "shorten = 0.0\n[hardware]\ngain = [1.0, 1.0]\n",
            "hardware.gain",
        ),
        (
            "shorten = 0.0\n[hardware]\noffset = 1.0\n",
            "hardware.offset[0]",
        ),
        (
            "shorten = 0.0\n[hardware]\nmarker = [0.0, nan, 0.0]\n",
            "hardware.marker[1]",
        ),
        (
            "shorten = 0.0\n[hardware]\nbase_position = [inf, 0.0, 0.0]\n",
            "hardware.base_position[0]",
        ),
        (
            "tension = 1.0\n[hardware]\ngain = 0.9\n",
            "hardware.gain[0] / hardware.offset[0]",
        ),
        (
            "\n[hardware]\noffset = 0.001\n",
            "hardware.gain[0] / hardware.offset[0]",
        ),
    ];
    let one = small_one_cable();
    for (extra, field) in cases {
        let e = Model::from_toml_str(&format!("{one}{extra}")).expect_err(extra);
        assert_eq!(e.field(), Some(field), "{extra}: {e}");
    }
    let e =
        Model::from_toml_str(&format!("{one}\n[hardware]\nspool = 1.0\n")).expect_err("unknown");
    assert!(e.to_string().contains("spool"), "{e}");
}

mod batch {
    use super::*;
    use ccrkit::calibrate::data::{family, DataOptions, Dataset};
    use ccrkit::calibrate::fit::{calibrate, fitted_toml, FitOptions};
    use ccrkit::calibrate::predict::{predict, PredictOptions};
    use ccrkit::calibrate::{aligned_errors, ErrorStats};
    use ccrkit::method::run::SolveRequest;
    use ccrkit::method::{MethodKind, Settings};
    use nalgebra::Vector3;

    const V4_TRAIN: &str = "models/hardware/data/v4/tdcr_sysid_20260511-183002_train.csv";

    fn opts(chunk: usize) -> PredictOptions {
        let mut s = Settings::new();
        s.push("sub-arcs", "1");
        PredictOptions {
            request: SolveRequest::new(MethodKind::Energy).with_settings(s),
            chunk,
            progress: ccrkit::progress::ProgressHandle::none(),
        }
    }

    const V6_TRAIN: &str = "models/hardware/data/v6/tdcrv6_sysid_20260406-181730_train.csv";

    /// Every `step`-th row of the train file `file`.
    fn train_rows(file: &str, step: usize) -> Dataset {
        let d = Dataset::from_file(root(file), &DataOptions::default()).expect("data");
        let idx: Vec<usize> = (0..d.len()).step_by(step).collect();
        d.select(&idx)
    }

    fn v4_rows(step: usize) -> Dataset {
        train_rows(V4_TRAIN, step)
    }

    /// The metric: invariant to a common shift of the prediction, and equal to the plain RMSE of
    /// the centred differences (a hand-computed case).
    #[test]
    fn aligned_metric_by_hand() {
        let real = [Vector3::new(0.0, 0.0, 0.0), Vector3::new(1.0, 0.0, 0.0)];
        let sim = [Vector3::new(5.0, 1.0, 0.0), Vector3::new(7.0, 1.0, 0.0)];
        // Offsets (5,1,0) and (6,1,0): mean (5.5,1,0); residuals ∓0.5 in x.
        let e = aligned_errors(&sim, &real);
        assert!(
            (e[0] - 0.5).abs() < 1e-15 && (e[1] - 0.5).abs() < 1e-15,
            "{e:?}"
        );
        let s = ErrorStats::of(&e).expect("stats");
        assert!((s.rmse - 0.5).abs() < 1e-15 && (s.max - 0.5).abs() < 1e-15);
        assert_eq!(family("rep1_all3_same_dir120_hold"), "all3_same");
        assert_eq!(family("rep1_tendon3_id5_pull"), "tendon3_id5_pull");
        assert_eq!(family("rep1_seg2_circle"), "seg2_circle");
    }

    /// Bad data is refused naming the row and column; a model/data mismatch and predict's
    /// non-options are refused by name.
    #[test]
    fn bad_data_is_refused_by_name() {
        let o = DataOptions::default();
        let e = Dataset::from_csv_str("a,servo_1_mm\nx,zz\n", "d.csv", &o).expect_err("nan");
        assert_eq!(e.field(), Some("d.csv row 1 column servo_1_mm"), "{e}");
        let e = Dataset::from_csv_str("a,b\n1,2\n", "d.csv", &o).expect_err("no servo");
        assert_eq!(e.field(), Some("columns"), "{e}");
        let named = DataOptions {
            columns: vec!["q".into()],
            unit: 1e-3,
        };
        let e = Dataset::from_csv_str("a,b\n1,2\n", "d.csv", &named).expect_err("missing");
        assert_eq!(e.field(), Some("columns"), "{e}");
        let e = Dataset::from_csv_str("servo_1_mm\n1,2\n", "d.csv", &o).expect_err("fields");
        assert_eq!(e.field(), Some("d.csv row 1"), "{e}");
        let m = model("v4");
        let d = Dataset::from_csv_str("servo_1_mm\n1\n", "d.csv", &o).expect("one column");
        let e = predict(&m, &d, &opts(8)).expect_err("9 cables");
        assert!(e.to_string().contains("columns"), "{e}");
        let mut bad = opts(8);
        bad.request.steps = 3;
        let e = predict(&m, &v4_rows(400), &bad).expect_err("steps");
        assert!(e.to_string().contains("steps"), "{e}");
        let e = predict(&m, &v4_rows(400), &opts(0)).expect_err("chunk");
        assert!(e.to_string().contains("chunk"), "{e}");
    }

    /// Prediction keeps row order and does not depend on chunking: every row solved cold
    /// (chunk 1) and warm-started in chunks of 50 agree to the solver tolerance, and both equal
    /// a direct solve of that row.
    #[test]
    fn predict_is_ordered_and_independent_of_chunks() {
        let m = model("v4");
        let d = v4_rows(8);
        let cold = predict(&m, &d, &opts(1)).expect("cold");
        let warm = predict(&m, &d, &opts(50)).expect("warm");
        assert_eq!(cold.len(), d.len());
        for (a, b) in cold.iter().zip(&warm) {
            let (a, b) = (
                a.tip.as_ref().expect("cold row"),
                b.tip.as_ref().expect("warm row"),
            );
            assert!((a - b).norm() < 1e-8, "{a:?} vs {b:?}");
        }
        for i in [0, d.len() / 2, d.len() - 1] {
            let act = m.hardware.actuation(&d.commands[i]);
            let s = Energy::default()
                .with_sub_arcs(1)
                .solve(&m.robot, &act, &Scene::empty(), None)
                .expect("row");
            let t = m.hardware.measured_tip(&s);
            assert!(
                (t - warm[i].tip.as_ref().expect("row")).norm() < 1e-8,
                "row {i}"
            );
        }
    }

    /// A parameter at its bound whose free step points outside the model does not stall the
    /// fit: on FTDCR v6 (every 4th train row) the data would make the backlash negative, so
    /// from the nominal model (backlash 0) every unprojected step was rejected and the fit
    /// stopped at iteration 0; projected, the backlash stays ≥ 0 and the gain still descends.
    #[test]
    fn a_parameter_held_at_its_bound_does_not_stall_the_fit() {
        let nominal = model("v6");
        let d = train_rows(V6_TRAIN, 4);
        let mut o = FitOptions::new(opts(64));
        o.params = vec!["gain".into(), "backlash".into()];
        let rep = calibrate(&nominal, &d, &o).expect("fit");
        println!(
            "{} -> {} mm ({}); {:?}",
            1e3 * rep.before.rmse,
            1e3 * rep.after.rmse,
            rep.stop,
            rep.params.iter().map(|p| p.value).collect::<Vec<_>>()
        );
        assert!(rep.history.len() > 2, "stalled: {}", rep.stop);
        assert!(
            rep.after.rmse < rep.before.rmse - 2e-4,
            "{} -> {}",
            rep.before.rmse,
            rep.after.rmse
        );
        // Held at the bound, not pushed past it.
        assert_eq!(rep.params[1].value, 0.0, "backlash");
        assert!(rep.history.windows(2).all(|w| w[1].rmse <= w[0].rmse));
    }

    /// A base tilt given as a rotation vector longer than π (valid: the same rotation as its
    /// wrapped form) is fitted from its wrapped form: the fitted angle is within [−π, π] with a
    /// finite standard error, and the fit equals, to the bit, the one started from the wrapped
    /// vector (adversarial pass: from 1e4 rad the fit ended at −1367 ± 2e4 rad).
    #[test]
    fn a_tilt_beyond_pi_is_fitted_from_the_same_rotation_wrapped() {
        let d = train_rows(V6_TRAIN, 16);
        let mut o = FitOptions::new(opts(64));
        o.params = vec!["base.ry".into()];
        let mut far = model("v6");
        far.hardware.base_rotation = Vector3::new(0.0, 1e4, 0.0);
        let mut near = far.clone();
        near.hardware.base_rotation = far.hardware.canonical_base_rotation();
        assert!(near.hardware.base_rotation.norm() <= std::f64::consts::PI);
        let (a, b) = (
            calibrate(&far, &d, &o).expect("fit from 1e4 rad"),
            calibrate(&near, &d, &o).expect("fit from the wrapped tilt"),
        );
        let (pa, pb) = (&a.params[0], &b.params[0]);
        println!(
            "from 1e4 rad: {} ± {:?} rad; wrapped: {} ± {:?} rad",
            pa.value, pa.sigma, pb.value, pb.sigma
        );
        assert!(pa.value.abs() <= std::f64::consts::PI + 0.1, "{}", pa.value);
        let sigma = pa.sigma.expect("a standard error");
        assert!(sigma < 0.1, "{sigma}");
        assert_eq!(pa.value, pb.value);
        assert_eq!(a.after.rmse, b.after.rmse);
    }

    /// Calibration recovers known parameters: tips made by the model with chosen gains,
    /// offsets, cable compliance and marker (plus a frame shift the metric removes) are fitted back from the
    /// nominal model to 1e-5 relative, RMSE to ~0, and the written model reproduces them.
    #[test]
    fn calibrate_recovers_known_parameters() {
        let nominal = model("v4");
        let mut truth = nominal.clone();
        let set = |m: &mut Model, seg: usize, g: f64, o: f64| {
            for c in 3 * seg..3 * seg + 3 {
                m.hardware.gain[c] = g;
                m.hardware.offset[c] = o;
            }
        };
        set(&mut truth, 0, 0.85, -0.0003);
        set(&mut truth, 1, 0.97, 0.0004);
        set(&mut truth, 2, 1.06, 0.0001);
        truth.hardware.marker.z = 0.005;
        for c in truth.robot.cables.iter_mut() {
            c.stiffness = Some(4000.0);
        }
        truth.hardware.base_position += Vector3::new(0.002, -0.001, 0.003);
        let mut d = v4_rows(6);
        let p = predict(&truth, &d, &opts(64)).expect("truth");
        d.tips = Some(
            p.iter()
                .map(|r| *r.tip.as_ref().expect("truth row"))
                .collect(),
        );
        let rep = calibrate(&nominal, &d, &FitOptions::new(opts(64))).expect("fit");
        assert!(
            rep.before.rmse > 2e-3,
            "nominal is off: {}",
            rep.before.rmse
        );
        assert!(
            rep.after.rmse < 1e-6,
            "fit rmse {} ({})",
            rep.after.rmse,
            rep.stop
        );
        let want = [
            0.85,
            0.97,
            1.06,
            -0.0003,
            0.0004,
            0.0001,
            1.0 / 4000.0,
            0.005,
        ];
        assert_eq!(rep.params.len(), want.len());
        for (f, w) in rep.params.iter().zip(want) {
            assert!(
                (f.value - w).abs() < 1e-5 * w.abs().max(1e-3),
                "{}: {} vs {w}",
                f.name,
                f.value
            );
            assert!(f.sigma.is_some(), "{}", f.name);
        }
        // Cost never rises.
        assert!(rep.history.windows(2).all(|w| w[1].rmse <= w[0].rmse));
        // The written file loads and predicts the truth without alignment.
        let text = std::fs::read_to_string(root("models/hardware/ftdcr_v4.toml")).expect("text");
        let out = fitted_toml(&text, &rep.model, "test").expect("toml");
        let back = Model::from_toml_str(&out).expect("fitted model loads");
        let q = predict(&back, &d, &opts(64)).expect("fitted");
        let tips = d.tips.as_ref().expect("tips");
        for (r, t) in q.iter().zip(tips) {
            assert!((r.tip.as_ref().expect("row") - t).norm() < 1e-6);
        }
    }
}
