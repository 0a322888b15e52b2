//! The section problem (paper eq. 1–2, readings 1–7 of `docs/guide/paper.md`) in the frame of the
//! solved disk i−1: the relative pose, the objective terms, the cable constraints, and their values
//! and exact derivatives.

use super::obstacles::SectionWorld;
use crate::error::SolveError;
use crate::model::robot::Robot;
use crate::numeric::ad::{Real, D2, V3};
use crate::numeric::so3::{exp_so3, gram_schmidt};
use nalgebra::{Matrix3, Vector3, Vector6};
use std::cell::Cell;

/// Relative pose of disk i in the frame of disk i−1.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Pose {
    pub(super) p: Vector3<f64>,
    pub(super) q: Matrix3<f64>,
}

impl Pose {
    pub(super) fn straight(l0: f64) -> Self {
        Pose {
            p: Vector3::new(0.0, 0.0, l0),
            q: Matrix3::identity(),
        }
    }
    /// Whether `other` is within `dp` (position, largest component) and `dq` (rotation,
    /// largest entry) of this pose.
    pub(super) fn within(&self, other: &Pose, dp: f64, dq: f64) -> bool {
        (self.p - other.p).amax() <= dp && (self.q - other.q).amax() <= dq
    }
    /// Right-perturbation retraction: p + dp, Q exp(dω).
    pub(super) fn retract(&self, dx: &Vector6<f64>, alpha: f64) -> Self {
        Pose {
            p: self.p + alpha * Vector3::new(dx[0], dx[1], dx[2]),
            q: gram_schmidt(&(self.q * exp_so3(&(alpha * Vector3::new(dx[3], dx[4], dx[5]))))),
        }
    }
}

/// One objective term: an angle between an undeformed direction and its solved image.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Term {
    /// Unit undeformed direction (ẑ for the tangent, ĥ for a coupler) in disk i−1's frame.
    pub(super) dir: Vector3<f64>,
    /// Orthonormal basis of the plane normal to `dir` (for the zero-face equations).
    pub(super) e1: Vector3<f64>,
    pub(super) e2: Vector3<f64>,
    /// How many cables share this coupler (1 for the tangent).
    pub(super) weight: f64,
    /// `tangent` or the cable names joined with `+`.
    pub(super) label: String,
    pub(super) tangent: bool,
}

impl Term {
    pub(super) fn new(dir: Vector3<f64>, weight: f64, label: String, tangent: bool) -> Self {
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
#[derive(Debug, Clone, PartialEq)]
pub(super) struct CableCon {
    pub(super) cables: Vec<usize>,
    pub(super) h_prev: Vector3<f64>,
    pub(super) h: Vector3<f64>,
    pub(super) length: f64,
    /// Term index of this cable's coupler (its hole direction on disk i).
    pub(super) coupler: usize,
    /// Whether the length equals the undeformed straight chord to within [`UNSHORTENED_TOL`]:
    /// then the tangent and this coupler at zero put the chord exactly at its length (see
    /// `degenerate.rs`).
    pub(super) unshortened: bool,
}

/// A cable whose segment length differs from its undeformed straight chord by at most this
/// \[m\] is "unshortened": the constraint residual this leaves on its degenerate face is below
/// the default Newton tolerance `1e-12` m of [`super::Geometric::literal`].
pub(super) const UNSHORTENED_TOL: f64 = 1e-13;

/// Everything one section problem needs, in disk i−1's frame.
pub(super) struct SectionData {
    /// Section index (1-based).
    pub(super) section: usize,
    pub(super) l0: f64,
    pub(super) terms: Vec<Term>,
    pub(super) cons: Vec<CableCon>,
    /// Cables that reach the section but whose shared segment is tighter for another cable.
    pub(super) always_slack: Vec<usize>,
    /// Names, for errors.
    pub(super) names: Vec<String>,
    /// Unit hole direction when all driven holes of disk i are collinear with its centre.
    pub(super) gauge: Option<Vector3<f64>>,
    /// Obstacles this section can touch (None: none near).
    pub(super) world: Option<SectionWorld>,
    /// Newton steps split the constraint rows by Gram–Schmidt
    /// ([`crate::numeric::kkt::kkt_step6_gs`]) and take the closed-form derivatives
    /// ([`SectionData::eval_d2`]); false for `geometric-squared` in a scene with obstacles near
    /// the robot, whose contact candidates stop at a 1e-7 step, so that a rounding-level change
    /// upstream moves its recorded tips (by 1.2e-8 m on the pillar, measured 2026-11-27). The
    /// literal method takes both next to obstacles too since its contact candidates converge
    /// to 1e-11 (wall tips moved 2e-15 m, pillar 1e-11 m, the parry noise there).
    pub(super) gram_schmidt: bool,
    /// Search with the start nudges and stall count of the former search (the quick search's
    /// are smaller, see `faces::nudge` and `newton::MAX_SHORT_STEPS`): a retry where the quick
    /// search found no certified pose. (Sections near obstacles took it always while their
    /// contact candidates converged only to 1e-7; see `Geometric::solve_section`.)
    pub(super) former_search: Cell<bool>,
    /// Contact candidates converge at the step tolerance of the former search
    /// (`newton::FORMER_CONTACT_STEP_TOL`, 1e-7) instead of 1e-11: the last retry of a section
    /// near obstacles where neither search certified a pose at 1e-11 (see
    /// `Geometric::solve_section`).
    pub(super) loose_contacts: Cell<bool>,
}

pub(super) const SAME_POINT: f64 = 1e-12;

impl SectionData {
    /// Whether `other` poses exactly the same problem (every number equal, bit for bit) and
    /// neither has obstacles near: the section index and the cable names aside, the search
    /// then sees the same inputs.
    pub(super) fn same_problem(&self, other: &SectionData) -> bool {
        self.world.is_none()
            && other.world.is_none()
            && self.l0 == other.l0
            && self.terms == other.terms
            && self.cons == other.cons
            && self.always_slack == other.always_slack
            && self.gauge == other.gauge
            && self.gram_schmidt == other.gram_schmidt
    }

    pub(super) fn new(robot: &Robot, frac: &[Option<f64>], i: usize) -> Result<Self, SolveError> {
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
            let chord0 = robot.undeformed_chord(c, i);
            let length = (1.0 - f) * chord0;
            let unshortened = (length - chord0).abs() <= UNSHORTENED_TOL;
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
            let coupler = match coupler_members
                .iter()
                .position(|(hh, _)| hh.normalize().cross(&h.normalize()).norm() < 1e-9)
            {
                Some(k) => {
                    coupler_members[k].1.push(c);
                    1 + k
                }
                None => {
                    coupler_members.push((h, vec![c]));
                    coupler_members.len()
                }
            };
            match cons
                .iter_mut()
                .find(|k| (k.h - h).norm() < SAME_POINT && (k.h_prev - hp).norm() < SAME_POINT)
            {
                Some(k) => {
                    if length < k.length {
                        always_slack.extend(k.cables.iter().copied());
                        k.cables = vec![c];
                        k.length = length;
                        k.unshortened = unshortened;
                    } else {
                        always_slack.push(c);
                    }
                }
                None => cons.push(CableCon {
                    cables: vec![c],
                    h_prev: hp,
                    h,
                    length,
                    coupler,
                    unshortened,
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
        let data = SectionData {
            section: i,
            l0,
            terms,
            cons,
            always_slack,
            names: robot.cables.iter().map(|c| c.name.clone()).collect(),
            gauge,
            world: None,
            gram_schmidt: true,
            former_search: Cell::new(false),
            loose_contacts: Cell::new(false),
        };
        match data.prove_infeasible() {
            Some(e) => Err(e),
            None => Ok(data),
        }
    }

    /// Bits of the coupler terms (every term but the tangent, term 0).
    fn coupler_bits(&self) -> u32 {
        ((1u32 << self.terms.len()) - 1) & !1
    }

    /// Whether a face sets two or more coupler angles to zero. The holes of a disk lie in its
    /// plane, so two non-collinear couplers at zero fix `Q = I` and every coupler is then zero:
    /// such a face is the one face "all couplers zero", three equations (not two per term).
    pub(super) fn rotation_fixed(&self, face: u32) -> bool {
        (face & self.coupler_bits()).count_ones() >= 2
    }

    /// The faces worth a Newton run, in increasing bit order: the tangent zero or not, times no
    /// coupler zero, one coupler zero, or all couplers zero (`Q = I`) — `2 (couplers + 2)`
    /// faces, not `2^terms` — keeping those whose equations (`fixed` besides the face's own)
    /// leave a pose to solve for (at most 6 in all).
    ///
    /// A face with one equation too many is kept when one of them is redundant on it
    /// ([`SectionData::redundant_rows`] of the taut set `taut`): an unshortened taut cable
    /// whose coupler and the tangent are zero.
    pub(super) fn faces(&self, fixed: usize, taut: &[usize]) -> Vec<u32> {
        let couplers = self.terms.len() - 1;
        let mut rotation: Vec<(u32, usize)> = vec![(0, 0)];
        rotation.extend((1..=couplers).map(|t| (1u32 << t, 2)));
        if couplers >= 2 {
            rotation.push((self.coupler_bits(), 3));
        }
        let mut faces: Vec<u32> = rotation
            .iter()
            .flat_map(|&(bits, rank)| [(bits, rank), (bits | 1, rank + 2)])
            .filter(|&(bits, rank)| {
                fixed + rank <= 6 || (fixed + rank == 7 && self.redundant_rows(bits, taut) > 0)
            })
            .map(|(bits, _)| bits)
            .collect();
        faces.sort_unstable();
        faces
    }

    /// Objective and constraints at pose ⊕ δ (δ = (dp, dω)) evaluated at δ = 0, generic over
    /// the scalar: `f64` for values, [`D2`] for exact first and second derivatives in δ. The
    /// constraints go into `cons` (cleared first: Newton and the line search's trial points
    /// reuse one buffer instead of allocating a `Vec` each), the objective is returned.
    /// Inlined where it is called (the line search's trial points: 0.3 M instructions of a
    /// 13 M paper case I once it was not).
    #[inline]
    pub(super) fn eval<T: SectionScalar>(
        &self,
        pose: &Pose,
        face: u32,
        active: &[usize],
        squared: bool,
        cons: &mut Vec<T>,
    ) -> T {
        let p = T::position(&pose.p);
        let q = &pose.q;
        let rot = |h: &Vector3<f64>| -> V3<T> { T::rotated(q, h) };
        let mut obj = T::cst(0.0);
        cons.clear();
        cons.push(p.norm() + (-self.l0));
        for &j in active {
            let k = &self.cons[j];
            let chord = p.add(&rot(&k.h)).add(&V3::cst(&(-k.h_prev)));
            cons.push(chord.norm() + (-k.length));
        }
        let fixed_rotation = self.rotation_fixed(face);
        for (t, term) in self.terms.iter().enumerate() {
            let v = if term.tangent { p } else { rot(&term.dir) };
            if fixed_rotation && !term.tangent {
                if t == 1 {
                    // Two or more coupler angles zero: Q = I, all couplers zero. Three
                    // equations, the axial part of Q exp(δω), whose Jacobian at Q = I is I.
                    let c: [V3<T>; 3] = std::array::from_fn(|k| rot(&Vector3::ith(k, 1.0)));
                    cons.push((c[1].0[2] - c[2].0[1]) * 0.5);
                    cons.push((c[2].0[0] - c[0].0[2]) * 0.5);
                    cons.push((c[0].0[1] - c[1].0[0]) * 0.5);
                }
            } else if face & (1 << t) != 0 {
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
        obj
    }

    pub(super) fn term_angles(&self, pose: &Pose) -> Vec<f64> {
        (0..self.terms.len())
            .map(|t| self.term_angle(pose, t))
            .collect()
    }

    /// Term `t`'s angle at this pose \[rad\] (one entry of [`SectionData::term_angles`]).
    pub(super) fn term_angle(&self, pose: &Pose, t: usize) -> f64 {
        let t = &self.terms[t];
        let v = if t.tangent { pose.p } else { pose.q * t.dir };
        let c = t.dir.cross(&v).norm();
        c.atan2(t.dir.dot(&v))
    }

    pub(super) fn chord(&self, pose: &Pose, j: usize) -> f64 {
        let k = &self.cons[j];
        (pose.p + pose.q * k.h - k.h_prev).norm()
    }
}

/// The scalars a section problem is evaluated in, at δ = 0 of the perturbation
/// `p + δp`, `Q exp([δω]×)`: plain values, or values with derivatives in δ.
pub(super) trait SectionScalar: Real {
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
pub(super) fn squared_angle<T: Real>(u: &V3<T>, v: &V3<T>) -> T {
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
