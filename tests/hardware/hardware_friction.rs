//! Rigid-tendon FTDCR rows with capstan friction that ended `not_converged` because
//! the lagged-weight passes of `energy/friction.rs` do not contract, and now converge.
//!
//! On the nominal (rigid-tendon) v4 with μ = 0.1 the `all3_same_dir180_hold` rows pull the
//! distal tendon by 6 mm while its two neighbours are paid out by only 0.46 mm: all three distal
//! tendons are taut and, being rigid, compress the backbone with 110–150 N each. The lagged map
//! changes the stationarity by `λ Δw ∇L` with `Δw ≈ a Δθ`, a gain of order `μ λ r ℓ / EI` ≈ 1 at
//! these tensions: its passes contract by ≈ 0.8 per pass on row 84 and not at all on row 85
//! (the residual wanders between 0.05 and 0.25). The Newton polish, tried after pass 0 only,
//! started from a wrong taut set and failed; it is now tried again once the taut set has
//! settled, and converges quadratically.
//!
//! The answer is checked against the friction equilibrium built from the public
//! `elastic_energy` and `cable_lengths` alone (no solver residual): lengths at their targets,
//! tensions ≥ 0, and on every sub-arc `j` the stationarity `∂E/∂ξ_j + Σ_c λ_c w_cj ∂L_c/∂ξ_j = 0`
//! with the capstan weights `w_cj = e^{−aΘ_j}(1 − e^{−aθ_j})/(aθ_j)` computed here from the
//! strains (the straight tendons' sub-arc lengths depend on that sub-arc's strains only, so
//! `∂L_c/∂ξ_j` is `∂L_cj/∂ξ_j`; central differences along random directions of `ξ_j`). With
//! every weight 1 (no friction) the same check fails, so it can tell the two apart.

use ccrkit::method::energy::{cable_lengths, elastic_energy, Energy};
use ccrkit::method::WarmState;
use ccrkit::model::hardware::directions;
use ccrkit::{Actuation, Method, Model, Scene, Shape, Shortening};

/// v4 val rows 83–87 (`tdcr_sysid_20260511-183002_val.csv`, counted from 0 after the header,
/// `all3_same_dir180` then `_hold`): the nine servo displacements \[mm\] in file order.
const V4_VAL: [[f64; 9]; 5] = [
    [
        -4.095729, 1.932816, 1.902136, -6.44272, 6.181943, -0.092039, -6.181943, 6.350681,
        -6.197283,
    ],
    [
        -0.153398, 0.0, 0.0, -0.874369, 0.751651, 0.0, -0.460194, 5.997866, -0.460194,
    ],
    [
        -0.107379, -0.01534, 0.0, -0.368155, 0.214757, -0.01534, -0.444854, 5.445633, -0.414175,
    ],
    [
        -0.107379, 0.0, 0.0, -0.245437, 0.01534, -0.01534, -0.352816, 4.86272, -0.398835,
    ],
    [
        -0.107379, -0.01534, 0.0, -0.199418, 0.01534, -0.01534, -0.306796, 4.295147, -0.352816,
    ],
];

/// The nominal v4 (rigid tendons) with capstan friction μ on every cable.
fn v4(mu: f64) -> Model {
    let path = format!(
        "{}/models/hardware/ftdcr_v4.toml",
        env!("CARGO_MANIFEST_DIR")
    );
    let mut m = Model::from_file(path).expect("model loads");
    m.hardware.friction.iter_mut().for_each(|f| *f = mu);
    m
}

/// Strains and tensions of an energy shape.
fn state(s: &Shape) -> (Vec<f64>, Vec<f64>) {
    match &s.report.warm {
        Some(WarmState::Energy(e)) => (e.strains.clone(), e.multipliers.clone()),
        other => panic!("energy shapes carry their state, got {other:?}"),
    }
}

/// Capstan weights `w_cj` (module docs) of every cable over the `nsub` sub-arcs of length
/// `ell`, for the signed coefficients of `act` and the strains `xi`; `friction = false` gives
/// every weight 1. Written from the capstan law, not from the solver's code.
fn capstan_weights(
    m: &Model,
    act: &Actuation,
    xi: &[f64],
    ell: &[f64],
    sub: usize,
    friction: bool,
) -> Vec<Vec<f64>> {
    (0..m.robot.cables.len())
        .map(|c| {
            let a = if friction { act.cables[c].capstan } else { 0.0 };
            let reach = m.robot.cables[c].ends_at * sub;
            let mut wrap = 0.0;
            (0..ell.len())
                .map(|j| {
                    if j >= reach {
                        return 0.0;
                    }
                    let th = ell[j] * xi[4 * j].hypot(xi[4 * j + 1]);
                    let x = a * th;
                    let mean = if x.abs() < 1e-12 {
                        1.0 - 0.5 * x
                    } else {
                        (1.0 - (-x).exp()) / x
                    };
                    let w = (-a * wrap).exp() * mean;
                    wrap += th;
                    w
                })
                .collect()
        })
        .collect()
}

/// The worst relative stationarity error of the friction equilibrium over every sub-arc (two
/// random directions each), `|∂E·v + Σ_c λ_c w_cj ∂L_c·v| / (|∂E·v| + Σ_c |λ_c w_cj ∂L_c·v|)`.
fn stationarity(m: &Model, act: &Actuation, set: &Energy, s: &Shape, friction: bool) -> f64 {
    let (xi, lam) = state(s);
    let sub = xi.len() / (4 * m.robot.sections());
    let ell: Vec<f64> = (0..xi.len() / 4)
        .map(|j| m.robot.section_length(j / sub + 1) / sub as f64)
        .collect();
    let w = capstan_weights(m, act, &xi, &ell, sub, friction);
    let mut seed = 0x2545_f491_4f6c_dd1d_u64;
    let mut rnd = || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    let mut worst = 0.0f64;
    for j in 0..ell.len() {
        for _ in 0..2 {
            // Curvatures and twist in 1/m, the axial strain dimensionless: steps of 1e-4 and
            // 1e-7 keep each well inside its linear range.
            let v = [1e-4 * rnd(), 1e-4 * rnd(), 1e-4 * rnd(), 1e-7 * rnd()];
            let at = |t: f64| {
                let mut x = xi.clone();
                for q in 0..4 {
                    x[4 * j + q] += t * v[q];
                }
                let e = elastic_energy(&m.robot, set, &x).expect("energy");
                (e, cable_lengths(&m.robot, set, &x).expect("lengths"))
            };
            let ((ep, lp), (em, lm)) = (at(1.0), at(-1.0));
            let de = 0.5 * (ep - em);
            let mut sum = de;
            let mut scale = de.abs();
            for c in 0..lam.len() {
                let f = lam[c] * w[c][j] * 0.5 * (lp[c] - lm[c]);
                sum += f;
                scale += f.abs();
            }
            if scale > 0.0 {
                worst = worst.max(sum.abs() / scale);
            }
        }
    }
    worst
}

/// Lengths at their targets (rigid tendons: `L_c ≤ L0_c − δ_c`, equal when taut, to 1e-9 m)
/// and tensions ≥ 0; returns the taut cables.
fn assert_lengths(m: &Model, act: &Actuation, set: &Energy, s: &Shape, what: &str) -> Vec<usize> {
    let (xi, lam) = state(s);
    let len = cable_lengths(&m.robot, set, &xi).expect("lengths");
    let len0 = cable_lengths(&m.robot, set, &vec![0.0; xi.len()]).expect("lengths");
    let mut taut = vec![];
    for c in 0..lam.len() {
        let Some(Shortening::Length(d)) = act.cables[c].shorten else {
            panic!("displacement-driven rows");
        };
        let gap = len[c] - (len0[c] - d);
        assert!(lam[c] >= 0.0, "{what}: cable {c} pushes, λ = {}", lam[c]);
        assert!(gap <= 1e-9, "{what}: cable {c} too long by {gap:e} m");
        if lam[c] > 0.0 {
            taut.push(c);
            assert!(gap.abs() <= 1e-9, "{what}: taut cable {c} off by {gap:e} m");
        }
    }
    taut
}

/// Rows 84 and 87, each warm-started from the row before it as `predict` does (the pair is
/// enough: both failed so on main), converge with μ = 0.1 and satisfy the friction
/// equilibrium; the frictionless equilibrium does not hold at the same answer.
#[test]
fn rigid_tendon_rows_with_friction_converge_to_the_capstan_equilibrium() {
    let m = v4(0.1);
    let set = Energy::default();
    for (row, pair) in [(84, &V4_VAL[0..2]), (87, &V4_VAL[3..5])] {
        let u: Vec<Vec<f64>> = pair
            .iter()
            .map(|r| r.iter().map(|x| 1e-3 * x).collect())
            .collect();
        let dirs = directions(&u);
        let acts: Vec<Actuation> = (0..2)
            .map(|i| m.hardware.actuation_moving(&u[i], &dirs[i]))
            .collect();
        assert!(
            acts[1].cables.iter().any(|c| c.capstan != 0.0),
            "row {row}: the cables move, so friction acts"
        );
        let prev = set
            .solve(&m.robot, &acts[0], &Scene::empty(), None)
            .expect("the row before converges");
        let s = set
            .solve(&m.robot, &acts[1], &Scene::empty(), Some(&prev))
            .unwrap_or_else(|e| panic!("row {row}: {e}"));
        let what = format!("row {row}");
        let taut = assert_lengths(&m, &acts[1], &set, &s, &what);
        let (_, lam) = state(&s);
        let with = stationarity(&m, &acts[1], &set, &s, true);
        let without = stationarity(&m, &acts[1], &set, &s, false);
        println!(
            "{what}: taut {taut:?}, tensions {lam:.1?} N, {} iterations, stationarity {with:.1e} \
             (frictionless weights {without:.1e})",
            s.report.iterations
        );
        assert!(
            taut.len() >= 3,
            "{what}: the distal tendons pull against each other"
        );
        assert!(with < 1e-6, "{what}: friction equilibrium off by {with:e}");
        assert!(
            without > 1e-3,
            "{what}: the check does not see friction ({without:e})"
        );
    }
}
