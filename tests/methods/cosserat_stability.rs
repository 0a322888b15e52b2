//! The rod's `report.stable`: the focal-point test along the rod
//! (`src/method/cosserat/mod.rs`, "Stability") against Euler's closed-form buckling load and
//! against the energy model's reduced-Hessian test on the paper cases.

use crate::common;
use crate::common::paper;
use ccrkit::actuation::Input;
use ccrkit::method::cosserat::Cosserat;
use ccrkit::method::energy::Energy;
use ccrkit::{Method, Model, Scene};

/// Case I's robot with slack cables and a compressive dead load `p` \[N\] at the tip.
fn column(p: f64) -> Model {
    let text = std::fs::read_to_string(format!(
        "{}/models/paper/case1.toml",
        env!("CARGO_MANIFEST_DIR")
    ))
    .expect("case I")
    .replace("tension = 4.169250", "tension = 0.0")
    .replace("tension = 3.825900", "tension = 0.0");
    Model::from_toml_str(&format!(
        "{text}\n[loads]\ntip_force = [0.0, 0.0, {}]\n",
        -p
    ))
    .expect("column parses")
}

/// A clamped–free column under a compressive dead tip load `P` stays straight for every `P`
/// (the straight rod is an equilibrium), but is stable only below Euler's load
/// `P_cr = π² EI / (4 L²)`. Both rods say so at `0.98 P_cr` and `1.02 P_cr` (the full rod's
/// shear and extension move its critical load by `P/GA`, `P/EA` ≈ 1e-5 here). At `5 P_cr` the
/// tip compliance `tan(kL)/k` (`k² = P/EI`, `kL = 3.51`) is positive again: only the
/// focal point passed on the way (`kL = π/2` at `s = L/√5`) shows the column unstable.
#[test]
fn euler_column_is_stable_below_the_buckling_load_only() {
    let base = column(0.0);
    let ei = base.robot.backbone.ei();
    let len = base.robot.length();
    let p_cr = std::f64::consts::PI.powi(2) * ei / (4.0 * len * len);
    for rod in [Cosserat::kirchhoff(), Cosserat::full()] {
        let rod = rod.with_control(Input::Tension);
        for (factor, expect) in [(0.98, true), (1.02, false), (5.0, false), (0.2, true)] {
            let model = column(factor * p_cr);
            let shape = rod
                .solve(&model.robot, &model.actuation, &Scene::empty(), None)
                .expect("the straight column solves");
            let bend = shape
                .disks
                .iter()
                .map(|d| d.position.x.hypot(d.position.y))
                .fold(0.0, f64::max);
            assert!(bend < 1e-12, "column bent by {bend:e} m");
            eprintln!(
                "{} at {factor} P_cr ({:.4} N): stable {:?}",
                rod.name(),
                factor * p_cr,
                shape.report.stable
            );
            assert_eq!(
                shape.report.stable,
                Some(expect),
                "{} at {factor} P_cr",
                rod.name()
            );
        }
    }
}

/// On the paper cases (force control, the file's tensions; and displacement control) both
/// rods find their answer stable, as the energy model's reduced Hessian does.
#[test]
fn paper_cases_are_stable_for_the_rod_and_the_energy_model() {
    for n in 1..=3 {
        let model = paper(n);
        let energy = Energy::default()
            .solve(&model.robot, &model.actuation, &Scene::empty(), None)
            .expect("energy solves");
        assert_eq!(energy.report.stable, Some(true), "energy, case {n}");
        for rod in [Cosserat::kirchhoff(), Cosserat::full()] {
            for control in [Input::Tension, Input::Shortening] {
                let rod = rod.clone().with_control(control);
                let shape = rod
                    .solve(&model.robot, &model.actuation, &Scene::empty(), None)
                    .expect("rod solves");
                eprintln!(
                    "case {n} {} {control:?}: stable {:?}",
                    rod.name(),
                    shape.report.stable
                );
                assert_eq!(shape.report.stable, Some(true), "case {n} {}", rod.name());
            }
        }
    }
}

/// A straight rod compressed by its own three balanced tendons (10 N each, 30 N in all, ~90×
/// Euler's load) does not buckle: cables guided along the rod and tied to it follow it, as a
/// duct-guided prestressing tendon does not buckle its column. The same 30 N as a dead tip
/// load does buckle it. (With the rod's wrench alone in the test, without the cut cables',
/// case I under its file's tensions was called unstable.)
#[test]
fn balanced_tendons_do_not_buckle_the_rod_that_guides_them() {
    let mut text = String::from(
        "name = \"guided\"\n[robot]\nsections = 9\nsection_length = 0.020\ndisk_radius = 0.012\n\
         disk_thickness = 0.002\nbackbone = { youngs_modulus = 1.1e9, poisson_ratio = 0.3, \
         diameter = 0.003 }\n",
    );
    for (i, a) in [0.0, 2.0943951023931953, 4.1887902047863905]
        .iter()
        .enumerate()
    {
        text.push_str(&format!(
            "\n[[cables]]\nname = \"c{i}\"\nradius = 0.008\nangles = {{ straight = {a} }}\n\
             tension = 10.0\n"
        ));
    }
    let guided = Model::from_toml_str(&text).expect("guided parses");
    let dead = column(30.0);
    for rod in [Cosserat::kirchhoff(), Cosserat::full()] {
        let rod = rod.with_control(Input::Tension);
        let g = rod
            .solve(&guided.robot, &guided.actuation, &Scene::empty(), None)
            .expect("guided solves");
        let d = rod
            .solve(&dead.robot, &dead.actuation, &Scene::empty(), None)
            .expect("dead load solves");
        let bend = g
            .disks
            .iter()
            .map(|k| k.position.x.hypot(k.position.y))
            .fold(0.0, f64::max);
        assert!(bend < 1e-9, "{}: guided rod bent by {bend:e} m", rod.name());
        assert_eq!(g.report.stable, Some(true), "{} guided", rod.name());
        assert_eq!(d.report.stable, Some(false), "{} dead load", rod.name());
    }
}

/// `stability = skip` (a rod setting, reachable as `--set stability=skip`) leaves
/// out the focal-point pass. The shape is the same to the bit (the pass only reads the
/// answer), `stable` is `None` meaning not checked and a note says so; with `check` (the
/// default) the same solve is `Some(true)`. A method without the test refuses the setting
/// by name, and a bad value names the field.
#[test]
fn stability_skip_leaves_the_shape_and_reports_not_checked() {
    use ccrkit::method::{MethodKind, Settings};
    for n in 1..=3 {
        let model = paper(n);
        for kind in [MethodKind::Cosserat, MethodKind::Kirchhoff] {
            for control in ["force", "displacement"] {
                let solve = |stability: &str| {
                    let s = Settings::new()
                        .with("control", control)
                        .with("stability", stability);
                    kind.build(&s)
                        .expect("builds")
                        .solve(&model.robot, &model.actuation, &Scene::empty(), None)
                        .expect("solves")
                };
                let (checked, skipped) = (solve("check"), solve("skip"));
                let tag = format!("case {n} {kind} {control}");
                assert_eq!(checked.report.stable, Some(true), "{tag}");
                assert_eq!(skipped.report.stable, None, "{tag}");
                assert!(
                    skipped
                        .report
                        .notes
                        .iter()
                        .any(|s| s == "stability not checked (stability = skip)"),
                    "{tag}: {:?}",
                    skipped.report.notes
                );
                assert!(!checked
                    .report
                    .notes
                    .iter()
                    .any(|s| s.contains("not checked")));
                for (a, b) in checked.disks.iter().zip(&skipped.disks) {
                    assert_eq!(a.position, b.position, "{tag}");
                    assert_eq!(a.rotation, b.rotation, "{tag}");
                }
                assert_eq!(checked.report.base_wrench, skipped.report.base_wrench);
            }
        }
    }
    // The command line reaches it; JSON leaves `stable` out (None).
    let json = |set: &str| {
        common::ccrkit_json(&[
            "solve",
            "models/paper/case1.toml",
            "--method",
            "cosserat",
            "--set",
            set,
            "--json",
            "-",
        ])
    };
    assert_eq!(json("stability=check")["report"]["stable"], true);
    let skipped = json("stability=skip");
    assert!(skipped["report"].get("stable").is_none(), "{skipped}");
    // Refused where it does not apply, and a bad value names the field.
    let err = MethodKind::Energy
        .build(&Settings::new().with("stability", "skip"))
        .err()
        .expect("energy refuses `stability`")
        .to_string();
    assert!(
        err.contains("stability") && err.contains("cosserat"),
        "{err}"
    );
    let err = MethodKind::Cosserat
        .build(&Settings::new().with("stability", "maybe"))
        .err()
        .expect("bad value refused")
        .to_string();
    assert!(
        err.contains("stability") && err.contains("check, skip"),
        "{err}"
    );
}

/// An answer whose stability the rod cannot decide says so (every doubt is reported):
/// adaptive steps run no variational pass, so `stable` is `None` and a note names why; the
/// same case with fixed steps decides it and carries no such note.
#[test]
fn undecided_stability_is_a_note_not_a_silence() {
    let m = paper(1);
    let fixed = common::solve(&Cosserat::full(), &m);
    assert_eq!(fixed.report.stable, Some(true));
    assert!(!fixed
        .report
        .notes
        .iter()
        .any(|n| n.contains("stability not")));
    let adaptive = common::solve(&Cosserat::full().with_adaptive(Some(1e-7)), &m);
    assert_eq!(adaptive.report.stable, None);
    assert!(
        adaptive
            .report
            .notes
            .iter()
            .any(|n| n.starts_with("stability not decided") && n.contains("--adaptive")),
        "{:?}",
        adaptive.report.notes
    );
}
