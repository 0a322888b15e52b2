//! The second derivative of a feature–obstacle distance in the strains, for the contact
//! curvature `−μ ∇²d` of a pressing pair in the Lagrangian Hessian.
//!
//! # Derivation
//!
//! Write the distance as a minimum over the feature's points, `d(ξ) = min_s D(x(s, ξ))`, with
//! `D` the distance to the obstacle (gradient `n`, Hessian `G`: `crate::contact::curvature`)
//! and `s` the witness's parameters on the feature: none for a point, the fraction `t` along
//! a segment (backbone capsule axis, cable chord) where the witness is inside it, the rim angle
//! of a disk (its support point in `−n`), the two face coordinates where a disk face touches.
//! With `φ(s, ξ) = D(x(s, ξ))` stationary in `s` at the witness, the envelope theorem and
//! the implicit function theorem for `s*(ξ)` give (e.g. Fiacco, *Introduction to Sensitivity
//! and Stability Analysis in Nonlinear Programming*, 1983, §2.4)
//!
//! ```text
//! ∇d  = n · ∂x/∂ξ
//! ∇²d = φ_ξξ − φ_ξs φ_ss⁻¹ φ_sξ
//! φ_ξξ = n · ∂²x/∂ξ²  +  Jᵀ G J                   (J = ∂x/∂ξ at fixed s)
//! φ_sξ = x_sᵀ G J  +  n · ∂x_s/∂ξ,    φ_ss = x_sᵀ G x_s + n · x_ss
//! ```
//!
//! * `−μ n · ∂²x/∂ξ²` is the curvature of a dead force `μ n` at the witness
//!   (`energy/curvature.rs`); a segment's witness at fraction `t` splits it, `(1 − t) μ n` at one
//!   end and `t μ n` at the other.
//! * `Jᵀ G J` carries the obstacle's own curvature: zero against a flat face (point–plane pairs
//!   curve only through the feature's own map `ξ ↦ x`), `(I − n nᵀ)/(R + d)` against a ball.
//! * The sliding term: a disk's rim point `x = p + R y(θ)` has `x_θ = R y_θ`,
//!   `n · x_θθ = r_disk |P Rᵀ n|` (`P` onto the disk plane) and, turning with the frame,
//!   `n · ∂x_θ/∂ξ = ω · (x_θ × n)`; a segment's `x_t = b − a`, `x_tt = 0`,
//!   `∂x_t/∂ξ = J_b − J_a`. Where `φ_ss` is not positive definite (a segment parallel to a
//!   plane, a face on a face) `d` is not twice differentiable and the term is left out.
//!
//! `J` and `φ_sξ` are dense rows over the sub-arcs upstream of the feature, so their part is a
//! low-rank term `[J; φ_sξ]ᵀ diag(−μ G, μ φ_ss⁻¹) [J; φ_sξ]`. A unit test checks the whole
//! `∇²d` against central differences of the exact distance gradient.

use super::contacts::{Ends, Feat, Kin, Pair, World};
use super::curvature::{point_velocity, twists, FrameLoads, LowRank};
use crate::contact::curvature::{distance_hessian, sliding_inverse};
use crate::contact::features::segment_fraction;
use nalgebra::{DMatrix, Matrix3, Vector3};

/// One witness parameter: its tangent `x_s`, `n · x_ss`, and `n · ∂x_s/∂ξ`.
struct Param {
    tangent: Vector3<f64>,
    normal_curv: f64,
    turn: Vec<f64>,
}

impl World<'_> {
    /// Add `−μ ∇²d` of the pair `p` (multiplier `mu`, `kin` with integrals) as forces on the
    /// frames (`loads`) and low-rank terms (`low`), module docs.
    pub(super) fn pair_curvature(
        &self,
        kin: &Kin,
        p: &Pair,
        mu: f64,
        loads: &mut FrameLoads,
        low: &mut Vec<LowRank>,
    ) {
        let nsub = kin.pos.len() - 1;
        let nv = 4 * nsub;
        let n = p.normal;
        let force = n * mu;
        let mut jac = [vec![0.0; nv], vec![0.0; nv], vec![0.0; nv]];
        let mut params = vec![];
        let mut d_pt = p.dist;
        match p.ends {
            Ends::Rigid(f) => {
                let x = p.point_robot;
                loads.add(f, &x, &force);
                point_jac(kin, f, &x, 1.0, &mut jac);
                let r = &kin.rot[f];
                let u = -(r.transpose() * n);
                let uxy = (u.x * u.x + u.y * u.y).sqrt();
                let rd = self.robot.disk_radius;
                if uxy > 1e-6 {
                    let ys = Vector3::new(-u.y, u.x, 0.0) * (rd / uxy);
                    params.push(turning(kin, f, r * ys, &n, rd * uxy));
                } else {
                    for e in [Vector3::x(), Vector3::y()] {
                        params.push(turning(kin, f, r * e, &n, 0.0));
                    }
                }
            }
            Ends::Segment((fa, pa), (fb, pb)) => {
                let t = segment_fraction(&p.point_robot, &pa, &pb);
                loads.add(fa, &pa, &(force * (1.0 - t)));
                loads.add(fb, &pb, &(force * t));
                let mut ja = [vec![0.0; nv], vec![0.0; nv], vec![0.0; nv]];
                let mut jb = [vec![0.0; nv], vec![0.0; nv], vec![0.0; nv]];
                point_jac(kin, fa, &pa, 1.0, &mut ja);
                point_jac(kin, fb, &pb, 1.0, &mut jb);
                for i in 0..3 {
                    for k in 0..nv {
                        jac[i][k] = (1.0 - t) * ja[i][k] + t * jb[i][k];
                    }
                }
                if t > 1e-9 && t < 1.0 - 1e-9 {
                    let turn = (0..nv)
                        .map(|k| (0..3).map(|i| n[i] * (jb[i][k] - ja[i][k])).sum())
                        .collect();
                    params.push(Param {
                        tangent: pb - pa,
                        normal_curv: 0.0,
                        turn,
                    });
                }
                if let Feat::Backbone(_) = p.feat {
                    d_pt += self.robot.body_radius();
                }
            }
        }
        let o = &self.scene.obstacles[p.obstacle];
        // A face contact's distance is to its triangle's plane (`contact::solid::face_contacts`):
        // `G = 0` exactly, not differenced from the mesh's normal field (which, from a witness
        // near an edge of the face, differences across to the neighbour's normal).
        let g = if p.part.is_some() {
            None
        } else {
            distance_hessian(&*o.shape, &o.parry_pose, &p.point_obstacle, &n, d_pt)
                .filter(|g| g.amax() > 0.0)
        };
        self.push_terms(g, &jac, &params, mu, low);
    }

    /// The low-rank term `[J; φ_sξ]ᵀ diag(−μ G, μ φ_ss⁻¹) [J; φ_sξ]` (module docs).
    fn push_terms(
        &self,
        g: Option<Matrix3<f64>>,
        jac: &[Vec<f64>; 3],
        params: &[Param],
        mu: f64,
        low: &mut Vec<LowRank>,
    ) {
        let nv = jac[0].len();
        let gm = g.unwrap_or_else(Matrix3::zeros);
        let mut rows = vec![];
        for pa in params {
            let gx = gm * pa.tangent;
            rows.push(
                (0..nv)
                    .map(|v| pa.turn[v] + (0..3).map(|i| gx[i] * jac[i][v]).sum::<f64>())
                    .collect::<Vec<f64>>(),
            );
        }
        let tangents: Vec<Vector3<f64>> = params.iter().map(|p| p.tangent).collect();
        let curv: Vec<f64> = params.iter().map(|p| p.normal_curv).collect();
        let sliding = sliding_inverse(&gm, &tangents, &curv).map(|inv| inv * mu);
        if let Some(g) = g {
            low.push(LowRank {
                w: jac.to_vec(),
                m: DMatrix::from_fn(3, 3, |a, b| -mu * g[(a, b)]),
            });
        }
        if let Some(m) = sliding {
            low.push(LowRank { w: rows, m });
        }
    }
}

/// Add `w ∂x/∂ξ` of the point `x` carried by frame `f` into the rows `jac` (one per
/// coordinate).
fn point_jac(kin: &Kin, f: usize, x: &Vector3<f64>, w: f64, jac: &mut [Vec<f64>; 3]) {
    for j in 0..f {
        let tw = twists(kin, j);
        for (a, t) in tw.iter().enumerate() {
            let v = point_velocity(t, x) * w;
            for i in 0..3 {
                jac[i][4 * j + a] += v[i];
            }
        }
    }
}

/// A witness parameter of a feature carried rigidly by frame `f`: its tangent turns with the
/// frame, `n · ∂x_s/∂ξ = ω · (x_s × n)`.
fn turning(kin: &Kin, f: usize, tangent: Vector3<f64>, n: &Vector3<f64>, curv: f64) -> Param {
    let nsub = kin.pos.len() - 1;
    let mut turn = vec![0.0; 4 * nsub];
    let c = tangent.cross(n);
    for j in 0..f {
        let tw = twists(kin, j);
        for a in 0..3 {
            turn[4 * j + a] = tw[a][0] * c.x + tw[a][1] * c.y + tw[a][2] * c.z;
        }
    }
    Param {
        tangent,
        normal_curv: curv,
        turn,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::method::energy::contacts::{kinematics, PairKey};
    use crate::method::energy::curvature::dense;
    use crate::method::energy::test_fixture::{bent_state, case2_beside, world, Third};
    use crate::method::energy::Energy;

    /// `∇²d` of every pair (backbone capsules, disks, cable chords against a box, a ball and
    /// a cylinder) equals central differences of the exact distance gradient.
    #[test]
    fn distance_hessians_match_finite_differences() {
        let model = case2_beside(Third::Cylinder);
        let set = Energy::default().with_sub_arcs(2);
        let prob = set
            .setup(&model.robot, &model.actuation, &model.scene)
            .expect("problem");
        let world = world(&model, 2);
        let nv = prob.nvar();
        let xi = bent_state(nv);
        let kin = kinematics(&xi, &prob.ell, true);
        let (pairs, _) = world.pairs(&kin);
        let grad_at = |x: &[f64], key: PairKey| -> Vec<f64> {
            world
                .pairs(&kinematics(x, &prob.ell, true))
                .0
                .into_iter()
                .find(|p| p.key() == key)
                .map(|p| p.grad)
                .expect("pair still present")
        };
        let zero = vec![0.0; prob.nblocks * prob.nb * prob.nb];
        let mut seen = vec![];
        let mut rel = vec![];
        for p in &pairs {
            let (mut loads, mut low) = (FrameLoads::new(prob.nsub + 1), vec![]);
            // μ = −1: the assembled −μ ∇²d is ∇²d.
            world.pair_curvature(&kin, p, -1.0, &mut loads, &mut low);
            let h = dense(&prob.curvature(&xi, &kin, &loads, &low, &zero));
            let scale = h.amax();
            let h_step = 1e-4;
            let mut worst = 0.0f64;
            for i in 0..nv {
                let (mut xp, mut xm) = (xi.clone(), xi.clone());
                xp[i] += h_step;
                xm[i] -= h_step;
                let (gp, gm) = (grad_at(&xp, p.key()), grad_at(&xm, p.key()));
                for k in 0..nv {
                    let fd = (gp[k] - gm[k]) / (2.0 * h_step);
                    worst = worst.max((fd - h[(i, k)]).abs());
                }
            }
            eprintln!(
                "{:?} vs {} at {:.3e} m: |∇²d − fd| ≤ {:.1e} of max |∇²d|",
                p.feat,
                p.obstacle,
                p.dist,
                worst / scale
            );
            rel.push(worst / scale);
            // Every pair within the noise of GJK's normals (~1e-5 rad where the polish
            // cannot improve them, over the 1e-4 step); a missing or wrong term is O(1).
            assert!(
                worst <= 1e-2 * scale,
                "{:?} vs {} at {:e} m: worst |Δ| {worst:e}, scale {scale:e}",
                p.feat,
                p.obstacle,
                p.dist
            );
            seen.push((p.feat, p.obstacle));
        }
        // Most pairs agree to the differences' truncation error (median ~1e-8).
        let close = rel.iter().filter(|&&r| r <= 1e-5).count();
        assert!(
            5 * close >= 4 * rel.len(),
            "{close} of {} within 1e-5",
            rel.len()
        );
        for kind in 0..3 {
            assert!(seen.iter().any(|(f, _)| matches!(
                (f, kind),
                (Feat::Backbone(_), 0) | (Feat::Disk(_), 1) | (Feat::Cable(..), 2)
            )));
        }
        for o in 0..3 {
            assert!(seen.iter().any(|(_, k)| *k == o), "{seen:?}");
        }
    }
}
