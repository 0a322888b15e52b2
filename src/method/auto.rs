//! `auto`: the cheapest model and resolution whose estimated error ([`super::estimate`]) for
//! this robot, input and scene is within a tolerance.
//!
//! The candidates are the registry's resolution ladders, cheapest first: `energy`'s sub-arcs
//! (1, 2, 3, 4, 6, 8, 12, 16); where its model part, the shear it leaves out, exceeds the
//! tolerance, the same ladder with `shear = on` (the rod's continuum, model part 0,
//! `energy/shear.rs`: dearer per solve); then the Cosserat rod's fixed RK4 steps (2 … 20 per
//! section) where `energy` cannot meet the tolerance or cannot solve the problem (a tip
//! moment, or obstacles with shear). On a ladder:
//!
//! 1. the coarsest rung is solved and estimated: `energy`'s discretization part read from the
//!    answer alone where it can be ([`estimate::a_priori_discretization`]: no further solve),
//!    else one extra solve one rung up or down, without stability or Jacobian
//!    (`estimate::quiet`); within the tolerance, it is the answer;
//! 2. otherwise the method's order predicts the discretization part of every finer rung from
//!    the last one measured, `e(n) = e(m) (m/n)^p`, and the first rung predicted within 70 % of
//!    what the model part leaves of the tolerance is solved, warm-started from the last
//!    answer; its estimate is the a-priori one again, or Richardson against that answer (no
//!    further solve);
//! 3. repeat until a rung's estimate is within the tolerance or the ladder ends.
//!
//! `energy`'s a-priori estimate comes per section, so where it applies its ladder is walked
//! section by section instead (`Search::refine`): each section gets the fewest sub-arcs whose
//! predicted part keeps the sum within 70 % of the room (`refined`: `m'_i ∝ c_i^{1/3}`,
//! Lagrange), never fewer than before nor more than the ladder's finest rung, and the answer at
//! those counts (`sub-arcs=1,2,2,4`) is solved and estimated again. On 25 seeded random robots
//! its answers had fewer sub-arcs in total than uniform refinement's, in as many solves
//! (`tests/methods/adaptive.rs`).
//!
//! The rungs are solved without the output check; the answer handed out passes it once.
//! The answer says what was chosen, its estimate and the cost of everything solved
//! ([`AutoReport`] in `report.auto`). Next to obstacles the model part is not estimated, so only
//! the discretization part is held to the tolerance (the report's note says so). When no
//! rung meets the tolerance, the answer with the smallest estimate is returned with
//! `met = false`.

use super::estimate::{self, ErrorEstimate, SAFETY};
use super::run::SolveRequest;
use super::{MethodKind, Settings};
use crate::error::SolveError;
use crate::model::actuation::Actuation;
use crate::model::robot::Robot;
use crate::model::scene::Scene;
use crate::shape::Shape;
use serde::{Deserialize, Serialize};
use std::time::Instant;

pub use super::estimate::A_PRIORI;

/// What `auto` chose and what it cost.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AutoReport {
    /// The method chosen.
    pub method: String,
    /// Its resolution (`sub-arcs=2`, `rk4-steps=6`).
    pub setting: String,
    /// The tolerance asked for \[m\].
    pub tolerance_m: f64,
    /// Whether the chosen answer's estimate is within it.
    pub met: bool,
    /// Solves run (answers and estimates).
    pub solves: usize,
    /// Wall time of all of them \[s\].
    pub cost_s: f64,
}

/// One rung: the method, its resolution setting and value, and (`energy`) whether it models
/// the shear.
#[derive(Clone)]
struct Rung {
    kind: MethodKind,
    name: &'static str,
    n: usize,
    order: f64,
    shear: bool,
    /// `energy`'s sub-arcs of each section where they differ (empty: `n` in each).
    per: Vec<usize>,
}

impl Rung {
    /// The resolution's value: `4`, or one count per section, `1,2,4`.
    fn value(&self) -> String {
        if self.per.is_empty() {
            return self.n.to_string();
        }
        let c: Vec<String> = self.per.iter().map(|n| n.to_string()).collect();
        c.join(",")
    }

    /// What the answer reports as the chosen setting (`sub-arcs=4`, `sub-arcs=1,2,4`,
    /// `sub-arcs=4, shear=on`).
    fn describe(&self) -> String {
        let shear = if self.shear { ", shear=on" } else { "" };
        format!("{}={}{shear}", self.name, self.value())
    }

    /// The rung of this method at `per` sub-arcs per section (an adaptive `energy` rung).
    /// Equal counts are the uniform rung (`sub-arcs=5`).
    fn at(&self, per: Vec<usize>) -> Rung {
        let n = per.iter().copied().max().unwrap_or(self.n);
        let uniform = per.iter().all(|&m| m == n);
        Rung {
            n,
            per: if uniform { vec![] } else { per },
            ..self.clone()
        }
    }
}

/// The fixed-step rungs of `kind` from the registry's ladder, coarse to fine (`energy` from
/// one sub-arc per section: the cheapest in hindsight on 9 of 10 random robots, `ccrkit study
/// auto`). `shear`: `energy`'s rungs with `shear = on`.
fn ladder(kind: MethodKind, shear: bool) -> Vec<Rung> {
    let (name, order) = match kind {
        MethodKind::Energy => ("sub-arcs", estimate::SUB_ARC_ORDER),
        _ => ("rk4-steps", estimate::RK4_ORDER),
    };
    kind.info()
        .resolutions
        .iter()
        .filter_map(|(_, pairs)| {
            let s = pairs.iter().find(|(k, _)| *k == name)?;
            Some(Rung {
                kind,
                name,
                n: s.1.parse().ok()?,
                order,
                shear,
                per: vec![],
            })
        })
        .collect()
}

/// The settings of a rung: the caller's (those the method takes, resolution left out), the
/// input, the rung's resolution.
fn rung_settings(rung: &Rung, base: &Settings, control: &str) -> Settings {
    let mut s = Settings::new();
    for (k, v) in base.iter() {
        let k = super::settings::canonical(k);
        let own = ["sub-arcs", "rk4-steps", "adaptive", "control", "shear"].contains(&k.as_str());
        if !own && rung.kind.check_setting(&k).is_ok() {
            s.push(k, v);
        }
    }
    s.push("control", control);
    s.push(rung.name, rung.value());
    if rung.shear {
        s.push("shear", "on");
    }
    s
}

/// What a walk along the ladders found so far.
struct Search<'a> {
    robot: &'a Robot,
    act: &'a Actuation,
    scene: &'a Scene,
    tolerance: f64,
    base: &'a Settings,
    control: String,
    solves: usize,
    best: Option<(Shape, ErrorEstimate, String)>,
    /// The last estimate's a-priori part per section, where it had one.
    parts: Option<Vec<f64>>,
}

impl Search<'_> {
    fn solve(&mut self, rung: &Rung, warm: Option<&Shape>) -> Result<Shape, SolveError> {
        self.solves += 1;
        SolveRequest::new(rung.kind)
            .with_settings(rung_settings(rung, self.base, &self.control))
            .solver()?
            .solve_unchecked(super::SolveInput {
                robot: self.robot,
                act: self.act,
                scene: self.scene,
                warm,
            })
    }

    /// Keep `shape` if its estimate is the smallest yet; true when it meets the tolerance.
    fn offer(&mut self, rung: &Rung, shape: Shape, est: ErrorEstimate, model: f64) -> bool {
        let bound = est.discretization_m.unwrap_or(f64::INFINITY) + model;
        let met = bound <= self.tolerance;
        let better = self
            .best
            .as_ref()
            .is_none_or(|(_, e, _)| bound < e.known_parts_m());
        if better || met {
            self.best = Some((shape, est, rung.describe()));
        }
        met
    }

    /// The estimate of `shape`, solved at `rung`: the discretization part read from the
    /// answer alone where it can be (`energy`, [`estimate::a_priori_discretization`]), else
    /// Richardson against `against` (the previous rung's answer, no further solve) or, without
    /// one, against one extra solve ([`estimate::estimate`]).
    fn estimate(
        &mut self,
        rung: &Rung,
        shape: &Shape,
        against: Option<(&Rung, &Shape)>,
    ) -> Result<ErrorEstimate, SolveError> {
        let settings = rung_settings(rung, self.base, &self.control);
        let answer = estimate::Answer {
            kind: rung.kind,
            settings: &settings,
            robot: self.robot,
            act: self.act,
            scene: self.scene,
            shape,
        };
        let local = estimate::a_priori_parts(rung.kind, &settings, self.robot, shape);
        self.parts = local.as_ref().ok().cloned();
        let (disc, from, fallback) = match (local.map(|p| p.iter().sum()), against) {
            (Ok(d), _) => (d, A_PRIORI.to_string(), String::new()),
            (Err(why), Some((from, last))) => {
                let ratio = rung.n as f64 / from.n as f64;
                let d = shape.tip_distance(last);
                let e = SAFETY * estimate::richardson(d, ratio, rung.order, true);
                let fallback =
                    format!("no a-priori estimate ({why}): measured against the previous rung");
                (e, from.describe(), fallback)
            }
            (Err(_), None) => {
                let est = estimate::estimate(&answer)?;
                // The companion solved, and each one that failed before it.
                self.solves += usize::from(est.discretization_m.is_some()) + est.failed.len();
                return Ok(est);
            }
        };
        let (m, note) = estimate::model_estimate(&answer, None);
        Ok(ErrorEstimate {
            bound_m: m.map(|m| m + disc),
            discretization_m: Some(disc),
            model_m: m,
            against: from,
            order: rung.order,
            cost_s: 0.0,
            note,
            fallback,
            failed: vec![],
        })
    }

    /// Walk one method's ladder; true when a rung met the tolerance.
    fn walk(&mut self, rungs: &[Rung]) -> Result<bool, SolveError> {
        let Some(first) = rungs.first() else {
            return Ok(false);
        };
        let a0 = self.solve(first, None)?;
        let e0 = self.estimate(first, &a0, None)?;
        let model = e0.model_m.unwrap_or(0.0);
        let disc0 = e0.discretization_m;
        if self.offer(first, a0.clone(), e0, model) {
            return Ok(true);
        }
        // Its extra solves failed (named in the estimate): no order to predict from.
        let Some(mut disc) = disc0 else {
            return Ok(false);
        };
        if model > self.tolerance {
            return Ok(false);
        }
        if let Some(parts) = self.parts.take() {
            let cap = rungs.last().map_or(first.n, |r| r.n);
            return self.refine(first, a0, parts, model, cap);
        }
        let (mut at, mut last) = (0, a0);
        while at + 1 < rungs.len() {
            let room = 0.7 * (self.tolerance - model);
            let from = &rungs[at];
            let next = (at + 1..rungs.len())
                .find(|&j| disc * (from.n as f64 / rungs[j].n as f64).powf(from.order) <= room)
                .unwrap_or(rungs.len() - 1);
            let rung = &rungs[next];
            let shape = self.solve(rung, Some(&last))?;
            let est = self.estimate(rung, &shape, Some((from, &last)))?;
            let model = est.model_m.unwrap_or(0.0);
            disc = est.discretization_m.unwrap_or(f64::INFINITY);
            if self.offer(rung, shape.clone(), est, model) {
                return Ok(true);
            }
            if model > self.tolerance {
                return Ok(false);
            }
            (at, last) = (next, shape);
        }
        Ok(false)
    }
}

impl Search<'_> {
    /// Walk `energy`'s sub-arcs section by section from `rung`'s answer `last`, whose a-priori
    /// estimate per section is `parts` (model part `model`): each section refined as
    /// [`refined`] predicts, none beyond `cap`, until an answer's estimate is within the
    /// tolerance; true when one is.
    fn refine(
        &mut self,
        rung: &Rung,
        mut last: Shape,
        mut parts: Vec<f64>,
        mut model: f64,
        cap: usize,
    ) -> Result<bool, SolveError> {
        let mut counts = vec![rung.n; parts.len()];
        loop {
            let room = 0.7 * (self.tolerance - model);
            let next = refined(&counts, &parts, room, rung.order, cap);
            if next == counts {
                return Ok(false);
            }
            let at = rung.at(next.clone());
            let shape = self.solve(&at, Some(&last))?;
            let est = self.estimate(&at, &shape, None)?;
            model = est.model_m.unwrap_or(0.0);
            if self.offer(&at, shape.clone(), est, model) {
                return Ok(true);
            }
            let Some(p) = self.parts.take() else {
                return Ok(false);
            };
            if model > self.tolerance {
                return Ok(false);
            }
            (counts, parts, last) = (next, p, shape);
        }
    }
}

/// The fewest sub-arcs per section (none fewer than `counts`, none more than `cap`) whose
/// predicted estimate is within `room`, when section `i` at `counts[i]` sub-arcs has the part
/// `parts[i]` and parts fall as `(m / m')^order`: minimizing `Σ m'_i` under
/// `Σ c_i m'_i^−p ≤ room` (`c_i = parts_i m_i^p`) gives `m'_i ∝ c_i^{1/(p+1)}` (Lagrange),
/// rounded up, then each section lowered while the prediction stays within `room`.
fn refined(counts: &[usize], parts: &[f64], room: f64, order: f64, cap: usize) -> Vec<usize> {
    let c: Vec<f64> = parts
        .iter()
        .zip(counts)
        .map(|(e, &m)| e * (m as f64).powf(order))
        .collect();
    let predict = |m: &[usize]| -> f64 {
        c.iter()
            .zip(m)
            .map(|(c, &m)| c / (m as f64).powf(order))
            .sum()
    };
    let weight: Vec<f64> = c.iter().map(|c| c.powf(1.0 / (order + 1.0))).collect();
    let scale = (weight.iter().sum::<f64>() / room.max(0.0)).powf(1.0 / order);
    let mut out: Vec<usize> = counts
        .iter()
        .zip(&weight)
        .map(|(&m, w)| {
            let want = (w * scale).ceil();
            if want.is_finite() {
                (want as usize).clamp(m, cap.max(m))
            } else {
                cap.max(m)
            }
        })
        .collect();
    // Rounding up overshoots: lower each section in turn while the prediction still fits.
    let mut lowered = true;
    while lowered {
        lowered = false;
        for i in 0..out.len() {
            if out[i] > counts[i] {
                out[i] -= 1;
                if predict(&out) <= room {
                    lowered = true;
                } else {
                    out[i] += 1;
                }
            }
        }
    }
    out
}

/// A tip distance `metres` for people, in millimetres: four decimals, or four significant
/// digits in scientific notation below a micrometre (a tolerance of a picometre is not
/// `0.0000 mm`). Every such distance is finite ([`crate::model::bounds::TIP_DISTANCE`]);
/// another prints as `—`.
pub fn mm(metres: f64) -> String {
    let x = metres * 1e3;
    if !x.is_finite() {
        "— mm".to_string()
    } else if x == 0.0 || x.abs() >= 1e-3 {
        format!("{x:.4} mm")
    } else {
        format!("{x:.3e} mm")
    }
}

/// The cheapest answer whose estimated tip distance from the converged rod is within
/// `tolerance` \[m\] (module docs): the shape, with `report.error_estimate` and `report.auto`
/// filled and a note naming the choice. `base` settings are passed to the rungs of the
/// methods that take them (resolution settings excepted); `control` chooses the input where a
/// cable gives both (default: shortening, as `energy`).
pub fn choose(
    robot: &Robot,
    act: &Actuation,
    scene: &Scene,
    tolerance: f64,
    base: &Settings,
) -> Result<Shape, SolveError> {
    crate::model::bounds::TIP_DISTANCE.check("tolerance", tolerance)?;
    let t0 = Instant::now();
    let mut search = Search {
        robot,
        act,
        scene,
        tolerance,
        base,
        control: base.get("control").unwrap_or("displacement").to_string(),
        solves: 0,
        best: None,
        parts: None,
    };
    let mut failure = None;
    let mut met = false;
    // `energy` without shear, with shear (its model part then 0), the rod.
    let ladders = [
        (MethodKind::Energy, false),
        (MethodKind::Energy, true),
        (MethodKind::Cosserat, false),
    ];
    for (kind, shear) in ladders {
        if let Err(e) = kind.check_support(robot, scene) {
            failure.get_or_insert(e);
            continue;
        }
        match search.walk(&ladder(kind, shear)) {
            Ok(true) => {
                met = true;
                break;
            }
            Ok(false) => {}
            Err(e) => {
                failure.get_or_insert(e);
            }
        }
    }
    let solves = search.solves;
    let Some((mut shape, mut est, setting)) = search.best else {
        return Err(failure.unwrap_or_else(|| SolveError::InvalidInput {
            field: "method".into(),
            reason: "auto found no method for this robot and scene".into(),
        }));
    };
    // The rungs were solved without the output check: the answer handed out passes it.
    crate::check::output(robot, &shape)?;
    let cost = t0.elapsed().as_secs_f64();
    est.cost_s = cost;
    let bound = est.known_parts_m();
    shape.report.notes.push(format!(
        "auto: {} {setting}, estimated {} {} the tolerance {}; {solves} solves in {:.1} µs{}",
        shape.method,
        mm(bound),
        if met { "within" } else { "above" },
        mm(tolerance),
        cost * 1e6,
        if est.model_m.is_none() {
            " (model part unknown: only the discretization part is held to it)"
        } else {
            ""
        }
    ));
    shape.report.auto = Some(AutoReport {
        method: shape.method.clone(),
        setting,
        tolerance_m: tolerance,
        met,
        solves,
        cost_s: cost,
    });
    shape.report.error_estimate = Some(est);
    Ok(shape)
}

/// The request that solves at what an `auto` answer chose (its method, the caller's settings
/// it takes, the input, the chosen resolution): for reach, plan, predict and batches, which
/// solve many actuations at one choice.
pub fn settled(shape: &Shape, base: &Settings) -> Option<SolveRequest> {
    let a = shape.report.auto.as_ref()?;
    let kind = MethodKind::from_name(&a.method)?;
    let shear = a.setting.ends_with(", shear=on");
    let rungs = ladder(kind, shear);
    let rung = match rungs.iter().find(|r| r.describe() == a.setting) {
        Some(r) => r.clone(),
        // An adaptive `energy` rung: `sub-arcs=1,2,4`.
        None => {
            let value = a.setting.strip_suffix(", shear=on").unwrap_or(&a.setting);
            let per = value
                .strip_prefix("sub-arcs=")?
                .split(',')
                .map(|n| n.trim().parse().ok())
                .collect::<Option<Vec<usize>>>()?;
            rungs.first()?.at(per)
        }
    };
    let control = base.get("control").unwrap_or("displacement");
    Some(SolveRequest::new(kind).with_settings(rung_settings(&rung, base, control)))
}

#[cfg(test)]
mod tests {
    #[test]
    fn tip_distances_print_with_their_digits() {
        assert_eq!(super::mm(1e-4), "0.1000 mm");
        assert_eq!(super::mm(0.0), "0.0000 mm");
        assert_eq!(super::mm(1e-12), "1.000e-9 mm");
        assert_eq!(super::mm(100.0), "100000.0000 mm");
        assert_eq!(super::mm(f64::INFINITY), "— mm");
    }
}
