//! Closed-form first and second derivatives of the section problem (analytic
//! derivatives in place of dual numbers, for speed).
//!
//! Every function of the section problem is a function `φ(v)` of one 3-vector `v(δ)` of the
//! perturbation `δ = (δp, δω)` (pose `p + δp`, `Q exp([δω]×)`):
//!
//! - `v = p + δp` (the tangent term, the backbone length),
//! - `v = Q exp([δω]×) h` (a coupler term),
//! - `v = p + δp + Q exp([δω]×) h − h′` (a cable chord).
//!
//! With `γ = ∇φ(v)`, `Γ = ∇²φ(v)` and the Jacobian `J = [A | B]` of `v` (A = I or 0,
//! `B = −Q [h]×` or 0), the chain rule gives `∇_δ φ = Jᵀ γ` and
//! `∇²_δ φ = Jᵀ Γ J + Σ_r γ_r ∇²v_r`, where the only second derivative of `v` is the rotation's,
//! `Σ_r γ_r ∂²(Q exp([ω]×) h)_r/∂ω_i∂ω_j = ½ ((Qᵀγ)_i h_j + (Qᵀγ)_j h_i) − (γ·Q h) δ_ij`
//! (from `exp([ω]×) h = h + ω × h + ½ ω × (ω × h) + O(|ω|³)`, see
//! [`SectionScalar::rotated`](super::problem::SectionScalar)).
//!
//! The three `φ` used, with `r = |v|`:
//!
//! - the norm `|v|`: `γ = v/r`, `Γ = (I − v vᵀ/r²)/r`;
//! - the component ratio `e·v/r` of a zero face: `γ = e/r − (e·v) v/r³`,
//!   `Γ = −(e vᵀ + v eᵀ)/r³ − (e·v)(I/r³ − 3 v vᵀ/r⁵)`;
//! - the angle `θ = atan2(s, a)` to a unit direction `u`, with `a = u·v`, `w = v − a u`,
//!   `s = |w|`, `ŵ = w/s`, `P = I − u uᵀ`: `γ = (a ŵ − s u)/r²` and
//!   `Γ = 2as/r⁴ u uᵀ + (s² − a²)/r⁴ (u ŵᵀ + ŵ uᵀ) + a (P − ŵ ŵᵀ)/(s r²) − 2as/r⁴ ŵ ŵᵀ`
//!   (differentiate `∂θ/∂a = −s/r²`, `∂θ/∂w = a ŵ/r²`); its square `θ²` has
//!   `2θγ` and `2γγᵀ + 2θΓ`.
//!
//! The gauge equation and a squared angle on its small-angle branch keep the dual-number path ([`SectionData::eval`]), which the test below
//! also checks this one against.

use super::problem::SectionData;
use super::problem::{squared_angle, Pose};
use crate::numeric::ad::{Real, D2, V3};
use crate::numeric::so3::hat;
use nalgebra::{Matrix3, Vector3};

/// `φ(v)`, `∇φ`, `∇²φ` at one `v`.
struct Local {
    v: f64,
    g: Vector3<f64>,
    h: Matrix3<f64>,
}

fn norm(v: &Vector3<f64>) -> Local {
    let r = v.norm();
    Local {
        v: r,
        g: v / r,
        h: (Matrix3::identity() - v * v.transpose() / (r * r)) / r,
    }
}

fn ratio(e: &Vector3<f64>, v: &Vector3<f64>) -> Local {
    let r = v.norm();
    let (r3, ev) = (r * r * r, e.dot(v));
    Local {
        v: ev / r,
        g: e / r - v * (ev / r3),
        h: -(e * v.transpose() + v * e.transpose()) / r3
            - (Matrix3::identity() / r3 - v * v.transpose() * (3.0 / (r3 * r * r))) * ev,
    }
}

fn angle(u: &Vector3<f64>, v: &Vector3<f64>) -> Local {
    let a = u.dot(v);
    let s = u.cross(v).norm();
    let w = v - u * a;
    let wh = w / w.norm();
    let r2 = a * a + s * s;
    let r4 = r2 * r2;
    let uu = u * u.transpose();
    let ww = wh * wh.transpose();
    Local {
        v: s.atan2(a),
        g: (wh * a - u * s) / r2,
        h: uu * (2.0 * a * s / r4)
            + (u * wh.transpose() + wh * u.transpose()) * ((s * s - a * a) / r4)
            + (Matrix3::identity() - uu - ww) * (a / (s * r2))
            - ww * (2.0 * a * s / r4),
    }
}

fn squared(l: Local) -> Local {
    Local {
        v: l.v * l.v,
        g: l.g * (2.0 * l.v),
        h: l.g * l.g.transpose() * 2.0 + l.h * (2.0 * l.v),
    }
}

/// Lift `φ(v)` to δ: `has_p` when `v` contains `p + δp`, `h` when it contains `Q exp([δω]×) h`.
fn lift(q: &Matrix3<f64>, has_p: bool, h: Option<&Vector3<f64>>, l: &Local) -> D2<6> {
    let mut d = D2::<6>::cst(l.v);
    if has_p {
        for i in 0..3 {
            d.g[i] = l.g[i];
            for j in 0..3 {
                d.h[i][j] = l.h[(i, j)];
            }
        }
    }
    if let Some(h) = h {
        let b = -(q * hat(h));
        let gw = b.transpose() * l.g;
        let qg = q.transpose() * l.g;
        let gqh = l.g.dot(&(q * h));
        let hb = l.h * b;
        let ww = b.transpose() * hb;
        for i in 0..3 {
            d.g[3 + i] = gw[i];
            for j in 0..3 {
                let mut x = ww[(i, j)] + 0.5 * (qg[i] * h[j] + qg[j] * h[i]);
                if i == j {
                    x -= gqh;
                }
                d.h[3 + i][3 + j] = x;
                if has_p {
                    d.h[j][3 + i] = hb[(j, i)];
                    d.h[3 + i][j] = hb[(j, i)];
                }
            }
        }
    }
    d
}

/// The three equations `Q = I` of a face with every coupler zero (see [`SectionData::eval`]):
/// the axial part of `Q exp([δω]×)`, `½ (c₁_z − c₂_y, c₂_x − c₀_z, c₀_y − c₁_x)` with
/// `c_k = Q exp([δω]×) e_k`; each component is linear in `c_k` (`γ` a unit vector, `Γ = 0`).
fn axial(q: &Matrix3<f64>) -> [D2<6>; 3] {
    let component = |k: usize, r: usize| {
        let e = Vector3::ith(k, 1.0);
        let local = Local {
            v: (q * e)[r],
            g: Vector3::ith(r, 1.0),
            h: Matrix3::zeros(),
        };
        lift(q, false, Some(&e), &local)
    };
    let half = |a: D2<6>, b: D2<6>| (a + b * -1.0) * 0.5;
    [
        half(component(1, 2), component(2, 1)),
        half(component(2, 0), component(0, 2)),
        half(component(0, 1), component(1, 0)),
    ]
}

impl SectionData {
    /// [`SectionData::eval`] in [`D2`], from the closed forms above: the constraints go into
    /// `cons` (cleared first; Newton reuses one buffer), the objective is returned.
    pub(super) fn eval_d2(
        &self,
        pose: &Pose,
        face: u32,
        active: &[usize],
        squared_obj: bool,
        cons: &mut Vec<D2<6>>,
    ) -> D2<6> {
        let q = &pose.q;
        let fixed_rotation = self.rotation_fixed(face);
        let small_squared = squared_obj
            && self.terms.iter().enumerate().any(|(t, term)| {
                let v = if term.tangent { pose.p } else { q * term.dir };
                let (u, v) = (V3::<f64>::cst(&term.dir), V3::<f64>::cst(&v));
                face & (1 << t) == 0 && squared_angle(&u, &v) < 1e-12
            });
        if self.gauge.is_some() || small_squared {
            return self.eval::<D2<6>>(pose, face, active, squared_obj, cons);
        }
        let mut obj = D2::<6>::cst(0.0);
        cons.clear();
        cons.push(lift(q, true, None, &norm(&pose.p)) + (-self.l0));
        for &j in active {
            let k = &self.cons[j];
            let chord = pose.p + q * k.h - k.h_prev;
            cons.push(lift(q, true, Some(&k.h), &norm(&chord)) + (-k.length));
        }
        for (t, term) in self.terms.iter().enumerate() {
            if fixed_rotation && !term.tangent {
                if t == 1 {
                    cons.extend(axial(q));
                }
                continue;
            }
            let (v, h) = if term.tangent {
                (pose.p, None)
            } else {
                (q * term.dir, Some(&term.dir))
            };
            if face & (1 << t) != 0 {
                cons.push(lift(q, term.tangent, h, &ratio(&term.e1, &v)));
                cons.push(lift(q, term.tangent, h, &ratio(&term.e2, &v)));
            } else {
                let a = angle(&term.dir, &v);
                let a = if squared_obj { squared(a) } else { a };
                obj = obj + lift(q, term.tangent, h, &a) * term.weight;
            }
        }
        obj
    }
}

#[cfg(test)]
mod tests {
    use crate::model::Model;
    use crate::numeric::so3::exp_so3;
    use nalgebra::Vector3;

    use super::super::problem::{Pose, SectionData};

    /// The closed forms equal the dual-number derivatives on every face of a 3-cable section
    /// (including the faces that fix the rotation), both objectives, at poses off the kinks.
    #[test]
    fn closed_forms_equal_dual_numbers() {
        let text = "name = \"t\"\n[robot]\nsections = 3\nsection_length = 0.02\ndisk_radius = 0.012\ndisk_thickness = 0.002\nbackbone = { youngs_modulus = 1.1e9, poisson_ratio = 0.3, diameter = 0.003 }\n\
            [[cables]]\nname = \"A\"\nradius = 0.008\nangles = { helix = { start = 0.0, per_disk = 0.3 } }\nshorten_percent = 3.0\n\
            [[cables]]\nname = \"B\"\nradius = 0.007\nangles = { straight = 2.0 }\nshorten_percent = 2.0\n\
            [[cables]]\nname = \"C\"\nradius = 0.006\nangles = { straight = 4.0 }\nshorten_percent = 1.0\n";
        let m = Model::from_toml_str(text).expect("model");
        let frac: Vec<Option<f64>> = (0..3)
            .map(|c| m.actuation.shortening_fraction(&m.robot, c))
            .collect();
        let data = SectionData::new(&m.robot, &frac, 2).expect("section");
        let pose = Pose {
            p: Vector3::new(0.002, -0.001, 0.0199).normalize() * 0.0201,
            q: exp_so3(&Vector3::new(0.05, -0.08, 0.03)),
        };
        let active = [0usize, 2];
        for squared in [false, true] {
            for face in 0..(1u32 << data.terms.len()) {
                let mut ca = vec![];
                let fa = data.eval_d2(&pose, face, &active, squared, &mut ca);
                let mut cg = vec![];
                let fg =
                    data.eval::<crate::numeric::ad::D2<6>>(&pose, face, &active, squared, &mut cg);
                assert_eq!(ca.len(), cg.len());
                for (a, g) in std::iter::once((&fa, &fg)).chain(ca.iter().zip(&cg)) {
                    let scale = 1.0 + g.v.abs();
                    assert!((a.v - g.v).abs() < 1e-14 * scale, "value {} {}", a.v, g.v);
                    for i in 0..6 {
                        let gs = 1.0 + g.g.iter().fold(0.0f64, |m, x| m.max(x.abs()));
                        assert!((a.g[i] - g.g[i]).abs() < 1e-12 * gs, "grad {i} face {face}");
                        let hs = 1.0 + g.h.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
                        for j in 0..6 {
                            assert!(
                                (a.h[i][j] - g.h[i][j]).abs() < 1e-11 * hs,
                                "hess {i} {j} face {face} squared {squared}: {} vs {}",
                                a.h[i][j],
                                g.h[i][j]
                            );
                        }
                    }
                }
            }
        }
    }
}
