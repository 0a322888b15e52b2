//! The shape of a converged energy solve: disk frames and backbone samples from the strains,
//! cable paths (slack sections marked), tensions, contacts and the typed warm start.

use super::kinematics::sheared_exp;
use super::newton::Solution;
use super::problem::{Problem, Target};
use super::Energy;
use crate::method::output::cable_paths;
use crate::method::warm::{EnergyWarm, WarmState};
use crate::method::Method;
use crate::shape::{DiskFrame, Shape, SolveReport};
use nalgebra::{Matrix3, Vector3};

impl Energy {
    /// Assemble the [`Shape`] of the solution `sol` of `prob`.
    pub(super) fn build_shape(
        &self,
        prob: &Problem,
        sol: Solution,
        mut notes: Vec<String>,
    ) -> Shape {
        if !sol.contacts.is_empty() {
            notes.push(if self.contact_sensitivity {
                "stable and jacobian: contact curvature −Σ μ ∇²d by central differences of \
                 the exact contact gradients"
                    .into()
            } else {
                "stable and jacobian not computed with pressing contacts \
                 (`--set contact-sensitivity=on`)"
                    .into()
            });
        }
        let (xi, lam) = (&sol.xi[..], &sol.lam[..]);
        let robot = prob.robot;
        let n = robot.sections();
        let ns = self.samples_per_sub_arc.max(1);
        let mut rot = Matrix3::identity();
        let mut pos = Vector3::zeros();
        let mut disks = Vec::with_capacity(n + 1);
        disks.push(DiskFrame {
            s: 0.0,
            position: pos,
            rotation: rot,
        });
        let mut backbone = vec![pos];
        for j in 0..prob.nsub {
            let x = &xi[4 * j..4 * j + 4];
            let g = prob.shear_at(j);
            for q in 1..ns {
                let (_, p) = sheared_exp(x, g, prob.ell[j] * q as f64 / ns as f64);
                backbone.push(pos + rot * p);
            }
            let (r, p) = sheared_exp(x, g, prob.ell[j]);
            pos += rot * p;
            rot *= r;
            backbone.push(pos);
            if let Ok(k) = prob.first.binary_search(&(j + 1)) {
                disks.push(DiskFrame {
                    s: robot.disk_s[k],
                    position: pos,
                    rotation: rot,
                });
            }
        }
        let nc = robot.cables.len();
        let mut len = vec![0.0; nc];
        prob.lengths(xi, &mut len);
        let slack_sections: Vec<Vec<usize>> = (0..nc)
            .map(|c| match prob.targets[c] {
                Target::Length(t) if lam[c] == 0.0 && len[c] < t - self.tolerance => {
                    (1..=robot.cables[c].ends_at).collect()
                }
                _ => vec![],
            })
            .collect();
        let mut cables = cable_paths(robot, &disks, &slack_sections);
        for (c, path) in cables.iter_mut().enumerate() {
            path.tension = match prob.targets[c] {
                Target::Length(_) => Some(lam[c]),
                Target::Tension(t) => Some(t),
                Target::Free => None,
            };
            // The displacement under which this shape is the answer: the path change plus the
            // stretch `T/k − T₀/k` of a compliant cable (a free cable: the path change).
            let stretch = path.tension.map_or(0.0, |t| {
                t * prob.compliance[c] - robot.cables[c].pretension_stretch()
            });
            path.shortening = prob.len0.get(c).map(|l0| l0 - len[c] + stretch);
        }
        let state = WarmState::Energy(EnergyWarm {
            sub_arcs: prob.first.windows(2).map(|w| w[1] - w[0]).collect(),
            length: self.cable_length,
            strains: xi.to_vec(),
            multipliers: lam.to_vec(),
            // Blocks at a shear a warm start could not tell from its own: none with shear.
            hessian: if self.shear { None } else { sol.hessian },
            shear: prob.shear.borrow().clone(),
        });
        Shape {
            method: self.name().into(),
            disks,
            backbone,
            cables,
            contacts: sol.contacts,
            port: None,
            report: SolveReport {
                converged: true,
                iterations: sol.iterations,
                residual: sol.residual,
                solve_time_s: 0.0, // filled in by `Method::solve`
                sections: vec![],
                base_wrench: None,
                notes,
                stable: sol.sensitivity.stable,
                jacobian: sol.sensitivity.jacobian,
                error_estimate: None,
                auto: None,
                unique: None,
                warm: Some(state),
            },
        }
    }
}
