//! The start of a solve from a previous shape (module docs, "Warm starts"): its base wrench
//! and tensions, and from a shape of this method its last Jacobian, predicted to the new load
//! by the load ratio; without a warm shape, the global balance.

use super::problem::Problem;
use super::shooting::Setup;
use super::{Buf, MAX_CABLES};
use crate::method::warm::WarmState;
use crate::shape::Shape;
use nalgebra::{DMatrix, DVector, Vector3};

/// What a warm shape gives the rod.
pub(super) struct Warm {
    /// Base wrench `n(0)`, `m(0)/L` and every cable's tension.
    pub(super) x: Option<(Vector3<f64>, Vector3<f64>, Vec<f64>)>,
    /// Only the tensions (a shape without a base wrench: another model's).
    pub(super) tensions: Option<Vec<f64>>,
    /// The last Jacobian (a shape of this method only).
    pub(super) jac: Option<DMatrix<f64>>,
    /// The shape came from this method (its base wrench carries this discretization).
    pub(super) same: bool,
    /// The warm solution's unknown cables and their length targets.
    targets: Option<(Vec<usize>, Vec<f64>)>,
    /// The start was moved by the predictor step ([`Warm::start`]).
    pub(super) predicted: bool,
}

/// Load ratio of tensions `tn` to `tw` along `tw`'s ray: `tn·tw / tw·tw` (1 without load).
fn load_ratio(tn: &Buf, tw: &Buf) -> f64 {
    let a: f64 = tn.iter().zip(tw).map(|(a, b)| a * b).sum();
    let b: f64 = tw.iter().map(|b| b * b).sum();
    if b > 0.0 && (a / b).is_finite() {
        a / b
    } else {
        1.0
    }
}

impl Warm {
    /// Read a warm shape (`None`: a cold start). Length-controlled cables that were slack
    /// with zero tension start slack (`slack`).
    pub(super) fn read(
        warm: Option<&Shape>,
        name: &str,
        len_l: f64,
        length_cables: &[usize],
        slack: &mut [bool],
    ) -> Warm {
        let nc = slack.len();
        // A warm start from this method also carries its last Jacobian (`report.warm`) and
        // the offset of its base wrench from the global balance.
        let same = warm.is_some_and(|w| w.method == name);
        let (jac, targets) = match warm.filter(|_| same).map(|w| &w.report.warm) {
            Some(Some(WarmState::Rod {
                jacobian,
                unknown,
                targets,
            })) if jacobian.nrows() >= 6 && jacobian.is_square() => (
                Some(jacobian.clone()),
                Some((unknown.clone(), targets.clone())),
            ),
            _ => (None, None),
        };
        let mut x = None;
        let mut tensions = None;
        if let Some(w) = warm.filter(|w| w.cables.len() == nc) {
            let tens: Vec<f64> = w
                .cables
                .iter()
                .map(|c| c.tension.filter(|t| t.is_finite()).unwrap_or(0.0))
                .collect();
            match w.report.base_wrench {
                Some(bw) if bw.iter().all(|v| v.is_finite()) => {
                    for &c in length_cables {
                        slack[c] = w.cables[c].slack && tens[c] == 0.0;
                    }
                    x = Some((
                        Vector3::new(bw[0], bw[1], bw[2]),
                        Vector3::new(bw[3], bw[4], bw[5]) / len_l,
                        tens,
                    ));
                }
                // Another model's shape (energy, geometric): its cable tensions (the energy
                // model's multipliers) start the length-controlled cables; the base wrench then
                // follows from the global balance.
                _ if w.cables.iter().any(|c| c.tension.is_some_and(|t| t > 0.0)) => {
                    // Cables the other model leaves (numerically) slack start slack: a taut
                    // cable at zero tension makes the inextensible rod's Jacobian singular.
                    let top = tens.iter().fold(0.0f64, |a, &b| a.max(b));
                    for &c in length_cables {
                        slack[c] = tens[c] <= 1e-6 * top;
                    }
                    tensions = Some(tens);
                }
                _ => {}
            }
        }
        Warm {
            x,
            tensions,
            jac,
            same,
            targets,
            predicted: false,
        }
    }

    /// Predictor for new length targets (displacement control): the warm solution `x_w`
    /// solves `F(x_w; ℓ_w) = 0`, and `F` depends on the targets only through its length rows,
    /// `F_j = k_ℓ (ℓ_j − ℓ_target,j)`, so `F(x_w; ℓ_new) = k_ℓ (ℓ_w − ℓ_new)` is known without
    /// integrating, and the Newton step with the warm Jacobian,
    /// `x₀ = x_w − J_w⁻¹ F(x_w; ℓ_new)`, is the first-order sensitivity `∂x/∂ℓ_target` applied
    /// to the change. Only when the unknown cables are the warm solution's. True if `x0`
    /// moved.
    fn predict(&self, prob: &Problem, setup: &Setup, x0: &mut DVector<f64>) -> bool {
        let (Some(j), Some((unknown, targets))) = (&self.jac, &self.targets) else {
            return false;
        };
        if *unknown != setup.unknown || j.nrows() != x0.len() || unknown.is_empty() {
            return false;
        }
        let mut f = DVector::zeros(x0.len());
        for (k, (&c, &t)) in unknown.iter().zip(targets).enumerate() {
            f[6 + k] = prob.kl[c] * (t - prob.target(c, 1.0));
        }
        if f.iter().all(|v| *v == 0.0) {
            return false;
        }
        match j.clone().lu().solve(&f) {
            Some(dx) if dx.iter().all(|v| v.is_finite()) => {
                *x0 -= dx;
                true
            }
            _ => false,
        }
    }

    /// The warm contacts' force `f` and moment `m` about the base \[N, N m\] added to the base
    /// wrench of a start from another model's shape, which [`Warm::start`] took from the
    /// global balance of the straight rod without contacts: at the warm shape the rod's
    /// internal wrench at the base carries the reactions too (a rod's own shape brings its
    /// base wrench whole). Without it, Newton from the energy model's answer beside the
    /// obstacles started a full reaction's moment away and did not converge.
    pub(super) fn with_contacts(
        &self,
        prob: &Problem,
        (f, m): (&Vector3<f64>, &Vector3<f64>),
        x0: &mut DVector<f64>,
    ) {
        if self.x.is_some() {
            return;
        }
        for i in 0..3 {
            x0[i] += f[i];
            x0[3 + i] += m[i] / prob.len_l;
        }
    }

    /// The start `x0` of the first active-set round: the warm base wrench and tensions; with
    /// no shape-dependent external load, the global balance at the new tensions plus the warm
    /// solution's offset from it, scaled by the load ratio `ρ` (and the tendon part of the
    /// Jacobian likewise). Cold: the global balance.
    pub(super) fn start(&mut self, prob: &Problem, setup: &Setup, x0: &mut DVector<f64>) {
        let Some((n0, m0s, tens)) = &self.x else {
            if let Some(tens) = &self.tensions {
                for (j, &c) in setup.unknown.iter().enumerate() {
                    x0[6 + j] = tens[c];
                }
            }
            prob.balance_guess(x0, setup, 1.0);
            return;
        };
        let len_l = prob.len_l;
        let nc = prob.robot.cables.len();
        for i in 0..3 {
            x0[i] = n0[i];
            x0[3 + i] = m0s[i];
        }
        for (j, &c) in setup.unknown.iter().enumerate() {
            x0[6 + j] = tens[c];
        }
        if self.predict(prob, setup, x0) {
            self.predicted = true;
            return;
        }
        if !prob.shape_free_loads() {
            return;
        }
        let same = self.same;
        // The balance is exact for the rod but not for its discretization, which
        // misses it by the integration error; a warm start from this method has
        // measured that offset. The offset vanishes with the load and, to first
        // order, grows with it: keep it, scaled by the load ratio `ρ`.
        let mut tw = [0.0; MAX_CABLES];
        tw[..nc].copy_from_slice(tens);
        let tn = prob.tensions(x0, setup, 1.0);
        let (nb, mb) = prob.balance(&tn, 1.0);
        let (nw, mw) = if same {
            prob.balance(&tw, 1.0)
        } else {
            (*n0, m0s * len_l)
        };
        let rho = if same { load_ratio(&tn, &tw) } else { 1.0 };
        for i in 0..3 {
            x0[i] = nb[i] + (n0[i] - nw[i]) * rho;
            x0[3 + i] = (mb[i] + (m0s[i] * len_l - mw[i]) * rho) / len_l;
        }
        // Likewise the tendon part of the Jacobian, `J − J₀` (`J₀`: the unloaded
        // straight rod's, a rigid transport along `L e3`), for the wrench block.
        if let Some(j) = self.jac.as_mut().filter(|j| j.nrows() == x0.len()) {
            let j0 = prob.transport_jacobian(&Vector3::new(0.0, 0.0, len_l));
            for r in 0..6 {
                for c in 0..6 {
                    j[(r, c)] = j0[(r, c)] + rho * (j[(r, c)] - j0[(r, c)]);
                }
            }
        }
    }
}
