//! The reach measurement on seeded random robots with a port (`ccrkit_test_support::
//! port_robots`): one target per robot, the tip of random admissible inputs — shortenings, or
//! tensions solved by `energy` under `control = force` whose reported shortenings lie within
//! the limits — at a random insertion and rotation within the port's limits. A reach succeeds
//! when it says reached and its answer, solved forward as `ccrkit solve` does, puts the tip
//! within 1e-6 m of the target. Shared by `examples/reach_random_ports.rs` (timing) and
//! `tests/inverse/reach_random.rs` (rate).

use ccrkit::actuation::{Actuation, CableDrive};
use ccrkit::method::run::SolveRequest;
use ccrkit::method::{MethodKind, Settings};
use ccrkit::reach::{reach, ReachOptions, Space, Target};
use ccrkit::Model;
use ccrkit_test_support::port_robots::port_robot;
use ccrkit_test_support::rng::Rng;

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
            let mut s = Settings::new();
            s.push("control", "force");
            let shape = SolveRequest::new(MethodKind::Energy)
                .with_settings(s)
                .run(&m)
                .ok()?
                .shape;
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
    let tip = nalgebra::Vector3::from(t);
    let t0 = std::time::Instant::now();
    let r = reach(
        &model,
        &req,
        &Target { tip, tangent: None },
        &ReachOptions::default(),
    );
    let seconds = t0.elapsed().as_secs_f64();
    let (ok, distance, reason) = match r {
        Ok(r) => {
            let again = space.solve_as_cli(&model, &r.u).map(|s| s.tip());
            let d = again.map_or(f64::INFINITY, |a| (a - tip).norm());
            (r.reached && d <= 1e-6, d, r.reason)
        }
        Err(e) => (false, f64::INFINITY, e.to_string()),
    };
    Some(Outcome {
        seed,
        cables: model.robot.cables.len(),
        tension_driven: robot.tension_driven,
        ok,
        seconds,
        distance,
        reason,
    })
}
