//! The reach measurement on seeded random robots with a port (`ccrkit_test_support::
//! port_robots`): one target per robot, the tip of random admissible inputs — shortenings, or
//! tensions solved by `energy` under `control = force` whose reported shortenings lie within
//! the limits — at a random insertion and rotation within the port's limits. A reach succeeds
//! when it says reached and its answer, solved forward as `ccrkit solve` does, puts the tip
//! within 1e-6 m of the target. Shared by `examples/reach_random_ports.rs` (timing) and
//! `tests/inverse/reach_random.rs` (rate).
//!
//! In tension space ([`measure_tensions`]): the same robots with tension limits `[0, T_max]`,
//! searched by `energy` under `control = force`, targets the tips of random tensions within
//! them at a random insertion and rotation.

use ccrkit::actuation::{Actuation, CableDrive};
use ccrkit::method::run::SolveRequest;
use ccrkit::method::{MethodKind, Settings};
use ccrkit::reach::{reach, ReachOptions, Space, Target};
use ccrkit::Model;
use ccrkit_test_support::port_robots::port_robot;
use ccrkit_test_support::rng::Rng;

/// The request of the tension-space measurement: `energy` under `control = force`.
pub fn by_tension() -> SolveRequest {
    let mut s = Settings::new();
    s.push("control", "force");
    SolveRequest::new(MethodKind::Energy).with_settings(s)
}

/// One robot's outcome.
pub struct Outcome {
    /// Seed of the robot.
    pub seed: u64,
    /// Cables and whether targets were tension-made.
    pub cables: usize,
    pub tension_driven: bool,
    /// Reached and forward-checked to 1e-6 m.
    pub ok: bool,
    /// Wall time of the reach \[s\].
    pub seconds: f64,
    /// Forward solves the reach took (0 when it failed with an error).
    pub solves: usize,
    /// The answer's distance from the target \[m\] and its reason when not reached.
    pub distance: f64,
    pub reason: String,
}

/// The target of robot `seed`, if its draw is admissible (`None`: the forward solve failed,
/// or a tension draw needs shortenings beyond the limits).
fn target(model: &Model, space: &Space, rng: &mut Rng, tension: Option<f64>) -> Option<[f64; 3]> {
    let n = space.dim();
    let k = space.cables();
    let x: Vec<f64> = (0..n)
        .map(|c| rng.range(space.lo[c], space.hi[c]))
        .collect();
    let tip = match tension {
        None => space.solve_as_cli(model, &x).ok()?.tip(),
        Some(most) => {
            let mut m = model.clone();
            m.actuation = Actuation {
                cables: (0..k)
                    .map(|_| CableDrive {
                        tension: Some(rng.range(0.0, most)),
                        ..CableDrive::default()
                    })
                    .collect(),
                insertion: Some(x[k]),
                rotation: Some(x[k + 1]),
            };
            let shape = by_tension().run(&m).ok()?.shape;
            let inside = shape.cables.iter().enumerate().all(|(c, p)| {
                p.shortening
                    .is_some_and(|u| u >= space.lo[c] && u <= space.hi[c])
            });
            if !inside {
                return None;
            }
            shape.tip()
        }
    };
    Some([tip.x, tip.y, tip.z])
}

/// Measure robot `seed` (`None` when its target draw is not admissible).
pub fn measure(seed: u64) -> Option<Outcome> {
    let robot = port_robot(seed);
    let model = Model::from_toml_str(&robot.toml).ok()?;
    let req = SolveRequest::new(MethodKind::Energy);
    let space = Space::new(&model, &req, false).ok()?;
    let mut rng = Rng(seed.wrapping_mul(0x2545_F491_4F6C_DD1D) | 1);
    let tension = robot.tension_driven.then_some(robot.max_tension);
    let t = (0..5).find_map(|_| target(&model, &space, &mut rng, tension))?;
    run(seed, &model, &req, &space, t, robot.tension_driven)
}

/// Measure robot `seed` in tension space: its cables limited to `[0, T_max]` N, searched by
/// tension; the target the tip of random tensions within them (`None` when that solve fails).
pub fn measure_tensions(seed: u64) -> Option<Outcome> {
    let robot = port_robot(seed);
    let mut text = robot.toml.clone();
    let cables = Model::from_toml_str(&text).ok()?.robot.cables.len();
    for c in 0..cables {
        text += &format!("[limits.c{c}]\ntension = [0.0, {}]\n", robot.max_tension);
    }
    let model = Model::from_toml_str(&text).ok()?;
    let req = by_tension();
    let space = Space::new(&model, &req, false).ok()?;
    let mut rng = Rng(seed.wrapping_mul(0x2545_F491_4F6C_DD1D) | 1);
    let x: Vec<f64> = (0..space.dim())
        .map(|c| rng.range(space.lo[c], space.hi[c]))
        .collect();
    let tip = space.solve_as_cli(&model, &x).ok()?.tip();
    run(seed, &model, &req, &space, [tip.x, tip.y, tip.z], true)
}

/// Reach `t` on `model` and check the answer forward.
fn run(
    seed: u64,
    model: &Model,
    req: &SolveRequest,
    space: &Space,
    t: [f64; 3],
    tension_driven: bool,
) -> Option<Outcome> {
    let tip = nalgebra::Vector3::from(t);
    let t0 = std::time::Instant::now();
    let r = reach(
        model,
        req,
        &Target { tip, tangent: None },
        &ReachOptions::default(),
    );
    let seconds = t0.elapsed().as_secs_f64();
    let (ok, distance, reason, solves) = match r {
        Ok(r) => {
            let again = space.solve_as_cli(model, &r.u).map(|s| s.tip());
            let d = again.map_or(f64::INFINITY, |a| (a - tip).norm());
            (r.reached && d <= 1e-6, d, r.reason, r.solves)
        }
        Err(e) => (false, f64::INFINITY, e.to_string(), 0),
    };
    Some(Outcome {
        seed,
        cables: model.robot.cables.len(),
        tension_driven,
        ok,
        seconds,
        solves,
        distance,
        reason,
    })
}
