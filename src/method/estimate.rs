//! How far an answer is from the converged reference: an estimate of the tip's distance from
//! the converged Cosserat rod (shear and extension, converged resolution) driven by the same
//! inputs, in two parts.
//!
//! * **Discretization** (the method against itself converged): Richardson extrapolation from
//!   one extra solve at half the resolution (or, at the coarsest rung, twice it), with the
//!   method's order measured, not assumed (`tests/methods/estimate/`): `energy`'s constant-strain
//!   sub-arcs converge at order 2 in the sub-arc length, the rods' fixed-step RK4 at order 4
//!   in the step. With resolutions `h` and `r·h` of tips `x_h`, `x_rh`, the error of the fine
//!   one is `|x_h − x_rh| / (r^p − 1)` and that of the coarse one `|x_h − x_rh| · r^p /
//!   (r^p − 1)`. The adaptive rod's error follows its tolerance (error ∝ tol, measured), so its
//!   companion runs at 16× the tolerance; as it often takes the very same steps there, its
//!   part is at least `tol ×` the robot's length.
//! * **Model** (the method's model against the Cosserat rod's), where known: the strains a
//!   model leaves out, to first order. With the backbone's internal force `n(s)` — the tip
//!   force, the weight beyond `s`, and every cable's pull `−T t` along its chord `t` (a cut
//!   through backbone and cables carries the loads beyond it, so the backbone carries the
//!   cables' tensions back) — the rod's shear strain `v⊥ = n⊥ / GA` and axial strain `n·t /
//!   EA` move the tip by `∫ R K⁻¹ Rᵀ n ds`, summed section by section. `energy` models the
//!   extension but no shear (the shear part); `constant-curvature` neither (both parts; in
//!   its regime the force is axial); `energy` with `shear = on` models both (0: the rod's
//!   continuum, `energy/shear.rs`); `cosserat` is the reference (0). `kirchhoff`'s error is
//!   not first order in the strains it leaves out (3–15× that estimate on random robots), so
//!   its model part is the Cosserat rod's distance at the companion resolution. The geometric methods are not a
//!   mechanical model, and with obstacles, capstan friction or curvature stiffening the rod
//!   has no counterpart: the model part is then unknown (`None`), and so is the bound.
//!
//! `energy`'s discretization part can also be read from the answer alone, without the extra
//! solve ([`a_priori_discretization`], `energy/local_error.rs`: the strain each constant-strain
//! sub-arc leaves out, from the cables' pull and the loads along it); `auto` uses it.
//!
//! Each part is multiplied by a safety factor calibrated on seeded random robots against the
//! converged rod ([`SAFETY`]; the calibration and how often the bound held are in
//! `docs/guide/methods.md`). The estimate costs one extra solve (about half the answer's own
//! cost at the coarser rung) and is computed only when asked for
//! ([`SolveRequest::estimate`](super::run::SolveRequest)).

use super::{MethodKind, Settings};
use crate::error::SolveError;
use crate::model::actuation::Actuation;
use crate::model::robot::Robot;
use crate::model::scene::Scene;
use crate::shape::Shape;
use nalgebra::{Matrix3, Vector3};
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// Order of `energy`'s sub-arcs (tip error ∝ (section length / sub-arcs)^2), measured.
pub const SUB_ARC_ORDER: f64 = 2.0;
/// Order of the rods' fixed-step RK4 (tip error ∝ step^4), measured.
pub const RK4_ORDER: f64 = 4.0;
/// Order of the adaptive rod's tip error in its tolerance, measured.
pub const ADAPTIVE_ORDER: f64 = 1.0;
/// Ratio of the adaptive companion's tolerance.
const ADAPTIVE_RATIO: f64 = 16.0;
/// Safety factor on each part, calibrated on seeded random robots (module docs).
pub const SAFETY: f64 = 2.0;

/// An estimate of a shape's tip distance from the converged reference rod.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ErrorEstimate {
    /// The estimated bound: discretization + model \[m\]; `None` when the model part is unknown.
    pub bound_m: Option<f64>,
    /// The discretization part \[m\] (0 for a closed form or a section solver).
    pub discretization_m: f64,
    /// The model part \[m\]; `None` when the rod has no counterpart (see the note).
    pub model_m: Option<f64>,
    /// The extra solve the discretization part was measured against (`sub-arcs=2`), `the
    /// answer's own strains` (`energy`'s a-priori part, [`a_priori_discretization`]), or empty.
    pub against: String,
    /// The order of convergence used (0 without an extra solve).
    pub order: f64,
    /// Wall time of the estimate (the extra solve and the model part) \[s\].
    pub cost_s: f64,
    /// Why a part is unknown, or empty.
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub note: String,
}

/// A method's resolution, as the estimator reads it from its settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Resolution {
    /// `energy`: constant-strain sub-arcs per section.
    SubArcs(usize),
    /// The rods: fixed RK4 steps per section (before bend refinement).
    Rk4(usize),
    /// The rods: adaptive Dormand–Prince with this tolerance.
    Adaptive(f64),
    /// No discretization of its own model (a closed form, a section solver).
    Exact,
}

/// The resolution of `kind` configured by `settings` (registry defaults where not set).
pub fn resolution(kind: MethodKind, settings: &Settings) -> Resolution {
    let value = |name: &str| -> Option<String> {
        settings
            .get(name)
            .map(str::to_string)
            .or_else(|| kind.setting(name).ok().map(|s| s.default.to_string()))
    };
    match kind {
        MethodKind::Energy => Resolution::SubArcs(
            value("sub-arcs")
                .and_then(|v| v.trim().parse().ok())
                .unwrap_or(4),
        ),
        MethodKind::Cosserat | MethodKind::Kirchhoff => {
            match value("adaptive").and_then(|v| v.trim().parse::<f64>().ok()) {
                Some(tol) => Resolution::Adaptive(tol),
                None => Resolution::Rk4(
                    value("rk4-steps")
                        .and_then(|v| v.trim().parse().ok())
                        .unwrap_or(3),
                ),
            }
        }
        _ => Resolution::Exact,
    }
}

/// The companion solve of a resolution: the setting to change, its value, the refinement
/// ratio `r`, whether the companion is the coarser one, and the order `p`.
struct Companion {
    name: &'static str,
    value: String,
    ratio: f64,
    coarser: bool,
    order: f64,
}

fn companion(res: Resolution) -> Option<Companion> {
    // One rung down: close enough to stay in the asymptotic range (3 RK4 steps against 1 is
    // not), cheap enough to cost less than the answer.
    let halve = |name: &'static str, n: usize, order: f64| {
        let (m, coarser) = match n {
            1 => (2, false),
            2 => (1, true),
            n if n < 6 => (n - 1, true),
            n => (n / 2, true),
        };
        Companion {
            name,
            value: m.to_string(),
            ratio: n.max(m) as f64 / n.min(m) as f64,
            coarser,
            order,
        }
    };
    match res {
        Resolution::SubArcs(k) => Some(halve("sub-arcs", k, SUB_ARC_ORDER)),
        Resolution::Rk4(n) => Some(halve("rk4-steps", n, RK4_ORDER)),
        Resolution::Adaptive(tol) => {
            let coarser = tol * ADAPTIVE_RATIO <= 1.0;
            let other = if coarser {
                tol * ADAPTIVE_RATIO
            } else {
                tol / ADAPTIVE_RATIO
            };
            Some(Companion {
                name: "adaptive",
                value: format!("{other:e}"),
                ratio: ADAPTIVE_RATIO,
                coarser,
                order: ADAPTIVE_ORDER,
            })
        }
        Resolution::Exact => None,
    }
}

/// Richardson: the error of a solve from its distance `d` to the companion at ratio `r` and
/// order `p` (`coarser`: the companion is the coarse one, so the solve is the fine one).
pub fn richardson(d: f64, ratio: f64, order: f64, coarser: bool) -> f64 {
    let g = ratio.powf(order);
    if coarser {
        d / (g - 1.0)
    } else {
        d * g / (g - 1.0)
    }
}

/// Calibration factor of `energy`'s a-priori discretization part
/// ([`a_priori_discretization`]), before [`SAFETY`]: the true discretization error (against 32
/// sub-arcs) over the leading term of `energy/local_error.rs` was at most 0.998 on 800
/// answers (random robots 0–199 at 1–4 sub-arcs), 0.994 on 800 more (seeds 1000–1199), median
/// 0.50 (`tests/methods/estimate/a_priori.rs`).
pub const LOCAL_FACTOR: f64 = 1.0;

/// The discretization part of an `energy` answer read from the answer alone \[m\] (safety
/// factor included): the strain each constant-strain sub-arc leaves out, from the cables'
/// pull and the loads along it (`energy/local_error.rs`), times [`LOCAL_FACTOR`]. `None`
/// where it does not apply (another method, a port, contacts, chord lengths, a tip moment):
/// Richardson's extra solve then measures it.
pub fn a_priori_discretization(
    kind: MethodKind,
    settings: &Settings,
    robot: &Robot,
    shape: &Shape,
) -> Option<f64> {
    if kind != MethodKind::Energy {
        return None;
    }
    let routing = match settings.get("routing").map(str::trim) {
        None | Some("spline") => crate::model::routing::RoutingFit::Spline,
        Some("fourier8") => crate::model::routing::RoutingFit::Fourier8,
        Some(_) => return None,
    };
    super::energy::local_error::local_error(robot, shape, routing)
        .map(|e| SAFETY * LOCAL_FACTOR * e)
}

/// How the model part of `kind` is estimated.
#[derive(Clone, Copy, PartialEq)]
enum ModelPart {
    /// The reference model itself.
    Zero,
    /// The strains it leaves out, to first order: (shear, extension).
    FirstOrder(bool, bool),
    /// The Cosserat rod at the companion resolution against the method there: the
    /// inextensible rod's error is not first order in the left-out strains (calibration:
    /// 3–15× the first-order estimate on random robots).
    RodAtCompanion,
    /// Not a mechanical model.
    Unknown,
}

fn model_part(kind: MethodKind, settings: &Settings) -> ModelPart {
    match kind {
        MethodKind::Cosserat => ModelPart::Zero,
        // With `shear = on` it is the rod's continuum (`energy/shear.rs`): nothing left out.
        MethodKind::Energy if sheared(settings) => ModelPart::FirstOrder(false, false),
        MethodKind::Energy => ModelPart::FirstOrder(true, false),
        // In its regime (straight cables tied at the tip, no loads) the backbone carries only
        // an axial force, whose strain the first-order sum takes exactly.
        MethodKind::ConstantCurvature => ModelPart::FirstOrder(true, true),
        MethodKind::Kirchhoff => ModelPart::RodAtCompanion,
        MethodKind::Geometric | MethodKind::GeometricSquared => ModelPart::Unknown,
    }
}

/// Whether `energy`'s settings model the shear (`shear = on`; the registry's default is off).
fn sheared(settings: &Settings) -> bool {
    settings.get("shear").is_some_and(|v| v.trim() == "on")
}

/// The model part, to first order in the left-out strains (module docs) \[m\], unscaled.
pub fn left_out_strain_tip(robot: &Robot, shape: &Shape, shear: bool, extension: bool) -> f64 {
    let b = &robot.backbone;
    let (ga, ea) = (b.ga(), b.ea());
    let n = shape.disks.len();
    if n < 2 || !(shear || extension) {
        return 0.0;
    }
    let l = &robot.loads;
    let line_mass = b.density * b.area();
    let total = shape.disks[n - 1].s;
    let mut moved = Vector3::zeros();
    for j in 0..n - 1 {
        let seg = shape.disks[j + 1].position - shape.disks[j].position;
        let len = seg.norm();
        if len <= 0.0 {
            continue;
        }
        let t = seg / len;
        let s_mid = 0.5 * (shape.disks[j].s + shape.disks[j + 1].s);
        // The loads beyond the section's middle, and the cables' pull back along their chords.
        let beyond_mass = l.disk_mass * (n - 1 - j) as f64 + line_mass * (total - s_mid).max(0.0);
        let mut force = l.tip_force + l.gravity * beyond_mass;
        for c in &shape.cables {
            let tension = c.tension.unwrap_or(0.0);
            if let (Some(a), Some(b)) = (c.points.get(j), c.points.get(j + 1)) {
                let chord = b - a;
                if chord.norm() > 0.0 && tension > 0.0 {
                    force -= chord.normalize() * tension;
                }
            }
        }
        let tt: Matrix3<f64> = t * t.transpose();
        let mut compliance = Matrix3::zeros();
        if shear {
            compliance += (Matrix3::identity() - tt) / ga;
        }
        if extension {
            compliance += tt / ea;
        }
        moved += compliance * force * len;
    }
    moved.norm()
}

/// Estimate how far `shape` (solved by `kind` with `settings` for `robot`, `act`, `scene`)
/// is from the converged reference rod: one extra solve for the discretization part, the
/// left-out strains for the model part (module docs).
pub(crate) fn estimate(
    kind: MethodKind,
    settings: &Settings,
    robot: &Robot,
    act: &Actuation,
    scene: &Scene,
    shape: &Shape,
) -> Result<ErrorEstimate, SolveError> {
    let t0 = Instant::now();
    let part = model_part(kind, settings);
    let mut rod_gap = None;
    let res = resolution(kind, settings);
    let (discretization, against, order) = match companion(res) {
        Some(c) => {
            let mut s = settings.clone();
            s.push(c.name, &c.value);
            quiet(kind, &mut s);
            // Never handed out, so only the finite half of the output check.
            let at = |k: MethodKind| {
                let other = super::run::SolveRequest::new(k)
                    .with_settings(s.clone())
                    .solver()?
                    .solve_unchecked(robot, act, scene, Some(shape))?;
                crate::check::finite(&other)?;
                Ok::<_, SolveError>(other)
            };
            let other = at(kind)?;
            if part == ModelPart::RodAtCompanion && scene.is_empty() {
                rod_gap = Some(at(MethodKind::Cosserat)?.tip_distance(&other));
            }
            let d = other.tip_distance(shape);
            (
                SAFETY * richardson(d, c.ratio, c.order, c.coarser),
                format!("{}={}", c.name, c.value),
                c.order,
            )
        }
        None => (0.0, String::new(), 0.0),
    };
    // An adaptive stepper often takes the same steps at 16× its tolerance: its error is
    // then read from the tolerance, per metre of robot (calibration, module docs).
    let discretization = match res {
        Resolution::Adaptive(tol) => discretization.max(SAFETY * tol * robot.length()),
        _ => discretization,
    };
    let (model, note) = model_estimate(kind, settings, robot, act, scene, shape, rod_gap);
    Ok(ErrorEstimate {
        bound_m: model.map(|m| m + discretization),
        discretization_m: discretization,
        model_m: model,
        against,
        order,
        cost_s: t0.elapsed().as_secs_f64(),
        note,
    })
}

/// Settings that skip what a companion solve does not need (the tip is the same to the bit):
/// `energy`'s stability and Jacobian, the rods' stability test.
pub(crate) fn quiet(kind: MethodKind, s: &mut Settings) {
    match kind {
        MethodKind::Energy => s.push("sensitivity", "off"),
        MethodKind::Cosserat | MethodKind::Kirchhoff => s.push("stability", "skip"),
        _ => {}
    }
}

/// The model part of `kind`'s `shape` \[m\] (safety factor included) and why it is unknown
/// when it is; `rod_gap` is the Cosserat rod's distance at the companion (for `kirchhoff`).
pub(crate) fn model_estimate(
    kind: MethodKind,
    settings: &Settings,
    robot: &Robot,
    act: &Actuation,
    scene: &Scene,
    shape: &Shape,
    rod_gap: Option<f64>,
) -> (Option<f64>, String) {
    let mut note = String::new();
    let unmodelled = if !scene.is_empty() {
        Some("the model part next to obstacles is not estimated (the rod with contact is its reference: `ccrkit compare`, guide obstacles)")
    } else if robot.backbone.stiffening > 0.0 {
        Some("the rod has no curvature stiffening: the model part is unknown")
    } else if act.cables.iter().any(|d| d.capstan != 0.0) {
        Some("the rod has no capstan friction: the model part is unknown")
    } else {
        None
    };
    let model = match (model_part(kind, settings), unmodelled) {
        (ModelPart::Zero, _) => Some(0.0),
        (ModelPart::Unknown, _) => {
            note = format!("{kind} is not a mechanical model: the model part is unknown");
            None
        }
        (_, Some(why)) => {
            note = why.into();
            None
        }
        (ModelPart::FirstOrder(shear, ext), None) => {
            Some(SAFETY * left_out_strain_tip(robot, shape, shear, ext))
        }
        (ModelPart::RodAtCompanion, None) => rod_gap.map(|g| SAFETY * g),
    };
    (model, note)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn richardson_recovers_a_pure_power_law() {
        // e(h) = C h^p exactly: tips at the true value plus the error along one axis.
        let (c, p, h) = (3.0, 2.0, 0.1);
        let e = |h: f64| c * h.powf(p);
        let d = e(2.0 * h) - e(h);
        assert!((richardson(d, 2.0, p, true) - e(h)).abs() < 1e-12);
        assert!((richardson(d, 2.0, p, false) - e(2.0 * h)).abs() < 1e-12);
    }

    #[test]
    fn resolutions_read_settings_and_registry_defaults() {
        let s = Settings::new();
        assert_eq!(resolution(MethodKind::Energy, &s), Resolution::SubArcs(4));
        assert_eq!(resolution(MethodKind::Cosserat, &s), Resolution::Rk4(3));
        let a = Settings::new().with("adaptive", "1e-6");
        assert_eq!(
            resolution(MethodKind::Kirchhoff, &a),
            Resolution::Adaptive(1e-6)
        );
        let off = Settings::new()
            .with("adaptive", "off")
            .with("rk4-steps", "8");
        assert_eq!(resolution(MethodKind::Cosserat, &off), Resolution::Rk4(8));
        assert_eq!(resolution(MethodKind::Geometric, &s), Resolution::Exact);
    }
}
