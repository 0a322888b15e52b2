//! The shear's step beside the SQP (`energy/shear.rs`, "Condensation") next to obstacles:
//! the pressing contacts' reactions load the shear as dead loads do, and a shear change, which
//! moves every frame beyond it, is guarded as a Newton step is, so that no feature passes
//! through an obstacle between two iterates.

use super::Sqp;
use crate::method::energy::shear::contact_forces;

/// A full shear step whose bound on any point's move is below this fraction of the tolerance
/// is not taken (it would change no residual the solve reads).
const NEGLIGIBLE: f64 = 1e-3;

/// Halvings of a shear step the step guard refuses before the step is left out.
const HALVINGS: usize = 30;

impl Sqp<'_, '_> {
    /// The shear's Newton step on its own equilibrium at the iterate (none without
    /// `shear = on`), then the linearization at the iterate ([`Sqp::linearize`]). Returns the
    /// full step's bound on how far it moves any point \[m\], the shear's residual.
    ///
    /// With obstacles the iterate is linearized first: its frames carry the integrals `M_j`
    /// and its pairs the last step's multipliers, whose reactions `μ n̂` at the witnesses are
    /// forces at the frames for the shear's equilibrium (`∂d/∂γ_a = n̂ · M_j e_a` for a
    /// witness beyond sub-arc `j`, as `∂d/∂ε`). The step is then taken as far as the step
    /// guard of the line search allows (halved until it does: every point moves by at most
    /// the robot's distance to the obstacles, or half the pair margin when closer, or every
    /// pair passes `energy/step_guard.rs`), and the iterate is linearized again at the new
    /// shear, its pairs those the guard found there.
    pub(super) fn shear_and_linearize(&mut self) -> f64 {
        let prob = self.prob;
        if !prob.set.shear {
            self.linearize();
            return 0.0;
        }
        let Some(wd) = self.world else {
            let moved = prob.condense_shear(&self.xi, &self.lam);
            self.linearize();
            return moved;
        };
        self.linearize();
        let Some(k0) = self.kin.take() else {
            return 0.0;
        };
        let forces = contact_forces(&self.pairs, &self.mu, k0.pos.len());
        let step = prob.shear_newton(&self.xi, &self.lam, Some(&k0), &forces);
        let full = step
            .iter()
            .zip(&prob.ell)
            .map(|(d, l)| l * d[0].hypot(d[1]))
            .sum::<f64>();
        if full <= NEGLIGIBLE * prob.set.tolerance {
            self.kin = Some(k0);
            return full;
        }
        let before = prob.shear.borrow().clone();
        let mut scale = 1.0;
        for _ in 0..HALVINGS {
            prob.add_shear(&step, scale);
            let k1 = prob.kin(&self.xi, false);
            let (p1, c1) = wd.pairs_near(&k1, &self.pairs);
            let clear = wd.max_move(&k0, &k1) <= self.clear.max(0.5 * wd.margin())
                || wd.step_is_clear((&k0, &self.pairs, self.clear), (&k1, &p1, c1));
            if clear {
                self.next_pairs = Some((p1, c1));
                self.linearize();
                return full;
            }
            *prob.shear.borrow_mut() = before.clone();
            scale *= 0.5;
        }
        // No part of the step is clear: the shear stays, and the residual says so.
        self.kin = Some(k0);
        full
    }
}
