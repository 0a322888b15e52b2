//! Profiling aid for warm starts of the energy model (issue 16): solve a paper case `repeat`
//! times cold, or warm from the solution of a 2 % smaller actuation, for callgrind:
//! `valgrind --tool=callgrind target/release/examples/energy_warm_profile 2 warm 50`.

use ccrkit::method::energy::Energy;
use ccrkit::{Method, Model, Scene};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let case = args.get(1).map_or("2", |s| s.as_str());
    let warm = args.get(2).is_some_and(|s| s == "warm");
    let repeat: usize = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(1);
    let model = Model::from_file(format!("models/paper/case{case}.toml")).expect("model");
    let (scene, method) = (Scene::empty(), Energy::default());
    let prev = method
        .solve(&model.robot, &model.actuation.scaled(0.98), &scene, None)
        .expect("previous");
    let mut iterations = 0;
    for _ in 0..repeat {
        let s = method
            .solve(
                &model.robot,
                &model.actuation,
                &scene,
                warm.then_some(&prev),
            )
            .expect("solve");
        iterations += s.report.iterations;
    }
    println!("case {case}, warm {warm}: {iterations} iterations in {repeat} solves");
}
