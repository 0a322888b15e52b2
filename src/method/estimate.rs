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
//! `docs/guide/methods.md`). The estimate reads `energy`'s discretization part a priori; it
//! costs one extra solve (about half the answer's own cost at the coarser rung) where that does
//! not apply, and says why (`fallback`); an extra solve that fails is named (`failed`) and the
//! next companion (one rung up) tried. Computed only when asked for
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
    /// The discretization part \[m\] (0 for a closed form or a section solver); `None` when
    /// every extra solve that measures it failed (`failed` names them).
    pub discretization_m: Option<f64>,
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
    /// Why the discretization part was measured by an extra solve rather than read from the
    /// answer alone ([`a_priori`]: `energy with contacts`, `cosserat has none`), or empty.
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub fallback: String,
    /// Each extra solve that failed, by its setting, status name and message
    /// (`sub-arcs=1: not_converged: …`); a later companion may still have measured the part.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub failed: Vec<String>,
}

impl ErrorEstimate {
    /// The bound where both parts are known, else the known parts with an unknown one taken
    /// as 0 (`auto` holds that to its tolerance next to obstacles), `+∞` without a
    /// discretization part.
    pub fn known_parts_m(&self) -> f64 {
        self.discretization_m.unwrap_or(f64::INFINITY) + self.model_m.unwrap_or(0.0)
    }
}

/// What an estimate read from the answer alone was measured against (`against`).
pub const A_PRIORI: &str = "the answer's own strains";

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

/// The companions of a resolution, the one to try first first: one rung down (close enough
/// to stay in the asymptotic range — 3 RK4 steps against 1 is not — and cheaper than the
/// answer), then, should that solve fail (a coarse rod that does not converge), one rung up.
fn companions(res: Resolution) -> Vec<Companion> {
    let at = |name: &'static str, n: usize, m: usize, order: f64| Companion {
        name,
        value: m.to_string(),
        ratio: n.max(m) as f64 / n.min(m) as f64,
        coarser: m < n,
        order,
    };
    let fixed = |name: &'static str, n: usize, order: f64| {
        let up = if n < 6 { n + 1 } else { n + n / 2 };
        match n {
            0 | 1 => vec![at(name, n.max(1), 2, order)],
            n if n < 6 => vec![at(name, n, n - 1, order), at(name, n, up, order)],
            n => vec![at(name, n, n / 2, order), at(name, n, up, order)],
        }
    };
    match res {
        Resolution::SubArcs(k) => fixed("sub-arcs", k, SUB_ARC_ORDER),
        Resolution::Rk4(n) => fixed("rk4-steps", n, RK4_ORDER),
        Resolution::Adaptive(tol) => {
            let other = |coarser: bool| Companion {
                name: "adaptive",
                value: format!(
                    "{:e}",
                    if coarser {
                        tol * ADAPTIVE_RATIO
                    } else {
                        tol / ADAPTIVE_RATIO
                    }
                ),
                ratio: ADAPTIVE_RATIO,
                coarser,
                order: ADAPTIVE_ORDER,
            };
            if tol * ADAPTIVE_RATIO <= 1.0 {
                vec![other(true), other(false)]
            } else {
                vec![other(false)]
            }
        }
        Resolution::Exact => vec![],
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
/// where it does not apply (another method, contacts, chord lengths, a tip moment; through a
/// port it reads the robot beyond it, as solved):
/// Richardson's extra solve then measures it.
pub fn a_priori_discretization(
    kind: MethodKind,
    settings: &Settings,
    robot: &Robot,
    shape: &Shape,
) -> Option<f64> {
    a_priori(kind, settings, robot, shape).ok()
}

/// [`a_priori_discretization`], or why it does not apply (`energy with contacts`, `energy with
/// chord cable lengths`, `cosserat has none`, …).
pub fn a_priori(
    kind: MethodKind,
    settings: &Settings,
    robot: &Robot,
    shape: &Shape,
) -> Result<f64, String> {
    a_priori_parts(kind, settings, robot, shape).map(|e| e.iter().sum())
}

/// [`a_priori`] per section, base first \[m\] (safety factor included; their sum is the
/// estimate): where `auto` refines the sub-arcs.
pub fn a_priori_parts(
    kind: MethodKind,
    settings: &Settings,
    robot: &Robot,
    shape: &Shape,
) -> Result<Vec<f64>, String> {
    if kind != MethodKind::Energy {
        return Err(format!("{kind} has none"));
    }
    let routing = match settings.get("routing").map(str::trim) {
        None | Some("spline") => crate::model::routing::RoutingFit::Spline,
        Some("fourier8") => crate::model::routing::RoutingFit::Fourier8,
        Some(other) => return Err(format!("{kind} with routing = {other}")),
    };
    super::energy::local_error::local_error(robot, shape, routing)
        .map(|e| e.iter().map(|x| SAFETY * LOCAL_FACTOR * x).collect())
        .map_err(|why| format!("{kind} {why}"))
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

/// An answer whose error is estimated: `shape`, solved by `kind` with `settings` for `robot`
/// under `act` in `scene` (what [`estimate`] and [`model_estimate`] read).
#[derive(Clone, Copy)]
pub(crate) struct Answer<'a> {
    /// The method that solved it.
    pub kind: MethodKind,
    /// Its settings.
    pub settings: &'a Settings,
    /// The robot.
    pub robot: &'a Robot,
    /// The actuation.
    pub act: &'a Actuation,
    /// The obstacles.
    pub scene: &'a Scene,
    /// The answer.
    pub shape: &'a Shape,
}

/// Estimate how far `shape` (solved by `kind` with `settings` for `robot`, `act`, `scene`)
/// is from the converged reference rod: the discretization part read from the answer alone
/// where it can be ([`a_priori`]), else by one extra solve (two where the first fails); the
/// left-out strains for the model part (module docs). A failed extra solve is named in the
/// estimate (`failed`), never an error of the answer.
pub(crate) fn estimate(answer: &Answer<'_>) -> Result<ErrorEstimate, SolveError> {
    let Answer {
        kind,
        settings,
        robot,
        act,
        scene,
        shape,
    } = *answer;
    let t0 = Instant::now();
    let res = resolution(kind, settings);
    let mut failed = vec![];
    let (discretization, against, order, fallback, rod_gap) =
        match a_priori(kind, settings, robot, shape) {
            Ok(d) => (
                Some(d),
                A_PRIORI.to_string(),
                SUB_ARC_ORDER,
                String::new(),
                None,
            ),
            Err(_) if res == Resolution::Exact => {
                (Some(0.0), String::new(), 0.0, String::new(), None)
            }
            Err(why) => {
                // Never handed out, so only the finite half of the output check.
                let solve = |k: MethodKind, s: &Settings| {
                    let other = super::run::SolveRequest::new(k)
                        .with_settings(s.clone())
                        .solver()?
                        .solve_unchecked(super::SolveInput {
                            robot,
                            act,
                            scene,
                            warm: Some(shape),
                        })?;
                    crate::check::finite(&other)?;
                    Ok(other)
                };
                let rod =
                    model_part(kind, settings) == ModelPart::RodAtCompanion && scene.is_empty();
                let m = measure(kind, settings, shape, rod, &solve, &mut failed);
                let fallback = format!("no a-priori estimate ({why}): measured by an extra solve");
                (m.discretization, m.against, m.order, fallback, m.rod_gap)
            }
        };
    // An adaptive stepper often takes the same steps at 16× its tolerance: its error is
    // then read from the tolerance, per metre of robot (calibration, module docs).
    let discretization = match res {
        Resolution::Adaptive(tol) => discretization.map(|d| d.max(SAFETY * tol * robot.length())),
        _ => discretization,
    };
    let (model, mut note) = model_estimate(answer, rod_gap);
    if discretization.is_none() {
        note = join(
            &note,
            "every extra solve that measures the discretization part failed (`failed`): no bound",
        );
    }
    Ok(ErrorEstimate {
        bound_m: model.zip(discretization).map(|(m, d)| m + d),
        discretization_m: discretization,
        model_m: model,
        against,
        order,
        cost_s: t0.elapsed().as_secs_f64(),
        note,
        fallback,
        failed,
    })
}

/// Two notes in one.
fn join(a: &str, b: &str) -> String {
    if a.is_empty() {
        b.to_string()
    } else {
        format!("{a}; {b}")
    }
}

/// The discretization part measured by Richardson against a companion solve, what it was
/// measured against and its order, and (`kirchhoff`) the Cosserat rod's distance there.
struct Measured {
    discretization: Option<f64>,
    against: String,
    order: f64,
    rod_gap: Option<f64>,
}

/// Richardson against the first companion ([`companions`]) whose solve (`solve`: a method and
/// its settings, warm from the answer) succeeds; each failure pushed to `failed` by setting,
/// status name and message. `rod`: also solve the Cosserat rod there (`kirchhoff`).
fn measure(
    kind: MethodKind,
    settings: &Settings,
    shape: &Shape,
    rod: bool,
    solve: &dyn Fn(MethodKind, &Settings) -> Result<Shape, SolveError>,
    failed: &mut Vec<String>,
) -> Measured {
    let mut out = Measured {
        discretization: None,
        against: String::new(),
        order: 0.0,
        rod_gap: None,
    };
    for c in companions(resolution(kind, settings)) {
        let mut s = settings.clone();
        s.push(c.name, &c.value);
        quiet(kind, &mut s);
        let label = format!("{}={}", c.name, c.value);
        let other = match solve(kind, &s) {
            Ok(o) => o,
            Err(e) => {
                failed.push(format!("{kind} {label}: {}: {e}", e.kind()));
                continue;
            }
        };
        if rod {
            match solve(MethodKind::Cosserat, &s) {
                Ok(r) => out.rod_gap = Some(r.tip_distance(&other)),
                Err(e) => failed.push(format!("cosserat {label}: {}: {e}", e.kind())),
            }
        }
        let d = other.tip_distance(shape);
        out.discretization = Some(SAFETY * richardson(d, c.ratio, c.order, c.coarser));
        out.against = label;
        out.order = c.order;
        break;
    }
    out
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
pub(crate) fn model_estimate(answer: &Answer<'_>, rod_gap: Option<f64>) -> (Option<f64>, String) {
    let (kind, settings, robot) = (answer.kind, answer.settings, answer.robot);
    let (act, scene, shape) = (answer.act, answer.scene, answer.shape);
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
        (ModelPart::RodAtCompanion, None) => {
            if rod_gap.is_none() {
                note = format!("the Cosserat rod beside {kind}'s companion did not solve: the model part is unknown");
            }
            rod_gap.map(|g| SAFETY * g)
        }
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

    /// A cosserat answer of paper case I at `rk4-steps = 3` and its settings.
    fn case1_rod() -> (Shape, Settings) {
        let model = crate::Model::from_file("models/paper/case1.toml").expect("case I");
        let s = Settings::new().with("rk4-steps", 3);
        let shape = super::super::run::SolveRequest::new(MethodKind::Cosserat)
            .with_settings(s.clone())
            .run(&model)
            .expect("solves")
            .shape;
        (shape, s)
    }

    /// `shape` with its tip moved by `d` along x.
    fn moved(shape: &Shape, d: f64) -> Shape {
        let mut s = shape.clone();
        if let Some(last) = s.disks.last_mut() {
            last.position.x += d;
        }
        s
    }

    #[test]
    fn a_companion_that_fails_is_named_and_the_next_one_measures() {
        let (shape, s) = case1_rod();
        let not_converged = || SolveError::NotConverged {
            method: "cosserat".into(),
            section: None,
            iterations: 40,
            residual: 1.0,
            detail: String::new(),
        };
        // 3 steps: the coarse companion (2) fails, the fine one (4) is 1 µm away.
        let solve = |_: MethodKind, c: &Settings| match c.get("rk4-steps") {
            Some("2") => Err(not_converged()),
            _ => Ok(moved(&shape, 1e-6)),
        };
        let mut failed = vec![];
        let m = measure(MethodKind::Cosserat, &s, &shape, false, &solve, &mut failed);
        assert_eq!(failed.len(), 1, "{failed:?}");
        assert!(failed[0].starts_with("cosserat rk4-steps=2: not_converged: "));
        assert_eq!(m.against, "rk4-steps=4");
        // The answer is the coarse one of the pair: d · g / (g − 1), g = (4/3)^4.
        let g = (4.0f64 / 3.0).powi(4);
        let want = SAFETY * 1e-6 * g / (g - 1.0);
        let got = m.discretization.expect("measured by the fine companion");
        assert!((got - want).abs() < 1e-9 * want, "{got:e} vs {want:e}");
        // Both fail: no discretization part, two failures named.
        let mut failed = vec![];
        let none = measure(
            MethodKind::Cosserat,
            &s,
            &shape,
            false,
            &|_, _| Err(not_converged()),
            &mut failed,
        );
        assert!(none.discretization.is_none());
        assert_eq!(failed.len(), 2, "{failed:?}");
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
