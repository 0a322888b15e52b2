//! Compliant cables (`stiffness` k, `pretension` T₀ of a cable) in the rod (`cosserat`,
//! `kirchhoff`, displacement control), against independent truths: the series-spring identity
//! (a compliant solve at shortening `d` equals the inextensible solve at `d + T₀/k − T/k`),
//! the closed-form tension of three symmetric pretensioned cables, and the energy model,
//! which honours the same fields with its own discretization and solver.

use ccrkit::actuation::{Actuation, Input};
use ccrkit::method::cosserat::Cosserat;
use ccrkit::method::energy::Energy;
use ccrkit::{Method, Model, Scene, Shape};
use nalgebra::Vector3;

use crate::common::one_cable::{assert_series_springs, compliant_v4, one_cable, spring, tension};
use crate::common::one_cable::{three_pretensioned, V4_BEND};

fn rods() -> [Cosserat; 2] {
    [
        Cosserat::full().with_control(Input::Shortening),
        Cosserat::kirchhoff().with_control(Input::Shortening),
    ]
}

fn solve(rod: &dyn Method, m: &Model, act: &Actuation, warm: Option<&Shape>) -> Shape {
    rod.solve(&m.robot, act, &Scene::empty(), warm)
        .unwrap_or_else(|e| panic!("{} solves: {e}", rod.name()))
}

/// Series springs: the compliant cable shortened by `d` ends with tension `T`; the
/// inextensible cable shortened by `d + T₀/k − T/k` gives the same tip (1e-9 m) and tension
/// (1e-6 relative). Both rods, a stiff and a soft backbone, with and without pretension.
#[test]
fn compliant_rod_equals_rigid_rod_at_the_effective_shortening() {
    for rod in rods() {
        assert_series_springs(rod.name(), |m, act| solve(&rod, m, act, None));
    }
}

/// Three straight cables at 120° with pretension T₀ and no command: the robot stays straight
/// and each cable holds `T = T₀ / (1 + 3 k L / EA)` (compatibility
/// `L (1 + ε) − (L − T₀/k) = T/k`, `ε = −3T/EA`); the inextensible rod holds `T = T₀`.
#[test]
fn symmetric_pretension_matches_the_closed_form() {
    let (k, t0, e) = (4000.0, 2.0, 2.5e8);
    let file = three_pretensioned(e, k, t0);
    let m = Model::from_toml_str(&file).expect("model");
    let ea = e * std::f64::consts::PI * 0.001 * 0.001;
    let l = 0.1;
    for rod in rods() {
        let s = solve(&rod, &m, &m.actuation, None);
        let full = rod.model == ccrkit::method::cosserat::RodModel::Full;
        let want = if full {
            t0 / (1.0 + 3.0 * k * l / ea)
        } else {
            t0
        };
        for c in 0..3 {
            let t = tension(&s, c);
            eprintln!(
                "{} cable {c}: T = {t:.12} N, closed form {want:.12} N",
                rod.name()
            );
            assert!(
                (t - want).abs() < 1e-9 * t0,
                "{} cable {c}: {t} vs {want}",
                rod.name()
            );
        }
        let z = if full { l * (1.0 - 3.0 * want / ea) } else { l };
        let tip = s.tip();
        assert!(
            (tip - Vector3::new(0.0, 0.0, z)).norm() < 1e-12,
            "{}: {tip:?} vs z {z}",
            rod.name()
        );
    }
}

/// FTDCR v4 with every cable compliant and pretensioned (k = 3000 + 200 c N/m, T₀ = 0.3 N,
/// `one_cable::compliant_v4`, as `tests/methods/compliance.rs`), on bending commands where some cables go slack:
/// both rods, cold and warm-started from the energy model, converge, their cable slack/taut
/// pattern is the energy model's, and their tips agree with it (the rod integrates the
/// exact cable paths, the energy model uses constant-strain sub-arcs: the rigid FTDCR
/// samples agree to < 1 µm, `tests/methods/cosserat_refs.rs`).
#[test]
fn compliant_ftdcr_rod_matches_the_energy_model() {
    let m = compliant_v4();
    let commands: [[f64; 9]; 3] = [
        V4_BEND,
        [1e-3, 1e-3, 1e-3, 2e-3, 2e-3, 2e-3, 0.5e-3, 0.5e-3, 0.5e-3],
        [0.0, 6e-3, -3e-3, 2e-3, 0.0, 0.0, -1e-3, 0.0, 5e-3],
    ];
    let mut worst = [0.0f64; 2];
    let mut worst_compression = 0.0f64;
    let (ea, l) = (m.robot.backbone.ea(), m.robot.length());
    for (i, u) in commands.iter().enumerate() {
        let act = m.hardware.actuation(u);
        let energy = Energy::default()
            .solve(&m.robot, &act, &Scene::empty(), None)
            .expect("energy solves");
        let pull: f64 = (0..9).map(|c| tension(&energy, c)).sum();
        worst_compression = worst_compression.max(pull * l / ea);
        for (j, rod) in rods().iter().enumerate() {
            for warm in [None, Some(&energy)] {
                let s = solve(rod, &m, &act, warm);
                let d = s.tip_distance(&energy);
                worst[j] = worst[j].max(d);
                let dt = (0..9)
                    .map(|c| (tension(&s, c) - tension(&energy, c)).abs())
                    .fold(0.0, f64::max);
                if j == 1 {
                    for c in 0..9 {
                        let k = m.robot.cables[c].stiffness.expect("compliant");
                        let gap = (tension(&s, c) - tension(&energy, c)).abs();
                        assert!(
                            gap <= k * pull * l / ea,
                            "command {i} kirchhoff cable {c}: tension differs by {gap} N"
                        );
                    }
                }
                eprintln!(
                    "command {i} {} warm {}: {} iterations, tip {:.2e} m from energy, tensions \
                     differ by ≤ {dt:.2e} N",
                    rod.name(),
                    warm.is_some(),
                    s.report.iterations,
                    d
                );
                for c in 0..9 {
                    assert_eq!(
                        s.cables[c].slack,
                        tension(&energy, c) == 0.0,
                        "command {i} {} cable {c}: rod tension {}, energy {}",
                        rod.name(),
                        tension(&s, c),
                        tension(&energy, c)
                    );
                }
            }
        }
    }
    eprintln!(
        "tips to energy: cosserat ≤ {:.2e} m, kirchhoff ≤ {:.2e} m (compression ≤ {:.2e} m)",
        worst[0], worst[1], worst_compression
    );
    assert!(worst[0] < 1e-8, "cosserat {:e} m from energy", worst[0]);
    // The inextensible rod lacks the backbone's compression `Σ τ L / EA` (≤ 0.18 mm here),
    // which the energy model and `cosserat` have; a cable's path differs by at most about
    // that, so its tension by at most `k Σ τ L / EA` (checked above, per cable). Through the
    // soft rod (EI = 2.5e-3 N m²) those tension changes move the tip by up to 1.3 mm, as the
    // rigid FTDCR samples differ by 0.003–2.2 mm (`tests/methods/cosserat_refs.rs`).
    assert!(worst[1] < 2e-3, "kirchhoff {:e} m from energy", worst[1]);
}

/// The exact (variational) shooting Jacobian with compliant cables, against central
/// differences of the residual (relative 1e-6, as `tests/methods/cosserat.rs` checks the rigid one),
/// and against the rigid cables' Jacobian at the same point: they differ only by
/// `−k_ℓ/k` on each cable's own tension column, `k_ℓ = EI/(r̄² L)` (module docs, "Shooting").
/// The one-cable robot (`k_ℓ/k` ≈ 49, larger than the column's rigid entries) and paper
/// case I with both cables compliant.
#[test]
fn compliant_variational_jacobian_matches_central_differences() {
    let case1 = std::fs::read_to_string(format!(
        "{}/models/paper/case1.toml",
        env!("CARGO_MANIFEST_DIR")
    ))
    .expect("case I");
    let soft1 = case1
        .replace(
            "tension = 4.169250",
            "tension = 4.169250\nstiffness = 800.0\npretension = 0.5",
        )
        .replace(
            "tension = 3.825900",
            "tension = 3.825900\nstiffness = 1500.0",
        );
    let pairs = [
        (one_cable(2e11, &spring(500.0, 1.5)), one_cable(2e11, "")),
        (soft1, case1),
    ];
    for (soft, rigid) in &pairs {
        let soft = Model::from_toml_str(soft).expect("compliant model");
        let rigid = Model::from_toml_str(rigid).expect("rigid model");
        assert!(soft.robot.cables.iter().all(|c| c.stiffness.is_some()));
        let robot = &soft.robot;
        for rod in rods() {
            let jac = |m: &Model| {
                rod.shooting_jacobians(&m.robot, &m.actuation, 2.0, 1e-4)
                    .expect("valid")
                    .expect("variational Jacobian available")
            };
            let (f, jv, jc) = jac(&soft);
            assert!(f.iter().all(|v| v.is_finite()));
            let scale = jc.abs().max();
            let err = (&jv - &jc).abs().max();
            let (_, jr, _) = jac(&rigid);
            let mut want = jr.clone();
            for (j, cable) in robot.cables.iter().enumerate() {
                let rbar = cable.radius.iter().sum::<f64>() / cable.radius.len() as f64;
                let kl = robot.backbone.ei() / (rbar * rbar * robot.length());
                want[(6 + j, 6 + j)] -= kl / cable.stiffness.expect("compliant");
            }
            let off = (&jv - &want).abs().max();
            eprintln!(
                "{} cables {}: vs central differences {err:.2e}, vs rigid − k_l/k {off:.2e}, \
                 scale {scale:.2e}",
                robot.cables.len(),
                rod.name()
            );
            assert!(err <= 1e-6 * scale, "{}: {err:e} vs {scale:e}", rod.name());
            assert!(off <= 1e-12 * scale, "{}: {off:e} vs {scale:e}", rod.name());
        }
    }
}
