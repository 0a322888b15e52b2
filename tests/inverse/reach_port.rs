//! `reach` with a port: insertion and rotation as unknowns within the port's limits, their
//! Jacobian columns against central differences, round trips over seeded random inputs
//! (cables, insertion, rotation), and the answer's JSON.

use crate::common;

use ccrkit::method::run::SolveRequest;
use ccrkit::method::MethodKind;
use ccrkit::reach::{reach, sensitivity, ReachOptions, Space, Target};
use ccrkit::Model;
use rand_core::{Rng, SeedableRng};
use rand_xorshift::XorShiftRng;

const ROOT: &str = env!("CARGO_MANIFEST_DIR");

fn energy() -> SolveRequest {
    SolveRequest::new(MethodKind::Energy)
}

/// Paper case 1 with a third cable, deployed through a port tilted 30° about x at
/// (0.01, 0, 0.02): insertion within [0.09, 0.18] m, rotation within ±2 rad.
fn ported() -> Model {
    let text = std::fs::read_to_string(format!("{ROOT}/models/paper/case1.toml")).unwrap();
    let extra = "\n[[cables]]\nname = \"C\"\nradius = 0.008\nangles = { straight = 4.1887902047863905 }\n\
                 [port]\nposition = [0.01, 0.0, 0.02]\norientation = { rpy = [0.5235987755982988, 0.0, 0.0] }\n\
                 insertion = 0.15\nlimits = { insertion = [0.09, 0.18], rotation = [-2.0, 2.0] }\n";
    Model::from_toml_str(&(text + extra)).unwrap()
}

fn uniform(rng: &mut XorShiftRng, lo: f64, hi: f64) -> f64 {
    lo + (hi - lo) * (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64
}

/// The unknowns are the three cables, the insertion and the rotation, in the port's limits.
#[test]
fn the_space_has_insertion_and_rotation() {
    let model = ported();
    let space = Space::new(&model, &energy(), false).unwrap();
    assert_eq!(space.dim(), 5);
    assert!(space.has_port());
    assert_eq!((space.lo[3], space.hi[3]), (0.09, 0.18));
    assert_eq!((space.lo[4], space.hi[4]), (-2.0, 2.0));
    assert_eq!(space.rest[3..], [0.15, 0.0]);
    let a = space.actuation(&[0.001, 0.0, 0.0, 0.12, 0.3]);
    assert_eq!((a.insertion, a.rotation), (Some(0.12), Some(0.3)));
    // The documented effort: Σu² + (ρ_d (d − d₀))² + (ρ_ψ ψ)², ρ_ψ the mean hole radius.
    let e = space.effort(&[0.001, 0.0, 0.0, 0.12, 0.3]);
    let want = 1e-6 + (0.1f64 * (0.12 - 0.15)).powi(2) + (0.008f64 * 0.3).powi(2);
    assert!((e - want).abs() < 1e-18, "{e} vs {want}");
}

/// The rotation's column (exact: a rigid turn about the port axis), the insertion's (the rod's
/// kinematics, `src/reach/sens.rs`; here straight cables) and the cable columns (the method's,
/// mapped through the port) agree with central differences of full solves (one-sided at a
/// limit).
#[test]
fn port_columns_match_central_differences() {
    let model = ported();
    let space = Space::new(&model, &energy(), false).unwrap();
    for x in [
        vec![0.004, 0.001, 0.0, 0.13, 0.4],
        vec![0.0, 0.006, 0.002, 0.18, -1.1],
    ] {
        let shape = space.solve(&x, None).unwrap();
        let s = sensitivity(&space, &x, &shape, false).unwrap();
        assert!(s.exact, "the cable columns should be the method's");
        assert!(
            s.exact_insertion,
            "the insertion's column should be the formula"
        );
        for (j, h) in [(0, 1e-6), (1, 1e-6), (2, 1e-6), (3, 1e-5), (4, 1e-5)] {
            let at = |v: f64| {
                let mut y = x.clone();
                y[j] = (y[j] + v).clamp(space.lo[j], space.hi[j]);
                (y[j], space.solve(&y, Some(&shape)).unwrap())
            };
            let ((a, sa), (b, sb)) = (at(h), at(-h));
            let fd = (sa.tip() - sb.tip()) / (a - b);
            let col = s.position.column(j);
            let err = (col - fd).norm();
            let tol = 1e-5 * fd.norm().max(1e-3);
            assert!(
                err <= tol,
                "column {j} at {x:?}: {col} vs {fd}, off by {err:.3e}"
            );
        }
    }
}

/// Over 30 seeded random inputs within every limit (cables, insertion, rotation), the tip they
/// make is reached, the answer solved forward gives it to 1e-9 m, and its insertion and
/// rotation lie within the port's limits and drive the reported shape.
#[test]
fn round_trip_through_the_port() {
    let model = ported();
    let space = Space::new(&model, &energy(), false).unwrap();
    let mut rng = XorShiftRng::seed_from_u64(5);
    let (mut ok, n) = (0, 30);
    for _ in 0..n {
        let x: Vec<f64> = (0..space.dim())
            .map(|c| uniform(&mut rng, space.lo[c], space.hi[c]))
            .collect();
        let tip = space.solve_as_cli(&model, &x).unwrap().tip();
        let r = reach(
            &model,
            &energy(),
            &Target { tip, tangent: None },
            &ReachOptions::default(),
        )
        .unwrap();
        let again = space.solve_as_cli(&model, &r.u).unwrap();
        assert!((again.tip() - r.shape.tip()).norm() <= 1e-9);
        let port = r.shape.port.as_ref().unwrap();
        assert_eq!(
            (Some(port.insertion), Some(port.rotation)),
            (r.insertion, r.rotation)
        );
        assert!(space.contains(&r.u));
        assert!((r.effort_m2 - space.effort(&r.u)).abs() <= 1e-15);
        if r.reached {
            ok += 1;
            assert!((again.tip() - tip).norm() <= 1e-7);
        }
    }
    eprintln!("port round trip: reached {ok} of {n}");
    assert!(ok >= 29, "reached {ok} of {n}");
}

/// `ccrkit reach --json` of a robot with a port carries the insertion and the rotation.
#[test]
fn the_answer_json_carries_insertion_and_rotation() {
    let dir = std::env::temp_dir().join(format!("ccrkit_reach_port_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let model = ported();
    let space = Space::new(&model, &energy(), false).unwrap();
    let tip = space
        .solve_as_cli(&model, &[0.003, 0.0, 0.001, 0.12, 0.7])
        .unwrap()
        .tip();
    let text = std::fs::read_to_string(format!("{ROOT}/models/paper/case1.toml")).unwrap();
    let extra = "\n[[cables]]\nname = \"C\"\nradius = 0.008\nangles = { straight = 4.1887902047863905 }\n\
                 [port]\nposition = [0.01, 0.0, 0.02]\norientation = { rpy = [0.5235987755982988, 0.0, 0.0] }\n\
                 insertion = 0.15\nlimits = { insertion = [0.09, 0.18], rotation = [-2.0, 2.0] }\n";
    let file = dir.join("ported.toml");
    std::fs::write(&file, text + extra).unwrap();
    let j = common::ccrkit_json(&[
        "reach".to_string(),
        file.display().to_string(),
        format!("--tip={},{},{}", tip.x, tip.y, tip.z),
        "--json=-".into(),
    ]);
    assert_eq!(j["reached"], true);
    let (d, psi) = (
        j["insertion"].as_f64().unwrap(),
        j["rotation"].as_f64().unwrap(),
    );
    assert!((0.09..=0.18).contains(&d) && (-2.0..=2.0).contains(&psi));
    assert_eq!(j["shape"]["port"]["insertion"].as_f64(), Some(d));
    assert_eq!(
        j["effort"]["measure"],
        "sum_shorten_squared_plus_scaled_port_motion"
    );
}
