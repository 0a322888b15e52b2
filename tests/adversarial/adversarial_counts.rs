//! Every count a user can set has a limit (`ccrkit::counts`): an absurd value is refused by
//! name, before any work, on the command line and in the library alike; the user's guide
//! prints the same table. Before, `reach --starts 1000000000` and `roadmap build --samples
//! 1000000000` ran past two minutes.

use crate::common::adversarial_harness::{bin, root, scratch};
use ccrkit::counts::COUNTS;
use std::io::Read;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};
use wait_timeout::ChildExt;

/// Runs the binary in `dir` for at most `budget`: exit code (None when killed) and stderr.
fn run_within(dir: &std::path::Path, args: &[String], budget: Duration) -> (Option<i32>, String) {
    let mut child = Command::new(bin())
        .args(args)
        .current_dir(dir)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the binary starts");
    let mut err = child.stderr.take().expect("stderr piped");
    let te = std::thread::spawn(move || {
        let mut s = String::new();
        let _ = err.read_to_string(&mut s);
        s
    });
    match child.wait_timeout(budget) {
        Ok(Some(s)) => (s.code(), te.join().unwrap_or_default()),
        _ => {
            let _ = child.kill();
            let _ = child.wait();
            (None, te.join().unwrap_or_default())
        }
    }
}

#[test]
fn absurd_counts_on_the_command_line_are_refused_by_name_at_once() {
    let dir = scratch("counts");
    let r = root();
    let path = |p: &str| r.join(p).to_string_lossy().into_owned();
    let (plan, case1) = (
        path("models/plan/two_segment.toml"),
        path("models/paper/case1.toml"),
    );
    let (v4, data) = (
        path("models/hardware/ftdcr_v4.toml"),
        path("models/hardware/data/v4/tdcr_sysid_20260511-183002_val.csv"),
    );
    let huge = "1000000000";
    let build = |flag: &'static str, value: &'static str| {
        vec![
            "roadmap",
            "build",
            plan.as_str(),
            "--out",
            "r.json",
            flag,
            value,
        ]
    };
    let jobs: Vec<(Vec<&str>, &str)> = vec![
        (
            vec!["reach", &plan, "--tip", "0,0.02,0.1", "--starts", huge],
            "starts",
        ),
        (
            vec![
                "plan",
                &plan,
                "--to-tip",
                "0,0.02,0.1",
                "--max-samples",
                huge,
            ],
            "max_samples",
        ),
        (build("--samples", huge), "samples"),
        (build("--expand", huge), "expand"),
        (build("--shard", "0/1000000000"), "shard"),
        (build("--neighbours", huge), "neighbours"),
        (
            vec![
                "calibrate",
                &v4,
                "--data",
                &data,
                "--out",
                "f.toml",
                "--max-iterations",
                huge,
            ],
            "max_iterations",
        ),
        (
            vec![
                "predict", &v4, "--data", &data, "--out", "p.csv", "--chunk", huge,
            ],
            "chunk",
        ),
        (
            vec![
                "study",
                "speed-accuracy",
                &case1,
                "--out",
                "s",
                "--repeats",
                huge,
            ],
            "repeats",
        ),
        (
            vec!["study", "stability", &case1, "--out", "s", "--grid", huge],
            "grid",
        ),
        (
            vec![
                "study",
                "workspace",
                &case1,
                "--out",
                "s",
                "--samples",
                huge,
            ],
            "samples",
        ),
        (
            vec!["study", "workspace", &case1, "--out", "s", "--chunk", huge],
            "chunk",
        ),
        (vec!["study", "auto", "--robots", huge], "robots"),
        (vec!["study", "auto", "--repeats", huge], "repeats"),
        (vec!["solve", &case1, "--steps", huge], "steps"),
        (vec!["solve", &case1, "--repeat", huge], "repeat"),
    ];
    for (args, field) in jobs {
        let args: Vec<String> = args.iter().map(|s| s.to_string()).collect();
        let t = Instant::now();
        let (code, stderr) = run_within(&dir, &args, Duration::from_secs(20));
        let first = stderr
            .lines()
            .find(|l| l.starts_with("error"))
            .unwrap_or("");
        assert_eq!(code, Some(1), "{args:?}: {stderr}");
        assert!(
            first.starts_with(&format!("error: invalid input `{field}`")),
            "{args:?}: {first}"
        );
        assert!(
            t.elapsed() < Duration::from_secs(10),
            "{args:?}: {:?}",
            t.elapsed()
        );
    }
}

/// The `auto` study refuses, by name and before any solve, what it cannot run: a tolerance
/// that is not a positive length (it once printed a row of `NaN mm` and counted the robot as an
/// answer), a tolerance asked twice (each robot counted twice), none at all, and seeds past
/// `u64::MAX` (`first_seed + robots` wrapped to an empty study in release builds and
/// panicked in debug ones).
#[test]
fn the_auto_study_refuses_tolerances_and_seeds_it_cannot_run_by_name() {
    use ccrkit::study::{auto_study, AutoStudyOptions, StudyError};
    let refused = |opts: AutoStudyOptions, field: &str| {
        let t = Instant::now();
        match auto_study(&opts) {
            Err(StudyError::Solve(ccrkit::SolveError::InvalidInput { field: f, reason })) => {
                assert_eq!(f, field, "{reason}");
                assert!(!reason.is_empty());
            }
            other => panic!("{field}: {other:?}"),
        }
        // Refused before the first robot's reference solve.
        assert!(t.elapsed() < Duration::from_millis(100), "{field}");
    };
    let with = |tolerances: Vec<f64>| AutoStudyOptions {
        robots: 1,
        tolerances,
        ..AutoStudyOptions::default()
    };
    for bad in [f64::NAN, 0.0, -1e-3, f64::INFINITY, f64::NEG_INFINITY] {
        refused(with(vec![1e-3, bad]), "tolerances");
    }
    refused(with(vec![]), "tolerances");
    refused(with(vec![1e-3, 1e-4, 1e-3]), "tolerances");
    let past_the_last_seed = AutoStudyOptions {
        robots: 2,
        first_seed: u64::MAX,
        ..AutoStudyOptions::default()
    };
    refused(past_the_last_seed, "first_seed");
    refused(
        AutoStudyOptions {
            robots: 0,
            ..AutoStudyOptions::default()
        },
        "robots",
    );
    refused(
        AutoStudyOptions {
            repeats: 0,
            ..AutoStudyOptions::default()
        },
        "repeats",
    );
}

/// Each count's check takes its whole range and refuses one past either end by its field.
#[test]
fn every_count_takes_its_range_and_refuses_beyond_it_by_name() {
    for c in COUNTS {
        assert_eq!(c.check(c.min).ok(), Some(c.min), "{c:?}");
        assert_eq!(c.check(c.max).ok(), Some(c.max), "{c:?}");
        for v in [c.max + 1, usize::MAX]
            .into_iter()
            .chain(c.min.checked_sub(1))
        {
            match c.check(v) {
                Err(ccrkit::SolveError::InvalidInput { field, reason }) => {
                    assert_eq!(field, c.field);
                    assert!(reason.contains(&c.max.to_string()), "{reason}");
                }
                other => panic!("{c:?} at {v}: {other:?}"),
            }
        }
    }
}

/// The guide's table of limits lists every count with its range, as the code has it.
#[test]
fn the_guide_lists_every_count_with_its_limit() {
    let guide = std::fs::read_to_string(root().join("docs/guide/errors.md")).expect("guide");
    for c in COUNTS {
        let row = format!("| `{}` | {} | {} | {} |", c.field, c.set_by, c.min, c.max);
        assert!(
            guide.contains(&row),
            "docs/guide/errors.md lacks the row\n{row}"
        );
    }
}

/// The guide's table of adversarial suites gives each suite's number of tests as it is.
#[test]
fn the_guide_counts_the_adversarial_tests_as_they_are() {
    let guide = std::fs::read_to_string(root().join("docs/guide/errors.md")).expect("guide");
    let dir = root().join("tests/adversarial");
    let mut suites = 0;
    for entry in std::fs::read_dir(&dir).expect("suites") {
        let path = entry.expect("entry").path();
        let name = path.file_stem().and_then(|s| s.to_str()).unwrap_or("");
        if !name.starts_with("adversarial_") {
            continue;
        }
        let text = std::fs::read_to_string(&path).expect("suite");
        let tests = text.lines().filter(|l| l.trim() == "#[test]").count();
        let row = format!("| `{name}` | {tests} |");
        assert!(
            guide.contains(&row),
            "docs/guide/errors.md should say {row}"
        );
        suites += 1;
    }
    assert!(suites >= 6, "{suites} suites");
}
