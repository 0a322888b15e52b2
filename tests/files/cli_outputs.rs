//! The command line's outputs a new user reads: the shape JSON names the model, the method and
//! the input that drove the solve; `ccrkit view` writes a page for shapes, plans and sweeps and
//! names bad options.

use crate::common;

use serde_json::Value;

fn ccrkit(args: &[&str]) -> std::process::Output {
    common::cli::ccrkit_in(&common::cli::root(), args)
}

fn solve_json(method: &str) -> Value {
    let out = ccrkit(&[
        "solve",
        "models/paper/case1.toml",
        "--method",
        method,
        "--json",
        "-",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("JSON on stdout")
}

#[test]
fn shape_json_names_model_method_and_driving_input() {
    let model = common::paper(1);
    let j = solve_json("energy");
    assert_eq!(j["model"], "paper-case-1");
    assert_eq!(j["method"], "energy");
    assert_eq!(j["input"]["control"], "shortening");
    let cables = j["input"]["cables"].as_array().unwrap();
    // case1.toml: A shortened 4 %, B 3 % of the undeformed straight-chord length.
    for (c, pct) in [(0, 4.0), (1, 3.0)] {
        assert_eq!(cables[c]["name"], model.robot.cables[c].name.as_str());
        assert_eq!(cables[c]["drive"], "shorten");
        let want = model.robot.undeformed_chord_length(c) * pct / 100.0;
        let got = cables[c]["shorten_m"].as_f64().unwrap();
        assert!((got - want).abs() < 1e-12, "cable {c}: {got} vs {want}");
    }
    let j = solve_json("cosserat");
    assert_eq!(j["input"]["control"], "tension");
    let t = j["input"]["cables"][0]["tension_n"].as_f64().unwrap();
    assert_eq!(t, 4.169250);
    // The JSON still reads back as a shape.
    ccrkit::Shape::from_json_str(&j.to_string()).unwrap();
}

#[test]
fn view_writes_pages_for_methods_plans_and_sweeps() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli-view");
    std::fs::create_dir_all(&dir).unwrap();
    let p = |n: &str| dir.join(n).display().to_string();
    let shape = solve_json("geometric");
    // Made for case 1 among the wall (the view's model and `--scene`).
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let model = ccrkit::Model::from_file(root.join("models/paper/case1.toml")).unwrap();
    let mut scene = model.scene.clone();
    scene.merge(ccrkit::Scene::from_file(root.join("models/scenes/wall.toml")).unwrap());
    let request = ccrkit::method::run::SolveRequest::new(ccrkit::method::MethodKind::Geometric);
    let made_for = ccrkit::fingerprint::MadeFor::new(&model.robot, &scene, 0.0, &request);
    let plan = serde_json::json!({
        "waypoints": [{ "shape": shape }, { "shape": shape }],
        "made_for": made_for,
    });
    std::fs::write(p("plan.json"), plan.to_string()).unwrap();
    std::fs::write(
        p("ws.csv"),
        "sample,A_shortening_fraction,tip_x_m,tip_y_m,tip_z_m,status,iterations\n0,0.01,0.001,0,0.17,converged,4\n",
    )
    .unwrap();
    let out = ccrkit(&[
        "view",
        "models/paper/case1.toml",
        "--scene",
        "models/scenes/wall.toml",
        "--method",
        "geometric,energy",
        "--plan",
        &p("plan.json"),
        "--sweep",
        &p("ws.csv"),
        "--color-by",
        "iterations",
        "--out",
        &p("all.html"),
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(
        err.contains("3 layers, 1 obstacles, 2 frames, 1 tips"),
        "{err}"
    );
    let html = std::fs::read_to_string(p("all.html")).unwrap();
    assert!(html.starts_with("<!DOCTYPE html>") && html.contains("window.CCRKIT_DATA="));
    // Bad inputs are refused by name, and nothing is written.
    for (args, what) in [
        (vec!["--method", "nope"], "nope"),
        (
            vec!["--sweep", &p("ws.csv"), "--color-by", "zzz"],
            "color-by",
        ),
        (vec!["--color-by", "tip_x_m"], "--sweep"),
        (vec!["--plan", "models/paper/case1.toml"], "plan"),
    ] {
        let mut a = vec!["view", "models/paper/case1.toml", "--out"];
        let bad = p("bad.html");
        a.push(&bad);
        a.extend(args.iter().copied());
        let out = ccrkit(&a);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success() && err.contains(what), "{a:?}: {err}");
        assert!(!dir.join("bad.html").exists());
    }
}

#[test]
fn compare_draws_the_methods_overlaid() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli-compare");
    std::fs::create_dir_all(&dir).unwrap();
    let svg = dir.join("cmp.svg").display().to_string();
    let out = ccrkit(&[
        "compare",
        "models/paper/case1.toml",
        "--methods",
        "geometric,energy",
        "--scene",
        "models/scenes/wall.toml",
        "--plot",
        &svg,
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = std::fs::read_to_string(&svg).unwrap();
    for label in ["geometric", "energy", "obstacles", "contacts (reaction)"] {
        assert!(text.contains(label), "`{label}` not in the figure");
    }
    // A figure format it cannot write is refused before anything is solved.
    let out = ccrkit(&["compare", "models/paper/case1.toml", "--plot", "x.gif"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && err.contains("gif"), "{err}");
}

#[test]
fn view_draws_a_plan_written_by_ccrkit_plan() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli-plan-view");
    std::fs::create_dir_all(&dir).unwrap();
    let p = |n: &str| dir.join(n).display().to_string();
    std::fs::write(
        p("to.json"),
        "{\"actuation\": [{\"cable\": \"A\", \"shorten\": 0.0015}, {\"cable\": \"B\", \"shorten\": 0.0005}]}",
    )
    .unwrap();
    std::fs::write(
        p("from.json"),
        "{\"actuation\": [{\"cable\": \"A\", \"shorten\": 0.0}, {\"cable\": \"B\", \"shorten\": 0.0}]}",
    )
    .unwrap();
    let out = ccrkit(&[
        "plan",
        "models/paper/case1.toml",
        "--scene",
        "models/scenes/wall.toml",
        "--from-actuation",
        &p("from.json"),
        "--to-actuation",
        &p("to.json"),
        "--seed",
        "1",
        "--json",
        &p("plan.json"),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let plan: Value =
        serde_json::from_str(&std::fs::read_to_string(p("plan.json")).unwrap()).unwrap();
    let n = plan["waypoints"].as_array().unwrap().len();
    let out = ccrkit(&[
        "view",
        "models/paper/case1.toml",
        "--scene",
        "models/scenes/wall.toml",
        "--plan",
        &p("plan.json"),
        "--out",
        &p("plan.html"),
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(
        err.contains(&format!("1 layers, 1 obstacles, {n} frames")),
        "{err}"
    );
}

/// `predict` exits 1 with a named error when no row solved (it exited 0 with every row
/// failed), and still writes the CSV of statuses; with some rows failed and others solved it
/// exits 0 and the summary and the statuses say which failed.
#[test]
fn predict_fails_by_name_only_when_no_row_solved() {
    let dir = std::env::temp_dir().join(format!("ccrkit-predict-exit-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    let real = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("models/hardware/data/v4/tdcr_sysid_20260511-183002_val.csv"),
    )
    .expect("data");
    let lines: Vec<&str> = real.lines().take(6).collect();
    // The first servo pulled 900 mm in the chosen rows: no shape meets that (`infeasible`).
    let csv = |bad: &[usize]| -> String {
        let mut out = vec![lines[0].to_string()];
        for (i, r) in lines[1..].iter().enumerate() {
            let mut c: Vec<&str> = r.split(',').collect();
            if bad.contains(&i) {
                c[2] = "900";
            }
            out.push(c.join(","));
        }
        format!("{}\n", out.join("\n"))
    };
    for (name, bad, solved) in [
        ("all", vec![0, 1, 2, 3, 4], 0),
        ("some", vec![0, 2], 3),
        ("none", vec![], 5),
    ] {
        let data = dir.join(format!("{name}.csv"));
        std::fs::write(&data, csv(&bad)).expect("write");
        let out_csv = dir.join(format!("{name}.out.csv"));
        let out = ccrkit(&[
            "predict",
            "models/hardware/ftdcr_v4.toml",
            "--data",
            &data.to_string_lossy(),
            "--out",
            &out_csv.to_string_lossy(),
        ]);
        let (so, se) = (
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr),
        );
        assert!(
            so.contains(&format!("rows 5  solved {solved}  failed {}", 5 - solved)),
            "{name}: {so}"
        );
        let statuses: Vec<String> = std::fs::read_to_string(&out_csv)
            .expect("the CSV is written either way")
            .lines()
            .skip(1)
            .map(|l| l.rsplit(',').next().unwrap_or("").to_string())
            .collect();
        for (i, s) in statuses.iter().enumerate() {
            let want = if bad.contains(&i) { "infeasible" } else { "ok" };
            assert_eq!(s, want, "{name}: row {i}");
        }
        if solved == 0 {
            assert_eq!(out.status.code(), Some(1), "{name}: {so} {se}");
            assert!(
                se.contains("error: no row solved: 5 of 5 rows failed")
                    && se.contains("row 1: infeasible actuation"),
                "{name}: {se}"
            );
        } else {
            assert_eq!(out.status.code(), Some(0), "{name}: {se}");
        }
    }
}
