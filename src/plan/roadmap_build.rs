//! Building a roadmap ([`super::roadmap`]'s module docs): seeded uniform samples, samples
//! along the insertion through a port and Gaussian expansion around admissible nodes (solved
//! in parallel, the same on any threads and in every shard: [`super::roadmap_sample`]), then
//! every candidate edge — each node with its
//! nearest neighbours, one sorted list — checked in parallel, or only a shard's share of it
//! ([`super::roadmap_shard`]).

use super::edge::{Checker, EdgeCheck, Node};
use super::metric::Metric;
use super::roadmap::{
    nearest, scene_fingerprint, settings_of, BuildOptions, Roadmap, RoadmapNode, FORMAT,
};
use crate::error::SolveError;
use crate::method::run::SolveRequest;
use crate::model::Model;
use crate::progress::ProgressHandle;
use crate::reach::Space;
use std::collections::BTreeSet;
use std::time::Instant;

/// Build a roadmap of `model` solved by `request`.
pub fn build(
    model: &Model,
    request: &SolveRequest,
    opts: &BuildOptions,
) -> Result<Roadmap, SolveError> {
    crate::counts::ROADMAP_SAMPLES.check(opts.samples)?;
    crate::counts::ROADMAP_EXPAND.check(opts.expand)?;
    crate::counts::ROADMAP_NEIGHBOURS.check(opts.neighbours)?;
    if let Some(s) = opts.shard {
        crate::counts::ROADMAP_SHARDS.check(s.count)?;
    }
    if !(opts.spread.is_finite() && opts.spread > 0.0 && opts.spread <= 1.0) {
        return Err(SolveError::InvalidInput {
            field: "spread".into(),
            reason: format!("must be in (0, 1], got {:e}", opts.spread),
        });
    }
    if let Some(m) = opts.margin {
        crate::model::bounds::CLEARANCE.check("margin", m)?;
    }
    let t0 = Instant::now();
    let space = Space::new(model, request, false)?;
    let margin = opts.margin.unwrap_or(space.margin);
    let progress = &opts.progress;
    progress.start("roadmap nodes", Some((opts.samples + opts.expand) as u64));
    let (nodes, node_solves) = super::roadmap_sample::sample_nodes(model, &space, margin, opts);
    progress.finish();
    let plain: Vec<RoadmapNode> = nodes.iter().map(plain_node).collect();
    let candidates = candidate_edges(&Metric::of(&space), &plain, opts.neighbours);
    let mine: Vec<(usize, usize)> = match opts.shard {
        Some(s) => candidates
            .into_iter()
            .enumerate()
            .filter(|(c, _)| c % s.count == s.index)
            .map(|(_, e)| e)
            .collect(),
        None => candidates,
    };
    progress.start("roadmap edges", Some(mine.len() as u64));
    let (checked, edge_solves) = check_edges(&space, margin, &nodes, &mine, progress);
    progress.finish();
    let (edges, edge_clearance) = checked.into_iter().flatten().unzip();
    Ok(Roadmap {
        format: FORMAT.into(),
        robot: model.robot.name.clone(),
        robot_fingerprint: crate::fingerprint::robot(&space.robot),
        space: space.input.name().into(),
        space_fingerprint: crate::fingerprint::space(&space),
        cables: space.cable_names(),
        lo: space.lo.clone(),
        hi: space.hi.clone(),
        method: request.method.name().into(),
        settings: settings_of(request),
        margin,
        scene: scene_fingerprint(&space.scene),
        seed: opts.seed,
        neighbours: opts.neighbours,
        nodes: plain,
        edges,
        edge_clearance,
        shard: opts.shard,
        build_solves: node_solves + edge_solves,
        build_time_s: t0.elapsed().as_secs_f64(),
    })
}

/// The pairs a build tries: each node with its `neighbours` nearest (by the planners'
/// metric), each pair once, in increasing order — the same list in every shard, so shard `k`
/// of `N` takes every `N`-th from the `k`-th and the shards together check each pair once.
fn candidate_edges(
    metric: &Metric,
    nodes: &[RoadmapNode],
    neighbours: usize,
) -> Vec<(usize, usize)> {
    use rayon::prelude::*;
    let near: Vec<Vec<usize>> = nodes
        .par_iter()
        .map(|n| nearest(metric, nodes, &n.u, neighbours + 1))
        .collect();
    let mut pairs = BTreeSet::new();
    for (i, js) in near.into_iter().enumerate() {
        for j in js {
            if i != j {
                pairs.insert((i.min(j), i.max(j)));
            }
        }
    }
    pairs.into_iter().collect()
}

/// Validated edge of a build: its nodes and its certified and measured clearances.
type Checked = Option<((usize, usize), [Option<f64>; 2])>;

/// Check `pairs` in parallel (one [`Checker`] per worker; an edge's check depends on its two
/// nodes only, so the answers do not depend on the threads): each pair's validated edge or
/// `None`, in the order of `pairs`, and the solves the checks took.
fn check_edges(
    space: &Space,
    margin: f64,
    nodes: &[Node],
    pairs: &[(usize, usize)],
    progress: &ProgressHandle,
) -> (Vec<Checked>, usize) {
    use rayon::prelude::*;
    let out: Vec<(Checked, usize)> = pairs
        .par_iter()
        .map_init(
            || Checker::new(space, margin),
            |ck, &(a, b)| {
                let before = ck.stats.solves;
                let edge = match ck.edge(&nodes[a], &nodes[b]) {
                    EdgeCheck::Clear {
                        certified,
                        measured,
                        ..
                    } => Some(((a, b), [super::finite(certified), super::finite(measured)])),
                    EdgeCheck::Blocked => None,
                };
                progress.advance(1);
                (edge, ck.stats.solves - before)
            },
        )
        .collect();
    let solves = out.iter().map(|x| x.1).sum();
    (out.into_iter().map(|x| x.0).collect(), solves)
}

fn plain_node(n: &Node) -> RoadmapNode {
    let t = n.shape.tip();
    RoadmapNode {
        u: n.u.clone(),
        tip: [t.x, t.y, t.z],
        clearance: n.clearance.is_finite().then_some(n.clearance),
    }
}
