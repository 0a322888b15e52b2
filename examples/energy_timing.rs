//! Time `--method energy` on one model file: `cargo run --release --example energy_timing
//! [MODEL.toml] [SUB_ARCS] [REPEAT]`; `CHORD=1` for the chord measure, `WARM=1` to start from
//! the solution of a 10 % smaller actuation.

use ccrkit::method::energy::Energy;
use ccrkit::{Method, Model, Scene};
use std::time::Instant;

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let file = args
        .first()
        .cloned()
        .unwrap_or("models/paper/case3.toml".into());
    let sa: usize = args.get(1).map(|s| s.parse()).transpose()?.unwrap_or(4);
    let reps: usize = args.get(2).map(|s| s.parse()).transpose()?.unwrap_or(2000);
    let model = Model::from_file(&file)?;
    let e =
        Energy::default()
            .with_sub_arcs(sa)
            .with_cable_length(if std::env::var("CHORD").is_ok() {
                ccrkit::actuation::LengthMeasure::Chord
            } else {
                ccrkit::actuation::LengthMeasure::Path
            });
    let scene = Scene::empty();
    // WARM=1: start from the solution of a 10 % smaller actuation.
    let mut before = model.actuation.clone();
    for (ci, d) in before.cables.iter_mut().enumerate() {
        if let Some(f) = model.actuation.shortening_fraction(&model.robot, ci) {
            d.shorten = Some(ccrkit::Shortening::Fraction(0.9 * f));
        }
    }
    let prev = e.solve(&model.robot, &before, &scene, None)?;
    let warm = std::env::var("WARM").is_ok().then_some(&prev);
    let mut times = Vec::with_capacity(reps);
    let mut it = 0;
    for _ in 0..reps {
        let t = Instant::now();
        let s = e.solve(&model.robot, &model.actuation, &scene, warm)?;
        times.push(t.elapsed().as_secs_f64());
        it = s.report.iterations;
    }
    times.sort_by(f64::total_cmp);
    println!(
        "{file}: sub_arcs {sa}, warm {}, {it} iterations, median {:.1} µs",
        warm.is_some(),
        times[reps / 2] * 1e6
    );
    Ok(())
}
