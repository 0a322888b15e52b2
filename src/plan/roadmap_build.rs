//! Building a roadmap ([`super::roadmap`]'s module docs): seeded uniform samples, samples
//! along the insertion through a port and Gaussian expansion around admissible nodes (one
//! sequential pass, the same in every shard), then every candidate edge — each node with its
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
use rand_core::SeedableRng;
use rand_xorshift::XorShiftRng;
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
    if !(opts.spread.is_finite() && opts.spread > 0.0 && opts.spread <= 1.0) {
        return Err(SolveError::InvalidInput {
            field: "spread".into(),
            reason: format!("must be in (0, 1], got {}", opts.spread),
        });
    }
    let t0 = Instant::now();
    let space = Space::new(model, request, false)?;
    let margin = opts.margin.unwrap_or(space.margin);
    let mut ck = Checker::new(&space, margin);
    let mut rng = XorShiftRng::seed_from_u64(opts.seed);
    let progress = &opts.progress;
    progress.start("roadmap nodes", Some((opts.samples + opts.expand) as u64));
    let nodes = sample_nodes(model, &mut ck, opts, &mut rng);
    progress.finish();
    let plain: Vec<RoadmapNode> = nodes.iter().map(plain_node).collect();
    let candidates = candidate_edges(&ck.metric, &plain, opts.neighbours);
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
        nodes: plain,
        edges,
        edge_clearance,
        shard: opts.shard,
        build_solves: ck.stats.solves + edge_solves,
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
    let mut pairs = BTreeSet::new();
    for (i, n) in nodes.iter().enumerate() {
        for j in nearest(metric, nodes, &n.u, neighbours + 1) {
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

/// The admissible nodes of a build: uniform samples and the model's actuation, then the
/// expansion around them (module docs).
fn sample_nodes(
    model: &Model,
    ck: &mut Checker,
    opts: &BuildOptions,
    rng: &mut XorShiftRng,
) -> Vec<Node> {
    let space = ck.space;
    let unit = super::rrt::unit;
    let mut nodes: Vec<Node> = Vec::new();
    let own = super::actuation_of_in(model, &model.actuation, space.input);
    if space.contains(&own) {
        nodes.extend(ck.node(&own, None));
    }
    for i in 1..=opts.samples {
        opts.progress.advance(1);
        // Through a port every few samples slide the last admissible node along its
        // insertion (`insert.rs`), warm from it.
        if space.has_port() && i % super::insert::ALONG_EVERY == 0 && !nodes.is_empty() {
            let last = nodes[nodes.len() - 1].clone();
            let u = super::insert::along_insertion(space, &last.u, rng);
            nodes.extend(ck.node(&u, Some(&last.shape)));
            continue;
        }
        let u: Vec<f64> = space
            .lo
            .iter()
            .zip(&space.hi)
            .map(|(l, h)| l + unit(rng) * (h - l))
            .collect();
        nodes.extend(ck.node(&u, None));
    }
    for _ in 0..opts.expand {
        opts.progress.advance(1);
        if nodes.is_empty() {
            break;
        }
        let k = (unit(rng) * nodes.len() as f64) as usize % nodes.len();
        let u: Vec<f64> = (0..space.dim())
            .map(|c| {
                let range = space.hi[c] - space.lo[c];
                nodes[k].u[c] + opts.spread * range * gaussian(rng)
            })
            .collect();
        let u = space.clamp(&u);
        let warm = nodes[k].shape.clone();
        nodes.extend(ck.node(&u, Some(&warm)));
    }
    nodes
}

/// A standard normal number (Box–Muller on two uniform numbers of the generator).
fn gaussian(rng: &mut XorShiftRng) -> f64 {
    let a = 1.0 - super::rrt::unit(rng);
    let b = super::rrt::unit(rng);
    (-2.0 * a.ln()).sqrt() * (std::f64::consts::TAU * b).cos()
}

fn plain_node(n: &Node) -> RoadmapNode {
    let t = n.shape.tip();
    RoadmapNode {
        u: n.u.clone(),
        tip: [t.x, t.y, t.z],
        clearance: n.clearance.is_finite().then_some(n.clearance),
    }
}
