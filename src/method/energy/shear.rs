//! Shear in the energy model (`shear = on`): the Timoshenko–Reissner rod of
//! [`crate::method::cosserat`] (Rucker & Webster 2011, eq. 1–7: `v − e₃ = K_se⁻¹ Rᵀ n`,
//! `K_se = diag(GA, GA, EA)`), as a energy, with the same stiffnesses read from
//! [`crate::model::robot::Backbone`] (`GA` without a shear coefficient, as the rod takes it).
//!
//! # Energy
//!
//! On sub-arc `j` the linear strain is `v_j = (γx, γy, 1 + ε)` (Reissner 1972; Simo 1985):
//! the cross-section slides by `γ` against the backbone's tangent. The strain energy gains
//! the shear term (Timoshenko 1921, the shear part of `½ (v − e₃)ᵀ K_se (v − e₃)`):
//!
//! ```text
//! E = Σ_j ½ ℓ_j (EI κ² + GJ τ² + EA ε² + GA |γ_j|²)
//! ```
//!
//! The kinematics take the whole `v` (`p' = R v`: [`super::kinematics::sheared_exp`]), and a
//! cable runs along the sheared centreline: its body-frame tangent is `w = v + u × r + r'`
//! (R&W eq. 6), so `∂w/∂γ_a = e_a` and, for the path measure,
//!
//! ```text
//! ∂L_c/∂γ_a = ∫_j ŵ_a ds,        ∂²L_c/∂γ_a∂γ_b = ∫_j (δ_ab − ŵ_a ŵ_b) / |w| ds
//! ```
//!
//! A dead load at a frame beyond sub-arc `j` moves by `∂x/∂γ_a = M_j e_a`
//! (`energy/contacts.rs`), so the load potential `V = −Σ F·p` has `∂V/∂γ_a = −(M_jᵀ S_j)_a`
//! (`S_j` the loads beyond `j`), constant in `γ` (positions are affine in `v`).
//!
//! # Condensation: the shear from the equilibrium of the shear force
//!
//! The stationarity of the total potential (energy, tension potentials or multipliers `w_c`
//! times lengths, loads) in `γ_j` is local to the sub-arc:
//!
//! ```text
//! ℓ_j GA γ_j + Σ_c w_c ∫_j ŵ_⊥ ds − (M_jᵀ S_j)_⊥ = 0
//! ```
//!
//! — the rod's `v_⊥ = n_⊥ / GA` with the backbone's internal force `n = −Σ T ŵ` (the cables'
//! pull back along their tangents) plus the loads beyond. Given the bending, twist and
//! stretch and the cable weights, it is a 2×2 strictly convex problem per sub-arc (GA > 0,
//! the cable term convex), with the exact gradient and Hessian above. So the shear is not a
//! degree of freedom of the SQP (its blocks stay 4×4): it is condensed alongside it. At every
//! iterate, before the linearization, the shear takes one Newton step on this equilibrium at
//! the iterate's strains and multipliers ([`Problem::condense_shear`]); the SQP step then
//! moves the other strains at fixed shear (its line search and residuals see the shear
//! fixed, with exact gradients and Hessians). This block Gauss–Seidel costs little because
//! shear and bending couple weakly (the off-diagonal `T r` against `√(EI · GA)`: 1e-3 or
//! less on a 6 mm silicone rod under 1 N). The solve has converged when, besides the SQP's
//! residuals, the shear step moved no point by more than [`Energy::tolerance`] (a bound:
//! `Σ ℓ_j |δγ_j|`): the stationarity then holds in every strain, the discrete Cosserat rod.
//! Measured on the paper's cases: one pass over the cables' Gauss nodes per iterate, and at
//! most one iteration more (module docs of [`super`], "Accuracy").
//! Next to obstacles the pressing contacts' reactions `μ n̂` load the shear as dead loads at
//! their witnesses do (`∂d/∂γ_a = n̂ · M_j e_a` for a witness beyond sub-arc `j`, as for `ε`:
//! [`contact_forces`]), and the shear's step, which moves every frame beyond it, passes the
//! line search's step guard (halved until it does), so no feature crosses an obstacle between
//! iterates (`newton/shear_step.rs`). Shear is refused with capstan friction and the chord
//! measure (whose chords would need the sheared exponential's AD).
//!
//! The tip Jacobian (`report.jacobian`) is taken at fixed shear: it leaves out the shear's
//! own response, a relative error of the order of the coupling above.

use super::contacts::{Ends, Kin, Pair};
use super::lengths::path_w;
use super::problem::Problem;
use super::problem::Target;
use super::Energy;
use crate::contact::features;
use crate::error::SolveError;
use crate::method::warm::WarmState;
use crate::method::Method;
use crate::shape::Shape;
use nalgebra::Vector3;

impl Problem<'_> {
    /// Shear energy `Σ_j ½ ℓ_j GA |γ_j|²` \[J\] (0 without shear).
    pub(super) fn shear_energy(&self) -> f64 {
        self.shear
            .borrow()
            .iter()
            .zip(&self.ell)
            .map(|(g, l)| 0.5 * l * self.ga * (g[0] * g[0] + g[1] * g[1]))
            .sum()
    }

    /// The generalized force of the dead loads and of `extra` (forces at the frames, e.g. the
    /// pressing contacts': [`contact_forces`]) on the shear of every sub-arc, `(M_jᵀ S_j)_⊥`
    /// (module docs; empty without either); `kin` with integrals.
    fn shear_loads(&self, kin: Option<&Kin>, extra: &[Vector3<f64>]) -> Vec<[f64; 2]> {
        let Some(kin) = kin.filter(|_| !self.frame_forces.is_empty() || !extra.is_empty()) else {
            return vec![];
        };
        let mut out = vec![[0.0; 2]; self.nsub];
        let mut sum = Vector3::zeros();
        let zero = Vector3::zeros();
        for j in (0..self.nsub).rev() {
            sum +=
                self.frame_forces.get(j + 1).unwrap_or(&zero) + extra.get(j + 1).unwrap_or(&zero);
            let ms = kin.m_int[j].tr_mul(&sum);
            out[j] = [ms.x, ms.y];
        }
        out
    }

    /// Gradient and Hessian (xx, xy, yy) of the total potential in the shear of every
    /// sub-arc (module docs) at the strains `xi`, with cable weights `wgt` (multipliers of
    /// the length-driven cables, input tensions), the loads' frames `kin` (integrals) and the
    /// forces `extra` at the frames ([`Problem::shear_loads`]).
    pub(super) fn shear_derivatives(
        &self,
        xi: &[f64],
        wgt: &[f64],
        kin: Option<&Kin>,
        extra: &[Vector3<f64>],
    ) -> Vec<([f64; 2], [f64; 3])> {
        let loads = self.shear_loads(kin, extra);
        let shear = self.shear.borrow();
        let mut out: Vec<([f64; 2], [f64; 3])> = (0..shear.len())
            .map(|j| {
                let k = self.ell[j] * self.ga;
                let (g, load) = (shear[j], loads.get(j).copied().unwrap_or_default());
                ([k * g[0] - load[0], k * g[1] - load[1]], [k, 0.0, k])
            })
            .collect();
        for (c, cable) in self.robot.cables.iter().enumerate() {
            let wc = wgt[c];
            if wc == 0.0 || self.targets[c] == Target::Free {
                continue;
            }
            for j in 0..self.first[cable.ends_at].min(shear.len()) {
                let x = &xi[4 * j..4 * j + 4];
                let (r, h) = &mut out[j];
                for nd in &self.nodes[c][j] {
                    // ∂|w|/∂γ = ŵ_⊥, ∂²|w|/∂γ² = (I − ŵŵᵀ)_⊥ / |w|.
                    let w = path_w(nd, x, shear[j]);
                    let n = w.norm();
                    let (ex, ey, f) = (w.x / n, w.y / n, wc * nd[4]);
                    r[0] += f * ex;
                    r[1] += f * ey;
                    let f = f / n;
                    h[0] += f * (1.0 - ex * ex);
                    h[1] -= f * ex * ey;
                    h[2] += f * (1.0 - ey * ey);
                }
            }
        }
        out
    }

    /// One Newton step `δγ_j = −H_j⁻¹ ∇_j` on the shear equilibrium of every sub-arc at the
    /// strains `xi` and multipliers `lam` (module docs), with the forces `extra` at the frames
    /// `kin` (the pressing contacts'; `kin` is computed here when `None` and loads need it).
    pub(super) fn shear_newton(
        &self,
        xi: &[f64],
        lam: &[f64],
        kin: Option<&Kin>,
        extra: &[Vector3<f64>],
    ) -> Vec<[f64; 2]> {
        let wgt: Vec<f64> = (0..lam.len())
            .map(|c| self.cable_weight(c, lam[c]))
            .collect();
        let own = (kin.is_none() && !self.frame_forces.is_empty()).then(|| self.kin(xi, true));
        let derivs = self.shear_derivatives(xi, &wgt, kin.or(own.as_ref()), extra);
        derivs
            .iter()
            .map(|(r, h)| {
                // The 2×2 Hessian is positive definite (GA > 0, the cables convex).
                let det = h[0] * h[2] - h[1] * h[1];
                [
                    -(h[2] * r[0] - h[1] * r[1]) / det,
                    -(h[0] * r[1] - h[1] * r[0]) / det,
                ]
            })
            .collect()
    }

    /// Add `scale · step` to the shear; returns the bound `Σ ℓ_j |δγ_j|` on how far it moved
    /// any point \[m\] (a shear change translates the frames beyond it by `M_j δγ_j`, and
    /// `|M_j e_a| ≤ ℓ_j`; it turns none).
    pub(super) fn add_shear(&self, step: &[[f64; 2]], scale: f64) -> f64 {
        let mut moved = 0.0;
        for (j, (g, d)) in self.shear.borrow_mut().iter_mut().zip(step).enumerate() {
            g[0] += scale * d[0];
            g[1] += scale * d[1];
            moved += self.ell[j] * (scale * d[0]).hypot(scale * d[1]);
        }
        moved
    }

    /// [`Problem::shear_newton`] without obstacles, taken: the bound of [`Problem::add_shear`].
    pub(super) fn condense_shear(&self, xi: &[f64], lam: &[f64]) -> f64 {
        let step = self.shear_newton(xi, lam, None, &[]);
        self.add_shear(&step, 1.0)
    }
}

/// The forces the pressing pairs (`pairs` with multipliers `mu`, the reaction `μ n̂` at the
/// witness) put on the frames of `nframes` sub-arc ends, as [`Problem::shear_loads`] reads
/// them: a disk's on its frame, a segment's witness at fraction `t` split `(1 − t, t)` over
/// its end frames (the way the point moves with them, `energy/contacts.rs`).
pub(super) fn contact_forces(pairs: &[Pair], mu: &[f64], nframes: usize) -> Vec<Vector3<f64>> {
    let mut out = vec![Vector3::zeros(); nframes];
    for (p, &m) in pairs.iter().zip(mu).filter(|(_, &m)| m > 0.0) {
        let f = p.normal * m;
        match p.ends {
            Ends::Rigid(k) => out[k] += f,
            Ends::Segment((fa, pa), (fb, pb)) => {
                let t = features::segment_fraction(&p.point_robot, &pa, &pb);
                out[fa] += f * (1.0 - t);
                out[fb] += f * t;
            }
        }
    }
    out
}

impl Energy {
    /// The shear a solve starts from: a warm shape's of the same layout, else zero (none
    /// without `shear`).
    pub(super) fn start_shear(&self, prob: &Problem, warm: Option<&Shape>) {
        *prob.shear.borrow_mut() = if self.shear {
            warm_shear(warm, prob.nsub).unwrap_or_else(|| vec![[0.0; 2]; prob.nsub])
        } else {
            vec![]
        };
    }

    /// Refuse what shear does not support (module docs), naming it.
    pub(super) fn check_shear(&self, friction: bool) -> Result<(), SolveError> {
        if !self.shear {
            return Ok(());
        }
        let why = if friction {
            "capstan friction"
        } else if self.cable_length != crate::model::actuation::LengthMeasure::Path {
            "the chord cable length (use length = path)"
        } else {
            return Ok(());
        };
        Err(SolveError::Unsupported {
            method: self.name().into(),
            reason: format!("shear = on does not support {why}: set shear = off"),
        })
    }
}

/// The shear of a warm shape of this method with `nsub` sub-arcs, if it carries one.
fn warm_shear(warm: Option<&Shape>, nsub: usize) -> Option<Vec<[f64; 2]>> {
    match &warm?.report.warm {
        Some(WarmState::Energy(e)) if e.shear.len() == nsub => Some(e.shear.clone()),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::actuation::Actuation;
    use crate::model::scene::Scene;
    use crate::model::Model;

    /// The lung rod (helical tendons: the cables pull across the backbone) with gravity and
    /// a tip force.
    fn loaded_lung_rod() -> Model {
        let text = std::fs::read_to_string(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/models/soft/lung_rod.toml"
        ))
        .expect("lung rod");
        let text = text.replace("tension = 0.0", "tension = 1.5");
        Model::from_toml_str(&format!(
            "{text}\n[loads]\ngravity = [-9.81, 0.0, 0.0]\ntip_force = [0.0, 0.02, -0.01]\n"
        ))
        .expect("model")
    }

    /// The gradient and Hessian of the total potential in one sub-arc's shear against central
    /// differences of the potential itself (energy, tension potentials, loads).
    #[test]
    fn shear_stationarity_matches_central_differences() {
        let model = loaded_lung_rod();
        let set = Energy {
            shear: true,
            ..Energy::default()
        };
        let prob0 = set
            .setup(&model.robot, &model.actuation, &model.scene)
            .expect("setup");
        let prob = prob0;
        *prob.shear.borrow_mut() = (0..prob.nsub)
            .map(|j| [1e-3 * (j as f64).sin(), -2e-3 * (j as f64).cos()])
            .collect();
        let xi: Vec<f64> = (0..prob.nvar())
            .map(|i| match i % 4 {
                3 => -1e-3,
                a => 2.0 * ((i + a) as f64).sin(),
            })
            .collect();
        let nc = model.robot.cables.len();
        let wgt: Vec<f64> = (0..nc).map(|c| 0.7 + c as f64).collect();
        let total = |p: &Problem| {
            let mut len = vec![0.0; nc];
            p.lengths(&xi, &mut len);
            let kin = p.kin(&xi, false);
            p.energy(&xi)
                + len.iter().zip(&wgt).map(|(l, w)| l * w).sum::<f64>()
                + p.load_potential(Some(&kin))
        };
        let kin = prob.kin(&xi, true);
        let derivs = |p: &Problem| p.shear_derivatives(&xi, &wgt, Some(&kin), &[]);
        assert_eq!(prob.shear_loads(Some(&kin), &[]).len(), prob.nsub, "loads");
        let base = derivs(&prob);
        let h = 1e-6;
        for j in [0, prob.nsub / 2, prob.nsub - 1] {
            let g0 = prob.shear_at(j);
            let (grad, hess) = base[j];
            let hess = [[hess[0], hess[1]], [hess[1], hess[2]]];
            for a in 0..2 {
                let at = |d: f64| {
                    prob.shear.borrow_mut()[j][a] = g0[a] + d;
                    let v = total(&prob);
                    let gr = derivs(&prob)[j].0;
                    prob.shear.borrow_mut()[j] = g0;
                    (v, gr)
                };
                let (fp, gp) = at(h);
                let (fm, gm) = at(-h);
                let fd = (fp - fm) / (2.0 * h);
                assert!(
                    (fd - grad[a]).abs() < 1e-7 * (1.0 + grad[a].abs()),
                    "∂Π/∂γ[{j}][{a}]: {fd} vs {}",
                    grad[a]
                );
                for b in 0..2 {
                    let fd2 = (gp[b] - gm[b]) / (2.0 * h);
                    assert!(
                        (fd2 - hess[b][a]).abs() < 1e-6 * (1.0 + hess[b][a].abs()),
                        "∂²Π/∂γ[{j}][{a}]∂γ[{b}]: {fd2} vs {}",
                        hess[b][a]
                    );
                }
            }
        }
    }
    /// The reaction of one contact as a load on the shear ([`contact_forces`], read by
    /// [`Problem::shear_loads`]) is the gradient of its distance in the shear strains,
    /// `∂d/∂γ_a = n̂ · M_j e_a`: against central differences of the queried distance, for
    /// backbone, disk and cable-chord pairs of paper case II bent beside a box, a ball and a
    /// capsule.
    #[test]
    fn contact_reactions_load_the_shear_as_their_distance_gradient() {
        use crate::method::energy::contacts::Feat;
        use crate::method::energy::test_fixture::{bent_state, case2_beside, world, Third};
        let model = case2_beside(Third::Capsule);
        let set = Energy {
            shear: true,
            ..Energy::default()
        };
        let (act, empty) = (Actuation::free(&model.robot), Scene::empty());
        let prob = set.setup(&model.robot, &act, &empty).expect("setup");
        let world = world(&model, set.sub_arcs);
        *prob.shear.borrow_mut() = (0..prob.nsub)
            .map(|j| [2e-3 * (j as f64).sin(), -1e-3 * (j as f64).cos()])
            .collect();
        let xi = bent_state(prob.nvar());
        let kin = prob.kin(&xi, true);
        let (pairs, _) = world.pairs(&kin);
        for kind in ["backbone", "disk", "cable"] {
            let has = |f: &Feat| match f {
                Feat::Backbone(_) => kind == "backbone",
                Feat::Disk(_) => kind == "disk",
                Feat::Cable(..) => kind == "cable",
            };
            assert!(pairs.iter().any(|p| has(&p.feat)), "no {kind} pair");
        }
        let dist_at = |j: usize, a: usize, d: f64, key| {
            let g0 = prob.shear_at(j);
            prob.shear.borrow_mut()[j][a] = g0[a] + d;
            let dist = super::super::test_fixture::pair_dist(&world, &prob.kin(&xi, false), key);
            prob.shear.borrow_mut()[j] = g0;
            dist
        };
        let h = 1e-4;
        let mut checked = 0;
        for (i, p) in pairs.iter().enumerate() {
            let mut mu = vec![0.0; pairs.len()];
            mu[i] = 1.0;
            let forces = contact_forces(&pairs, &mu, prob.nsub + 1);
            let gen = prob.shear_loads(Some(&kin), &forces);
            let scale = gen.iter().flatten().fold(0.0f64, |m, g| m.max(g.abs()));
            assert!(scale > 0.0, "{:?}", p.feat);
            for j in (0..prob.nsub).step_by(3) {
                for a in 0..2 {
                    let fd = (dist_at(j, a, h, p.key()) - dist_at(j, a, -h, p.key())) / (2.0 * h);
                    // The polished normals' noise (`contacts.rs` tests) times the lever.
                    assert!(
                        (fd - gen[j][a]).abs() <= 2e-5 * scale,
                        "{:?}: ∂d/∂γ[{j}][{a}] {} vs fd {fd}",
                        p.feat,
                        gen[j][a]
                    );
                    checked += 1;
                }
            }
        }
        assert!(checked > 50, "{checked}");
    }
}
