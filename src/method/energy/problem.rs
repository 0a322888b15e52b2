//! The problem of one energy solve, fixed before iterating: sub-arc lengths and stiffnesses,
//! routing samples at the Gauss nodes, what each cable imposes ([`Target`]), dead loads,
//! obstacles within reach; the energy, the load potential and its gradient, the cable length
//! constraint ([`Problem::cable_gap`]).

use super::contacts::{Kin, World};
use super::kinematics::{sub_arc_exp, GL_NODES, GL_W, GL_X};
use super::lengths::Node;
use super::Energy;
use crate::contact::broad;
use crate::error::SolveError;
use crate::method::Method;
use crate::model::actuation::{Actuation, Drive, LengthMeasure};
use crate::model::robot::Robot;
use crate::model::routing::Route;
use crate::model::scene::Scene;
use crate::numeric::so3::log_so3;
use crate::shape::DiskFrame;
use nalgebra::Vector3;
use std::borrow::Cow;
use std::cell::RefCell;

/// Routing samples of one cable, `[j][q]` (sub-arc, Gauss node).
pub(super) type NodeRow = Vec<[Node; GL_NODES]>;

/// What an energy solve needs of the robot alone (with the settings): computed once per
/// robot by [`crate::method::Method::prepare`], shared by every solve of it.
pub(super) struct RobotPart {
    /// Routing samples `[c][j][q]` (path measure; empty for chords).
    pub(super) nodes: Vec<NodeRow>,
    /// Undeformed length of every cable in the chosen measure \[m\].
    pub(super) len0: Vec<f64>,
}

/// What a cable imposes in this method, from its resolved [`Drive`]: a length constraint
/// (its target length in the chosen measure), a constant tension, or nothing.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Target {
    /// Length constraint with this target \[m\].
    Length(f64),
    /// Constant tension \[N\] (potential `T L`).
    Tension(f64),
    /// Nothing.
    Free,
}

/// Everything fixed during one solve.
pub(super) struct Problem<'a> {
    pub(super) robot: &'a Robot,
    pub(super) set: &'a Energy,
    /// Sub-arc index at which each section starts, base first, then the total: section `i`
    /// (1-based) is sub-arcs `first[i − 1]..first[i]`, and disk `k`'s frame is frame
    /// `first[k]` ([`Energy::counts`]: sections may differ).
    pub(super) first: Vec<usize>,
    /// Total sub-arcs.
    pub(super) nsub: usize,
    /// Sub-arc lengths.
    pub(super) ell: Vec<f64>,
    /// Diagonal stiffness of each variable (ℓ·EI, ℓ·EI, ℓ·GJ, ℓ·EA).
    pub(super) k: Vec<f64>,
    /// The backbone's curvature stiffening `β` \[m²\] (0: the energy is the quadratic
    /// `½ Σ k ξ²`; [`Problem::energy`]).
    pub(super) stiffening: f64,
    /// Gauss samples `[c][j][q]` (path measure; empty for sub-arcs the cable does not reach).
    pub(super) nodes: Cow<'a, [NodeRow]>,
    pub(super) targets: Vec<Target>,
    /// Compliance `1/k` of each cable \[m/N\] (0: inextensible).
    pub(super) compliance: Vec<f64>,
    /// Undeformed length of every cable in the chosen measure \[m\] (set by
    /// [`Energy::setup_from`]; the straight rod's).
    pub(super) len0: Vec<f64>,
    /// Block size (4 for paths, 4m for chords) and count.
    pub(super) nb: usize,
    pub(super) nblocks: usize,
    /// Stationarity scale: r̄ / (EI ℓ_min).
    pub(super) stat_scale: f64,
    /// Obstacles within reach (none: no distance constraints).
    pub(super) world: Option<World<'a>>,
    /// Dead loads at the sub-arc ends (frame `f` = end of sub-arc `f − 1`; empty: none):
    /// backbone weight lumped half to each end of its sub-arc, disk weights, the tip force.
    pub(super) frame_forces: Vec<Vector3<f64>>,
    /// Shear strains `(γx, γy)` of every sub-arc: the one part of the problem an iteration
    /// changes, condensed from the equilibrium of the shear force at every Newton iterate
    /// (`energy/shear.rs`); empty: the unshearable model (`shear = off`).
    pub(super) shear: RefCell<Vec<[f64; 2]>>,
    /// Shear stiffness `GA` of the backbone \[N\] (the Cosserat rod's, [`crate::model::robot::Backbone::ga`]).
    pub(super) ga: f64,
    /// Compute the stability and tip Jacobian at the solution ([`Energy::sensitivity`]; off in
    /// the passes of a solve with capstan friction, `energy/friction.rs`).
    pub(super) want_sensitivity: bool,
}

impl Problem<'_> {
    /// Cable `c`'s weight in the objective and its Hessian: the multiplier `lam` of a length
    /// target (the cable's tension), the given tension of a tension target, 0 for a free cable.
    pub(super) fn cable_weight(&self, c: usize, lam: f64) -> f64 {
        match self.targets[c] {
            Target::Length(_) => lam,
            Target::Tension(t) => t,
            Target::Free => 0.0,
        }
    }

    pub(super) fn nvar(&self) -> usize {
        4 * self.nsub
    }

    /// The shear strains of sub-arc `j` (zero without shear).
    #[inline]
    pub(super) fn shear_at(&self, j: usize) -> [f64; 2] {
        self.shear.borrow().get(j).copied().unwrap_or_default()
    }

    /// Frames at the sub-arc ends of the strains `xi` with this problem's shear; with
    /// `integrals`, also `M_j`, `N_j` (`energy/contacts.rs`).
    pub(super) fn kin(&self, xi: &[f64], integrals: bool) -> Kin {
        super::contacts::sheared_kinematics(xi, &self.shear.borrow(), &self.ell, integrals)
    }

    /// Section (1-based) of sub-arc `j`.
    pub(super) fn section_of(&self, j: usize) -> usize {
        section_of(&self.first, j)
    }

    /// Sub-arcs of section `i` (1-based).
    pub(super) fn count(&self, i: usize) -> usize {
        self.first[i] - self.first[i - 1]
    }

    /// The cable length constraint of displacement-driven cable `c` at path length `len` and
    /// tension `lam`: `L_c − t_c − λ_c/k_c` \[m\], ≤ 0 when satisfied (0 when the cable is
    /// taut), with the unstretched target `t_c = L_c⁰ − δ_c − T₀_c/k_c` (module docs of
    /// [`super`], "Compliant cables"). The one place that says what a cable's length must be:
    /// the residual reads it with the iterate's tension; the step's QP row reads the rigid part
    /// (`lam = 0`) and puts `1/k` on its dual diagonal ([`Problem::compliance`]); the merit
    /// counts a compliant cable as the spring potential [`Problem::spring_energy`].
    #[inline]
    pub(super) fn cable_gap(&self, c: usize, len: f64, lam: f64) -> f64 {
        match self.targets[c] {
            Target::Length(t) => len - t - lam * self.compliance[c],
            _ => len,
        }
    }

    /// Bound on the round-off of the cable terms of the merit at lengths `len` \[J\]: each
    /// cable's weight (`pen` on a length target — the ℓ1 penalty of a rigid cable and, as
    /// `pen ≥ λ`, the slope `k (L − t)₊` of a compliant cable's spring — or `|T|` on a tension
    /// target) times the round-off of its computed length.
    ///
    /// A length is a recursively summed total of `n` positive terms (`ds |w|` at every Gauss
    /// node for paths; one chord per section, each a chain of `m` exponentials, for chords),
    /// each term good to a few units of round-off `u`. Recursive summation errs by at most
    /// `γ_{n−1} Σ|x_i|`, `γ_n = n u / (1 − n u)` (Higham, *Accuracy and Stability of Numerical
    /// Algorithms*, 2nd ed., §4.2), so `|L̂ − L| ≤ (n + 8) ε L` with `ε = 2u` bounds the terms'
    /// own error, the sum and the subtraction of the target (`8 m` terms per chord).
    ///
    /// Why the line search takes a step within this bound (`newton/line_search.rs`): near the
    /// solution the ℓ1 merit `φ = E + pen Σ (L_c − t_c)₊ + …` changes by `∇φ·d ≈ −dᵀHd` (H the
    /// Lagrangian Hessian, ⪰ K the energy's) once the lengths are met. With `β > 0` (non-quadratic
    /// energy) the second Newton step of an FTDCR row predicts ~1e-15 J while `pen × δL` is
    /// ~1e-14 J, so `φ(x + d) − φ(x)` is round-off of either sign and Armijo's test rejected the
    /// unit step at random; the backtracked step then took the step's multipliers with a tiny
    /// `α`, and stationarity stalled at 1e-8–1e-6 (`tests/hardware/hardware_roundoff.rs`).
    /// A merit that cannot resolve the decrease cannot judge the step, so it is taken when both
    /// the predicted decrease and the actual change lie below the bound: the unit Newton step is
    /// what converges locally (Nocedal & Wright, *Numerical Optimization*, 2nd ed., §18.7; the
    /// rows of the test take two iterations), merits that reject it near
    /// the solution are the known failure of §15.5–15.6, and accepting within an error bound of
    /// `φ` is the approximate Armijo test of Hager & Zhang (SIAM J. Optim. 16 (2005) 170–192,
    /// §4: near a minimizer `φ` differences lose their accuracy). The residuals still decide
    /// convergence, and `|∇φ·d| ≤ bound` keeps the step small: the step's QP gives
    /// `∇φ·d ≤ −dᵀHd`, and `H ⪰ K` for the convex cable terms, so `dᵀKd ≤ bound`.
    pub(super) fn merit_roundoff(&self, len: &[f64], pen: f64) -> f64 {
        (0..len.len())
            .map(|c| {
                let weight = match self.targets[c] {
                    Target::Length(_) => pen,
                    Target::Tension(t) => t.abs(),
                    Target::Free => 0.0,
                };
                let terms = match self.set.cable_length {
                    LengthMeasure::Path => self.nodes[c].len() * GL_NODES,
                    LengthMeasure::Chord => 8 * self.first[self.robot.cables[c].ends_at],
                };
                weight * (terms + 8) as f64 * f64::EPSILON * len[c].abs()
            })
            .sum()
    }

    /// Whether cable `c` is a displacement-driven compliant cable (a spring, not a constraint,
    /// in the merit).
    #[inline]
    pub(super) fn is_spring(&self, c: usize) -> bool {
        self.compliance[c] > 0.0 && matches!(self.targets[c], Target::Length(_))
    }

    /// Tension of compliant cable `c` at path length `len`, `k (L − t)₊` \[N\] (0 for others).
    #[inline]
    pub(super) fn spring_tension(&self, c: usize, len: f64) -> f64 {
        if self.is_spring(c) {
            self.cable_gap(c, len, 0.0).max(0.0) / self.compliance[c]
        } else {
            0.0
        }
    }

    /// Potential of the compliant cables, `Σ ½ k (L − t)₊²` \[J\]: eliminating the tension from
    /// `L − t − λ/k ≤ 0 ⊥ λ ≥ 0` gives `λ = k (L − t)₊`, the force of this potential.
    pub(super) fn spring_energy(&self, len: &[f64]) -> f64 {
        (0..len.len())
            .filter(|&c| self.is_spring(c))
            .map(|c| 0.5 * self.spring_tension(c, len[c]) * self.cable_gap(c, len[c], 0.0).max(0.0))
            .sum()
    }

    /// The elastic energy `E(ξ) = Σ_j ½ ℓ_j (EI κ_j² (1 + β κ_j²) + GJ τ_j² + EA ε_j²)`,
    /// `κ_j² = κx² + κy²` \[J\]. With the backbone's curvature stiffening `β = 0` it is the
    /// quadratic `½ Σ k ξ²` of the module docs of [`super`]; `β > 0` adds `½ β ℓ EI κ⁴` per
    /// sub-arc, convex (κ⁴ is), so the problem stays convex. A constant-curvature arc under a
    /// pure moment `M` is stationary at `∂/∂κ (½ EI κ² (1 + β κ²)) = EI κ (1 + 2 β κ²) = M`
    /// (`tests/methods/stiffening.rs` checks that closed form).
    pub(super) fn energy(&self, xi: &[f64]) -> f64 {
        let quad =
            0.5 * xi.iter().zip(&self.k).map(|(x, k)| k * x * x).sum::<f64>() + self.shear_energy();
        if self.stiffening == 0.0 {
            return quad;
        }
        quad + (0..self.nsub)
            .map(|j| {
                let k2 = xi[4 * j] * xi[4 * j] + xi[4 * j + 1] * xi[4 * j + 1];
                0.5 * self.stiffening * self.k[4 * j] * k2 * k2
            })
            .sum::<f64>()
    }

    /// `∇E` into `g` (overwritten): `k_i ξ_i`, plus `2 β ℓ EI κ² κ_a` on the two curvatures
    /// `κ_a` of each sub-arc when `β > 0` ([`Problem::energy`]).
    pub(super) fn energy_gradient(&self, xi: &[f64], g: &mut [f64]) {
        for i in 0..self.nvar() {
            g[i] = self.k[i] * xi[i];
        }
        if self.stiffening == 0.0 {
            return;
        }
        for j in 0..self.nsub {
            let (kx, ky) = (xi[4 * j], xi[4 * j + 1]);
            let c = 2.0 * self.stiffening * self.k[4 * j] * (kx * kx + ky * ky);
            g[4 * j] += c * kx;
            g[4 * j + 1] += c * ky;
        }
    }

    /// `∇²E`'s 2×2 curvature block of sub-arc `j` beyond the diagonal `k` when `β > 0`:
    /// `ℓ EI β (2 κ² δ_ab + 4 κ_a κ_b)`, `a, b ∈ {x, y}` (the exact second derivative of
    /// `½ β ℓ EI κ⁴`; [`Problem::energy`]). Zero for `β = 0`.
    #[inline]
    pub(super) fn stiffening_block(&self, xi: &[f64], j: usize) -> [[f64; 2]; 2] {
        let (kx, ky) = (xi[4 * j], xi[4 * j + 1]);
        let c = self.stiffening * self.k[4 * j];
        let k2 = kx * kx + ky * ky;
        [
            [c * (2.0 * k2 + 4.0 * kx * kx), c * 4.0 * kx * ky],
            [c * 4.0 * kx * ky, c * (2.0 * k2 + 4.0 * ky * ky)],
        ]
    }

    /// Whether an iterate needs its frames (obstacles or dead loads); they are computed once
    /// per point and shared by both.
    pub(super) fn needs_frames(&self) -> bool {
        self.world.is_some() || !self.frame_forces.is_empty()
    }

    /// Potential of the dead loads, `V = −Σ F_f · p_f` \[J\] (0 without loads), at the frames
    /// `kin` of the strains.
    pub(super) fn load_potential(&self, kin: Option<&Kin>) -> f64 {
        let Some(kin) = kin.filter(|_| !self.frame_forces.is_empty()) else {
            return 0.0;
        };
        -self
            .frame_forces
            .iter()
            .zip(&kin.pos)
            .map(|(f, p)| f.dot(p))
            .sum::<f64>()
    }

    /// Add `∇V` to `g`. A frame origin beyond sub-arc `j` moves by
    /// `∂x/∂u_a = (M_j e_a) × x − N_{j,a}`, `∂x/∂ε = M_j e_z` (`energy/contacts.rs`), so with
    /// the suffix sums `S_j = Σ_{f>j} F_f`, `C_j = Σ_{f>j} p_f × F_f`:
    /// `∂V/∂u_a = −((M_j e_a) · C_j − N_{j,a} · S_j)`, `∂V/∂ε = −(M_j e_z) · S_j`.
    /// `kin` must carry the integrals.
    pub(super) fn add_load_gradient(&self, kin: Option<&Kin>, g: &mut [f64]) {
        let Some(kin) = kin.filter(|_| !self.frame_forces.is_empty()) else {
            return;
        };
        let (mut sum, mut mom) = (Vector3::zeros(), Vector3::zeros());
        for j in (0..self.nsub).rev() {
            let f = &self.frame_forces[j + 1];
            sum += f;
            mom += kin.pos[j + 1].cross(f);
            let m = &kin.m_int[j];
            let mc = m.tr_mul(&mom);
            let ms = m.tr_mul(&sum);
            let nj = &kin.n_int[j];
            g[4 * j] -= mc.x - nj[0].dot(&sum);
            g[4 * j + 1] -= mc.y - nj[1].dot(&sum);
            g[4 * j + 2] -= mc.z - nj[2].dot(&sum);
            g[4 * j + 3] -= ms.z;
        }
    }

    /// Strains that put the disks where `disks` has them, approximately: per section, the
    /// constant strain whose exponential has the section's relative rotation (`u = log(R)/l`)
    /// and its chord length (`ε`), on every sub-arc of the section. A start for shapes from
    /// other methods (e.g. the geometric method's inside a tube, where the straight start
    /// would cross the wall); non-finite frames leave the straight start.
    pub(super) fn strains_from_disks(&self, disks: &[DiskFrame], xi: &mut [f64]) {
        let mut out = vec![0.0; xi.len()];
        for i in 1..disks.len() {
            let (a, b) = (&disks[i - 1], &disks[i]);
            let r = a.rotation.transpose() * b.rotation;
            let p = a.rotation.transpose() * (b.position - a.position);
            let l = self.robot.section_length(i);
            let u = log_so3(&r) / l;
            let (_, unit) = sub_arc_exp(&[u.x, u.y, u.z, 0.0], l);
            let stretch = p.norm() / unit.norm();
            for j in self.first[i - 1]..self.first[i] {
                out[4 * j..4 * j + 4].copy_from_slice(&[u.x, u.y, u.z, stretch - 1.0]);
            }
        }
        if out.iter().all(|v| v.is_finite()) {
            xi.copy_from_slice(&out);
        }
    }

    /// Upper bound on how far a change `d` of the strains moves any point of the robot \[m\]:
    /// turning sub-arc `j` by `ℓ_j |δu_j|` moves what lies beyond it by at most that angle
    /// times the length beyond, stretching it by `ℓ_j |δε_j|`.
    pub(super) fn move_bound(&self, d: &[f64]) -> f64 {
        let total: f64 = self.ell.iter().sum();
        let mut s = 0.0;
        let mut bound = 0.0;
        for (j, l) in self.ell.iter().enumerate() {
            let du =
                (d[4 * j] * d[4 * j] + d[4 * j + 1] * d[4 * j + 1] + d[4 * j + 2] * d[4 * j + 2])
                    .sqrt();
            bound += l * (du * (total - s) + d[4 * j + 3].abs());
            s += l;
        }
        bound
    }
}

impl Energy {
    /// The problem of one solve of `robot` (its routing samples computed here).
    pub(super) fn setup<'a>(
        &'a self,
        robot: &'a Robot,
        act: &Actuation,
        scene: &'a Scene,
    ) -> Result<Problem<'a>, SolveError> {
        let part = self.robot_part(robot)?;
        self.setup_from(robot, act, scene, Cow::Owned(part.nodes), &part.len0)
    }

    /// Routing samples and undeformed cable lengths of `robot` (straight backbone, ξ = 0).
    pub(super) fn robot_part(&self, robot: &Robot) -> Result<RobotPart, SolveError> {
        let mut prob = self.bare(robot, Cow::Owned(vec![]), &self.counts(robot)?);
        if self.cable_length == LengthMeasure::Path {
            prob.nodes = Cow::Owned(self.gauss_nodes(robot, &prob.ell, &prob.first)?);
        }
        let mut len0 = vec![0.0; robot.cables.len()];
        prob.lengths(&vec![0.0; prob.nvar()], &mut len0);
        Ok(RobotPart {
            nodes: prob.nodes.into_owned(),
            len0,
        })
    }

    /// The sub-arcs, stiffnesses and block layout of `robot`, with the routing samples
    /// `nodes` and the sub-arcs `counts` of each section ([`Energy::counts`]); every cable
    /// free, no loads, no obstacles.
    fn bare<'a>(
        &'a self,
        robot: &'a Robot,
        nodes: Cow<'a, [NodeRow]>,
        counts: &[usize],
    ) -> Problem<'a> {
        let n = robot.sections();
        let mut first = Vec::with_capacity(n + 1);
        first.push(0);
        for m in counts {
            first.push(first.last().copied().unwrap_or(0) + m);
        }
        let nsub = first[n];
        let bb = &robot.backbone;
        let (ei, gj, ea) = (bb.ei(), bb.gj(), bb.ea());
        let mut ell = Vec::with_capacity(nsub);
        let mut k = Vec::with_capacity(4 * nsub);
        for (i, &m) in counts.iter().enumerate() {
            let l = robot.section_length(i + 1) / m as f64;
            for _ in 0..m {
                ell.push(l);
                k.extend_from_slice(&[l * ei, l * ei, l * gj, l * ea]);
            }
        }
        // The chord measure's blocks are sections, of one count (`Energy::check`).
        let (nb, nblocks) = match self.cable_length {
            LengthMeasure::Path => (4, nsub),
            LengthMeasure::Chord => (4 * counts.first().copied().unwrap_or(1), n),
        };
        let rbar = robot
            .cables
            .iter()
            .flat_map(|c| c.radius.iter())
            .fold(0.0f64, |a, &r| a.max(r));
        let rbar = if rbar > 0.0 { rbar } else { robot.disk_radius };
        let lmin = ell.iter().cloned().fold(f64::INFINITY, f64::min);
        Problem {
            robot,
            set: self,
            first,
            nsub,
            ell,
            k,
            stiffening: bb.stiffening,
            nodes,
            targets: vec![Target::Free; robot.cables.len()],
            compliance: robot.cables.iter().map(|c| c.compliance()).collect(),
            len0: vec![],
            nb,
            nblocks,
            stat_scale: rbar / (ei * lmin),
            world: None,
            frame_forces: vec![],
            shear: RefCell::new(vec![]),
            ga: bb.ga(),
            want_sensitivity: self.sensitivity,
        }
    }

    /// The problem of one solve from the robot's prepared part (`nodes`, `len0` of
    /// [`Energy::robot_part`]): dead loads, obstacles within reach, what each cable imposes.
    pub(super) fn setup_from<'a>(
        &'a self,
        robot: &'a Robot,
        act: &Actuation,
        scene: &'a Scene,
        nodes: Cow<'a, [NodeRow]>,
        len0: &[f64],
    ) -> Result<Problem<'a>, SolveError> {
        let mut prob = self.bare(robot, nodes, &self.counts(robot)?);
        prob.len0 = len0.to_vec();
        prob.frame_forces = self.dead_loads(robot, &prob.ell, &prob.first)?;
        if !scene.is_empty() {
            let near = broad::robot_obstacles(robot, scene)?;
            prob.world = World::new(robot, scene, near, prob.first.clone());
        }
        // Capstan friction is this method's to honour (`energy/friction.rs`).
        let drives = self.kind().drives(robot, act, self.control)?;
        for (c, cable) in robot.cables.iter().enumerate() {
            prob.targets[c] = match drives[c] {
                Drive::Shorten { length: d, .. } => {
                    let target = len0[c] - d - cable.pretension_stretch();
                    if target <= 0.0 {
                        return Err(SolveError::Infeasible {
                            cable: cable.name.clone(),
                            section: cable.ends_at,
                            reason: format!(
                                "shortening {d:.6} m (plus the pretension's stretch {:.3e} m) \
                                 is not less than the cable's undeformed length {:.6} m",
                                cable.pretension_stretch(),
                                len0[c]
                            ),
                        });
                    }
                    Target::Length(target)
                }
                Drive::Tension(t) => Target::Tension(t),
                Drive::Free => Target::Free,
            };
        }
        Ok(prob)
    }

    /// Dead loads at the sub-arc ends (empty: none): backbone weight lumped half to each end of
    /// its sub-arc, disk weights, the tip force; a tip moment is refused (no potential).
    fn dead_loads(
        &self,
        robot: &Robot,
        ell: &[f64],
        first: &[usize],
    ) -> Result<Vec<Vector3<f64>>, SolveError> {
        let n = robot.sections();
        let nsub = first[n];
        let bb = &robot.backbone;
        let loads = &robot.loads;
        if loads.tip_moment.norm() > 0.0 {
            return Err(SolveError::Unsupported {
                method: self.name().into(),
                reason: "a dead tip moment is not conservative (no potential): use the \
                         Cosserat model for tip moments"
                    .into(),
            });
        }
        let finite = |v: &Vector3<f64>| v.iter().all(|x| x.is_finite());
        if !finite(&loads.gravity) || !finite(&loads.tip_force) || !loads.disk_mass.is_finite() {
            return Err(SolveError::InvalidInput {
                field: "loads".into(),
                reason: "gravity, disk_mass and tip_force must be finite".into(),
            });
        }
        if loads.gravity.norm() > 0.0 || loads.tip_force.norm() > 0.0 {
            let mut ff = vec![Vector3::zeros(); nsub + 1];
            let w = loads.gravity * (bb.density * bb.area());
            for j in 0..nsub {
                ff[j] += w * (0.5 * ell[j]);
                ff[j + 1] += w * (0.5 * ell[j]);
            }
            for k in 1..=n {
                ff[first[k]] += loads.gravity * loads.disk_mass;
            }
            ff[nsub] += loads.tip_force;
            return Ok(ff);
        }
        Ok(vec![])
    }

    /// Routing samples `[c][j][q]` of every cable at the Gauss nodes of the sub-arcs it
    /// reaches (path measure): the routing curve fitted once per solve.
    fn gauss_nodes(
        &self,
        robot: &Robot,
        ell: &[f64],
        first: &[usize],
    ) -> Result<Vec<Vec<[Node; GL_NODES]>>, SolveError> {
        let mut nodes = Vec::with_capacity(robot.cables.len());
        for (c, cable) in robot.cables.iter().enumerate() {
            let route = Route::new(robot, c, self.routing)?;
            let mut per = Vec::with_capacity(first[cable.ends_at]);
            for sec in 1..=cable.ends_at {
                for k in 0..first[sec] - first[sec - 1] {
                    let j = first[sec - 1] + k;
                    let s0 = robot.disk_s[sec - 1] + k as f64 * ell[j];
                    let mut arr = [[0.0; 5]; GL_NODES];
                    for q in 0..GL_NODES {
                        let s = s0 + 0.5 * ell[j] * (GL_X[q] + 1.0);
                        let rp = route.eval(s, sec - 1);
                        arr[q] = [rp.r.x, rp.r.y, rp.dr.x, rp.dr.y, 0.5 * ell[j] * GL_W[q]];
                    }
                    per.push(arr);
                }
            }
            nodes.push(per);
        }
        Ok(nodes)
    }
}

/// Section (1-based) of sub-arc `j` when section `i` starts at sub-arc `first[i − 1]`
/// ([`Problem::first`]).
pub(super) fn section_of(first: &[usize], j: usize) -> usize {
    first.partition_point(|&f| f <= j).max(1)
}
