//! A fixed number of rod solves for instruction-count profiling (`valgrind --tool=callgrind`):
//! `cargo run --release --example rod_profile -- <case> [repeats]`, case one of `lung24`
//! (the soft lung rod, tension-driven, unloaded path), `lung24-shoot` (the same rod shooting),
//! `case1`..`case3` (the paper cases, force control, shooting), `case1-disp`..`case3-disp`
//! (displacement control). Every solve at the default settings with `stability = skip`;
//! prints the tip of the last answer so nothing is optimised away.

use ccrkit::actuation::Input;
use ccrkit::method::cosserat::Cosserat;
use ccrkit::{Method, Model, Scene};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let case = args.next().unwrap_or_else(|| "lung24".into());
    let repeats: usize = args.next().map(|s| s.parse()).transpose()?.unwrap_or(100);
    let base = Cosserat {
        check_stability: false,
        ..Cosserat::full()
    };
    let (model, m) = match case.as_str() {
        "lung24" | "lung24-shoot" => (
            Model::from_toml_str(&ccrkit_test_support::soft::lung_rod_toml(
                24,
                [1.5, 2.5, 0.7],
            ))?,
            base.with_unloaded(case == "lung24"),
        ),
        other => {
            let (n, disp) = match other.strip_suffix("-disp") {
                Some(n) => (n, true),
                None => (other, false),
            };
            let file = format!("{}/models/paper/{n}.toml", env!("CARGO_MANIFEST_DIR"));
            let control = if disp {
                Input::Shortening
            } else {
                Input::Tension
            };
            (Model::from_file(file)?, base.with_control(control))
        }
    };
    let scene = Scene::empty();
    let mut tip = nalgebra::Vector3::zeros();
    for _ in 0..repeats {
        let shape = m.solve(&model.robot, &model.actuation, &scene, None)?;
        tip = shape.tip();
    }
    println!("{case} x{repeats}: tip {tip:?}");
    Ok(())
}
