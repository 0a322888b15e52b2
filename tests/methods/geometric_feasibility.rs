//! The literal method calls an actuation `Infeasible` only with a proof. Regression
//! set: the 42 points of the case III stability map (12 × 12 grid, shortenings 0–18 %) that
//! were reported `infeasible` in islands although the energy model solves every point.

use ccrkit::method::geometric::Geometric;
use ccrkit::{Method, Model, Scene, SolveError};
use nalgebra::{Rotation3, Vector3};

/// (index of A's shortening, indices of B's) on the 12-point grid `k · 0.18 / 11`.
const FORMER_ISLANDS: [(usize, &[usize]); 11] = [
    (0, &[1, 6, 7]),
    (1, &[3, 4, 6, 7]),
    (2, &[1, 5, 6, 7, 8, 9]),
    (3, &[6, 7, 8, 9, 10, 11]),
    (4, &[6, 7, 10, 11]),
    (5, &[1, 2, 7]),
    (6, &[2, 3, 5, 6, 7]),
    (7, &[0, 1, 2, 3, 4, 5, 6, 7]),
    (9, &[4]),
    (10, &[5]),
    (11, &[4]),
];

fn case3(a: f64, b: f64) -> Model {
    let text = std::fs::read_to_string("models/paper/case3.toml").expect("case III");
    let text = text
        .replace(
            "shorten_percent = 3.0",
            &format!("shorten_percent = {}", a * 100.0),
        )
        .replace(
            "shorten_percent = 2.0",
            &format!("shorten_percent = {}", b * 100.0),
        );
    Model::from_toml_str(&text).expect("parses")
}

/// Every former island point solves, with its constraints met — B alone at 1.64 % too, since
/// the degenerate faces of `geometric/degenerate.rs` (an unshortened cable at its length with
/// its tension free): before them it was `NotConverged`.
#[test]
fn case3_former_islands_solve_and_nothing_is_called_infeasible_without_proof() {
    let mut solved = 0;
    let mut total = 0;
    for (ia, bs) in FORMER_ISLANDS {
        for &ib in bs {
            total += 1;
            let m = case3(ia as f64 * 0.18 / 11.0, ib as f64 * 0.18 / 11.0);
            match Geometric::literal().solve(&m.robot, &m.actuation, &Scene::empty(), None) {
                Ok(s) => {
                    solved += 1;
                    for i in 1..=m.robot.sections() {
                        let seg = (s.disks[i].position - s.disks[i - 1].position).norm();
                        assert!((seg - m.robot.section_length(i)).abs() < 1e-9);
                    }
                    for (c, _) in m.robot.cables.iter().enumerate() {
                        let f = m
                            .actuation
                            .shortening_fraction(&m.robot, c)
                            .expect("driven");
                        for i in 1..=m.robot.sections() {
                            let p = &s.cables[c].points;
                            let chord = (p[i] - p[i - 1]).norm();
                            let target = (1.0 - f) * m.robot.undeformed_chord(c, i);
                            assert!(chord <= target + 1e-9, "({ia},{ib}) cable {c} section {i}");
                        }
                    }
                }
                Err(e) => panic!("({ia},{ib}): {e}"),
            }
        }
    }
    assert_eq!(total, 42);
    assert_eq!(solved, 42, "{solved} of 42 former islands solve");
}

/// The last unsolved point, A unshortened and B shortened 1.64 %: in section 4 A must be taut
/// at exactly its length (its chord is the undeformed one: tangent and A's coupler are zero)
/// while the energy model, solving the same actuation, finds A's tension zero — the degenerate
/// complementarity `degenerate.rs` certifies. Checked independently of the solver: the segment
/// lengths, both chords against their lengths, and A's section-4 chord equal to its straight
/// chord to 1e-12 m.
#[test]
fn case3_unshortened_cable_at_its_length_solves() {
    let m = case3(0.0, 0.18 / 11.0);
    let s = Geometric::literal()
        .solve(&m.robot, &m.actuation, &Scene::empty(), None)
        .expect("A 0 %, B 1.64 % solves");
    let sec4 = &s.report.sections[3];
    assert!(sec4.zero_terms.iter().any(|t| t == "tangent"), "{sec4:?}");
    assert!(sec4.zero_terms.iter().any(|t| t == "A"), "{sec4:?}");
    assert!(!sec4.slack.iter().any(|c| c == "A"), "A is taut: {sec4:?}");
    let chord = |c: usize, i: usize| (s.cables[c].points[i] - s.cables[c].points[i - 1]).norm();
    assert!((chord(0, 4) - m.robot.undeformed_chord(0, 4)).abs() < 1e-12);
    for i in 1..=m.robot.sections() {
        assert!(
            chord(0, i) <= m.robot.undeformed_chord(0, i) + 1e-12,
            "A {i}"
        );
        assert!(chord(1, i) <= (1.0 - 0.18 / 11.0) * m.robot.undeformed_chord(1, i) + 1e-12);
    }
    let e = ccrkit::method::energy::Energy::default()
        .solve(&m.robot, &m.actuation, &Scene::empty(), None)
        .expect("energy solves it");
    assert!(e.report.converged);
}

/// The whole 12 × 12 case III map (`ccrkit study stability models/paper/case3.toml --grid 12
/// --methods geometric,energy`): no point that the energy model solves is left unsolved by the
/// literal method, cold or continued (was 143/144).
#[test]
fn case3_map_has_no_point_only_energy_solves() {
    let text = std::fs::read_to_string("models/paper/case3.toml").expect("case III");
    let model = Model::from_toml_str(&text).expect("parses");
    let opts = ccrkit::study::StabilityOptions {
        grid: 12,
        methods: vec!["geometric".into(), "energy".into()],
        ..Default::default()
    };
    let st = ccrkit::study::stability(&model, &opts).expect("study runs");
    let ok = |method: &str, cont: bool, ia: usize, ib: usize| {
        st.points.iter().any(|p| {
            p.method == method
                && p.continuation == cont
                && (p.ia, p.ib) == (ia, ib)
                && p.status.is_ok()
        })
    };
    let mut energy_ok = 0;
    for cont in [false, true] {
        for ia in 0..12 {
            for ib in 0..12 {
                if ok("energy", cont, ia, ib) {
                    energy_ok += 1;
                    assert!(ok("geometric", cont, ia, ib), "({ia},{ib}) cont {cont}");
                }
            }
        }
    }
    assert_eq!(energy_ok, 2 * 144);
}

/// A random robot once reported infeasible: cable c0 (0°, 5.7 mm) shortened 5.67 %, c2
/// (173°, 4 mm) at 0 %. An explicit pose (found by a random search) meets both lengths with
/// margin, so the actuation is feasible and must not be called `Infeasible`.
#[test]
fn a_feasible_antagonist_pair_is_not_called_infeasible() {
    let l0 = 0.02;
    let (ra, rc, pc) = (0.005701580770154482, 0.004, 3.0191455400926364f64);
    let (la, lc) = ((1.0 - 0.05667315657297711) * l0, l0);
    let (th, ph) = (1.3567219246986753f64, 1.4716468923751918f64);
    let p = l0 * Vector3::new(th.sin() * ph.cos(), th.sin() * ph.sin(), th.cos());
    let q = Rotation3::new(Vector3::new(
        -2.7659896003171554,
        0.3058576569581755,
        -0.00797195196248394,
    ));
    let ha = Vector3::new(ra, 0.0, 0.0);
    let hc = Vector3::new(rc * pc.cos(), rc * pc.sin(), 0.0);
    assert!((p + q * ha - ha).norm() < la - 5e-5, "witness meets A");
    assert!((p + q * hc - hc).norm() < lc - 5e-5, "witness meets C");
    let text = format!(
        r#"name = "random"
[robot]
sections = 6
section_length = 0.02
disk_radius = 0.012
disk_thickness = 0.002
backbone = {{ youngs_modulus = 1.1e9, poisson_ratio = 0.3, diameter = 0.003 }}
[[cables]]
name = "c0"
radius = {ra}
angles = {{ straight = 0.0 }}
shorten_percent = 5.667315657297711
[[cables]]
name = "c2"
radius = {rc}
angles = {{ straight = {pc} }}
shorten_percent = 0.0
"#
    );
    let m = Model::from_toml_str(&text).expect("parses");
    let r = Geometric::literal().solve(&m.robot, &m.actuation, &Scene::empty(), None);
    assert!(
        !matches!(r, Err(SolveError::Infeasible { .. })),
        "feasible, yet: {:?}",
        r.err()
    );
}

/// Antagonists that the bound of `feasibility.rs` proves impossible are `Infeasible`, with the
/// reason naming both cables and the bound.
#[test]
fn proved_infeasibility_names_the_pair_and_the_bound() {
    let opposite = r#"name = "antagonists"
[robot]
sections = 3
section_length = 0.02
disk_radius = 0.012
disk_thickness = 0.002
backbone = { youngs_modulus = 1.1e9, poisson_ratio = 0.3, diameter = 0.003 }
[[cables]]
name = "A"
radius = 0.008
angles = { straight = 0.0 }
shorten_percent = 2.0
[[cables]]
name = "B"
radius = 0.008
angles = { straight = 3.141592653589793 }
shorten_percent = 1.0
"#;
    let m = Model::from_toml_str(opposite).expect("parses");
    match Geometric::literal().solve(&m.robot, &m.actuation, &Scene::empty(), None) {
        Err(SolveError::Infeasible {
            reason, section, ..
        }) => {
            assert_eq!(section, 1);
            assert!(
                reason.contains("cables A and B") && reason.contains("m²"),
                "{reason}"
            );
        }
        other => panic!("expected Infeasible, got {other:?}"),
    }
}

/// The literal method reports `stable` from its certificate: on the paper cases
/// every section's reduced Hessian is positive definite (or nothing is free), so `true`.
#[test]
fn paper_cases_report_a_stable_certificate() {
    for c in 1..=3 {
        let m = Model::from_file(format!("models/paper/case{c}.toml")).expect("case");
        let s = Geometric::literal()
            .solve(&m.robot, &m.actuation, &Scene::empty(), None)
            .expect("solves");
        assert_eq!(s.report.stable, Some(true), "case {c}");
    }
}
