//! Adaptive integration (`--adaptive TOL`): Dormand–Prince 5(4) with error control over
//! *stretches* — runs of sections between disks where the internal wrench jumps (a cable
//! ends, a point load acts, the tip). Inside a stretch the right-hand side is continuous (the
//! routes are C² across disks), so a step may cross disks; the disks it crosses are read
//! from the method's continuous extension (Shampine 1986, as in Hairer's `dopri5`).
//!
//! Why stretches: with every disk a step boundary, one step per section is the least the
//! integrator can take, and on the paper cases one DP45 step per section is already more
//! accurate than any tolerance above ~1e-7, so `TOL` from 1e-2 to 1e-7 gave the same answer
//! before. Over stretches the steps follow the tolerance: the error (scaled max-norm
//! of the local error estimate: positions / L, R, strains, curvatures · L) is kept below
//! `TOL` per step, and the tip error falls with it (test
//! `adaptive_tolerance_controls_the_tip_error`).

use super::problem::{LoadCase, Problem, Trace};
use super::{v3, Buf, RodModel, State, MAX_CABLES};

/// Dense-output coefficients of Dormand–Prince 5(4) (Shampine 1986; Hairer's `dopri5`).
const D: [f64; 7] = [
    -12715105075.0 / 11282082432.0,
    0.0,
    87487479700.0 / 32700410799.0,
    -10690763975.0 / 1880347072.0,
    701980252875.0 / 199316789632.0,
    -1453857185.0 / 822651844.0,
    69997945.0 / 29380423.0,
];

/// Steps allowed over the whole rod in one pass before it is given up (a budget, not a
/// resolution: the paper cases need well under 100 at `TOL = 1e-10`).
pub(super) const MAX_ADAPTIVE_STEPS: usize = 100_000;

/// One Dormand–Prince step.
pub(super) struct Step {
    y: State,
    len: Buf,
    err: f64,
    k: [State; 7],
}

impl Step {
    /// The continuous extension at `θ ∈ [0, 1]` of the step of size `h` from `y0`
    /// (fourth order; Hairer's `contd5`).
    fn dense(&self, y0: &State, h: f64, theta: f64) -> State {
        let k = &self.k;
        let ydiff = self.y - y0;
        let bspl = k[0] * h - ydiff;
        let c4 = ydiff - k[6] * h - bspl;
        let mut c5 = State::zeros();
        for (ki, di) in k.iter().zip(D) {
            if di != 0.0 {
                c5 += ki * (h * di);
            }
        }
        let t1 = 1.0 - theta;
        y0 + (ydiff + (bspl + (c4 + c5 * t1) * theta) * t1) * theta
    }
}

impl Problem<'_> {
    /// The last disk of the stretch that starts with section `k`: the first disk `j ≥ k`
    /// where a cable ends, a point load acts, or the rod ends.
    pub(super) fn stretch_end(&self, k: usize, ld: &LoadCase) -> usize {
        let nsec = self.robot.sections();
        let point_load = self.disk_weight.norm() * ld.lam > 0.0;
        (k..nsec)
            .find(|&j| {
                point_load
                    || self.robot.cables.iter().any(|c| c.ends_at == j)
                    || ld.push.iter().any(|q| q.touch.disk == j)
            })
            .unwrap_or(nsec)
    }

    /// The section (within `secs`) that arc length `s` falls in (a disk belongs to the
    /// section it ends).
    #[inline]
    fn section_at(&self, s: f64, secs: (usize, usize)) -> usize {
        let ds = &self.robot.disk_s;
        (secs.0..secs.1).find(|&j| s <= ds[j]).unwrap_or(secs.1)
    }

    /// Integrate the stretch of sections `secs.0..=secs.1` adaptively. The states at the
    /// disks it crosses (`secs.0..secs.1`) are pushed to `crossed`; the backbone gets the
    /// step ends and the crossed disks in order. `steps` counts accepted and rejected
    /// steps against [`MAX_ADAPTIVE_STEPS`]; `false` if that budget is spent or the state
    /// stops being finite.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn stretch(
        &self,
        secs: (usize, usize),
        y: &mut State,
        ld: &LoadCase,
        len: &mut Buf,
        h_adapt: &mut f64,
        steps: &mut usize,
        trace: &mut Option<&mut Trace>,
        crossed: &mut Vec<State>,
    ) -> bool {
        let Some(tol) = self.set.adaptive else {
            return false;
        };
        let ds = &self.robot.disk_s;
        let (s0, s1) = (ds[secs.0 - 1], ds[secs.1]);
        let mut next = secs.0; // next disk to cross
        let mut s = s0;
        let mut mesh = self.mesh.borrow_mut();
        while s < s1 - 1e-15 * s1.abs().max(1.0) {
            *steps += 1;
            if *steps > MAX_ADAPTIVE_STEPS || !h_adapt.is_finite() {
                return false;
            }
            let h = if mesh.frozen {
                match mesh.ends.get(mesh.cursor) {
                    Some(&end) if end > s && end <= s1 => end - s,
                    _ => return false,
                }
            } else {
                h_adapt.min(s1 - s)
            };
            self.work.set(self.work.get() + 7);
            let step = self.dp45(s, h, y, secs, ld, len);
            let e = step.err / tol;
            mesh.worst = mesh.worst.max(e);
            if mesh.frozen || e <= 1.0 || h < 1e-12 * self.len_l {
                let s_new = if h == s1 - s { s1 } else { s + h };
                if mesh.frozen {
                    mesh.cursor += 1;
                } else {
                    mesh.ends.push(s_new);
                }
                while next < secs.1 && ds[next] <= s_new {
                    let yd = step.dense(y, h, (ds[next] - s) / h);
                    if let Some(t) = trace.as_deref_mut() {
                        t.backbone.push(v3(&yd, 0));
                    }
                    crossed.push(yd);
                    next += 1;
                }
                *y = step.y;
                *len = step.len;
                s = s_new;
                if let Some(t) = trace.as_deref_mut() {
                    t.backbone.push(v3(y, 0));
                }
            }
            let fac = if e == 0.0 {
                5.0
            } else {
                (0.9 * e.powf(-0.2)).clamp(0.2, 5.0)
            };
            *h_adapt = h * fac;
            if !e.is_finite() {
                return false;
            }
        }
        true
    }

    /// Scaled max-norm of a state error (for the adaptive integrator).
    fn err_norm(&self, e: &State) -> f64 {
        let l = self.len_l;
        let wn = match self.set.model {
            RodModel::Full => 1.0,
            RodModel::Kirchhoff => 1.0 / self.fscale,
        };
        let mut m = 0.0f64;
        for i in 0..18 {
            let w = match i {
                0..=2 => 1.0 / l,
                3..=11 => 1.0,
                12..=14 => wn,
                _ => l,
            };
            m = m.max((e[i] * w).abs());
        }
        m
    }

    /// One Dormand–Prince 5(4) step from `s` (Hairer, Nørsett & Wanner, *Solving ODEs I*,
    /// §II.5): the fifth-order state, lengths, scaled error estimate, and the seven stage
    /// slopes (for the dense output). The step may cross disks of the stretch `secs =
    /// (first, last)` section; each stage reads the route of the section it falls in.
    fn dp45(
        &self,
        s: f64,
        h: f64,
        y: &State,
        secs: (usize, usize),
        ld: &LoadCase,
        len: &Buf,
    ) -> Step {
        use crate::numeric::ode::dormand_prince::{A, B4, B5, C};
        let mut k = [State::zeros(); 7];
        let mut lr = [[0.0; MAX_CABLES]; 7];
        for i in 0..7 {
            let mut yi = *y;
            for j in 0..i {
                if A[i][j] != 0.0 {
                    yi += k[j] * (h * A[i][j]);
                }
            }
            let si = s + C[i] * h;
            k[i] = self.rucker_webster(si, &yi, self.section_at(si, secs), ld, &mut lr[i]);
        }
        let mut yn = *y;
        let mut e = State::zeros();
        let mut ln = *len;
        for i in 0..7 {
            yn += k[i] * (h * B5[i]);
            e += k[i] * (h * (B5[i] - B4[i]));
            for c in 0..self.robot.cables.len() {
                ln[c] += h * B5[i] * lr[i][c];
            }
        }
        Step {
            y: yn,
            len: ln,
            err: self.err_norm(&e),
            k,
        }
    }
}
