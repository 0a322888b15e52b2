//! The second derivative of a feature–obstacle distance in one section's variables, for the
//! contact curvature `−μ ∇²d` of a pressing pair in the Lagrangian Hessian of the literal
//! method's Newton–KKT step.
//!
//! # Derivation
//!
//! The energy model's (`method/energy/contact_curvature.rs`, there in the strains of every
//! sub-arc), written in the section's six variables `δ = (δp, δω)` of the pose
//! `p + δp, Q exp([δω]×)` (`problem.rs`). The distance is a minimum over the feature's points,
//! `d(δ) = min_s D(x(s, δ))` with `D` the signed distance to the obstacle (gradient `ν`, the
//! unit normal from the obstacle towards the robot; Hessian `G`:
//! [`crate::contact::curvature::distance_hessian`], zero against a flat face,
//! `(I − ν νᵀ − a aᵀ)/(R + D)` against a cylinder of radius `R` and axis `a`) and `s` the
//! witness's parameters on the feature. With `φ(s, δ) = D(x(s, δ))` stationary in `s` at the
//! witness, the envelope and implicit function theorems give (Fiacco, *Introduction to
//! Sensitivity and Stability Analysis in Nonlinear Programming*, 1983, §2.4)
//!
//! ```text
//! ∇²d = φ_δδ − φ_δs φ_ss⁻¹ φ_sδ
//! φ_δδ = ν · ∂²x/∂δ²  +  Jᵀ G J                   (J = ∂x/∂δ at fixed s, 3×6)
//! φ_sδ = x_sᵀ G J  +  ν · ∂x_s/∂δ,    φ_ss = x_sᵀ G x_s + ν · x_ss
//! ```
//!
//! A point `ℓ` of disk `i` (its own frame) sits at `x = x_{i−1} + R (p + δp) + R Q exp([δω]×) ℓ`
//! (`R`: disk `i−1`'s rotation), so `J = [R, −R Q [ℓ]×]` and, with `m = (R Q)ᵀ ν` and
//! `∂²(exp([w]×) ℓ)/∂w_i∂w_j = ½ (e_i ℓ_j + e_j ℓ_i) − ℓ δ_ij` (`problem.rs`),
//! `ν · ∂²x/∂ω_i∂ω_j = ½ (m_i ℓ_j + m_j ℓ_i) − (m·ℓ) δ_ij` — the feature's own rotation
//! curvature, the whole term for a disk rim point against a plane that does not slide.
//!
//! * **Disk** (witness on the rim, `ℓ = (r cos θ, r sin θ, ±h)`): the rim angle slides,
//!   `ℓ_θ = (−ℓ_y, ℓ_x, 0)`, `x_θ = R Q ℓ_θ`, `ν · x_θθ = m · (−ℓ_x, −ℓ_y, 0) = r |m_xy|` (the
//!   witness is the support point in `−ν`), and `ν · ∂x_θ/∂ω = ℓ_θ × m` (from
//!   `∂x_θ/∂ω_k = −R Q (ℓ_θ × e_k)`). Where `ν` is nearly along the disk axis (`|m_xy| ≤`
//!   [`FACE_ON`], a face or the rim seen face on) the pair adds no curvature.
//! * **Cable chord** from the fixed hole `h'` (disk `i−1`) to the hole `h` of disk `i`, witness
//!   at fraction `t`: `x = (1 − t) h' + t b(δ)`, so `J = t J_b`, `ν · ∂²x = t ν · ∂²b`, and
//!   where `0 < t < 1` the fraction slides: `x_t = b − h'`, `x_tt = 0`, `ν · ∂x_t/∂δ = ν J_b =
//!   [Rᵀν, h × m]`.
//! * **Backbone** capsule from `x_{i−1}` to `x_{i−1} + R p`: the same with `b` not turning
//!   (`ν · ∂²b = 0`, `ν J_b = [Rᵀν, 0]`) and `G` taken at the axis, `D = d + r_backbone`.
//!
//! Where `φ_ss` is not positive definite (a segment parallel to a plane, a face on a face) `d` is
//! not twice differentiable and the sliding term is left out, as in the energy model.
//! `tests::distance_hessians_match_finite_differences` checks the whole `∇²d` against central
//! differences of the distance gradient of `obstacles.rs`.

use super::obstacles::{Feature, Pair, SectionWorld};
use super::problem::Pose;
use crate::contact::curvature::{distance_hessian, sliding_inverse};
use crate::contact::features::segment_fraction;
use nalgebra::{DMatrix, Matrix3, Matrix6, SMatrix, Vector3, Vector6};

/// A disk whose contact normal `m` (its own frame) has `|m_xy| ≤` this is seen face on: its
/// witness may jump between the rim and a face, or sit on the rim edge where `ν · x_θθ =
/// r |m_xy|` is too small to divide by (the test found a disk rim on the pillar's cap edge at
/// `|m_xy| = 1.1e-5` whose sliding term was off by 10⁴). Such a pair adds no curvature (the
/// step's Hessian as before the contact curvature).
const FACE_ON: f64 = 1e-3;

/// `J = ∂x/∂δ`, 3×6.
type Jac = SMatrix<f64, 3, 6>;

/// One witness parameter: its tangent `x_s` (world), `ν · x_ss`, and `ν · ∂x_s/∂δ`.
struct Param {
    tangent: Vector3<f64>,
    normal_curv: f64,
    turn: Vector6<f64>,
}

/// `[a; b]` as a 6-vector.
fn join(a: &Vector3<f64>, b: &Vector3<f64>) -> Vector6<f64> {
    Vector6::new(a.x, a.y, a.z, b.x, b.y, b.z)
}

/// `∂x/∂δ = [R, −R Q [ℓ]×]` of the point `ℓ` of disk `i` (`rq = R Q`).
fn disk_point_jac(r: &Matrix3<f64>, rq: &Matrix3<f64>, l: &Vector3<f64>) -> Jac {
    let mut j = Jac::zeros();
    j.fixed_view_mut::<3, 3>(0, 0).copy_from(r);
    j.fixed_view_mut::<3, 3>(0, 3)
        .copy_from(&(-(rq * l.cross_matrix())));
    j
}

/// `ν · ∂²x/∂δ²` of the point `ℓ` of disk `i`, `m = (R Q)ᵀ ν` (module docs).
fn disk_point_curvature(m: &Vector3<f64>, l: &Vector3<f64>) -> Matrix6<f64> {
    let mut h = Matrix6::zeros();
    let ml = m.dot(l);
    for i in 0..3 {
        for j in 0..3 {
            h[(3 + i, 3 + j)] = 0.5 * (m[i] * l[j] + m[j] * l[i]) - if i == j { ml } else { 0.0 };
        }
    }
    h
}

/// The pairs pressing at the last Newton step: (obstacle, feature, multiplier μ > 0).
#[derive(Default)]
pub(super) struct Pressed(Vec<(usize, Feature, f64)>);

impl Pressed {
    /// The pairs of `pairs` whose multiplier in `mu` is positive.
    pub(super) fn of(pairs: &[Pair], mu: &[f64]) -> Self {
        Pressed(
            pairs
                .iter()
                .zip(mu)
                .filter(|(_, m)| **m > 0.0)
                .map(|(p, m)| (p.obstacle, p.feature, *m))
                .collect(),
        )
    }
}

impl SectionWorld {
    /// Adds the contact curvature `−Σ μ ∇²d` of the pairs that pressed at the last step to the
    /// Lagrangian Hessian `h` (each pair of `pairs` found in `pressed`, with its multiplier;
    /// a pair whose `∇²d` is not defined, a disk seen face-on, adds nothing).
    pub(super) fn add_pressed_curvature(
        &self,
        pose: &Pose,
        pairs: &[Pair],
        pressed: &Pressed,
        h: &mut Matrix6<f64>,
    ) {
        for p in pairs {
            if let Some((_, _, m)) = pressed
                .0
                .iter()
                .find(|(k, f, _)| *k == p.obstacle && *f == p.feature)
            {
                if let Some(d2) = self.distance_hessian(pose, p) {
                    *h -= d2 * *m;
                }
            }
        }
    }

    /// `∇²d` of the pair `p` at `pose` in the section's variables (module docs); `None` for a
    /// disk whose normal is within [`FACE_ON`] of its axis.
    pub(super) fn distance_hessian(&self, pose: &Pose, p: &Pair) -> Option<Matrix6<f64>> {
        let r = &self.r_prev;
        let rq = r * pose.q;
        let x0 = self.x_prev + r * pose.p;
        let nu = p.normal;
        let m = rq.transpose() * nu;
        let mut params = vec![];
        let (jac, mut hess, d_pt) = match p.feature {
            Feature::Disk => {
                let l = rq.transpose() * (p.point_robot - x0);
                let uxy = m.x.hypot(m.y);
                // A disk's side on an edge or a side (the exact witness between the rims,
                // `contact/sat.rs`) is not a rim point: no rim curvature to add there.
                if uxy <= FACE_ON || l.z.abs() < self.half_thickness * (1.0 - 1e-9) {
                    return None;
                }
                {
                    let lt = Vector3::new(-l.y, l.x, 0.0);
                    params.push(Param {
                        tangent: rq * lt,
                        normal_curv: self.disk_radius * uxy,
                        turn: join(&Vector3::zeros(), &lt.cross(&m)),
                    });
                }
                (
                    disk_point_jac(r, &rq, &l),
                    disk_point_curvature(&m, &l),
                    p.dist,
                )
            }
            Feature::Cable(c) => {
                let Some((_, hp, h)) = self.holes.iter().find(|(k, _, _)| *k == c) else {
                    return Some(Matrix6::zeros());
                };
                let b = x0 + rq * h;
                let t = segment_fraction(&p.point_robot, hp, &b);
                let jb = disk_point_jac(r, &rq, h);
                if t > 1e-9 && t < 1.0 - 1e-9 {
                    params.push(Param {
                        tangent: b - hp,
                        normal_curv: 0.0,
                        turn: join(&(r.transpose() * nu), &h.cross(&m)),
                    });
                }
                (jb * t, disk_point_curvature(&m, h) * t, p.dist)
            }
            Feature::Backbone => {
                let t = segment_fraction(&p.point_robot, &self.x_prev, &x0);
                let mut jb = Jac::zeros();
                jb.fixed_view_mut::<3, 3>(0, 0).copy_from(r);
                if t > 1e-9 && t < 1.0 - 1e-9 {
                    params.push(Param {
                        tangent: x0 - self.x_prev,
                        normal_curv: 0.0,
                        turn: join(&(r.transpose() * nu), &Vector3::zeros()),
                    });
                }
                (jb * t, Matrix6::zeros(), p.dist + self.backbone_radius)
            }
        };
        let (shape, opose) = &self.shapes[p.obstacle];
        let g = distance_hessian(&**shape, opose, &p.point_obstacle, &nu, d_pt)
            .filter(|g| g.amax() > 0.0)
            .unwrap_or_else(Matrix3::zeros);
        hess += jac.transpose() * g * jac;
        Some(hess + sliding(&g, &jac, &params))
    }
}

/// `−φ_δs φ_ss⁻¹ φ_sδ` (module docs), zero where `φ_ss` is not positive definite
/// ([`sliding_inverse`], the energy model's criterion).
fn sliding(g: &Matrix3<f64>, jac: &Jac, params: &[Param]) -> Matrix6<f64> {
    let tangents: Vec<Vector3<f64>> = params.iter().map(|p| p.tangent).collect();
    let curv: Vec<f64> = params.iter().map(|p| p.normal_curv).collect();
    let Some(inv) = sliding_inverse(g, &tangents, &curv) else {
        return Matrix6::zeros();
    };
    let rows = DMatrix::from_fn(params.len(), 6, |a, j| {
        let row = (g * params[a].tangent).transpose() * jac + params[a].turn.transpose();
        row[j]
    });
    let m = rows.transpose() * inv * rows;
    -Matrix6::from_fn(|i, j| m[(i, j)])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::method::geometric::obstacles::random_section_worlds;
    use crate::model::scene::Scene;
    use crate::model::Model;

    /// Every pair's `∇²d` (disk rims and faces, cable chords, backbone capsules; against the
    /// wall's flat faces and the pillar's curved side) equals central differences of the
    /// distance gradient over the section's variables, symmetrized (the gradient at the moved
    /// pose is taken in that pose's own right perturbation, whose Lie bracket adds an
    /// antisymmetric `½ [∇d_ω]×`). Pairs at an edge of the wall or at a kink of `d` (the witness
    /// jumps between rim and face) are skipped where the differences disagree between two step
    /// sizes, which a smooth `d` never does. Against the wall's flat faces (the feature's own
    /// curvature, closed form) every pair agrees to 1e-8 of the largest entry (measured 1.6e-10);
    /// against the pillar, whose `G` is differenced from parry's projections and whose witnesses
    /// are GJK's polished by four alternating projections, to 1e-2 (measured 5.8e-3, a backbone
    /// capsule nearly along the pillar), and 90 % of all pairs to 1e-4 (measured 3.7e-5; median
    /// 1.5e-11). A missing or wrong term is O(1).
    #[test]
    fn distance_hessians_match_finite_differences() {
        let robot = Model::from_file("models/paper/case1.toml").unwrap().robot;
        let mut checked = [[0usize; 3]; 2];
        let (mut curved, mut face_on) = (0, 0);
        let (mut worst, mut all) = ([0.0f64; 2], vec![]);
        for (s, name) in ["wall", "pillar"].iter().enumerate() {
            let scene = Scene::from_file(format!("models/scenes/{name}.toml")).unwrap();
            for (w, pose) in random_section_worlds(
                &robot,
                &scene,
                &mut crate::numeric::test_rng::Rng(0x9e37_79b9_7f4a_7c15 + s as u64),
            ) {
                let pairs = w.pairs(&pose);
                for p in pairs.iter().filter(|p| p.dist > 1e-4) {
                    let Some(h) = w.distance_hessian(&pose, p) else {
                        face_on += 1;
                        continue;
                    };
                    let grad_at = |dx: &Vector6<f64>| {
                        let moved = pose.retract(dx, 1.0);
                        w.pairs(&moved)
                            .into_iter()
                            .find(|q| q.obstacle == p.obstacle && q.feature == p.feature)
                            .map(|q| q.grad)
                    };
                    let fd = |step: f64| -> Option<Matrix6<f64>> {
                        let mut m = Matrix6::zeros();
                        for k in 0..6 {
                            let e = Vector6::ith(k, step);
                            let col = (grad_at(&e)? - grad_at(&-e)?) / (2.0 * step);
                            m.set_column(k, &col);
                        }
                        Some((m + m.transpose()) * 0.5)
                    };
                    let (Some(f1), Some(f2)) = (fd(1e-5), fd(2e-5)) else {
                        continue;
                    };
                    let scale = f1.amax().max(1e-3);
                    if (f1 - f2).amax() > 1e-4 * scale {
                        continue;
                    }
                    let rel = (h - f1).amax() / scale;
                    assert!(
                        rel <= [1e-8, 1e-2][s],
                        "{name} {:?} at {:.3e} m:\n{h}\nvs\n{f1}",
                        p.feature,
                        p.dist
                    );
                    worst[s] = worst[s].max(rel);
                    all.push(rel);
                    let kind = match p.feature {
                        Feature::Backbone => 0,
                        Feature::Disk => 1,
                        Feature::Cable(_) => 2,
                    };
                    checked[s][kind] += 1;
                    if s == 1 && kind == 1 && h.fixed_view::<3, 3>(0, 0).amax() > 1.0 {
                        curved += 1;
                    }
                }
            }
        }
        all.sort_by(f64::total_cmp);
        let median = all[all.len() / 2];
        let p90 = all[9 * all.len() / 10];
        eprintln!("checked pairs [wall, pillar] × [backbone, disk, cable]: {checked:?}; pillar disks with position curvature: {curved}; disks face on (no term): {face_on}; worst relative difference [wall, pillar] {:.1e} / {:.1e}, median {median:.1e}, 90 % {p90:.1e}", worst[0], worst[1]);
        assert!(p90 <= 1e-4, "90 % of the pairs within {p90:e}");
        for row in checked {
            assert!(row.iter().all(|&n| n >= 5), "{checked:?}");
        }
        assert!(curved >= 5, "{curved}");
    }
}
