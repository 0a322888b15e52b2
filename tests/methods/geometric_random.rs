//! Random robots through the geometric section solver: every outcome is either a shape that
//! meets its constraints (segments l0, taut cables at their length, slack ones not longer) or a
//! named error — `Infeasible` only with a proof, `NotConverged` with its
//! iterations when the face search finds no certified pose (before, such robots were called
//! infeasible; `tests/methods/geometric_feasibility.rs` shows one with an explicit feasible pose) —
//! never a panic, a hang or a NaN shape. `not_converged_robots_stay_few` draws a fixed set of
//! robots from the same strategy and asserts how many may end `NotConverged` (a tight ceiling).

use ccrkit::method::geometric::Geometric;
use ccrkit::{Method, Model, Scene, SolveError};
use proptest::prelude::*;
use proptest::strategy::ValueTree;
use proptest::test_runner::{TestCaseError, TestRunner};

/// Constraint residual a returned shape must meet [m].
const CONSTRAINT_TOL: f64 = 1e-9;

#[derive(Debug, Clone)]
struct CableSpec {
    start: f64,
    per_disk: f64,
    radius: f64,
    ends_at: Option<usize>,
    shorten_percent: Option<f64>,
}

fn cable() -> impl Strategy<Value = CableSpec> {
    (
        0.0..std::f64::consts::TAU,
        prop_oneof![Just(0.0), -0.6..0.6f64],
        0.004..0.010f64,
        prop_oneof![Just(None), (1usize..=6).prop_map(Some)],
        prop_oneof![Just(None), (-3.0..6.0f64).prop_map(Some)],
    )
        .prop_map(
            |(start, per_disk, radius, ends_at, shorten_percent)| CableSpec {
                start,
                per_disk,
                radius,
                ends_at,
                shorten_percent,
            },
        )
}

fn model_text(cables: &[CableSpec]) -> String {
    let mut s = String::from(
        "name = \"random\"\n[robot]\nsections = 6\nsection_length = 0.02\ndisk_radius = 0.012\ndisk_thickness = 0.002\nbackbone = { youngs_modulus = 1.1e9, poisson_ratio = 0.3, diameter = 0.003 }\n",
    );
    for (k, c) in cables.iter().enumerate() {
        s += &format!(
            "[[cables]]\nname = \"c{k}\"\nradius = {}\nangles = {{ helix = {{ start = {}, per_disk = {} }} }}\n",
            c.radius, c.start, c.per_disk
        );
        if let Some(e) = c.ends_at {
            s += &format!("ends_at = {e}\n");
        }
        if let Some(p) = c.shorten_percent {
            s += &format!("shorten_percent = {p}\n");
        }
    }
    s
}

/// What one robot ended in.
#[derive(Debug, PartialEq)]
enum Outcome {
    Solved,
    Infeasible,
    NotConverged,
}

/// Solve one random robot and check its outcome (see the module docs).
fn check(cables: &[CableSpec]) -> Result<Outcome, TestCaseError> {
    let model = Model::from_toml_str(&model_text(cables)).expect("valid by construction");
    let robot = &model.robot;
    match Geometric::literal().solve(robot, &model.actuation, &Scene::empty(), None) {
        Ok(s) => {
            for d in &s.disks {
                prop_assert!(d.position.iter().all(|x| x.is_finite()));
                prop_assert!(d.rotation.iter().all(|x| x.is_finite()));
            }
            for i in 1..=robot.sections() {
                let seg = (s.disks[i].position - s.disks[i - 1].position).norm();
                prop_assert!((seg - robot.section_length(i)).abs() < CONSTRAINT_TOL);
            }
            for (c, cable) in robot.cables.iter().enumerate() {
                let Some(f) = model.actuation.shortening_fraction(robot, c) else {
                    continue;
                };
                let path = &s.cables[c];
                for i in 1..=cable.ends_at {
                    let chord = (path.points[i] - path.points[i - 1]).norm();
                    let target = (1.0 - f) * robot.undeformed_chord(c, i);
                    if path.slack_sections.contains(&i) {
                        prop_assert!(
                            chord <= target + CONSTRAINT_TOL,
                            "slack cable {} too long in {}",
                            c,
                            i
                        );
                    } else {
                        prop_assert!(
                            (chord - target).abs() < CONSTRAINT_TOL,
                            "cable {} section {}: {} vs {}",
                            c,
                            i,
                            chord,
                            target
                        );
                    }
                }
            }
            Ok(Outcome::Solved)
        }
        // Antagonistic shortenings proved impossible for an incompressible backbone.
        Err(SolveError::Infeasible { .. }) => Ok(Outcome::Infeasible),
        // Not proved infeasible and not solved: said so, with the work done.
        Err(SolveError::NotConverged { iterations, .. }) => {
            prop_assert!(iterations > 0);
            Ok(Outcome::NotConverged)
        }
        Err(other) => Err(TestCaseError::fail(format!(
            "unexpected error kind: {other}"
        ))),
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, .. ProptestConfig::default() })]

    #[test]
    fn a_shape_that_meets_its_constraints_or_a_named_error(cables in prop::collection::vec(cable(), 1..=6)) {
        check(&cables)?;
    }
}

/// Robots drawn by the deterministic runner (same strategy, fixed seed) in
/// [`not_converged_robots_stay_few`].
const COUNTED_ROBOTS: u32 = 200;

/// `NotConverged` outcomes among [`COUNTED_ROBOTS`] deterministic robots: the count measured
/// on this solver (2026-11-25: 186 solved, 1 proved infeasible, 13 not converged; 2026-11-26,
/// with the former search as a retry of the quick one, `faces.rs`: 187, 1, 12). The goal
/// is 0; each of the 12 is a section whose face search found no certified candidate (a
/// named error, not a wrong shape). A change that fails more robots fails here; one that fails
/// fewer lowers this number.
const NOT_CONVERGED_CEILING: usize = 12;

#[test]
fn not_converged_robots_stay_few() {
    let mut runner = TestRunner::deterministic();
    let strategy = prop::collection::vec(cable(), 1..=6);
    let mut counts = [0usize; 3];
    for _ in 0..COUNTED_ROBOTS {
        let cables = strategy.new_tree(&mut runner).expect("draws").current();
        let outcome = check(&cables).unwrap_or_else(|e| panic!("{e}: {cables:?}"));
        counts[outcome as usize] += 1;
    }
    println!(
        "{COUNTED_ROBOTS} robots: {} solved, {} infeasible (proved), {} not converged",
        counts[0], counts[1], counts[2]
    );
    assert!(
        counts[2] <= NOT_CONVERGED_CEILING,
        "{} not converged (ceiling {NOT_CONVERGED_CEILING})",
        counts[2]
    );
}
