//! Queries on a roadmap ([`super::roadmap`]), one or many in a run ([`Queries`]).
//!
//! A query tries the straight edge from its start to its goal, through a port the staged
//! insert-first paths (`insert.rs`), then the graph: the start and the goal linked to their
//! nearest nodes by clear edges, the shortest path searched (Dijkstra, lengths in actuation
//! space lengthened near obstacles), its nodes solved and its edges validated as the path is
//! walked, those that fail dropped and the search repeated (lazy validation, as in Bohlin &
//! Kavraki, "Path planning using lazy PRM", ICRA 2000). (The graph first was slower in the
//! generated airway, 10.4 against 14.6 queries per CPU-second on seed 11's 296-node roadmap:
//! few ends link to so sparse a roadmap, and the failed links cost more than the staged paths.)
//!
//! Nothing in the file is believed about safety: every node a path uses is solved and measured
//! in this run, every edge validated in it ([`super::edge`]). What a [`Queries`] keeps from one
//! query to the next is only what it measured itself: the roadmap's nodes it solved, the
//! roadmap's edges it validated (with their samples, reused as waypoints) or found blocked —
//! never the edges to a query's own start and goal. So the first queries of a run validate the
//! roadmap's edges they use, and later ones mostly the links to their own ends.

use super::edge::{Checker, EdgeCheck, Node, Stats};
use super::roadmap::{nearest, Roadmap};
use super::{check_options, endpoints, finish, Goal, Plan, PlanOptions, PlanStats};
use crate::error::SolveError;
use crate::method::run::SolveRequest;
use crate::model::Model;
use crate::reach::Space;
use std::collections::{BinaryHeap, HashSet};
use std::time::Instant;

/// Nearest nodes a query's end tries to link to.
const LINK_CANDIDATES: usize = 12;

/// Many queries on one roadmap, in one space and scene, keeping what each validated
/// (module docs). Made by [`Roadmap::queries`].
pub struct Queries<'a> {
    roadmap: &'a Roadmap,
    model: &'a Model,
    ck: Checker<'a>,
    /// Roadmap nodes solved in this run (lazily), `Some(None)` once refused.
    solved: Vec<Option<Option<Node>>>,
    /// The roadmap's edges not found blocked in this run, with their search weights; made
    /// when a query first searches the graph (most in an airway are answered before it).
    adj: Option<Vec<Vec<(usize, f64)>>>,
    /// Bit patterns of the nodes' actuations: the edges between two of them are kept.
    keys: HashSet<Vec<u64>>,
}

impl Roadmap {
    /// Queries on this roadmap for `model` solved by `request` in `space` (made from the two),
    /// keeping `margin` (default: the space's): refused by name when the roadmap was built for
    /// another robot, space, method or limits, or is a shard.
    pub fn queries<'a>(
        &'a self,
        model: &'a Model,
        request: &SolveRequest,
        space: &'a Space,
        margin: Option<f64>,
    ) -> Result<Queries<'a>, SolveError> {
        self.check_fits(space, request)?;
        let ck = Checker::new(space, margin.unwrap_or(space.margin)).keep_samples();
        let n = self.nodes.len();
        let bits = |u: &[f64]| u.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        Ok(Queries {
            roadmap: self,
            model,
            ck,
            solved: vec![None; n],
            adj: None,
            keys: self.nodes.iter().map(|x| bits(&x.u)).collect(),
        })
    }

    /// Every edge's search weight, both ways, by node.
    fn adjacency(&self, ck: &Checker) -> Vec<Vec<(usize, f64)>> {
        let mut adj: Vec<Vec<(usize, f64)>> = vec![Vec::new(); self.nodes.len()];
        for &(a, b) in &self.edges {
            let w = weight(
                ck,
                &self.nodes[a].u,
                &self.nodes[b].u,
                [a, b].map(|i| self.clear(i)),
            );
            adj[a].push((b, w));
            adj[b].push((a, w));
        }
        adj
    }

    /// The clearance node `i` was built with: a search weight only.
    fn clear(&self, i: usize) -> f64 {
        self.nodes[i].clearance.unwrap_or(f64::INFINITY)
    }
}

/// An edge's search weight: its actuation length, lengthened near obstacles (× (1 + 1 mm / c)
/// for the smaller clearance c of its ends), so paths keep away from them.
fn weight(ck: &Checker, a: &[f64], b: &[f64], c: [f64; 2]) -> f64 {
    ck.metric.dist(a, b) * (1.0 + 1e-3 / c[0].min(c[1]).max(1e-6))
}

impl Queries<'_> {
    /// [`plan`](super::plan) on the roadmap, from `start` (default: the model's actuation) to
    /// `goal`, keeping the margin the queries were made with (`opts.margin`, when given, must
    /// be it).
    pub fn plan(
        &mut self,
        start: Option<Vec<f64>>,
        goal: &Goal,
        opts: &PlanOptions,
    ) -> Result<Plan, SolveError> {
        check_options(opts)?;
        if let Some(m) = opts.margin.filter(|&m| m != self.ck.margin) {
            return Err(SolveError::InvalidInput {
                field: "margin".into(),
                reason: format!(
                    "these queries keep {} m from the obstacles, this one asks for {m} m",
                    self.ck.margin
                ),
            });
        }
        let t0 = Instant::now();
        self.ck.stats = Stats::default();
        let out = endpoints(&mut self.ck, self.model, start, goal)
            .and_then(|(s, g)| self.query(s, g, opts, t0));
        let keys = &self.keys;
        self.ck.retain_edges(|k| keys.contains(k));
        out
    }

    /// The straight edge, the staged paths, then the graph (module docs).
    fn query(
        &mut self,
        s: Node,
        g: Node,
        opts: &PlanOptions,
        t0: Instant,
    ) -> Result<Plan, SolveError> {
        let mut stats = PlanStats {
            planner: "roadmap",
            ..PlanStats::default()
        };
        if let EdgeCheck::Clear { .. } = self.ck.edge(&s, &g) {
            return finish(&mut self.ck, vec![s, g], opts, stats, t0);
        }
        if let Some(path) = super::insert::staged(&mut self.ck, &s, &g) {
            return finish(&mut self.ck, path, opts, stats, t0);
        }
        if let Some(path) = self.search(&s, &g, &mut stats) {
            return finish(&mut self.ck, path, opts, stats, t0);
        }
        Err(SolveError::NoPath {
            samples: self.roadmap.nodes.len(),
            reason: "the roadmap does not connect the start to the goal".into(),
        })
    }

    /// The graph's path from `s` to `g` (module docs), its nodes solved and edges validated;
    /// `None` when the graph, repaired, does not join them.
    fn search(&mut self, s: &Node, g: &Node, stats: &mut PlanStats) -> Option<Vec<Node>> {
        let n = self.roadmap.nodes.len();
        let (si, gi) = (n, n + 1);
        let roadmap = self.roadmap;
        let kept = self.adj.get_or_insert_with(|| roadmap.adjacency(&self.ck));
        let mut adj = kept.clone();
        adj.extend([Vec::new(), Vec::new()]);
        // Each end is linked to its nearest node with a clear edge; only when the roadmap then
        // does not join them, to up to three.
        let mut want = 0;
        loop {
            let Some(ids) = shortest(&adj, si, gi) else {
                if want == 3 {
                    return None;
                }
                want = if want == 0 { 1 } else { 3 };
                for (end, idx) in [(s, si), (g, gi)] {
                    let have: Vec<usize> = adj[idx].iter().map(|e| e.0).collect();
                    for j in self.links(end, want, &have) {
                        let c = [end.clearance, self.roadmap.clear(j)];
                        let w = weight(&self.ck, &end.u, &self.roadmap.nodes[j].u, c);
                        adj[idx].push((j, w));
                        adj[j].push((idx, w));
                    }
                }
                continue;
            };
            stats.tree_nodes = ids.len();
            // Solve and check the path's nodes in order, and its edges.
            let mut path = vec![s.clone()];
            let mut broken: Option<(usize, usize)> = None;
            for w in ids.windows(2) {
                let b = w[1];
                let node = if b == gi {
                    Some(g.clone())
                } else {
                    let warm = path[path.len() - 1].shape.clone();
                    self.solve_node(b, &warm)
                };
                match node {
                    Some(node)
                        if self.ck.edge(&path[path.len() - 1], &node) != EdgeCheck::Blocked =>
                    {
                        path.push(node)
                    }
                    _ => {
                        broken = Some((w[0], b));
                        break;
                    }
                }
            }
            let Some((a, b)) = broken else {
                return Some(path);
            };
            stats.edges_repaired += 1;
            for adj in [Some(&mut adj), self.adj.as_mut()].into_iter().flatten() {
                if let Some(x) = adj.get_mut(a) {
                    x.retain(|e| e.0 != b);
                }
                if let Some(x) = adj.get_mut(b) {
                    x.retain(|e| e.0 != a);
                }
            }
        }
    }

    /// Up to `want` links in all from `end` to its nearest nodes (of the
    /// [`LINK_CANDIDATES`] nearest) by clear edges, beyond those in `have`.
    fn links(&mut self, end: &Node, want: usize, have: &[usize]) -> Vec<usize> {
        let mut out = Vec::new();
        for j in nearest(
            &self.ck.metric,
            &self.roadmap.nodes,
            &end.u,
            LINK_CANDIDATES,
        ) {
            if have.len() + out.len() >= want {
                break;
            }
            if have.contains(&j) {
                continue;
            }
            let Some(nj) = self.solve_node(j, &end.shape) else {
                continue;
            };
            if let EdgeCheck::Clear { .. } = self.ck.edge(end, &nj) {
                out.push(j);
            }
        }
        out
    }

    /// Roadmap node `j` solved (warm from `warm`) and checked: its clearance measured in this
    /// run, never taken from the file.
    fn solve_node(&mut self, j: usize, warm: &crate::shape::Shape) -> Option<Node> {
        if let Some(x) = &self.solved[j] {
            return x.clone();
        }
        let out = self.ck.node(&self.roadmap.nodes[j].u, Some(warm));
        self.solved[j] = Some(out.clone());
        out
    }
}

/// Dijkstra from node `s` to node `g` over `adj` (lengths in the planners' metric).
fn shortest(adj: &[Vec<(usize, f64)>], s: usize, g: usize) -> Option<Vec<usize>> {
    #[derive(PartialEq)]
    struct Item(f64, usize);
    impl Eq for Item {}
    impl PartialOrd for Item {
        fn partial_cmp(&self, o: &Self) -> Option<std::cmp::Ordering> {
            Some(self.cmp(o))
        }
    }
    impl Ord for Item {
        fn cmp(&self, o: &Self) -> std::cmp::Ordering {
            o.0.total_cmp(&self.0).then(o.1.cmp(&self.1))
        }
    }
    let mut d = vec![f64::INFINITY; adj.len()];
    let mut prev = vec![usize::MAX; adj.len()];
    let mut heap = BinaryHeap::new();
    d[s] = 0.0;
    heap.push(Item(0.0, s));
    while let Some(Item(di, i)) = heap.pop() {
        if i == g {
            break;
        }
        if di > d[i] {
            continue;
        }
        for &(j, w) in &adj[i] {
            if di + w < d[j] {
                d[j] = di + w;
                prev[j] = i;
                heap.push(Item(d[j], j));
            }
        }
    }
    if !d[g].is_finite() {
        return None;
    }
    let mut path = vec![g];
    while path[path.len() - 1] != s {
        path.push(prev[path[path.len() - 1]]);
    }
    path.reverse();
    Some(path)
}
