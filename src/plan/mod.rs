//! `plan`: a path of actuations from a start to a goal along which the robot keeps a margin
//! from every obstacle, every edge validated at a resolution that certifies it.
//!
//! * Search: RRT-Connect in the actuation space (`src/plan/rrt.rs`, why there) or, for repeated
//!   queries, a precomputed roadmap ([`roadmap`]).
//! * Validation: [`edge`] — sub-intervals bisected until a bound on how far any feature
//!   moves ([`crate::reach::motion_bound`], inflated by the Lipschitz factor
//!   [`edge::KAPPA`]) fits inside the measured clearances.
//! * Then greedy shortcuts (farthest first, at most [`PlanOptions::shortcuts`] edge checks),
//!   and each remaining edge cut into pieces of at most [`PlanOptions::output_step`] for the
//!   output waypoints: the edge's own bisection samples where the plan validated it, new
//!   solves elsewhere (trusted roadmap edges).
//! * Deterministic: one seeded generator (xorshift, `rand_xorshift`) drives every random
//!   choice; solves are deterministic.
//!
//! The goal is an actuation or a tip position; a tip goes through [`crate::reach::reach`]
//! (keeping the same margin) first. Shapes are solved without obstacles and checked against
//! them (the robot keeps clear, so the obstacle-aware solve is the same shape).
//!
//! # Tension space
//!
//! Planned in the space `reach` searches ([`Space`]): the cables' shortenings \[m\], or, when
//! the request's method is driven by tension (`energy` with `control = force`, `cosserat`),
//! their tensions \[N\] within their tension limits — the same `--method`/`--set` choose it for
//! `reach`, `plan` and `roadmap`. The planners are generic over the space: distances in metres
//! of cable either way ([`metric`], "In tension space"), and the edge check bounds the motion
//! between *solved shapes* \[m\] whatever input moved them ([`edge`], "In tension space").
//! A plan's waypoints, its JSON (`"space": "tension"`, each cable's `tension` \[N\] beside the
//! `shorten` it made), the trajectory CSV (a `<cable>_tension_n` column per cable) and the
//! actuation files it reads (each entry's `tension`) carry tensions; roadmaps record their
//! space ([`roadmap::Roadmap::space`]) and are refused by name in the other.

mod actuation_file;
pub mod edge;
mod insert;
pub mod metric;
pub mod motion;
pub mod roadmap;
mod roadmap_build;
mod roadmap_nodes;
mod roadmap_query;
mod roadmap_sample;
pub mod roadmap_shard;
mod rrt;
mod trajectory;

pub use actuation_file::{
    actuation_of, actuation_of_in, read_actuation, read_actuation_file, read_actuation_in,
    ActuationFile,
};
pub use edge::{Checker, EdgeCheck, Node, Stats};

use crate::error::SolveError;
use crate::fingerprint::MadeFor;
use crate::method::run::SolveRequest;
use crate::model::actuation::Input;
use crate::model::Model;
use crate::reach::{reach_in, CableActuation, ReachOptions, Space, Target};
use crate::shape::ShapeJson;
use nalgebra::Vector3;
use rand_core::SeedableRng;
use rand_xorshift::XorShiftRng;
use roadmap::Roadmap;
use serde::Serialize;
use std::time::Instant;

/// Where to go.
#[derive(Debug, Clone, PartialEq)]
pub enum Goal {
    /// Shortenings \[m\] (tensions \[N\] in tension space), one per cable, then with a port
    /// the insertion \[m\] and the rotation \[rad\].
    Actuation(Vec<f64>),
    /// A tip position \[m\] (reached first by least-effort [`crate::reach::reach`]).
    Tip(Vector3<f64>),
}

/// How to plan.
#[derive(Debug, Clone, PartialEq)]
pub struct PlanOptions {
    /// Seed of every random choice (RRT-Connect's samples; a roadmap query makes none).
    pub seed: u64,
    /// Margin kept from the obstacles \[m\] (default: the scene's `clearance`).
    pub margin: Option<f64>,
    /// Largest step of a tree, as a fraction of the limits box's largest extent along one
    /// unknown, measured in the planners' metric ([`metric`]: with a port, insertion and
    /// rotation in metres of cable).
    pub step: f64,
    /// Samples before giving up.
    pub max_samples: usize,
    /// Shortcut attempts: edge checks of the greedy shortcut stage (`src/plan/rrt.rs`).
    pub shortcuts: usize,
    /// Largest actuation change between output waypoints, in the planners' metric \[m of
    /// cable\] ([`metric`]).
    pub output_step: f64,
}

impl Default for PlanOptions {
    fn default() -> Self {
        PlanOptions {
            seed: 1,
            margin: None,
            step: 0.15,
            max_samples: 5000,
            shortcuts: 60,
            output_step: 1e-3,
        }
    }
}

/// Planner statistics.
#[derive(Debug, Clone, Default, Serialize)]
pub struct PlanStats {
    /// Planner: `rrt-connect` or `roadmap`.
    pub planner: &'static str,
    /// Samples drawn.
    pub samples: usize,
    /// Nodes in the trees (or roadmap nodes used).
    pub tree_nodes: usize,
    /// Waypoints removed by shortcuts.
    pub shortcut_removed: usize,
    /// Path length in actuation space before and after shortcuts, in the planners' metric
    /// \[m of cable\].
    pub length_before_m: f64,
    /// After.
    pub length_after_m: f64,
    /// Checks made.
    pub checks: Stats,
    /// Roadmap edges repaired (re-validated and dropped) in this query.
    pub edges_repaired: usize,
    /// Wall time \[s\].
    pub time_s: f64,
}

/// A planned path.
#[derive(Debug, Clone)]
pub struct Plan {
    /// Waypoints, start to goal.
    pub waypoints: Vec<Node>,
    /// Cable names.
    pub cables: Vec<String>,
    /// What the cables' values of the waypoints are: shortenings \[m\] or tensions \[N\].
    pub input: Input,
    /// Margin kept \[m\].
    pub margin_m: f64,
    /// Smallest clearance measured on any solved shape along the path \[m\].
    pub min_clearance_m: f64,
    /// Certified lower bound over every edge (under the Lipschitz estimate) \[m\].
    pub certified_clearance_m: f64,
    /// Seed used.
    pub seed: u64,
    /// Statistics.
    pub stats: PlanStats,
    /// The robot, obstacles, margin and method it was planned for, checked where a plan file
    /// is read back (`view --plan`).
    pub made_for: MadeFor,
}

/// One waypoint in JSON.
#[derive(Debug, Clone, Serialize)]
pub struct WaypointJson {
    /// Per-cable inputs: shortenings with the tensions they made, or in tension space
    /// tensions with the shortenings they made.
    pub actuation: Vec<CableActuation>,
    /// Insertion \[m\] (robots with a port).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub insertion: Option<f64>,
    /// Rotation \[rad\] (robots with a port).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rotation: Option<f64>,
    /// Tip \[m\].
    pub tip: [f64; 3],
    /// Clearance \[m\] (absent without obstacles).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub clearance_m: Option<f64>,
    /// The shape.
    pub shape: ShapeJson,
}

/// JSON form of a [`Plan`].
#[derive(Debug, Clone, Serialize)]
pub struct PlanJson {
    /// The space planned in: `shortening` (cables' `shorten` \[m\] are the inputs) or
    /// `tension` (their `tension` \[N\]).
    pub space: &'static str,
    /// Waypoints.
    pub waypoints: Vec<WaypointJson>,
    /// See [`Plan::min_clearance_m`] (absent without obstacles).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub min_clearance_m: Option<f64>,
    /// See [`Plan::certified_clearance_m`].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub certified_clearance_m: Option<f64>,
    /// Margin \[m\].
    pub margin_m: f64,
    /// How edges were validated.
    pub validation: &'static str,
    /// Seed.
    pub seed: u64,
    /// Statistics.
    pub statistics: PlanStats,
    /// What it was planned for (robot and obstacle fingerprints, margin, method).
    pub made_for: MadeFor,
}

pub(crate) fn finite(x: f64) -> Option<f64> {
    x.is_finite().then_some(x)
}

impl Plan {
    /// JSON form.
    pub fn to_json(&self) -> PlanJson {
        PlanJson {
            space: self.input.name(),
            waypoints: self
                .waypoints
                .iter()
                .map(|n| {
                    let t = n.shape.tip();
                    let port = (n.u.len() == self.cables.len() + 2)
                        .then(|| (n.u[self.cables.len()], n.u[self.cables.len() + 1]));
                    WaypointJson {
                        actuation: CableActuation::of(&self.cables, self.input, &n.u, &n.shape),
                        insertion: port.map(|p| p.0),
                        rotation: port.map(|p| p.1),
                        tip: [t.x, t.y, t.z],
                        clearance_m: finite(n.clearance),
                        shape: n.shape.to_json(),
                    }
                })
                .collect(),
            min_clearance_m: finite(self.min_clearance_m),
            certified_clearance_m: finite(self.certified_clearance_m),
            margin_m: self.margin_m,
            validation: "bisection until (c0 + c1 - 2 D)/2 >= margin per sub-interval, D the \
                         bound on feature motion between its end shapes (Lipschitz estimate, \
                         factor 2)",
            seed: self.seed,
            statistics: self.stats.clone(),
            made_for: self.made_for.clone(),
        }
    }
}

/// A start or goal, solved and checked (named `field` in errors).
/// The solved, checked start (default: the model's actuation) and goal of a plan: what both
/// planners begin with.
pub(crate) fn endpoints(
    ck: &mut Checker,
    model: &Model,
    start: Option<Vec<f64>>,
    goal: &Goal,
) -> Result<(Node, Node), SolveError> {
    let start = start.unwrap_or_else(|| actuation_of_in(model, &model.actuation, ck.space.input));
    let goal_u = goal_actuation(ck.space, model, goal, ck.margin)?;
    let s = endpoint(ck, &start, "start")?;
    let g = endpoint(ck, &goal_u, "goal")?;
    Ok((s, g))
}

pub(crate) fn endpoint(ck: &mut Checker, u: &[f64], field: &str) -> Result<Node, SolveError> {
    let space = ck.space;
    if let Some(reason) = space.outside(u) {
        return Err(SolveError::InvalidInput {
            field: field.into(),
            reason,
        });
    }
    let shape = space.solve(u, None)?;
    let c = space.clearance(&shape);
    if let Some(c) = c.as_ref().filter(|c| c.distance < ck.margin) {
        return Err(SolveError::InvalidInput {
            field: field.into(),
            reason: format!(
                "{} is {:.3e} m from `{}`, closer than the margin {} m",
                c.feature, c.distance, c.obstacle, ck.margin
            ),
        });
    }
    if let Some(v) = space.tension_violation(&shape) {
        return Err(SolveError::InvalidInput {
            field: field.into(),
            reason: v,
        });
    }
    ck.stats.solves += 1;
    Ok(Node {
        u: u.to_vec(),
        shape,
        clearance: c.map_or(f64::INFINITY, |c| c.distance),
        exact: true,
    })
}

/// The goal's actuation (a tip goes through reach, keeping `margin`).
pub(crate) fn goal_actuation(
    space: &Space,
    model: &Model,
    goal: &Goal,
    margin: f64,
) -> Result<Vec<f64>, SolveError> {
    match goal {
        Goal::Actuation(u) => Ok(u.clone()),
        Goal::Tip(t) => {
            let opts = ReachOptions {
                margin: Some(margin),
                ..ReachOptions::default()
            };
            let r = reach_in(
                space,
                model,
                &Target {
                    tip: *t,
                    tangent: None,
                },
                &opts,
            )?;
            Ok(r.require_reached()?.u)
        }
    }
}

pub(crate) fn check_options(o: &PlanOptions) -> Result<(), SolveError> {
    let bad = |field: &str, reason: String| {
        Err(SolveError::InvalidInput {
            field: field.into(),
            reason,
        })
    };
    if !(o.step.is_finite() && o.step > 0.0 && o.step <= 1.0) {
        return bad("step", format!("must be in (0, 1], got {}", o.step));
    }
    if !(o.output_step.is_finite() && o.output_step > 0.0) {
        return bad("output_step", format!("must be > 0, got {}", o.output_step));
    }
    crate::counts::PLAN_SAMPLES.check(o.max_samples)?;
    crate::counts::PLAN_SHORTCUTS.check(o.shortcuts)?;
    if let Some(m) = o.margin {
        crate::model::bounds::CLEARANCE.check("margin", m)?;
    }
    Ok(())
}

/// Plan from `start` (default: the model's actuation) to `goal` for `model` solved by
/// `request` (obstacles: the model's and the request's): on `roadmap` when one is given
/// ([`Roadmap`]: its graph searched, repaired where the scene changed), else by RRT-Connect.
/// Both planners share everything up to the solved, admissible end points: the options
/// checked (a bad margin or step is refused by name whichever planner is asked), the clock,
/// the space, the margin (the options', else the space's), the checker.
pub fn plan(
    model: &Model,
    request: &SolveRequest,
    start: Option<Vec<f64>>,
    goal: &Goal,
    opts: &PlanOptions,
    roadmap: Option<&Roadmap>,
) -> Result<Plan, SolveError> {
    check_options(opts)?;
    let t0 = Instant::now();
    let space = Space::new(model, request, false)?;
    if let Some(rm) = roadmap {
        return rm
            .queries(model, request, &space, opts.margin)?
            .plan(start, goal, opts);
    }
    let margin = opts.margin.unwrap_or(space.margin);
    let mut ck = Checker::new(&space, margin).keep_samples();
    let (s, g) = endpoints(&mut ck, model, start, goal)?;
    let mut rng = XorShiftRng::seed_from_u64(opts.seed);
    let range = ck.metric.largest_range(&space.lo, &space.hi);
    let found = rrt::rrt_connect(&mut ck, s, g, opts.step * range, opts.max_samples, &mut rng)
        .map_err(|samples| SolveError::NoPath {
            samples,
            reason: format!(
                "RRT-Connect found no clear path keeping {margin} m from the obstacles"
            ),
        })?;
    let stats = PlanStats {
        planner: "rrt-connect",
        samples: found.samples,
        tree_nodes: found.tree_nodes,
        ..PlanStats::default()
    };
    finish(&mut ck, found.path, opts, stats, t0)
}

/// The solved points strictly between `from` (the last of `out`) and `to`, every
/// `1/ceil(|to − from| / step)` of the way, each warm-started from the one before.
fn fill(
    ck: &mut Checker,
    out: &mut Vec<Node>,
    from: &[f64],
    to: &[f64],
    step: f64,
    samples: usize,
) -> Result<(), SolveError> {
    let pieces = (ck.dist(from, to) / step).ceil().max(1.0) as usize;
    for k in 1..pieces {
        let f = k as f64 / pieces as f64;
        let u: Vec<f64> = from.iter().zip(to).map(|(a, b)| a + f * (b - a)).collect();
        let prev = out[out.len() - 1].shape.clone();
        let Some(n) = ck.node(&u, Some(&prev)) else {
            let why = ck.why_not(&u, Some(&prev)).unwrap_or_default();
            return Err(SolveError::NoPath {
                samples,
                reason: format!("the point {u:?} of a validated edge is not admissible: {why}"),
            });
        };
        out.push(n);
    }
    Ok(())
}

/// Shortcut, cut into output waypoints, measure; shared by both planners.
pub(crate) fn finish(
    ck: &mut Checker,
    mut path: Vec<Node>,
    opts: &PlanOptions,
    mut stats: PlanStats,
    t0: Instant,
) -> Result<Plan, SolveError> {
    let metric = ck.metric.clone();
    let length = |p: &[Node]| p.windows(2).map(|w| metric.dist(&w[0].u, &w[1].u)).sum();
    stats.length_before_m = length(&path);
    stats.shortcut_removed = rrt::shortcut(ck, &mut path, opts.shortcuts);
    stats.length_after_m = length(&path);
    // Every remaining edge is validated again (a shortcut's edge was; the tree's were) to
    // collect the certified bound, then cut for output.
    let mut certified = f64::INFINITY;
    let mut measured = f64::INFINITY;
    let mut out: Vec<Node> = vec![path[0].clone()];
    for w in path.windows(2) {
        match ck.edge(&w[0], &w[1]) {
            EdgeCheck::Clear {
                certified: c,
                measured: m,
                ..
            } => {
                certified = certified.min(c);
                measured = measured.min(m);
            }
            EdgeCheck::Blocked => {
                return Err(SolveError::NoPath {
                    samples: stats.samples,
                    reason: "an edge of the path failed its final validation".into(),
                })
            }
        }
        // Waypoints every ≤ output_step: the edge's own bisection samples where it has them
        // (real solves, kept by the checker), new solves only across gaps wider than that.
        let mut stops: Vec<Node> = ck
            .samples_along(&w[0].u, &w[1].u)
            .into_iter()
            .map(|(_, n)| n.clone())
            .collect();
        stops.push(w[1].clone());
        let mut next = 0;
        while next < stops.len() {
            let from = out[out.len() - 1].u.clone();
            let within = stops[next..]
                .iter()
                .take_while(|n| ck.dist(&from, &n.u) <= opts.output_step)
                .count();
            if within == 0 {
                let to = &stops[next].u;
                fill(ck, &mut out, &from, to, opts.output_step, stats.samples)?;
                out.push(stops[next].clone());
                next += 1;
            } else {
                next += within;
                out.push(stops[next - 1].clone());
            }
        }
    }
    // Waypoints taken from an edge's samples may hold a lower bound only: measured now.
    for n in &mut out {
        ck.measure(n);
        measured = measured.min(n.clearance);
    }
    stats.checks = ck.stats.clone();
    stats.time_s = t0.elapsed().as_secs_f64();
    Ok(Plan {
        waypoints: out,
        cables: ck.space.cable_names(),
        input: ck.space.input,
        margin_m: ck.margin,
        min_clearance_m: measured,
        certified_clearance_m: certified,
        seed: opts.seed,
        stats,
        made_for: MadeFor {
            margin_m: ck.margin,
            ..MadeFor::of_space(ck.space)
        },
    })
}
