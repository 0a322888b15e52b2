//! The reach measurement on seeded random robots with a port (2–6 cables, straight and
//! helical, tied at the tip or at inner disks, targets made by shortenings or by tensions):
//! success rate (forward-checked to 1e-6 m) and the median and worst time of a reach.
//!
//! `cargo run --release --example reach_random_ports [COUNT] [FIRST_SEED] [tension]` (default
//! 200 robots from seed 1; `tension`: search tensions within `[0, T_max]` N instead of
//! shortenings, `reach_measure::measure_tensions`)

#[path = "common/reach_measure.rs"]
mod reach_measure;

fn main() {
    let count: u64 = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(200);
    let first: u64 = std::env::args()
        .nth(2)
        .and_then(|a| a.parse().ok())
        .unwrap_or(1);
    let tension = std::env::args().nth(3).as_deref() == Some("tension");
    let mut out = Vec::new();
    let mut seed = first - 1;
    while (out.len() as u64) < count {
        seed += 1;
        let o = if tension {
            reach_measure::measure_tensions(seed)
        } else {
            reach_measure::measure(seed)
        };
        if let Some(o) = o {
            if !o.ok {
                println!(
                    "robot {} ({} cables, {}): not reached, {:.2e} m away: {}",
                    o.seed,
                    o.cables,
                    if o.tension_driven {
                        "tensions"
                    } else {
                        "shortenings"
                    },
                    o.distance,
                    o.reason
                );
            }
            out.push(o);
        }
    }
    let ok = out.iter().filter(|o| o.ok).count();
    let mut t: Vec<f64> = out.iter().map(|o| o.seconds * 1e3).collect();
    t.sort_by(f64::total_cmp);
    let tension = out.iter().filter(|o| o.tension_driven).count();
    let mut solves: Vec<usize> = out.iter().map(|o| o.solves).collect();
    solves.sort_unstable();
    let mean = solves.iter().sum::<usize>() as f64 / solves.len() as f64;
    println!(
        "forward solves per reach: median {}, mean {mean:.1}, worst {}",
        solves[solves.len() / 2],
        solves[solves.len() - 1]
    );
    println!(
        "{ok} of {} reached ({:.1} %; {tension} with tension-made targets), reach time median {:.1} ms, \
         90th percentile {:.1} ms, worst {:.1} ms",
        out.len(),
        100.0 * ok as f64 / out.len() as f64,
        t[t.len() / 2],
        t[t.len() * 9 / 10],
        t[t.len() - 1]
    );
}
