//! A roadmap for repeated queries (a probabilistic roadmap, Kavraki et al., IEEE T-RA 1996,
//! in the actuation space): `build` samples admissible actuations (seeded), solves them and
//! connects each to its nearest neighbours by validated edges ([`super::edge`]); `query`
//! connects a start and a goal to their nearest nodes, searches the graph (Dijkstra, lengths
//! in actuation space lengthened near obstacles), and hands the path to the same shortcut and output stage as the
//! single-query planner.
//!
//! A roadmap remembers the robot it was built for (a fingerprint of every field that shapes it,
//! [`crate::fingerprint::robot`]), the cable names and limits, the method and its settings, the
//! margin, a fingerprint of the obstacles (names, poses, bounds, clearance) and its space:
//! shortenings or tensions ([`Roadmap::space`], with a fingerprint of the space's unknowns,
//! limits and scales, [`crate::fingerprint::space`]). A query with another robot (a hole
//! radius of 4.0 mm instead of 4.5), cables, limits, method or space (a roadmap of tensions
//! asked for shortenings) is refused by name. Nothing in the file is believed about safety: the nodes and edges of each
//! candidate path are solved and checked again under the query's scene and margin, those that
//! fail are dropped and the search repeated ([`super::PlanStats::edges_repaired`]), so every
//! clearance a plan reports is measured in this run (a node's clearance edited to 0.5 m once
//! came back as "≥ 228 mm certified"). The stored clearances only weight the search.
//!
//! # Sampling biased to the free space
//!
//! Where the admissible actuations are a thin set of the limits box — the two-segment robot
//! inside the bent tube (`models/plan/vessel.toml`): about 1 uniform sample in 200 keeps the
//! margin — uniform samples leave the roadmap nearly empty. After the uniform phase
//! ([`BuildOptions::samples`], plus the model's own actuation) `build` therefore draws
//! [`BuildOptions::expand`] samples around admissible nodes: each picks a node already found
//! (seeded, uniformly) and adds a Gaussian step of standard deviation
//! [`BuildOptions::spread`] times each cable's range, clamped into the limits (the expansion
//! step of Kavraki et al. 1996, with Gaussian steps as in Boor, Overmars & van der Stappen,
//! "The Gaussian sampling strategy for probabilistic roadmap planners", ICRA 1999). Samples
//! that keep the margin join the roadmap, so it grows along the free space's connected parts
//! that the uniform phase touched.
//!
//! # Through a port
//!
//! Nodes are points `[u, d, ψ]` (shortenings, insertion \[m\], rotation \[rad\]), nearest
//! neighbours and path lengths are measured in the planners' metric ([`super::metric`]), every
//! `insert::ALONG_EVERY`-th uniform sample slides the last admissible uniform node before it
//! along its insertion (`roadmap_sample.rs`), and a query tries the staged insert-first paths (`insert`) before the
//! graph.

use super::metric::Metric;
pub use super::roadmap_build::build;
pub use super::roadmap_query::Queries;
use crate::error::{ModelError, SolveError};
use crate::method::run::SolveRequest;
use crate::model::scene::Scene;
use crate::progress::ProgressHandle;
use crate::reach::Space;
pub use crate::study::Shard;
use serde::{Deserialize, Serialize};

/// Format tag of roadmap files.
pub const FORMAT: &str = "ccrkit-roadmap-3";

/// How to build a roadmap.
#[derive(Debug, Clone)]
pub struct BuildOptions {
    /// Samples drawn (inadmissible ones are dropped).
    pub samples: usize,
    /// Neighbours each node tries to connect to.
    pub neighbours: usize,
    /// Seed.
    pub seed: u64,
    /// Margin \[m\] (default: the scene's `clearance`).
    pub margin: Option<f64>,
    /// Samples drawn around admissible nodes (see the module docs).
    pub expand: usize,
    /// Standard deviation of an expansion step, as a fraction of each cable's range.
    pub spread: f64,
    /// Build only this shard's edges (`None`: all); merge the shards with
    /// [`super::roadmap_shard::merge`] ([`super::roadmap_shard`]).
    pub shard: Option<Shard>,
    /// Where the build reports its progress (nodes, then edges).
    pub progress: ProgressHandle,
}

impl Default for BuildOptions {
    fn default() -> Self {
        BuildOptions {
            samples: 400,
            neighbours: 8,
            seed: 1,
            margin: None,
            expand: 400,
            spread: 0.1,
            shard: None,
            progress: ProgressHandle::none(),
        }
    }
}

/// One roadmap node.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RoadmapNode {
    /// Shortenings \[m\] (tensions \[N\] in tension space), then with a port the insertion
    /// \[m\] and the rotation \[rad\].
    pub u: Vec<f64>,
    /// Tip \[m\].
    pub tip: [f64; 3],
    /// Clearance \[m\] (absent without obstacles).
    pub clearance: Option<f64>,
}

/// A roadmap (JSON file).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Roadmap {
    /// [`FORMAT`].
    pub format: String,
    /// Robot name.
    pub robot: String,
    /// The robot's fingerprint ([`crate::fingerprint::robot`]).
    pub robot_fingerprint: String,
    /// The space its nodes are points of: `shortening` (cables' values in m) or `tension`
    /// (in N); absent in older files.
    #[serde(default)]
    pub space: String,
    /// The space's fingerprint ([`crate::fingerprint::space`]).
    #[serde(default)]
    pub space_fingerprint: String,
    /// Cable names.
    pub cables: Vec<String>,
    /// Lower limit of each unknown (\[m\] or \[N\] per cable, then \[m\], \[rad\]).
    pub lo: Vec<f64>,
    /// Upper limit of each unknown (as `lo`).
    pub hi: Vec<f64>,
    /// Method name and settings.
    pub method: String,
    /// Settings `NAME=VALUE`.
    pub settings: Vec<String>,
    /// Margin \[m\].
    pub margin: f64,
    /// Obstacle fingerprint.
    pub scene: String,
    /// Seed.
    pub seed: u64,
    /// Neighbours each node tried to connect to (`--neighbours`): the candidate edges, which
    /// the shards of one build must share (0 in a file written before it was recorded).
    #[serde(default)]
    pub neighbours: usize,
    /// Nodes.
    pub nodes: Vec<RoadmapNode>,
    /// Validated edges (node indices).
    pub edges: Vec<(usize, usize)>,
    /// Per edge: its certified and its smallest measured clearance \[m\] when built (infinite
    /// without obstacles, written as `null`); a record only: a query validates every edge it
    /// uses again.
    #[serde(default)]
    pub edge_clearance: Vec<[Option<f64>; 2]>,
    /// The shard of the edges this file holds (`None`: a whole roadmap); a shard is only
    /// input to [`super::roadmap_shard::merge`], never to a query.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shard: Option<Shard>,
    /// Build statistics: solves (of a merged roadmap: all shards', each of which samples the
    /// nodes again), build time \[s\] (of a merged roadmap: the shards' sum).
    pub build_solves: usize,
    /// Build time \[s\].
    pub build_time_s: f64,
}

/// A fingerprint of the obstacles: names, poses, bounds and the clearance
/// ([`crate::fingerprint::scene`]).
pub fn scene_fingerprint(scene: &Scene) -> String {
    crate::fingerprint::scene(scene)
}

pub(super) fn settings_of(request: &SolveRequest) -> Vec<String> {
    request
        .settings
        .iter()
        .map(|(k, v)| format!("{k}={v}"))
        .collect()
}

/// The `k` nearest of `nodes` to `u` (indices, nearest first).
pub(super) fn nearest(metric: &Metric, nodes: &[RoadmapNode], u: &[f64], k: usize) -> Vec<usize> {
    let mut d: Vec<(f64, usize)> = nodes
        .iter()
        .enumerate()
        .map(|(i, n)| (metric.dist(&n.u, u), i))
        .collect();
    // A total order (distance, then index): the same k and order as a full sort.
    let order = |a: &(f64, usize), b: &(f64, usize)| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1));
    if k < d.len() {
        d.select_nth_unstable_by(k, order);
        d.truncate(k);
    }
    d.sort_by(order);
    d.into_iter().map(|x| x.1).collect()
}

/// A shard `s` a roadmap says it is (`p` names where it came from): `k/N` with `0 <= k < N`
/// and N within [`crate::counts::ROADMAP_SHARDS`], else `Invalid` naming `shard`.
pub(super) fn check_shard(s: Shard, p: &str) -> Result<(), ModelError> {
    let n = crate::counts::ROADMAP_SHARDS;
    if s.index < s.count && n.check(s.count).is_ok() {
        return Ok(());
    }
    Err(ModelError::invalid(
        "shard",
        format!(
            "`{p}` says shard {}/{}: expected k/N with 0 <= k < N <= {}",
            s.index, s.count, n.max
        ),
    ))
}

impl Roadmap {
    /// Read a roadmap file.
    pub fn load(path: &std::path::Path) -> Result<Roadmap, ModelError> {
        let text = crate::model::read::read_text(path, "roadmap")?;
        Roadmap::from_json(&text, &path.display().to_string())
    }

    /// A roadmap from its JSON text (`name` says where it came from in errors), with the
    /// checks [`Roadmap::load`] makes.
    pub fn from_json(text: &str, name: &str) -> Result<Roadmap, ModelError> {
        let p = name;
        let r: Roadmap = serde_json::from_str(text).map_err(|e| ModelError::Parse {
            path: p.to_string(),
            reason: e.to_string(),
        })?;
        if r.format != FORMAT {
            return Err(ModelError::invalid(
                "format",
                format!(
                    "`{p}` is `{}`, expected `{FORMAT}` (older roadmaps name no robot \
                     fingerprint or space: build it again)",
                    r.format
                ),
            ));
        }
        if let Some(s) = r.shard {
            check_shard(s, p)?;
        }
        let n = r.nodes.len();
        if let Some(e) = r.edges.iter().find(|e| e.0 >= n || e.1 >= n) {
            return Err(ModelError::invalid(
                "edges",
                format!("edge {e:?} names a node beyond the {n} nodes"),
            ));
        }
        Ok(r)
    }

    /// Write the roadmap as JSON, atomically ([`crate::output`]).
    pub fn save(&self, path: &std::path::Path) -> Result<(), ModelError> {
        let text = self.to_json(&path.display().to_string())?;
        Ok(crate::output::write_file(path, text.as_bytes())?)
    }

    /// The roadmap's JSON text (what [`Roadmap::save`] writes; `name` for errors).
    pub fn to_json(&self, name: &str) -> Result<String, ModelError> {
        serde_json::to_string(self).map_err(|e| ModelError::Parse {
            path: name.to_string(),
            reason: e.to_string(),
        })
    }

    pub(super) fn check_fits(
        &self,
        space: &Space,
        request: &SolveRequest,
    ) -> Result<(), SolveError> {
        let bad = |reason: String| {
            Err(SolveError::InvalidInput {
                field: "roadmap".into(),
                reason,
            })
        };
        if let Some(s) = self.shard {
            return bad(format!(
                "is shard {}/{} of a roadmap: merge the shards first (`ccrkit roadmap merge`)",
                s.index, s.count
            ));
        }
        let robot = crate::fingerprint::robot(&space.robot);
        if self.robot_fingerprint != robot {
            return Err(SolveError::InvalidInput {
                field: "roadmap.robot_fingerprint".into(),
                reason: format!(
                    "the roadmap was built for robot `{}` with fingerprint {}; this model's robot \
                     `{}` has {} (a hole, a disk, the backbone or a cable's routing differs): \
                     build a roadmap for this robot",
                    self.robot, self.robot_fingerprint, space.robot.name, robot
                ),
            });
        }
        if self.space != space.input.name() {
            return Err(SolveError::InvalidInput {
                field: "roadmap.space".into(),
                reason: format!(
                    "the roadmap was built in {} space; `{}` with these settings drives cables \
                     by {}: build a roadmap with the same --method and --set",
                    self.space,
                    request.method.name(),
                    space.input.name()
                ),
            });
        }
        if self.cables != space.cable_names() || self.lo != space.lo || self.hi != space.hi {
            return bad(format!(
                "built for cables {:?} with limits {:?} … {:?}; this model has {:?}, {:?} … {:?}",
                self.cables,
                self.lo,
                self.hi,
                space.cable_names(),
                space.lo,
                space.hi
            ));
        }
        if self.method != request.method.name() || self.settings != settings_of(request) {
            return bad(format!(
                "built with {} {:?}, asked for {} {:?}",
                self.method,
                self.settings,
                request.method.name(),
                settings_of(request)
            ));
        }
        if self.space_fingerprint != crate::fingerprint::space(space) {
            return Err(SolveError::InvalidInput {
                field: "roadmap.space_fingerprint".into(),
                reason: format!(
                    "the roadmap's {} space (fingerprint {}) differs from this model's ({}): \
                     its cables, limits or scales changed",
                    self.space,
                    self.space_fingerprint,
                    crate::fingerprint::space(space)
                ),
            });
        }
        super::roadmap_nodes::check(self, space)
    }
}
