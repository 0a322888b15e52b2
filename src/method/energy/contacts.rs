//! Obstacles in the whole-robot energy model: distance constraints with exact first
//! derivatives in the strains, for the sequential-QP solver of [`super`].
//!
//! # Features and constraints
//!
//! The same robot features as the section solver ([`crate::method::geometric`]), at the
//! energy model's resolution:
//!
//! * **backbone**: one capsule of the backbone radius per sub-arc, between the sub-arc's end
//!   points (the arc between them bulges by at most `ℓ² κ / 8`: 2.5 µm for a 5 mm sub-arc at
//!   κ = 8 /m; raise [`super::Energy::sub_arcs`] to shrink it);
//! * **disks**: thin cylinders (radius, thickness of the robot's disks) at every disk frame;
//! * **cables**: the straight chord between the cable's holes on consecutive disks (what the
//!   section solver constrains and what [`crate::shape::CablePath`] draws).
//!
//! Each feature–obstacle pair closer than a margin gives one constraint
//! `c = clearance − d(ξ) ≤ 0` on the signed distance `d` from parry3d. The energy is in J and
//! `d` in m, so the multiplier of the constraint is a force \[N\]: the normal reaction the
//! obstacle puts on the robot (reported in [`crate::shape::Contact::multiplier`]).
//!
//! # Derivative of a point with respect to the strains
//!
//! Raising the body twist `u` by `δu` on `ds` at arc length `s` turns everything beyond `s`
//! about `p(s)` by the world angle `R(s) δu ds`; raising the stretch `ε` translates it by
//! `R(s) e_z δε ds` (from `p' = R v`, `R' = R û`, R&W eq. 1). The strains are constant on a
//! sub-arc `j`, so a world point `x` carried by a frame beyond it moves as
//!
//! ```text
//! ∂x/∂u_a = ∫_j (R e_a) × (x − p) ds = (M_j e_a) × x − N_{j,a},   a = κx, κy, τ
//! ∂x/∂ε   = ∫_j R e_z ds          = M_j e_z
//! M_j = ∫_j R ds,   N_{j,a} = ∫_j (R e_a) × p ds
//! ```
//!
//! (`M_j`, `N_j` by 5-point Gauss–Legendre on the sub-arc's closed-form exponential; the
//! integrand is analytic, so the error is far below round-off for the rotations a sub-arc
//! makes.) With `n̂` the unit normal from the obstacle towards the robot, `∂d = n̂ · ∂x`, i.e.
//! `∂d/∂u_a = (M_jᵀ (x × n̂))_a − n̂ · N_{j,a}` and `∂d/∂ε = (M_jᵀ n̂)_z`. A witness point at
//! fraction `t` of a segment between points carried by frames `f_a ≤ f_b` moves as
//! `(1 − t) ∂a + t ∂b` (at the closest point the derivative in `t` vanishes). A unit test
//! checks the gradient against central differences of the distance.
//!
//! The constraint curvature `−μ ∇²d` of a pressing pair couples every sub-arc upstream of the
//! contact; it enters the Lagrangian Hessian in the block semiseparable form of
//! `energy/curvature.rs` (derivation of `∇²d` in `energy/contact_curvature.rs`).

use super::kinematics::{sheared_exp, GL_NODES, GL_W, GL_X};
use crate::contact::features::{self, Touching};
use crate::contact::parry::SEPARATION_SHIFT;
use crate::contact::primitives::{self, Convex};
use crate::contact::{broad, polish, Witness};
use crate::model::robot::Robot;
use crate::model::scene::Scene;
use crate::shape::Contact;
use nalgebra::{Matrix3, Vector3};
use parry3d::math::Pose as PPose;
use parry3d::shape::Shape as PShape;

/// Pairs closer than this get [`EXTRA_POLISH`] more rounds of the witness polish \[m\].
const TOUCHING: f64 = 1e-4;

/// Extra rounds of [`polish`] (4 alternating projections each) for a disk near touching.
const EXTRA_POLISH: usize = 9;

/// A robot feature.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Feat {
    /// Backbone capsule of sub-arc `j` (1-based).
    Backbone(usize),
    /// Disk `k` (1-based; the base disk is checked once, before solving).
    Disk(usize),
    /// Chord of cable `c` in section `i`.
    Cable(usize, usize),
}

/// One feature–obstacle pair, linearized.
pub(super) struct Pair {
    /// Obstacle index in the scene.
    pub obstacle: usize,
    pub feat: Feat,
    /// Signed distance \[m\].
    pub dist: f64,
    /// `∂d/∂ξ` (empty when only distances were asked for).
    pub grad: Vec<f64>,
    pub point_robot: Vector3<f64>,
    pub point_obstacle: Vector3<f64>,
    /// Unit normal from the obstacle towards the robot.
    pub normal: Vector3<f64>,
    /// How the feature moves with the frames.
    pub ends: Ends,
    /// `None` for the feature's closest pair with the obstacle; a triangle of a solid mesh for
    /// one of its face contacts ([`crate::contact::solid::face_contacts`]; the closest pair is
    /// then the one of smallest distance among them, or a `None` pair closer still).
    pub part: Option<u32>,
    /// The triangle of a solid mesh the obstacle's witness lies on (the face's for a face
    /// contact), `None` for other obstacles: where the next query of this feature starts
    /// its closest-triangle search ([`crate::contact::parry::query_hinted`]).
    pub triangle: Option<u32>,
}

/// Identity of a pair across iterations: obstacle, feature, face ([`Pair::part`]).
pub(super) type PairKey = (usize, Feat, Option<u32>);

impl Pair {
    /// Identity of the pair across iterations.
    pub fn key(&self) -> PairKey {
        (self.obstacle, self.feat, self.part)
    }
}

/// Frames at every sub-arc end, and the integrals `M_j`, `N_j` of every sub-arc.
pub(super) struct Kin {
    pub rot: Vec<Matrix3<f64>>,
    pub pos: Vec<Vector3<f64>>,
    pub m_int: Vec<Matrix3<f64>>,
    pub n_int: Vec<[Vector3<f64>; 3]>,
}

/// Forward kinematics of the strains `xi` (sub-arc lengths `ell`, no shear); with
/// `integrals`, also `M_j`, `N_j` for the gradients.
#[cfg(test)]
pub(super) fn kinematics(xi: &[f64], ell: &[f64], integrals: bool) -> Kin {
    sheared_kinematics(xi, &[], ell, integrals)
}

/// [`kinematics`] with the shear strains `shear[j]` of every sub-arc (empty: none;
/// `energy/shear.rs`). The derivatives above hold unchanged: `p` integrates `R v` whatever
/// `v` is, and `∂x/∂v_a = M_j e_a` for each axis `a`.
pub(super) fn sheared_kinematics(
    xi: &[f64],
    shear: &[[f64; 2]],
    ell: &[f64],
    integrals: bool,
) -> Kin {
    let nsub = ell.len();
    let mut kin = Kin {
        rot: Vec::with_capacity(nsub + 1),
        pos: Vec::with_capacity(nsub + 1),
        m_int: Vec::with_capacity(if integrals { nsub } else { 0 }),
        n_int: Vec::with_capacity(if integrals { nsub } else { 0 }),
    };
    let (mut r, mut p) = (Matrix3::identity(), Vector3::zeros());
    kin.rot.push(r);
    kin.pos.push(p);
    for j in 0..nsub {
        let x = &xi[4 * j..4 * j + 4];
        let g = shear.get(j).copied().unwrap_or_default();
        if integrals {
            let mut mi = Matrix3::zeros();
            let mut ni = [Vector3::zeros(); 3];
            for q in 0..GL_NODES {
                let w = 0.5 * ell[j] * GL_W[q];
                let (rl, pl) = sheared_exp(x, g, 0.5 * ell[j] * (1.0 + GL_X[q]));
                let rs = r * rl;
                let ps = p + r * pl;
                mi += rs * w;
                for (a, na) in ni.iter_mut().enumerate() {
                    *na += rs.column(a).cross(&ps) * w;
                }
            }
            kin.m_int.push(mi);
            kin.n_int.push(ni);
        }
        let (rl, pl) = sheared_exp(x, g, ell[j]);
        p += r * pl;
        r *= rl;
        kin.rot.push(r);
        kin.pos.push(p);
    }
    kin
}

/// The obstacles that can matter for this robot, and its feature sizes.
pub(super) struct World<'a> {
    pub(super) scene: &'a Scene,
    pub(super) robot: &'a Robot,
    /// Scene indices kept by the robot-level broad phase.
    pub(super) near: Vec<usize>,
    /// Pairs farther apart than this are left out of the step \[m\].
    pub(super) margin: f64,
    /// Sub-arc index at which each section starts, then the total (`Problem::first`).
    pub(super) first: Vec<usize>,
}

impl<'a> World<'a> {
    /// `None` when no obstacle comes within reach of the robot (the broad phase: a ball of
    /// the robot's length plus disk radius around the base).
    pub fn new(
        robot: &'a Robot,
        scene: &'a Scene,
        near: Vec<usize>,
        first: Vec<usize>,
    ) -> Option<Self> {
        if near.is_empty() {
            return None;
        }
        let lmax = (1..=robot.sections())
            .map(|i| robot.section_length(i))
            .fold(0.0, f64::max);
        Some(World {
            scene,
            robot,
            near,
            margin: scene.clearance + 0.5 * lmax,
            first,
        })
    }

    /// The scene's clearance \[m\].
    pub fn clearance(&self) -> f64 {
        self.scene.clearance
    }

    /// Pairs farther apart than this are left out of a step \[m\].
    pub fn margin(&self) -> f64 {
        self.margin
    }

    /// A feature this close to a solid mesh's wall gets the faces beside its closest triangle
    /// within the same distance as pairs of their own ([`crate::contact::solid::face_contacts`]):
    /// the clearance plus a tenth of the longest section \[m\].
    pub fn face_band(&self) -> f64 {
        let clearance = self.scene.clearance;
        clearance + 0.2 * (self.margin - clearance)
    }

    /// Obstacles kept by the broad phase.
    pub fn obstacle_count(&self) -> usize {
        self.near.len()
    }

    /// How far any point of the robot moves between two states, bounded above: the largest
    /// move of a sub-arc end plus the disk radius times the largest change of its frame
    /// (`|ΔR|_F` bounds `|ΔR x|` for `|x| ≤ 1`) \[m\].
    pub fn max_move(&self, a: &Kin, b: &Kin) -> f64 {
        let r = self.robot.disk_radius.max(self.robot.body_radius());
        a.pos
            .iter()
            .zip(&b.pos)
            .zip(a.rot.iter().zip(&b.rot))
            .map(|((pa, pb), (ra, rb))| (pb - pa).norm() + r * (rb - ra).norm())
            .fold(0.0, f64::max)
    }

    /// Add `w ∂d/∂ξ` of a point `x` carried by frame `f` (sub-arcs `1..=f` move it), `n` the
    /// unit normal from the obstacle to the robot (module docs).
    fn point_grad(kin: &Kin, f: usize, x: &Vector3<f64>, n: &Vector3<f64>, w: f64, g: &mut [f64]) {
        if w == 0.0 {
            return;
        }
        let xn = x.cross(n);
        for j in 0..f {
            let m = &kin.m_int[j];
            let mc = m.tr_mul(&xn);
            let mn = m.tr_mul(n);
            let nj = &kin.n_int[j];
            g[4 * j] += w * (mc.x - n.dot(&nj[0]));
            g[4 * j + 1] += w * (mc.y - n.dot(&nj[1]));
            g[4 * j + 2] += w * (mc.z - n.dot(&nj[2]));
            g[4 * j + 3] += w * mn.z;
        }
    }

    /// Every feature–obstacle pair within the margin at `kin`, with gradients if `kin` carries
    /// the integrals, and a lower bound on the distance between the robot and the obstacles:
    /// the smallest distance found, the margin for a pair beyond it, or the distance to the
    /// bounds of an obstacle not queried.
    pub fn pairs(&self, kin: &Kin) -> (Vec<Pair>, f64) {
        self.pairs_near(kin, &[])
    }

    /// [`World::pairs`] at a state close to the one where `hints` were found (a line search's
    /// trial point and its iterate): a pair that was near touching there is queried from its
    /// old normal at once ([`features::witness_near`]), without the query that would run EPA
    /// when the two barely overlap. The same pairs, witnesses equal to GJK's tolerance.
    pub fn pairs_near(&self, kin: &Kin, hints: &[Pair]) -> (Vec<Pair>, f64) {
        self.pairs_until(kin, hints, None)
            .expect("no stop rule: every pair is queried")
    }

    /// [`World::pairs_near`] that gives up (`None`) as soon as `stop.rejects` is true of the
    /// pairs found so far (asked each time a pair closer than `stop.clearance` is found, in
    /// the order of the returned pairs). The rule must be monotone in the pairs found (true
    /// of a prefix ⇒ true of every longer one, as for a sum of the non-negative terms
    /// `max(0, clearance − d)`). A call that does not give up returns what
    /// [`World::pairs_near`] returns, to the bit.
    pub fn pairs_until(
        &self,
        kin: &Kin,
        hints: &[Pair],
        stop: Option<Stop<'_>>,
    ) -> Option<(Vec<Pair>, f64)> {
        let (lo, hi) = self.robot_box(kin);
        let (candidates, clear) = broad::within_box(self.scene, &self.near, &lo, &hi, self.margin);
        let mut q = Collect {
            world: self,
            kin,
            candidates,
            hints,
            clear,
            out: vec![],
            stop,
            stopped: false,
        };
        let robot = self.robot;
        let nsub = kin.pos.len() - 1;
        let parts = features::BodyParts::of(robot);
        let rb = parts.radius;
        let (rd, ht) = (robot.disk_radius, robot.disk_thickness / 2.0);
        let identity = PPose::IDENTITY;
        for j in 1..=nsub {
            let (pa, pb) = (kin.pos[j - 1], kin.pos[j]);
            q.feature(
                Feat::Backbone(j),
                (&features::backbone(&pa, &pb, rb), &identity),
                || Convex::Segment(pa, pb, rb),
                (0.5 * (pa + pb), 0.5 * (pb - pa).norm() + rb),
                Ends::Segment((j - 1, pa), (j, pb)),
            );
        }
        let disk = features::disk(robot);
        // A rod without spacer disks has stations, no disks; cables inside the rod are inside
        // its body (which meets the world for them).
        let disks = if parts.disks { robot.sections() } else { 0 };
        for k in 1..=disks {
            let f = self.first[k];
            q.feature(
                Feat::Disk(k),
                (&disk, &features::disk_pose(&kin.rot[f], &kin.pos[f])),
                || Convex::Disk(kin.rot[f], kin.pos[f], rd, ht),
                (kin.pos[f], (rd * rd + ht * ht).sqrt()),
                Ends::Rigid(f),
            );
        }
        let exposed = parts.cables;
        for (c, cable) in robot.cables.iter().enumerate().filter(|_| exposed) {
            for i in 1..=cable.ends_at {
                let (fa, fb) = (self.first[i - 1], self.first[i]);
                let pa = kin.pos[fa] + kin.rot[fa] * cable.hole(i - 1);
                let pb = kin.pos[fb] + kin.rot[fb] * cable.hole(i);
                if (pb - pa).norm() == 0.0 {
                    continue;
                }
                q.feature(
                    Feat::Cable(c, i),
                    (&features::chord(&pa, &pb), &identity),
                    || Convex::Segment(pa, pb, 0.0),
                    (0.5 * (pa + pb), 0.5 * (pb - pa).norm()),
                    Ends::Segment((fa, pa), (fb, pb)),
                );
            }
        }
        (!q.stopped).then_some((q.out, q.clear))
    }

    /// Fill in `∂d/∂ξ` of `pairs` found at the frames of `kin` without the integrals
    /// (the line search's), now that `kin` carries them: what [`World::pairs`] gives there.
    pub fn add_gradients(&self, kin: &Kin, pairs: &mut [Pair]) {
        for p in pairs {
            p.grad = World::grad(kin, p.ends, &p.point_robot, &p.normal);
        }
    }

    /// Robot-level box: the bounds of every frame origin grown by the largest feature reach
    /// (disk radius, half a sub-arc); obstacles farther than the margin from it only bound
    /// `clear`.
    fn robot_box(&self, kin: &Kin) -> (Vector3<f64>, Vector3<f64>) {
        let grow = self.robot.disk_radius.max(self.robot.body_radius())
            + kin
                .pos
                .windows(2)
                .map(|w| 0.5 * (w[1] - w[0]).norm())
                .fold(0.0, f64::max);
        let (mut lo, mut hi) = (kin.pos[0], kin.pos[0]);
        for p in &kin.pos {
            lo = lo.inf(p);
            hi = hi.sup(p);
        }
        let g3 = Vector3::repeat(grow);
        (lo - g3, hi + g3)
    }

    /// `∂d/∂ξ` of a witness at `a` with normal `n` (from the obstacle to the robot) on a
    /// feature moving as `ends` (a segment's point at fraction `t` moves as
    /// `(1 − t) ∂a + t ∂b`; module docs).
    fn grad(kin: &Kin, ends: Ends, a: &Vector3<f64>, n: &Vector3<f64>) -> Vec<f64> {
        let mut grad = vec![0.0; 4 * (kin.pos.len() - 1)];
        match ends {
            Ends::Rigid(f) => Self::point_grad(kin, f, a, n, 1.0, &mut grad),
            Ends::Segment((fa, pa), (fb, pb)) => {
                let t = features::segment_fraction(a, &pa, &pb);
                Self::point_grad(kin, fa, &pa, n, 1.0 - t, &mut grad);
                Self::point_grad(kin, fb, &pb, n, t, &mut grad);
            }
        }
        grad
    }

    /// The pair as a reported contact with multiplier `mu` \[N\].
    pub fn contact(&self, p: &Pair, mu: f64) -> Contact {
        let feature = match p.feat {
            Feat::Backbone(j) => Touching::Backbone {
                section: super::problem::section_of(&self.first, j - 1),
            },
            Feat::Disk(k) => Touching::Disk { disk: k },
            Feat::Cable(c, i) => Touching::Cable {
                name: &self.robot.cables[c].name,
                section: i,
            },
        };
        let w = Witness {
            robot: p.point_robot,
            obstacle: p.point_obstacle,
            normal: p.normal,
            dist: p.dist,
        };
        features::record(
            self.scene.obstacles[p.obstacle].name.clone(),
            feature,
            &w,
            mu,
        )
    }
}

/// When a line search's trial is rejected whatever the pairs not yet queried
/// ([`World::pairs_until`]).
pub(super) struct Stop<'s> {
    /// The clearance each pair's distance is held to \[m\].
    pub clearance: f64,
    /// Whether the pairs found so far prove the trial rejected (monotone in them).
    pub rejects: &'s dyn Fn(&[Pair]) -> bool,
}

/// The pairs of one [`World::pairs_until`] call, gathered feature by feature.
struct Collect<'w, 'a> {
    world: &'w World<'a>,
    kin: &'w Kin,
    /// Obstacles the robot-level pass kept.
    candidates: Vec<usize>,
    /// Pairs found at a nearby state ([`World::pairs_near`]).
    hints: &'w [Pair],
    /// Lower bound on the distance between the robot and the obstacles so far \[m\].
    clear: f64,
    out: Vec<Pair>,
    /// The stop rule, asked after each pair closer than its clearance is found.
    stop: Option<Stop<'w>>,
    /// The stop rule fired: the call returns nothing.
    stopped: bool,
}

impl Collect<'_, '_> {
    /// Query feature `feat` (shape `g` at `gpose`, the same as the convex set `convex()`, inside
    /// the ball `(centre, radius)`, moving as `ends`) against every candidate obstacle: in
    /// closed form against a box where a face decides the distance, and against a ball
    /// ([`primitives::closed_witness`], exact; parry's answer agrees to its own accuracy), else
    /// by parry.
    fn feature(
        &mut self,
        feat: Feat,
        (g, gpose): (&dyn PShape, &PPose),
        convex: impl Fn() -> Convex,
        (center, radius): (Vector3<f64>, f64),
        ends: Ends,
    ) {
        let (world, kin) = (self.world, self.kin);
        let (scene, margin) = (world.scene, world.margin);
        let robot = world.robot;
        for i in 0..self.candidates.len() {
            let k = self.candidates[i];
            if self.stopped {
                return;
            }
            let o = &scene.obstacles[k];
            // Bounds farther than the margin: no query, their distance bounds `clear`.
            let lower = scene.bounds_distance(k, &center) - radius;
            if lower > margin {
                self.clear = self.clear.min(lower);
                continue;
            }
            // The exact distance from the centre of the feature's ball to a simple shape, the
            // same way: a pair it puts beyond the margin is one the query would find beyond it.
            if features::ball_gap(&*o.shape, &o.parry_pose, &center, radius)
                .is_some_and(|gap| gap > margin)
            {
                self.clear = self.clear.min(margin);
                continue;
            }
            let closed = primitives::closed_witness(&*o.shape, &o.parry_pose, &convex(), margin);
            let near = self
                .hints
                .iter()
                .find(|h| h.key() == (k, feat, None) && h.dist < SEPARATION_SHIFT)
                .map(|h| (&h.normal, h.dist));
            // The triangle this feature's first pair lay on at the nearby state.
            let hint = self
                .hints
                .iter()
                .find(|h| h.obstacle == k && h.feat == feat)
                .and_then(|h| h.triangle);
            let found = match closed {
                Some(decided) => decided.map(|w| (w, w.dist, None)),
                None => features::witness_near(
                    (g, gpose),
                    (&*o.shape, &o.parry_pose),
                    margin,
                    (near, hint),
                    o.field(),
                ),
            };
            let Some((mut w, raw, triangle)) = found else {
                self.clear = self.clear.min(margin);
                continue;
            };
            self.clear = self.clear.min(raw);
            // A disk touching a smooth obstacle (rim against a cylinder): the alternating
            // projections of the polish converge slowly there, and the normal's error
            // (~1e-5 rad after one polish) would be the floor of the stationarity residual
            // with the contact curvature in the Hessian; continue them near touching.
            if matches!(feat, Feat::Disk(_)) && w.dist.abs() < TOUCHING && closed.is_none() {
                for _ in 0..EXTRA_POLISH {
                    match polish(g, gpose, &*o.shape, &o.parry_pose, &w) {
                        // A fixed point: `polish` reads only the obstacle point, normal and
                        // distance, so every further round would return this same witness.
                        Some(p)
                            if p.obstacle == w.obstacle
                                && p.normal == w.normal
                                && p.dist == w.dist =>
                        {
                            w = p;
                            break;
                        }
                        Some(p) => w = p,
                        None => break,
                    }
                }
            }
            let mut a = w.robot;
            if let Ends::Rigid(f) = ends {
                let (rd, ht) = (robot.disk_radius, robot.disk_thickness / 2.0);
                a = features::disk_support(&kin.rot[f], &kin.pos[f], &w.normal, rd, ht)
                    .unwrap_or(a);
            }
            let grad = if kin.m_int.is_empty() {
                vec![]
            } else {
                World::grad(kin, ends, &a, &w.normal)
            };
            let faces = match crate::contact::solid::solid(&*o.shape) {
                // Near a solid mesh's wall (or just across it): the faces beside the closest
                // triangle that are about to hold the feature too (a concave wall).
                Some(mesh) if w.dist.abs() <= world.face_band() => {
                    crate::contact::solid::face_contacts(
                        gpose,
                        g,
                        &o.parry_pose,
                        mesh,
                        world.face_band(),
                        crate::contact::pvec(&w.normal),
                    )
                }
                _ => vec![],
            };
            // The closest triangle is one of the faces when its witness lies inside its face
            // (the same distance, in closed form): then the faces stand for it, keyed by
            // their triangles, so a pair keeps its identity (and multiplier) while the
            // closest triangle changes from one iterate to the next.
            let closest_is_face = faces
                .first()
                .is_some_and(|(_, f)| f.dist <= w.dist + 1e-9 * (1.0 + w.dist.abs()));
            if !closest_is_face {
                self.push(k, feat, ends, (None, triangle), &w, a, grad);
            }
            for (t, f) in faces {
                if self.stopped {
                    return;
                }
                let grad = if kin.m_int.is_empty() {
                    vec![]
                } else {
                    World::grad(kin, ends, &f.robot, &f.normal)
                };
                self.push(k, feat, ends, (Some(t), Some(t)), &f, f.robot, grad);
            }
        }
    }

    /// Add the pair of feature `feat` (moving as `ends`) with obstacle `k` (face `part`, on
    /// mesh triangle `triangle`) at witness `w` (robot point `a`, gradient `grad`), and ask
    /// the stop rule if it violates.
    #[allow(clippy::too_many_arguments)]
    fn push(
        &mut self,
        k: usize,
        feat: Feat,
        ends: Ends,
        (part, triangle): (Option<u32>, Option<u32>),
        w: &Witness,
        a: Vector3<f64>,
        grad: Vec<f64>,
    ) {
        let violates = self.stop.as_ref().filter(|st| st.clearance - w.dist > 0.0);
        self.out.push(Pair {
            obstacle: k,
            feat,
            dist: w.dist,
            grad,
            point_robot: a,
            point_obstacle: w.obstacle,
            normal: w.normal,
            ends,
            part,
            triangle,
        });
        if let Some(st) = violates {
            self.stopped = (st.rejects)(&self.out);
        }
    }
}

/// How a feature moves with the frames.
#[derive(Debug, Clone, Copy)]
pub(super) enum Ends {
    /// Rigidly with frame `f`.
    Rigid(usize),
    /// A segment between a point of frame `fa` and one of frame `fb`.
    Segment((usize, Vector3<f64>), (usize, Vector3<f64>)),
}

#[cfg(test)]
mod tests;
