//! A roadmap's nodes ([`super::roadmap`]'s module docs, "Sampling biased to the free space"),
//! solved in parallel and the same on any number of threads.
//!
//! Each sample draws its numbers from its own generator, seeded by the build's seed and the
//! sample's index ([`sample_rng`]), so a sample is the same whichever thread solves it and
//! whatever was solved before. The samples are solved in three parallel phases, each from what
//! the phases before found, and the admissible ones kept in the order of their index:
//!
//! 1. the model's own actuation and the uniform samples (cold solves);
//! 2. through a port, every [`super::insert::ALONG_EVERY`]-th sample index instead slides the
//!    last admissible uniform node before it along its insertion (warm from it);
//! 3. the expansion, in rounds: a round of as many samples as nodes known (at least
//!    [`ROUND_MIN`]) picks its nodes among those known when it starts, so the rounds — and the
//!    nodes — do not depend on the threads.
//!
//! Before (one sequential pass) sampling took half the CPU of the default airway build, all on
//! one core while the edges ran on every core.

use super::edge::{Checker, Node};
use super::roadmap::BuildOptions;
use crate::model::Model;
use crate::reach::Space;
use rand_core::SeedableRng;
use rand_xorshift::XorShiftRng;
use rayon::prelude::*;

/// Fewest samples in one expansion round (module docs): small rounds leave cores idle.
const ROUND_MIN: usize = 64;

/// The generator of sample `index` of the build seeded `seed` (SplitMix64 of the two, so
/// neighbouring indices and seeds give unrelated streams).
pub(super) fn sample_rng(seed: u64, index: u64) -> XorShiftRng {
    let mut z = seed
        .wrapping_mul(0x9E37_79B9_7F4A_7C15)
        .wrapping_add(index.wrapping_add(1).wrapping_mul(0xBF58_476D_1CE4_E5B9));
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    XorShiftRng::seed_from_u64(z ^ (z >> 31))
}

/// What one sample solves: its actuation and the node it is warm-started from.
type Job = (Vec<f64>, Option<usize>);

/// Solve `jobs` in parallel against `known` warm starts (one [`Checker`] per worker: the
/// hint it keeps changes only the cost), each job's node or `None`, in the order of `jobs`.
fn solve_all(
    space: &Space,
    margin: f64,
    known: &[Node],
    jobs: &[Job],
    opts: &BuildOptions,
) -> Vec<Option<Node>> {
    jobs.par_iter()
        .map_init(
            || Checker::new(space, margin),
            |ck, (u, warm)| {
                opts.progress.advance(1);
                ck.node(u, warm.map(|k| &known[k].shape))
            },
        )
        .collect()
}

/// The admissible nodes of a build (module docs) and the solves they took.
pub(super) fn sample_nodes(
    model: &Model,
    space: &Space,
    margin: f64,
    opts: &BuildOptions,
) -> (Vec<Node>, usize) {
    let unit = super::rrt::unit;
    let along = |i: usize| space.has_port() && i.is_multiple_of(super::insert::ALONG_EVERY);
    // Phase 1: the model's own actuation (index 0) and the uniform samples.
    let own = super::actuation_of_in(model, &model.actuation, space.input);
    let mut jobs: Vec<(usize, Job)> = Vec::new();
    if space.contains(&own) {
        jobs.push((0, (own, None)));
    }
    for i in (1..=opts.samples).filter(|&i| !along(i)) {
        let mut rng = sample_rng(opts.seed, i as u64);
        let u: Vec<f64> = space
            .lo
            .iter()
            .zip(&space.hi)
            .map(|(l, h)| l + unit(&mut rng) * (h - l))
            .collect();
        jobs.push((i, (u, None)));
    }
    let mut solves = jobs.len();
    let first = solve_all(
        space,
        margin,
        &[],
        &jobs.iter().map(|j| j.1.clone()).collect::<Vec<_>>(),
        opts,
    );
    let mut found: Vec<(usize, Node)> = jobs
        .iter()
        .zip(first)
        .filter_map(|((i, _), n)| n.map(|n| (*i, n)))
        .collect();
    // Phase 2: along the insertion, from the last admissible uniform node before the index.
    let mut slides: Vec<(usize, Job)> = Vec::new();
    for i in (1..=opts.samples).filter(|&i| along(i)) {
        let Some(k) = found.iter().rposition(|(j, _)| *j < i) else {
            continue;
        };
        let mut rng = sample_rng(opts.seed, i as u64);
        let u = super::insert::along_insertion(space, &found[k].1.u, &mut rng);
        slides.push((i, (u, Some(k))));
    }
    let uniform: Vec<Node> = found.iter().map(|x| x.1.clone()).collect();
    solves += slides.len();
    let slid = solve_all(
        space,
        margin,
        &uniform,
        &slides.iter().map(|j| j.1.clone()).collect::<Vec<_>>(),
        opts,
    );
    found.extend(
        slides
            .iter()
            .zip(slid)
            .filter_map(|((i, _), n)| n.map(|n| (*i, n))),
    );
    found.sort_by_key(|x| x.0);
    let mut nodes: Vec<Node> = found.into_iter().map(|x| x.1).collect();
    // Phase 3: the expansion, in rounds.
    let mut next = opts.samples + 1;
    let end = opts.samples + opts.expand;
    while next <= end && !nodes.is_empty() {
        let round = nodes.len().max(ROUND_MIN).min(end + 1 - next);
        let jobs: Vec<Job> = (next..next + round)
            .map(|i| {
                let mut rng = sample_rng(opts.seed, i as u64);
                let k = (unit(&mut rng) * nodes.len() as f64) as usize % nodes.len();
                let u: Vec<f64> = (0..space.dim())
                    .map(|c| {
                        let range = space.hi[c] - space.lo[c];
                        nodes[k].u[c] + opts.spread * range * gaussian(&mut rng)
                    })
                    .collect();
                (space.clamp(&u), Some(k))
            })
            .collect();
        solves += jobs.len();
        let out = solve_all(space, margin, &nodes, &jobs, opts);
        nodes.extend(out.into_iter().flatten());
        next += round;
    }
    (nodes, solves)
}

/// A standard normal number (Box–Muller on two uniform numbers of the generator).
fn gaussian(rng: &mut XorShiftRng) -> f64 {
    let a = 1.0 - super::rrt::unit(rng);
    let b = super::rrt::unit(rng);
    (-2.0 * a.ln()).sqrt() * (std::f64::consts::TAU * b).cos()
}
