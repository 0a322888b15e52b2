//! The planning benchmark in generated airways (`examples/common/airway_tasks.rs`): for each
//! airway seed, targets beyond the trachea (at a chosen depth) labelled reachable by a clear forward solve; each
//! is reached (`reach`, forward-checked to 1e-6 m), and its own actuation is planned to cold
//! from the retracted catheter (`plan`, RRT-Connect); every answer and every waypoint goes through the
//! independent dense check against the exact triangles. Prints the success rates over the
//! reachable targets, the median and worst times, and the smallest dense clearance.
//!
//! `cargo run --release --example airway_benchmark [FIRST_SEED] [SEEDS] [TARGETS] [DEPTH]`
//! (default seeds 11–12, 4 targets each, in generation 1 or deeper; `DEPTH` 2: two
//! generations below the trachea or deeper, fewer when the draws find fewer)

#[path = "common/airway_tasks.rs"]
mod airway_tasks;

use airway_tasks::{measure, quantile, GENERATIONS};

fn main() -> anyhow::Result<()> {
    let mut args = std::env::args().skip(1);
    let first: u64 = args.next().map_or(Ok(11), |s| s.parse())?;
    let seeds: u64 = args.next().map_or(Ok(2), |s| s.parse())?;
    let targets: usize = args.next().map_or(Ok(4), |s| s.parse())?;
    let depth: u32 = args.next().map_or(Ok(1), |s| s.parse())?;
    let dir = std::env::temp_dir().join(format!("ccrkit-airway-benchmark-{}", std::process::id()));
    let mut all = Vec::new();
    for seed in first..first + seeds {
        let m = measure(
            seed,
            GENERATIONS,
            targets,
            depth,
            &dir.join(seed.to_string()),
        )?;
        for o in &m {
            println!(
                "seed {seed} generation {}: reach {} {:.2} s CPU ({:.2} s wall; dense {:.2} mm), plan {} {:.2} s CPU ({:.2} s wall; {} waypoints, dense {:.2} mm){}",
                o.generation,
                if o.reached { "ok" } else { "missed" },
                o.reach_cpu_s,
                o.reach_s,
                o.reach_dense * 1e3,
                if o.planned { "ok" } else { "failed" },
                o.plan_cpu_s,
                o.plan_s,
                o.waypoints,
                o.plan_dense * 1e3,
                if o.reason.is_empty() { String::new() } else { format!(": {}", o.reason) }
            );
        }
        all.extend(m);
    }
    std::fs::remove_dir_all(&dir).ok();
    let n = all.len();
    let reached = all.iter().filter(|o| o.reached).count();
    let planned = all.iter().filter(|o| o.planned).count();
    let mut reach_t: Vec<f64> = all.iter().map(|o| o.reach_cpu_s).collect();
    let mut plan_t: Vec<f64> = all.iter().map(|o| o.plan_cpu_s).collect();
    let mut reach_w: Vec<f64> = all.iter().map(|o| o.reach_s).collect();
    let mut plan_w: Vec<f64> = all.iter().map(|o| o.plan_s).collect();
    // Over the answers found (a failed plan has no waypoint).
    let dense = all
        .iter()
        .flat_map(|o| [o.reach_dense, o.plan_dense])
        .filter(|d| *d > f64::NEG_INFINITY)
        .fold(f64::INFINITY, f64::min);
    println!(
        "{n} reachable targets in {seeds} airways: reach {reached} ({:.0} %), CPU median {:.2} s, worst {:.2} s \
         (wall {:.2} s, {:.2} s); plan {planned} ({:.0} %), cold CPU median {:.2} s, worst {:.2} s (wall {:.2} s, \
         {:.2} s); smallest dense clearance of an answer or waypoint {:.3} mm",
        100.0 * reached as f64 / n.max(1) as f64,
        quantile(&mut reach_t, 0.5),
        quantile(&mut reach_t, 1.0),
        quantile(&mut reach_w, 0.5),
        quantile(&mut reach_w, 1.0),
        100.0 * planned as f64 / n.max(1) as f64,
        quantile(&mut plan_t, 0.5),
        quantile(&mut plan_t, 1.0),
        quantile(&mut plan_w, 0.5),
        quantile(&mut plan_w, 1.0),
        dense * 1e3
    );
    Ok(())
}
