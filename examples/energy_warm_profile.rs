//! Profiling aid for warm starts of the energy model: solve a paper case `repeat`
//! times cold, or warm from the solution of a smaller actuation (the fraction FRAC of it, default
//! 0.98: 2 % smaller), for callgrind:
//! `valgrind --tool=callgrind target/release/examples/energy_warm_profile CASE [cold|warm] [REPEAT] [FRAC]`,
//! e.g. `… energy_warm_profile 2 warm 50 0.9`.

use ccrkit::method::energy::Energy;
use ccrkit::{Method, Model, Scene};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let case = args.get(1).map_or("2", |s| s.as_str());
    let warm = args.get(2).is_some_and(|s| s == "warm");
    let repeat: usize = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(1);
    let frac: f64 = match args.get(4) {
        None => 0.98,
        Some(f) => match f.parse::<f64>() {
            Ok(v) if v.is_finite() && v > 0.0 => v,
            _ => {
                eprintln!("FRAC must be a number > 0, got `{f}`");
                std::process::exit(2);
            }
        },
    };
    let model = Model::from_file(format!("models/paper/case{case}.toml")).expect("model");
    let (scene, method) = (Scene::empty(), Energy::default());
    let prev = method
        .solve(&model.robot, &model.actuation.scaled(frac), &scene, None)
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
