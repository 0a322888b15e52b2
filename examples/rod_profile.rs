//! A fixed number of rod solves for instruction-count profiling (`valgrind --tool=callgrind`):
//! `cargo run --release --example rod_profile -- <case> [repeats]`, case one of `lung24`
//! (the 24-section soft lung rod, tension-driven), `randomN` (seeded random robot N),
//! `case1`..`case3` (the paper cases, force
//! control), `case1-disp`..`case3-disp` (displacement control), each unloaded (the rod's
//! unloaded path), and suffixes in any order: `-shoot` always shoots (`solver = shooting`),
//! `-check` keeps the stability test, `-loaded` adds lateral gravity (`[0, −9.81, 0]` m/s²)
//! on a nitinol backbone (6450 kg/m³) and a tip force `[0.05, 0, 0]` N (the rod then shoots). Every solve at the default
//! settings (`CCRKIT_PROFILE_STEPS=N`: N RK4 steps per section) with `stability = skip`
//! unless `-check`; prints the tip of the last answer so nothing is optimised away. A third
//! argument `accuracy` also prints the tip's distance to the converged rod (shooting, 64 RK4
//! steps per section, residual 1e-10 N).

use ccrkit::actuation::Input;
use ccrkit::method::cosserat::Cosserat;
use ccrkit::{Method, Model, Scene};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let case = args.next().unwrap_or_else(|| "lung24".into());
    let repeats: usize = args.next().map(|s| s.parse()).transpose()?.unwrap_or(100);
    let mut name = case.as_str();
    let (mut unloaded, mut check, mut loaded) = (true, false, false);
    loop {
        if let Some(n) = name.strip_suffix("-shoot") {
            (name, unloaded) = (n, false);
        } else if let Some(n) = name.strip_suffix("-check") {
            (name, check) = (n, true);
        } else if let Some(n) = name.strip_suffix("-loaded") {
            (name, loaded) = (n, true);
        } else {
            break;
        }
    }
    let mut base = Cosserat {
        check_stability: check,
        ..Cosserat::full()
    };
    if let Ok(n) = std::env::var("CCRKIT_PROFILE_STEPS") {
        base = base.with_steps(n.parse()?);
    }
    let mut model = match name {
        "lung24" => Model::from_toml_str(&ccrkit_test_support::soft::lung_rod_toml(
            24,
            [1.5, 2.5, 0.7],
        ))?,
        other if other.starts_with("random") => {
            ccrkit::study::random::random_model(other.trim_start_matches("random").parse()?)?
        }
        other => Model::from_file(format!(
            "{}/models/paper/{}.toml",
            env!("CARGO_MANIFEST_DIR"),
            other.trim_end_matches("-disp")
        ))?,
    };
    if loaded {
        model.robot.backbone.density = 6450.0; // nitinol
        model.robot.loads.gravity = nalgebra::Vector3::new(0.0, -9.81, 0.0);
        model.robot.loads.tip_force = nalgebra::Vector3::new(0.05, 0.0, 0.0);
    }
    let control = match name.ends_with("-disp") {
        true => Input::Shortening,
        false => Input::Tension,
    };
    let m = base.with_unloaded(unloaded).with_control(control);
    let scene = Scene::empty();
    let mut tip = nalgebra::Vector3::zeros();
    for _ in 0..repeats {
        let shape = m.solve(&model.robot, &model.actuation, &scene, None)?;
        tip = shape.tip();
    }
    println!("{case} x{repeats}: tip {tip:?}");
    if args.next().as_deref() == Some("accuracy") {
        let converged = Cosserat {
            tolerance: 1e-10,
            ..m.clone().with_unloaded(false).with_steps(
                std::env::var("CCRKIT_PROFILE_REF_STEPS").map_or(Ok(64), |s| s.parse())?,
            )
        };
        let reference = converged.solve(&model.robot, &model.actuation, &scene, None)?;
        let shape = m.solve(&model.robot, &model.actuation, &scene, None)?;
        println!(
            "tip error {:.4} µm, {} iterations; notes: {:?}",
            shape.tip_distance(&reference) * 1e6,
            shape.report.iterations,
            shape.report.notes
        );
    }
    Ok(())
}
