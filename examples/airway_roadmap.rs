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
use ccrkit::reach::Space;
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
    let goals: Vec<Goal> = tasks.iter().map(|t| Goal::Actuation(t.u.clone())).collect();
    let start = setup.retracted(&space);
    let opts = PlanOptions::default();
    // Each query alone (`ccrkit plan --roadmap`), then all in one run of queries that keeps
    // the roadmap's nodes and edges it validated.
    let mut rows = Vec::new();
    rows.push(run("each query alone", &setup, &goals, |g| {
        plan(
            &model,
            &setup.request,
            Some(start.clone()),
            g,
            &opts,
            Some(&roadmap),
        )
    }));
    let file_space = Space::new(&model, &setup.request, false)?;
    let mut session = roadmap.queries(&model, &setup.request, &file_space, None)?;
    rows.push(run("one run of queries", &setup, &goals, |g| {
        session.plan(Some(start.clone()), g, &opts)
    }));
    for r in rows {
        println!("{r}");
    }
    Ok(())
}

/// Answer every goal by `query`, each answer through the dense check; the summary line.
fn run(
    name: &str,
    setup: &Setup,
    goals: &[Goal],
    mut query: impl FnMut(&Goal) -> Result<ccrkit::plan::Plan, ccrkit::SolveError>,
) -> String {
    let (mut cpu, mut wall, mut found) = (Vec::new(), Vec::new(), 0);
    for goal in goals {
        let t0 = std::time::Instant::now();
        let c0 = cpu_seconds(t0);
        let p = query(goal);
        let (w, c) = (t0.elapsed().as_secs_f64(), cpu_seconds(t0) - c0);
        wall.push(w);
        cpu.push(c);
        match p {
            Ok(p) => {
                let dense = plan_dense_clearance(setup, &p);
                found += usize::from(dense >= 0.0);
                println!(
                    "{name}: {} waypoints, {c:.3} s CPU ({w:.3} s wall), dense {:.2} mm; \
                     graph nodes {}, solves {}, edges checked {} (blocked {}), repaired {}",
                    p.waypoints.len(),
                    dense * 1e3,
                    p.stats.tree_nodes,
                    p.stats.checks.solves,
                    p.stats.checks.edges_checked,
                    p.stats.checks.edges_rejected,
                    p.stats.edges_repaired,
                );
            }
            Err(e) => println!("{name}: failed, {c:.3} s CPU ({w:.3} s wall): {e}"),
        }
    }
    let total: f64 = cpu.iter().sum();
    format!(
        "{name}: {found} of {} planned and densely clear ({:.0} %); CPU median {:.3} s, worst {:.3} s; \
         {:.1} queries per CPU-second; wall median {:.3} s",
        goals.len(),
        100.0 * found as f64 / goals.len().max(1) as f64,
        quantile(&mut cpu, 0.5),
        quantile(&mut cpu, 1.0),
        goals.len() as f64 / total,
        quantile(&mut wall, 0.5),
    )
}
