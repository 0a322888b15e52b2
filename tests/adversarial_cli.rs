//! Adversarial command lines (issue 11): absurd numbers for every bounded flag, devices and
//! directories as input files, every setting on every method that does not take it, every
//! subcommand with broken arguments — each run of the built binary under a wall-time budget,
//! judged by `adversarial_harness` (no panic, no hang, no exit 0 with a non-finite number,
//! every failure named).

mod adversarial_harness;
use adversarial_harness::{args, methods, root, run, run_all, scratch, Tally, Verdict};
use std::time::{Duration, Instant};

const BUDGET: Duration = Duration::from_secs(30);

fn case(n: usize) -> String {
    root()
        .join(format!("models/paper/case{n}.toml"))
        .display()
        .to_string()
}

/// Flags with absurd values on `solve`, for every method.
fn flag_jobs() -> Vec<Vec<String>> {
    let c1 = case(1);
    let absurd = [
        "0",
        "-1",
        "nan",
        "inf",
        "-inf",
        "1e308",
        "4000000000",
        "18446744073709551615",
        "18446744073709551616",
        "",
        "x",
    ];
    let mut jobs = vec![];
    for m in methods() {
        for flag in ["--steps", "--repeat", "--rk4-steps", "--adaptive"] {
            for v in absurd {
                jobs.push(args(&["solve", &c1, "--method", &m, flag, v]));
            }
        }
        for flag in ["--control", "--routing", "--length"] {
            for v in [
                "force",
                "displacement",
                "spline",
                "fourier8",
                "chord",
                "",
                "nan",
            ] {
                jobs.push(args(&["solve", &c1, "--method", &m, flag, v]));
            }
        }
        for s in [
            "tolerance=nan",
            "tolerance=0",
            "tolerance=1e308",
            "max-iterations=0",
            "max-iterations=18446744073709551616",
            "sub-arcs=1000",
            "samples-per-sub-arc=0",
            "bend-refine=-1",
            "min-stretch=2",
            "zero-angle=1",
            "no-such-setting=1",
            "=",
            "novalue",
        ] {
            jobs.push(args(&["solve", &c1, "--method", &m, "--set", s]));
        }
        for w in methods() {
            jobs.push(args(&["solve", &c1, "--method", &m, "--warm-from", &w]));
        }
        jobs.push(args(&[
            "solve",
            &c1,
            "--method",
            &m,
            "--warm-from",
            "geometric",
            "--steps",
            "3",
        ]));
        jobs.push(args(&["solve", &c1, "--method", &m, "--plot", "out.pdf"]));
    }
    jobs
}

/// Devices, directories, missing and empty files in every file position.
fn file_jobs(dir: &std::path::Path) -> Vec<Vec<String>> {
    std::fs::write(dir.join("empty.toml"), "").expect("write");
    std::fs::write(dir.join("binary.toml"), [0u8, 159, 146, 150, 255]).expect("write");
    let mut scene_mesh = String::from("[[obstacles]]\nshape = \"mesh\"\npath = \"/dev/zero\"\n");
    std::fs::write(dir.join("zero_mesh.toml"), &scene_mesh).expect("write");
    scene_mesh = scene_mesh.replace("/dev/zero", "/dev/urandom.stl");
    std::fs::write(dir.join("urandom_mesh.toml"), &scene_mesh).expect("write");
    let c1 = case(1);
    let bad = [
        "/dev/zero",
        "/dev/urandom",
        "/dev/null",
        "/",
        "no/such/file.toml",
        "empty.toml",
        "binary.toml",
    ];
    let mut jobs = vec![];
    for b in bad {
        jobs.push(args(&["solve", b]));
        jobs.push(args(&["solve", &c1, "--scene", b]));
        jobs.push(args(&["compare", b]));
        jobs.push(args(&["compare", &c1, "--scene", b]));
        jobs.push(args(&["export", "urdf", b, "--out", "x.urdf"]));
    }
    for s in ["zero_mesh.toml", "urandom_mesh.toml"] {
        jobs.push(args(&["solve", &c1, "--scene", s]));
    }
    jobs
}

/// Other subcommands with broken arguments.
fn subcommand_jobs() -> Vec<Vec<String>> {
    let (c1, c2) = (case(1), case(2));
    let mut jobs = vec![
        args(&["compare", &c1, "--methods", "no-such"]),
        args(&["compare", &c1, "--methods", "energy:control=sideways"]),
        args(&["compare", &c1, "--methods", "geometric:routing=spline"]),
        args(&["compare", &c1, "--tolerance", "nan"]),
        args(&["compare", &c1, "--tolerance", "-1"]),
        args(&["compare", &c2, "--methods", ",,"]),
        args(&["export", "urdf", &c1, "--mode", "wobbly", "--out", "x.urdf"]),
        args(&["export", "urdf", &c1, "--out", "/dev/full/x.urdf"]),
        args(&["export", "urdf", &c1, "--out", "/proc/version"]),
        args(&["solve", &c1, "--json", "/dev/full"]),
        args(&["solve", &c1, "--json", "/no/such/dir/x.json"]),
        args(&["solve", &c1, "--plot", "/no/such/dir/x.svg"]),
        args(&["methods", "extra"]),
        args(&["no-such-command"]),
        args(&[]),
    ];
    for m in methods() {
        jobs.push(args(&[
            "export", "urdf", &c1, "--method", &m, "--out", "x.urdf",
        ]));
    }
    // Studies: absurd sizes and ranges are refused before any solve (small grids otherwise).
    jobs.push(args(&["study", "merge", "m.csv", "/dev/zero"]));
    jobs.push(args(&["study", "merge", "m.csv", "no-such.csv"]));
    for (flag, v) in [
        ("--grid", "0"),
        ("--grid", "4000000000"),
        ("--max-percent", "nan"),
        ("--max-percent", "1e308"),
        ("--max-percent", "-5"),
        ("--tension-factor", "inf"),
        ("--methods", "no-such"),
        ("--input", "sideways"),
    ] {
        let mut a = args(&["study", "stability", &c1, "--out", "st", "--grid", "2"]);
        a.extend(args(&[flag, v]));
        jobs.push(a);
    }
    for (flag, v) in [
        ("--samples", "0"),
        ("--samples", "18446744073709551615"),
        ("--shard", "3/2"),
        ("--shard", "0/0"),
        ("--chunk", "0"),
        ("--max-percent", "nan"),
        ("--method", "no-such"),
    ] {
        let mut a = args(&["study", "workspace", &c1, "--out", "ws", "--samples", "4"]);
        a.extend(args(&[flag, v]));
        jobs.push(a);
    }
    jobs
}

#[test]
fn adversarial_command_lines_end_named_and_bounded() {
    let dir = scratch("cli");
    let mut jobs: Vec<(Vec<String>, Option<std::path::PathBuf>)> = vec![];
    for a in flag_jobs()
        .into_iter()
        .chain(file_jobs(&dir))
        .chain(subcommand_jobs())
    {
        jobs.push((a, None));
    }
    let t = run_all(&dir, jobs, BUDGET);
    t.report_and_assert("command lines");
}

/// Issue 11 #11: the huge step counts end quickly, with the right kind of error.
#[test]
fn huge_step_counts_are_refused_at_once_by_name() {
    let dir = scratch("steps");
    let c1 = case(1);
    for (m, flag, v, field) in [
        ("cosserat", "--rk4-steps", "4000000000", "rk4-steps"),
        ("geometric", "--steps", "1000000000", "steps"),
        ("energy", "--repeat", "18446744073709551615", "repeat"),
    ] {
        let a = args(&["solve", &c1, "--method", m, flag, v]);
        let t0 = Instant::now();
        let out = std::process::Command::new(adversarial_harness::bin())
            .args(&a)
            .current_dir(&dir)
            .output()
            .expect("runs");
        assert!(t0.elapsed() < Duration::from_secs(5), "{a:?} took long");
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{a:?}: {err}");
        assert!(
            err.contains(&format!("invalid input `{field}`")),
            "{a:?}: {err}"
        );
    }
}

/// Issue 11 #11: devices as model, scene or mesh end in a named size error, quickly.
#[test]
fn devices_as_files_end_in_a_named_size_error() {
    let dir = scratch("devices");
    std::fs::write(
        dir.join("mesh.toml"),
        "[[obstacles]]\nshape = \"mesh\"\npath = \"zero.stl\"\n",
    )
    .expect("write");
    if !std::path::Path::new("/dev/zero").exists() {
        eprintln!("no /dev/zero here: skipped");
        return;
    }
    #[cfg(unix)]
    std::os::unix::fs::symlink("/dev/zero", dir.join("zero.stl")).expect("symlink");
    let c1 = case(1);
    for a in [
        args(&["solve", "/dev/zero"]),
        args(&["solve", "/dev/urandom"]),
        args(&["solve", &c1, "--scene", "/dev/zero"]),
        args(&["solve", &c1, "--scene", "mesh.toml"]),
    ] {
        let t0 = Instant::now();
        let v = run(&dir, &a, Duration::from_secs(20), None);
        assert_eq!(v, Verdict::Named, "{a:?}");
        assert!(t0.elapsed() < Duration::from_secs(10), "{a:?} took long");
    }
    let out = std::process::Command::new(adversarial_harness::bin())
        .args(["solve", "/dev/zero"])
        .output()
        .expect("runs");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("MiB limit"), "{err}");
    let mut t = Tally::default();
    t.add(&args(&["solve", "/dev/zero"]), &Verdict::Named);
    t.report_and_assert("devices");
}
