//! Tension-space plans on the soft lung rod (`models/soft/lung_rod.toml`, three tendons inside
//! a 6 mm silicone rod, tensions 0…3.5 N, inserted through a port and turned about it) beside
//! the nodule of `models/soft/nodule.toml`: seeded start/goal pairs, each a uniform draw of
//! tensions, insertion and rotation within the limits kept when its shape is admissible (it
//! solves, does not pass through itself and keeps the 1 mm margin). Shared by
//! `examples/plan_tension.rs` (success rate and median time) and
//! `tests/inverse/plan_tension.rs` (every plan re-checked densely).

use ccrkit::method::run::SolveRequest;
use ccrkit::method::{MethodKind, Settings};
use ccrkit::plan::{plan, Goal, Plan, PlanOptions};
use ccrkit::reach::Space;
use ccrkit::{Model, Scene, SolveError};
use ccrkit_test_support::rng::Rng;

const ROOT: &str = env!("CARGO_MANIFEST_DIR");

/// The request that makes the space one of tensions: `energy` under `control = force` (what
/// `--set control=force` asks on the command line).
pub fn by_tension() -> SolveRequest {
    let mut s = Settings::new();
    s.push("control", "force");
    SolveRequest::new(MethodKind::Energy).with_settings(s)
}

/// The lung rod with the nodule in its scene.
pub fn lung_nodule() -> Model {
    let mut m = Model::from_file(format!("{ROOT}/models/soft/lung_rod.toml")).expect("lung rod");
    let nodule = Scene::from_file(format!("{ROOT}/models/soft/nodule.toml")).expect("nodule");
    m.scene = nodule;
    m
}

/// Start/goal pair `k` of the seeded draws from `seed` (`max_draws` uniform draws at most per
/// end): two admissible points of `space`, or `None` when the draws found none.
pub fn pair(space: &Space, rng: &mut Rng, max_draws: usize) -> Option<(Vec<f64>, Vec<f64>)> {
    let mut end = || {
        (0..max_draws).find_map(|_| {
            let x: Vec<f64> = (0..space.dim())
                .map(|c| rng.range(space.lo[c], space.hi[c]))
                .collect();
            let shape = space.solve(&x, None).ok()?;
            space.admissible(&shape).then_some(x)
        })
    };
    Some((end()?, end()?))
}

/// One planned pair: its outcome and wall time \[s\].
pub struct Outcome {
    /// The plan, or why none was found.
    pub plan: Result<Plan, SolveError>,
    /// Wall time of the plan \[s\].
    pub seconds: f64,
}

/// Plan `count` seeded pairs (from `seed`) on the lung rod beside the nodule, in tension space.
pub fn measure(count: usize, seed: u64) -> Vec<Outcome> {
    let model = lung_nodule();
    let req = by_tension();
    let space = Space::new(&model, &req, false).expect("tension space");
    let mut rng = Rng(seed.wrapping_mul(0x2545_F491_4F6C_DD1D) | 1);
    let mut out = Vec::new();
    while out.len() < count {
        let Some((s, g)) = pair(&space, &mut rng, 50) else {
            continue;
        };
        let opts = PlanOptions {
            seed: seed + out.len() as u64,
            ..PlanOptions::default()
        };
        let t0 = std::time::Instant::now();
        let plan = plan(&model, &req, Some(s), &Goal::Actuation(g), &opts, None);
        out.push(Outcome {
            plan,
            seconds: t0.elapsed().as_secs_f64(),
        });
    }
    out
}
