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
//! * **Samples along the insertion** ([`along_insertion`]): a share of the random samples
//!   keeps an existing node's cables and rotation and draws only a new insertion, so trees and
//!   roadmaps grow along `d`: such neighbours are close in the metric (a metre of insertion
//!   counts a tenth of a metre of cable) and are joined first.
//!
//! Without a port none of this applies and the planners are unchanged.

use super::edge::{Checker, EdgeCheck, Node};
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

/// The first staged path from `s` to `g` whose every leg is clear (module docs), or `None`
/// (and always `None` without a port).
pub(crate) fn staged(ck: &mut Checker, s: &Node, g: &Node) -> Option<Vec<Node>> {
    if !ck.space.has_port() {
        return None;
    }
    'paths: for stops in candidates(ck.space, &s.u, &g.u) {
        let mut path = vec![s.clone()];
        for u in stops {
            let last = &path[path.len() - 1];
            if ck.dist(&last.u, &u) == 0.0 || ck.dist(&u, &g.u) == 0.0 {
                continue;
            }
            let warm = last.shape.clone();
            let Some(n) = ck.node(&u, Some(&warm)) else {
                continue 'paths;
            };
            if ck.edge(&path[path.len() - 1], &n) == EdgeCheck::Blocked {
                continue 'paths;
            }
            path.push(n);
        }
        if ck.edge(&path[path.len() - 1], g) == EdgeCheck::Blocked {
            continue;
        }
        path.push(g.clone());
        return Some(path);
    }
    None
}

/// `base` (a point of `space` with a port) with a new insertion drawn uniformly within the
/// limits: a sample along the insertion (module docs).
pub(crate) fn along_insertion(space: &Space, base: &[f64], rng: &mut XorShiftRng) -> Vec<f64> {
    let k = space.cables();
    let mut x = base.to_vec();
    x[k] = space.lo[k] + unit(rng) * (space.hi[k] - space.lo[k]);
    x
}
