//! Every solve reports each cable's tension and shortening, whatever drove it: a tension-driven
//! solve's reported shortenings drive the same method back to the same shape and tensions.

use ccrkit::actuation::{Actuation, CableDrive, Shortening};
use ccrkit::method::run::SolveRequest;
use ccrkit::method::{MethodKind, Settings};
use ccrkit::{Model, Scene, Shape};

/// Three cables (straight, helical per metre, straight tied at an inner disk), one compliant,
/// tension-driven; `extra` appended (a port).
fn model(extra: &str, compliant: bool) -> Model {
    let k = if compliant {
        "stiffness = 3000.0\npretension = 0.2\n"
    } else {
        ""
    };
    let text = format!(
        "name = \"report\"\n[robot]\nsections = 8\nsection_length = 0.015\ndisk_radius = 0.008\n\
         disk_thickness = 0.0015\nbackbone = {{ youngs_modulus = 5e10, poisson_ratio = 0.3, diameter = 0.001 }}\n\
         [[cables]]\nname = \"A\"\nradius = 0.005\nangles = {{ straight = 0.0 }}\ntension = 1.2\n{k}\
         [[cables]]\nname = \"B\"\nradius = 0.005\nangles = {{ helix = {{ start = 2.0, per_metre = 8.0 }} }}\ntension = 0.6\n\
         [[cables]]\nname = \"C\"\nradius = 0.005\nangles = {{ straight = 4.0 }}\nends_at = 5\ntension = 0.4\n\
         {extra}\n"
    );
    Model::from_toml_str(&text).expect("model parses")
}

fn solve(m: &Model, kind: MethodKind, control: &str, act: &Actuation) -> Shape {
    let settings = if kind.info().inputs.len() > 1 {
        Settings::new().with("control", control)
    } else {
        Settings::new()
    };
    SolveRequest::new(kind)
        .with_settings(settings)
        .solver()
        .expect("builds")
        .solve(&m.robot, act, &Scene::empty(), None)
        .unwrap_or_else(|e| panic!("{kind} {control}: {e}"))
}

/// The same cables driven by the shortenings `shape` reports, no tension given.
fn by_shortening(shape: &Shape, act: &Actuation) -> Actuation {
    let mut a = act.clone();
    a.cables = shape
        .cables
        .iter()
        .map(|c| CableDrive {
            shorten: Some(Shortening::Length(
                c.shortening.expect("shortening reported"),
            )),
            tension: None,
            capstan: 0.0,
        })
        .collect();
    a
}

#[test]
fn reported_shortenings_drive_the_same_shape_and_tensions_back() {
    let cases = [
        ("", false, "fixed base"),
        ("", true, "compliant cable A"),
        (
            "[port]\nposition = [0.01, 0.0, 0.02]\norientation = { rpy = [0.2, 0.1, -0.4] }\ninsertion = 0.08\nrotation = 0.5\n",
            false,
            "through a port",
        ),
    ];
    for (extra, compliant, what) in cases {
        let m = model(extra, compliant);
        for kind in [
            MethodKind::Energy,
            MethodKind::Cosserat,
            MethodKind::Kirchhoff,
        ] {
            if compliant && !kind.info().cable_compliance {
                continue;
            }
            let by_tension = solve(&m, kind, "force", &m.actuation);
            let act = by_shortening(&by_tension, &m.actuation);
            let back = solve(&m, kind, "displacement", &act);
            let d = by_tension.rms_distance(&back).expect("same disks");
            let mut worst_t = 0.0f64;
            for (a, b) in by_tension.cables.iter().zip(&back.cables) {
                let (ta, tb) = (a.tension.expect("tension"), b.tension.expect("tension"));
                worst_t = worst_t.max((ta - tb).abs());
            }
            println!("{what:<18} {kind:<10}: shape {d:.2e} m, tensions {worst_t:.2e} N");
            assert!(d < 1e-8, "{what} {kind}: shapes {d:e} m apart");
            assert!(
                worst_t < 1e-6,
                "{what} {kind}: tensions {worst_t:e} N apart"
            );
        }
    }
}

/// Constant curvature (straight cables tied at the tip) and the literal method, whose
/// displacement-driven answers report their own command back for taut cables.
#[test]
fn displacement_driven_solves_report_their_command_for_taut_cables() {
    let text = "name = \"cc\"\n[robot]\nsections = 6\nsection_length = 0.02\ndisk_radius = 0.008\n\
        disk_thickness = 0.0015\nbackbone = { youngs_modulus = 5e10, poisson_ratio = 0.3, diameter = 0.001 }\n\
        [[cables]]\nname = \"A\"\nradius = 0.005\nangles = { straight = 0.0 }\nshorten = 0.0015\n\
        [[cables]]\nname = \"B\"\nradius = 0.005\nangles = { straight = 1.5 }\nshorten = 0.0005\n\
        [[cables]]\nname = \"F\"\nradius = 0.004\nangles = { straight = 3.0 }\n";
    let m = Model::from_toml_str(text).expect("parses");
    for kind in [
        MethodKind::ConstantCurvature,
        MethodKind::Geometric,
        MethodKind::Energy,
        MethodKind::Cosserat,
    ] {
        let s = solve(&m, kind, "displacement", &m.actuation);
        for (c, want) in [(0, 0.0015), (1, 0.0005)] {
            let got = s.cables[c].shortening.expect("reported");
            assert!(!s.cables[c].slack, "{kind}: cable {c} slack");
            assert!(
                (got - want).abs() < 1e-9,
                "{kind} cable {c}: {got} vs {want}"
            );
        }
        // The free cable F is reported too: its path change on this shape.
        assert!(s.cables[2].shortening.is_some(), "{kind}: free cable");
    }
}
