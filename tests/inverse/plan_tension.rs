//! `plan` and roadmaps in tension space: the soft lung rod (three tendons inside a 6 mm
//! silicone rod, 0…3.5 N, through a port) planned around a nodule by tension, with and without
//! its port; every planned path re-checked 8× finer by independent cold solves against the
//! nodule in closed form (sphere to the backbone's capsules); the premise of the edge check
//! measured on tension edges; seeded start/goal pairs; the files: tensions under `tension`,
//! the trajectory's tension columns, a roadmap of one space refused by name in the other, an
//! actuation file read back by cable name and checked against the tension limits.

#[path = "../../examples/common/plan_tension_measure.rs"]
mod plan_tension_measure;

use ccrkit::actuation::Input;
use ccrkit::method::run::SolveRequest;
use ccrkit::method::MethodKind;
use ccrkit::plan::edge::KAPPA;
use ccrkit::plan::metric::Metric;
use ccrkit::plan::motion::motion;
use ccrkit::plan::roadmap::{build, BuildOptions};
use ccrkit::plan::{plan, read_actuation_in, Checker, EdgeCheck, Goal, Plan, PlanOptions};
use ccrkit::reach::{motion_bound, Space};
use ccrkit::{Model, Shape, SolveError};
use ccrkit_test_support::rng::Rng;
use nalgebra::Vector3;
use plan_tension_measure::{by_tension, lung_nodule, pair};

const NODULE: ([f64; 3], f64) = ([0.03, 0.0, 0.10], 0.008);

/// The lung rod without its port (the base bolted at the origin), beside the nodule.
fn no_port() -> Model {
    let mut m = lung_nodule();
    m.robot.port = None;
    m.actuation.insertion = None;
    m.actuation.rotation = None;
    m.limits.insertion = None;
    m.limits.rotation = None;
    m
}

/// The nodule's distance from the backbone's capsules (radius 3 mm), in closed form: the
/// sphere's centre to each segment, less both radii. Every segment counts, the part behind the
/// port too (it lies on the port axis at z ≤ 0, farther from the nodule than any point beyond).
fn nodule_clearance(shape: &Shape) -> f64 {
    let c = Vector3::from(NODULE.0);
    shape
        .backbone
        .windows(2)
        .map(|w| {
            let (a, b) = (w[0], w[1]);
            let ab = b - a;
            let t = if ab.norm_squared() > 0.0 {
                ((c - a).dot(&ab) / ab.norm_squared()).clamp(0.0, 1.0)
            } else {
                0.0
            };
            (a + t * ab - c).norm() - NODULE.1 - 0.003
        })
        .fold(f64::INFINITY, f64::min)
}

/// Every output edge of `p` re-solved cold (as `ccrkit solve` does) at 8 interpolations and
/// measured in closed form: at least the margin everywhere; returns the smallest clearance.
fn dense_recheck(model: &Model, space: &Space, p: &Plan) -> f64 {
    let mut worst = f64::INFINITY;
    for w in p.waypoints.windows(2) {
        for k in 0..8 {
            let f = k as f64 / 8.0;
            let u: Vec<f64> = w[0]
                .u
                .iter()
                .zip(&w[1].u)
                .map(|(a, b)| a + f * (b - a))
                .collect();
            let s = space
                .solve_as_cli(model, &u)
                .expect("a point of a planned edge solves");
            worst = worst.min(nodule_clearance(&s));
        }
    }
    let last = &p.waypoints[p.waypoints.len() - 1];
    worst = worst.min(nodule_clearance(&last.shape));
    assert!(
        worst >= p.margin_m - 1e-9,
        "dense re-check: clearance {worst:.4e} m below the margin {} m",
        p.margin_m
    );
    worst
}

fn tensions(t: f64, model: &Model) -> Vec<f64> {
    let mut u = vec![t; 3];
    if model.robot.port.is_some() {
        u.extend([model.robot.length(), 0.0]);
    }
    u
}

/// Through the port: from the straight rod to 1 N on every tendon, whose straight edge sweeps
/// the rod through the nodule. The plan goes round (retracting), every waypoint is within the
/// tension limits and a cold solve of its tensions, the path passes the dense re-check, and
/// the files carry tensions: the JSON's `space` and each cable's `tension` (beside the
/// shortening it made), the trajectory's `<cable>_tension_n` columns.
#[test]
fn plans_around_a_nodule_through_the_port() {
    let model = lung_nodule();
    let space = Space::new(&model, &by_tension(), false).unwrap();
    assert!(space.by_tension());
    let (s, g) = (tensions(0.0, &model), tensions(1.0, &model));
    let mut ck = Checker::new(&space, space.margin);
    let (ns, ng) = (ck.node(&s, None).unwrap(), ck.node(&g, None).unwrap());
    assert_eq!(
        ck.edge(&ns, &ng),
        EdgeCheck::Blocked,
        "the straight edge hits the nodule"
    );
    let p = plan(
        &model,
        &by_tension(),
        None,
        &Goal::Actuation(g.clone()),
        &PlanOptions::default(),
        None,
    )
    .unwrap();
    assert_eq!(p.input, Input::Tension);
    assert_eq!(p.waypoints[0].u, s);
    assert_eq!(p.waypoints.last().unwrap().u, g);
    for n in &p.waypoints {
        assert!(space.contains(&n.u), "{:?}", n.u);
        let cold = space.solve_as_cli(&model, &n.u).unwrap();
        assert!((cold.tip() - n.shape.tip()).norm() <= 1e-9);
    }
    let worst = dense_recheck(&model, &space, &p);
    assert!(
        p.certified_clearance_m <= worst + 1e-12,
        "{} > {worst}",
        p.certified_clearance_m
    );
    let j = serde_json::to_value(p.to_json()).unwrap();
    assert_eq!(j["space"], "tension");
    for (w, n) in j["waypoints"].as_array().unwrap().iter().zip(&p.waypoints) {
        for (c, a) in w["actuation"].as_array().unwrap().iter().enumerate() {
            assert_eq!(a["tension"].as_f64(), Some(n.u[c]));
            let made = n.shape.cables[c].shortening.unwrap();
            assert_eq!(a["shorten"].as_f64(), Some(made));
        }
    }
    let csv = p.trajectory_csv(&model).unwrap();
    let mut lines = csv.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let k = head.len() - 3;
    assert_eq!(
        head[k..],
        [
            "straight_tension_n",
            "helix_plus_tension_n",
            "helix_minus_tension_n"
        ]
    );
    for (line, n) in lines.zip(&p.waypoints) {
        let v: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
        assert_eq!(v[k..], n.u[..3]);
    }
}

/// Without the port the tensions alone must go round: RRT-Connect draws samples, and the path
/// passes the dense re-check.
#[test]
fn plans_around_a_nodule_by_tension_alone() {
    let model = no_port();
    let space = Space::new(&model, &by_tension(), false).unwrap();
    assert_eq!(space.dim(), 3);
    let g = tensions(1.0, &model);
    let p = plan(
        &model,
        &by_tension(),
        None,
        &Goal::Actuation(g),
        &PlanOptions::default(),
        None,
    )
    .unwrap();
    assert!(
        p.stats.samples > 0 && p.stats.checks.edges_rejected > 0,
        "{:?}",
        p.stats
    );
    dense_recheck(&model, &space, &p);
}

/// The edge that once certified too much: from the straight rod out to 1 N with the rod drawn
/// wholly into the port (nothing beyond it: clearance `+∞`). Independent cold solves along it
/// (201) stay at least the certified clearance away; the certificate comes from the deeper end.
#[test]
fn an_edge_out_of_the_port_is_certified_by_its_deeper_end() {
    let model = lung_nodule();
    let space = Space::new(&model, &by_tension(), false).unwrap();
    let a = tensions(0.0, &model);
    let mut b = tensions(1.0, &model);
    b[3] = 0.0;
    let mut ck = Checker::new(&space, space.margin);
    let (na, nb) = (ck.node(&a, None).unwrap(), ck.node(&b, None).unwrap());
    assert_eq!(nb.clearance, f64::INFINITY, "nothing beyond the port");
    let EdgeCheck::Clear { certified, .. } = ck.edge(&na, &nb) else {
        panic!("the edge is clear")
    };
    let mut worst = f64::INFINITY;
    for j in 0..=200 {
        let f = j as f64 / 200.0;
        let x: Vec<f64> = a.iter().zip(&b).map(|(p, q)| p + f * (q - p)).collect();
        worst = worst.min(nodule_clearance(&space.solve_as_cli(&model, &x).unwrap()));
    }
    assert!(
        worst >= certified - 1e-9,
        "swept {worst:e} m, certified {certified:e} m"
    );
}

/// The premise of the edge check in tension space, measured: on clear edges between seeded
/// admissible tensions, every certified sub-interval (between the bisection's samples) is
/// swept by 16 cold solves, and the features' detour through each, `D(a, t) + D(t, b)`, stays
/// within `κ D(a, b)`; the swept clearance stays above the sub-interval's certificate.
#[test]
fn the_premise_holds_along_tension_edges() {
    let model = no_port();
    let space = Space::new(&model, &by_tension(), false).unwrap();
    let mut ck = Checker::new(&space, space.margin).keep_samples();
    let mut rng = Rng(7);
    let (mut edges, mut pieces, mut worst_ratio) = (0, 0, 0.0_f64);
    for _ in 0..40 {
        if edges == 3 {
            break;
        }
        let Some((a, b)) = pair(&space, &mut rng, 50) else {
            continue;
        };
        let (na, nb) = (ck.node(&a, None).unwrap(), ck.node(&b, None).unwrap());
        if !matches!(ck.edge(&na, &nb), EdgeCheck::Clear { pieces: 2.., .. }) {
            continue;
        }
        edges += 1;
        let mut stops = vec![na.clone()];
        stops.extend(ck.samples_along(&a, &b).into_iter().map(|(_, n)| n.clone()));
        stops.push(nb.clone());
        for w in stops.windows(2) {
            let (p, q) = (&w[0], &w[1]);
            let m = motion(&space.robot, &p.shape, &q.shape);
            let certified = m.certified(p.clearance, q.clearance, KAPPA);
            if certified < space.margin {
                continue; // bisected further: not a certified sub-interval
            }
            pieces += 1;
            let d = motion_bound(&space.robot, &p.shape, &q.shape);
            for j in 1..16 {
                let f = j as f64 / 16.0;
                let x: Vec<f64> = p.u.iter().zip(&q.u).map(|(s, t)| s + f * (t - s)).collect();
                let mid = space.solve_as_cli(&model, &x).unwrap();
                let detour = motion_bound(&space.robot, &p.shape, &mid)
                    + motion_bound(&space.robot, &mid, &q.shape);
                worst_ratio = worst_ratio.max(detour / d.max(1e-15));
                let c = space.clearance(&mid).unwrap().distance;
                assert!(
                    c >= certified - 1e-9,
                    "swept {c:e} m, certified {certified:e} m"
                );
            }
        }
    }
    assert!(
        edges == 3 && pieces >= 3,
        "{edges} edges, {pieces} sub-intervals"
    );
    eprintln!("largest detour over D: {worst_ratio:.4} ({pieces} sub-intervals)");
    assert!(worst_ratio <= KAPPA, "a feature detoured {worst_ratio} D");
}

/// Seeded start/goal pairs through the port (the measurement of `examples/plan_tension.rs` on
/// its first pairs): at least 5 of 6 planned, and every plan passes the dense re-check.
#[test]
fn seeded_pairs_plan_and_pass_a_dense_recheck() {
    let model = lung_nodule();
    let space = Space::new(&model, &by_tension(), false).unwrap();
    let out = plan_tension_measure::measure(6, 1);
    let ok: Vec<&Plan> = out.iter().filter_map(|o| o.plan.as_ref().ok()).collect();
    let slowest = out.iter().map(|o| o.seconds).fold(0.0, f64::max);
    eprintln!("{} of 6 planned, slowest {:.1} ms", ok.len(), slowest * 1e3);
    assert!(ok.len() >= 5, "{} of 6 planned", ok.len());
    for p in ok {
        dense_recheck(&model, &space, p);
    }
}

/// The planners' distance in tension space is in metres of cable: a tension's scale is
/// `0.1 L / T̄` (0.012 m / 3.5 N on the lung rod), and its square times `(T̄ / 0.1 L)²` is
/// reach's effort \[N²\] of the move.
#[test]
fn the_tension_metric_is_the_effort_in_metres_of_cable() {
    let model = lung_nodule();
    let space = Space::new(&model, &by_tension(), false).unwrap();
    let m = Metric::of(&space);
    let rate = 3.5 / (0.1 * model.robot.length());
    assert!((space.per_metre() - rate).abs() < 1e-9 * rate);
    assert!((m.weights()[0] - 1.0 / rate).abs() < 1e-15);
    let (x, y) = ([0.2, 1.0, 3.0, 0.05, -0.4], [1.5, 0.3, 2.0, 0.09, 0.7]);
    let d: Vec<f64> = y
        .iter()
        .zip(&x)
        .zip(&space.rest)
        .map(|((a, b), r)| a - b + r)
        .collect();
    let e = space.effort(&d);
    assert!((m.dist(&x, &y).powi(2) * rate * rate - e).abs() <= 1e-12 * e);
}

/// A roadmap records its space: built by tension it answers a tension query and is refused by
/// name (`roadmap.space`) for shortenings; one built by shortening is refused for tensions.
#[test]
fn a_roadmap_of_one_space_is_refused_in_the_other() {
    let model = lung_nodule();
    let energy = SolveRequest::new(MethodKind::Energy);
    let opts = BuildOptions {
        samples: 40,
        expand: 40,
        ..BuildOptions::default()
    };
    let rm = build(&model, &by_tension(), &opts).unwrap();
    assert_eq!(rm.space, "tension");
    let goal = Goal::Actuation(tensions(1.0, &model));
    let p = plan(
        &model,
        &by_tension(),
        None,
        &goal,
        &PlanOptions::default(),
        Some(&rm),
    )
    .unwrap();
    assert_eq!(p.stats.planner, "roadmap");
    let refused = |r: Result<Plan, SolveError>| match r {
        Err(SolveError::InvalidInput { field, reason }) => {
            assert_eq!(field, "roadmap.space", "{reason}");
            reason
        }
        other => panic!("expected a refusal, got {:?}", other.map(|p| p.stats)),
    };
    let shortening_goal = Goal::Actuation(vec![0.0, 0.0, 0.0, model.robot.length(), 0.0]);
    let why = refused(plan(
        &model,
        &energy,
        None,
        &shortening_goal,
        &PlanOptions::default(),
        Some(&rm),
    ));
    assert!(why.contains("built in tension space"), "{why}");
    let small = BuildOptions {
        samples: 5,
        expand: 0,
        ..BuildOptions::default()
    };
    let rm_s = build(&model, &energy, &small).unwrap();
    assert_eq!(rm_s.space, "shortening");
    refused(plan(
        &model,
        &by_tension(),
        None,
        &goal,
        &PlanOptions::default(),
        Some(&rm_s),
    ));
    // The space's fingerprint: the same space gives the same, the other another.
    assert_ne!(rm.space_fingerprint, rm_s.space_fingerprint);
}

/// An actuation file read in tension space: each cable's `tension` by name; a missing one
/// named; a file written in the other space refused by name; a tension beyond its limit
/// refused at the goal, naming the cable, the value and the limits.
#[test]
fn actuation_files_carry_tensions_by_cable_name() {
    let model = lung_nodule();
    let dir = std::env::temp_dir().join(format!("ccrkit_plan_tension_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = |name: &str, text: &str| {
        let p = dir.join(name);
        std::fs::write(&p, text).unwrap();
        p
    };
    let entries = |t: [f64; 3]| {
        format!(
            "[{{\"cable\": \"helix_minus\", \"tension\": {}}}, {{\"cable\": \"straight\", \"tension\": {}}}, {{\"cable\": \"helix_plus\", \"tension\": {}}}]",
            t[2], t[0], t[1]
        )
    };
    let ok = file(
        "ok.json",
        &format!("{{\"actuation\": {}}}", entries([0.5, 1.0, 1.5])),
    );
    let u = read_actuation_in(&ok, &model, Input::Tension).unwrap();
    assert_eq!(u, vec![0.5, 1.0, 1.5, model.robot.length(), 0.0]);
    let missing = file(
        "missing.json",
        "{\"actuation\": [{\"cable\": \"straight\", \"shorten\": 0.001}]}",
    );
    let e = read_actuation_in(&missing, &model, Input::Tension)
        .unwrap_err()
        .to_string();
    assert!(e.contains("actuation[straight].tension"), "{e}");
    let other = file(
        "other.json",
        &format!(
            "{{\"space\": \"shortening\", \"actuation\": {}}}",
            entries([0.5, 1.0, 1.5])
        ),
    );
    let e = read_actuation_in(&other, &model, Input::Tension)
        .unwrap_err()
        .to_string();
    assert!(e.contains("space") && e.contains("shortening space"), "{e}");
    let high = file(
        "high.json",
        &format!("{{\"actuation\": {}}}", entries([0.5, 4.0, 1.5])),
    );
    let g = read_actuation_in(&high, &model, Input::Tension).unwrap();
    let r = plan(
        &model,
        &by_tension(),
        None,
        &Goal::Actuation(g),
        &PlanOptions::default(),
        None,
    );
    match r {
        Err(SolveError::InvalidInput { field, reason }) => {
            assert_eq!(field, "goal");
            assert!(
                reason.contains("cable `helix_plus` tension 4 N") && reason.contains("[0, 3.5] N"),
                "{reason}"
            );
        }
        other => panic!(
            "expected the goal refused, got {:?}",
            other.map(|p| p.stats)
        ),
    }
}
