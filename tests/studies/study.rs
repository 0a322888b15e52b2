//! Studies: CSV columns and finite values, failure kinds, the Pareto front, shard merging, and
//! the constant-curvature method against the Kirchhoff rod's closed-form arc.

use ccrkit::method::constant_curvature::ConstantCurvature;
use ccrkit::method::cosserat::Cosserat;
use ccrkit::study::{self, Input, Shard};
use ccrkit::{method_by_name, Method, Model, Scene, SolveError};
use nalgebra::Vector3;

use crate::common::{max_disk_distance, paper};

/// Agreement of the closed form with the Kirchhoff rod on straight tendons [m]
/// (integration + shooting error only).
const ARC_TOL: f64 = 1e-8;

fn header_and_rows(csv: &str) -> (Vec<String>, Vec<Vec<String>>) {
    let mut lines = csv.lines();
    let header = lines
        .next()
        .expect("header")
        .split(',')
        .map(String::from)
        .collect();
    let rows = lines
        .map(|l| l.split(',').map(String::from).collect())
        .collect();
    (header, rows)
}

fn col(header: &[String], name: &str) -> usize {
    header
        .iter()
        .position(|h| h == name)
        .unwrap_or_else(|| panic!("column `{name}` missing from {header:?}"))
}

fn finite(x: &str) -> bool {
    x.parse::<f64>().is_ok_and(f64::is_finite)
}

#[test]
fn each_reference_has_its_own_pareto_front() {
    // Errors against the force-driven and the displacement-driven rod are different
    // quantities: a displacement-driven row is not dominated by a force-driven one.
    let row = |method: &str, time: f64, err: f64, reference: &str| study::SpeedAccuracyRow {
        method: method.into(),
        setting: "default".into(),
        status: study::Status::Ok,
        median_time_s: time,
        tip_error_m: err,
        rms_error_m: err,
        iterations: 1,
        reference: reference.into(),
    };
    let rows = [
        row("fast-force", 1e-5, 1e-9, "force"),
        row("slow-force", 1e-3, 1e-6, "force"),
        row("disp", 1e-4, 1e-5, "displacement"),
        row("disp-slow", 1e-3, 1e-4, "displacement"),
    ];
    assert_eq!(
        study::speed_accuracy_front(&rows),
        vec![true, false, true, false]
    );
}

#[test]
fn pareto_front_is_non_dominated() {
    let pts = [
        (1.0, 5.0),
        (2.0, 3.0),
        (2.0, 4.0), // dominated by (2, 3)
        (3.0, 3.0), // dominated by (2, 3)
        (4.0, 1.0),
        (5.0, 0.5),
        (6.0, 0.5), // dominated by (5, 0.5)
        (f64::NAN, 0.1),
    ];
    let front = study::pareto_front(&pts);
    assert_eq!(
        front,
        vec![true, true, false, false, true, true, false, false]
    );
    for (i, p) in pts.iter().enumerate().filter(|(i, _)| front[*i]) {
        for (j, q) in pts.iter().enumerate() {
            let dominates = q.0 <= p.0 && q.1 <= p.1 && (q.0 < p.0 || q.1 < p.1);
            assert!(!dominates, "front point {i} dominated by {j}");
        }
    }
}

#[test]
fn speed_accuracy_csv_has_columns_and_finite_values() {
    let model = paper(1);
    let opts = study::SpeedAccuracyOptions {
        progress: ccrkit::progress::ProgressHandle::none(),
        repeats: 1,
        methods: vec![
            "geometric-squared".into(),
            "cosserat".into(),
            "constant-curvature".into(),
        ],
    };
    let rows = study::speed_accuracy(&model, &opts).expect("study runs");
    let (h, rows_csv) = header_and_rows(&study::speed_accuracy_csv(&rows));
    for c in [
        "method",
        "setting",
        "median_time_s",
        "tip_error_m",
        "rms_error_m",
    ] {
        col(&h, c);
    }
    let ladder = |m: &str| {
        ccrkit::method::MethodKind::from_name(m)
            .expect("registered")
            .info()
            .resolutions
            .len()
    };
    let want: usize = opts.methods.iter().map(|m| ladder(m)).sum();
    assert!(want >= 2 + 7, "the rods' ladder has at least 7 RK4 rows");
    assert_eq!(rows_csv.len(), want);
    for r in &rows_csv {
        assert_eq!(r[col(&h, "status")], "ok", "{r:?}");
        for c in ["median_time_s", "tip_error_m", "rms_error_m"] {
            assert!(finite(&r[col(&h, c)]), "{c} in {r:?}");
        }
    }
    // More steps, smaller error (against the 80-step full rod) — or every row at rounding:
    // case I's tendons are straight, and the unloaded rod integrates their arcs exactly.
    let k: Vec<_> = rows
        .iter()
        .filter(|r| r.method == "cosserat" && r.setting.starts_with("rk4"))
        .collect();
    let (first, last) = (k.first().expect("rows"), k.last().expect("rows"));
    assert!(
        first.tip_error_m >= last.tip_error_m || first.tip_error_m <= 1e-12,
        "{} → {}",
        first.tip_error_m,
        last.tip_error_m
    );
}

/// The study's adaptive rows follow their tolerance: on paper case I each
/// `adaptive` row of the rods' ladder (1e-3, 1e-5, 1e-7) is at least 10× closer to the
/// 80-step reference than the one before. Before the rod's steps ran over stretches, one
/// Dormand–Prince step per section already beat every tolerance above ~1e-7, and the
/// 1e-3 and 1e-5 rows of the chart were the same point.
#[test]
fn adaptive_rows_follow_their_tolerance() {
    let opts = study::SpeedAccuracyOptions {
        progress: ccrkit::progress::ProgressHandle::none(),
        repeats: 1,
        methods: vec!["cosserat".into()],
    };
    let rows = study::speed_accuracy(&paper(1), &opts).expect("study runs");
    let adaptive: Vec<_> = rows
        .iter()
        .filter(|r| r.setting.starts_with("adaptive"))
        .collect();
    assert_eq!(adaptive.len(), 3, "three adaptive rows");
    for w in adaptive.windows(2) {
        let (a, b) = (w[0], w[1]);
        eprintln!(
            "{} {:.2e} m -> {} {:.2e} m",
            a.setting, a.rms_error_m, b.setting, b.rms_error_m
        );
        assert!(a.status.is_ok() && b.status.is_ok(), "{a:?} {b:?}");
        assert!(
            b.rms_error_m * 10.0 <= a.rms_error_m,
            "{}: {:e} m, {}: {:e} m",
            a.setting,
            a.rms_error_m,
            b.setting,
            b.rms_error_m
        );
    }
}

#[test]
fn unsupported_methods_carry_their_kind() {
    // Case II has a helical cable: the constant-curvature closed form cannot represent it.
    let model = paper(2);
    let opts = study::SpeedAccuracyOptions {
        progress: ccrkit::progress::ProgressHandle::none(),
        repeats: 1,
        methods: vec!["constant-curvature".into()],
    };
    let rows = study::speed_accuracy(&model, &opts).expect("study runs");
    assert!(rows.iter().all(|r| r.status == "unsupported"));
    let err = method_by_name("constant-curvature")
        .expect("known")
        .solve(&model.robot, &model.actuation, &Scene::empty(), None)
        .expect_err("helix is unsupported");
    assert_eq!(err.kind(), "unsupported");
    assert!(err.to_string().contains("`A`"), "{err}");
}

#[test]
fn stability_csv_on_a_small_grid() {
    let model = paper(1);
    let opts = study::StabilityOptions {
        grid: 5,
        methods: vec!["geometric-squared".into(), "constant-curvature".into()],
        ..Default::default()
    };
    let st = study::stability(&model, &opts).expect("study runs");
    assert_eq!(st.points.len(), 2 * 2 * 25);
    let (h, rows) = header_and_rows(&study::stability_csv(&st));
    for c in [
        "method",
        "continuation",
        "a",
        "b",
        "status",
        "iterations",
        "residual",
    ] {
        col(&h, c);
    }
    for r in &rows {
        assert!(finite(&r[col(&h, "a")]) && finite(&r[col(&h, "b")]));
        if r[col(&h, "status")] == "ok" {
            assert!(finite(&r[col(&h, "residual")]), "{r:?}");
            assert!(finite(&r[col(&h, "tip_x_m")]), "{r:?}");
        }
        assert_ne!(r[col(&h, "status")], "nan", "non-finite shape: {r:?}");
    }
}

#[test]
fn a_failed_grid_point_carries_its_error_kind() {
    // Two opposite straight cables both shortened: no arc (and no shape) can do it.
    let text = r#"
name = "opposite"
[robot]
sections = 4
section_length = 0.02
disk_radius = 0.012
disk_thickness = 0.002
backbone = { youngs_modulus = 1.1e9, poisson_ratio = 0.3, diameter = 0.003 }
[[cables]]
name = "A"
radius = 0.008
angles = { straight = 0.0 }
shorten_percent = 1.0
[[cables]]
name = "B"
radius = 0.008
angles = { straight = 3.141592653589793 }
shorten_percent = 1.0
"#;
    let model = Model::from_toml_str(text).expect("parses");
    let opts = study::StabilityOptions {
        grid: 3,
        methods: vec!["constant-curvature".into()],
        ..Default::default()
    };
    let st = study::stability(&model, &opts).expect("study runs");
    let corner = st
        .points
        .iter()
        .find(|p| p.ia == 2 && p.ib == 2)
        .expect("corner");
    assert_eq!(corner.status, "infeasible");
    let origin = st
        .points
        .iter()
        .find(|p| p.ia == 0 && p.ib == 0)
        .expect("origin");
    assert_eq!(origin.status, "ok");
    let csv = study::stability_csv(&st);
    assert!(csv.contains(",infeasible,"));
    // The console line (CLI and example) counts the failures by kind and names the first
    // failure by the swept cables, in percent shortening.
    for s in study::stability_summary(&st) {
        let line = s.line(&st.cables);
        assert!(line.contains("infeasible"), "{line}");
        assert!(line.contains(&format!("/{:<5} ok", s.total)), "{line}");
        assert!(
            line.contains("first failure at A") && line.contains(" %, B "),
            "{line}"
        );
    }
    // The outcome of a solve that returns NaN coordinates is not `ok`: it is the output
    // check's verdict on such a shape, `not_converged` (the one outcome vocabulary), with
    // no shape kept.
    let mut s = method_by_name("constant-curvature")
        .expect("known")
        .solve(
            &model.robot,
            &ccrkit::Actuation::free(&model.robot),
            &Scene::empty(),
            None,
        )
        .expect("free robot solves");
    s.disks[1].position.x = f64::NAN;
    let o = study::outcome(Ok(s));
    assert_eq!(o.status, "not_converged");
    assert!(o.shape.is_none());
    let e = SolveError::NotConverged {
        method: "x".into(),
        section: None,
        iterations: 7,
        residual: 0.5,
        detail: String::new(),
    };
    let o = study::outcome(Err(e));
    assert_eq!((o.status.name(), o.iterations), ("not_converged", 7));
}

fn small_workspace(shard: Option<Shard>) -> String {
    let model = paper(1);
    let opts = study::WorkspaceOptions {
        samples: 23,
        method: "geometric-squared".into(),
        chunk: 4,
        shard,
        ..Default::default()
    };
    let ws = study::workspace(&model, &opts).expect("sweep runs");
    study::workspace_csv(&ws)
}

#[test]
fn sharded_sweeps_merge_to_the_unsharded_one() {
    let whole = small_workspace(None);
    let (h, rows) = header_and_rows(&whole);
    assert_eq!(rows.len(), 23);
    for c in ["sample", "tip_x_m", "tip_y_m", "tip_z_m", "status"] {
        col(&h, c);
    }
    for r in &rows {
        if r[col(&h, "status")] == "ok" {
            assert!(finite(&r[col(&h, "tip_z_m")]));
        }
    }
    let shards: Vec<String> = (0..3)
        .map(|k| small_workspace(Some(Shard { index: k, count: 3 })))
        .collect();
    let merged = study::merge_csv(&[shards[2].clone(), shards[0].clone(), shards[1].clone()])
        .expect("merges");
    assert_eq!(merged, whole);
    assert!(study::merge_csv(&[shards[0].clone(), shards[0].clone()]).is_err());
    assert!("3/3".parse::<Shard>().is_err());
    assert_eq!(
        "1/4".parse::<Shard>().expect("parses"),
        Shard { index: 1, count: 4 }
    );
}

/// One straight cable at angle `angle`, 9 sections of 20 mm.
fn one_cable(angle: f64, input: &str) -> Model {
    let text = format!(
        r#"
name = "one"
[robot]
sections = 9
section_length = 0.020
disk_radius = 0.012
disk_thickness = 0.002
backbone = {{ youngs_modulus = 1.1e9, poisson_ratio = 0.3, diameter = 0.003 }}
[[cables]]
name = "A"
radius = 0.008
angles = {{ straight = {angle} }}
{input}
"#
    );
    Model::from_toml_str(&text).expect("parses")
}

fn tight(c: Cosserat) -> Cosserat {
    Cosserat {
        tolerance: 1e-12,
        ..c.with_steps(40)
    }
}

#[test]
fn constant_curvature_is_the_kirchhoff_arc() {
    // Force input: EI κ = τ r, bending towards the cable.
    let model = one_cable(0.7, "tension = 1.5");
    let cc = ConstantCurvature::force()
        .solve(&model.robot, &model.actuation, &Scene::empty(), None)
        .expect("cc solves");
    let rod = tight(Cosserat::kirchhoff().with_control(Input::Tension))
        .solve(&model.robot, &model.actuation, &Scene::empty(), None)
        .expect("rod solves");
    assert!(max_disk_distance(&cc, &rod) < ARC_TOL);
    let kappa = 1.5 * 0.008 / model.robot.backbone.ei();
    let l = model.robot.length();
    let inplane = (1.0 - (kappa * l).cos()) / kappa;
    let exact = Vector3::new(
        inplane * 0.7f64.cos(),
        inplane * 0.7f64.sin(),
        (kappa * l).sin() / kappa,
    );
    assert!((cc.tip() - exact).norm() < 1e-12);
    for (a, b) in cc.disks.iter().zip(&rod.disks) {
        assert!((a.rotation - b.rotation).norm() < 1e-6, "frames differ");
    }
    // Displacement input: the rod's path length along the arc is exactly the closed form's.
    let model = one_cable(0.7, "shorten_percent = 3.0");
    let cc = ConstantCurvature::displacement()
        .solve(&model.robot, &model.actuation, &Scene::empty(), None)
        .expect("cc solves");
    let rod = tight(Cosserat::kirchhoff().with_control(Input::Shortening))
        .solve(&model.robot, &model.actuation, &Scene::empty(), None)
        .expect("rod solves");
    assert!(max_disk_distance(&cc, &rod) < ARC_TOL);
    let (tc, tr) = (
        cc.cables[0].tension.expect("cc tension"),
        rod.cables[0].tension.expect("rod tension"),
    );
    assert!((tc - tr).abs() < 1e-6 * tr, "tensions {tc} vs {tr}");
}

#[test]
fn constant_curvature_two_cables_match_the_rod_and_the_geometric_method() {
    // Case I: two straight cables. Force input: the Kirchhoff rod is the same arc.
    let model = paper(1);
    let cc = ConstantCurvature::force()
        .solve(&model.robot, &model.actuation, &Scene::empty(), None)
        .expect("cc solves");
    let rod = tight(Cosserat::kirchhoff().with_control(Input::Tension))
        .solve(&model.robot, &model.actuation, &Scene::empty(), None)
        .expect("rod solves");
    assert!(max_disk_distance(&cc, &rod) < ARC_TOL);
    // Displacement input: both cables taut, against the rod in displacement control.
    let cc = ConstantCurvature::displacement()
        .solve(&model.robot, &model.actuation, &Scene::empty(), None)
        .expect("cc solves");
    assert!(cc.cables.iter().all(|c| !c.slack));
    let rod = tight(Cosserat::kirchhoff().with_control(Input::Shortening))
        .solve(&model.robot, &model.actuation, &Scene::empty(), None)
        .expect("rod solves");
    assert!(max_disk_distance(&cc, &rod) < ARC_TOL);
}

#[test]
fn constant_curvature_matches_the_geometric_method_on_one_cable() {
    // One straight cable: the same bending plane exactly; the deflection differs by the
    // geometric model's own section reading (its sections split a disk's turn between the
    // chord tilt and the disk rotation by the angle objective, not as an arc's θ/2 and θ):
    // measured 6.6 mm of tip distance over 180 mm, 49.9 against 55.9 mm of deflection.
    let model = one_cable(0.3, "shorten_percent = 3.0");
    let cc = ConstantCurvature::displacement()
        .solve(&model.robot, &model.actuation, &Scene::empty(), None)
        .expect("cc solves");
    let geo = method_by_name("geometric")
        .expect("known")
        .solve(&model.robot, &model.actuation, &Scene::empty(), None)
        .expect("geometric solves");
    let d = cc.tip_distance(&geo);
    assert!(d < 0.05 * model.robot.length(), "tip distance {d}");
    for s in [&cc, &geo] {
        let t = s.tip();
        assert!(
            (t.y.atan2(t.x) - 0.3).abs() < 1e-9,
            "bending plane of {}",
            s.method
        );
    }
}

#[test]
fn constant_curvature_slack_and_unsupported_routings() {
    // A paid-out cable (negative shortening) is slack: the robot stays straight.
    let model = one_cable(0.0, "shorten_percent = -1.0");
    let s = ConstantCurvature::displacement()
        .solve(&model.robot, &model.actuation, &Scene::empty(), None)
        .expect("solves");
    assert!(s.cables[0].slack);
    assert!((s.tip() - Vector3::new(0.0, 0.0, model.robot.length())).norm() < 1e-15);
    // A cable tied at an inner disk is named.
    let model = one_cable(0.0, "shorten_percent = 1.0\nends_at = 4");
    let e = ConstantCurvature::displacement()
        .solve(&model.robot, &model.actuation, &Scene::empty(), None)
        .expect_err("inner termination unsupported");
    assert_eq!(e.kind(), "unsupported");
    assert!(e.to_string().contains("`A`"), "{e}");
    // Study inputs name their CSV columns in SI.
    assert_eq!(Input::Tension.csv_name(), "tension_n");
}

/// `auto`'s rows in the speed–accuracy study: one per tolerance, each judged against the
/// converged rod driven by the input it chose, and each within its tolerance there.
#[test]
fn auto_rows_meet_their_tolerance_against_the_rod() {
    let opts = study::SpeedAccuracyOptions {
        progress: ccrkit::progress::ProgressHandle::none(),
        repeats: 1,
        methods: vec![study::AUTO.into()],
    };
    let rows = study::speed_accuracy(&paper(2), &opts).expect("study runs");
    assert_eq!(rows.len(), study::AUTO_TOLERANCES.len());
    for (r, t) in rows.iter().zip(study::AUTO_TOLERANCES) {
        assert!(r.status.is_ok(), "{r:?}");
        assert!(
            r.setting.starts_with(&format!("tol {} mm: ", t * 1e3)),
            "{r:?}"
        );
        assert!(r.tip_error_m <= t, "{} m above {t} m: {r:?}", r.tip_error_m);
    }
}
