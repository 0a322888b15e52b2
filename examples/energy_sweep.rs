//! Energy model against the Cosserat rod (displacement control, same lengths): RMS over the
//! disks, tension errors and solve time, per sub-arc count and cable-length measure.
//!
//! `cargo run --release --example energy_sweep [OUT_DIR] [--model MODEL.toml ...]`
//!
//! Like every example, the first argument is the output folder (default `target`); it writes
//! `OUT_DIR/energy_sweep.csv`. Models default to the three paper cases.

use ccrkit::actuation::{Input, LengthMeasure};
use ccrkit::method::cosserat::Cosserat;
use ccrkit::method::energy::Energy;
use ccrkit::{Method, Model, Scene};
use std::time::Instant;

fn main() -> anyhow::Result<()> {
    let mut args = std::env::args().skip(1).peekable();
    let out = match args.peek() {
        Some(a) if !a.starts_with("--") => {
            std::path::PathBuf::from(args.next().unwrap_or_default())
        }
        _ => std::path::PathBuf::from("target"),
    };
    let mut files: Vec<String> = vec![];
    while let Some(a) = args.next() {
        match (a.as_str(), args.next()) {
            ("--model", Some(f)) => files.push(f),
            _ => anyhow::bail!("usage: energy_sweep [OUT_DIR] [--model MODEL.toml ...]"),
        }
    }
    if files.is_empty() {
        files = (1..=3)
            .map(|n| format!("models/paper/case{n}.toml"))
            .collect();
    }
    std::fs::create_dir_all(&out)?;
    let mut csv = String::from("model,length,sub_arcs,rms_m,iterations,time_s\n");
    let scene = Scene::empty();
    for f in &files {
        let model = Model::from_file(f)?;
        for (len, cl) in [
            (LengthMeasure::Path, LengthMeasure::Path),
            (LengthMeasure::Chord, LengthMeasure::Chord),
        ] {
            let rod = Cosserat {
                tolerance: 1e-11,
                ..Cosserat::full()
                    .with_control(Input::Shortening)
                    .with_length(len)
                    .with_steps(40)
            };
            let cos = rod.solve(&model.robot, &model.actuation, &scene, None)?;
            for sa in [1, 2, 3, 4, 6, 8] {
                if cl == LengthMeasure::Chord && sa > 4 {
                    continue;
                }
                let e = Energy::default().with_sub_arcs(sa).with_cable_length(cl);
                let t = Instant::now();
                let reps = 20;
                let mut shape = None;
                for _ in 0..reps {
                    shape = Some(e.solve(&model.robot, &model.actuation, &scene, None)?);
                }
                let dt = t.elapsed().as_secs_f64() / reps as f64;
                let s = shape.expect("solved");
                let rms = s.rms_distance(&cos).unwrap_or(f64::NAN);
                let tens: Vec<String> = s
                    .cables
                    .iter()
                    .zip(&cos.cables)
                    .map(|(a, b)| {
                        let (ta, tb) = (a.tension.unwrap_or(0.0), b.tension.unwrap_or(0.0));
                        format!(
                            "{} {:.4}/{:.4} N ({:+.2} %)",
                            a.name,
                            ta,
                            tb,
                            100.0 * (ta - tb) / tb.max(1e-12)
                        )
                    })
                    .collect();
                csv += &format!("{f},{len:?},{sa},{rms:e},{},{dt:e}\n", s.report.iterations);
                println!(
                    "{f} {len:?} sub_arcs {sa}: RMS {:.4} mm, {} it, {:.1} µs, [{}]",
                    rms * 1e3,
                    s.report.iterations,
                    dt * 1e6,
                    tens.join(", ")
                );
            }
        }
    }
    let path = out.join("energy_sweep.csv");
    ccrkit::output::write_file(&path, csv)?;
    println!("wrote {}", path.display());
    Ok(())
}
