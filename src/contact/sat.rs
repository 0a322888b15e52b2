//! The exact signed distance and normal of a robot feature (segment, capsule, disk) and a box
//! or cylinder obstacle, from their support functions, where a box edge or corner or a
//! cylinder's rim decides it (a face: [`super::primitives`]).
//!
//! # Why
//!
//! parry's GJK answer near touching, polished by alternating projections
//! ([`super::parry::polish`]), leaves the normal off by up to ~1e-6 rad where a disk's rim meets
//! a box edge or a cylinder's rim: the projections contract by only `R/(R + shift)` per round
//! there (`R` the rim's radius). A Newton solve pressing the disk on the obstacle
//! (a contact force of ~60 rad/m) then chatters at 1e-8–1e-7 m and its stationarity misses the
//! certificate's tolerance, so a section's taut-set search runs every face and start three
//! times (a generated scene: 3381 Newton iterations where the committed wall takes 254).
//!
//! # The separating-axis maximum
//!
//! For convex sets `F` (the feature) and `B` (the obstacle) with support functions `h`, the
//! signed distance is `d = max_{|n| = 1} φ(n)`, `φ(n) = −h_F(−n) − h_B(n)`: the distance when
//! they are apart, minus the penetration depth when they overlap, with the maximizing `n` the
//! normal from the obstacle towards the feature. Every shape here has a support function of the
//! form `n·c + Σ w_j |n·v_j| + Σ ρ_k |P_k n| + r|n|` (`P_k` the projection across an axis):
//! a box `Σ e_i |n·u_i|`, a cylinder `ρ|P_a n| + h|n·a|`, a disk the same, a segment
//! `(L/2)|n·d̂|`, a capsule that plus its radius. So `φ` is concave and smooth except on the
//! kinks `n·v_j = 0` (the support is an edge or a face: a box edge or face, a segment seen
//! side on, a cylinder's side) and `P_k n = 0` (a cap seen face on; left to parry).
//!
//! It is maximized on the unit sphere by an active set over the kinks: Newton on the sphere
//! with the active kinks as equalities (at most 2 unknowns), a kink crossed by a step joins the
//! set, an active kink whose multiplier leaves its subgradient interval `|λ_j| ≤ w_j` leaves it
//! (the optimality condition of the concave, piecewise smooth `φ`). The answer is used only
//! when it agrees with parry's (the start) to parry's accuracy; `None` otherwise.

use super::parry::SEPARATION_SHIFT;
use super::Witness;
use arrayvec::ArrayVec;
use nalgebra::{Matrix2, Matrix3, Vector2, Vector3};

/// A few directions (a basis, the active kinks), on the stack: the solve runs per
/// contact query, thousands of times per solve.
type Dirs = ArrayVec<Vector3<f64>, MAX_KINKS>;

/// Kinks `|n·v|` a pair can have (box 3 + feature 1, or cylinder 1 + feature 1).
const MAX_KINKS: usize = 4;

/// A kink term starts active when `|n·v|` is below this at parry's normal.
const START_ACTIVE: f64 = 1e-6;

/// [`near_witness`] moves the feature again along the moved pair's normal where it differs
/// from the hint by more than this (as [`super::parry::query_near`] does).
const NORMAL_KEPT: f64 = 1e-6;

/// A rim term `ρ|P n|` this close to its kink (a cap seen face on) is left to parry.
const RIM_KINK: f64 = 1e-6;

/// One convex shape's support function `h(n) = n·c + Σ w_j |n·v_j| + Σ ρ_k |P_k n| + r|n|`
/// and how to find its support point.
#[derive(Clone, Debug)]
pub(crate) struct SupportShape {
    /// Centre `c`.
    pub(crate) centre: Vector3<f64>,
    /// Kink terms `(w_j, v_j)`, `v_j` unit.
    pub(crate) kinks: ArrayVec<(f64, Vector3<f64>), 3>,
    /// Rim terms `(ρ_k, a_k)`, `a_k` unit (the projection is across `a_k`).
    pub(crate) rims: ArrayVec<(f64, Vector3<f64>), 1>,
    /// Radius of the swept ball `r`.
    pub(crate) radius: f64,
}

impl SupportShape {
    /// A box of half extents `e` with axes the columns of `rot`, centred at `c`.
    pub(crate) fn cuboid(c: Vector3<f64>, rot: &Matrix3<f64>, e: &Vector3<f64>) -> Self {
        SupportShape {
            centre: c,
            kinks: (0..3).map(|i| (e[i], rot.column(i).into_owned())).collect(),
            rims: ArrayVec::new(),
            radius: 0.0,
        }
    }
    /// A cylinder (or disk) of radius `rho`, half height `half` along the unit `axis`.
    pub(crate) fn cylinder(c: Vector3<f64>, axis: Vector3<f64>, rho: f64, half: f64) -> Self {
        SupportShape {
            centre: c,
            kinks: [(half, axis)].into_iter().collect(),
            rims: [(rho, axis)].into_iter().collect(),
            radius: 0.0,
        }
    }
    /// The segment `a → b` swept by a ball of radius `r` (`None` for a zero length).
    pub(crate) fn segment(a: &Vector3<f64>, b: &Vector3<f64>, r: f64) -> Option<Self> {
        let d = b - a;
        let l = d.norm();
        (l > 0.0).then(|| SupportShape {
            centre: 0.5 * (a + b),
            kinks: [(0.5 * l, d / l)].into_iter().collect(),
            rims: ArrayVec::new(),
            radius: r,
        })
    }

    /// The support point in direction `n` (unit), `None` where it is not unique (a kink or a
    /// rim's axis within `tol`).
    fn support(&self, n: &Vector3<f64>, tol: f64) -> Option<Vector3<f64>> {
        let mut p = self.centre + self.radius * n;
        for (w, v) in &self.kinks {
            let s = n.dot(v);
            if *w > 0.0 && s.abs() <= tol {
                return None;
            }
            p += *w * s.signum() * v;
        }
        for (rho, a) in &self.rims {
            let pn = n - a * n.dot(a);
            let len = pn.norm();
            if len <= RIM_KINK {
                return None;
            }
            p += *rho / len * pn;
        }
        Some(p)
    }
}

/// The pair's `φ` with its kinks in one list (the feature's at `−n`: every term is even).
struct Pair<'a> {
    /// `c_F − c_B`.
    delta: Vector3<f64>,
    kinks: [(f64, Vector3<f64>); MAX_KINKS],
    n_kinks: usize,
    rims: ArrayVec<(f64, Vector3<f64>), 2>,
    radius: f64,
    feature: &'a SupportShape,
    obstacle: &'a SupportShape,
}

impl Pair<'_> {
    /// `φ(n)`, its gradient and Hessian in R³ with the kinks' signs `sign` (active kinks'
    /// terms are zero on their stratum and left out).
    fn eval(
        &self,
        n: &Vector3<f64>,
        active: u32,
        sign: &[f64],
    ) -> (f64, Vector3<f64>, Matrix3<f64>) {
        let mut v = n.dot(&self.delta) - self.radius * n.norm();
        let nn = n.norm();
        let mut g = self.delta - self.radius * n / nn;
        let mut h = -self.radius * (Matrix3::identity() - n * n.transpose() / (nn * nn)) / nn;
        for (j, (w, u)) in self.kinks[..self.n_kinks].iter().enumerate() {
            if active & (1 << j) == 0 {
                v -= w * sign[j] * n.dot(u);
                g -= *w * sign[j] * u;
            }
        }
        for (rho, a) in &self.rims {
            let pm = Matrix3::identity() - a * a.transpose();
            let pn = pm * n;
            let len = pn.norm();
            v -= rho * len;
            g -= *rho / len * pn;
            h -= *rho / len * (pm - pn * pn.transpose() / (len * len));
        }
        (v, g, h)
    }
}

/// `v` less its components along the orthonormal `basis`, one vector after the other
/// (modified Gram–Schmidt).
fn reject(v: &Vector3<f64>, basis: &[Vector3<f64>]) -> Vector3<f64> {
    basis.iter().fold(*v, |r, b| r - b * b.dot(&r))
}

/// `basis` extended by the active kinks' directions `cons` that are independent of it
/// (rejection above 1e-9), orthonormal.
fn with_kinks(mut basis: Dirs, cons: &[Vector3<f64>]) -> Dirs {
    for c in cons {
        let r = reject(c, &basis);
        if r.norm() > 1e-9 {
            let _ = basis.try_push(r.normalize());
        }
    }
    basis
}

/// Orthonormal basis of the directions orthogonal to `n` and to every active kink's `v`:
/// 0, 1 or 2 vectors; `None` when the active kinks leave no unit `n` (rank 3).
fn tangent_basis(n: &Vector3<f64>, cons: &[Vector3<f64>]) -> Dirs {
    let mut basis = with_kinks([*n].into_iter().collect(), cons);
    let fixed = basis.len();
    for e in [Vector3::x(), Vector3::y(), Vector3::z()] {
        let r = reject(&e, &basis);
        if r.norm() > 1e-6 && basis.len() < 3 {
            let _ = basis.try_push(r.normalize());
        }
    }
    basis.drain(..fixed);
    basis
}

/// The projection of `n` on the directions orthogonal to the active kinks, normalized.
fn onto_stratum(n: &Vector3<f64>, cons: &[Vector3<f64>]) -> Option<Vector3<f64>> {
    let m = reject(n, &with_kinks(Dirs::new(), cons));
    (m.norm() > 1e-6).then(|| m.normalize())
}

/// The pair's `φ` of `feature` and `obstacle` (kinks of zero weight left out).
fn pair_of<'a>(feature: &'a SupportShape, obstacle: &'a SupportShape) -> Option<Pair<'a>> {
    let mut kinks = [(0.0, Vector3::zeros()); MAX_KINKS];
    let mut n_kinks = 0;
    for k in obstacle.kinks.iter().chain(&feature.kinks) {
        if k.0 > 0.0 {
            *kinks.get_mut(n_kinks)? = *k;
            n_kinks += 1;
        }
    }
    Some(Pair {
        delta: feature.centre - obstacle.centre,
        kinks,
        n_kinks,
        rims: obstacle.rims.iter().chain(&feature.rims).copied().collect(),
        radius: feature.radius + obstacle.radius,
        feature,
        obstacle,
    })
}

/// The witness at the maximizing `n`.
fn answer(pair: &Pair, n: &Vector3<f64>) -> Option<Witness> {
    let (dist, _, _) = pair.eval(n, 0, &signs(pair, n));
    let (robot, obstacle) = witnesses(pair, n, dist)?;
    Some(Witness {
        robot,
        obstacle,
        normal: *n,
        dist,
    })
}

/// The signed distance, normal (obstacle towards feature) and witness points of `feature` and
/// `obstacle` by the separating-axis maximum (module docs), started from parry's answer
/// `start` (its normal from the obstacle towards the feature). `None` where it does not
/// decide: a cap seen face on, no convergence, non-unique witnesses it cannot place, or an
/// answer that disagrees with `start` by more than parry's accuracy (1e-6 m, 1e-3 rad).
pub(crate) fn sat_witness(
    feature: &SupportShape,
    obstacle: &SupportShape,
    start: &Witness,
) -> Option<Witness> {
    let pair = pair_of(feature, obstacle)?;
    let w = answer(&pair, &maximize(&pair, &start.normal.normalize())?)?;
    let agrees = (w.dist - start.dist).abs() <= 1e-6 && (w.normal - start.normal).norm() <= 1e-3;
    agrees.then_some(w)
}

/// The witness of `feature` and `obstacle` when they are apart, by the separating-axis maximum
/// from any start normal `n0` (obstacle towards feature), without parry's answer: `None` where
/// they touch or overlap or the maximum does not decide (then ask parry, [`sat_witness`]).
///
/// Apart, the answer is the distance itself, whatever the start: `φ` is concave and
/// positively homogeneous, so `max_{|n|≤1} φ` is a convex problem; a maximum on the sphere
/// with `φ(n) > 0` (the active set's stationarity, `∂φ(n) ∋ μ n`, with `μ = φ(n) > 0` by
/// Euler's identity) is its KKT point and so the global maximum, the distance. Overlapping,
/// the sphere is not convex and a start can end in a local maximum that is not the depth.
pub(crate) fn sat_apart(
    feature: &SupportShape,
    obstacle: &SupportShape,
    n0: &Vector3<f64>,
) -> Option<Witness> {
    let pair = pair_of(feature, obstacle)?;
    let w = answer(&pair, &maximize(&pair, &n0.normalize())?)?;
    (w.dist > 0.0).then_some(w)
}

/// The witness of `feature` and `obstacle` touching or overlapping, from the normal `hint`
/// (obstacle towards feature) and distance `hint_dist` of the same pair a moment ago, without
/// parry: the route of [`super::parry::query_near`] with exact answers. The feature is moved
/// clear along `hint` by [`SEPARATION_SHIFT`] plus the old depth, where the moved pair is apart
/// and [`sat_apart`] gives its distance whatever the start; once more along that answer's
/// normal where it turned by more than [`NORMAL_KEPT`]; moved back, that answer is the start of
/// [`sat_witness`] on the pair itself, kept where the two agree (as parry's shifted answer is).
///
/// Moving a convex feature by `s` along a direction `ε` off the contact normal changes the
/// distance by `s` to within `s (1 − cos ε)`, so the start is within that of the pair's; the
/// maximum from it is the local maximum parry's route ends in where the two starts lie in its
/// basin. `None` where this does not decide (the moved pair still overlaps, a cap seen face
/// on, no agreement): ask parry.
pub(crate) fn near_witness(
    feature: &SupportShape,
    obstacle: &SupportShape,
    (hint, hint_dist): (&Vector3<f64>, f64),
) -> Option<Witness> {
    let mut n = hint.normalize();
    let mut shift = SEPARATION_SHIFT + (-hint_dist).max(0.0);
    for round in 0..2 {
        let mut moved = feature.clone();
        moved.centre += shift * n;
        let w = sat_apart(&moved, obstacle, &n)?;
        let start = Witness {
            robot: w.robot - shift * n,
            obstacle: w.obstacle,
            normal: w.normal,
            dist: w.dist - shift,
        };
        if round == 1 || (w.normal - n).norm() <= NORMAL_KEPT {
            return sat_witness(feature, obstacle, &start);
        }
        shift = SEPARATION_SHIFT + (-start.dist).max(0.0);
        n = w.normal;
    }
    None
}

/// The kinks' signs at `n`.
fn signs(pair: &Pair, n: &Vector3<f64>) -> [f64; MAX_KINKS] {
    std::array::from_fn(|j| {
        if j < pair.n_kinks {
            n.dot(&pair.kinks[j].1).signum()
        } else {
            1.0
        }
    })
}

/// The active-set maximum of `φ` on the sphere from `n0` (module docs).
fn maximize(pair: &Pair, n0: &Vector3<f64>) -> Option<Vector3<f64>> {
    let nk = pair.n_kinks;
    let mut sign = signs(pair, n0);
    let mut active: u32 = (0..nk)
        .filter(|&j| n0.dot(&pair.kinks[j].1).abs() <= START_ACTIVE)
        .fold(0, |m, j| m | (1 << j));
    let mut n = *n0;
    for _ in 0..8 {
        let cons: Dirs = (0..nk)
            .filter(|j| active & (1 << j) != 0)
            .map(|j| pair.kinks[j].1)
            .collect();
        n = onto_stratum(&n, &cons)?;
        let mut crossed = None;
        let mut converged = false;
        for _ in 0..30 {
            if pair
                .rims
                .iter()
                .any(|(_, a)| (n - a * n.dot(a)).norm() <= RIM_KINK)
            {
                return None;
            }
            let b = tangent_basis(&n, &cons);
            if b.is_empty() {
                converged = true;
                break;
            }
            let (v, g, h) = pair.eval(&n, active, &sign);
            let step: ArrayVec<f64, 2> = if b.len() == 1 {
                let gr = b[0].dot(&g);
                let hr = b[0].dot(&(h * b[0])) - v;
                if hr >= 0.0 {
                    return None;
                }
                [-gr / hr].into_iter().collect()
            } else {
                let gr = Vector2::new(b[0].dot(&g), b[1].dot(&g));
                let hr = Matrix2::from_fn(|r, c| b[r].dot(&(h * b[c]))) - v * Matrix2::identity();
                // Newton for a maximum: (−H) x = g, with −H positive definite.
                let x = (-hr).cholesky()?.solve(&gr);
                [x[0], x[1]].into_iter().collect()
            };
            let dn: Vector3<f64> = b.iter().zip(&step).map(|(bi, s)| bi * *s).sum();
            let next = (n + dn).normalize();
            // A kink the step crosses joins the active set, at the crossing.
            let cross = (0..nk)
                .filter(|j| active & (1 << j) == 0)
                .filter_map(|j| {
                    let u = pair.kinks[j].1;
                    let (a0, a1) = (n.dot(&u), next.dot(&u));
                    (a1 * sign[j] < 0.0).then(|| (j, a0 / (a0 - a1)))
                })
                .min_by(|a, b| a.1.total_cmp(&b.1));
            if let Some((j, t)) = cross {
                n = (n + dn * t).normalize();
                crossed = Some(j);
                break;
            }
            n = next;
            if dn.amax() <= 1e-13 {
                converged = true;
                break;
            }
        }
        if let Some(j) = crossed {
            active |= 1 << j;
            continue;
        }
        if !converged {
            return None;
        }
        // Multipliers of the active kinks: the tangential gradient of the smooth part is
        // Σ λ_j (v_j across n); each must lie in [−w_j, w_j].
        let (_, g, _) = pair.eval(&n, active, &sign);
        let gt = g - n * n.dot(&g);
        let act: ArrayVec<usize, MAX_KINKS> = (0..nk).filter(|j| active & (1 << j) != 0).collect();
        if act.is_empty() {
            return Some(n);
        }
        let vt: ArrayVec<Vector3<f64>, MAX_KINKS> = act
            .iter()
            .map(|&j| {
                let u = pair.kinks[j].1;
                u - n * n.dot(&u)
            })
            .collect();
        let lambda = least_squares(&vt, &gt)?;
        let worst = act
            .iter()
            .zip(&lambda)
            .map(|(&j, &l)| (j, l, l.abs() - pair.kinks[j].0 * (1.0 + 1e-9)))
            .filter(|x| x.2 > 0.0)
            .max_by(|a, b| a.2.total_cmp(&b.2));
        match worst {
            None => return Some(n),
            Some((j, l, _)) => {
                active &= !(1 << j);
                sign[j] = l.signum();
                // Off the kink on the side the multiplier asks for.
                n = (n + 1e-9 * sign[j] * vt[act.iter().position(|&k| k == j)?]).normalize();
            }
        }
    }
    None
}

/// `λ` with `Σ λ_j v_j = g` in the least-squares sense (1 or 2 vectors; 3 active kinks leave
/// no direction).
fn least_squares(v: &[Vector3<f64>], g: &Vector3<f64>) -> Option<ArrayVec<f64, 2>> {
    match v {
        [a] => {
            (a.norm_squared() > 1e-18).then(|| [a.dot(g) / a.norm_squared()].into_iter().collect())
        }
        [a, b] => {
            let m = Matrix2::new(a.dot(a), a.dot(b), b.dot(a), b.dot(b));
            let x = m.try_inverse()? * Vector2::new(a.dot(g), b.dot(g));
            Some([x[0], x[1]].into_iter().collect())
        }
        _ => None,
    }
}

/// The witness points at the maximizing `n` with distance `dist`: the feature's support point
/// in `−n` and the obstacle's in `n`, the one not unique placed from the other; where neither
/// is (an edge across an edge), the closest points of their two lines.
fn witnesses(pair: &Pair, n: &Vector3<f64>, dist: f64) -> Option<(Vector3<f64>, Vector3<f64>)> {
    let tol = 1e-12;
    match (
        pair.feature.support(&-n, tol),
        pair.obstacle.support(n, tol),
    ) {
        (Some(a), _) => Some((a, a - dist * n)),
        (None, Some(b)) => Some((b + dist * n, b)),
        (None, None) => {
            let (pa, da) = edge_line(pair.feature, &-n, tol)?;
            let (pb, db) = edge_line(pair.obstacle, n, tol)?;
            // Closest points of the lines pa + s da and pb + t db.
            let w = pa - pb;
            let (b, d, e) = (da.dot(&db), da.dot(&w), db.dot(&w));
            let den = 1.0 - b * b;
            if den < 1e-12 {
                return None;
            }
            let s = (b * e - d) / den;
            let a = pa + s * da;
            Some((a, a - dist * n))
        }
    }
}

/// The line of a shape's support set in `n` when it is an edge (exactly one kink of the shape
/// active, no rim at its kink): a point on it and its direction.
fn edge_line(
    shape: &SupportShape,
    n: &Vector3<f64>,
    tol: f64,
) -> Option<(Vector3<f64>, Vector3<f64>)> {
    let mut p = shape.centre + shape.radius * n;
    let mut dir = None;
    for (w, v) in &shape.kinks {
        let s = n.dot(v);
        if *w > 0.0 && s.abs() <= tol {
            if dir.is_some() {
                return None;
            }
            dir = Some(*v);
        } else {
            p += *w * s.signum() * v;
        }
    }
    for (rho, a) in &shape.rims {
        let pn = n - a * n.dot(a);
        let len = pn.norm();
        if len <= RIM_KINK {
            return None;
        }
        p += *rho / len * pn;
    }
    dir.map(|d| (p, d))
}

/// The support function of a box or cylinder obstacle at `pose`; `None` for other shapes.
pub(crate) fn obstacle_support(
    shape: &dyn parry3d::shape::Shape,
    pose: &parry3d::math::Pose,
) -> Option<SupportShape> {
    use super::{nvec, pvec};
    let axis = |v: Vector3<f64>| nvec(pose.rotation * pvec(&v));
    let c = nvec(pose.translation);
    if let Some(b) = shape.as_cuboid() {
        let rot =
            Matrix3::from_columns(&[axis(Vector3::x()), axis(Vector3::y()), axis(Vector3::z())]);
        return Some(SupportShape::cuboid(c, &rot, &nvec(b.half_extents)));
    }
    // parry's cylinder axis is its local y.
    let cy = shape.as_cylinder()?;
    Some(SupportShape::cylinder(
        c,
        axis(Vector3::y()),
        cy.radius,
        cy.half_height,
    ))
}

/// The support function of a robot feature.
pub(crate) fn feature_support(f: &super::primitives::Convex) -> Option<SupportShape> {
    use super::primitives::Convex;
    match f {
        Convex::Segment(a, b, r) => SupportShape::segment(a, b, *r),
        Convex::Disk(rot, x, radius, half) => Some(SupportShape::cylinder(
            *x,
            rot.column(2).into_owned(),
            *radius,
            *half,
        )),
    }
}

/// The exact witness of a robot feature apart from a box or cylinder obstacle (`shape` at
/// `opose`), by [`sat_apart`] started from one round of alternating point projections (the
/// obstacle's point nearest the feature's centre, the feature's nearest that, the obstacle's
/// nearest that), no GJK; `None` for other shapes and where they touch or overlap or the
/// maximum does not decide (parry then answers, and [`sat_witness`] polishes it).
pub(crate) fn apart_witness(
    shape: &dyn parry3d::shape::Shape,
    opose: &parry3d::math::Pose,
    hull: &super::primitives::Convex,
) -> Option<Witness> {
    use super::{nvec, pvec};
    let (o, f) = (obstacle_support(shape, opose)?, feature_support(hull)?);
    let project = |p: &Vector3<f64>| nvec(shape.project_point(opose, pvec(p), true).point);
    let a = hull.closest(&project(&f.centre));
    let n0 = a - project(&a);
    (n0.norm() > 1e-12).then(|| sat_apart(&f, &o, &n0))?
}

#[cfg(test)]
#[path = "sat_tests.rs"]
pub(crate) mod tests;
