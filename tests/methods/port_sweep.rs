//! Continuity through the port: a fine insertion sweep (1000 steps through the whole length,
//! every disk passing through the port, one step landing exactly on each disk of the
//! twelve-section rod) moves the tip continuously, for the default method (energy) and the
//! Cosserat rod.

use ccrkit::method::run::SolveRequest;
use ccrkit::method::{MethodKind, Settings};
use ccrkit::{Model, Shape};
use nalgebra::Vector3;

const STEPS: usize = 1000;

/// The tip at every insertion `d_k = k L / STEPS`, k = 1..=STEPS (cold solves, no warm start:
/// each shape is the method's answer at that insertion alone).
fn sweep(m: &Model, kind: MethodKind) -> Vec<Vector3<f64>> {
    let solver = SolveRequest::new(kind)
        .with_settings(Settings::new())
        .solver()
        .expect("a solver");
    let len = m.robot.length();
    (1..=STEPS)
        .map(|k| {
            let mut a = m.actuation.clone();
            a.insertion = Some(len * k as f64 / STEPS as f64);
            let s: Shape = solver
                .solve(&m.robot, &a, &m.scene, None)
                .unwrap_or_else(|e| panic!("{kind:?} at step {k}: {e}"));
            s.tip()
        })
        .collect()
}

fn steps(tips: &[Vector3<f64>]) -> Vec<f64> {
    tips.windows(2).map(|w| (w[1] - w[0]).norm()).collect()
}

/// A straight cable pulled by a fixed tension bends the exposed part into an arc of constant
/// curvature (`T·r/EI`, the same at every insertion), so inserting by δ moves the tip along
/// that arc by `v·δ ≤ δ` (`v = 1 − T/EA` the rod's stretch): no step of the sweep may exceed
/// the sweep step, not when a disk passes through the port nor when the port sits exactly on
/// one. A robot with spacer disks (8 sections) and the soft rod without disks (12 stations).
#[test]
fn a_fixed_tension_sweep_moves_the_tip_by_at_most_the_insertion_step() {
    let disks = "name = \"sweep\"\n[robot]\nsections = 8\nsection_length = 0.015\ndisk_radius = 0.008\n\
         disk_thickness = 0.0015\nbackbone = { youngs_modulus = 5e10, poisson_ratio = 0.3, diameter = 0.001 }\n\
         [[cables]]\nname = \"A\"\nradius = 0.005\nangles = { straight = 0.3 }\ntension = 4.0\n\
         [port]\nposition = [0.01, -0.02, 0.03]\norientation = { rpy = [0.3, -0.2, 0.5] }\n";
    let mut rod = Model::from_file("models/soft/lung_rod.toml").expect("the committed model");
    rod.actuation.cables[0].tension = Some(1.5);
    for (name, m) in [
        ("disks", Model::from_toml_str(disks).expect("parses")),
        ("rod", rod),
    ] {
        let delta = m.robot.length() / STEPS as f64;
        for kind in [MethodKind::DEFAULT, MethodKind::Cosserat] {
            let tips = sweep(&m, kind);
            let st = steps(&tips);
            let (k, worst) =
                st.iter()
                    .enumerate()
                    .fold((0, 0.0_f64), |a, (k, &s)| if s > a.1 { (k, s) } else { a });
            assert!(
                worst <= delta * (1.0 + 1e-6),
                "{name} {kind:?}: step {k} moved the tip {worst:e} m, the sweep step is {delta:e} m"
            );
            // The arc bends: the tip does move (a test that could not fail otherwise).
            assert!(
                st.iter().all(|&s| s > 0.5 * delta),
                "{name} {kind:?}: {st:?}"
            );
        }
    }
}

/// Helical cables (the lung rod at several tensions, turned): the exposed part's shape changes
/// with the insertion, so the tip's speed is not 1, but it is smooth: no step is more than
/// 1.5 times its larger neighbour (plus rounding), as a jump of the solve when a station passes
/// the port would make it (its neighbours move by O(δ), the jump step by the jump), and the
/// energy model and the rod trace the same path (to 2.5 % of the length: the energy model has
/// no shear, `tests/rod_body.rs`).
#[test]
fn a_helical_sweep_through_the_port_is_continuous() {
    let mut m = Model::from_file("models/soft/lung_rod.toml").expect("the committed model");
    for (c, t) in m.actuation.cables.iter_mut().zip([1.0, 2.0, 0.5]) {
        c.tension = Some(t);
    }
    m.actuation.rotation = Some(0.7);
    let delta = m.robot.length() / STEPS as f64;
    let mut paths = vec![];
    for kind in [MethodKind::DEFAULT, MethodKind::Cosserat] {
        let tips = sweep(&m, kind);
        let st = steps(&tips);
        for k in 1..st.len() - 1 {
            let near = st[k - 1].max(st[k + 1]);
            assert!(
                st[k] <= 1.5 * near + 1e-9,
                "{kind:?}: step {k} ({:.4} mm inserted) moved the tip {:e} m, its neighbours {:e} and {:e} m",
                1e3 * delta * (k + 1) as f64,
                st[k],
                st[k - 1],
                st[k + 1]
            );
        }
        let worst = st.iter().cloned().fold(0.0, f64::max);
        eprintln!(
            "{kind:?}: largest tip step {:.3} × the insertion step",
            worst / delta
        );
        paths.push(tips);
    }
    let gap = paths[0]
        .iter()
        .zip(&paths[1])
        .map(|(a, b)| (a - b).norm())
        .fold(0.0, f64::max);
    assert!(
        gap < 0.025 * m.robot.length(),
        "energy vs cosserat along the sweep: {gap:e} m"
    );
}
