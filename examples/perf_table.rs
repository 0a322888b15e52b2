//! Regenerates the one table of benchmark medians in `docs/guide/performance.md` (between its
//! `performance-table` markers) from criterion's results, so the guide never carries a number
//! typed by hand.
//!
//! ```text
//! cargo run --release --example perf_table                 # run every benchmark, then write the table
//! cargo run --release --example perf_table -- solve energy # run these benches again, then write it
//! cargo run --release --example perf_table -- --no-run     # write it from target/criterion as it is
//! ```
//!
//! Each bench target is listed with `cargo bench --bench B -- --list`, run with
//! `--warm-up-time 1 --measurement-time 3`, and every benchmark it lists becomes one row:
//! criterion's median (`target/criterion/**/new/estimates.json`) with its 95 % confidence
//! interval, and the throughput where the bench declares one. A benchmark without results is an
//! error naming it, never a row left out. The table ends with a checksum of its text, which
//! `tests/docs/main.rs` checks, so an edit by hand fails the tests.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

/// The bench targets in the table's order, each with what one iteration is.
const BENCHES: &[(&str, &str)] = &[
    (
        "solve",
        "one solve of a paper case by a section solver (`geometric`, `geometric-squared`)",
    ),
    (
        "energy",
        "one `energy` solve of a paper case: cold, or warm from a 10 % / 2 % smaller actuation",
    ),
    (
        "cosserat",
        "one `cosserat` solve of a paper case: force or displacement control, loaded, cold or warm",
    ),
    (
        "obstacles",
        "paper case I in a scene: a `geometric` solve (no prefix), an `energy` solve (`energy_`), the broad phase alone (`broad_phase_`)",
    ),
    (
        "scene",
        "reading a scene file of 0 or 1000 obstacles, TOML or JSON",
    ),
    (
        "reach",
        "`reach` on paper case I, through a port (`port_behind_block`) and on the soft lung rod in tension space (`lung_rod_tension`); `plan` around a ball and in the vessel",
    ),
    (
        "clearance",
        "one whole-shape clearance of the catheter in a generated airway of 110 988 triangles, a seeded reachable target's shape per iteration: exact on the triangles (`reach::clearance`, `airway_1e5`) and the grid's certified bounds alone (`reach::clearance_bounds`, `airway_1e5_grid`)",
    ),
    (
        "predict",
        "`predict` on the 1620 rows of FTDCR v4 train, `sub-arcs` 1 and 4, on every core",
    ),
    (
        "batch",
        "10 000 `energy` solves of paper case I: a Rust loop, `solve_batch` on 1 and 2 threads",
    ),
];

/// The markers around the generated table.
const BEGIN: &str = "<!-- performance-table:begin -->";
const END: &str = "<!-- performance-table:end -->";

fn main() {
    if let Err(e) = run() {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
}

fn run() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let no_run = args.iter().any(|a| a == "--no-run");
    let chosen: Vec<&str> = args
        .iter()
        .filter(|a| !a.starts_with("--"))
        .map(|a| a.as_str())
        .collect();
    for c in &chosen {
        if !BENCHES.iter().any(|(b, _)| b == c) {
            return Err(format!(
                "unknown bench `{c}` (one of: {})",
                names().join(", ")
            ));
        }
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let target =
        std::env::var_os("CARGO_TARGET_DIR").map_or_else(|| root.join("target"), PathBuf::from);
    let load = std::fs::read_to_string("/proc/loadavg").unwrap_or_default();
    let load = load.split_whitespace().next().unwrap_or("unknown");
    // How the results were made: kept beside them, so `--no-run` can say it again.
    let note = target.join("criterion").join("ccrkit-perf-table.txt");
    let how = if no_run {
        std::fs::read_to_string(&note).map_or_else(
            |_| "as found in `target/criterion`".to_string(),
            |s| s.trim().to_string(),
        )
    } else {
        let which = if chosen.is_empty() {
            "every bench".to_string()
        } else {
            chosen.join(", ")
        };
        format!(
            "on {} by `cargo run --release --example perf_table` ({which}, load average {load} \
             at the start)",
            today()
        )
    };
    let mut ids = BTreeMap::new();
    for (bench, _) in BENCHES {
        ids.insert(*bench, list(root, bench)?);
        let run_it = !no_run && (chosen.is_empty() || chosen.contains(bench));
        if run_it {
            cargo(
                root,
                &[
                    "bench",
                    "--bench",
                    bench,
                    "--",
                    "--warm-up-time",
                    "1",
                    "--measurement-time",
                    "3",
                ],
            )?;
        }
    }
    if !no_run {
        ccrkit::output::write_file(&note, &how)
            .map_err(|e| format!("cannot write {}: {e}", note.display()))?;
    }
    let results = read_results(&target.join("criterion"))?;
    let table = table(&ids, &results, &how, &commit(root))?;
    let path = root.join("docs/guide/performance.md");
    let doc = std::fs::read_to_string(&path)
        .map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    let (head, rest) = doc
        .split_once(BEGIN)
        .ok_or(format!("{} has no {BEGIN}", path.display()))?;
    let (_, tail) = rest
        .split_once(END)
        .ok_or(format!("{} has no {END}", path.display()))?;
    let out = format!("{head}{BEGIN}\n{table}{END}{tail}");
    ccrkit::output::write_file(&path, out)
        .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    println!("wrote {}", path.display());
    Ok(())
}

fn names() -> Vec<&'static str> {
    BENCHES.iter().map(|(b, _)| *b).collect()
}

/// Runs cargo in the repository with inherited output; an error if it fails.
fn cargo(root: &Path, args: &[&str]) -> Result<(), String> {
    let status = Command::new(std::env::var("CARGO").unwrap_or_else(|_| "cargo".into()))
        .args(args)
        .current_dir(root)
        .status()
        .map_err(|e| format!("cannot run cargo: {e}"))?;
    status
        .success()
        .then_some(())
        .ok_or(format!("`cargo {}` failed: {status}", args.join(" ")))
}

/// The benchmark ids a bench target defines (`cargo bench --bench B -- --list`).
fn list(root: &Path, bench: &str) -> Result<Vec<String>, String> {
    let out = Command::new(std::env::var("CARGO").unwrap_or_else(|_| "cargo".into()))
        .args(["bench", "--bench", bench, "--", "--list"])
        .current_dir(root)
        .output()
        .map_err(|e| format!("cannot run cargo: {e}"))?;
    if !out.status.success() {
        return Err(format!(
            "listing bench `{bench}` failed:\n{}",
            String::from_utf8_lossy(&out.stderr)
        ));
    }
    let ids: Vec<String> = String::from_utf8_lossy(&out.stdout)
        .lines()
        .filter_map(|l| l.strip_suffix(": benchmark"))
        .map(str::to_string)
        .collect();
    if ids.is_empty() {
        return Err(format!("bench `{bench}` lists no benchmark"));
    }
    Ok(ids)
}

/// Criterion's median of one benchmark \[ns\], its 95 % interval, and its throughput.
struct Estimate {
    median: f64,
    lo: f64,
    hi: f64,
    elements: Option<f64>,
}

/// Every `new/` result under `dir`, by criterion's full id.
fn read_results(dir: &Path) -> Result<BTreeMap<String, Estimate>, String> {
    let mut out = BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        let Ok(entries) = std::fs::read_dir(&d) else {
            continue;
        };
        for e in entries.flatten() {
            let p = e.path();
            if !p.is_dir() {
                continue;
            }
            if p.file_name().is_some_and(|n| n == "new") && p.join("estimates.json").is_file() {
                let (id, est) = read_one(&p)?;
                out.insert(id, est);
            } else {
                stack.push(p);
            }
        }
    }
    Ok(out)
}

fn json(path: &Path) -> Result<serde_json::Value, String> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    serde_json::from_str(&text).map_err(|e| format!("cannot parse {}: {e}", path.display()))
}

fn read_one(dir: &Path) -> Result<(String, Estimate), String> {
    let bench = json(&dir.join("benchmark.json"))?;
    let est = json(&dir.join("estimates.json"))?;
    let num = |v: &serde_json::Value, what: &str| {
        v.as_f64()
            .ok_or(format!("{}: no number at {what}", dir.display()))
    };
    let id = bench["full_id"]
        .as_str()
        .ok_or(format!("{}: no full_id", dir.display()))?;
    let m = &est["median"];
    Ok((
        id.to_string(),
        Estimate {
            median: num(&m["point_estimate"], "median.point_estimate")?,
            lo: num(
                &m["confidence_interval"]["lower_bound"],
                "median lower bound",
            )?,
            hi: num(
                &m["confidence_interval"]["upper_bound"],
                "median upper bound",
            )?,
            elements: bench["throughput"]["Elements"].as_f64(),
        },
    ))
}

/// A time in ns with a unit that keeps 3–4 significant digits.
fn time(ns: f64) -> String {
    let (v, unit) = match ns {
        x if x < 1e3 => (x, "ns"),
        x if x < 1e6 => (x / 1e3, "µs"),
        x if x < 1e9 => (x / 1e6, "ms"),
        x => (x / 1e9, "s"),
    };
    let digits = if v < 10.0 {
        2
    } else if v < 100.0 {
        1
    } else {
        0
    };
    format!("{v:.digits$} {unit}")
}

fn table(
    ids: &BTreeMap<&str, Vec<String>>,
    results: &BTreeMap<String, Estimate>,
    how: &str,
    commit: &str,
) -> Result<String, String> {
    let mut missing = Vec::new();
    let mut rows = String::new();
    for (bench, what) in BENCHES {
        rows.push_str(&format!("| **`{bench}`** | {what} | | |\n"));
        for id in &ids[bench] {
            let Some(e) = results.get(id) else {
                missing.push(format!("{bench}: {id}"));
                continue;
            };
            let rate = e.elements.map_or(String::new(), |n| {
                format!("{:.0} /s", n / (e.median * 1e-9))
            });
            rows.push_str(&format!(
                "| | `{id}` | {} [{}–{}] | {rate} |\n",
                time(e.median),
                time(e.lo),
                time(e.hi)
            ));
        }
    }
    if !missing.is_empty() {
        return Err(format!(
            "no criterion results for (run those benches first):\n  {}",
            missing.join("\n  ")
        ));
    }
    let body = format!(
        "Benchmarks run {how}; table written at commit {commit}.\n\n| bench | benchmark | median [95 % interval] | throughput |\n\
         |---|---|---|---|\n{rows}"
    );
    Ok(format!("{body}\n<!-- checksum {:016x} -->\n", fnv1a(&body)))
}

/// FNV-1a, 64 bits: the checksum `tests/docs/main.rs` recomputes over the table's text.
pub fn fnv1a(text: &str) -> u64 {
    text.bytes().fold(0xcbf2_9ce4_8422_2325, |h, b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    })
}

fn commit(root: &Path) -> String {
    Command::new("git")
        .args(["rev-parse", "--short", "HEAD"])
        .current_dir(root)
        .output()
        .ok()
        .filter(|o| o.status.success())
        .map_or("unknown".into(), |o| {
            String::from_utf8_lossy(&o.stdout).trim().to_string()
        })
}

/// Today's date (UTC) as YYYY-MM-DD, from the days since 1970 (Hinnant's civil-from-days).
fn today() -> String {
    let secs = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    let z = (secs / 86_400) as i64 + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!("{year:04}-{month:02}-{day:02}")
}
