//! Integration base to tip: fixed RK4 steps (or adaptive Dormand–Prince RK45) over each
//! section, the jumps of the internal wrench at the disks (tendon ties, disk weights, tip
//! wrench, kink forces of cables passing a disk), and one shooting pass ([`Problem::shoot`]).

use super::problem::{LoadCase, Problem, Shot, Trace};
use super::variational::Var;
use super::{put3, rot_of, v3, Buf, RodModel, State, E3, MAX_CABLES};
use crate::model::actuation::LengthMeasure;
use crate::numeric::ode::rk4;
use crate::numeric::so3::hat;
use nalgebra::{Matrix3, Matrix6, Vector3, Vector6};

impl Problem<'_> {
    /// Integrate section `sec` with its fixed RK4 steps (and the tangents, if `var`).
    pub(super) fn section(
        &self,
        sec: usize,
        y: &mut State,
        ld: &LoadCase,
        len: &mut Buf,
        trace: &mut Option<&mut Trace>,
        var: &mut Option<&mut Var>,
    ) {
        let (s0, s1) = (self.robot.disk_s[sec - 1], self.robot.disk_s[sec]);
        let nsteps = self.nsteps[sec];
        let h = (s1 - s0) / nsteps as f64;
        for j in 0..nsteps {
            // Each step starts at its own arc length (never drop s0).
            let s = s0 + j as f64 * h;
            match var.as_deref_mut() {
                Some(vr) => self.rk4_t(s, h, y, sec, ld, len, vr),
                None => {
                    // Path lengths are a quadrature beside the state: the same stages, weighed alike.
                    let mut lr = [[0.0; MAX_CABLES]; 4];
                    *y += rk4::step(s, h, *y, |i, si, yi| {
                        self.rucker_webster(si, yi, sec, ld, &mut lr[i])
                    });
                    self.add_rk4_lengths(len, &lr, h);
                }
            }
            if let Some(t) = trace.as_deref_mut() {
                t.backbone.push(v3(y, 0));
            }
        }
    }

    /// `len[c] += h (ṗ₁ + 2ṗ₂ + 2ṗ₃ + ṗ₄)/6` from the four stages' path-length rates `lr`.
    #[inline]
    pub(super) fn add_rk4_lengths(&self, len: &mut Buf, lr: &[Buf; 4], h: f64) {
        for c in 0..self.robot.cables.len() {
            len[c] += rk4::increment(&[lr[0][c], lr[1][c], lr[2][c], lr[3][c]], h);
        }
    }

    /// Rod force and moment (base frame) from the state.
    #[inline]
    pub(super) fn wrench(&self, y: &State) -> (Vector3<f64>, Vector3<f64>) {
        let r = rot_of(y);
        let u = v3(y, 15);
        let n = match self.set.model {
            RodModel::Full => r * self.kse.component_mul(&(v3(y, 12) - E3)),
            RodModel::Kirchhoff => v3(y, 12),
        };
        (n, r * self.kbt.component_mul(&u))
    }

    /// Set the strains (and `n` for Kirchhoff) from a rod wrench.
    #[inline]
    pub(super) fn set_wrench(&self, y: &mut State, n: &Vector3<f64>, m: &Vector3<f64>) {
        let r = rot_of(y);
        match self.set.model {
            RodModel::Full => put3(y, 12, &(E3 + r.tr_mul(n).component_div(&self.kse))),
            RodModel::Kirchhoff => put3(y, 12, n),
        }
        put3(y, 15, &r.tr_mul(m).component_div(&self.kbt));
    }

    /// Integrate base to tip from the base wrench `n0`, `m0` (one shooting pass): the
    /// residual `[n(L⁺), m(L⁺)/L]`, the cable lengths and the tip. The geometry goes to
    /// `trace` (default: the problem's `last`), the tangents to `var` if given.
    pub(super) fn shoot(
        &self,
        n0: &Vector3<f64>,
        m0: &Vector3<f64>,
        ld: &LoadCase,
        trace: Option<&mut Trace>,
        mut var: Option<&mut Var>,
    ) -> Shot {
        let robot = self.robot;
        if self.set.adaptive.is_none() {
            let nd = var.as_deref().map_or(0, |v| v.nd);
            let steps: usize = self.nsteps[1..].iter().sum();
            self.work.set(self.work.get() + 4 * steps * (1 + nd));
        }
        let mut last = self.last.borrow_mut();
        let rec: &mut Trace = match trace {
            Some(t) => t,
            None => &mut last,
        };
        rec.start(n0, m0, ld);
        let mut trace = Some(rec);
        let mut y = State::zeros();
        y.as_mut_slice()[3..12].copy_from_slice(Matrix3::<f64>::identity().as_slice());
        self.set_wrench(&mut y, n0, m0);
        let mut path = [0.0; MAX_CABLES];
        let mut chord = [0.0; MAX_CABLES];
        let mut prev = [Vector3::zeros(); MAX_CABLES];
        for (c, cable) in robot.cables.iter().enumerate() {
            prev[c] = cable.hole(0);
        }
        if let Some(t) = trace.as_deref_mut() {
            t.disks.push((Vector3::zeros(), Matrix3::identity()));
            t.backbone.push(Vector3::zeros());
        }
        let mut h_adapt = self.len_l / (robot.sections() as f64 * 4.0);
        let nsec = robot.sections();
        let bad = Shot::failed();
        let mut touch = Vec::with_capacity(ld.push.len());
        {
            let mut mesh = self.mesh.borrow_mut();
            mesh.cursor = 0;
            mesh.worst = 0.0;
            if !mesh.frozen {
                mesh.ends.clear();
            }
        }
        let mut crossed = Vec::new();
        let mut steps = 0;
        let mut k = 1;
        while k <= nsec {
            if self.set.adaptive.is_some() {
                // Adaptive: integrate to the next disk with a jump, reading the disks crossed
                // on the way from the continuous extension.
                let b = self.stretch_end(k, ld);
                crossed.clear();
                let secs = (k, b);
                let (len, h) = (&mut path, &mut h_adapt);
                if !self.stretch(
                    secs,
                    &mut y,
                    ld,
                    len,
                    h,
                    &mut steps,
                    &mut trace,
                    &mut crossed,
                ) || crossed.len() != b - k
                {
                    return bad;
                }
                for (j, yj) in (k..b).zip(&crossed) {
                    if let Some(t) = trace.as_deref_mut() {
                        t.disks.push((v3(yj, 0), rot_of(yj)));
                    }
                    // No jump at a crossed disk: only the chords move on.
                    self.disk_loads(j, yj, ld, &mut chord, &mut prev);
                }
                k = b;
            } else {
                self.section(k, &mut y, ld, &mut path, &mut trace, &mut var);
            }
            let r = rot_of(&y);
            let p = v3(&y, 0);
            if let Some(vr) = var.as_deref_mut() {
                self.disk_tangents(k, &y, ld, &prev, vr);
            }
            if let Some(t) = trace.as_deref_mut() {
                t.disks.push((p, r));
            }
            let (mut n, mut m) = self.disk_loads(k, &y, ld, &mut chord, &mut prev);
            // Contact forces at this disk (`contact.rs`).
            let Some(pushed) = self.contact_loads(k, (&p, &r), ld, (&mut n, &mut m), &mut touch)
            else {
                return bad;
            };
            let tied_here = robot
                .cables
                .iter()
                .enumerate()
                .any(|(c, cable)| cable.ends_at == k && ld.tau[c] != 0.0);
            let point_load = self.disk_weight.norm() * ld.lam > 0.0;
            if k < nsec && (tied_here || point_load || pushed) {
                // The variational pass is only run where no such jump occurs (`var_ok`).
                debug_assert!(var.is_none());
                match self.kink_forces(k, &y, ld, n, m) {
                    Some((n2, m2)) => (n, m) = (n2, m2),
                    None => return bad,
                }
            }
            self.set_wrench(&mut y, &n, &m);
            if k == nsec {
                let mm = m / self.len_l;
                let resid = Vector6::new(n.x, n.y, n.z, mm.x, mm.y, mm.z);
                let len = match self.set.length {
                    LengthMeasure::Path => path,
                    LengthMeasure::Chord => chord,
                };
                if let Some(t) = trace.as_deref_mut() {
                    t.len.extend_from_slice(&len[..robot.cables.len()]);
                }
                return Shot {
                    resid,
                    len,
                    tip: p,
                    touch,
                };
            }
            k += 1;
        }
        bad
    }

    /// The internal wrench just after disk `k` from the state just before it, with the
    /// point loads there: tie forces of cables ending at `k` (`F = −τ t` at `p + R r`),
    /// the disk weight and, at the tip, the tip wrench. Adds the chords to `chord` and moves
    /// each running cable's last hole `prev` to disk `k`.
    fn disk_loads(
        &self,
        k: usize,
        y: &State,
        ld: &LoadCase,
        chord: &mut Buf,
        prev: &mut [Vector3<f64>; MAX_CABLES],
    ) -> (Vector3<f64>, Vector3<f64>) {
        let robot = self.robot;
        let r = rot_of(y);
        let p = v3(y, 0);
        let (mut n, mut m) = self.wrench(y);
        let v = match self.set.model {
            RodModel::Full => v3(y, 12),
            RodModel::Kirchhoff => E3,
        };
        let u = v3(y, 15);
        self.advance_chords(k, &p, &r, chord, prev);
        for (c, cable) in robot.cables.iter().enumerate() {
            if cable.ends_at < k {
                continue;
            }
            let t = ld.tau[c];
            if cable.ends_at == k && t != 0.0 {
                let rp = self.eval_route(c, robot.disk_s[k], k);
                let pd = u.cross(&rp.r) + rp.dr + v;
                let f = r * pd * (-t / pd.norm());
                n -= f;
                m -= (r * rp.r).cross(&f);
            }
        }
        n -= self.disk_weight * ld.lam;
        if k == robot.sections() {
            n -= self.tip_f * ld.lam;
            m -= self.tip_m * ld.lam;
        }
        (n, m)
    }

    /// Add each running cable's chord to disk `k` (at `p`, `R`) to `chord` and move its last
    /// hole `prev` there.
    pub(super) fn advance_chords(
        &self,
        k: usize,
        p: &Vector3<f64>,
        r: &Matrix3<f64>,
        chord: &mut Buf,
        prev: &mut [Vector3<f64>; MAX_CABLES],
    ) {
        for (c, cable) in self.robot.cables.iter().enumerate() {
            if cable.ends_at >= k {
                let hole = p + r * cable.hole(k);
                chord[c] += (hole - prev[c]).norm();
                prev[c] = hole;
            }
        }
    }

    /// Kink forces of cables passing inner disk `k` where the strains jump (a cable is tied
    /// there, or a point load acts): a passing cable changes direction at its hole,
    /// `t⁻ = (v⁻ + u⁻ × r + r′)/|·| → t⁺`, and, frictionless, pushes the disk with
    /// `F = τ (t⁺ − t⁻)`, a point force the distributed Rucker–Webster loads cannot carry.
    /// `n⁺ = n⁻ − F`, `m⁺ = m⁻ − (R r) × F`, with `t⁺` from the post-jump strains, which
    /// depend on `F`: the wrench after the jump solves `z = g(z)`, `z = (n⁺, m⁺)`.
    ///
    /// Newton on `z − g(z) = 0` with the exact `∂g/∂z` ([`Self::kink_map`]). A plain fixed
    /// point `z ← g(z)` contracts only by about `Σ τ r² / EI` (the cables' kink moment per unit
    /// bending strain) and diverges once the passing cables pull harder than that: the FTDCR
    /// v4 rod with 20–40 N balanced tendon pulls reached it, its passes failed
    /// and Newton's line searches with them. `(n_base, m_base)`: the wrench after the other
    /// point loads; `None` if Newton does not settle.
    fn kink_forces(
        &self,
        k: usize,
        y: &State,
        ld: &LoadCase,
        n_base: Vector3<f64>,
        m_base: Vector3<f64>,
    ) -> Option<(Vector3<f64>, Vector3<f64>)> {
        let l = self.len_l;
        let (mut n, mut m) = (n_base, m_base);
        for _ in 0..50 {
            let (gn, gm, dg) = self.kink_map(k, y, ld, &n, &m, n_base, m_base);
            // Unknowns scaled as (n, m/L) so both blocks are in newtons.
            let mut a = Matrix6::identity();
            let mut rhs = Vector6::zeros();
            for i in 0..3 {
                rhs[i] = gn[i] - n[i];
                rhs[3 + i] = (gm[i] - m[i]) / l;
                for j in 0..3 {
                    a[(i, j)] -= dg[(i, j)];
                    a[(i, 3 + j)] -= dg[(i, 3 + j)] * l;
                    a[(3 + i, j)] -= dg[(3 + i, j)] / l;
                    a[(3 + i, 3 + j)] -= dg[(3 + i, 3 + j)];
                }
            }
            let d = a.lu().solve(&rhs)?;
            let dn = Vector3::new(d[0], d[1], d[2]);
            let dm = Vector3::new(d[3], d[4], d[5]) * l;
            n += dn;
            m += dm;
            if !(n.iter().chain(m.iter()).all(|v| v.is_finite())) {
                return None;
            }
            let change = dn.norm() + dm.norm() / l;
            if change <= 1e-14 * (1.0 + n.norm() + m.norm() / l) {
                return Some((n, m));
            }
        }
        None
    }

    /// The map `g(z)` of [`Self::kink_forces`] at `z = (n, m)` and its Jacobian `∂g/∂z`
    /// (6×6, columns `(n, m)`): with `v⁺ = e3 + Kse⁻¹ Rᵀ n` (Kirchhoff: `e3`),
    /// `u⁺ = Kbt⁻¹ Rᵀ m`, `t⁺ = u⁺ × r + r′ + v⁺`, `e = t⁺/|t⁺|`, `∂e = (I − e eᵀ)/|t⁺| ∂t⁺`,
    /// each passing cable's `F = τ R (e − e⁻)` gives `∂F/∂n = τ R P Kse⁻¹ Rᵀ`,
    /// `∂F/∂m = −τ R P r̂ Kbt⁻¹ Rᵀ` (`P = (I − e eᵀ)/|t⁺|`), and `g = (n_base − Σ F,
    /// m_base − Σ (R r) × F)`.
    #[allow(clippy::too_many_arguments)]
    fn kink_map(
        &self,
        k: usize,
        y: &State,
        ld: &LoadCase,
        n: &Vector3<f64>,
        m: &Vector3<f64>,
        n_base: Vector3<f64>,
        m_base: Vector3<f64>,
    ) -> (Vector3<f64>, Vector3<f64>, Matrix6<f64>) {
        let robot = self.robot;
        let r = rot_of(y);
        let v = match self.set.model {
            RodModel::Full => v3(y, 12),
            RodModel::Kirchhoff => E3,
        };
        let u = v3(y, 15);
        let mut yy = *y;
        self.set_wrench(&mut yy, n, m);
        let (vp, dvdn) = match self.set.model {
            RodModel::Full => (
                v3(&yy, 12),
                Matrix3::from_diagonal(&self.kse.map(|x| 1.0 / x)) * r.transpose(),
            ),
            RodModel::Kirchhoff => (E3, Matrix3::zeros()),
        };
        let up = v3(&yy, 15);
        let dudm = Matrix3::from_diagonal(&self.kbt.map(|x| 1.0 / x)) * r.transpose();
        let (mut gn, mut gm) = (n_base, m_base);
        let mut dg = Matrix6::zeros();
        for (c, cable) in robot.cables.iter().enumerate() {
            let t = ld.tau[c];
            if cable.ends_at <= k || t == 0.0 {
                continue;
            }
            let rm = self.routes[c].eval(robot.disk_s[k], k - 1);
            let rpl = self.routes[c].eval(robot.disk_s[k], k);
            let tm = u.cross(&rm.r) + rm.dr + v;
            let tp = up.cross(&rpl.r) + rpl.dr + vp;
            let np = tp.norm();
            let e = tp / np;
            let f = r * (e - tm / tm.norm()) * t;
            let arm = hat(&(r * rm.r));
            gn -= f;
            gm -= arm * f;
            let rp = r * (Matrix3::identity() - e * e.transpose()) * (t / np);
            let dfdn = rp * dvdn;
            let dfdm = -rp * hat(&rpl.r) * dudm;
            for (col, dfd) in [(0, dfdn), (3, dfdm)] {
                let dm = arm * dfd;
                for i in 0..3 {
                    for j in 0..3 {
                        dg[(i, col + j)] -= dfd[(i, j)];
                        dg[(3 + i, col + j)] -= dm[(i, j)];
                    }
                }
            }
        }
        (gn, gm, dg)
    }
}
