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
