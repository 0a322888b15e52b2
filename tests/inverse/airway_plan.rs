//! Planning in a generated airway, on a small count (`examples/common/airway_tasks.rs`; more
//! airways and targets: `cargo run --release --example airway_benchmark`): the 3 mm
//! two-segment catheter through a port in the lower trachea, targets beyond the trachea
//! labelled reachable by a clear forward solve; each reached (forward-checked to 1e-6 m) and
//! its actuation planned to cold from the retracted catheter; every answer and waypoint
//! checked by the independent dense check against the exact triangles.

#[path = "../../examples/common/airway_tasks.rs"]
pub(crate) mod airway_tasks;

use airway_tasks::{measure, GENERATIONS};

/// In the airway of seed 31 (not tuned on), 3 reachable targets: every one reached and
/// planned to (measured: 3 of 3 each), every answer and waypoint inside the lumen by the
/// dense check, failures named.
#[test]
fn a_catheter_reaches_and_plans_in_a_generated_airway() {
    let dir = std::env::temp_dir().join(format!("ccrkit-airway-plan-{}", std::process::id()));
    let out = measure(31, GENERATIONS, 3, 1, &dir).expect("the airway and the catheter load");
    std::fs::remove_dir_all(&dir).ok();
    assert_eq!(out.len(), 3, "3 reachable targets drawn");
    for o in &out {
        assert!(o.generation >= 1);
        if o.reached {
            assert!(o.reach_dense >= 0.0);
        }
        if o.planned {
            assert!(o.plan_dense >= 0.0 && o.waypoints >= 2);
        }
        if !(o.reached && o.planned) {
            assert!(!o.reason.is_empty(), "a failure names its reason");
        }
    }
    let reached = out.iter().filter(|o| o.reached).count();
    let planned = out.iter().filter(|o| o.planned).count();
    assert!(reached >= 3, "reached {reached} of 3: {out:?}");
    assert!(planned >= 3, "planned {planned} of 3: {out:?}");
}

/// The out-first staged path (`src/plan/insert.rs`): seed 11's first target bends the
/// catheter's proximal segment, whose cables are tied in the port at the retracted insertion
/// (they reach the port at 40 mm: 120 mm of catheter, tied at 80 mm). RRT-Connect missed it in
/// 5 000 samples before; the staged path finds it before any random sample, pulls no
/// proximal cable while it is tied, ends on the goal, and every waypoint is inside the lumen
/// by the dense check.
#[test]
fn a_goal_bending_the_tied_segment_is_planned_by_inserting_first() {
    use airway_tasks::{dense_clearance, Setup};
    use ccrkit::plan::{plan, Goal, PlanOptions};
    let dir = std::env::temp_dir().join(format!("ccrkit-airway-out-{}", std::process::id()));
    let setup = Setup::new(11, GENERATIONS, &dir).expect("the airway and the catheter load");
    let space = setup.space().expect("the space");
    let task = setup.tasks(&space, 11, 1, 1, 200).remove(0);
    std::fs::remove_dir_all(&dir).ok();
    let k = space.cables();
    let robot = &setup.model.robot;
    let out = |c: usize| robot.length() - robot.disk_s[robot.cables[c].ends_at];
    let proximal: Vec<usize> = (0..k).filter(|&c| out(c) > 0.0).collect();
    assert_eq!(proximal.len(), 3);
    let retracted = setup.retracted(&space);
    assert!(
        proximal.iter().any(|&c| task.u[c] > 0.0)
            && proximal.iter().all(|&c| out(c) > retracted[k]),
        "the goal pulls a cable tied at the retracted insertion: {:?}",
        task.u
    );
    let opts = PlanOptions {
        max_samples: 1,
        ..PlanOptions::default()
    };
    let p = plan(
        &setup.model,
        &setup.request,
        Some(retracted),
        &Goal::Actuation(task.u.clone()),
        &opts,
        None,
    )
    .expect("planned by a staged path");
    assert_eq!(p.stats.samples, 0, "no random sample drawn");
    let last = &p.waypoints[p.waypoints.len() - 1];
    assert!(last
        .u
        .iter()
        .zip(&task.u)
        .all(|(a, b)| (a - b).abs() < 1e-12));
    for w in &p.waypoints {
        for &c in &proximal {
            assert!(
                w.u[k] > out(c) || w.u[c] <= 0.0,
                "cable {c} pulled while tied: {:?}",
                w.u
            );
        }
        let dense = dense_clearance(&setup, &w.shape);
        assert!(
            dense >= 0.0,
            "a waypoint {dense} m from the wall: {:?}",
            w.u
        );
    }
}

/// The grids' certified clearance bounds (`reach::clearance_bounds`, no triangle queried)
/// contain the exact clearance on the triangles (`reach::clearance`) for the shapes of seeded
/// in-limit actuations in seed 31's airway — clear, near the wall and across it — and where
/// they decide a margin test they decide it as the exact clearance does.
#[test]
fn grid_bounds_contain_the_exact_clearance_in_an_airway() {
    use airway_tasks::Setup;
    let dir = std::env::temp_dir().join(format!("ccrkit-airway-bounds-{}", std::process::id()));
    let setup = Setup::new(31, GENERATIONS, &dir).expect("the airway and the catheter load");
    let space = setup.space().expect("the space");
    std::fs::remove_dir_all(&dir).ok();
    let mut rng = ccrkit_test_support::rng::Rng(0x5EED_0B0D);
    // Draws (most cross the wall) and clear targets' actuations (`Setup::tasks`).
    let mut inputs: Vec<Vec<f64>> = (0..60).map(|_| setup.draw(&space, &mut rng)).collect();
    inputs.extend(setup.tasks(&space, 7, 12, 0, 2400).into_iter().map(|t| t.u));
    let (mut shapes, mut decided, mut across) = (0, 0, 0);
    for u in inputs {
        let Ok(shape) = space.solve(&u, None) else {
            continue;
        };
        let b = space.clearance_bounds(&shape).expect("an obstacle");
        let exact = space.clearance(&shape).expect("an obstacle").distance;
        assert!(
            b.lower <= exact + 1e-12 && exact <= b.upper + 1e-12,
            "{} ≤ {exact} ≤ {}",
            b.lower,
            b.upper
        );
        for margin in [space.margin, 1e-3, 3e-3] {
            if let Some(keeps) = b.keeps(margin) {
                assert_eq!(keeps, exact >= margin, "margin {margin}: exact {exact}");
                decided += 1;
            }
        }
        shapes += 1;
        across += usize::from(exact < 0.0);
    }
    // Measured when written: 56 shapes, 43 across the wall, 147 of 168 margin tests decided.
    println!(
        "{shapes} shapes, {across} across the wall, {decided} of {} decided",
        3 * shapes
    );
    assert!(
        shapes - across >= 10 && across >= 20,
        "{shapes} shapes, {across} across"
    );
    assert!(
        decided * 10 >= 8 * 3 * shapes,
        "{decided} of {}",
        3 * shapes
    );
}

/// An edge's bisection samples measured only as far as their sub-intervals' certificates need
/// (`src/plan/edge.rs`, "Measured as far as needed") make the cuts exact clearances make, in
/// seed 11's airway: on the staged legs to its first targets, every sample's clearance is at
/// most its exact clearance (equal where it says exact); with exact clearances every final
/// sub-interval is certified and every sub-interval that was cut is not — and some samples
/// were not measured to the end (measured: 6 clear edges, 50 samples, 26 of them).
#[test]
fn edge_samples_measured_as_far_as_needed_cut_as_exact_clearances_do() {
    use airway_tasks::Setup;
    use ccrkit::plan::motion::motion;
    use ccrkit::plan::{edge::KAPPA, Checker, EdgeCheck, Node};
    let dir = std::env::temp_dir().join(format!("ccrkit-airway-legs-{}", std::process::id()));
    let setup = Setup::new(11, GENERATIONS, &dir).expect("the airway and the catheter load");
    let space = setup.space().expect("the space");
    let tasks = setup.tasks(&space, 11, 3, 1, 600);
    std::fs::remove_dir_all(&dir).ok();
    let k = space.cables();
    let margin = space.margin;
    let mut ck = Checker::new(&space, margin).keep_samples();
    let s = ck.node(&setup.retracted(&space), None).expect("the start");
    let exact = |n: &Node| space.clearance(&n.shape).expect("an obstacle").distance;
    let certified = |a: (&Node, f64), b: (&Node, f64)| {
        motion(&space.robot, &a.0.shape, &b.0.shape).certified(a.1, b.1, KAPPA)
    };
    let (mut clear, mut samples, mut bounded) = (0, 0, 0);
    for task in &tasks {
        let g = ck.node(&task.u, None).expect("the goal");
        // Straight in halfway to the goal's depth; the goal backed out by 5 mm, or turned.
        let moved = |from: &Node, i: usize, to: f64| {
            let mut u = from.u.clone();
            u[i] = to;
            u
        };
        let ends = [
            (s.clone(), moved(&s, k, 0.5 * (s.u[k] + g.u[k]))),
            (g.clone(), moved(&g, k, g.u[k] - 5e-3)),
            (g.clone(), moved(&g, k + 1, g.u[k + 1] + 0.3)),
        ];
        for (a, u) in &ends {
            let Some(b) = ck.node(u, Some(&a.shape)) else {
                continue;
            };
            let (a, b) = (a, &b);
            if !matches!(ck.edge(a, b), EdgeCheck::Clear { .. }) {
                continue;
            }
            clear += 1;
            let mut along: Vec<(f64, Node, f64)> = vec![(0.0, a.clone(), exact(a))];
            for (t, n) in ck.samples_along(&a.u, &b.u) {
                let e = exact(n);
                assert!(n.clearance <= e + 1e-12, "{} > exact {e}", n.clearance);
                if n.exact {
                    assert_eq!(n.clearance.to_bits(), e.to_bits());
                } else {
                    bounded += 1;
                }
                assert!(n.clearance >= margin);
                along.push((t, n.clone(), e));
            }
            along.push((1.0, b.clone(), exact(b)));
            samples += along.len() - 2;
            for w in along.windows(2) {
                let c = certified((&w[0].1, w[0].2), (&w[1].1, w[1].2));
                assert!(c >= margin, "a final sub-interval certified {c} < {margin}");
            }
            // Each sample cut the sub-interval of dyadic half-width 2^-j about it.
            let at = |t: f64| along.iter().find(|x| x.0 == t).expect("an end of a cut");
            for x in &along[1..along.len() - 1] {
                let j = (1..60)
                    .find(|&j| (x.0 * f64::powi(2.0, j)).fract() == 0.0)
                    .expect("dyadic");
                let h = f64::powi(2.0, -j);
                let (lo, hi) = (at(x.0 - h), at(x.0 + h));
                let c = certified((&lo.1, lo.2), (&hi.1, hi.2));
                assert!(c < margin, "cut a sub-interval certified {c} ≥ {margin}");
            }
        }
    }
    println!("{clear} clear edges, {samples} samples, {bounded} not measured to the end");
    assert!(
        clear >= 4 && bounded >= 10,
        "{clear} clear, {bounded} bounded"
    );
}
