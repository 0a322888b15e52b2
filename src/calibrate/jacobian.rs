//! The Jacobian of the calibration residual (`fit.rs`) in the scaled parameters.
//!
//! **From the solver's sensitivities** (when every row's shape carries a tip Jacobian in the
//! cables' shortenings, as the energy model's do, and every parameter is one of gain, offset,
//! compliance, backlash, `marker.z` with the marker on the tip axis). The measured marker is
//! `s = R_b (p + m_z t) + t_b` (`model/hardware.rs`), so with the reported `∂p/∂δ_c`,
//! `∂t/∂δ_c`: `∂s/∂δ_c = R_b (∂p/∂δ_c + m_z ∂t/∂δ_c)`. Each parameter moves the rows through
//! the cable's shortening `δ_c = g_c u_c − o_c − ½ b_c s_c` (`s_c` its direction of motion) or through its length constraint
//! `L_c − L_c⁰ + δ_c + T₀_c/k_c − λ_c/k_c = 0` (`energy` module docs, "Compliant cables"):
//!
//! ```text
//! ∂s/∂g_c = u_c ∂s/∂δ_c      ∂s/∂o_c = −∂s/∂δ_c      ∂s/∂(1/k_c) = (T₀_c − λ_c) ∂s/∂δ_c
//! ∂s/∂b_c = −½ s_c ∂s/∂δ_c  ∂s/∂m_z = R_b t    ∂s/∂(1/EA) = ℓ_c (T₀_c − λ_c) ∂s/∂δ_c
//! ∂s/∂ω_k = (J_l(ω) e_k) × R_b (p + m_z t)   (R_b = exp([ω]×), ω the base's rotation vector)
//! ```
//!
//! The last line: `exp([ω + ε e_k]×) = exp([ε J_l(ω) e_k]×) exp([ω]×) + O(ε²)` with the left
//! Jacobian of SO(3) `J_l(ω) = I + (1 − cos θ)/θ² [ω]× + (θ − sin θ)/θ³ [ω]×²`, `θ = |ω|`
//! (Barfoot, *State Estimation for Robotics*, 2017, §7.1.5, eqs. 7.86 and 7.91), so a change
//! of `ω_k` turns the marker by the small rotation `ε J_l e_k`. About one axis alone
//! (`ω ∥ e_k`) `J_l e_k = e_k`: the rotation about that axis.
//!
//! (the compliance enters the constraint as a shortening of `(T₀ − λ)/k`, and the implicit
//! function theorem treats both alike). The aligned residual `r_i = s_i − mean_j(s_j − m_j) −
//! m_i` then has `∂r_i = ∂s_i − mean_j ∂s_j`. One pass over the data per Jacobian instead of
//! one per parameter; a unit test checks it against the finite differences below.
//!
//! The capstan friction coefficient (`friction`) and the backbone's curvature stiffening
//! (`stiffening`) have no such formula (they change the equilibrium equations, not a cable's
//! shortening): their columns alone come from finite differences, the others still from the sensitivities (which the energy model
//! also reports with friction, `energy/friction.rs`).
//!
//! **Finite differences** otherwise: `∂r/∂x_k ≈ (r(x + h e_k) − r(x)) / h`, `h = 10⁻⁴` in
//! scaled variables (gain 10⁻⁴, lengths 0.1 µm, compliance 10⁻⁸ m/N: ≥ 10³ times the energy
//! solver's 10⁻¹⁰ m tolerance), each row of the perturbed solve warm-started from that row's
//! solution at `x` (one or two Newton steps); backwards where the forward point fails, then
//! the same with steps 10⁻³ and 10⁻⁵ where both fail.

use super::fit::{Eval, Fitter};
use super::params::{Param, Target};
use crate::error::SolveError;
use crate::model::actuation::Input;
use crate::model::Model;
use crate::numeric::so3::abc;
use crate::shape::Shape;
use nalgebra::{DMatrix, DVector, Vector3};

impl Fitter<'_> {
    /// The residual's Jacobian at `x` (evaluated as `at`), module docs.
    pub(super) fn jacobian(
        &mut self,
        x: &DVector<f64>,
        at: &Eval,
    ) -> Result<DMatrix<f64>, SolveError> {
        match self.sensitivity_jacobian(x, at) {
            Some((mut j, missing)) => {
                // Columns the sensitivities do not give (friction, stiffening): finite
                // differences.
                for k in missing {
                    let col = self.difference_column(x, at, k)?;
                    j.set_column(k, &col);
                }
                Ok(j)
            }
            None => self.difference_jacobian(x, at),
        }
    }

    /// From the rows' tip sensitivities; `None` where the rows carry none, else the matrix
    /// with the columns of the parameters they do not cover (`friction`, `stiffening`) left zero
    /// and listed.
    pub(super) fn sensitivity_jacobian(
        &self,
        x: &DVector<f64>,
        at: &Eval,
    ) -> Option<(DMatrix<f64>, Vec<usize>)> {
        let m = self.model_at(x);
        let n = at.shapes.len();
        let np = self.params.len();
        let mut ds = Vec::with_capacity(n);
        for ((shape, u), dir) in at.shapes.iter().zip(&self.commands).zip(&self.dirs) {
            ds.push(tip_derivatives(&m, &self.params, shape.as_ref()?, u, dir)?);
        }
        let missing: Vec<usize> = (0..np)
            .filter(|&k| {
                matches!(
                    self.params[k].target,
                    Target::Friction(_) | Target::Stiffening
                )
            })
            .collect();
        let mut j = DMatrix::zeros(3 * n, np);
        for k in (0..np).filter(|k| !missing.contains(k)) {
            let mean = ds.iter().map(|d| d[k]).sum::<Vector3<f64>>() / n.max(1) as f64;
            let scale = self.params[k].scale();
            for (i, d) in ds.iter().enumerate() {
                j.fixed_view_mut::<3, 1>(3 * i, k)
                    .copy_from(&((d[k] - mean) * scale));
            }
        }
        Some((j, missing))
    }

    /// Forward differences (backwards where the forward point fails), module docs.
    pub(super) fn difference_jacobian(
        &mut self,
        x: &DVector<f64>,
        at: &Eval,
    ) -> Result<DMatrix<f64>, SolveError> {
        let mut j = DMatrix::zeros(at.r.len(), x.len());
        for k in 0..x.len() {
            let col = self.difference_column(x, at, k)?;
            j.set_column(k, &col);
        }
        Ok(j)
    }

    /// Column `k` by forward differences (backwards where the forward point fails, or leaves
    /// the parameter's range), module docs; where both sides fail, again with the step ×10 and
    /// ÷10 (a row of a nearly degenerate active set — rigid tendons, several taut cables per
    /// segment — can miss the solver's tolerance at one perturbed point and not at another).
    fn difference_column(
        &mut self,
        x: &DVector<f64>,
        at: &Eval,
        k: usize,
    ) -> Result<DVector<f64>, SolveError> {
        for h in [1e-4, 1e-3, 1e-5] {
            for sign in [1.0, -1.0] {
                let mut xp = x.clone();
                xp[k] += sign * h;
                if !self.params[k].admissible(xp[k] * self.params[k].scale()) {
                    continue;
                }
                if let Some(e) = self.eval(&xp, Some(&at.shapes)) {
                    return Ok((&e.r - &at.r) / (sign * h));
                }
            }
        }
        Err(SolveError::InvalidInput {
            field: format!("fit `{}`", self.params[k].name),
            reason: "rows fail to solve on both sides of the current value (finite differences \
                     with steps 1e-4, 1e-3, 1e-5 of its scale)"
                .into(),
        })
    }
}

/// `∂s/∂x_k` (SI parameters) of one row's measured marker (module docs); `None` when the
/// shape has no sensitivities for every cable's shortening, or a parameter is not covered.
fn tip_derivatives(
    model: &Model,
    params: &[Param],
    shape: &Shape,
    u: &[f64],
    dir: &[f64],
) -> Option<Vec<Vector3<f64>>> {
    let hw = &model.hardware;
    if hw.marker.x != 0.0 || hw.marker.y != 0.0 {
        return None;
    }
    let jac = shape.report.jacobian.as_ref()?;
    let nc = model.robot.cables.len();
    let rb = hw.base_matrix();
    let mut dsd: Vec<Option<Vector3<f64>>> = vec![None; nc];
    for (col, (name, input)) in jac.inputs.iter().enumerate() {
        if input != Input::Shortening.name() {
            return None;
        }
        let c = model.robot.cable_index(name)?;
        let dp = Vector3::from(jac.position[col]) + hw.marker.z * Vector3::from(jac.tangent[col]);
        dsd[c] = Some(rb * dp);
    }
    let dsd: Vec<Vector3<f64>> = dsd.into_iter().collect::<Option<_>>()?;
    let sum = |g, f: &dyn Fn(usize) -> Option<f64>| -> Option<Vector3<f64>> {
        Param::cables(g, nc)
            .into_iter()
            .map(|c| Some(dsd[c] * f(c)?))
            .sum()
    };
    params
        .iter()
        .map(|p| match &p.target {
            Target::Gain(g) => sum(g, &|c| Some(u[c])),
            Target::Offset(g) => sum(g, &|_| Some(-1.0)),
            Target::Backlash(g) => sum(g, &|c| Some(-0.5 * dir.get(c).copied().unwrap_or(0.0))),
            Target::Compliance(g) => sum(g, &|c| {
                Some(model.robot.cables[c].pretension - shape.cables[c].tension?)
            }),
            Target::Marker(2) => {
                let tip = shape.disks.last()?;
                Some(rb * tip.rotation.column(2).into_owned())
            }
            Target::AxialCompliance(g) => sum(g, &|c| {
                Some(
                    model.robot.undeformed_chord_length(c)
                        * (model.robot.cables[c].pretension - shape.cables[c].tension?),
                )
            }),
            Target::BaseRotation(k) => {
                let tip = shape.disks.last()?;
                let q = tip.position + hw.marker.z * tip.rotation.column(2).into_owned();
                Some(left_jacobian_column(&hw.base_rotation, *k).cross(&(rb * q)))
            }
            Target::Marker(_) => None,
            // Not from the sensitivities: finite differences (`sensitivity_jacobian`).
            Target::Friction(_) | Target::Stiffening => Some(Vector3::zeros()),
        })
        .collect()
}

/// Column `k` of the left Jacobian of SO(3) at the rotation vector `w` (module docs), with the
/// coefficients of [`abc`] (series near θ = 0, where the closed forms lose digits).
fn left_jacobian_column(w: &Vector3<f64>, k: usize) -> Vector3<f64> {
    let e = Vector3::ith(k, 1.0);
    let (_, b, c) = abc(w.norm_squared());
    let we = w.cross(&e);
    e + b * we + c * w.cross(&we)
}

#[cfg(test)]
mod tests {
    use crate::calibrate::data::{DataOptions, Dataset};
    use crate::calibrate::fit::{FitOptions, Fitter};
    use crate::calibrate::predict::PredictOptions;
    use crate::method::run::SolveRequest;
    use crate::method::{MethodKind, Settings};
    use crate::model::Model;
    use nalgebra::DVector;

    /// The Jacobian from the solver's sensitivities equals finite differences of full solves
    /// (FTDCR v4 train rows, compliant cables, a turned base; every default parameter, backlash,
    /// `base.rz`, and the EA form of the compliance per segment).
    #[test]
    fn sensitivity_jacobian_matches_finite_differences() {
        let root = env!("CARGO_MANIFEST_DIR");
        let mut model =
            Model::from_file(format!("{root}/models/hardware/ftdcr_v4.toml")).expect("v4");
        for (c, cable) in model.robot.cables.iter_mut().enumerate() {
            cable.stiffness = Some(3000.0 + 100.0 * c as f64);
            cable.pretension = 0.2;
        }
        model.hardware.marker.z = 0.01;
        model.hardware.gain[4] = 0.9;
        model.hardware.backlash = vec![3e-4; 9];
        let data = Dataset::from_file(
            format!("{root}/models/hardware/data/v4/tdcr_sysid_20260511-183002_train.csv"),
            &DataOptions::default(),
        )
        .expect("data");
        let idx: Vec<usize> = (0..data.len()).step_by(40).collect();
        let data = data.select(&idx);
        let mut s = Settings::new();
        s.push("sub-arcs", "1");
        let opts = FitOptions::new(PredictOptions {
            request: SolveRequest::new(MethodKind::Energy).with_settings(s),
            chunk: 8,
            progress: crate::progress::ProgressHandle::none(),
        });
        model.hardware.base_rotation.z = 0.1;
        let default = crate::calibrate::params::default_names(&model.robot);
        // The default set with backlash and base.rz; the same with the EA form of compliance;
        // per-cable gains and offsets with the base tilted about all three axes (below).
        let mut sets = vec![default.clone(), default.clone(), default];
        sets[0].extend(["backlash".to_string(), "base.rz".to_string()]);
        sets[2] = [
            "gain.s0t1_servo3",
            "gain.s2t2_servo7",
            "offset.s1t0_servo5",
            "compliance",
            "marker.z",
            "base.rx",
            "base.ry",
            "base.rz",
        ]
        .map(String::from)
        .to_vec();
        sets[1].retain(|n| n != "compliance");
        sets[1].extend(
            [
                "axial-compliance.seg0",
                "axial-compliance.seg1",
                "axial-compliance.seg2",
            ]
            .map(String::from),
        );
        for (i, names) in sets.into_iter().enumerate() {
            if i == 2 {
                // A general rotation vector: `J_l e_k ≠ e_k` for every k.
                model.hardware.base_rotation = nalgebra::Vector3::new(-0.045, 0.02, 0.1);
            }
            let opts = FitOptions {
                params: names,
                ..opts.clone()
            };
            let (mut f, _) = Fitter::new(&model, &data, &opts).expect("fitter");
            let x = DVector::from_iterator(
                f.params.len(),
                f.params.iter().map(|p| p.get(&model) / p.scale()),
            );
            let at = f.eval(&x, None).expect("evaluates");
            let (js, missing) = f.sensitivity_jacobian(&x, &at).expect("sensitivities");
            assert!(missing.is_empty());
            let jd = f.difference_jacobian(&x, &at).expect("differences");
            for k in 0..x.len() {
                let (a, b) = (js.column(k), jd.column(k));
                let err = (a - b).norm() / b.norm().max(1e-12);
                println!("{}: relative difference {err:.2e}", f.params[k].name);
                assert!(err < 1e-3, "{}: {err:e}", f.params[k].name);
            }
        }
    }

    /// The left Jacobian's columns equal central differences of the exponential map:
    /// `∂/∂ε exp([ω + ε e_k]×) exp([ω]×)ᵀ = [J_l e_k]×` (module docs), on both sides of the
    /// small-angle switch.
    #[test]
    fn left_jacobian_matches_differences_of_the_exponential() {
        use crate::numeric::so3::exp_so3;
        use nalgebra::Vector3;
        for w in [
            Vector3::new(-0.045, 0.02, 0.1),
            Vector3::new(1.2, -0.7, 2.0),
            Vector3::new(3e-5, -2e-5, 1e-5),
            Vector3::zeros(),
        ] {
            let r0t = exp_so3(&w).transpose();
            for k in 0..3 {
                let h = 1e-6;
                let e = Vector3::ith(k, h);
                let d = (exp_so3(&(w + e)) - exp_so3(&(w - e))) * r0t / (2.0 * h);
                // The skew part's axial vector.
                let v = 0.5 * crate::numeric::so3::vee_skew(&d);
                let j = super::left_jacobian_column(&w, k);
                assert!((j - v).norm() < 1e-8, "w {w:?} k {k}: {j:?} against {v:?}");
                // Not the identity's column unless ω ∥ e_k (or 0): the check can fail.
                if w.norm() > 0.5 {
                    assert!((j - Vector3::ith(k, 1.0)).norm() > 0.1);
                }
            }
        }
    }
}
