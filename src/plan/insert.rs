//! Planning that knows the insertion: targets deep in anatomy are reached by inserting first
//! and bending late, or by bending first and inserting along the bent shape; a robot in a
//! narrow lumen moves along its insertion far more freely than across it.
//!
//! * **Staged connections** ([`staged`]): after the straight start–goal edge and before any
//!   random sample, both planners try the few paths a clinician would: move the base (insert
//!   and turn) with the cables held, then bend; relax the cables, move the base, bend; bend
//!   first, then move the base; retract to the shallowest insertion, bend and turn there,
//!   insert. Each leg is an ordinary validated edge ([`super::edge`]); the first path whose
//!   legs are all clear is taken (then shortened as any path is).
//! * **Out first** ([`out_first`]): a goal that pulls a cable tied in the port at the start's
//!   insertion (the proximal segment of a catheter barely out) cannot be bent there, and
//!   inserting straight to the goal's depth runs into the first bifurcation. So: insert,
//!   with the segments already out steered, until the last cable the goal pulls reaches the
//!   port; then insert on to the goal while the freed cables are pulled in proportion (each
//!   freed segment bends at its goal curvature as it comes out). Tried after the paths above,
//!   the steerings ranked by the robot's clearance where the cables come out. Measured in the
//!   generated airway (`tests/inverse/airway_plan.rs`): seed 11's first target, which
//!   RRT-Connect missed in 5 000 samples (12.6 s of CPU), planned before any sample.
//! * **Samples along the insertion** ([`along_insertion`]): a share of the random samples
//!   keeps an existing node's cables and rotation and draws only a new insertion, so trees and
//!   roadmaps grow along `d`: such neighbours are close in the metric (a metre of insertion
//!   counts a tenth of a metre of cable) and are joined first.
//!
//! Without a port none of this applies and the planners are unchanged.

use super::edge::{Checker, Node};
use super::rrt::unit;
use crate::reach::Space;
use rand_xorshift::XorShiftRng;

/// One in this many random samples is drawn along the insertion (with a port).
pub(crate) const ALONG_EVERY: usize = 3;

/// The staged paths from `s` to `g` (module docs), the legs' way-points strictly between.
fn candidates(space: &Space, s: &[f64], g: &[f64]) -> Vec<Vec<Vec<f64>>> {
    let k = space.cables();
    let mix = |cables: &[f64], base: &[f64]| -> Vec<f64> {
        let mut x = cables[..k].to_vec();
        x.extend_from_slice(&base[k..]);
        space.clamp(&x)
    };
    let relaxed = |base: &[f64]| -> Vec<f64> {
        let mut x = vec![0.0; k];
        x.extend_from_slice(&base[k..]);
        space.clamp(&x)
    };
    let mut shallow_s = s.to_vec();
    shallow_s[k] = space.lo[k];
    let mut shallow_g = g.to_vec();
    shallow_g[k] = space.lo[k];
    vec![
        vec![mix(s, g)],
        vec![relaxed(s), relaxed(g)],
        vec![mix(g, s)],
        vec![shallow_s, shallow_g],
    ]
}

/// The insertion at which cable `c`'s tying disk reaches the port: from there on it bends
/// the material it holds (`model/port.rs`, "Cables behind the port") \[m\].
fn out_at(space: &Space, c: usize) -> f64 {
    let robot = &space.robot;
    robot.length() - robot.disk_s[robot.cables[c].ends_at]
}

/// The out-first paths from a shallow `s` to a deeper `g` that pulls a cable still tied in
/// the port at `s`'s insertion (module docs): stops at `s`'s insertion and at `out`, the
/// insertion at which the last cable `g` pulls reaches the port, the robot turned to `g`'s
/// rotation, the tied cables at `s`'s values, the cables of the deepest segment out bent
/// towards one of [`STEER_DIRECTIONS`] directions by a third or two thirds of the bend their
/// limits allow (`u_c = r_c θ cos(α_c − φ)`, the planar constant-curvature relation) or at
/// `g`'s values, the other cables out at `g`'s. From `out` to `g` the newly freed cables are
/// pulled in proportion to the insertion — so their segments bend as they come out, each at
/// the curvature it has at `g` (the bent length grows with the shortening). Empty when `g`
/// pulls no cable tied at `s`'s insertion, or is not deeper than where they come out.
fn out_first(space: &Space, s: &[f64], g: &[f64]) -> Vec<[Vec<f64>; 2]> {
    let robot = &space.robot;
    let k = space.cables();
    let (ds, dg) = (s[k], g[k]);
    let tied = |c: usize| out_at(space, c) >= ds;
    let out = (0..k)
        .filter(|&c| tied(c) && g[c] > s[c].max(0.0))
        .map(|c| out_at(space, c))
        .fold(f64::NEG_INFINITY, f64::max);
    let deepest = (0..k)
        .filter(|&c| !tied(c))
        .map(|c| robot.cables[c].ends_at)
        .max();
    let (true, Some(deepest)) = (out.is_finite() && out < dg, deepest) else {
        return Vec::new();
    };
    let steer: Vec<usize> = (0..k)
        .filter(|&c| robot.cables[c].ends_at == deepest)
        .collect();
    let hole = |c: usize| robot.cables[c].hole(0);
    let most = steer
        .iter()
        .map(|&c| space.hi[c] / hole(c).norm().max(1e-12))
        .fold(f64::INFINITY, f64::min)
        .max(0.0);
    let stops = |free: &dyn Fn(usize) -> f64| {
        let mut bent: Vec<f64> = (0..k)
            .map(|c| if tied(c) { s[c] } else { free(c) })
            .collect();
        bent.extend([ds, g[k + 1]]);
        let mut deep = bent.clone();
        deep[k] = out;
        [space.clamp(&bent), space.clamp(&deep)]
    };
    let mut paths = vec![stops(&|c| g[c])];
    if space.by_tension() {
        return paths;
    }
    for theta in [most / 3.0, 2.0 * most / 3.0] {
        for j in 0..STEER_DIRECTIONS {
            let phi = std::f64::consts::TAU * j as f64 / STEER_DIRECTIONS as f64;
            let (cp, sp) = (phi.cos(), phi.sin());
            paths.push(stops(&|c| {
                if steer.contains(&c) {
                    theta * (hole(c).x * cp + hole(c).y * sp)
                } else {
                    g[c]
                }
            }));
        }
    }
    paths
}

/// Directions the deepest segment out is bent towards on an out-first path ([`out_first`]).
const STEER_DIRECTIONS: usize = 6;

/// At most this many out-first paths are checked, those whose robot is clearest where the
/// tied cables come out first.
const STEERED_PATHS: usize = 3;

/// The out-first paths from `s` to `g` (either may be the deeper one: a path from deep to
/// shallow is the reverse of one from shallow to deep), each stop solved, the paths whose
/// robot is clear where the tied cables come out ranked by its clearance there (most first,
/// at most [`STEERED_PATHS`]): their stops, and the nodes solved.
fn out_first_ranked(ck: &mut Checker, s: &Node, g: &Node) -> (Vec<Vec<Vec<f64>>>, Vec<Node>) {
    let forward = out_first(ck.space, &s.u, &g.u);
    let (paths, from, reverse) = if forward.is_empty() {
        (out_first(ck.space, &g.u, &s.u), g, true)
    } else {
        (forward, s, false)
    };
    let mut ranked: Vec<(f64, Vec<Vec<f64>>)> = Vec::new();
    let mut known = Vec::new();
    for [bent, deep] in paths {
        let Some(n) = ck.node(&deep, Some(&from.shape)) else {
            continue;
        };
        let mut stops = vec![bent, deep];
        if reverse {
            stops.reverse();
        }
        ranked.push((n.clearance, stops));
        known.push(n);
    }
    ranked.sort_by(|a, b| b.0.total_cmp(&a.0));
    ranked.truncate(STEERED_PATHS);
    (ranked.into_iter().map(|r| r.1).collect(), known)
}

/// The first staged path from `s` to `g` whose every leg is clear (module docs), or `None`
/// (and always `None` without a port).
pub(crate) fn staged(ck: &mut Checker, s: &Node, g: &Node) -> Option<Vec<Node>> {
    if !ck.space.has_port() {
        return None;
    }
    for stops in candidates(ck.space, &s.u, &g.u) {
        if let Some(path) = along(ck, s, g, stops, &[]) {
            return Some(path);
        }
    }
    let (paths, known) = out_first_ranked(ck, s, g);
    paths
        .into_iter()
        .find_map(|stops| along(ck, s, g, stops, &known))
}

/// The path `s`, `stops`, `g` when every leg is clear (a stop equal to its neighbour
/// skipped; a stop among `known` not solved again): the stops solved first, then the legs
/// checked together ([`Checker::legs`]: a blocked leg is found before the clear ones are
/// certified in full).
fn along(
    ck: &mut Checker,
    s: &Node,
    g: &Node,
    stops: Vec<Vec<f64>>,
    known: &[Node],
) -> Option<Vec<Node>> {
    let mut path = vec![s.clone()];
    for u in stops {
        let last = &path[path.len() - 1];
        if ck.dist(&last.u, &u) == 0.0 || ck.dist(&u, &g.u) == 0.0 {
            continue;
        }
        let n = match known.iter().find(|n| n.u == u) {
            Some(n) => n.clone(),
            None => {
                let warm = last.shape.clone();
                ck.node(&u, Some(&warm))?
            }
        };
        path.push(n);
    }
    path.push(g.clone());
    let refs: Vec<&Node> = path.iter().collect();
    ck.legs(&refs).then_some(path)
}

/// `base` (a point of `space` with a port) with a new insertion drawn uniformly within the
/// limits: a sample along the insertion (module docs).
pub(crate) fn along_insertion(space: &Space, base: &[f64], rng: &mut XorShiftRng) -> Vec<f64> {
    let k = space.cables();
    let mut x = base.to_vec();
    x[k] = space.lo[k] + unit(rng) * (space.hi[k] - space.lo[k]);
    x
}
