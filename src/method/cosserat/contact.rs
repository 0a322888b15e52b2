//! Frictionless contact of the rod with obstacles: point forces at the disks, complementary
//! to the disks' gaps, solved inside the boundary-value problem (module docs, "Contact").
//!
//! # Formulation
//!
//! The rod touches the world with its disks (thin cylinders of the disk radius and
//! thickness, the features `energy` and the section solvers use; a rod without spacer disks
//! with a ball of the body's radius at each section end, its stations). A disk `k` pressed by
//! obstacle `o` takes the point force `F = λ n̂` at the witness point `a` on its rim (`n̂`:
//! the unit normal from the obstacle towards the robot), so the rod's internal wrench jumps
//! there as at a tendon tie, `n⁺ = n⁻ − F`, `m⁺ = m⁻ − (a − p) × F` (R&W eq. 18–19 for a
//! general point load). Frictionless contact is the complementarity
//!
//! ```text
//! λ ≥ 0,   g = d(disk, obstacle) − clearance ≥ 0,   λ g = 0
//! ```
//!
//! (Signorini's conditions for a point contact of a rod: Antman, *Nonlinear Problems of
//! Elasticity*, 2nd ed., ch. 4; the shooting form with the contact forces as unknowns of the
//! boundary-value problem and the gaps as extra residuals is that of Till, Aloi & Rucker,
//! "Real-time dynamics of soft and continuum robots based on Cosserat rod models", IJRR 38(6)
//! 2019, §6, for a static rod.) For a fixed **active set** `A` of (disk, obstacle) pairs the
//! contacts are bilateral: the unknowns of the shooting problem gain one `λ_i` per active pair
//! and its residual one row `k_g g_i` per pair, `k_g = EI/L³` (the cantilever's tip stiffness,
//! so a gap row is in newtons like the wrench rows and one tolerance serves all). `n̂`, `a`
//! and `g` are queried in the pass itself from the disk's pose (the shared contact module:
//! closed form against a box face, parry3d's polished witness otherwise), so the residual is
//! a function of the unknowns alone and Newton's Jacobian (forward differences: the
//! variational pass does not differentiate a point load at an inner disk, module docs) has
//! the columns `∂(residual, g)/∂λ` the brief of the method asks for.
//!
//! **Active set** (outer loop, as the slack cables'): start from none (or the contacts of a
//! warm shape, whose forces and moment about the base then join the base wrench's start; a
//! warm start Newton cannot take is dropped for the cold start's approach); after each
//! converged solve drop the pair with the most negative `λ`, else add
//! every pair whose disk lies deeper than [`PENETRATION_TOL`] in an obstacle; stop when
//! neither happens. Each change is one Newton solve from the last answer.
//!
//! **What is not modelled**: contact of the backbone between disks and of the cable chords.
//! The answer is checked for them ([`RodWorld::crossing`]): a backbone piece or chord deeper
//! than [`CROSSING_TOL`] in an obstacle is the named error `Obstructed`, not an answer.

use super::approach::STEP_DEPTH;
use super::problem::{Problem, Trace};
use super::shooting::Setup;
use crate::contact::features::{self, Touching};
use crate::contact::primitives::{self, Convex};
use crate::contact::{broad, polish, ppose, Witness};
use crate::error::SolveError;
use crate::model::robot::Robot;
use crate::model::scene::Scene;
use crate::numeric::so3::gram_schmidt;
use crate::shape::{Contact, Shape};
use nalgebra::{DVector, Matrix3, Vector3};
use parry3d::math::Pose as PPose;
use parry3d::shape::{Ball, Shape as PShape};

/// A disk deeper than this in an obstacle joins the active set \[m\].
pub(super) const PENETRATION_TOL: f64 = 1e-8;

/// A backbone piece or cable chord deeper than this in an obstacle makes the answer an
/// `Obstructed` error \[m\] (the rod's contacts act at the disks only).
pub(super) const CROSSING_TOL: f64 = 1e-6;

/// Rounds of [`polish`] for a disk near a curved obstacle (as `energy/contacts.rs`).
const POLISH_ROUNDS: usize = 10;

/// One contact of the active set: disk `disk` (1-based; a station of a rod without disks)
/// against obstacle `obstacle` (scene index).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Touch {
    pub(super) disk: usize,
    pub(super) obstacle: usize,
}

/// A contact's load in one pass: the normal force `force` \[N\] of `touch`.
#[derive(Debug, Clone, Copy)]
pub(super) struct Push {
    pub(super) touch: Touch,
    pub(super) force: f64,
}

/// The scene as the rod sees it: the obstacles within reach and the contact feature.
pub(super) struct RodWorld<'a> {
    scene: &'a Scene,
    robot: &'a Robot,
    /// Distinct obstacles within reach (the broad phase every method starts from).
    near: Vec<usize>,
    /// Spacer disks touch (cylinders); else stations (balls of the body radius).
    disks: bool,
    feature: Box<dyn PShape>,
}

impl<'a> RodWorld<'a> {
    /// The world of `robot` in `scene`, after the broad phase's checks (contact budget, base
    /// clear); `None` when no obstacle is within reach.
    pub(super) fn new(robot: &'a Robot, scene: &'a Scene) -> Result<Option<Self>, SolveError> {
        if scene.is_empty() {
            return Ok(None);
        }
        let near = broad::robot_obstacles(robot, scene)?;
        if near.is_empty() {
            return Ok(None);
        }
        let disks = robot.has_disks();
        let feature: Box<dyn PShape> = if disks {
            Box::new(features::disk(robot))
        } else {
            Box::new(Ball::new(robot.body_radius()))
        };
        Ok(Some(RodWorld {
            scene,
            robot,
            near,
            disks,
            feature,
        }))
    }

    /// The scene's clearance \[m\].
    pub(super) fn clearance(&self) -> f64 {
        self.scene.clearance
    }

    /// The farthest a point of the contact feature lies from its frame's centre (the disk
    /// radius, or the body radius of a rod without disks): what a turn of the frame moves it
    /// by, per radian \[m\].
    fn reach(&self) -> f64 {
        self.robot.disk_radius.max(self.robot.body_radius())
    }

    /// The feature's parry pose at a disk frame `(p, r)`.
    fn pose(&self, p: &Vector3<f64>, r: &Matrix3<f64>) -> PPose {
        if self.disks {
            features::disk_pose(r, p)
        } else {
            ppose(&Matrix3::identity(), p)
        }
    }

    /// The witness of the disk at `(p, r)` against obstacle `o`, or `None` beyond `margin`:
    /// in closed form where a box face or a ball decides it (`primitives::closed_witness`), else parry's
    /// polished answer with the robot point on the disk rim exactly (`disk_support`).
    pub(super) fn witness(
        &self,
        o: usize,
        p: &Vector3<f64>,
        r: &Matrix3<f64>,
        margin: f64,
    ) -> Option<Witness> {
        let ob = &self.scene.obstacles[o];
        let robot = self.robot;
        let (rd, ht) = (robot.disk_radius, robot.disk_thickness / 2.0);
        // RK4 integrates the frame only approximately: under a hard bend (a rim pressed with
        // kilonewtons) it drifts ~1e-3 from orthonormal, and a rim point read at the drifted
        // frame sits micrometres off the rigid disk the answer reports (its frame projected,
        // `gram_schmidt`). The contact is that rigid disk's: a frame whose drift moves the rim
        // by more than a nanometre (a tenth of `PENETRATION_TOL`) is projected first.
        let projected;
        let drift = (r.transpose() * r - Matrix3::identity()).amax();
        let r = if drift * self.reach() > 0.1 * PENETRATION_TOL {
            projected = gram_schmidt(r);
            &projected
        } else {
            r
        };
        let convex = if self.disks {
            Convex::Disk(*r, *p, rd, ht)
        } else {
            Convex::Segment(*p, *p, robot.body_radius())
        };
        if let Some(decided) =
            primitives::closed_witness(&*ob.shape, &ob.parry_pose, &convex, margin)
        {
            return decided;
        }
        let g = &*self.feature;
        let gpose = self.pose(p, r);
        let (mut w, _) =
            features::witness(g, &gpose, &*ob.shape, &ob.parry_pose, margin, ob.field())?;
        for _ in 0..POLISH_ROUNDS {
            match polish(g, &gpose, &*ob.shape, &ob.parry_pose, &w) {
                Some(q) if q.obstacle == w.obstacle && q.normal == w.normal && q.dist == w.dist => {
                    break
                }
                Some(q) => w = q,
                None => break,
            }
        }
        if self.disks {
            w.robot = features::disk_support(r, p, &w.normal, rd, ht).unwrap_or(w.robot);
        }
        Some(w)
    }

    /// The (disk, obstacle) pair of the pass `trace` not in `active` whose disk lies deepest
    /// inside the clearance, if deeper than [`PENETRATION_TOL`].
    pub(super) fn penetrating(&self, trace: &Trace, active: &[Touch]) -> Option<Touch> {
        let mut out: Option<(Touch, f64)> = None;
        let margin = self.clearance();
        for (k, (p, r)) in trace.disks.iter().enumerate().skip(1) {
            for &o in &self.near {
                let t = Touch {
                    disk: k,
                    obstacle: o,
                };
                if active.contains(&t) {
                    continue;
                }
                if let Some(w) = self.witness(o, p, r, margin) {
                    let deep = w.dist < self.clearance() - PENETRATION_TOL;
                    if deep && out.is_none_or(|(_, d)| w.dist < d) {
                        out = Some((t, w.dist));
                    }
                }
            }
        }
        out.map(|(t, _)| t)
    }

    /// The `Obstructed` error of a start whose disk lies deeper than [`STEP_DEPTH`] inside
    /// the clearance of an obstacle at the frames `at` (the deepest such disk), if any: no
    /// load step can move it ([`RodWorld::guard`]), so the approach could only stall at load
    /// factor 0.
    pub(super) fn start_inside(&self, at: &[(Vector3<f64>, Matrix3<f64>)]) -> Option<SolveError> {
        let mut deepest: Option<(usize, usize, f64)> = None;
        for (k, (p, r)) in at.iter().enumerate().skip(1) {
            for &o in &self.near {
                let Some(w) = self.witness(o, p, r, self.clearance()) else {
                    continue;
                };
                let depth = self.clearance() - w.dist;
                if depth > STEP_DEPTH && deepest.is_none_or(|(_, _, d)| depth > d) {
                    deepest = Some((k, o, depth));
                }
            }
        }
        let (k, o, depth) = deepest?;
        Some(SolveError::Obstructed {
            obstacle: self.scene.obstacles[o].name.clone(),
            section: k,
            reason: format!(
                "the straight start's disk {k} lies {depth:.3e} m inside the clearance, and no \
                 load step can move it out; start from a shape that is clear of it (e.g. \
                 --warm-from energy or geometric)"
            ),
        })
    }

    /// The first disk not in `active` that moved from the frames `a` to `b` farther than its
    /// distance to an obstacle at `a` plus [`STEP_DEPTH`] (`approach.rs`), if any. A disk's
    /// move is bounded by `|Δp| + r |ΔR|_F`, `r` the disk (or body) radius.
    pub(super) fn guard(
        &self,
        a: &[(Vector3<f64>, Matrix3<f64>)],
        b: &[(Vector3<f64>, Matrix3<f64>)],
        active: &[Touch],
    ) -> Option<usize> {
        let r = self.reach();
        let clearance = self.clearance();
        for (k, ((pa, ra), (pb, rb))) in a.iter().zip(b).enumerate().skip(1) {
            let moved = (pb - pa).norm() + r * (rb - ra).norm();
            for &o in &self.near {
                if active.contains(&Touch {
                    disk: k,
                    obstacle: o,
                }) {
                    continue;
                }
                let reach = clearance + moved + STEP_DEPTH;
                if let Some(w) = self.witness(o, pa, ra, reach) {
                    if moved > w.dist - clearance + STEP_DEPTH {
                        return Some(k);
                    }
                }
            }
        }
        None
    }

    /// The first backbone piece (between the pass's integration points) or cable chord
    /// deeper than [`CROSSING_TOL`] inside the clearance of an obstacle, as the `Obstructed`
    /// error that says why: the rod's contacts act at its disks only.
    pub(super) fn crossing(
        &self,
        backbone: &[Vector3<f64>],
        chords: &[(usize, Vec<Vector3<f64>>)],
    ) -> Result<(), SolveError> {
        let robot = self.robot;
        let rb = features::BodyParts::of(robot).radius;
        let limit = self.clearance() - CROSSING_TOL;
        let identity = PPose::IDENTITY;
        let deep = |g: &dyn PShape, o: usize| {
            let ob = &self.scene.obstacles[o];
            features::witness(
                g,
                &identity,
                &*ob.shape,
                &ob.parry_pose,
                limit.max(0.0),
                ob.field(),
            )
            .is_some_and(|(w, _)| w.dist < limit)
        };
        let per_section = backbone.len().saturating_sub(1) / robot.sections().max(1);
        for (i, w) in backbone.windows(2).enumerate() {
            let capsule = features::backbone(&w[0], &w[1], rb);
            if let Some(&o) = self.near.iter().find(|&&o| deep(&capsule, o)) {
                let section = (i / per_section.max(1) + 1).min(robot.sections());
                return Err(self.obstructed(o, section, "the backbone"));
            }
        }
        if features::BodyParts::of(robot).cables {
            for (c, holes) in chords {
                for (i, h) in holes.windows(2).enumerate() {
                    let chord = features::chord(&h[0], &h[1]);
                    if let Some(&o) = self.near.iter().find(|&&o| deep(&chord, o)) {
                        let what = format!("cable `{}`", robot.cables[*c].name);
                        return Err(self.obstructed(o, i + 1, &what));
                    }
                }
            }
        }
        Ok(())
    }

    fn obstructed(&self, o: usize, section: usize, what: &str) -> SolveError {
        SolveError::Obstructed {
            obstacle: self.scene.obstacles[o].name.clone(),
            section,
            reason: format!(
                "{what} crosses this obstacle between disks; the rod's contacts act at its \
                 disks only (start from a clear shape, e.g. --warm-from energy, or use energy)"
            ),
        }
    }

    /// The active set a warm shape's disk contacts give (obstacles matched by name among
    /// those within reach), with their multipliers as the forces' start, and the force and
    /// moment about the base \[N, N m\] those forces put on the rod at the shape's contact
    /// points (the base wrench's start: `Warm::with_contacts`).
    pub(super) fn warm_contacts(
        &self,
        contacts: &[Contact],
    ) -> (Vec<Push>, Vector3<f64>, Vector3<f64>) {
        let (mut f, mut m) = (Vector3::zeros(), Vector3::zeros());
        let mut out: Vec<Push> = vec![];
        for c in contacts {
            let Some(disk) = c.disk.filter(|&k| k >= 1 && k <= self.robot.sections()) else {
                continue;
            };
            let found = self
                .near
                .iter()
                .copied()
                .find(|&o| self.scene.obstacles[o].name == c.obstacle);
            if let Some(obstacle) = found {
                let touch = Touch { disk, obstacle };
                if !out.iter().any(|p| p.touch == touch) {
                    let force = if c.multiplier.is_finite() {
                        c.multiplier.max(0.0)
                    } else {
                        0.0
                    };
                    let load = Vector3::from(c.normal) * force;
                    f += load;
                    m += Vector3::from(c.point_robot).cross(&load);
                    out.push(Push { touch, force });
                }
            }
        }
        (out, f, m)
    }

    /// The contact a shape reports for `push` at its witness `w`.
    pub(super) fn record(&self, push: &Push, w: &Witness) -> Contact {
        let feature = if self.disks {
            Touching::Disk {
                disk: push.touch.disk,
            }
        } else {
            Touching::Backbone {
                section: push.touch.disk,
            }
        };
        let name = self.scene.obstacles[push.touch.obstacle].name.clone();
        features::record(name, feature, w, push.force)
    }
}

impl Problem<'_> {
    /// Scale of a gap row: `EI/L³` \[N/m\] (module docs).
    pub(super) fn gap_scale(&self) -> f64 {
        self.fscale / self.len_l
    }

    /// Apply the contact forces of `ld` at disk `k` (frame `p`, `r`) to the wrench `(n, m)`
    /// and record their witnesses in `touch`. `Some(true)` if a force acts here, `None` if
    /// a witness could not be found (the pass fails).
    pub(super) fn contact_loads(
        &self,
        k: usize,
        (p, r): (&Vector3<f64>, &Matrix3<f64>),
        ld: &super::problem::LoadCase,
        (n, m): (&mut Vector3<f64>, &mut Vector3<f64>),
        touch: &mut Vec<Witness>,
    ) -> Option<bool> {
        let mut here = false;
        let Some(world) = &self.world else {
            return Some(false);
        };
        for push in ld.push.iter().filter(|q| q.touch.disk == k) {
            let w = world.witness(push.touch.obstacle, p, r, self.len_l)?;
            let f = w.normal * push.force;
            *n -= f;
            *m -= (w.robot - p).cross(&f);
            touch.push(w);
            here = true;
        }
        Some(here)
    }

    /// Complementarity at a converged `x` (module docs, "Active set"): the active contact
    /// with the most negative force leaves; else the disk deepest in an obstacle joins. True if the set changed.
    pub(super) fn update_contacts(
        &self,
        x: &DVector<f64>,
        setup: &Setup,
        active: &mut Vec<Touch>,
    ) -> bool {
        self.update_contacts_at(x, setup, active, 1.0)
    }

    /// [`Problem::update_contacts`] at load factor `lam`.
    pub(super) fn update_contacts_at(
        &self,
        x: &DVector<f64>,
        setup: &Setup,
        active: &mut Vec<Touch>,
        lam: f64,
    ) -> bool {
        let Some(world) = &self.world else {
            return false;
        };
        let c0 = setup.first_contact();
        let pulling = (0..setup.contacts.len())
            .filter(|&i| x[c0 + i] < -self.set.tolerance)
            .min_by(|&a, &b| x[c0 + a].total_cmp(&x[c0 + b]));
        if let Some(i) = pulling {
            active.retain(|t| *t != setup.contacts[i]);
            return true;
        }
        let (n0, m0) = self.base_wrench(x);
        let mut trace = Trace::default();
        self.pass(&n0, &m0, &self.load_case(x, setup, lam), Some(&mut trace));
        let Some(add) = world.penetrating(&trace, active) else {
            return false;
        };
        active.push(add);
        active.sort_by_key(|t| (t.disk, t.obstacle));
        true
    }

    /// The base wrench `(n(0), m(0))` of the unknowns `x`.
    pub(super) fn base_wrench(&self, x: &DVector<f64>) -> (Vector3<f64>, Vector3<f64>) {
        (
            Vector3::new(x[0], x[1], x[2]),
            Vector3::new(x[3], x[4], x[5]) * self.len_l,
        )
    }

    /// The answer's contacts into `shape.contacts` (one per active pair, its force the
    /// multiplier, in newtons), after checking that no backbone piece or cable chord crosses
    /// an obstacle ([`RodWorld::crossing`]).
    pub(super) fn contacts_of(
        &self,
        x: &DVector<f64>,
        setup: &Setup,
        shape: &mut Shape,
    ) -> Result<(), SolveError> {
        let Some(world) = &self.world else {
            return Ok(());
        };
        let chords: Vec<_> = shape
            .cables
            .iter()
            .enumerate()
            .filter(|(_, c)| !c.slack)
            .map(|(i, c)| (i, c.points.clone()))
            .collect();
        world.crossing(&shape.backbone, &chords)?;
        if setup.contacts.is_empty() {
            return Ok(());
        }
        let (n0, m0) = self.base_wrench(x);
        let ld = self.load_case(x, setup, 1.0);
        let shot = self.pass(&n0, &m0, &ld, Some(&mut Trace::default()));
        shape.contacts = ld
            .push
            .iter()
            .zip(&shot.touch)
            .map(|(p, w)| world.record(p, w))
            .collect();
        shape.report.notes.push(format!(
            "{} contacts at disks (frictionless point forces, active set)",
            setup.contacts.len()
        ));
        Ok(())
    }
}
