//! Roadmaps built in shards and merged: for a build larger than one machine (or one process).
//!
//! Shard `k` of `N` ([`super::roadmap::BuildOptions::shard`]) samples the same nodes as the
//! whole build (each sample is seeded by its index, so the nodes do not depend on the threads
//! or the shard: `roadmap_sample.rs`; sampling is cheap beside the edges, each of whose checks
//! solves several shapes along it) and checks every `N`-th candidate edge starting at the
//! `k`-th, of the one sorted candidate list every shard computes alike. An edge's check depends
//! on its two nodes only, so [`merge`] — the union of the shards' edges, sorted — gives the
//! roadmap a single build gives, edge for edge (`tests/inverse/roadmap_shards.rs`); only the
//! build statistics differ (each shard's node solves count once per shard).
//!
//! ```text
//! ccrkit roadmap build robot.toml --shard 0/4 --out part0.json     # … one per machine
//! ccrkit roadmap merge part0.json part1.json part2.json part3.json --out roadmap.json
//! ```

use super::roadmap::Roadmap;
use crate::error::ModelError;

/// The roadmap the shards `parts` (of one build, any order) make together: refused by name
/// when a part is a whole roadmap, when the parts were built for different robots, scenes,
/// options or nodes, or when a shard is missing or given twice.
pub fn merge(mut parts: Vec<Roadmap>) -> Result<Roadmap, ModelError> {
    let bad = |field: &str, reason: String| Err(ModelError::invalid(field, reason));
    let Some(first) = parts.first() else {
        return bad("shards", "no roadmap shard given".into());
    };
    let Some(count) = first.shard.map(|s| s.count) else {
        return bad(
            "shard",
            "the first file is a whole roadmap, not a shard".into(),
        );
    };
    let mut seen = Vec::new();
    for (k, p) in parts.iter().enumerate() {
        let Some(s) = p.shard else {
            return bad("shard", format!("file {k} is a whole roadmap, not a shard"));
        };
        // Read files are checked already; a roadmap made in code is checked here, before
        // one flag per shard is allocated.
        super::roadmap::check_shard(s, &format!("file {k}"))?;
        seen.resize(count, false);
        if s.count != count || s.index >= count {
            return bad(
                "shard",
                format!(
                    "file {k} is shard {}/{}, the first is of {count}",
                    s.index, s.count
                ),
            );
        }
        if std::mem::replace(&mut seen[s.index], true) {
            return bad("shard", format!("shard {}/{count} is given twice", s.index));
        }
        if !same_build(first, p) {
            return bad(
                "shard",
                format!(
                    "file {k} (shard {}/{count}) was built for another robot, scene, method, \
                     options or seed, or sampled other nodes",
                    s.index
                ),
            );
        }
    }
    if let Some(missing) = seen.iter().position(|s| !s) {
        return bad("shard", format!("shard {missing}/{count} is missing"));
    }
    let solves = parts.iter().map(|p| p.build_solves).sum();
    let time = parts.iter().map(|p| p.build_time_s).sum();
    let mut edges = Vec::new();
    for p in &mut parts {
        if p.edge_clearance.len() != p.edges.len() {
            return bad(
                "edge_clearance",
                format!(
                    "shard {:?} has {} edges and {} clearance records",
                    p.shard,
                    p.edges.len(),
                    p.edge_clearance.len()
                ),
            );
        }
        edges.extend(p.edges.drain(..).zip(p.edge_clearance.drain(..)));
    }
    edges.sort_by_key(|e| e.0);
    if let Some(w) = edges.windows(2).find(|w| w[0].0 == w[1].0) {
        return bad("edges", format!("edge {:?} is in two shards", w[0].0));
    }
    let mut out = parts.swap_remove(0);
    (out.edges, out.edge_clearance) = edges.into_iter().unzip();
    out.shard = None;
    out.build_solves = solves;
    out.build_time_s = time;
    Ok(out)
}

/// Two parts of one build: everything but the edges, the shard and the statistics equal.
fn same_build(a: &Roadmap, b: &Roadmap) -> bool {
    build_of(a) == build_of(b)
}

/// What a roadmap's build is of: every field but the edges, the shard and the statistics (each
/// field named, so that a new one does not compile until placed on one side); the margin by
/// its bits.
fn build_of(r: &Roadmap) -> impl PartialEq + '_ {
    let Roadmap {
        format,
        robot,
        robot_fingerprint,
        space,
        space_fingerprint,
        cables,
        lo,
        hi,
        method,
        settings,
        margin,
        scene,
        seed,
        neighbours,
        nodes,
        edges: _,
        edge_clearance: _,
        shard: _,
        build_solves: _,
        build_time_s: _,
    } = r;
    (
        (format, robot, robot_fingerprint, space, space_fingerprint),
        (cables, lo, hi, method, settings),
        (margin.to_bits(), scene, seed, neighbours, nodes),
    )
}
