//! Tension-space plans on the soft lung rod beside a nodule (`examples/common/
//! plan_tension_measure.rs`): seeded admissible start/goal pairs of tensions \[N\], insertion
//! and rotation, planned by RRT-Connect; prints the success rate and the median and worst
//! time of a plan.
//!
//! `cargo run --release --example plan_tension [COUNT] [SEED]` (default 50 pairs, seed 1)

#[path = "common/plan_tension_measure.rs"]
mod plan_tension_measure;

fn main() {
    let count: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(50);
    let seed: u64 = std::env::args()
        .nth(2)
        .and_then(|a| a.parse().ok())
        .unwrap_or(1);
    let out = plan_tension_measure::measure(count, seed);
    let mut times: Vec<f64> = out.iter().map(|o| o.seconds).collect();
    times.sort_by(f64::total_cmp);
    let ok = out.iter().filter(|o| o.plan.is_ok()).count();
    for (k, o) in out.iter().enumerate() {
        if let Err(e) = &o.plan {
            println!("pair {k}: {e}");
        }
    }
    let planners = |name: &str| {
        out.iter()
            .filter(|o| o.plan.as_ref().is_ok_and(|p| p.stats.planner == name))
            .count()
    };
    let detours = out
        .iter()
        .filter(|o| {
            o.plan
                .as_ref()
                .is_ok_and(|p| p.stats.checks.edges_rejected > 0)
        })
        .count();
    println!(
        "{ok} of {count} pairs planned ({} by RRT-Connect, {detours} round a refused edge); \
         median {:.1} ms, worst {:.1} ms",
        planners("rrt-connect"),
        times[times.len() / 2] * 1e3,
        times[times.len() - 1] * 1e3
    );
}
