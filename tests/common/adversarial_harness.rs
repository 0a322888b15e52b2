//! The adversarial harness: run the built `ccrkit` binary under a wall-time budget and judge
//! the outcome:
//! - no panic (exit 101 or a signal), no hang (killed at the budget);
//! - exit 0 only with finite numbers: the `--json` file parses and holds no `null` where a
//!   number belongs (serde_json writes NaN/inf as `null`), stdout has no `NaN`/`inf`;
//! - every failure a named kind: exit 1 with an `error:` line carrying one of ccrkit's error
//!   messages (field or reason named), or exit 2 from the argument parser naming the option.
//!
//! Each test tallies its runs and prints `adversarial <name>: runs …, panics …, hangs …,
//! non-finite …, named errors …, solved …` (see with `--nocapture`).

#![allow(dead_code)]

use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::Mutex;
use std::time::{Duration, Instant};
use wait_timeout::ChildExt;

/// The binary cargo built for these tests.
pub fn bin() -> PathBuf {
    PathBuf::from(env!("CARGO_BIN_EXE_ccrkit"))
}

/// The tests' shared paths and binary runs (`common::cli`).
pub use super::cli;

/// Repository root.
pub fn root() -> PathBuf {
    cli::root()
}

/// A fresh scratch directory `ccrkit-adv-NAME-PID` in the system's temporary folder.
pub fn scratch(name: &str) -> PathBuf {
    cli::scratch(&format!("adv-{name}"))
}

/// Phrases that start ccrkit's named errors (`ModelError`, `SolveError`, `ExportError`,
/// study and settings errors, and the command line's own: a file it cannot write, an option
/// out of range): each names the field, option, file, cable, section or reason.
pub const NAMED: &[&str] = &[
    "cannot read `",
    "cannot parse `",
    "invalid field `",
    "invalid input `",
    "infeasible actuation: cable `",
    "did not converge",
    "obstructed by `",
    "cannot solve this:",
    "shape does not match robot",
    "invalid option `",
    "cannot write `",
    "cannot plot to `",
    "writing ",
    "tolerance must be",
    "unknown --",
    "shard `",
    "contact budget exceeded:",
    "no row solved:",
    "airway option `",
];

/// How one run ended.
#[derive(Debug, Clone, PartialEq)]
pub enum Verdict {
    /// Exit 0 with finite output.
    Solved,
    /// A named error (exit 1 or a parser error, exit 2).
    Named,
    /// Exit 101 or killed by a signal.
    Panic(String),
    /// Still running at the budget (killed).
    Hang,
    /// Exit 0 with a non-finite number.
    NonFinite(String),
    /// Failed without a named error.
    Unnamed(String),
}

/// Counts over many runs.
#[derive(Debug, Default, Clone)]
pub struct Tally {
    /// Runs.
    pub runs: usize,
    /// Panics.
    pub panics: usize,
    /// Hangs.
    pub hangs: usize,
    /// Exit 0 with non-finite numbers.
    pub non_finite: usize,
    /// Named errors.
    pub named: usize,
    /// Unnamed failures.
    pub unnamed: usize,
    /// Exit 0, finite.
    pub solved: usize,
    /// The first few bad outcomes, with their command.
    pub bad: Vec<String>,
}

impl Tally {
    /// Count one verdict.
    pub fn add(&mut self, args: &[String], v: &Verdict) {
        self.runs += 1;
        let bad = match v {
            Verdict::Solved => {
                self.solved += 1;
                None
            }
            Verdict::Named => {
                self.named += 1;
                None
            }
            Verdict::Panic(m) => {
                self.panics += 1;
                Some(m.clone())
            }
            Verdict::Hang => {
                self.hangs += 1;
                Some("hang".to_string())
            }
            Verdict::NonFinite(m) => {
                self.non_finite += 1;
                Some(m.clone())
            }
            Verdict::Unnamed(m) => {
                self.unnamed += 1;
                Some(m.clone())
            }
        };
        if let Some(m) = bad {
            if self.bad.len() < 20 {
                self.bad.push(format!("ccrkit {}\n    {m}", args.join(" ")));
            }
        }
    }

    /// Print the counts and fail when anything went wrong.
    pub fn report_and_assert(&self, name: &str) {
        println!(
            "adversarial {name}: runs {}, panics {}, hangs {}, non-finite {}, named errors {}, unnamed failures {}, solved {}",
            self.runs, self.panics, self.hangs, self.non_finite, self.named, self.unnamed, self.solved
        );
        assert!(
            self.bad.is_empty(),
            "{name}: {} bad outcomes:\n{}",
            self.panics + self.hangs + self.non_finite + self.unnamed,
            self.bad.join("\n")
        );
    }
}

/// Run `ccrkit ARGS` in `dir` with a wall-time budget; `json` is the `--json` file the run
/// writes, if any.
pub fn run(dir: &Path, args: &[String], budget: Duration, json: Option<&Path>) -> Verdict {
    if let Some(j) = json {
        let _ = std::fs::remove_file(j);
    }
    let mut child = match Command::new(bin())
        .args(args)
        .current_dir(dir)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
    {
        Ok(c) => c,
        Err(e) => return Verdict::Unnamed(format!("cannot start: {e}")),
    };
    // Drain the pipes on threads so a chatty child cannot block on a full pipe.
    let mut out = child.stdout.take().expect("stdout piped");
    let mut err = child.stderr.take().expect("stderr piped");
    let to = std::thread::spawn(move || {
        let mut s = String::new();
        let _ = out.read_to_string(&mut s);
        s
    });
    let te = std::thread::spawn(move || {
        let mut s = String::new();
        let _ = err.read_to_string(&mut s);
        s
    });
    let t0 = Instant::now();
    let status = match child.wait_timeout(budget) {
        Ok(Some(s)) => s,
        _ => {
            let _ = child.kill();
            let _ = child.wait();
            return Verdict::Hang;
        }
    };
    let _elapsed = t0.elapsed();
    let stdout = to.join().unwrap_or_default();
    let stderr = te.join().unwrap_or_default();
    judge(status.code(), &stdout, &stderr, json)
}

/// The verdict on one finished run.
pub fn judge(code: Option<i32>, stdout: &str, stderr: &str, json: Option<&Path>) -> Verdict {
    let first_err = stderr
        .lines()
        .find(|l| l.starts_with("error"))
        .unwrap_or("")
        .to_string();
    match code {
        None => Verdict::Panic(format!("killed by a signal; stderr: {stderr}")),
        Some(101) => Verdict::Panic(stderr.lines().take(3).collect::<Vec<_>>().join(" | ")),
        Some(0) => {
            if let Some(tok) = non_finite_token(stdout) {
                return Verdict::NonFinite(format!("stdout holds `{tok}`"));
            }
            match json {
                Some(j) if j.exists() => match std::fs::read_to_string(j) {
                    Ok(text) => match serde_json::from_str::<serde_json::Value>(&text) {
                        Ok(v) => match null_number(&v, "") {
                            Some(path) => Verdict::NonFinite(format!("`{path}` is null")),
                            None => Verdict::Solved,
                        },
                        Err(e) => Verdict::NonFinite(format!("JSON does not parse: {e}")),
                    },
                    Err(e) => Verdict::Unnamed(format!("cannot read the JSON: {e}")),
                },
                _ => Verdict::Solved,
            }
        }
        Some(1) if NAMED.iter().any(|n| first_err.contains(n)) => Verdict::Named,
        // The argument parser: a named option, or its usage text when no command is given.
        Some(2)
            if (first_err.starts_with("error:") && first_err.contains('\''))
                || stderr.contains("Usage: ccrkit") =>
        {
            Verdict::Named
        }
        Some(c) => Verdict::Unnamed(format!("exit {c}: {}", stderr.trim())),
    }
}

/// A `NaN` or `inf` token in console text.
fn non_finite_token(text: &str) -> Option<String> {
    text.split(|c: char| !(c.is_ascii_alphanumeric()))
        .find(|t| matches!(*t, "NaN" | "nan" | "inf" | "Inf" | "infinity"))
        .map(str::to_string)
}

/// The path of a `null` in a shape's JSON (`tension` is the one optional number written as
/// `null`: a method that computes no tension).
fn null_number(v: &serde_json::Value, path: &str) -> Option<String> {
    match v {
        serde_json::Value::Null if !path.ends_with(".tension") => Some(path.to_string()),
        serde_json::Value::Array(a) => a
            .iter()
            .enumerate()
            .find_map(|(k, x)| null_number(x, &format!("{path}[{k}]"))),
        serde_json::Value::Object(m) => m
            .iter()
            .find_map(|(k, x)| null_number(x, &format!("{path}.{k}"))),
        _ => None,
    }
}

/// Run many argument lists on two worker threads; each job is (arguments, `--json` file).
pub fn run_all(dir: &Path, jobs: Vec<(Vec<String>, Option<PathBuf>)>, budget: Duration) -> Tally {
    let tally = Mutex::new(Tally::default());
    let next = Mutex::new(0usize);
    std::thread::scope(|s| {
        for _ in 0..2 {
            s.spawn(|| loop {
                let k = {
                    let mut n = next.lock().expect("lock");
                    *n += 1;
                    *n - 1
                };
                let Some((args, json)) = jobs.get(k) else {
                    break;
                };
                let v = run(dir, args, budget, json.as_deref());
                tally.lock().expect("lock").add(args, &v);
            });
        }
    });
    tally.into_inner().expect("lock")
}

/// Strings from `&str`s.
pub fn args(a: &[&str]) -> Vec<String> {
    a.iter().map(|s| s.to_string()).collect()
}

/// The registered method names, read from the binary's library (`MethodKind::ALL`).
pub fn methods() -> Vec<String> {
    ccrkit::method::MethodKind::ALL
        .iter()
        .map(|k| k.name().to_string())
        .collect()
}
