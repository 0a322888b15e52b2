//! `reach` in tension space: a tension-driven method (`energy` under `control = force`)
//! searches the cables' tensions \[N\] within their tension limits, beside a port's insertion
//! and rotation. Round trips on the soft lung rod (`models/soft/lung_rod.toml`) and on seeded
//! random robots with a port, the tension columns against central differences of full
//! solves, the closest answer of a target out of reach, and the limits it needs.

use crate::reach_random::reach_measure::{self, by_tension};
use ccrkit::reach::{reach, sensitivity, ReachOptions, Space, Target};
use ccrkit::{Model, SolveError};
use nalgebra::Vector3;

const ROOT: &str = env!("CARGO_MANIFEST_DIR");

fn lung() -> Model {
    Model::from_file(format!("{ROOT}/models/soft/lung_rod.toml")).expect("lung rod")
}

/// Tensions (1, 2, 0.5) N at insertion 80 mm, turned 0.5 rad: reach finds tensions within
/// [0, 3.5] N that put the tip there (solved forward as `ccrkit solve` does, to 1e-9 m), with
/// no more effort than the tensions that made the target; its JSON names tensions and N².
#[test]
fn the_lung_rod_reaches_a_tension_made_target() {
    let model = lung();
    let space = Space::new(&model, &by_tension(), false).expect("tension space");
    assert!(space.by_tension());
    assert_eq!((space.lo[0], space.hi[0]), (0.0, 3.5));
    let made = [1.0, 2.0, 0.5, 0.08, 0.5];
    let tip = space.solve_as_cli(&model, &made).expect("solves").tip();
    let r = reach(
        &model,
        &by_tension(),
        &Target { tip, tangent: None },
        &ReachOptions::default(),
    )
    .expect("an answer");
    assert!(r.reached, "{}", r.reason);
    assert!(space.contains(&r.u), "{:?}", r.u);
    let again = space.solve_as_cli(&model, &r.u).expect("solves").tip();
    assert!((again - tip).norm() < 1e-9, "{:e}", (again - tip).norm());
    assert!(r.effort_m2 <= space.effort(&made) + 1e-9);
    for (c, a) in r.actuation.iter().enumerate() {
        assert_eq!(a.tension, Some(r.u[c]));
        assert!(a.shorten.is_finite(), "the shortening the tension made");
    }
    let j = serde_json::to_value(r.to_json()).expect("json");
    assert_eq!(
        j["effort"]["measure"],
        "sum_tension_squared_plus_scaled_port_motion"
    );
    assert!(j["effort"]["value_n2"].is_number() && j["effort"]["value_m2"].is_null());
}

/// The tension columns the method reports (implicit function theorem) equal central
/// differences of full solves (±1e-4 N) to 1e-5 relative.
#[test]
fn tension_columns_match_central_differences() {
    let model = lung();
    let space = Space::new(&model, &by_tension(), false).expect("tension space");
    let u = [0.3, 0.1, 0.5, 0.1, -0.3];
    let shape = space.solve(&u, None).expect("solves");
    let s = sensitivity(&space, &u, &shape, false).expect("sensitivities");
    assert!(s.exact);
    let h = 1e-4;
    for c in 0..3 {
        let at = |x: f64| {
            let mut v = u.to_vec();
            v[c] += x;
            space.solve(&v, Some(&shape)).expect("solves").tip()
        };
        let fd: Vector3<f64> = (at(h) - at(-h)) / (2.0 * h);
        let col = s.position.column(c);
        assert!(
            (col - fd).norm() <= 1e-5 * fd.norm().max(1e-3),
            "cable {c}: {col:?} vs {fd:?}"
        );
    }
}

/// A target 1 m away is out of reach: the closest answer, within the limits, its distance
/// and the reason.
#[test]
fn a_target_out_of_reach_ends_with_the_closest_answer() {
    let model = lung();
    let tip = Vector3::new(0.0, 0.0, 1.0);
    let r = reach(
        &model,
        &by_tension(),
        &Target { tip, tangent: None },
        &ReachOptions::default(),
    )
    .expect("an answer");
    assert!(!r.reached);
    let space = Space::new(&model, &by_tension(), false).unwrap();
    assert!(space.contains(&r.u));
    assert!((r.tip_error_m - (r.shape.tip() - tip).norm()).abs() < 1e-12);
    assert!(r.tip_error_m >= 1.0 - 0.12 - 1e-9 && r.tip_error_m < 1.0);
    assert!(r.reason.contains("closest residual"), "{}", r.reason);
    assert!(matches!(
        r.require_reached(),
        Err(SolveError::Unreachable { .. })
    ));
}

/// Tension space needs a finite upper tension limit per cable: refused by name without one.
#[test]
fn tension_space_needs_tension_limits() {
    let text = std::fs::read_to_string(format!("{ROOT}/models/soft/lung_rod.toml")).unwrap();
    let text = text.replace("[limits.helix_minus]\ntension = [0.0, 3.5]\n", "");
    let model = Model::from_toml_str(&text).expect("parses");
    let e = Space::new(&model, &by_tension(), false)
        .err()
        .expect("refused");
    assert!(e.to_string().contains("limits.helix_minus.tension"), "{e}");
}

/// Random tension-driven robots with a port (2–6 cables, straight and helical, tied at the
/// tip or at inner disks): at least 29 of the first 30 reached in tension space, forward-
/// checked to 1e-6 m (measured: 30 of 30; 100 of the first 100 with
/// `cargo run --release --example reach_random_ports 100 1 tension`); a miss ends with the
/// closest answer and a reason.
#[test]
fn random_robots_are_reached_in_tension_space() {
    let mut out = Vec::new();
    let mut seed = 0;
    while out.len() < 30 {
        seed += 1;
        out.extend(reach_measure::measure_tensions(seed));
    }
    assert!(out.iter().any(|o| o.cables == 2) && out.iter().any(|o| o.cables >= 5));
    for o in out.iter().filter(|o| !o.ok) {
        assert!(
            o.distance.is_finite() && !o.reason.is_empty(),
            "robot {}",
            o.seed
        );
    }
    let ok = out.iter().filter(|o| o.ok).count();
    assert!(ok >= 29, "reached {ok} of 30");
}
