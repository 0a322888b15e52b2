//! Roadmaps in a generated airway (`examples/common/airway_tasks.rs`): writes the airway of a
//! seed, its lumen scene and the two-segment catheter with its port placed in the trachea
//! (`catheter.toml`) into `DIR`, for `ccrkit roadmap build`; then, once `DIR/roadmap.json`
//! is there, answers `QUERIES` plans from it — from the retracted catheter to the actuation of
//! each reachable target the benchmark draws — and prints how many were found, their times
//! (the thread's CPU and the wall clock) and the query rate, every waypoint checked by the
//! independent dense check against the exact triangles.
//!
//! ```sh
//! cargo run --release --example airway_roadmap [SEED] [DIR] [QUERIES]
//! ccrkit roadmap build DIR/catheter.toml --scene DIR/scene.toml --samples 4000 --expand 8000 --out DIR/roadmap.json
//! cargo run --release --example airway_roadmap [SEED] [DIR] [QUERIES]
//! ```
//!
//! (default seed 11, `DIR` `target/airway-roadmap-SEED`, 8 queries).

#[path = "common/airway_tasks.rs"]
mod airway_tasks;

use airway_tasks::{cpu_seconds, plan_dense_clearance, quantile, Setup, GENERATIONS};
use ccrkit::plan::roadmap::Roadmap;
use ccrkit::plan::{plan, Goal, PlanOptions};
use ccrkit::Model;

fn main() -> anyhow::Result<()> {
    let mut args = std::env::args().skip(1);
    let seed: u64 = args.next().map_or(Ok(11), |s| s.parse())?;
    let dir = args.next().map_or_else(
        || std::path::PathBuf::from(format!("target/airway-roadmap-{seed}")),
        std::path::PathBuf::from,
    );
    let queries: usize = args.next().map_or(Ok(8), |s| s.parse())?;
    let setup = Setup::new(seed, GENERATIONS, &dir)?;
    let model_path = setup.write_model(&dir)?;
    let roadmap_path = dir.join("roadmap.json");
    if !roadmap_path.exists() {
        println!(
            "wrote {}; build the roadmap with\n  ccrkit roadmap build {} --scene {} --out {}\nand run this again",
            dir.display(),
            model_path.display(),
            dir.join("scene.toml").display(),
            roadmap_path.display()
        );
        return Ok(());
    }
    let t = std::time::Instant::now();
    let roadmap = Roadmap::load(&roadmap_path)?;
    println!(
        "roadmap: {} nodes, {} edges, built in {:.1} s ({} solves); loaded in {:.2} s",
        roadmap.nodes.len(),
        roadmap.edges.len(),
        roadmap.build_time_s,
        roadmap.build_solves,
        t.elapsed().as_secs_f64()
    );
    // The model as the command line read it: the roadmap was built for that one.
    let model = Model::from_file(&model_path)?;
    let space = setup.space()?;
    let tasks = setup.tasks(&space, seed, queries, 1, 200 * queries);
    let (mut cpu, mut wall, mut found) = (Vec::new(), Vec::new(), 0);
    let t_all = std::time::Instant::now();
    for task in &tasks {
        let t0 = std::time::Instant::now();
        let c0 = cpu_seconds(t0);
        let p = plan(
            &model,
            &setup.request,
            Some(setup.retracted(&space)),
            &Goal::Actuation(task.u.clone()),
            &PlanOptions::default(),
            Some(&roadmap),
        );
        let (w, c) = (t0.elapsed().as_secs_f64(), cpu_seconds(t0) - c0);
        wall.push(w);
        cpu.push(c);
        match p {
            Ok(p) => {
                let dense = plan_dense_clearance(&setup, &p);
                found += usize::from(dense >= 0.0);
                println!(
                    "query: {} waypoints, {c:.3} s CPU ({w:.3} s wall), dense {:.2} mm, {} (graph nodes {}, solves {}, edges {} of which blocked {}, shortcut removed {})",
                    p.waypoints.len(),
                    dense * 1e3,
                    p.stats.planner,
                    p.stats.tree_nodes,
                    p.stats.checks.solves,
                    p.stats.checks.edges_checked,
                    p.stats.checks.edges_rejected,
                    p.stats.shortcut_removed,
                );
            }
            Err(e) => println!("query failed: {c:.3} s CPU ({w:.3} s wall): {e}"),
        }
    }
    let total = t_all.elapsed().as_secs_f64();
    println!(
        "{found} of {} queries planned; CPU median {:.3} s, worst {:.3} s; wall median {:.3} s; {:.1} queries per second of wall clock over all",
        tasks.len(),
        quantile(&mut cpu, 0.5),
        quantile(&mut cpu, 1.0),
        quantile(&mut wall, 0.5),
        tasks.len() as f64 / total
    );
    Ok(())
}
