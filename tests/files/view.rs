//! The 3-D view in a real browser: headless Chromium opens each page, the test reads back what
//! the page drew (`window.ccrkitScene`, mirrored into `<pre id="ccrkit-scene">`), compares it
//! with the shapes and the scene, checks that no console error or uncaught exception happened,
//! and that a screenshot is not blank.
//!
//! Chromium is found as `$CCRKIT_CHROMIUM`, `chromium` or `chromium-browser`; without it the
//! browser checks are skipped with a note, unless `CCRKIT_REQUIRE_BROWSER=1` (set by `.ci/run`
//! after `.ci/install-browser.sh`).

use crate::common;

use ccrkit::export::view::{read_plan, read_sweep, View};
use ccrkit::method::{run::SolveRequest, MethodKind};
use ccrkit::study::{workspace, workspace_csv, WorkspaceOptions};
use ccrkit::{Model, Scene, Shape};
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Command;

fn chromium() -> Option<PathBuf> {
    if let Ok(p) = std::env::var("CCRKIT_CHROMIUM") {
        return Some(PathBuf::from(p));
    }
    for name in ["chromium", "chromium-browser"] {
        let ok = Command::new(name).arg("--version").output();
        if ok.is_ok_and(|o| o.status.success()) {
            return Some(PathBuf::from(name));
        }
    }
    if std::env::var("CCRKIT_REQUIRE_BROWSER").as_deref() == Ok("1") {
        panic!("CCRKIT_REQUIRE_BROWSER=1 but no chromium found (install: .ci/install-browser.sh)");
    }
    eprintln!("note: chromium not found; browser checks of the 3-D view skipped");
    None
}

fn out_dir() -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join("view-test");
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn chrome(bin: &Path, args: &[&str], url: &str) -> std::process::Output {
    let profile = tempdir("profile");
    let mut cmd = Command::new(bin);
    cmd.args([
        "--headless",
        "--no-sandbox",
        "--disable-gpu",
        "--use-angle=swiftshader",
        "--enable-unsafe-swiftshader",
        "--no-first-run",
        "--disable-extensions",
        "--window-size=1200,800",
        "--virtual-time-budget=5000",
    ])
    .arg(format!("--user-data-dir={}", profile.display()))
    .args(args)
    .arg(url);
    let out = cmd.output().expect("chromium runs");
    let _ = std::fs::remove_dir_all(&profile);
    out
}

fn tempdir(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!(
        "ccrkit-view-{tag}-{}-{:?}",
        std::process::id(),
        std::thread::current().id()
    ));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Open the page, return its `window.ccrkitScene` and assert no error was caught.
fn read_back(bin: &Path, page: &Path, hash: &str) -> Value {
    let url = format!("file://{}{hash}", page.canonicalize().unwrap().display());
    let out = chrome(bin, &["--dump-dom"], &url);
    let dom = String::from_utf8_lossy(&out.stdout);
    let text = |id: &str| -> String {
        let open = format!("<pre id=\"{id}\" hidden=\"\">");
        let start = dom
            .find(&open)
            .unwrap_or_else(|| panic!("no #{id} in the DOM of {}: {dom:.2000}", page.display()))
            + open.len();
        let end = start + dom[start..].find("</pre>").unwrap();
        dom[start..end]
            .replace("&lt;", "<")
            .replace("&gt;", ">")
            .replace("&amp;", "&")
    };
    let errors = text("ccrkit-errors");
    assert_eq!(errors, "[]", "console errors in {}", page.display());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        !stderr.contains("Uncaught"),
        "uncaught exception in {}: {stderr}",
        page.display()
    );
    let scene: Value = serde_json::from_str(&text("ccrkit-scene")).expect("scene summary JSON");
    assert_eq!(scene["ready"], true, "{scene}");
    scene
}

/// Take a screenshot; assert that a real picture was drawn (not blank, not one colour).
fn screenshot(bin: &Path, page: &Path, png_path: &Path) {
    let url = format!("file://{}", page.canonicalize().unwrap().display());
    let arg = format!("--screenshot={}", png_path.display());
    let out = chrome(bin, &[&arg], &url);
    assert!(
        png_path.exists(),
        "no screenshot: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let dec = png::Decoder::new(std::io::BufReader::new(
        std::fs::File::open(png_path).unwrap(),
    ));
    let mut rd = dec.read_info().unwrap();
    let mut buf = vec![0; rd.output_buffer_size()];
    let info = rd.next_frame(&mut buf).unwrap();
    let ch = info.color_type.samples();
    let px = &buf[..info.buffer_size()];
    let n = px.len() / ch;
    let non_white = px
        .chunks(ch)
        .filter(|p| p[..3].iter().any(|&c| c < 235))
        .count();
    let blue = px
        .chunks(ch)
        .filter(|p| p[2] > p[0].saturating_add(60))
        .count();
    assert!(
        non_white * 50 > n,
        "screenshot nearly blank: {non_white} of {n} pixels drawn"
    );
    // The first layer's backbone and disks are blue (#1f77b4): the robot itself was drawn.
    assert!(blue > 500, "no robot in the screenshot: {blue} blue pixels");
}

fn solve(model: &Model, kind: MethodKind, scene: Option<Scene>) -> Shape {
    SolveRequest::new(kind)
        .with_scene(scene)
        .run(model)
        .unwrap()
        .shape
}

fn assert_layer(scene: &Value, k: usize, shape: &Shape) {
    let l = &scene["layers"][k];
    assert_eq!(l["method"], shape.method.as_str(), "{l}");
    assert_eq!(l["disks"], shape.disks.len(), "{l}");
    assert_eq!(l["cables"], shape.cables.len(), "{l}");
    assert_eq!(l["contacts"], shape.contacts.len(), "{l}");
    assert!(
        l["backbone_points"].as_u64().unwrap() >= shape.disks.len() as u64,
        "{l}"
    );
}

#[test]
fn methods_overlaid_next_to_a_wall_are_drawn_with_their_contacts() {
    let model = common::paper(1);
    let wall = Scene::from_file("models/scenes/wall.toml").unwrap();
    let energy = solve(&model, MethodKind::Energy, Some(wall.clone()));
    let geometric = solve(&model, MethodKind::Geometric, Some(wall.clone()));
    assert!(!energy.contacts.is_empty(), "the wall test needs contacts");
    let mut view = View::new("case 1 at the wall", &model.robot, &wall);
    view.add_shape("energy", &energy).unwrap();
    view.add_shape("geometric", &geometric).unwrap();
    let page = out_dir().join("wall.html");
    view.write(&page).unwrap();
    let html = std::fs::read_to_string(&page).unwrap();
    // Self-contained: no script, style or image is loaded from anywhere.
    for tag in ["<script src", "<link", "<img", "fetch(", "import("] {
        assert!(!html.contains(tag), "the page loads something: `{tag}`");
    }
    let Some(bin) = chromium() else { return };
    let scene = read_back(&bin, &page, "");
    assert_layer(&scene, 0, &energy);
    assert_layer(&scene, 1, &geometric);
    assert_eq!(scene["obstacles"], 1);
    assert_eq!(scene["frames"], 1);
    assert_eq!(
        serde_json::to_value(view.expected().layers)
            .unwrap()
            .as_array()
            .unwrap()
            .len(),
        2
    );
    screenshot(&bin, &page, &out_dir().join("wall.png"));
}

#[test]
fn every_obstacle_kind_and_a_sweep_cloud_are_drawn() {
    let model = common::paper(2);
    let scene = Scene::from_file("tests/data/view_obstacles.toml").unwrap();
    let shape = solve(&model, MethodKind::Geometric, None);
    let opts = WorkspaceOptions {
        samples: 40,
        ..Default::default()
    };
    let ws = workspace(&model, &opts).unwrap();
    let sweep = read_sweep(&workspace_csv(&ws)).unwrap();
    let solved = ws.samples.iter().filter(|s| s.tip.is_some()).count();
    assert_eq!(sweep.tips.len(), solved);
    let mut view = View::new("obstacles and sweep", &model.robot, &scene);
    view.add_shape("geometric", &shape).unwrap();
    view.set_sweep(&sweep, Some("status")).unwrap();
    let page = out_dir().join("obstacles.html");
    view.write(&page).unwrap();
    let Some(bin) = chromium() else { return };
    let got = read_back(&bin, &page, "");
    assert_layer(&got, 0, &shape);
    assert_eq!(got["obstacles"], scene.obstacles.len());
    assert_eq!(
        scene.obstacles.len(),
        5,
        "sphere, box, capsule, cylinder, mesh"
    );
    assert_eq!(got["points"], solved);
    assert_eq!(got["color_by"], "status");
}

#[test]
fn a_thousand_waypoint_plan_reads_back_and_stays_interactive() {
    let model = common::paper(1);
    // The closed form: 1000 solves in milliseconds (the viewer does not care which method).
    let kind = MethodKind::ConstantCurvature;
    let t = std::time::Instant::now();
    let method = kind.build(&Default::default()).unwrap();
    let n = 1000;
    // A plan file in `ccrkit plan`'s format, built from solves along the actuation.
    let waypoints: Vec<Value> = (0..n)
        .map(|k| {
            let act = model.actuation.scaled(k as f64 / (n - 1) as f64);
            let s = method
                .solve(&model.robot, &act, &Scene::empty(), None)
                .unwrap();
            serde_json::json!({ "actuation": {}, "shape": s.to_json() })
        })
        .collect();
    let made_for = ccrkit::fingerprint::MadeFor::new(
        &model.robot,
        &Scene::empty(),
        0.0,
        &SolveRequest::new(kind),
    );
    let text = serde_json::json!({
        "waypoints": waypoints,
        "min_clearance_m": 0.0,
        "made_for": made_for,
    })
    .to_string();
    eprintln!("{n} solves: {:.1} s", t.elapsed().as_secs_f64());
    let shapes = read_plan(&text, &model.robot, &Scene::empty()).unwrap();
    assert_eq!(shapes.len(), n);
    let mut view = View::new("plan", &model.robot, &Scene::empty());
    view.add_path("plan", &shapes).unwrap();
    let page = out_dir().join("plan.html");
    view.write(&page).unwrap();
    let Some(bin) = chromium() else { return };
    let got = read_back(&bin, &page, "#step-all");
    assert_eq!(got["frames"], n);
    assert_layer(&got, 0, &shapes[0]);
    let update = got["update_ms_mean"].as_f64().unwrap();
    let drawn = got["frame_ms_mean"].as_f64().unwrap();
    eprintln!(
        "plan of {n} waypoints: {} bytes; a frame change costs {update:.2} ms of script, \
         {drawn:.1} ms drawn by software GL (headless Chromium, 1200x800)",
        std::fs::metadata(&page).unwrap().len(),
    );
    // Interactive: the script's part of a frame change fits in one 60 Hz frame.
    assert!(update < 16.0, "frame change costs {update} ms of script");
}

#[test]
fn paper_case_pages_stay_under_two_megabytes() {
    for case in 1..=3 {
        let model = common::paper(case);
        let mut view = View::new("case", &model.robot, &model.scene);
        for kind in [
            MethodKind::Geometric,
            MethodKind::Energy,
            MethodKind::Cosserat,
        ] {
            view.add_shape(kind.name(), &solve(&model, kind, None))
                .unwrap();
        }
        let len = view.to_html().len();
        assert!(len < 2_000_000, "case {case}: {len} bytes");
    }
}

#[test]
fn bad_inputs_are_named() {
    let model = common::paper(1);
    let mut view = View::new("t", &model.robot, &Scene::empty());
    let mut s = solve(&model, MethodKind::Geometric, None);
    s.disks.pop();
    let e = view.add_shape("x", &s).unwrap_err().to_string();
    assert!(e.contains("disks"), "{e}");
    let e = view.add_path("x", &[]).unwrap_err().to_string();
    assert!(e.contains("no shape"), "{e}");
    let e = read_plan("{\"waypoints\": []}", &model.robot, &Scene::empty())
        .unwrap_err()
        .to_string();
    assert!(e.contains("plan.waypoints"), "{e}");
    let e = read_plan("{\"waypoints\": [{\"shape\": {\"method\": \"x\", \"disks\": [], \"backbone\": [], \"cables\": [], \"contacts\": [], \"report\": {\"converged\": true, \"iterations\": 0, \"residual\": 0, \"solve_time_s\": 0}}}]}", &model.robot, &Scene::empty())
        .unwrap_err()
        .to_string();
    assert!(e.contains("waypoints[0].shape.disks"), "{e}");
}

/// A plan through a port animates insertion and rotation: every frame of the page carries the
/// waypoint's insertion and rotation (the shape's), the robot carries the port's pose, and the
/// page opened at a waypoint reports that waypoint's insertion and rotation and draws the port.
#[test]
fn a_plan_through_a_port_carries_insertion_and_rotation_per_frame() {
    let mut model = Model::from_file("models/soft/lung_rod.toml").unwrap();
    model.robot.port.as_mut().unwrap().pose = nalgebra::Isometry3::translation(0.01, -0.02, 0.03);
    for (c, t) in model.actuation.cables.iter_mut().zip([0.6, 0.3, 0.2]) {
        c.tension = Some(t);
    }
    let solver = SolveRequest::new(MethodKind::DEFAULT).solver().unwrap();
    let states = [(0.03, -1.0), (0.06, 0.0), (0.09, 1.0), (0.11, 2.5)];
    let shapes: Vec<Shape> = states
        .iter()
        .map(|&(d, psi)| {
            let mut a = model.actuation.clone();
            a.insertion = Some(d);
            a.rotation = Some(psi);
            solver.solve(&model.robot, &a, &model.scene, None).unwrap()
        })
        .collect();
    let mut view = View::new("through the port", &model.robot, &model.scene);
    view.add_path("plan", &shapes).unwrap();
    let doc = serde_json::to_value(&view).unwrap();
    assert_eq!(
        doc["robot"]["port"]["position"],
        serde_json::json!([0.01, -0.02, 0.03])
    );
    for (k, (s, &(d, psi))) in shapes.iter().zip(&states).enumerate() {
        let p = s.port.as_ref().unwrap();
        assert_eq!((p.insertion, p.rotation), (d, psi));
        assert_eq!(
            doc["layers"][0]["frames"][k]["port"],
            serde_json::json!([d, psi]),
            "{k}"
        );
    }
    let page = out_dir().join("port_plan.html");
    view.write(&page).unwrap();
    let Some(bin) = chromium() else { return };
    for (k, &(d, psi)) in states.iter().enumerate() {
        let got = read_back(&bin, &page, &format!("#frame={k}"));
        assert_eq!(got["frame"], k, "{got}");
        assert_eq!(got["port"]["insertion"], d, "{got}");
        assert_eq!(got["port"]["rotation"], psi, "{got}");
        assert_layer(&got, 0, &shapes[k]);
    }
}
