//! `plan` and roadmaps through a port: the insertion and the rotation are planned beside the
//! cables. A plan to a target behind a block (reached only by inserting past it) whose every
//! waypoint, re-solved cold as `ccrkit solve` does, keeps the margin by parry3d on features
//! built in the test; a roadmap built and queried on the same robot; every edge's certified
//! clearance against fine sweeps of independent solves along the rotation, the insertion and
//! both; the planners' metric is a metric (proptest); the plan file's insertion and rotation
//! are checked when read back.

use super::plan::{dense_recheck, parry_clearance};
use ccrkit::method::run::SolveRequest;
use ccrkit::method::MethodKind;
use ccrkit::plan::metric::Metric;
use ccrkit::plan::motion::motion;
use ccrkit::plan::roadmap::{build, BuildOptions};
use ccrkit::plan::{plan, Checker, EdgeCheck, Goal, Plan, PlanOptions};
use ccrkit::reach::Space;
use ccrkit::Model;
use nalgebra::Vector3;
use proptest::prelude::*;

const ROOT: &str = env!("CARGO_MANIFEST_DIR");

fn energy() -> SolveRequest {
    SolveRequest::new(MethodKind::Energy)
}

fn behind_block() -> Model {
    Model::from_file(std::path::PathBuf::from(format!(
        "{ROOT}/models/port/behind_block.toml"
    )))
    .unwrap()
}

/// The target of `examples/port_reach.rs`: 9 mm beyond the block's far face, off to one side.
const TARGET: [f64; 3] = [-0.0585, 0.0429, 0.1353];

/// Every waypoint solved again cold as `ccrkit solve` does: the same tip, and clear of the
/// block by the margin measured by parry3d on the test's own features; the base values within
/// the port's limits. Returns the largest insertion along the plan.
fn waypoints_resolved_clear(model: &Model, space: &Space, p: &Plan) -> f64 {
    let k = space.cables();
    let mut deepest = f64::NEG_INFINITY;
    for (i, n) in p.waypoints.iter().enumerate() {
        assert_eq!(n.u.len(), k + 2, "waypoint {i} has {} values", n.u.len());
        assert!(
            space.contains(&n.u),
            "waypoint {i} {:?} outside the limits",
            n.u
        );
        let cold = space.solve_as_cli(model, &n.u).unwrap();
        let e = (cold.tip() - n.shape.tip()).norm();
        assert!(e <= 1e-9, "waypoint {i}: tip {e:e} m from a cold solve");
        let port = cold.port.as_ref().unwrap();
        assert_eq!((port.insertion, port.rotation), (n.u[k], n.u[k + 1]));
        let c = parry_clearance(model, &cold, &space.scene);
        assert!(
            c >= p.margin_m - 1e-9,
            "waypoint {i} is {c:e} m from the block, margin {}",
            p.margin_m
        );
        deepest = deepest.max(n.u[k]);
    }
    deepest
}

/// Plan from 60 mm out to the target behind the block: the robot must insert past the block
/// (its straight insertion runs into it), and every waypoint and every edge keep the margin.
#[test]
fn plan_behind_a_block() {
    let model = behind_block();
    let space = Space::new(&model, &energy(), false).unwrap();
    let goal = Goal::Tip(Vector3::from(TARGET));
    let p = plan(
        &model,
        &energy(),
        None,
        &goal,
        &PlanOptions::default(),
        None,
    )
    .unwrap();
    let last = p.waypoints.last().unwrap();
    assert!((last.shape.tip() - Vector3::from(TARGET)).norm() < 1e-6);
    let deepest = waypoints_resolved_clear(&model, &space, &p);
    // The block's far face is 126 mm out: the tip is beyond it only by inserting past it.
    assert!(deepest > 0.126, "deepest insertion {deepest} m");
    let worst = dense_recheck(&model, &p);
    assert!(p.certified_clearance_m <= worst + 1e-12);
    // The plan file carries the base values, and reads back.
    let json = serde_json::to_value(p.to_json()).unwrap();
    let w = &json["waypoints"][0];
    assert_eq!(w["insertion"].as_f64(), Some(0.06));
    assert_eq!(w["rotation"].as_f64(), Some(0.0));
    let text = serde_json::to_string(&json).unwrap();
    let shapes = ccrkit::export::view::read_plan(&text, &model.robot, &model.scene).unwrap();
    assert_eq!(shapes.len(), p.waypoints.len());
    // The trajectory's base joints are the waypoints' insertion and rotation.
    let csv = p.trajectory_csv(&model).unwrap();
    let mut lines = csv.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    assert_eq!(head[1..3], ["port_insertion", "port_rotation"]);
    for (line, n) in lines.zip(&p.waypoints) {
        let v: Vec<f64> = line
            .split(',')
            .skip(1)
            .map(|x| x.parse().unwrap())
            .collect();
        assert_eq!((v[0], v[1]), (n.u[2], n.u[3]));
    }
}

/// A plan file whose insertion or rotation was edited away from its shape's is refused by
/// waypoint and field.
#[test]
fn read_plan_checks_the_base_values() {
    let model = behind_block();
    let mut goal = model.actuation.clone();
    goal.insertion = Some(0.08);
    let g = ccrkit::plan::actuation_of(&model, &goal);
    let p = plan(
        &model,
        &energy(),
        None,
        &Goal::Actuation(g),
        &PlanOptions::default(),
        None,
    )
    .unwrap();
    let json = serde_json::to_value(p.to_json()).unwrap();
    for (key, value) in [("insertion", 0.07), ("rotation", 0.5)] {
        let mut j = json.clone();
        j["waypoints"][1][key] = serde_json::json!(value);
        let text = serde_json::to_string(&j).unwrap();
        let e = ccrkit::export::view::read_plan(&text, &model.robot, &model.scene).unwrap_err();
        let e = format!("{e:?}");
        assert!(
            e.contains(&format!("waypoints[1].{key}")) && e.contains("differs"),
            "{e}"
        );
    }
}

/// A roadmap built on the port robot answers a query behind the block; its nodes carry the
/// insertion and rotation, and the answer passes the same re-checks.
#[test]
fn roadmap_through_a_port() {
    let model = behind_block();
    let space = Space::new(&model, &energy(), false).unwrap();
    let opts = BuildOptions {
        samples: 150,
        expand: 150,
        ..BuildOptions::default()
    };
    let rm = build(&model, &energy(), &opts).unwrap();
    assert!(rm.nodes.iter().all(|n| n.u.len() == 4));
    assert_eq!(rm.lo[2..], space.lo[2..]);
    // Some nodes differ from another only in their insertion (samples along it).
    let along = rm.nodes.iter().enumerate().any(|(i, a)| {
        rm.nodes[..i]
            .iter()
            .any(|b| a.u[0] == b.u[0] && a.u[1] == b.u[1] && a.u[3] == b.u[3] && a.u[2] != b.u[2])
    });
    assert!(along, "no node was sampled along the insertion");
    let goal = Goal::Tip(Vector3::from(TARGET));
    let p = plan(
        &model,
        &energy(),
        None,
        &goal,
        &PlanOptions::default(),
        Some(&rm),
    )
    .unwrap();
    assert_eq!(p.stats.planner, "roadmap");
    waypoints_resolved_clear(&model, &space, &p);
    dense_recheck(&model, &p);
}

/// The port robot's roadmap nodes — uniform samples, samples slid along the insertion and the
/// expansion rounds, solved in parallel — and edges are the same built on one thread.
#[test]
fn port_roadmap_is_the_same_on_one_thread() {
    let model = behind_block();
    let opts = BuildOptions {
        samples: 45,
        expand: 80,
        neighbours: 4,
        ..BuildOptions::default()
    };
    let many = build(&model, &energy(), &opts).unwrap();
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap()
        .install(|| build(&model, &energy(), &opts).unwrap());
    assert!(many.nodes.len() > 20, "{} nodes", many.nodes.len());
    assert_eq!(many.nodes, one.nodes);
    assert_eq!(many.edges, one.edges);
    assert_eq!(many.build_solves, one.build_solves);
}

/// Each certified edge's bound holds on a fine sweep of independent cold solves along it:
/// along the rotation alone (where the bound is exact), along the insertion alone, and along
/// all inputs at once, each edge passing near the block.
#[test]
fn certified_clearance_holds_along_port_edges() {
    let model = behind_block();
    let space = Space::new(&model, &energy(), false).unwrap();
    let mut ck = Checker::new(&space, 0.001);
    // [A, B, d, ψ]: bent by B round the block's side, turned, inserted.
    let edges: [([f64; 4], [f64; 4]); 3] = [
        ([-0.0039, 0.0079, 0.16, 0.1], [-0.0039, 0.0079, 0.16, 0.7]),
        ([0.0, 0.0, 0.03, 0.0], [0.0, 0.0, 0.095, 0.0]),
        ([-0.001, 0.008, 0.1, 0.6], [-0.0039, 0.0079, 0.16, 0.41]),
    ];
    for (a, b) in edges {
        let na = ck
            .node(&a, None)
            .unwrap_or_else(|| panic!("{a:?} not clear"));
        let nb = ck
            .node(&b, None)
            .unwrap_or_else(|| panic!("{b:?} not clear"));
        if a[..3] == b[..3] {
            // Along the rotation alone the de-rotated shapes coincide (no loads): all of the
            // bound is the exact part, and it covers every disk's actual travel.
            let m = motion(&model.robot, &na.shape, &nb.shape);
            assert!(m.estimated < 1e-9, "{m:?}");
            let travel = na
                .shape
                .disks
                .iter()
                .zip(&nb.shape.disks)
                .map(|(p, q)| (p.position - q.position).norm())
                .fold(0.0, f64::max);
            assert!(
                travel <= m.exact && m.exact < 2.0 * travel,
                "{travel} vs {m:?}"
            );
        }
        let EdgeCheck::Clear { certified, .. } = ck.edge(&na, &nb) else {
            panic!("edge {a:?} – {b:?} blocked");
        };
        let mut worst = f64::INFINITY;
        for j in 0..=200 {
            let f = j as f64 / 200.0;
            let x: Vec<f64> = a.iter().zip(&b).map(|(p, q)| p + f * (q - p)).collect();
            let s = space.solve_as_cli(&model, &x).unwrap();
            worst = worst.min(parry_clearance(&model, &s, &space.scene));
        }
        eprintln!("edge {a:?} – {b:?}: swept {worst:.4e} m, certified {certified:.4e} m");
        assert!(
            worst >= certified - 1e-9 && certified >= 0.001,
            "edge {a:?} – {b:?}: swept {worst:e} m, certified {certified:e} m"
        );
    }
}

proptest! {
    #![proptest_config(crate::common::fixed_seed(ProptestConfig::with_cases(256)))]
    /// The planners' distance over cables, insertion and rotation is a metric: zero on the
    /// diagonal, symmetric, the triangle inequality; and it is reach's effort between points.
    #[test]
    fn the_distance_is_a_metric(
        x in prop::array::uniform4(-0.2f64..0.2),
        y in prop::array::uniform4(-0.2f64..0.2),
        z in prop::array::uniform4(-3.0f64..3.0),
    ) {
        let model = behind_block();
        let space = Space::new(&model, &energy(), false).unwrap();
        let m = Metric::of(&space);
        let (x, y, z) = (x.to_vec(), y.to_vec(), z.to_vec());
        prop_assert_eq!(m.dist(&x, &x), 0.0);
        prop_assert_eq!(m.dist(&x, &y), m.dist(&y, &x));
        prop_assert!(m.dist(&x, &z) <= m.dist(&x, &y) + m.dist(&y, &z) + 1e-15);
        if x != y {
            prop_assert!(m.dist(&x, &y) > 0.0);
        }
        // Its square is the effort of `y` measured from `x`.
        let d: Vec<f64> = y.iter().zip(&x).zip(&space.rest).map(|((a, b), r)| a - b + r).collect();
        let e = space.effort(&d);
        prop_assert!((m.dist(&x, &y).powi(2) - e).abs() <= 1e-12 * e.max(1e-12));
    }
}
