//! RRT-Connect in the actuation space (Kuffner & LaValle, "RRT-Connect: an efficient approach
//! to single-query path planning", ICRA 2000), then greedy shortcuts ([`shortcut`]).
//!
//! Why sampling in actuation space: every sample is one forward solve (tens of µs for
//! `energy`) and the space has one dimension per cable (2–9), where RRT-Connect is complete in
//! probability and needs no gradient of the clearance — which is a minimum over
//! feature–obstacle pairs and jumps where the closest pair changes, the case that stalls an
//! optimization-based planner. Both trees grow by steps of at most [`super::PlanOptions::step`]
//! towards seeded uniform samples in the limits box; each new node is solved warm from its
//! parent and its edge validated ([`super::edge`]). Through a port the staged paths that
//! insert first are tried before any sample, and every [`super::insert::ALONG_EVERY`]-th
//! sample moves a node of the growing tree along its insertion ([`super::insert`]).

use super::edge::{Checker, EdgeCheck, Node};
use super::metric::Metric;
use crate::shape::Shape;
use rand_core::Rng;
use rand_xorshift::XorShiftRng;

/// A uniform number in `[0, 1)` from the generator's top 53 bits.
pub(crate) fn unit(rng: &mut XorShiftRng) -> f64 {
    (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64
}

struct Tree {
    nodes: Vec<Node>,
    parent: Vec<Option<usize>>,
}

impl Tree {
    fn new(root: Node) -> Self {
        Tree {
            nodes: vec![root],
            parent: vec![None],
        }
    }
    fn nearest(&self, metric: &Metric, q: &[f64]) -> usize {
        let mut best = (0, f64::INFINITY);
        for (i, n) in self.nodes.iter().enumerate() {
            let d = metric.dist(&n.u, q);
            if d < best.1 {
                best = (i, d);
            }
        }
        best.0
    }
    /// Root → `i`.
    fn path_to(&self, mut i: usize) -> Vec<Node> {
        let mut out = vec![self.nodes[i].clone()];
        while let Some(p) = self.parent[i] {
            out.push(self.nodes[p].clone());
            i = p;
        }
        out.reverse();
        out
    }
}

enum Ext {
    Reached(usize),
    Advanced(usize),
    Trapped,
}

fn extend(ck: &mut Checker, tree: &mut Tree, q: &[f64], step: f64) -> Ext {
    let n = tree.nearest(&ck.metric, q);
    let from = &tree.nodes[n];
    let d = ck.dist(&from.u, q);
    let (target, reached): (Vec<f64>, bool) = if d <= step {
        (q.to_vec(), true)
    } else {
        (
            from.u
                .iter()
                .zip(q)
                .map(|(a, b)| a + step / d * (b - a))
                .collect(),
            false,
        )
    };
    let warm: Shape = from.shape.clone();
    let Some(node) = ck.node(&target, Some(&warm)) else {
        return Ext::Trapped;
    };
    if let EdgeCheck::Blocked = ck.edge(&tree.nodes[n], &node) {
        return Ext::Trapped;
    }
    tree.nodes.push(node);
    tree.parent.push(Some(n));
    let i = tree.nodes.len() - 1;
    if reached {
        Ext::Reached(i)
    } else {
        Ext::Advanced(i)
    }
}

/// The path found, with the samples drawn and the trees' sizes.
pub(crate) struct Found {
    pub path: Vec<Node>,
    pub samples: usize,
    pub tree_nodes: usize,
}

/// RRT-Connect from `start` to `goal`; `None` after `max_samples` samples.
pub(crate) fn rrt_connect(
    ck: &mut Checker,
    start: Node,
    goal: Node,
    step: f64,
    max_samples: usize,
    rng: &mut XorShiftRng,
) -> Result<Found, usize> {
    let (lo, hi) = (ck.space.lo.clone(), ck.space.hi.clone());
    let mut a = Tree::new(start);
    let mut b = Tree::new(goal);
    // The straight edge first: most queries in open space need nothing else.
    if let EdgeCheck::Clear { .. } = ck.edge(&a.nodes[0], &b.nodes[0]) {
        return Ok(Found {
            path: vec![a.nodes[0].clone(), b.nodes[0].clone()],
            samples: 0,
            tree_nodes: 2,
        });
    }
    // Through a port: the staged paths that insert first or bend first (`insert.rs`).
    if let Some(path) = super::insert::staged(ck, &a.nodes[0], &b.nodes[0]) {
        let tree_nodes = path.len();
        return Ok(Found {
            path,
            samples: 0,
            tree_nodes,
        });
    }
    let port = ck.space.has_port();
    let mut swapped = false;
    for s in 1..=max_samples {
        let q: Vec<f64> = if port && s % super::insert::ALONG_EVERY == 0 {
            // Along the insertion from one of this tree's nodes.
            let i = (unit(rng) * a.nodes.len() as f64) as usize % a.nodes.len();
            super::insert::along_insertion(ck.space, &a.nodes[i].u, rng)
        } else {
            lo.iter()
                .zip(&hi)
                .map(|(l, h)| l + unit(rng) * (h - l))
                .collect()
        };
        let new = match extend(ck, &mut a, &q, step) {
            Ext::Trapped => None,
            Ext::Reached(i) | Ext::Advanced(i) => Some(i),
        };
        if let Some(i) = new {
            let qn = a.nodes[i].u.clone();
            loop {
                match extend(ck, &mut b, &qn, step) {
                    Ext::Advanced(_) => continue,
                    Ext::Trapped => break,
                    Ext::Reached(j) => {
                        let (pa, pb) = (a.path_to(i), b.path_to(j));
                        let (mut first, second) = if swapped { (pb, pa) } else { (pa, pb) };
                        // `first` ends and `second` ends at the same actuation.
                        first.pop();
                        first.extend(second.into_iter().rev());
                        return Ok(Found {
                            path: first,
                            samples: s,
                            tree_nodes: a.nodes.len() + b.nodes.len(),
                        });
                    }
                }
            }
        }
        std::mem::swap(&mut a, &mut b);
        swapped = !swapped;
    }
    Err(max_samples)
}

/// Greedy shortcuts, farthest first: from each waypoint `i` in turn (start first), the
/// farthest later waypoint `j > i + 1` joined to it by a clear edge replaces every waypoint
/// between them. At most `tries` edge checks in all (an edge checked before, such as the
/// straight start–goal edge, costs no solve but counts). Returns the number of waypoints
/// removed.
///
/// Why farthest first rather than random pairs: every clear edge a shortcut validates costs
/// bisection solves, and a random pair's clear edge is often replaced later by a longer one
/// (its solves wasted); the farthest clear edge from a waypoint is the one that stays. On the
/// vessel example's roadmap path (10 waypoints) both end with the same 3 waypoints; random
/// pairs spent 34 solves on it, farthest first 15.
pub(crate) fn shortcut(ck: &mut Checker, path: &mut Vec<Node>, tries: usize) -> usize {
    let before = path.len();
    let mut left = tries;
    let mut i = 0;
    while i + 2 < path.len() && left > 0 {
        for j in (i + 2..path.len()).rev() {
            if left == 0 {
                break;
            }
            left -= 1;
            if let EdgeCheck::Clear { .. } = ck.edge(&path[i], &path[j]) {
                path.drain(i + 1..j);
                break;
            }
        }
        i += 1;
    }
    before - path.len()
}
