//! Nodes and edges of the actuation space, checked against the obstacles.
//!
//! # Edge validation (the resolution that certifies clearance)
//!
//! An edge is the straight segment between two actuations. It is cut in sub-intervals whose
//! end shapes are solved; for a sub-interval with end clearances `c₀, c₁` (≥ margin, by
//! [`super::super::reach::clearance`]) and end shapes whose features differ by at most `D`
//! ([`crate::reach::motion_bound`], a rigorous bound on the Hausdorff distance between the
//! two feature sets), every shape in between is at least
//!
//! ```text
//! (c₀ + c₁ − κ D) / 2
//! ```
//!
//! from every obstacle *if* no feature travels more than `κ D` along the sub-interval (a
//! Lipschitz estimate: the motion per unit of actuation inside the sub-interval is at most κ
//! times what its two ends show). A feature at parameter `t` is within `δ₀(t)` of its place
//! in the first end shape and `δ₁(t)` of the second, `δ₀ + δ₁ ≤ κ D`, and distances to an
//! obstacle are 1-Lipschitz in the feature's position, so the distance at `t` is at least
//! `max(c₀ − δ₀, c₁ − δ₁) ≥ (c₀ + c₁ − κ D)/2`. A sub-interval whose bound is below the
//! margin is bisected (its midpoint solved and checked) until the bound holds everywhere or a
//! midpoint is itself too close ([`EdgeCheck::Blocked`]), or the sub-interval is shorter than
//! [`MIN_STEP`] (refused). κ = [`KAPPA`] = 2: at the resolutions reached here the features
//! move along nearly straight lines, so their path is far shorter than twice the chord; the
//! tests re-check every planned path on 8× finer interpolations with parry3d.

use crate::reach::{motion_bound, Space};
use crate::shape::Shape;

/// Safety factor of the Lipschitz estimate (see the module docs).
pub const KAPPA: f64 = 2.0;
/// Shortest sub-interval an edge is cut into \[m of actuation\].
pub const MIN_STEP: f64 = 1e-6;

/// A solved, admissible point of the actuation space.
#[derive(Debug, Clone)]
pub struct Node {
    /// Shortenings \[m\], one per cable.
    pub u: Vec<f64>,
    /// Its shape.
    pub shape: Shape,
    /// Its clearance \[m\] (`+∞` without obstacles).
    pub clearance: f64,
}

/// Counters of the checks made.
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize)]
pub struct Stats {
    /// Forward solves.
    pub solves: usize,
    /// Nodes refused (too close, tension out of limits, solve failed).
    pub nodes_rejected: usize,
    /// Edges checked (an edge met again is not checked again).
    pub edges_checked: usize,
    /// Edges refused.
    pub edges_rejected: usize,
}

/// How an edge check ended.
#[derive(Debug, Clone, PartialEq)]
pub enum EdgeCheck {
    /// Certified: every shape along it keeps at least this clearance \[m\] (under the
    /// Lipschitz estimate) and the smallest clearance measured on its samples.
    Clear {
        /// Certified lower bound \[m\].
        certified: f64,
        /// Smallest clearance of a solved sample \[m\].
        measured: f64,
        /// Sub-intervals used.
        pieces: usize,
    },
    /// A solved point on it is too close, breaks a limit or fails to solve.
    Blocked,
}

/// An edge's key in the memo: the bit patterns of its two ends, in order.
type EdgeKey = (Vec<u64>, Vec<u64>);

fn edge_key(a: &[f64], b: &[f64]) -> EdgeKey {
    let bits = |u: &[f64]| u.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    let (ka, kb) = (bits(a), bits(b));
    if ka <= kb {
        (ka, kb)
    } else {
        (kb, ka)
    }
}

/// Node and edge checks in one actuation space.
pub struct Checker<'a> {
    /// The space.
    pub space: &'a Space,
    /// Margin kept from the obstacles \[m\].
    pub margin: f64,
    /// Counters.
    pub stats: Stats,
    /// Edges already checked (either direction): a path's edges are checked when found and
    /// again by the final validation, which then costs nothing.
    memo: std::collections::HashMap<EdgeKey, EdgeCheck>,
}

impl<'a> Checker<'a> {
    /// A checker keeping `margin` from the obstacles.
    pub fn new(space: &'a Space, margin: f64) -> Self {
        Checker {
            space,
            margin,
            stats: Stats::default(),
            memo: std::collections::HashMap::new(),
        }
    }

    /// Record the outcome of a check of the edge `a`–`b` made earlier under the same space
    /// and margin (a roadmap's validated edges), so [`Checker::edge`] returns it unchecked.
    pub fn trust_edge(&mut self, a: &[f64], b: &[f64], check: EdgeCheck) {
        self.memo.insert(edge_key(a, b), check);
    }

    /// Solve and check `u` (warm-started from `warm`); `None` when it is not admissible.
    pub fn node(&mut self, u: &[f64], warm: Option<&Shape>) -> Option<Node> {
        self.stats.solves += 1;
        let shape = match self.space.solve(u, warm) {
            Ok(s) => s,
            Err(_) => {
                self.stats.nodes_rejected += 1;
                return None;
            }
        };
        let clearance = self
            .space
            .clearance(&shape)
            .map_or(f64::INFINITY, |c| c.distance);
        if clearance < self.margin || self.space.tension_violation(&shape).is_some() {
            self.stats.nodes_rejected += 1;
            return None;
        }
        Some(Node {
            u: u.to_vec(),
            shape,
            clearance,
        })
    }

    /// Check the straight edge from `a` to `b` (see the module docs); an edge checked before
    /// (either direction) is not checked again.
    pub fn edge(&mut self, a: &Node, b: &Node) -> EdgeCheck {
        let key = edge_key(&a.u, &b.u);
        if let Some(out) = self.memo.get(&key) {
            return out.clone();
        }
        self.stats.edges_checked += 1;
        let out = self.edge_inner(a, b);
        if out == EdgeCheck::Blocked {
            self.stats.edges_rejected += 1;
        }
        self.memo.insert(key, out.clone());
        out
    }

    fn edge_inner(&mut self, a: &Node, b: &Node) -> EdgeCheck {
        if self.space.scene.is_empty() {
            return EdgeCheck::Clear {
                certified: f64::INFINITY,
                measured: f64::INFINITY,
                pieces: 1,
            };
        }
        let len = dist(&a.u, &b.u);
        let robot = &self.space.robot;
        let mut certified = f64::INFINITY;
        let mut measured = a.clearance.min(b.clearance);
        let mut pieces = 0;
        // Breadth-first over sub-intervals (midpoint, then quarters, …): a blocked edge is
        // usually refused after a few coarse midpoints; a clear edge solves the same
        // midpoints in any order. Owned sample nodes.
        let mut queue: std::collections::VecDeque<(Node, Node, f64)> =
            std::collections::VecDeque::from([(a.clone(), b.clone(), len)]);
        while let Some((n0, n1, l)) = queue.pop_front() {
            let bound = 0.5
                * (n0.clearance + n1.clearance - KAPPA * motion_bound(robot, &n0.shape, &n1.shape));
            if bound >= self.margin {
                certified = certified.min(bound);
                pieces += 1;
                continue;
            }
            if l < MIN_STEP {
                return EdgeCheck::Blocked;
            }
            let mid: Vec<f64> = n0.u.iter().zip(&n1.u).map(|(x, y)| 0.5 * (x + y)).collect();
            let Some(m) = self.node(&mid, Some(&n0.shape)) else {
                return EdgeCheck::Blocked;
            };
            measured = measured.min(m.clearance);
            queue.push_back((n0, m.clone(), 0.5 * l));
            queue.push_back((m, n1, 0.5 * l));
        }
        EdgeCheck::Clear {
            certified,
            measured,
            pieces,
        }
    }
}

/// Euclidean distance between two actuations \[m\].
pub fn dist(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y) * (x - y))
        .sum::<f64>()
        .sqrt()
}
