//! Solving the shooting problem: the residual (tip wrench and, per length-controlled taut
//! cable, its length error), Jacobians (variational, rigid transport, differences), Newton
//! with a backtracking line search and Broyden updates, and load continuation (module docs,
//! "Shooting", "Continuation").

use super::contact::{Push, Touch};
use super::problem::{LoadCase, Problem};
use super::Buf;
use crate::model::actuation::Drive;
use crate::numeric::so3::hat;
use nalgebra::{DMatrix, DVector, Vector3};

/// One configuration of unknowns: which cables carry unknown tensions.
pub(super) struct Setup {
    /// Cables whose tension is an unknown (length-controlled, taut).
    pub(super) unknown: Vec<usize>,
    /// Length-controlled cables currently slack (tension 0).
    pub(super) slack: Vec<bool>,
    /// The active contacts (`contact.rs`), ordered by disk: their forces are the last
    /// unknowns, their gaps the last residual rows.
    pub(super) contacts: Vec<Touch>,
}

impl Setup {
    /// Index of the first contact force in the unknowns.
    pub(super) fn first_contact(&self) -> usize {
        6 + self.unknown.len()
    }
}

/// A converged Newton run: solution, iterations, residual, last Jacobian (for warm starts).
pub(super) struct Newton {
    pub(super) x: DVector<f64>,
    pub(super) iterations: usize,
    pub(super) residual: f64,
    pub(super) jac: Option<DMatrix<f64>>,
}

/// Failure of a Newton run (for continuation / error reporting).
pub(super) struct Fail {
    pub(super) iterations: usize,
    pub(super) residual: f64,
    pub(super) detail: String,
}

impl Fail {
    fn new(iterations: usize, residual: f64, detail: impl Into<String>) -> Self {
        Fail {
            iterations,
            residual,
            detail: detail.into(),
        }
    }
}

impl Problem<'_> {
    pub(super) fn residual(&self, x: &DVector<f64>, setup: &Setup, lam: f64) -> DVector<f64> {
        self.residual_tip(x, setup, lam).0
    }

    /// Approximate Jacobian of the tip wrench residual w.r.t. the base wrench (force
    /// control): a base wrench change is carried rigidly to the tip, `δn(L) = δn0`,
    /// `δm(L) = δm0 − p_L × δn0` (tendon and shape corrections are left to Broyden).
    pub(super) fn transport_jacobian(&self, tip: &Vector3<f64>) -> DMatrix<f64> {
        let mut j = DMatrix::identity(6, 6);
        let t = hat(tip) * (-1.0 / self.len_l);
        for r in 0..3 {
            for c in 0..3 {
                j[(3 + r, c)] = t[(r, c)];
            }
        }
        j
    }

    fn residual_tip(
        &self,
        x: &DVector<f64>,
        setup: &Setup,
        lam: f64,
    ) -> (DVector<f64>, Vector3<f64>) {
        let n0 = Vector3::new(x[0], x[1], x[2]);
        let m0 = Vector3::new(x[3], x[4], x[5]) * self.len_l;
        let ld = self.load_case(x, setup, lam);
        let shot = self.shoot(&n0, &m0, &ld, None, None);
        let mut f = DVector::zeros(x.len());
        for i in 0..6 {
            f[i] = shot.resid[i];
        }
        for (j, &c) in setup.unknown.iter().enumerate() {
            f[6 + j] = self.length_row(c, shot.len[c], x[6 + j], lam);
        }
        let c0 = setup.first_contact();
        if shot.touch.len() == setup.contacts.len() {
            let (kg, clearance) = (self.gap_scale(), self.clearance());
            for (i, w) in shot.touch.iter().enumerate() {
                f[c0 + i] = kg * (w.dist - clearance);
            }
        } else if !setup.contacts.is_empty() {
            f.fill(f64::NAN);
        }
        if f.iter().any(|v| !v.is_finite()) {
            f.fill(f64::NAN);
        }
        (f, shot.tip)
    }

    /// The free (unstretched) length of cable `c` at load factor `lam`, in the chosen
    /// measure: the undeformed length minus the shortening and, for a compliant cable, minus
    /// the pretension stretch `T₀/k` (both scaled by `lam`, so zero load is the unloaded
    /// rod). A slack cable's path may not exceed it.
    pub(super) fn target(&self, c: usize, lam: f64) -> f64 {
        match self.modes[c] {
            Drive::Shorten { length: d, .. } => self.len0[c] - lam * (d + self.pre_stretch[c]),
            _ => self.len0[c],
        }
    }

    /// The length equation of a taut length-controlled cable `c` with path `len` and tension
    /// `tau`: `k_ℓ (ℓ − t − τ/k) = 0`, the path is the free length `t` ([`Self::target`])
    /// plus the cable's stretch `τ/k` (series spring; `1/k = 0` when inextensible) — the
    /// energy model's `L − t − λ/k` (`src/method/energy/`, "Compliant cables"). Its
    /// derivative in `τ` is `−k_ℓ/k`.
    #[inline]
    pub(super) fn length_row(&self, c: usize, len: f64, tau: f64, lam: f64) -> f64 {
        self.kl[c] * (len - self.target(c, lam) - tau * self.compliance[c])
    }

    /// The loads of a pass at `x`: the tensions ([`Problem::tensions`]) and the forces of
    /// the active contacts.
    pub(super) fn load_case(&self, x: &DVector<f64>, setup: &Setup, lam: f64) -> LoadCase {
        let c0 = setup.first_contact();
        let mut ld = LoadCase::new(self.tensions(x, setup, lam), lam);
        ld.push = setup
            .contacts
            .iter()
            .enumerate()
            .map(|(i, &touch)| Push {
                touch,
                force: x[c0 + i],
            })
            .collect();
        ld
    }

    /// The scene's clearance (0 without obstacles) \[m\].
    pub(super) fn clearance(&self) -> f64 {
        self.world.as_ref().map_or(0.0, |w| w.clearance())
    }

    /// True when the variational equations give the exact Jacobian of this shooting pass:
    /// fixed RK4 steps and no point load at an inner disk (a cable tied there, or disk
    /// weights: their kink forces come from a fixed point that is not differentiated).
    pub(super) fn var_ok(&self, setup: &Setup, tau: &Buf, lam: f64) -> bool {
        if self.set.adaptive.is_some()
            || self.disk_weight.norm() * lam > 0.0
            || !setup.contacts.is_empty()
        {
            return false;
        }
        let nsec = self.robot.sections();
        self.robot.cables.iter().enumerate().all(|(c, cable)| {
            cable.ends_at >= nsec || (tau[c] == 0.0 && !setup.unknown.contains(&c))
        })
    }

    /// A fresh Jacobian at `x`: variational where possible, else forward differences.
    fn jacobian(
        &self,
        x: &DVector<f64>,
        f: &DVector<f64>,
        setup: &Setup,
        lam: f64,
    ) -> DMatrix<f64> {
        if let Some((_, j, _)) = self.residual_jac(x, setup, lam) {
            return j;
        }
        let k = x.len();
        let mut j = DMatrix::zeros(k, k);
        let mut xp = x.clone();
        for col in 0..k {
            let h = 1e-7 * x[col].abs().max(self.fscale);
            xp[col] = x[col] + h;
            let fp = self.residual(&xp, setup, lam);
            xp[col] = x[col];
            j.set_column(col, &((fp - f) / h));
        }
        j
    }

    /// Newton with line search and Broyden updates at load factor `lam`.
    ///
    /// `jac0`: a Jacobian to start from (a warm start's, kept current by Broyden); without it
    /// the residual and the exact variational Jacobian come from one pass.
    pub(super) fn newton(
        &self,
        x0: &DVector<f64>,
        setup: &Setup,
        lam: f64,
        jac0: Option<&DMatrix<f64>>,
    ) -> Result<Newton, Fail> {
        let tol = self.set.tolerance;
        let mut x = x0.clone();
        // Adaptive steps: the start pass adapts the mesh, the passes of this solve replay it.
        self.mesh.borrow_mut().frozen = false;
        let jac0 = jac0.filter(|j| j.nrows() == x.len() && j.iter().all(|v| v.is_finite()));
        let (mut f, tip, var_jac) = match jac0 {
            Some(j) => {
                let (f, tip) = self.residual_tip(&x, setup, lam);
                (f, tip, Some((j.clone(), false)))
            }
            None => match self.residual_jac(&x, setup, lam) {
                Some((f, j, tip)) => (f, tip, Some((j, true))),
                None => {
                    let (f, tip) = self.residual_tip(&x, setup, lam);
                    (f, tip, None)
                }
            },
        };
        self.mesh.borrow_mut().frozen = self.set.adaptive.is_some();
        let norm_inf = |v: &DVector<f64>| v.iter().fold(0.0f64, |a, b| a.max(b.abs()));
        if !f[0].is_finite() {
            return Err(Fail::new(
                0,
                f64::NAN,
                "integration failed at the start point",
            ));
        }
        if norm_inf(&f) <= tol {
            let residual = norm_inf(&f);
            let jac = var_jac.map(|(j, _)| j);
            return Ok(Newton {
                x,
                iterations: 0,
                residual,
                jac,
            });
        }
        // Start Broyden from the variational Jacobian; without it, in force control from the
        // rigid transport Jacobian (no extra integrations), else from a difference Jacobian.
        let (mut jac, mut fresh) = if let Some(j) = var_jac {
            j
        } else if setup.unknown.is_empty()
            && setup.contacts.is_empty()
            && tip.iter().all(|v| v.is_finite())
        {
            (self.transport_jacobian(&tip), false)
        } else {
            // (The variational pass already declined at `x`: this is the difference one.)
            (self.jacobian(&x, &f, setup, lam), true)
        };
        for it in 1..=self.set.max_iterations {
            if self.over_budget() {
                return Err(Fail::new(it - 1, norm_inf(&f), self.budget_detail()));
            }
            let Some(dx) = jac.clone().lu().solve(&(-&f)) else {
                if fresh {
                    return Err(Fail::new(it, norm_inf(&f), "singular Jacobian"));
                }
                jac = self.jacobian(&x, &f, setup, lam);
                fresh = true;
                continue;
            };
            match self.line_search(&x, &dx, &f, setup, lam) {
                Some((xn, fnew)) => {
                    let s = &xn - &x;
                    let y = &fnew - &f;
                    let ss = s.norm_squared();
                    if ss > 0.0 {
                        let corr = (y - &jac * &s) * (s.transpose() / ss);
                        jac += corr;
                    }
                    x = xn;
                    f = fnew;
                    fresh = false;
                    let mut r = norm_inf(&f);
                    if r <= tol && self.set.adaptive.is_some() && self.mesh.borrow().worst > 2.0 {
                        // Converged on the frozen mesh, but a step of it misses the tolerance
                        // at this point (by more than the factor 2 allowed for the drift from
                        // where it was adapted): adapt it here and go on on the new mesh.
                        self.mesh.borrow_mut().frozen = false;
                        f = self.residual(&x, setup, lam);
                        self.mesh.borrow_mut().frozen = true;
                        r = norm_inf(&f);
                        if !r.is_finite() {
                            return Err(Fail::new(it, r, "integration failed on the adapted mesh"));
                        }
                    }
                    if r <= tol {
                        return Ok(Newton {
                            x,
                            iterations: it,
                            residual: r,
                            jac: Some(jac),
                        });
                    }
                }
                None => {
                    if fresh {
                        return Err(Fail::new(it, norm_inf(&f), "line search failed"));
                    }
                    jac = self.jacobian(&x, &f, setup, lam);
                    fresh = true;
                }
            }
        }
        Err(Fail::new(
            self.set.max_iterations,
            norm_inf(&f),
            "iteration limit",
        ))
    }

    /// Backtracking line search along `dx` from `x` (residual `f`): the first of 12 halvings
    /// of the step with sufficient decrease of `|F|²` (Armijo, `c = 1e-4`).
    fn line_search(
        &self,
        x: &DVector<f64>,
        dx: &DVector<f64>,
        f: &DVector<f64>,
        setup: &Setup,
        lam: f64,
    ) -> Option<(DVector<f64>, DVector<f64>)> {
        let f2 = f.norm_squared();
        let mut alpha = 1.0;
        for _ in 0..12 {
            let xn = x + dx * alpha;
            let fnew = self.residual(&xn, setup, lam);
            if fnew[0].is_finite() && fnew.norm_squared() <= (1.0 - 1e-4 * alpha) * f2 {
                return Some((xn, fnew));
            }
            alpha *= 0.5;
        }
        None
    }

    /// Newton from `x0` (unless `direct_start` is off); if that fails, load stepping from
    /// zero load. Returns the solution and the number of load steps taken (0: direct).
    pub(super) fn solve_with_continuation(
        &self,
        x0: &DVector<f64>,
        setup: &Setup,
        jac0: Option<&DMatrix<f64>>,
    ) -> Result<(Newton, usize), Fail> {
        let mut total = 0;
        if self.set.direct_start {
            match self.newton(x0, setup, 1.0, jac0) {
                Ok(n) => return Ok((n, 0)),
                Err(e) => {
                    total += e.iterations;
                    if self.over_budget() {
                        return Err(Fail::new(total, e.residual, self.budget_detail()));
                    }
                }
            }
        }
        let mut x = DVector::zeros(x0.len());
        let (mut lam, mut dl) = (0.0f64, 0.25f64);
        let mut steps = 0;
        let mut last = Fail::new(total, f64::NAN, "continuation");
        while lam < 1.0 {
            let l1 = (lam + dl).min(1.0);
            let mut xs = x.clone();
            if self.shape_free_loads() {
                self.balance_guess(&mut xs, setup, l1);
            }
            match self.newton(&xs, setup, l1, None) {
                Ok(mut n) => {
                    total += n.iterations;
                    steps += 1;
                    x = n.x.clone();
                    lam = l1;
                    dl = (dl * 1.5).min(0.5);
                    if lam >= 1.0 {
                        n.iterations = total;
                        return Ok((n, steps));
                    }
                }
                Err(e) => {
                    total += e.iterations;
                    if self.over_budget() {
                        return Err(Fail::new(
                            total,
                            e.residual,
                            format!(
                                "continuation at load factor {lam:.4}: {}",
                                self.budget_detail()
                            ),
                        ));
                    }
                    dl *= 0.5;
                    last = Fail::new(
                        total,
                        e.residual,
                        format!(
                            "continuation stalled at load factor {lam:.4} ({})",
                            e.detail
                        ),
                    );
                    if dl < 1.0 / 512.0 {
                        return Err(last);
                    }
                }
            }
        }
        Err(last)
    }
}
