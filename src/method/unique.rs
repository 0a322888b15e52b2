//! Is the answer the only equilibrium? (`solve --check unique`, [`SolveRequest::check_unique`].)
//!
//! A method answers with the equilibrium its default path reaches (`energy`: Newton–KKT from
//! the straight robot at the full input; the rods: shooting from the global-balance base
//! wrench at the full load, load stepping from zero when that fails; the section solvers:
//! each section's lowest certified candidate, base to tip). An input can have more than one
//! equilibrium, each converged and stable, and one solve cannot tell. The check solves the
//! same input with the same method along other paths:
//!
//! - **continuation**: the input ramped from zero in [`CONTINUATION_STEPS`] warm-started steps;
//! - **overshoot**: the input × [`OVERSHOOT`], then back to it (warm);
//! - **cable k leading**: cable k at its input and every other driven cable at
//!   [`LAGGING`] of its own, then the whole input (warm), for up to [`LEADING_CABLES`] cables;
//! - **from the other model**: warm-started from the answer of the other model driven by the
//!   same input (`energy` ↔ `cosserat`; the other methods: `energy`).
//!
//! Every converged answer more than [`DISTINCT_M`] from the answer's tip (and from the other
//! answers found) is another equilibrium, reported with its tip distance and stability. The
//! other model's own answer is reported too, with a verdict: when it disagrees (beyond
//! [`crate::study::compare::DISAGREE_TOL`]) and this method started from it comes back to its
//! answer, the gap is between the models (or one's resolution: `--estimate`), not a second
//! equilibrium of this method. The check costs the solves it lists (`solves`, `time_s`); a
//! failed try is listed with its error and proves nothing.

use super::run::SolveRequest;
use super::{MethodKind, Settings, Solver};
use crate::error::SolveError;
use crate::model::actuation::{Actuation, Shortening};
use crate::model::scene::Scene;
use crate::model::Model;
use crate::shape::Shape;
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// Two answers of one method whose tips lie farther apart are distinct equilibria \[m\]
/// (far above every method's solver tolerance, far below any disagreement a user acts on).
pub const DISTINCT_M: f64 = 1e-4;
/// Steps of the continuation from zero.
pub const CONTINUATION_STEPS: usize = 8;
/// The overshoot factor of the input before it comes back.
pub const OVERSHOOT: f64 = 1.3;
/// The fraction of its input each other driven cable starts at while one cable leads.
pub const LAGGING: f64 = 0.25;
/// Most cables tried as the leading one (the first driven ones in robot order).
pub const LEADING_CABLES: usize = 4;

/// One path tried.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct UniqueTry {
    /// The path (`continuation 8 steps`, `overshoot ×1.3`, `cable c1 leading`,
    /// `from cosserat's answer`).
    pub start: String,
    /// Tip distance from the answer \[m\] (`None`: the try did not converge).
    pub tip_distance_m: Option<f64>,
    /// The tip it reached, base frame \[m\] (`None`: the try did not converge).
    pub tip_m: Option<[f64; 3]>,
    /// Its stability, as the method reports it.
    pub stable: Option<bool>,
    /// A new equilibrium: converged, farther than [`DISTINCT_M`] from the answer and from
    /// every equilibrium an earlier try found.
    pub distinct: bool,
    /// Why it failed, when it did.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
}

/// The other model's answer to the same input.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct OtherModel {
    /// The model and the input it was driven by (`cosserat control=displacement`).
    pub method: String,
    /// Its tip's distance from the answer \[m\] (`None`: it did not solve).
    pub tip_distance_m: Option<f64>,
    /// Its tip, base frame \[m\] (`None`: it did not solve).
    pub tip_m: Option<[f64; 3]>,
    /// Its stability.
    pub stable: Option<bool>,
    /// What the distance means (`agrees`, `a gap between the models …`, its error).
    pub verdict: String,
}

/// The result of the check, in `report.unique`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct UniqueReport {
    /// No other equilibrium of this method was found, and at least one path converged (when
    /// none did, nothing was checked: `converged_tries` is 0).
    pub only: bool,
    /// Paths that converged (to this answer or another).
    pub converged_tries: usize,
    /// Equilibria found, the answer included.
    pub equilibria: usize,
    /// [`DISTINCT_M`].
    pub tolerance_m: f64,
    /// Every path tried, in order.
    pub tries: Vec<UniqueTry>,
    /// The other model's answer, when there is one for this method and input.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub other_model: Option<OtherModel>,
    /// Solves the check took (a continuation counts its steps).
    pub solves: usize,
    /// Wall time of the check \[s\].
    pub time_s: f64,
}

/// The method the answer of `kind` is checked against, with the settings that drive it by the
/// same input and measure the cables the same way.
fn other_request(kind: MethodKind, settings: &Settings) -> Option<SolveRequest> {
    let other = match kind {
        MethodKind::Energy => MethodKind::Cosserat,
        _ => MethodKind::Energy,
    };
    let input = kind.input_with(settings);
    if !other.accepts(input) {
        return None;
    }
    let mut s = Settings::new().with("control", super::settings::control_name(input));
    for key in ["length", "routing"] {
        if let (Some(v), true) = (settings.get(key), other.check_setting(key).is_ok()) {
            s.push(key, v);
        }
    }
    Some(SolveRequest::new(other).with_settings(s))
}

/// `act` with cable `lead`'s input kept and every other cable's scaled by `f`.
fn leading(act: &Actuation, lead: usize, f: f64) -> Actuation {
    let mut a = act.clone();
    for (_, d) in a.cables.iter_mut().enumerate().filter(|(k, _)| *k != lead) {
        d.shorten = d.shorten.map(|s| match s {
            Shortening::Length(x) => Shortening::Length(f * x),
            Shortening::Fraction(x) => Shortening::Fraction(f * x),
        });
        d.tension = d.tension.map(|t| f * t);
    }
    a
}

/// The tries' bookkeeping: equilibria found so far (tips), solves spent.
struct Found {
    tips: Vec<nalgebra::Vector3<f64>>,
    tries: Vec<UniqueTry>,
    solves: usize,
}

impl Found {
    fn record(&mut self, start: String, res: Result<Shape, SolveError>) {
        let tr = match res {
            Ok(s) if s.report.converged => {
                let tip = s.tip();
                let d0 = (tip - self.tips[0]).norm();
                let distinct = self.tips.iter().all(|t| (tip - t).norm() > DISTINCT_M);
                if distinct {
                    self.tips.push(tip);
                }
                UniqueTry {
                    start,
                    tip_distance_m: Some(d0),
                    tip_m: Some([tip.x, tip.y, tip.z]),
                    stable: s.report.stable,
                    distinct,
                    error: None,
                }
            }
            Ok(s) => UniqueTry {
                start,
                tip_distance_m: None,
                tip_m: None,
                stable: s.report.stable,
                distinct: false,
                error: Some(format!(
                    "did not converge (residual {:.1e})",
                    s.report.residual
                )),
            },
            Err(e) => UniqueTry {
                start,
                tip_distance_m: None,
                tip_m: None,
                stable: None,
                distinct: false,
                error: Some(e.to_string()),
            },
        };
        self.tries.push(tr);
    }
}

/// Check `answer`, solved by `request` on `model` in `scene` (module docs).
pub fn check(
    request: &SolveRequest,
    model: &Model,
    scene: &Scene,
    answer: &Shape,
) -> Result<UniqueReport, SolveError> {
    let t0 = Instant::now();
    let (robot, act) = (&model.robot, &model.actuation);
    let one = SolveRequest {
        steps: 1,
        warm_from: None,
        repeat: 1,
        estimate: false,
        check_unique: false,
        auto: None,
        ..request.clone()
    };
    let solver = one.solver()?;
    let mut f = Found {
        tips: vec![answer.tip()],
        tries: vec![],
        solves: 0,
    };
    let steps = if request.steps == CONTINUATION_STEPS {
        CONTINUATION_STEPS / 2
    } else {
        CONTINUATION_STEPS
    };
    let ramp = Solver::new(request.method.build(&request.settings)?, steps)
        .with_settings(request.settings.clone());
    f.solves += steps;
    f.record(
        format!("continuation {steps} steps"),
        ramp.solve(robot, act, scene, None),
    );
    let via = |f: &mut Found, from: &Actuation| {
        f.solves += 2;
        solver
            .solve(robot, from, scene, None)
            .and_then(|s| solver.solve(robot, act, scene, Some(&s)))
    };
    let r = via(&mut f, &act.scaled(OVERSHOOT));
    f.record(format!("overshoot ×{OVERSHOOT}"), r);
    let drives = request
        .method
        .drives(robot, act, request.method.input_with(&request.settings))?;
    let driven: Vec<usize> = (0..drives.len())
        .filter(|&k| !matches!(drives[k], crate::model::actuation::Drive::Free))
        .collect();
    if driven.len() > 1 {
        for &k in driven.iter().take(LEADING_CABLES) {
            let r = via(&mut f, &leading(act, k, LAGGING));
            f.record(format!("cable {} leading", robot.cables[k].name), r);
        }
    }
    let other_model = other_request(request.method, &request.settings)
        .map(|o| against_other(&o, &solver, model, scene, &mut f));
    let equilibria = f.tips.len();
    let converged_tries = f
        .tries
        .iter()
        .filter(|t| t.tip_distance_m.is_some())
        .count();
    Ok(UniqueReport {
        only: equilibria == 1 && converged_tries > 0,
        converged_tries,
        equilibria,
        tolerance_m: DISTINCT_M,
        tries: f.tries,
        other_model,
        solves: f.solves,
        time_s: t0.elapsed().as_secs_f64(),
    })
}

/// The other model's answer, and this method warm-started from it (a try).
fn against_other(
    other: &SolveRequest,
    solver: &Solver,
    model: &Model,
    scene: &Scene,
    f: &mut Found,
) -> OtherModel {
    let label = crate::study::compare::request_label(other);
    f.solves += 1;
    let theirs = other
        .solver()
        .and_then(|s| s.solve(&model.robot, &model.actuation, scene, None));
    let shape = match theirs {
        Ok(s) => s,
        Err(e) => {
            return OtherModel {
                method: label,
                tip_distance_m: None,
                tip_m: None,
                stable: None,
                verdict: format!("did not solve: {e}"),
            }
        }
    };
    let d = (shape.tip() - f.tips[0]).norm();
    f.solves += 1;
    let ours = solver.solve(&model.robot, &model.actuation, scene, Some(&shape));
    let back = ours.as_ref().ok().map(|s| (s.tip() - f.tips[0]).norm());
    f.record(format!("from {}'s answer", other.method), ours);
    let verdict = if d <= crate::study::compare::DISAGREE_TOL {
        "agrees".to_string()
    } else if back.is_some_and(|b| b <= DISTINCT_M) {
        format!(
            "disagrees; {} started from its answer comes back to this one: a gap between \
             the models or their resolutions (`--estimate`), not a second equilibrium found",
            solver.name()
        )
    } else {
        format!(
            "disagrees; {} started from its answer does not come back to this one (see \
             that try)",
            solver.name()
        )
    };
    let tip = shape.tip();
    OtherModel {
        method: label,
        tip_distance_m: Some(d),
        tip_m: Some([tip.x, tip.y, tip.z]),
        stable: shape.report.stable,
        verdict,
    }
}
