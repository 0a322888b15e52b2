//! The paper's geometric section solver (Mahapatra & Ghosal), generalized to N cables.
//!
//! # The literal method (`geometric`)
//!
//! The robot is solved one section at a time, base to tip (paper §2, steps 1–4, read as in
//! `paper/INTERPRETATION.md`). Section `i` lies between disks `i−1` and `i`. Everything is
//! written in the frame of the **solved** disk `i−1` (origin at its backbone point, z along its
//! normal, x at hole angle 0). In that frame the unknown is the rigid pose of disk `i`:
//! backbone point `p` and rotation `Q`, so hole `c` of disk `i` sits at `p + Q h_c(i)` with
//! `h_c(k) = r_c(k) (cos φ_c(k), sin φ_c(k), 0)`. A rigid disk keeps `|x_c − x_0| = r` and the
//! angle θ between holes (the last three constraints of eq. 2) by construction, and the paper's
//! frame `T` (steps 1–3, with `sign(θ)`) is the same rigid frame, so crossed-over cables need no
//! special case.
//!
//! The "undeformed" disk `i` (step 4) is disk `i` in its undeformed pose relative to disk
//! `i−1`: `p = l0 ẑ`, `Q = I`. Eq. 1, one coupler angle per displacement-driven cable plus the
//! tangent angle, is then
//!
//! ```text
//! F(p, Q) = Σ_c ang(h_c(i), Q h_c(i)) + ang(ẑ, p),    ang(a, b) = atan2(|a × b|, a · b)
//! ```
//!
//! subject to (eq. 2) `|p| = l0` and, for each cable, `|p + Q h_c(i) − h_c(i−1)| ≤ l_c^i` where
//! `l_c^i = (1 − Δ_c) |H_c(i) − H_c(i−1)|` is a uniform fraction of the cable's **undeformed
//! straight chord** between its two holes (INTERPRETATION item 1). The paper writes the cable
//! constraint as an equality; cables pull but cannot push, so ccrkit treats it as `≤`: a cable
//! whose chord comes out shorter than its length is reported slack.
//!
//! ## The kink
//!
//! Each angle is a cone at 0 (like a norm), and at the optimum one or more angles are exactly
//! zero. A smooth NLP solver stalls there. This solver enumerates **faces**: for each set `Z`
//! of terms that may vanish, it minimizes the other terms with the zero terms as equalities
//! `w_t = 0` (`w_t`: the two components of the solved direction orthogonal to the undeformed one,
//! so `|w_t| = sin ang_t`), by Newton–KKT with exact second derivatives ([`crate::numeric::ad`])
//! from several starts. A candidate is **certified** when it is feasible, stationary, has a
//! positive semi-definite reduced Hessian, every zero term's multiplier lies inside that term's
//! subgradient ball (`|μ_t| ≤ weight_t`), every other term is non-zero, and every taut cable's
//! multiplier is ≥ 0 (it pulls). The lowest certified candidate is returned, and the report
//! says which terms are zero in each section.
//!
//! ## Degenerate hole patterns
//!
//! When all driven holes of a disk are collinear with its centre (one cable, two cables with
//! coinciding holes as in case III at disks 7–9, or two opposite holes), the rotation of the disk
//! about that line changes neither the objective nor a constraint. It is fixed as INTERPRETATION
//! item 7 says: the disk normal is the incoming backbone chord made orthogonal to the hole
//! direction. Cables sharing a hole on both disks of a section share one segment constraint with
//! the tighter length; the other is slack there. Sections past every driven cable's end carry no
//! load and continue straight.
//!
//! # The squared variant (`geometric-squared`)
//!
//! Same sections and constraints, objective `Σ ang²` — a discrete bending energy, smooth, so one
//! face suffices. Not the paper's method; offered as a named option.

use crate::error::SolveError;
use crate::method::contact::{
    check_base, nvec, polish, ppose, pvec, query, y_to_z, Witness, CONTACT_TOL,
};
use crate::method::output::cable_paths;
use crate::method::settings::{parse_count, parse_in, Configure, MAX_ITERATIONS};
use crate::method::{Method, MethodKind};
use crate::model::actuation::{Actuation, Drive, Input};
use crate::model::robot::Robot;
use crate::model::scene::Scene;
use crate::numeric::ad::{Real, D2, V3};
use crate::numeric::kkt::{kkt_step, kkt_step6, multipliers};
use crate::numeric::qp::qp_step6;
use crate::numeric::so3::{exp_so3, gram_schmidt, orthonormalize};
use crate::shape::{Contact, DiskFrame, SectionReport, Shape, SolveReport};
use nalgebra::{DMatrix, DVector, Matrix3, Matrix6, Vector3, Vector6};
use parry3d::math::Pose as PPose;
use parry3d::shape::{Capsule, Cylinder, Segment, Shape as PShape};
use std::time::Instant;

/// Which objective the sections minimize.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Objective {
    /// The paper's: sum of the coupler angles and the tangent angle (eq. 1).
    Literal,
    /// Sum of squared angles (a discrete bending energy).
    Squared,
}

/// Settings of the geometric section solver.
#[derive(Debug, Clone)]
pub struct Geometric {
    /// Objective.
    pub objective: Objective,
    /// Newton iterations per candidate.
    pub max_iterations: usize,
    /// Constraint residual a candidate must reach \[m\].
    pub tolerance: f64,
    /// An angle at or below this is "zero" (on a kink) \[rad\].
    pub zero_angle: f64,
}

impl Geometric {
    /// The paper's literal method.
    pub fn literal() -> Self {
        Geometric {
            objective: Objective::Literal,
            max_iterations: 40,
            tolerance: 1e-12,
            zero_angle: 1e-7,
        }
    }
    /// The squared-angle variant.
    pub fn squared() -> Self {
        Geometric {
            objective: Objective::Squared,
            ..Self::literal()
        }
    }
}

impl Configure for Geometric {
    fn set(&mut self, name: &str, value: &str) -> Result<(), SolveError> {
        match name {
            "max-iterations" => self.max_iterations = parse_count(name, value, 1, MAX_ITERATIONS)?,
            "tolerance" => self.tolerance = parse_in(name, value, 0.0, 1.0)?,
            "zero-angle" => self.zero_angle = parse_in(name, value, 0.0, 1e-3)?,
            _ => return self.kind().check_setting(name),
        }
        Ok(())
    }
}

impl Method for Geometric {
    fn kind(&self) -> MethodKind {
        match self.objective {
            Objective::Literal => MethodKind::Geometric,
            Objective::Squared => MethodKind::GeometricSquared,
        }
    }

    fn solve(
        &self,
        robot: &Robot,
        act: &Actuation,
        scene: &Scene,
        warm: Option<&Shape>,
    ) -> Result<Shape, SolveError> {
        let start = Instant::now();
        let n = robot.sections();
        self.kind().check_support(robot, scene)?;
        let notes = vec![
            "cable segment length after actuation = (1 - shortening) x undeformed straight chord between holes".to_string(),
        ];
        // Displacement fraction per cable (None: free).
        let drives = act.drives(robot, self.name(), &[Input::Shortening], Input::Shortening)?;
        let frac: Vec<Option<f64>> = drives
            .iter()
            .map(|d| match d {
                Drive::Shorten { fraction, .. } => Some(*fraction),
                _ => None,
            })
            .collect();

        let mut rot = Matrix3::identity();
        let mut pos = Vector3::zeros();
        let mut disks = vec![DiskFrame {
            s: 0.0,
            position: pos,
            rotation: rot,
        }];
        let mut sections = Vec::with_capacity(n);
        let mut slack_sections: Vec<Vec<usize>> = vec![vec![]; robot.cables.len()];
        let mut prev_rel: Option<Pose> = None;
        let (mut total_it, mut worst) = (0usize, 0.0f64);
        // Broad phase, robot level: only obstacles within reach of the base take part.
        let reach = robot.length() + robot.disk_radius + scene.clearance + robot.disk_thickness;
        let relevant = scene.near(&Vector3::zeros(), reach);
        check_base(robot, scene, &relevant)?;
        let warm_rel = warm.filter(|w| w.disks.len() == n + 1).map(relative_poses);
        let mut contacts = vec![];
        for i in 1..=n {
            let mut data = SectionData::new(robot, &frac, i)?;
            data.world = SectionWorld::new(robot, scene, &relevant, i, &rot, &pos);
            let warm_i = warm_rel.as_ref().map(|w| w[i - 1]);
            let sol = self.solve_section(&data, i, prev_rel.as_ref(), warm_i.as_ref())?;
            contacts.extend(sol.contacts.iter().cloned());
            total_it += sol.report.iterations;
            worst = worst.max(sol.report.residual);
            for &c in &sol.slack {
                slack_sections[c].push(i);
            }
            pos += rot * sol.pose.p;
            rot = orthonormalize(&(rot * sol.pose.q));
            disks.push(DiskFrame {
                s: robot.disk_s[i],
                position: pos,
                rotation: rot,
            });
            prev_rel = Some(sol.pose);
            sections.push(sol.report);
        }
        let cables = cable_paths(robot, &disks, &slack_sections);
        let backbone = disks.iter().map(|d| d.position).collect();
        Ok(Shape {
            method: self.name().into(),
            disks,
            backbone,
            cables,
            contacts,
            report: SolveReport {
                converged: true,
                iterations: total_it,
                residual: worst,
                solve_time_s: start.elapsed().as_secs_f64(),
                sections,
                base_wrench: None,
                notes,
                stable: None,
                jacobian: None,
                warm: None,
            },
        })
    }
}

/// Relative pose of disk i in the frame of disk i−1.
#[derive(Debug, Clone, Copy)]
struct Pose {
    p: Vector3<f64>,
    q: Matrix3<f64>,
}

impl Pose {
    fn straight(l0: f64) -> Self {
        Pose {
            p: Vector3::new(0.0, 0.0, l0),
            q: Matrix3::identity(),
        }
    }
    /// Right-perturbation retraction: p + dp, Q exp(dω).
    fn retract(&self, dx: &Vector6<f64>, alpha: f64) -> Self {
        Pose {
            p: self.p + alpha * Vector3::new(dx[0], dx[1], dx[2]),
            q: gram_schmidt(&(self.q * exp_so3(&(alpha * Vector3::new(dx[3], dx[4], dx[5]))))),
        }
    }
}

/// One objective term: an angle between an undeformed direction and its solved image.
#[derive(Debug, Clone)]
struct Term {
    /// Unit undeformed direction (ẑ for the tangent, ĥ for a coupler) in disk i−1's frame.
    dir: Vector3<f64>,
    /// Orthonormal basis of the plane normal to `dir` (for the zero-face equations).
    e1: Vector3<f64>,
    e2: Vector3<f64>,
    /// How many cables share this coupler (1 for the tangent).
    weight: f64,
    /// `tangent` or the cable names joined with `+`.
    label: String,
    tangent: bool,
}

impl Term {
    fn new(dir: Vector3<f64>, weight: f64, label: String, tangent: bool) -> Self {
        let d = dir.normalize();
        let helper = if d.x.abs() < 0.9 {
            Vector3::x()
        } else {
            Vector3::y()
        };
        let e1 = (helper - d * d.dot(&helper)).normalize();
        let e2 = d.cross(&e1);
        Term {
            dir: d,
            e1,
            e2,
            weight,
            label,
            tangent,
        }
    }
}

/// A cable segment constraint `|p + Q h − h_prev| ≤ length`.
#[derive(Debug, Clone)]
struct CableCon {
    cables: Vec<usize>,
    h_prev: Vector3<f64>,
    h: Vector3<f64>,
    length: f64,
}

/// Everything one section problem needs, in disk i−1's frame.
struct SectionData {
    /// Section index (1-based).
    section: usize,
    l0: f64,
    terms: Vec<Term>,
    cons: Vec<CableCon>,
    /// Cables that reach the section but whose shared segment is tighter for another cable.
    always_slack: Vec<usize>,
    /// Names, for errors.
    names: Vec<String>,
    /// Unit hole direction when all driven holes of disk i are collinear with its centre.
    gauge: Option<Vector3<f64>>,
    /// Obstacles this section can touch (None: none near).
    world: Option<SectionWorld>,
}

const SAME_POINT: f64 = 1e-12;

impl SectionData {
    fn new(robot: &Robot, frac: &[Option<f64>], i: usize) -> Result<Self, SolveError> {
        let l0 = robot.section_length(i);
        let mut terms = vec![Term::new(Vector3::z(), 1.0, "tangent".into(), true)];
        let mut cons: Vec<CableCon> = vec![];
        let mut always_slack = vec![];
        let mut coupler_members: Vec<(Vector3<f64>, Vec<usize>)> = vec![];
        for (c, cable) in robot.cables.iter().enumerate() {
            let Some(f) = frac[c] else { continue };
            if !cable.reaches_section(i) {
                continue;
            }
            let (hp, h) = (cable.hole(i - 1), cable.hole(i));
            let length = (1.0 - f) * robot.undeformed_chord(c, i);
            // Shortest chord any pose allows: l0 − |h| − |h_prev|.
            let reach = l0 - h.norm() - hp.norm();
            if length < reach {
                return Err(SolveError::Infeasible {
                    cable: cable.name.clone(),
                    section: i,
                    reason: format!(
                        "segment length {length:.6} m is shorter than any pose allows ({reach:.6} m): shortening {:.2} % is out of reach",
                        f * 100.0
                    ),
                });
            }
            // ang(h, Qh) = ang(−h, −Qh): holes on one line through the centre give one term.
            match coupler_members
                .iter_mut()
                .find(|(hh, _)| hh.normalize().cross(&h.normalize()).norm() < 1e-9)
            {
                Some((_, m)) => m.push(c),
                None => coupler_members.push((h, vec![c])),
            }
            match cons
                .iter_mut()
                .find(|k| (k.h - h).norm() < SAME_POINT && (k.h_prev - hp).norm() < SAME_POINT)
            {
                Some(k) => {
                    if length < k.length {
                        always_slack.extend(k.cables.iter().copied());
                        k.cables = vec![c];
                        k.length = length;
                    } else {
                        always_slack.push(c);
                    }
                }
                None => cons.push(CableCon {
                    cables: vec![c],
                    h_prev: hp,
                    h,
                    length,
                }),
            }
        }
        for (h, members) in &coupler_members {
            let label = members
                .iter()
                .map(|&c| robot.cables[c].name.as_str())
                .collect::<Vec<_>>()
                .join("+");
            terms.push(Term::new(*h, members.len() as f64, label, false));
        }
        // Rank of the driven hole directions: a gauge is needed when they span one line.
        let gauge = match coupler_members.first() {
            None => None,
            Some((h0, _)) => {
                let u = h0.normalize();
                if coupler_members
                    .iter()
                    .all(|(h, _)| h.normalize().cross(&u).norm() < 1e-9)
                {
                    Some(u)
                } else {
                    None
                }
            }
        };
        Ok(SectionData {
            section: i,
            l0,
            terms,
            cons,
            always_slack,
            names: robot.cables.iter().map(|c| c.name.clone()).collect(),
            gauge,
            world: None,
        })
    }

    /// Objective and constraints at pose ⊕ δ (δ = (dp, dω)) evaluated at δ = 0, generic over
    /// the scalar: `f64` for values, [`D2`] for exact first and second derivatives in δ.
    fn eval<T: SectionScalar>(
        &self,
        pose: &Pose,
        face: u32,
        active: &[usize],
        squared: bool,
    ) -> (T, Vec<T>) {
        let p = T::position(&pose.p);
        let q = &pose.q;
        let rot = |h: &Vector3<f64>| -> V3<T> { T::rotated(q, h) };
        let mut obj = T::cst(0.0);
        let mut cons = Vec::with_capacity(1 + active.len() + 2 * self.terms.len() + 1);
        cons.push(p.norm() + (-self.l0));
        for &j in active {
            let k = &self.cons[j];
            let chord = p.add(&rot(&k.h)).add(&V3::cst(&(-k.h_prev)));
            cons.push(chord.norm() + (-k.length));
        }
        for (t, term) in self.terms.iter().enumerate() {
            let v = if term.tangent { p } else { rot(&term.dir) };
            if face & (1 << t) != 0 {
                let inv = T::cst(1.0) / v.norm();
                cons.push(v.dot_c(&term.e1) * inv);
                cons.push(v.dot_c(&term.e2) * inv);
            } else {
                let u = V3::<T>::cst(&term.dir);
                let a = if squared {
                    squared_angle(&u, &v)
                } else {
                    u.angle(&v)
                };
                obj = obj + a * term.weight;
            }
        }
        if let Some(u) = &self.gauge {
            // Disk normal in the plane of the hole direction and the incoming chord.
            let n = rot(&Vector3::z());
            cons.push(n.dot(&rot(u).cross(&p)) * T::cst(1.0 / (self.l0 * u.norm())));
        }
        (obj, cons)
    }

    fn term_angles(&self, pose: &Pose) -> Vec<f64> {
        self.terms
            .iter()
            .map(|t| {
                let v = if t.tangent { pose.p } else { pose.q * t.dir };
                let c = t.dir.cross(&v).norm();
                c.atan2(t.dir.dot(&v))
            })
            .collect()
    }

    fn chord(&self, pose: &Pose, j: usize) -> f64 {
        let k = &self.cons[j];
        (pose.p + pose.q * k.h - k.h_prev).norm()
    }
}

/// The scalars a section problem is evaluated in, at δ = 0 of the perturbation
/// `p + δp`, `Q exp([δω]×)`: plain values, or values with derivatives in δ.
trait SectionScalar: Real {
    /// `p + δp`.
    fn position(p: &Vector3<f64>) -> V3<Self>;
    /// `Q exp([δω]×) h`.
    fn rotated(q: &Matrix3<f64>, h: &Vector3<f64>) -> V3<Self>;
}

impl SectionScalar for f64 {
    fn position(p: &Vector3<f64>) -> V3<f64> {
        V3([p.x, p.y, p.z])
    }
    fn rotated(q: &Matrix3<f64>, h: &Vector3<f64>) -> V3<f64> {
        let v = q * h;
        V3([v.x, v.y, v.z])
    }
}

impl SectionScalar for D2<6> {
    fn position(p: &Vector3<f64>) -> V3<Self> {
        V3([D2::var(p.x, 0), D2::var(p.y, 1), D2::var(p.z, 2)])
    }
    /// Closed form at δω = 0, from `exp([w]×) h = h + w × h + ½ w × (w × h) + O(|w|³)`:
    /// value `Q h`; gradient `∂/∂w = −Q [h]×`; and, since
    /// `½ w × (w × h) = ½ (w (w·h) − h |w|²)`, the constant Hessian of component r
    /// `∂²/∂w_i∂w_j = ½ (Q_ri h_j + Q_rj h_i) − (Q h)_r δ_ij`. No dual arithmetic needed.
    fn rotated(q: &Matrix3<f64>, h: &Vector3<f64>) -> V3<Self> {
        let qh = q * h;
        let hx = Matrix3::new(0.0, -h.z, h.y, h.z, 0.0, -h.x, -h.y, h.x, 0.0);
        let g = -(q * hx);
        V3(std::array::from_fn(|r| {
            let mut d = D2::<6>::cst(qh[r]);
            for j in 0..3 {
                d.g[3 + j] = g[(r, j)];
                for i in 0..3 {
                    let mut v = 0.5 * (q[(r, i)] * h[j] + q[(r, j)] * h[i]);
                    if i == j {
                        v -= qh[r];
                    }
                    d.h[3 + i][3 + j] = v;
                }
            }
            d
        }))
    }
}

/// ang² evaluated smoothly through ang = 0 (ang² ≈ |u×v|²/(u·v)² there, exact to O(ang⁴)).
fn squared_angle<T: Real>(u: &V3<T>, v: &V3<T>) -> T {
    let cr = u.cross(v);
    let s2 = cr.dot(&cr);
    let c = u.dot(v);
    if s2.val() < 1e-16 * c.val() * c.val() {
        s2 / (c * c)
    } else {
        let a = s2.sqrt().atan2(c);
        a * a
    }
}

/// The accepted solution of one section.
struct SectionSolution {
    pose: Pose,
    slack: Vec<usize>,
    report: SectionReport,
    contacts: Vec<Contact>,
}

/// A converged, certified candidate.
#[derive(Clone)]
struct Candidate {
    pose: Pose,
    objective: f64,
    residual: f64,
    /// Multipliers of the active cable constraints (≥ 0 when the cable pulls).
    cable_lambda: Vec<f64>,
    face: u32,
    /// Active contacts with their multipliers.
    contacts: Vec<Contact>,
}

/// A Newton–KKT step.
struct Step {
    dx: Vector6<f64>,
    lambda: Vec<f64>,
    min_reduced_eigenvalue: f64,
}

/// What the pull-only check says of a candidate.
enum TautMove {
    Accept,
    Drop(usize),
    Add(usize),
}

/// Why a Newton run on one face was not accepted.
struct Rejected {
    iterations: usize,
    residual: f64,
}

impl Geometric {
    fn solve_section(
        &self,
        data: &SectionData,
        i: usize,
        prev: Option<&Pose>,
        warm: Option<&Pose>,
    ) -> Result<SectionSolution, SolveError> {
        let l0 = data.l0;
        if data.cons.is_empty() {
            // No driven cable here: an unloaded section continues straight.
            if let Some(w) = &data.world {
                if let Some(pair) = w
                    .pairs(&Pose::straight(l0))
                    .into_iter()
                    .find(|p| p.dist < w.clearance - CONTACT_TOL)
                {
                    return Err(SolveError::Obstructed {
                        obstacle: w.name(pair.obstacle),
                        section: i,
                        reason: "a section without driven cables continues straight, and straight runs into this obstacle".into(),
                    });
                }
            }
            return Ok(SectionSolution {
                contacts: vec![],
                pose: Pose::straight(l0),
                slack: data.always_slack.clone(),
                report: SectionReport {
                    section: i,
                    iterations: 0,
                    residual: 0.0,
                    objective: 0.0,
                    zero_terms: data.terms.iter().map(|t| t.label.clone()).collect(),
                    slack: data
                        .always_slack
                        .iter()
                        .map(|&c| data.names[c].clone())
                        .collect(),
                    candidates: 1,
                },
            });
        }
        let squared = self.objective == Objective::Squared;
        let straight = Pose::straight(l0);
        let mut iterations = 0usize;
        let mut closest = f64::INFINITY;
        let gauge = usize::from(data.gauge.is_some());
        let max_taut = 5 - gauge;
        let mut starts = self.starts(data, prev, &mut iterations);
        if let Some(w) = warm {
            starts.insert(0, nudge(w, l0));
        }
        let mut count = 0usize;
        // Cables pull, they do not push: the taut set T must give a certified pose whose taut
        // multipliers are ≥ 0 and where no other cable's chord exceeds its length.
        // Fast path: primal active set from the cables the straight pose violates.
        let mut taut: Vec<usize> = (0..data.cons.len())
            .filter(|&j| data.chord(&straight, j) > data.cons[j].length)
            .collect();
        let mut seen: Vec<Vec<usize>> = vec![];
        let mut accepted: Option<(Candidate, Vec<usize>)> = None;
        while taut.len() <= max_taut && !seen.contains(&taut) {
            seen.push(taut.clone());
            let Some(best) = self.best_on_taut_set(
                data,
                &taut,
                &starts,
                squared,
                &mut iterations,
                &mut count,
                &mut closest,
            ) else {
                break;
            };
            match self.taut_set_move(data, &taut, &best) {
                TautMove::Accept => {
                    accepted = Some((best, taut.clone()));
                    break;
                }
                TautMove::Drop(k) => {
                    taut.remove(k);
                }
                TautMove::Add(j) => {
                    taut.push(j);
                    taut.sort_unstable();
                }
            }
        }
        // Complete search: every taut set (small: cables reaching one section), lowest valid.
        if accepted.is_none() {
            let m = data.cons.len();
            for mask in 0u32..(1 << m) {
                let set: Vec<usize> = (0..m).filter(|j| mask & (1 << j) != 0).collect();
                if set.len() > max_taut || seen.contains(&set) {
                    continue;
                }
                let Some(best) = self.best_on_taut_set(
                    data,
                    &set,
                    &starts,
                    squared,
                    &mut iterations,
                    &mut count,
                    &mut closest,
                ) else {
                    continue;
                };
                if matches!(self.taut_set_move(data, &set, &best), TautMove::Accept)
                    && accepted
                        .as_ref()
                        .is_none_or(|(a, _)| best.objective < a.objective)
                {
                    accepted = Some((best, set));
                }
            }
        }
        let Some((best, taut)) = accepted else {
            // Certified poses existed, yet in each some cable would push or be overstretched;
            // or Newton runs stalled at a positive residual: the lengths cannot all be met.
            if (count > 0 || closest > 1e-8) && !data.cons.is_empty() {
                let worst = (0..data.cons.len())
                    .max_by(|&a, &b| {
                        let va = data.chord(&straight, a) - data.cons[a].length;
                        let vb = data.chord(&straight, b) - data.cons[b].length;
                        va.total_cmp(&vb)
                    })
                    .unwrap_or(0);
                let near = data
                    .world
                    .as_ref()
                    .map(|w| {
                        format!(
                            " and keeps clear of the obstacles near this section ({})",
                            w.names.join(", ")
                        )
                    })
                    .unwrap_or_default();
                return Err(SolveError::Infeasible {
                    cable: data.names[data.cons[worst].cables[0]].clone(),
                    section: i,
                    reason: format!(
                        "no set of taut cables meets every cable length (each certified pose leaves a cable pushing or overstretched) while the backbone segment keeps its length l0 = {l0} m (this method's backbone is incompressible){near}; {count} poses examined"
                    ),
                });
            }
            return Err(SolveError::NotConverged {
                method: self.name().into(),
                section: Some(i),
                iterations,
                residual: closest,
                detail: "no face of the section problem gave a certified minimum".into(),
            });
        };
        let angles = data.term_angles(&best.pose);
        let zero_terms = data
            .terms
            .iter()
            .enumerate()
            .filter(|(t, _)| best.face & (1 << t) != 0 || angles[*t] <= self.zero_angle)
            .map(|(_, t)| t.label.clone())
            .collect();
        let mut slack: Vec<usize> = data.always_slack.clone();
        for j in 0..data.cons.len() {
            if !taut.contains(&j) {
                slack.extend(data.cons[j].cables.iter().copied());
            }
        }
        slack.sort_unstable();
        Ok(SectionSolution {
            contacts: best.contacts.clone(),
            pose: best.pose,
            report: SectionReport {
                section: i,
                iterations,
                residual: best.residual,
                objective: best.objective,
                zero_terms,
                slack: slack.iter().map(|&c| data.names[c].clone()).collect(),
                candidates: count,
            },
            slack,
        })
    }

    /// Starting poses: the smooth squared-angle solution (angles off their kinks), the previous
    /// section's relative pose, and the straight pose, both nudged off the kinks.
    fn starts(&self, data: &SectionData, prev: Option<&Pose>, it: &mut usize) -> Vec<Pose> {
        let straight = Pose::straight(data.l0);
        let mut starts = vec![];
        if self.objective == Objective::Squared {
            starts.push(straight);
            if let Some(p) = prev {
                starts.push(*p);
            }
            return starts;
        }
        let all: Vec<usize> = (0..data.cons.len())
            .filter(|&j| data.chord(&straight, j) > data.cons[j].length)
            .take(5 - usize::from(data.gauge.is_some()))
            .collect();
        if let Some(c) = self.smooth_start(data, &all, it) {
            starts.push(c);
        }
        if let Some(p) = prev {
            starts.push(nudge(p, data.l0));
        }
        starts.push(nudge(&straight, data.l0));
        starts
    }

    /// Lowest certified candidate over every face with this taut set (the straight pose, the
    /// exact minimum F = 0, when no cable is taut).
    #[allow(clippy::too_many_arguments)]
    fn best_on_taut_set(
        &self,
        data: &SectionData,
        taut: &[usize],
        starts: &[Pose],
        squared: bool,
        iterations: &mut usize,
        count: &mut usize,
        closest: &mut f64,
    ) -> Option<Candidate> {
        let n_terms = data.terms.len();
        // All cables slack: the straight pose, unless an obstacle is in its way — then the
        // angles are minimized against the obstacles alone, like any other taut set (was:
        // give up, so a robot pushed off its minimal bend by an obstacle was "infeasible").
        let straight_blocked = data.world.as_ref().is_some_and(|w| {
            w.pairs(&Pose::straight(data.l0))
                .iter()
                .any(|p| p.dist < w.clearance - CONTACT_TOL)
        });
        if taut.is_empty() && !straight_blocked {
            *count += 1;
            return Some(Candidate {
                pose: Pose::straight(data.l0),
                objective: 0.0,
                residual: 0.0,
                cable_lambda: vec![],
                face: (1 << n_terms) - 1,
                contacts: vec![],
            });
        }
        let fixed = 1 + taut.len() + usize::from(data.gauge.is_some());
        let faces: Vec<u32> = if squared {
            vec![0]
        } else {
            (0u32..(1 << n_terms))
                .filter(|f| fixed + 2 * f.count_ones() as usize <= 6)
                .collect()
        };
        let mut best: Option<Candidate> = None;
        for &face in &faces {
            for s in starts {
                match self.newton(data, s, face, taut, squared) {
                    Ok((cand, it)) => {
                        *iterations += it;
                        *count += 1;
                        if best
                            .as_ref()
                            .is_none_or(|b| cand.objective < b.objective - 1e-12)
                        {
                            best = Some(cand);
                        }
                    }
                    Err(r) => {
                        *iterations += r.iterations;
                        *closest = closest.min(r.residual);
                    }
                }
            }
        }
        best
    }

    /// Pull-only check of a candidate: drop the taut cable that would push most, or add the
    /// slack cable whose chord exceeds its length most, or accept.
    fn taut_set_move(&self, data: &SectionData, taut: &[usize], best: &Candidate) -> TautMove {
        let neg = best
            .cable_lambda
            .iter()
            .enumerate()
            .filter(|(_, &l)| l < -1e-9)
            .min_by(|a, b| a.1.total_cmp(b.1));
        if let Some((k, _)) = neg {
            return TautMove::Drop(k);
        }
        let over = (0..data.cons.len())
            .filter(|j| !taut.contains(j))
            .map(|j| (j, data.chord(&best.pose, j) - data.cons[j].length))
            .filter(|&(_, e)| e > 1e-10)
            .max_by(|a, b| a.1.total_cmp(&b.1));
        match over {
            Some((j, _)) => TautMove::Add(j),
            None => TautMove::Accept,
        }
    }

    /// Solve the smooth squared-angle problem from the straight pose, as a start for the
    /// literal faces (its angles are generically non-zero).
    fn smooth_start(&self, data: &SectionData, active: &[usize], it: &mut usize) -> Option<Pose> {
        let r = self.newton(data, &Pose::straight(data.l0), 0, active, true);
        match r {
            Ok((c, k)) => {
                *it += k;
                Some(c.pose)
            }
            Err(e) => {
                *it += e.iterations;
                None
            }
        }
    }

    /// Newton–KKT (SQP when obstacles are near) on one face from one start; returns a
    /// certified candidate or why not.
    ///
    /// Obstacle pairs within the margin enter each step as linearized inequalities
    /// `d_j + ∇d_j·dx ≥ clearance`; such steps are convex QPs solved by clarabel, steps without
    /// near pairs are the dense equality-only Newton–KKT step. The line search uses the ℓ1
    /// merit `F + ρ (Σ|c| + Σ max(0, clearance − d_j))`.
    fn newton(
        &self,
        data: &SectionData,
        start: &Pose,
        face: u32,
        active: &[usize],
        squared: bool,
    ) -> Result<(Candidate, usize), Rejected> {
        let mut pose = *start;
        let world = data.world.as_ref();
        let penetration = |pose: &Pose| -> f64 {
            world.map_or(0.0, |w| {
                w.pairs(pose)
                    .iter()
                    .map(|p| (w.clearance - p.dist).max(0.0))
                    .sum()
            })
        };
        let eval_f64 = |pose: &Pose| data.eval::<f64>(pose, face, active, squared);
        let mut lambda: Option<Vec<f64>> = None;
        let mut last_res = f64::INFINITY;
        let mut short_steps = 0;
        let mut rows: Vec<Vector6<f64>> = Vec::with_capacity(6);
        for it in 1..=self.max_iterations {
            let (f, c) = data.eval::<D2<6>>(&pose, face, active, squared);
            let k = c.len();
            if !f.v.is_finite() || c.iter().any(|x| !x.v.is_finite()) {
                return Err(Rejected {
                    iterations: it,
                    residual: last_res,
                });
            }
            let g = Vector6::from_row_slice(&f.g);
            rows.clear();
            rows.extend(c.iter().map(|cj| Vector6::from_row_slice(&cj.g)));
            let cv: Vec<f64> = c.iter().map(|cj| cj.v).collect();
            let lam = match &lambda {
                Some(l) => l.clone(),
                None => {
                    let a = DMatrix::from_fn(k, 6, |r, col| rows[r][col]);
                    multipliers(&DVector::from_row_slice(g.as_slice()), &a)
                        .as_slice()
                        .to_vec()
                }
            };
            let mut h = Matrix6::from_fn(|r, col| f.h[r][col]);
            for (j, cj) in c.iter().enumerate() {
                h += Matrix6::from_fn(|r, col| cj.h[r][col]) * lam[j];
            }
            if h.iter().any(|x| !x.is_finite()) {
                return Err(Rejected {
                    iterations: it,
                    residual: last_res,
                });
            }
            if !squared && it > 1 {
                let angles = data.term_angles(&pose);
                let into_kink = data
                    .terms
                    .iter()
                    .enumerate()
                    .any(|(t, _)| face & (1 << t) == 0 && angles[t] < 10.0 * self.zero_angle);
                if into_kink {
                    // This candidate belongs to a face where that term is zero.
                    return Err(Rejected {
                        iterations: it,
                        residual: cv.iter().fold(0.0f64, |m, x| m.max(x.abs())),
                    });
                }
            }
            let pairs = world.map(|w| w.pairs(&pose)).unwrap_or_default();
            let clearance = world.map_or(0.0, |w| w.clearance);
            let (step, mu) = if pairs.is_empty() {
                (self.step(&h, &g, &rows, &cv), vec![])
            } else {
                let in_rows: Vec<Vector6<f64>> = pairs.iter().map(|p| -p.grad).collect();
                let in_rhs: Vec<f64> = pairs.iter().map(|p| p.dist - clearance).collect();
                let eq_rhs: Vec<f64> = cv.iter().map(|x| -x).collect();
                let Some(q) = qp_step6(&h, &g, &rows, &eq_rhs, &in_rows, &in_rhs, 1e-10) else {
                    return Err(Rejected {
                        iterations: it,
                        residual: last_res,
                    });
                };
                let res0 = cv.iter().fold(0.0f64, |m, x| m.max(x.abs()));
                let gap0 = pairs
                    .iter()
                    .map(|p| clearance - p.dist)
                    .fold(0.0f64, f64::max);
                if res0 <= 1e-8 && gap0 <= 1e-8 {
                    // Polish: the interior-point step is accurate to ~1e-7 only; with the
                    // active contacts identified, an exact Newton–KKT step on them as
                    // equalities converges quadratically (multiplier of dist ≥ c is −λ).
                    let mu_max = q.mu.iter().fold(1.0f64, |m, x| m.max(*x));
                    let act: Vec<usize> = (0..pairs.len())
                        .filter(|&j| q.mu[j] > 1e-9 * mu_max)
                        .collect();
                    let mut all = rows.clone();
                    let mut cc = cv.clone();
                    for &j in &act {
                        all.push(pairs[j].grad);
                        cc.push(pairs[j].dist - clearance);
                    }
                    let st = self.step(&h, &g, &all, &cc);
                    let mut mu = vec![0.0; pairs.len()];
                    for (k, &j) in act.iter().enumerate() {
                        mu[j] = -st.lambda[rows.len() + k];
                    }
                    (
                        Step {
                            dx: st.dx,
                            lambda: st.lambda[..rows.len()].to_vec(),
                            min_reduced_eigenvalue: st.min_reduced_eigenvalue,
                        },
                        mu,
                    )
                } else {
                    (
                        Step {
                            dx: q.x,
                            lambda: q.lambda_eq,
                            min_reduced_eigenvalue: f64::NAN,
                        },
                        q.mu,
                    )
                }
            };
            let res = cv.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            let worst_gap = pairs
                .iter()
                .map(|p| clearance - p.dist)
                .fold(0.0f64, f64::max);
            last_res = res.max(worst_gap);
            let mut kkt_res = g;
            for (r, l) in rows.iter().zip(&step.lambda) {
                kkt_res += r * *l;
            }
            for (p, m) in pairs.iter().zip(&mu) {
                kkt_res -= p.grad * *m;
            }
            let stat = kkt_res.amax();
            // With active contacts the step carries the ~1e-8 m noise of parry's iterative
            // distance queries on smooth shapes: converge at CONTACT_STEP_TOL there.
            let mu_max = mu.iter().fold(0.0f64, |m, x| m.max(*x));
            let in_contact = mu_max > 1e-10;
            let step_tol = if in_contact { CONTACT_STEP_TOL } else { 1e-11 };
            if res <= self.tolerance && worst_gap <= CONTACT_TOL && step.dx.amax() <= step_tol {
                // Active contacts join the equalities for the second-order check.
                let active_pairs: Vec<usize> = (0..pairs.len())
                    .filter(|&j| mu.get(j).copied().unwrap_or(0.0) > 1e-10)
                    .collect();
                let min_eig = step.min_reduced_eigenvalue;
                let contacts: Vec<Contact> = active_pairs
                    .iter()
                    .map(|&j| pairs[j].to_contact(world, data.section, mu[j]))
                    .collect();
                if mu.iter().any(|m| *m < -1e-9) {
                    return Err(Rejected {
                        iterations: it,
                        residual: last_res,
                    });
                }
                let stat_tol = if in_contact {
                    CONTACT_STAT_TOL * (1.0 + mu_max)
                } else {
                    1e-7
                };
                return self.certify(
                    data,
                    pose,
                    face,
                    active,
                    squared,
                    &step.lambda,
                    (stat, stat_tol),
                    min_eig,
                    res,
                    it,
                    contacts,
                );
            }
            // Line search on the ℓ1 merit F + ρ (Σ|c| + Σ penetration).
            let amax = |v: &[f64]| v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            let rho = 2.0 * amax(&step.lambda).max(amax(&lam)).max(amax(&mu)) + 1.0;
            let merit = |f: f64, c: &[f64], pen: f64| {
                f + rho * (c.iter().map(|x| x.abs()).sum::<f64>() + pen)
            };
            let m0 = merit(f.v, &cv, penetration(&pose));
            let mut alpha = 1.0;
            let mut accepted = false;
            for _ in 0..20 {
                let trial = pose.retract(&step.dx, alpha);
                let (ft, ct) = eval_f64(&trial);
                let mt = merit(ft, &ct, penetration(&trial));
                if mt.is_finite() && (mt < m0 || step.dx.amax() * alpha < 1e-8) {
                    pose = trial;
                    accepted = true;
                    break;
                }
                alpha *= 0.5;
            }
            if alpha < 1e-3 {
                short_steps += 1;
            } else {
                short_steps = 0;
            }
            if !accepted || short_steps >= 3 {
                return Err(Rejected {
                    iterations: it,
                    residual: last_res,
                });
            }
            lambda = Some(step.lambda);
        }
        Err(Rejected {
            iterations: self.max_iterations,
            residual: last_res,
        })
    }

    /// One Newton–KKT step: the allocation-free 6×6 kernel, or the general one when the
    /// constraint rows are redundant (its multiplier system is singular).
    fn step(&self, h: &Matrix6<f64>, g: &Vector6<f64>, rows: &[Vector6<f64>], c: &[f64]) -> Step {
        if let Some(s) = kkt_step6(h, g, rows, c, 1e-10) {
            return Step {
                dx: s.dx,
                lambda: s.lambda[..rows.len()].to_vec(),
                min_reduced_eigenvalue: s.min_reduced_eigenvalue,
            };
        }
        let hd = DMatrix::from_fn(6, 6, |r, col| h[(r, col)]);
        let gd = DVector::from_row_slice(g.as_slice());
        let ad = DMatrix::from_fn(rows.len(), 6, |r, col| rows[r][col]);
        let s = kkt_step(&hd, &gd, &ad, &DVector::from_row_slice(c), 1e-10);
        Step {
            dx: Vector6::from_row_slice(s.dx.as_slice()),
            lambda: s.lambda.as_slice().to_vec(),
            min_reduced_eigenvalue: s.min_reduced_eigenvalue,
        }
    }

    #[allow(clippy::too_many_arguments)]
    fn certify(
        &self,
        data: &SectionData,
        pose: Pose,
        face: u32,
        active: &[usize],
        squared: bool,
        lambda: &[f64],
        (stationarity, stat_tol): (f64, f64),
        min_eig: f64,
        residual: f64,
        it: usize,
        contacts: Vec<Contact>,
    ) -> Result<(Candidate, usize), Rejected> {
        let reject = Err(Rejected {
            iterations: it,
            residual,
        });
        if stationarity > stat_tol || min_eig < -1e-8 || min_eig.is_nan() {
            return reject;
        }
        let angles = data.term_angles(&pose);
        let mut row = 1 + active.len();
        let mut objective = 0.0;
        for (t, term) in data.terms.iter().enumerate() {
            if face & (1 << t) != 0 {
                let mu = (lambda[row].powi(2) + lambda[row + 1].powi(2)).sqrt();
                if mu > term.weight * (1.0 + 1e-9) {
                    return reject;
                }
                row += 2;
            } else {
                if !squared && angles[t] <= self.zero_angle {
                    return reject;
                }
                objective += term.weight
                    * if squared {
                        angles[t] * angles[t]
                    } else {
                        angles[t]
                    };
            }
        }
        let cable_lambda = (0..active.len()).map(|k| lambda[1 + k]).collect();
        Ok((
            Candidate {
                pose,
                objective,
                residual,
                cable_lambda,
                face,
                contacts,
            },
            it,
        ))
    }
}

/// A start moved slightly off every kink (deterministic).
fn nudge(p: &Pose, l0: f64) -> Pose {
    Pose {
        p: p.p + l0 * Vector3::new(1.3e-3, -0.7e-3, 0.0),
        q: orthonormalize(&(p.q * exp_so3(&Vector3::new(0.9e-3, 1.1e-3, -0.8e-3)))),
    }
}

/// Newton step size at which a candidate with active contacts has converged [m or rad]: parry's
/// GJK on smooth–smooth pairs (disk rim against a cylinder or a tube) leaves ~1e-8 of noise.
const CONTACT_STEP_TOL: f64 = 1e-7;

/// Stationarity a candidate with active contacts must meet, relative to (1 + largest contact
/// multiplier): the contact normals carry the same noise.
const CONTACT_STAT_TOL: f64 = 1e-6;

/// A robot feature of one section.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Feature {
    /// The backbone segment of the section, a capsule of the backbone radius.
    Backbone,
    /// The disk at the section's end, a thin cylinder.
    Disk,
    /// The straight chord of a cable (its index) in the section.
    Cable(usize),
}

/// One robot feature near one obstacle, linearized at the current pose.
struct Pair {
    obstacle: usize,
    feature: Feature,
    /// Signed distance \[m\].
    dist: f64,
    /// ∂dist/∂(dp, dω) in the section's variables.
    grad: Vector6<f64>,
    point_robot: Vector3<f64>,
    point_obstacle: Vector3<f64>,
    /// Unit normal from the obstacle towards the robot.
    normal: Vector3<f64>,
}

impl Pair {
    fn to_contact(&self, world: Option<&SectionWorld>, section: usize, mu: f64) -> Contact {
        let arr = |v: &Vector3<f64>| [v.x, v.y, v.z];
        let (feature, disk, sec) = match self.feature {
            Feature::Backbone => ("backbone".to_string(), None, Some(section)),
            Feature::Disk => ("disk".to_string(), Some(section), None),
            Feature::Cable(c) => (
                format!(
                    "cable:{}",
                    world.map_or(String::new(), |w| w.cable_names[c].clone())
                ),
                None,
                Some(section),
            ),
        };
        Contact {
            obstacle: world.map_or(String::new(), |w| w.name(self.obstacle)),
            feature,
            disk,
            section: sec,
            point_robot: arr(&self.point_robot),
            point_obstacle: arr(&self.point_obstacle),
            normal: arr(&self.normal),
            distance: self.dist,
            multiplier: mu,
        }
    }
}

/// What section `i` sees of the scene: the obstacles the broad phase kept, and the fixed
/// geometry of disk `i−1` in the base frame.
struct SectionWorld {
    names: Vec<String>,
    shapes: Vec<(parry3d::shape::SharedShape, PPose)>,
    cable_names: Vec<String>,
    r_prev: Matrix3<f64>,
    x_prev: Vector3<f64>,
    /// (cable, hole at disk i−1 in the base frame, hole at disk i in its disk frame).
    holes: Vec<(usize, Vector3<f64>, Vector3<f64>)>,
    backbone_radius: f64,
    disk_radius: f64,
    half_thickness: f64,
    clearance: f64,
    /// Pairs farther apart than this are left out of the step \[m\].
    margin: f64,
}

impl SectionWorld {
    fn new(
        robot: &Robot,
        scene: &Scene,
        relevant: &[usize],
        i: usize,
        r_prev: &Matrix3<f64>,
        x_prev: &Vector3<f64>,
    ) -> Option<SectionWorld> {
        if relevant.is_empty() {
            return None;
        }
        let l = robot.section_length(i);
        let margin = 0.5 * l + scene.clearance;
        let reach = l + robot.disk_radius + robot.disk_thickness + scene.clearance + margin;
        // Only the robot-level survivors are tested again (was: every obstacle of the scene
        // tested, then a quadratic `relevant.contains` filter).
        let near = scene.near_among(relevant, x_prev, reach);
        if near.is_empty() {
            return None;
        }
        Some(SectionWorld {
            names: near
                .iter()
                .map(|&k| scene.obstacles[k].name.clone())
                .collect(),
            shapes: near
                .iter()
                .map(|&k| {
                    (
                        scene.obstacles[k].shape.clone(),
                        scene.obstacles[k].parry_pose,
                    )
                })
                .collect(),
            cable_names: robot.cables.iter().map(|c| c.name.clone()).collect(),
            r_prev: *r_prev,
            x_prev: *x_prev,
            holes: robot
                .cables
                .iter()
                .enumerate()
                .filter(|(_, c)| c.reaches_section(i))
                .map(|(k, c)| (k, x_prev + r_prev * c.hole(i - 1), c.hole(i)))
                .collect(),
            backbone_radius: robot.backbone.radius(),
            disk_radius: robot.disk_radius,
            half_thickness: robot.disk_thickness / 2.0,
            clearance: scene.clearance,
            margin,
        })
    }

    fn name(&self, k: usize) -> String {
        self.names[k].clone()
    }

    /// Every feature–obstacle pair within the margin at this pose, linearized.
    ///
    /// With `n` the unit normal from the robot point `a` towards the obstacle, moving `a` by
    /// `δa` changes the distance by `−n·δa`. Points carried by the new disk move as
    /// `δa = R δp − R Q [ℓ]× δω` (ℓ: the point in the disk frame), points on a segment from a
    /// fixed end to a moving end by the fraction `t` of that.
    fn pairs(&self, pose: &Pose) -> Vec<Pair> {
        let r = &self.r_prev;
        let x0 = self.x_prev + r * pose.p;
        let ri = r * pose.q;
        let identity = PPose::IDENTITY;
        let mut out = vec![];
        let backbone = Capsule::new(pvec(&self.x_prev), pvec(&x0), self.backbone_radius);
        let disk = Cylinder::new(self.half_thickness, self.disk_radius);
        let disk_pose = ppose(&(ri * y_to_z()), &x0);
        // (cable, hole at disk i−1, hole at disk i, that hole in disk i's frame)
        type Chord = (usize, Vector3<f64>, Vector3<f64>, Vector3<f64>);
        let chords: Vec<Chord> = self
            .holes
            .iter()
            .map(|(c, hp, h)| (*c, *hp, x0 + ri * h, *h))
            .collect();
        for (k, (shape, opose)) in self.shapes.iter().enumerate() {
            let mut push = |feature: Feature, g: &dyn PShape, gpose: &PPose| {
                let Some(ct) = query(gpose, g, opose, &**shape, self.margin) else {
                    return;
                };
                let mut a = nvec(ct.point1);
                let mut n = nvec(ct.normal1);
                let mut po = nvec(ct.point2);
                let mut dist = ct.dist;
                let rough = Witness {
                    robot: a,
                    obstacle: po,
                    normal: -n,
                    dist,
                };
                if let Some(w) = polish(g, gpose, &**shape, opose, &rough) {
                    (a, po, n, dist) = (w.robot, w.obstacle, -w.normal, w.dist);
                }
                if feature == Feature::Disk {
                    // The iterative query places the witness on the rim to ~1e-6 only; for a
                    // convex feature it is exactly the support point along the normal.
                    let u = ri.transpose() * n;
                    let uxy = (u.x * u.x + u.y * u.y).sqrt();
                    if uxy > 1e-6 {
                        let l = Vector3::new(
                            self.disk_radius * u.x / uxy,
                            self.disk_radius * u.y / uxy,
                            self.half_thickness * u.z.signum(),
                        );
                        a = x0 + ri * l;
                    }
                }
                let rn = r.transpose() * n;
                let qrn = pose.q.transpose() * rn;
                let (gp, gw) = match feature {
                    Feature::Backbone => {
                        let d = x0 - self.x_prev;
                        let t = ((a - self.x_prev).dot(&d) / d.norm_squared()).clamp(0.0, 1.0);
                        (-t * rn, Vector3::zeros())
                    }
                    Feature::Disk => {
                        let l = ri.transpose() * (a - x0);
                        (-rn, qrn.cross(&l))
                    }
                    Feature::Cable(j) => {
                        let (_, hp, hc, h) = chords[j];
                        let d = hc - hp;
                        let t = if d.norm_squared() > 0.0 {
                            ((a - hp).dot(&d) / d.norm_squared()).clamp(0.0, 1.0)
                        } else {
                            1.0
                        };
                        (-t * rn, t * qrn.cross(&h))
                    }
                };
                out.push(Pair {
                    obstacle: k,
                    feature,
                    dist,
                    grad: Vector6::new(gp.x, gp.y, gp.z, gw.x, gw.y, gw.z),
                    point_robot: a,
                    point_obstacle: po,
                    normal: -n,
                });
            };
            push(Feature::Backbone, &backbone, &identity);
            push(Feature::Disk, &disk, &disk_pose);
            for (j, (_, hp, hc, _)) in chords.iter().enumerate() {
                if (hc - hp).norm() > 0.0 {
                    push(
                        Feature::Cable(j),
                        &Segment::new(pvec(hp), pvec(hc)),
                        &identity,
                    );
                }
            }
        }
        // Feature::Cable holds the index into `chords`; report the cable's own index.
        for p in &mut out {
            if let Feature::Cable(j) = p.feature {
                p.feature = Feature::Cable(chords[j].0);
            }
        }
        out
    }
}

/// Relative poses (disk i in the frame of disk i−1) of a solved shape, as warm starts.
fn relative_poses(shape: &Shape) -> Vec<Pose> {
    shape
        .disks
        .windows(2)
        .map(|w| Pose {
            p: w[0].rotation.transpose() * (w[1].position - w[0].position),
            q: w[0].rotation.transpose() * w[1].rotation,
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The closed-form derivatives of `Q exp([w]×) h` at w = 0 match central finite
    /// differences of the exact exponential map.
    #[test]
    fn rotated_derivatives_match_finite_differences() {
        let q = exp_so3(&Vector3::new(0.3, -0.5, 0.8));
        let h = Vector3::new(0.008, -0.003, 0.001);
        let d = <D2<6> as SectionScalar>::rotated(&q, &h);
        let f = |w: &Vector3<f64>| q * exp_so3(w) * h;
        let e = 1e-5;
        for r in 0..3 {
            assert!((d.0[r].v - (q * h)[r]).abs() < 1e-15);
            for i in 0..3 {
                let mut wp = Vector3::zeros();
                wp[i] = e;
                let fd = (f(&wp)[r] - f(&-wp)[r]) / (2.0 * e);
                assert!((fd - d.0[r].g[3 + i]).abs() < 1e-12, "gradient {r} {i}");
                for j in 0..3 {
                    let mut wj = Vector3::zeros();
                    wj[j] = e;
                    let fd2 = (f(&(wp + wj))[r] - f(&(wp - wj))[r] - f(&(wj - wp))[r]
                        + f(&(-wp - wj))[r])
                        / (4.0 * e * e);
                    assert!(
                        (fd2 - d.0[r].h[3 + i][3 + j]).abs() < 1e-7,
                        "hessian {r} {i} {j}"
                    );
                }
            }
        }
    }
}
