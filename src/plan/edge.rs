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
//! [`MIN_STEP`] in the planners' metric ([`super::metric`]; refused).
//!
//! Through a port ([`super::motion`]) the bound is `(c₀ + c₁ − κ D_q − R |Δψ|)/2`: the
//! rotation's part `R |Δψ|` is exact (a rigid turn about the port axis, `R` the farthest
//! feature point from the axis), `κ` multiplies only the motion `D_q` of the de-rotated shapes
//! (backbone matched by arc, as inserting resamples it), and a sub-interval whose insertion
//! change would let the backbone turn by more than [`super::motion::MAX_TURN`] is bisected
//! whatever its clearances — the condition under which `κ = 2` covers a point sliding out of
//! the port along the bent robot (derived there). A sub-interval whose insertion changes is
//! also held to its deeper end's clearance less the whole motion: the material crossing the
//! port was not measured at the shallower end ([`super::motion`], "Material crossing the
//! port"). κ = [`KAPPA`] = 2: at the resolutions reached here the features
//! move along nearly straight lines, so their path is far shorter than twice the chord; the
//! tests re-check every planned path on 8× finer interpolations with parry3d.
//!
//! # Measured as far as needed
//!
//! The bound is nondecreasing in `c₀` and `c₁`, so it holds with any lower bounds of the
//! clearances in their place. A sample solved at a sub-interval's midpoint `m` is therefore
//! measured only as far as the certificates of the two halves it makes need: with the motions
//! from each end to `m` known once `m` is solved, the least clearance of `m` for which both
//! halves' bounds reach the margin is `c*` (less when the other ends are clearer; none when a
//! half cannot be certified whatever `m`'s clearance, as when it inserts too far: it is cut
//! again, and `m` keeps the grids' proof of the margin when they give one, else is measured
//! exactly — its clearance is asked again, by the sub-intervals it ends, once they are known).
//! The grids' certified lower bound
//! ([`crate::reach::clearance_bounds`]) proving `c ≥ c*` costs no exact query; else the exact
//! clearance's question bounded by `c*` ([`crate::reach::clearance_below_hinted`]: no feature
//! whose grid bound is beyond `c*` queried, no triangle farther than `c*` visited) either
//! proves `c ≥ c*` or returns the exact clearance below it. A sample so proved keeps its
//! proof as its clearance ([`Node::exact`] false); should a sub-interval it ends still fall
//! short (its other end was cut again), the end is measured exactly and the bound taken again
//! before the sub-interval is cut — so the cuts, and the samples solved, are those of exact
//! clearances throughout. A sample ends two sub-intervals and is held once for both, so it is
//! measured exactly at most once. Without grids (a convex obstacle, a surface mesh) a sample is
//! measured exactly at once: there the bounded question, when it fell short, was asked again
//! exactly (the vessel's 28 roadmap queries: 961 M instructions so, 918 M measured at once). Refusals are too: a sample is refused when its exact clearance is
//! below the margin, and `c* ≥ margin`. Samples that become a plan's waypoints are measured
//! exactly before the plan is returned; the smallest clearance an edge reports
//! ([`EdgeCheck::Clear`]) is over the samples measured exactly.
//!
//! # In tension space
//!
//! The check is the same when the cables' unknowns are tensions \[N\]: nothing in it is
//! measured in the inputs. `D` is a distance between two *solved shapes* \[m\] (the motion
//! bound takes their disks, backbones and cable chords, not their inputs), the clearances are
//! measured on them, and `(c₀ + c₁ − κ D)/2` follows from the distance to an obstacle being
//! 1-Lipschitz in a feature's position, whatever moved the feature. The inputs enter only
//! through the premise that no feature travels more than `κ D` inside a sub-interval, and the
//! bisection makes that local: a sub-interval is halved until its own end shapes are that
//! close, so where a newton bends the robot far (a soft rod) the certified sub-intervals are
//! short in newtons, and where it barely moves it (near the tension limits of a stiff rod)
//! they are long. A jump of the equilibrium along the edge (a snap under force control) keeps
//! `D` of the sub-interval across it from shrinking: it is certified only if the jump itself
//! fits inside the clearances, else bisected to [`MIN_STEP`] and refused. The shortest
//! sub-interval is measured in the planners' metric, metres of cable either way
//! ([`super::metric`], "In tension space": on the lung rod `MIN_STEP` = 1e-6 m of cable is
//! 2.9e-4 N). `plan_tension::the_premise_holds_along_tension_edges` measures the premise on
//! the soft lung rod's edges (the features' largest detour against `κ D`, with 32 independent
//! solves per sub-interval) and the planned paths are re-checked 8× finer with parry3d.

use super::metric::Metric;
use crate::reach::{ClosestPair, Space};
use crate::shape::Shape;

/// Safety factor of the Lipschitz estimate (see the module docs).
pub const KAPPA: f64 = 2.0;
/// Shortest sub-interval an edge is cut into \[m of cable, the planners' metric\].
pub const MIN_STEP: f64 = 1e-6;

/// A solved, admissible point of the actuation space.
#[derive(Debug, Clone)]
pub struct Node {
    /// The point of the actuation space: shortenings \[m\], one per cable, then with a port
    /// the insertion \[m\] and the rotation \[rad\].
    pub u: Vec<f64>,
    /// Its shape.
    pub shape: Shape,
    /// Its clearance \[m\] (`+∞` without obstacles); when not [`Node::exact`], a lower bound.
    pub clearance: f64,
    /// Whether `clearance` is the exact clearance: true for every node a planner hands out
    /// (a plan's waypoints are measured before it is returned). False only for an edge's
    /// bisection sample proved at least `clearance` from every obstacle, as far as the
    /// certificates of the sub-intervals it ends needed (module docs, "Measured as far as
    /// needed"), and not measured further.
    pub exact: bool,
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
        /// Smallest clearance of a solved sample measured exactly (its ends and the samples
        /// [`Node::exact`]) \[m\].
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
    /// The distance over the space ([`super::metric`]).
    pub metric: Metric,
    /// Counters.
    pub stats: Stats,
    /// Edges already checked (either direction): a path's edges are checked when found and
    /// again by the final validation, which then costs nothing.
    memo: std::collections::HashMap<EdgeKey, EdgeCheck>,
    /// The closest feature–obstacle pair of the last clearance measured: the next shape is
    /// usually near it ([`crate::reach::clearance_hinted`]; changes the cost only).
    hint: Option<ClosestPair>,
    /// With [`Checker::keep_samples`]: each clear edge's solved samples, with their parameter
    /// along the edge from its key's first end.
    samples: Option<std::collections::HashMap<EdgeKey, Vec<(f64, Node)>>>,
}

impl<'a> Checker<'a> {
    /// A checker keeping `margin` from the obstacles.
    pub fn new(space: &'a Space, margin: f64) -> Self {
        Checker {
            space,
            margin,
            metric: Metric::of(space),
            stats: Stats::default(),
            memo: std::collections::HashMap::new(),
            hint: None,
            samples: None,
        }
    }

    /// The distance between two points of the space ([`Metric::dist`]) \[m of cable\].
    pub fn dist(&self, a: &[f64], b: &[f64]) -> f64 {
        self.metric.dist(a, b)
    }

    /// Keep the solved samples of every clear edge checked from now on, so the output stage
    /// of a plan reuses them as waypoints ([`Checker::samples_along`]) instead of solving new
    /// points of an edge it has already sampled finely.
    pub fn keep_samples(mut self) -> Self {
        self.samples = Some(std::collections::HashMap::new());
        self
    }

    /// The kept samples strictly inside the edge from `a` to `b` (checked clear before, in
    /// either direction), as (parameter from `a` in (0, 1), node), in order from `a`; empty when
    /// none were kept.
    pub fn samples_along(&self, a: &[f64], b: &[f64]) -> Vec<(f64, &Node)> {
        let key = edge_key(a, b);
        let Some(list) = self.samples.as_ref().and_then(|m| m.get(&key)) else {
            return Vec::new();
        };
        let forward = a.iter().map(|x| x.to_bits()).eq(key.0.iter().copied());
        let mut out: Vec<(f64, &Node)> = list
            .iter()
            .map(|(t, n)| (if forward { *t } else { 1.0 - *t }, n))
            .collect();
        out.sort_by(|x, y| x.0.total_cmp(&y.0));
        out
    }

    /// Solve and check `u` (warm-started from `warm`); `None` when it is not admissible.
    pub fn node(&mut self, u: &[f64], warm: Option<&Shape>) -> Option<Node> {
        self.node_within(u, warm, |_| Some(f64::INFINITY))
    }

    /// [`Checker::node`] measured only as far as `need` of its shape asks (module docs,
    /// "Measured as far as needed"): a shape proved at least `max(need, margin)` from every
    /// obstacle — by the grids' lower bound, else by the exact clearance's question bounded by
    /// it ([`Space::clearance_below_hinted`]) — keeps that proof as its clearance
    /// (not [`Node::exact`]); a closer one gets its exact clearance, and is refused below the
    /// margin. A `need` of `None` (not known yet) is met by the grids' proof of the margin, else
    /// the exact clearance. The same nodes are refused as by [`Checker::node`].
    fn node_within(
        &mut self,
        u: &[f64],
        warm: Option<&Shape>,
        need: impl FnOnce(&Shape) -> Option<f64>,
    ) -> Option<Node> {
        self.stats.solves += 1;
        let Ok(shape) = self.space.solve(u, warm) else {
            self.stats.nodes_rejected += 1;
            return None;
        };
        // Too close by the grids' bounds: refused as the exact clearance would refuse it.
        let bounds = self.space.clearance_bounds(&shape);
        if bounds.and_then(|b| b.keeps(self.margin)) == Some(false)
            || self.space.tension_violation(&shape).is_some()
        {
            self.stats.nodes_rejected += 1;
            return None;
        }
        // Without grids a sample is measured exactly at once (module docs).
        let want = match bounds {
            Some(_) => need(&shape),
            None => Some(f64::INFINITY),
        };
        let cap = want.unwrap_or(f64::INFINITY).max(self.margin);
        let lower = bounds.map_or(f64::NEG_INFINITY, |b| b.lower);
        let (clearance, exact) = if lower >= cap || (want.is_none() && lower >= self.margin) {
            (lower, false)
        } else {
            match self.space.clearance_below_hinted(&shape, cap, self.hint) {
                Some((c, pair)) => {
                    self.hint = Some(pair);
                    (c.distance, true)
                }
                // At least `cap` from every obstacle (nothing at all within an infinite cap).
                None if cap.is_finite() => (cap.max(lower), false),
                None => (f64::INFINITY, true),
            }
        };
        if clearance < self.margin {
            self.stats.nodes_rejected += 1;
            return None;
        }
        Some(Node {
            u: u.to_vec(),
            shape,
            clearance,
            exact,
        })
    }

    /// Measure the clearance of `n` exactly when it holds only a lower bound ([`Node::exact`]).
    pub fn measure(&mut self, n: &mut Node) {
        if n.exact {
            return;
        }
        n.clearance = match self.space.clearance_hinted(&n.shape, self.hint) {
            Some((c, pair)) => {
                self.hint = Some(pair);
                c.distance
            }
            None => f64::INFINITY,
        };
        n.exact = true;
    }

    /// Why `u` (solved warm from `warm`) is not admissible: the solve's error, the clearance
    /// below the margin, or the tension limit it breaks (`None` when it is admissible).
    pub fn why_not(&self, u: &[f64], warm: Option<&Shape>) -> Option<String> {
        let shape = match self.space.solve(u, warm) {
            Ok(s) => s,
            Err(e) => return Some(e.to_string()),
        };
        if let Some(c) = self
            .space
            .clearance(&shape)
            .filter(|c| c.distance < self.margin)
        {
            return Some(format!(
                "{} is {:.3e} m from `{}`, closer than the margin {} m",
                c.feature, c.distance, c.obstacle, self.margin
            ));
        }
        self.space.tension_violation(&shape)
    }

    /// Check the straight edge from `a` to `b` (see the module docs); an edge checked before
    /// (either direction) is not checked again.
    pub fn edge(&mut self, a: &Node, b: &Node) -> EdgeCheck {
        let key = edge_key(&a.u, &b.u);
        if let Some(out) = self.memo.get(&key) {
            return out.clone();
        }
        self.legs(&[a, b]);
        self.memo.get(&key).cloned().unwrap_or(EdgeCheck::Blocked)
    }

    /// Whether every leg of the path through `stops` is clear ([`Checker::edge`] of each pair
    /// in turn), checked together: the sub-intervals of all legs breadth first, so a blocked
    /// leg anywhere is refused after the coarse midpoints of every leg, before any clear leg is
    /// refined to its certificate (a staged path's first legs were certified in full before
    /// its last was found blocked). Each leg finished is remembered as [`Checker::edge`]
    /// remembers it; on a blocked leg the unfinished ones are dropped.
    pub fn legs(&mut self, stops: &[&Node]) -> bool {
        let mut open: Vec<Option<Leg>> = Vec::new();
        for w in stops.windows(2) {
            match self.memo.get(&edge_key(&w[0].u, &w[1].u)) {
                Some(EdgeCheck::Blocked) => return false,
                Some(EdgeCheck::Clear { .. }) => {}
                None if open
                    .iter()
                    .flatten()
                    .any(|l| l.key == edge_key(&w[0].u, &w[1].u)) => {}
                None => {
                    self.stats.edges_checked += 1;
                    open.push(Some(Leg::new(w[0], w[1])));
                }
            }
        }
        if self.space.scene.is_empty() {
            let clear = EdgeCheck::Clear {
                certified: f64::INFINITY,
                measured: f64::INFINITY,
                pieces: 1,
            };
            for leg in open.into_iter().flatten() {
                self.remember(leg.key, clear.clone(), (true, Vec::new()));
            }
            return true;
        }
        // The sub-intervals' ends, each held once (a sample ends two sub-intervals: measured
        // exactly for one, it is for the other too). Items: leg, end nodes (indices into
        // `nodes`), actuation length, parameters of the ends from the leg's start.
        let mut nodes: Vec<Node> = Vec::new();
        let mut queue: std::collections::VecDeque<(usize, [usize; 2], f64, f64, f64)> =
            std::collections::VecDeque::new();
        for (i, l) in open.iter_mut().enumerate() {
            let Some(l) = l.as_mut() else { continue };
            l.ends = [nodes.len(), nodes.len() + 1];
            let l_len = self.metric.dist(&l.a.u, &l.b.u);
            nodes.push(l.a.clone());
            nodes.push(l.b.clone());
            queue.push_back((i, l.ends, l_len, 0.0, 1.0));
        }
        let keep = self.samples.is_some();
        while let Some((i, [i0, i1], l, t0, t1)) = queue.pop_front() {
            if open[i].is_none() {
                continue;
            }
            let bound = self.piece_bound(&mut nodes, i0, i1);
            let Some(leg) = open[i].as_mut() else {
                continue;
            };
            if bound >= self.margin {
                leg.certified = leg.certified.min(bound);
                leg.pieces += 1;
                leg.pending -= 1;
                if leg.pending == 0 {
                    if let Some(leg) = open[i].take() {
                        let (key, clear, kept) = leg.finish(&nodes);
                        self.remember(key, clear, kept);
                    }
                }
                continue;
            }
            let (n0, n1) = (&nodes[i0], &nodes[i1]);
            let mid: Vec<f64> = n0.u.iter().zip(&n1.u).map(|(x, y)| 0.5 * (x + y)).collect();
            let m = if l < MIN_STEP {
                None
            } else {
                let (space, margin) = (self.space, self.margin);
                self.node_within(&mid, Some(&n0.shape), |m| need(space, margin, n0, m, n1))
            };
            let Some(m) = m else {
                self.stats.edges_rejected += 1;
                self.memo.insert(leg.key.clone(), EdgeCheck::Blocked);
                return false;
            };
            leg.pending += 1;
            let tm = 0.5 * (t0 + t1);
            let im = nodes.len();
            nodes.push(m);
            if keep {
                leg.kept.push((tm, im));
            }
            queue.push_back((i, [i0, im], 0.5 * l, t0, tm));
            queue.push_back((i, [im, i1], 0.5 * l, tm, t1));
        }
        true
    }

    /// The clearance certified along the sub-interval from `nodes[i0]` to `nodes[i1]` (module
    /// docs); when it is below the margin and an end holds only a lower bound, that end is
    /// measured exactly first (module docs, "Measured as far as needed").
    fn piece_bound(&mut self, nodes: &mut [Node], i0: usize, i1: usize) -> f64 {
        let motion = super::motion::motion(&self.space.robot, &nodes[i0].shape, &nodes[i1].shape);
        let bound = motion.certified(nodes[i0].clearance, nodes[i1].clearance, KAPPA);
        if bound >= self.margin || (nodes[i0].exact && nodes[i1].exact) {
            return bound;
        }
        self.measure(&mut nodes[i0]);
        self.measure(&mut nodes[i1]);
        motion.certified(nodes[i0].clearance, nodes[i1].clearance, KAPPA)
    }

    /// Remember a clear edge (and, with [`Checker::keep_samples`], its samples `kept`, whose
    /// parameters are from the end `forward` says: the key's first end or its second).
    fn remember(&mut self, key: EdgeKey, out: EdgeCheck, kept: Samples) {
        let (forward, mut kept) = kept;
        if let Some(m) = self.samples.as_mut() {
            // Stored from the key's first end (dyadic: 1 − t is exact).
            if !forward {
                kept.iter_mut().for_each(|(t, _)| *t = 1.0 - *t);
            }
            m.insert(key.clone(), kept);
        }
        self.memo.insert(key, out);
    }

    /// Forget the edges (and their samples) not between two points `keep` accepts (bit
    /// patterns of their actuations): what a run of many queries keeps between them.
    pub(crate) fn retain_edges(&mut self, keep: impl Fn(&[u64]) -> bool) {
        self.memo.retain(|k, _| keep(&k.0) && keep(&k.1));
        if let Some(m) = self.samples.as_mut() {
            m.retain(|k, _| keep(&k.0) && keep(&k.1));
        }
    }
}

/// The clearance \[m\] a sample `m` between `a` and `b` needs for both sub-intervals it cuts
/// theirs into to be certified ([`super::motion::Motion::certified`] at least the margin, the
/// ends' clearances as they stand), a little more for round-off; `None` when one of them cannot
/// be certified whatever `m`'s clearance (it will be cut again, `m` an end of a sub-interval
/// not known yet).
fn need(space: &Space, margin: f64, a: &Node, m: &Shape, b: &Node) -> Option<f64> {
    // The least clearance of the end `m` of a sub-interval moving by `mv`, the other end's `other`;
    // `m_second`: whether `m` is its second end.
    let least = |mv: super::motion::Motion, other: f64, m_second: bool| {
        if !mv.certifiable {
            return f64::INFINITY;
        }
        let travel = KAPPA * mv.estimated + mv.exact;
        let mut least = 2.0 * margin + travel - other;
        if mv.insertion_change != 0.0 {
            if (mv.insertion_change > 0.0) == m_second {
                least = least.max(margin + travel);
            } else if other - travel < margin {
                return f64::INFINITY;
            }
        }
        least
    };
    let robot = &space.robot;
    let first = least(super::motion::motion(robot, &a.shape, m), a.clearance, true);
    let second = least(
        super::motion::motion(robot, m, &b.shape),
        b.clearance,
        false,
    );
    let least = first.max(second);
    least
        .is_finite()
        .then(|| least + 1e-9 * least.abs() + 1e-12)
}

/// A clear edge's solved samples with their parameters, and whether those are from the edge
/// key's first end.
type Samples = (bool, Vec<(f64, Node)>);

/// One leg of [`Checker::legs`] being checked.
struct Leg {
    key: EdgeKey,
    a: Node,
    b: Node,
    /// Whether `a` is the key's first end.
    forward: bool,
    certified: f64,
    pieces: usize,
    /// Sub-intervals still queued.
    pending: usize,
    /// Its ends among the nodes of [`Checker::legs`].
    ends: [usize; 2],
    /// Midpoints solved, with their parameter from `a`, among the nodes of [`Checker::legs`].
    kept: Vec<(f64, usize)>,
}

impl Leg {
    fn new(a: &Node, b: &Node) -> Leg {
        let key = edge_key(&a.u, &b.u);
        Leg {
            forward: a.u.iter().map(|x| x.to_bits()).eq(key.0.iter().copied()),
            key,
            a: a.clone(),
            b: b.clone(),
            certified: f64::INFINITY,
            pieces: 0,
            pending: 1,
            ends: [0, 0],
            kept: Vec::new(),
        }
    }

    /// The key, clear answer and samples of a finished leg, its nodes among `nodes`: the
    /// smallest clearance measured is over its ends and samples measured exactly by then.
    fn finish(self, nodes: &[Node]) -> (EdgeKey, EdgeCheck, Samples) {
        let measured = self
            .ends
            .iter()
            .chain(self.kept.iter().map(|(_, i)| i))
            .map(|&i| &nodes[i])
            .filter(|n| n.exact)
            .map(|n| n.clearance)
            .fold(f64::INFINITY, f64::min);
        let clear = EdgeCheck::Clear {
            certified: self.certified,
            measured,
            pieces: self.pieces,
        };
        let kept = self
            .kept
            .into_iter()
            .map(|(t, i)| (t, nodes[i].clone()))
            .collect();
        (self.key, clear, (self.forward, kept))
    }
}
