//! Adversarial command lines: absurd numbers for every bounded flag, devices and
//! directories as input files, every setting on every method that does not take it, every
//! subcommand with broken arguments — each run of the built binary under a wall-time budget,
//! judged by `adversarial_harness` (no panic, no hang, no exit 0 with a non-finite number,
//! every failure named).

use crate::common::adversarial_harness;
use crate::common::adversarial_harness::cli::{ccrkit_in, paper_path};
use crate::common::adversarial_harness::{
    args, methods, root, run, run_all, scratch, Tally, Verdict,
};
use std::time::{Duration, Instant};

const BUDGET: Duration = Duration::from_secs(30);

/// Paper case `n` as a command-line argument.
fn case(n: usize) -> String {
    paper_path(n)
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
        // The deepest airways: the branches' placement sampled every pair and ran past five
        // minutes at 12 generations before the grid's count refused it.
        args(&["anatomy", "airway", "--generations", "12", "--out", "x.stl"]),
        args(&[
            "anatomy",
            "airway",
            "--generations",
            "12",
            "--asymmetry",
            "0.4",
            "--out",
            "x.obj",
        ]),
        args(&["anatomy", "airway", "--generations", "13", "--out", "x.stl"]),
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

/// Every run bounded: the huge step counts end quickly, with the right kind of error.
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
        let out = ccrkit_in(&dir, &a);
        assert!(t0.elapsed() < Duration::from_secs(5), "{a:?} took long");
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{a:?}: {err}");
        assert!(
            err.contains(&format!("invalid input `{field}`")),
            "{a:?}: {err}"
        );
    }
}

/// Every run bounded: devices as model, scene or mesh end in a named size error, quickly.
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
    let out = ccrkit_in(&root(), &["solve", "/dev/zero"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("MiB limit"), "{err}");
    let mut t = Tally::default();
    t.add(&args(&["solve", "/dev/zero"]), &Verdict::Named);
    t.report_and_assert("devices");
}

/// Every solve flag a method does not take is refused before solving, naming the
/// setting (the registry's `settings` say which methods take which).
#[test]
fn every_flag_a_method_does_not_take_is_refused_by_name() {
    let dir = scratch("unused");
    let c1 = case(1);
    let flags = [
        ("--control", "control", "force"),
        ("--routing", "routing", "spline"),
        ("--length", "length", "chord"),
        ("--rk4-steps", "rk4-steps", "3"),
        ("--adaptive", "adaptive", "1e-6"),
    ];
    let (mut refused, mut taken) = (0, 0);
    for k in ccrkit::method::MethodKind::ALL {
        for (flag, setting, value) in flags {
            let takes = k.info().settings.iter().any(|s| s.name == setting);
            let a = args(&["solve", &c1, "--method", k.name(), flag, value]);
            let out = ccrkit_in(&dir, &a);
            let err = String::from_utf8_lossy(&out.stderr);
            if takes {
                assert!(
                    !err.contains(&format!("invalid input `{setting}`")),
                    "{a:?}: {err}"
                );
                taken += 1;
            } else {
                assert_eq!(out.status.code(), Some(1), "{a:?} accepted: {err}");
                assert!(
                    err.contains(&format!("invalid input `{setting}`")),
                    "{a:?}: {err}"
                );
                refused += 1;
            }
        }
    }
    println!("unused flags: {refused} refused by name, {taken} taken");
    assert!(refused > 0 && taken > 0);
}

/// `--set stability=…` with bad values on every method, and `predict`/`calibrate` with absurd
/// data CSVs (empty, header only, non-numeric, 1e308 cables and tips, NaN, missing columns, ragged rows,
/// devices) and absurd options: each run named and bounded, never exit 0 with a non-finite
/// number (the `predict` CSV is checked for `NaN`/`inf` too).
#[test]
fn stability_setting_and_data_csvs_end_named_and_bounded() {
    let dir = scratch("data");
    let c1 = case(1);
    let mut jobs: Vec<(Vec<String>, Option<std::path::PathBuf>)> = vec![];
    for m in methods() {
        for v in [
            "check",
            "skip",
            "",
            "CHECK",
            "nan",
            "1",
            "check,skip",
            "maybe",
            "skip ",
        ] {
            jobs.push((
                args(&[
                    "solve",
                    &c1,
                    "--method",
                    &m,
                    "--set",
                    &format!("stability={v}"),
                ]),
                None,
            ));
        }
    }
    let model = root().join("models/hardware/ftdcr_v4.toml");
    let model = model.display().to_string();
    // `calibrate` of the v4 model on `data` to `out` with `--max-iterations iters` and `extra`.
    let calibrate = |data: &str, out: &str, iters: &str, extra: &[&str]| {
        let mut a = args(&[
            "calibrate",
            &model,
            "--data",
            data,
            "--out",
            out,
            "--max-iterations",
            iters,
        ]);
        a.extend(args(extra));
        a
    };
    let real = std::fs::read_to_string(
        root().join("models/hardware/data/v4/tdcr_sysid_20260511-183002_val.csv"),
    )
    .expect("hardware data");
    let lines: Vec<&str> = real.lines().take(31).collect();
    let header = lines[0];
    let body = &lines[1..];
    let with_cell = |v: &str| -> String {
        // The third cell (the first servo) of every row replaced by `v`.
        let rows: Vec<String> = body
            .iter()
            .map(|r| {
                let mut c: Vec<&str> = r.split(',').collect();
                c[2] = v;
                c.join(",")
            })
            .collect();
        format!("{header}\n{}\n", rows.join("\n"))
    };
    let with_last_cell = |v: &str| -> String {
        // The last cell (the tip's z) of every row replaced by `v`.
        let rows: Vec<String> = body
            .iter()
            .map(|r| {
                let mut c: Vec<&str> = r.split(',').collect();
                if let Some(last) = c.last_mut() {
                    *last = v;
                }
                c.join(",")
            })
            .collect();
        format!("{header}\n{}\n", rows.join("\n"))
    };
    let without = |col: &str| -> String {
        let cols: Vec<&str> = header.split(',').collect();
        let k = cols.iter().position(|c| *c == col).expect("column");
        lines
            .iter()
            .map(|r| {
                let mut c: Vec<&str> = r.split(',').collect();
                c.remove(k);
                c.join(",")
            })
            .collect::<Vec<_>>()
            .join("\n")
    };
    let csvs: Vec<(&str, String)> = vec![
        ("empty", String::new()),
        ("header", format!("{header}\n")),
        ("one", format!("{header}\n{}\n", body[0])),
        ("text", with_cell("x")),
        ("nan", with_cell("NaN")),
        ("inf", with_cell("inf")),
        ("huge", with_cell("1e308")),
        ("neghuge", with_cell("-1e308")),
        ("blank", with_cell("")),
        ("ragged", format!("{header}\n{}\n1,2,3\n", body[0])),
        ("no_tip_z", without("tip_z")),
        ("no_servo", without("servo_4_mm")),
        ("no_label", without("pattern_label")),
        ("binary", "\u{0}\u{1}\u{ff}".into()),
        ("tip_huge", with_last_cell("1e308")),
        (
            "tip_nan",
            real.lines()
                .take(31)
                .collect::<Vec<_>>()
                .join("\n")
                .replace(",18", ",NaN"),
        ),
    ];
    let mut files = vec![];
    for (name, text) in &csvs {
        let p = dir.join(format!("{name}.csv"));
        std::fs::write(&p, text).expect("write csv");
        files.push(p.display().to_string());
    }
    files.extend([
        "/dev/zero".into(),
        "/dev/null".into(),
        "/".into(),
        "no-such.csv".into(),
    ]);
    for (j, f) in files.iter().enumerate() {
        let out = format!("p{j}.csv");
        jobs.push((args(&["predict", &model, "--data", f, "--out", &out]), None));
        jobs.push((calibrate(f, &format!("f{j}.toml"), "2", &[]), None));
        // The default chooses among parameter sets; `--fit default` fits one, as before.
        let one = ["--fit", "default"];
        jobs.push((calibrate(f, &format!("g{j}.toml"), "2", &one), None));
    }
    let good = dir.join("good.csv");
    std::fs::write(&good, format!("{}\n", lines.join("\n"))).expect("write");
    let good = good.display().to_string();
    for extra in [
        &["--unit", "km"][..],
        &["--unit", ""],
        &["--chunk", "0"],
        &["--chunk", "18446744073709551615"],
        &["--columns", "servo_4_mm"],
        &["--columns", "no_such,servo_3_mm"],
        &[
            "--columns",
            "tip_x,tip_y,tip_z,servo_1_mm,servo_2_mm,servo_3_mm,servo_5_mm,servo_6_mm,servo_7_mm",
        ],
        &["--method", "no-such"],
        &["--set", "stability=maybe"],
    ] {
        let mut a = args(&["predict", &model, "--data", &good, "--out", "pe.csv"]);
        a.extend(args(extra));
        jobs.push((a, None));
    }
    for fit in [
        "no-such",
        "axial-compliance.seg9",
        "axial-compliance.segx",
        "axial-compliance.",
        "base.rz,base.rz",
        "base.rx",
        "",
        ",",
    ] {
        jobs.push((calibrate(&good, "fe.toml", "2", &["--fit", fit]), None));
    }
    for it in ["0", "18446744073709551616", "-1", "nan"] {
        jobs.push((calibrate(&good, "fe.toml", it, &[]), None));
    }
    let t = run_all(&dir, jobs, BUDGET);
    // Exit 0 of `predict` wrote a CSV: no `NaN`/`inf` in a row marked solved.
    for (j, file) in files.iter().enumerate() {
        if let Ok(text) = std::fs::read_to_string(dir.join(format!("p{j}.csv"))) {
            for l in text.lines().filter(|l| l.ends_with(",ok")) {
                assert!(
                    !l.to_lowercase().contains("nan") && !l.to_lowercase().contains("inf"),
                    "predict on {file} wrote a non-finite solved row: {l}"
                );
            }
        }
    }
    t.report_and_assert("stability setting and data CSVs");
}

/// A reader that goes away (`ccrkit solve … | head -c 0`) ends the process by SIGPIPE like
/// any Unix tool, never by a "Broken pipe" panic (exit 101). The pipe's read end is closed
/// before the spawn, so the first write meets a closed pipe whatever the scheduler does (closing
/// it after the spawn raced a fast solve that had already written into the open pipe: exit 0).
#[cfg(unix)]
#[test]
fn a_closed_stdout_is_not_a_panic() {
    use std::os::unix::process::ExitStatusExt;
    let c1 = case(1);
    for m in ["geometric", "energy", "cosserat"] {
        let out = std::process::Command::new(adversarial_harness::bin())
            .args(["solve", &c1, "--method", m])
            .stdout(reader_gone())
            .stderr(std::process::Stdio::piped())
            .output()
            .expect("runs");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!err.contains("panicked"), "{m}: {err}");
        assert_ne!(out.status.code(), Some(101), "{m}: {err}");
        assert_eq!(out.status.signal(), Some(libc_sigpipe()), "{m}: {err}");
    }
}

/// The write end of a pipe whose read end is already closed.
#[cfg(unix)]
fn reader_gone() -> std::process::Stdio {
    use std::os::fd::{FromRawFd, OwnedFd};
    let mut fds = [0i32; 2];
    // SAFETY: `pipe` fills both descriptors on success; each is owned exactly once below.
    assert_eq!(unsafe { libc::pipe(fds.as_mut_ptr()) }, 0, "pipe");
    // SAFETY: fds[0] and fds[1] are fresh descriptors this function alone owns.
    let (read, write) = unsafe { (OwnedFd::from_raw_fd(fds[0]), OwnedFd::from_raw_fd(fds[1])) };
    drop(read);
    std::process::Stdio::from(write)
}

/// SIGPIPE's number on Linux and the BSDs.
#[cfg(unix)]
fn libc_sigpipe() -> i32 {
    13
}

/// `predict --out -` writes the CSV to standard output, as `--json -` does elsewhere, and no
/// file named `-` (it used to write one, silently); the summary goes to standard error.
#[test]
fn predict_out_dash_is_standard_output() {
    let dir = scratch("predict-stdout");
    let data = root().join("models/hardware/data/v4/tdcr_sysid_20260511-183002_val.csv");
    let model = root().join("models/hardware/ftdcr_v4.toml");
    let out = ccrkit_in(
        &dir,
        &[
            "predict",
            &model.to_string_lossy(),
            "--data",
            &data.to_string_lossy(),
            "--out",
            "-",
        ],
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{err}");
    let csv = String::from_utf8_lossy(&out.stdout);
    let mut lines = csv.lines();
    assert!(
        lines
            .next()
            .is_some_and(|h| h.starts_with("tip_x,tip_y,tip_z")),
        "{csv:.200}"
    );
    let rows = std::fs::read_to_string(&data)
        .expect("data")
        .lines()
        .count()
        - 1;
    assert_eq!(lines.count(), rows);
    assert!(err.contains("rows "), "{err}");
    assert!(!dir.join("-").exists(), "a file named - was written");
}
