//! Planning in a generated airway, shared by `examples/airway.rs` (one plan, drawn),
//! `examples/airway_benchmark.rs` (rates and times over seeds) and
//! `tests/inverse/airway_plan.rs` (the rates asserted):
//!
//! * [`Setup::new`]: an airway from a seed (`ccrkit::anatomy::generate`), written as a binary
//!   STL with a lumen scene beside it (`free = "inside"`), and the catheter
//!   `models/anatomy/airway_catheter.toml` with its port placed [`PORT_ABOVE_CARINA`] above the
//!   carina on the trachea's axis (`ccrkit::anatomy::tasks::entrance`): the tip of a
//!   bronchoscope parked in the lower trachea, whose working channel the catheter comes out of.
//! * [`Setup::tasks`]: targets labelled reachable the way `reach_random_ports` labels them:
//!   the tip of a forward solve of a sampled in-limit actuation whose shape keeps the margin
//!   from the wall, in the branch (and generation) the tip lies in (`tasks::branch_of`).
//! * [`dense_clearance`]: the independent check of a shape against the exact triangles (no
//!   grid, no pseudo-normals, no signed distances): the backbone beyond the port sampled every
//!   [`DENSE_STEP`], each sample's unsigned distance to the triangles (parry's point query on
//!   the plain mesh) less the body's radius and half the step; the first sample inside the
//!   mesh by ray parity (`tasks::inside_mesh`). The backbone is one curve from that sample,
//!   every point of it within half a step of a sample; so when the result is positive no
//!   point of the body reaches the surface and the whole body is on the first sample's side:
//!   inside the lumen, at least the result away from the wall.

// Each example includes this module and uses the part it needs.
#![allow(dead_code)]

use anyhow::{anyhow, Result};
use ccrkit::anatomy::tasks::{branch_of, entrance, inside_mesh};
use ccrkit::anatomy::{generate, Airway, AirwayOptions};
use ccrkit::method::run::SolveRequest;
use ccrkit::method::MethodKind;
use ccrkit::plan::{plan, Goal, PlanOptions};
use ccrkit::reach::{reach_in, ReachOptions, Space, Target};
use ccrkit::{Model, Scene, Shape};
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use parry3d::math::Vector as PVec;
use parry3d::query::PointQuery;
use parry3d::shape::TriMesh;
use std::path::Path;

/// Where the port is: on the trachea's axis, this far above its end (the carina) \[m\].
pub const PORT_ABOVE_CARINA: f64 = 0.025;
/// Generations of the benchmark's airways (31 branches, about 75 000 triangles).
pub const GENERATIONS: u32 = 4;
/// Spacing of the dense check's samples along the backbone \[m\].
pub const DENSE_STEP: f64 = 2.5e-4;
/// Largest bend a sampled actuation asks of a segment \[rad\].
pub const MAX_BEND: f64 = 1.2;

/// An airway, its lumen scene, the catheter through its port, and the exact triangles.
pub struct Setup {
    /// The generated airway.
    pub airway: Airway,
    /// The catheter with its port placed in the trachea.
    pub model: Model,
    /// `energy` with the airway as the scene.
    pub request: SolveRequest,
    /// The plain mesh of the dense check (no pseudo-normals, no grid).
    pub mesh: TriMesh,
}

/// A target: the tip of a clear forward solve of `u`.
#[derive(Debug, Clone)]
pub struct Task {
    /// The tip \[m\].
    pub tip: Vector3<f64>,
    /// The actuation that made it (shortenings, insertion, rotation).
    pub u: Vec<f64>,
    /// The generation of the branch it lies in.
    pub generation: u32,
}

impl Setup {
    /// Generate the airway of `seed` with `generations`, write `airway.stl` and `scene.toml`
    /// into `dir`, and place the catheter's port in its trachea.
    pub fn new(seed: u64, generations: u32, dir: &Path) -> Result<Setup> {
        let opts = AirwayOptions {
            seed,
            generations,
            ..AirwayOptions::default()
        };
        Setup::from_options(&opts, dir)
    }

    /// [`Setup::new`] for the airway of `opts` (a finer meshing cell, say).
    pub fn from_options(opts: &AirwayOptions, dir: &Path) -> Result<Setup> {
        let airway = generate(opts)?;
        std::fs::create_dir_all(dir)?;
        ccrkit::mesh::write(&dir.join("airway.stl"), &airway.vertices, &airway.triangles)?;
        ccrkit::output::write_file(
            dir.join("scene.toml"),
            "# The generated airway as a lumen: the robot keeps 0.5 mm inside it.\n\
             clearance = 0.0005\n\n[[obstacles]]\nname = \"airway\"\nshape = \"mesh\"\n\
             path = \"airway.stl\"\nfree = \"inside\"\n",
        )?;
        let scene = Scene::from_file(dir.join("scene.toml"))?;
        let root = env!("CARGO_MANIFEST_DIR");
        let mut model = Model::from_file(format!("{root}/models/anatomy/airway_catheter.toml"))?;
        let (at, axis) = entrance(&airway, opts.trachea_length - PORT_ABOVE_CARINA);
        let turn = UnitQuaternion::rotation_between(&Vector3::z(), &axis)
            .ok_or_else(|| anyhow!("the trachea points along −z"))?;
        let port = model
            .robot
            .port
            .as_mut()
            .ok_or_else(|| anyhow!("the catheter model has no port"))?;
        port.pose = Isometry3::from_parts(Translation3::from(at), turn);
        let request = SolveRequest::new(MethodKind::Energy).with_scene(Some(scene));
        let mesh = ccrkit::mesh::trimesh(&airway.vertices, &airway.triangles, None)?;
        Ok(Setup {
            airway,
            model,
            request,
            mesh,
        })
    }

    /// Write the catheter with its port placed (`catheter.toml`: the model file with the
    /// port's `position` and `orientation` set) into `dir`, beside `airway.stl` and
    /// `scene.toml`, for the command line (`ccrkit roadmap build DIR/catheter.toml --scene
    /// DIR/scene.toml`). Its path.
    pub fn write_model(&self, dir: &Path) -> Result<std::path::PathBuf> {
        let root = env!("CARGO_MANIFEST_DIR");
        let text = std::fs::read_to_string(format!("{root}/models/anatomy/airway_catheter.toml"))?;
        let port = self
            .model
            .robot
            .port
            .as_ref()
            .ok_or_else(|| anyhow!("the catheter model has no port"))?;
        let (p, q) = (port.pose.translation.vector, port.pose.rotation);
        let placed = format!(
            "position = [{:?}, {:?}, {:?}]\norientation = {{ quaternion = [{:?}, {:?}, {:?}, {:?}] }}",
            p.x, p.y, p.z, q.w, q.i, q.j, q.k
        );
        let line = "position = [0.0, 0.0, 0.095]";
        if !text.contains(line) {
            return Err(anyhow!(
                "the catheter model's port has no `{line}` to replace"
            ));
        }
        let path = dir.join("catheter.toml");
        ccrkit::output::write_file(&path, text.replace(line, &placed))?;
        Ok(path)
    }

    /// The actuation space (shortenings, insertion, rotation) with the airway.
    pub fn space(&self) -> Result<Space> {
        Ok(Space::new(&self.model, &self.request, false)?)
    }

    /// The retracted start: every cable at rest, the shallowest insertion, unturned.
    pub fn retracted(&self, space: &Space) -> Vec<f64> {
        let k = space.cables();
        let mut x = vec![0.0; k];
        x.extend([space.lo[k], 0.0]);
        x
    }

    /// `count` targets drawn from `seed` (at most `tries` forward solves), each the tip of a
    /// clear forward solve of an in-limit actuation, in a branch of generation at least
    /// `min_generation`. An actuation bends each segment by an angle up to [`MAX_BEND`]
    /// towards a direction (its cables shortened by `r θ cos(φ_c − φ)`, clipped to the
    /// limits), at a uniform insertion and rotation; one whose solve fails (a cable tied in
    /// the port asked to shorten) or that comes within the margin of the wall is not a target.
    pub fn tasks(
        &self,
        space: &Space,
        seed: u64,
        count: usize,
        min_generation: u32,
        tries: usize,
    ) -> Vec<Task> {
        let mut rng = ccrkit_test_support::rng::Rng(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1);
        let mut out = Vec::new();
        for _ in 0..tries {
            if out.len() == count {
                break;
            }
            let u = self.draw(space, &mut rng);
            let Ok(shape) = space.solve(&u, None) else {
                continue;
            };
            if !space.admissible(&shape) {
                continue;
            }
            let tip = shape.tip();
            let Some(b) = branch_of(&self.airway, &tip) else {
                continue;
            };
            let generation = self.airway.branches[b].generation;
            if generation >= min_generation {
                out.push(Task { tip, u, generation });
            }
        }
        out
    }

    /// One sampled actuation ([`Setup::tasks`]).
    pub fn draw(&self, space: &Space, rng: &mut ccrkit_test_support::rng::Rng) -> Vec<f64> {
        let robot = &self.model.robot;
        let k = space.cables();
        let ends: Vec<usize> = robot.cables.iter().map(|c| c.ends_at).collect();
        let mut segments = ends.clone();
        segments.sort_unstable();
        segments.dedup();
        let bends: Vec<(usize, f64, f64)> = segments
            .iter()
            .map(|&e| {
                (
                    e,
                    rng.range(0.0, MAX_BEND),
                    rng.range(0.0, std::f64::consts::TAU),
                )
            })
            .collect();
        let mut u: Vec<f64> = (0..k)
            .map(|c| {
                let (_, theta, phi) = bends
                    .iter()
                    .find(|b| b.0 == ends[c])
                    .copied()
                    .unwrap_or_default();
                let hole = robot.cables[c].hole(0);
                let (r, angle) = (hole.x.hypot(hole.y), hole.y.atan2(hole.x));
                (r * theta * (angle - phi).cos()).clamp(space.lo[c], space.hi[c])
            })
            .collect();
        u.push(rng.range(space.lo[k], space.hi[k]));
        u.push(rng.range(space.lo[k + 1], space.hi[k + 1]));
        u
    }
}

/// The smallest [`dense_clearance`] over a plan's waypoints \[m\].
pub fn plan_dense_clearance(setup: &Setup, plan: &ccrkit::plan::Plan) -> f64 {
    plan.waypoints
        .iter()
        .map(|w| dense_clearance(setup, &w.shape))
        .fold(f64::INFINITY, f64::min)
}

/// The dense clearance of `shape` (module docs) \[m\]: negative when the body reaches the
/// wall, `-∞` when the first sample beyond the port is outside the mesh.
pub fn dense_clearance(setup: &Setup, shape: &Shape) -> f64 {
    let r = setup.model.robot.body_radius();
    let port = shape
        .port
        .as_ref()
        .map(|p| (p.pose.translation.vector, p.pose.rotation * Vector3::z()));
    let beyond = |x: &Vector3<f64>| port.is_none_or(|(o, a)| a.dot(&(x - o)) > 0.0);
    let mut worst = f64::INFINITY;
    let mut first = true;
    for w in shape.backbone.windows(2) {
        let steps = ((w[1] - w[0]).norm() / DENSE_STEP).ceil().max(1.0) as usize;
        for j in 0..=steps {
            let p = w[0] + (w[1] - w[0]) * (j as f64 / steps as f64);
            if !beyond(&p) {
                continue;
            }
            if first {
                first = false;
                if !inside_mesh(&setup.airway.vertices, &setup.airway.triangles, &p) {
                    return f64::NEG_INFINITY;
                }
            }
            let d = setup
                .mesh
                .distance_to_local_point(PVec::new(p.x, p.y, p.z), true);
            worst = worst.min(d - r - DENSE_STEP / 2.0);
        }
    }
    worst
}

/// The `q`-quantile of `v` (sorted here; `NaN` when empty).
pub fn quantile(v: &mut [f64], q: f64) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    v[((v.len() - 1) as f64 * q).round() as usize]
}

/// CPU time of the calling thread \[s\] (Linux: `/proc/thread-self/schedstat`, in ns), or
/// the wall clock since `wall` where that is not available: on a shared machine the CPU time
/// is what the computation cost, the wall clock also counts the other programs' turns.
pub fn cpu_seconds(wall: std::time::Instant) -> f64 {
    std::fs::read_to_string("/proc/thread-self/schedstat")
        .ok()
        .and_then(|s| s.split_whitespace().next()?.parse::<f64>().ok())
        .map_or_else(|| wall.elapsed().as_secs_f64(), |ns| ns * 1e-9)
}

/// One target's outcome in [`measure`].
#[derive(Debug, Clone)]
pub struct Outcome {
    /// The target's generation.
    pub generation: u32,
    /// `reach` said reached, its answer solved again puts the tip within 1e-6 m of the
    /// target, and the answer is clear by the dense check.
    pub reached: bool,
    /// Wall time of the reach \[s\].
    pub reach_s: f64,
    /// CPU time of the reach \[s\] ([`cpu_seconds`]).
    pub reach_cpu_s: f64,
    /// Dense clearance of the reach's answer \[m\] (`-∞` when none).
    pub reach_dense: f64,
    /// `plan` found a path from the retracted catheter to the target's actuation, every
    /// waypoint clear by the dense check.
    pub planned: bool,
    /// Wall time of the plan, found or not \[s\] (cold: a new RRT-Connect search).
    pub plan_s: f64,
    /// CPU time of the plan \[s\] ([`cpu_seconds`]).
    pub plan_cpu_s: f64,
    /// Waypoints of the plan.
    pub waypoints: usize,
    /// Smallest dense clearance over the plan's waypoints \[m\] (`-∞` when none).
    pub plan_dense: f64,
    /// Why a reach or a plan failed (empty when both succeeded).
    pub reason: String,
}

/// Reach and plan `targets` targets at generation `depth` or deeper (at least 1: beyond the
/// trachea) in the airway of `seed` (files written in `dir`; at most `200 · targets` draws
/// per generation below the trachea asked for, squared).
pub fn measure(
    seed: u64,
    generations: u32,
    targets: usize,
    depth: u32,
    dir: &Path,
) -> Result<Vec<Outcome>> {
    let setup = Setup::new(seed, generations, dir)?;
    let space = setup.space()?;
    let depth = depth.max(1);
    let tries = 200 * targets * (depth * depth) as usize;
    let tasks = setup.tasks(&space, seed, targets, depth, tries);
    let mut out = Vec::new();
    for task in tasks {
        let mut reason = Vec::new();
        let t0 = std::time::Instant::now();
        let c0 = cpu_seconds(t0);
        let target = Target {
            tip: task.tip,
            tangent: None,
        };
        let r = reach_in(&space, &setup.model, &target, &ReachOptions::default());
        let reach_s = t0.elapsed().as_secs_f64();
        let reach_cpu_s = cpu_seconds(t0) - c0;
        let (reached, reach_dense) = match r {
            Ok(r) => {
                let again = space.solve_as_cli(&setup.model, &r.u);
                let dense = again
                    .as_ref()
                    .map_or(f64::NEG_INFINITY, |s| dense_clearance(&setup, s));
                let close = again.is_ok_and(|s| (s.tip() - task.tip).norm() <= 1e-6);
                if !r.reached {
                    reason.push(format!("reach: {}", r.reason));
                }
                (r.reached && close && dense >= 0.0, dense)
            }
            Err(e) => {
                reason.push(format!("reach: {e}"));
                (false, f64::NEG_INFINITY)
            }
        };
        let t1 = std::time::Instant::now();
        let c1 = cpu_seconds(t1);
        let p = plan(
            &setup.model,
            &setup.request,
            Some(setup.retracted(&space)),
            &Goal::Actuation(task.u.clone()),
            &PlanOptions::default(),
            None,
        );
        let plan_s = t1.elapsed().as_secs_f64();
        let plan_cpu_s = cpu_seconds(t1) - c1;
        let (planned, waypoints, plan_dense) = match p {
            Ok(p) => {
                let dense = plan_dense_clearance(&setup, &p);
                (dense >= 0.0, p.waypoints.len(), dense)
            }
            Err(e) => {
                reason.push(format!("plan: {e}"));
                (false, 0, f64::NEG_INFINITY)
            }
        };
        out.push(Outcome {
            generation: task.generation,
            reached,
            reach_s,
            reach_cpu_s,
            reach_dense,
            planned,
            plan_s,
            plan_cpu_s,
            waypoints,
            plan_dense,
            reason: reason.join("; "),
        });
    }
    Ok(out)
}
