//! Plan files that lie: a plan read back (`view --plan`) names the robot and obstacles it was
//! made for, and is refused by name with another robot (the holes at 4.0 mm instead of 4.5),
//! other obstacles, or no such record; nothing in it is believed about safety.

use crate::common::adversarial_harness::cli::ccrkit_in;
use crate::common::adversarial_harness::{root, scratch};
use ccrkit::export::view::read_plan;
use ccrkit::export::ExportError;
use ccrkit::method::run::SolveRequest;
use ccrkit::method::MethodKind;
use ccrkit::plan::{plan, Goal, PlanOptions};
use ccrkit::{Model, Scene};

/// Paper case 1 with its holes at `radius` \[m\] and a ball beside the bend.
fn model_text(radius: f64) -> String {
    let text = std::fs::read_to_string(root().join("models/paper/case1.toml")).expect("case 1");
    let text = text.replace("radius = 0.008", &format!("radius = {radius}"));
    let ball = "[[obstacles]]\nname = \"ball\"\nshape = \"sphere\"\n\
                position = [0.064, 0.111, 0.104]\nradius = 0.012\n";
    format!("clearance = 0.0005\n{text}\n{ball}")
}

/// A far sphere, as a scene file's text.
const FAR: &str =
    "[[obstacles]]\nname = \"far\"\nshape = \"sphere\"\nposition = [0.5, 0, 0]\nradius = 0.01\n";

/// `plan`'s JSON for a short path of case 1 (A shortened a little).
fn plan_text(model: &Model) -> String {
    let request = SolveRequest::new(MethodKind::Energy);
    let goal = Goal::Actuation(vec![0.002, 0.0]);
    let p = plan(model, &request, None, &goal, &PlanOptions::default(), None).expect("plans");
    serde_json::to_string(&p.to_json()).expect("JSON")
}

fn refused_as(r: Result<Vec<ccrkit::Shape>, ExportError>, want: &str, says: &str) {
    match r {
        Err(ExportError::Input { field, reason }) => {
            assert_eq!(field, want, "{reason}");
            assert!(reason.contains(says), "{reason}");
        }
        other => panic!(
            "expected `{want}` refused, got {:?}",
            other.map(|s| s.len())
        ),
    }
}

/// Read back with its own robot and obstacles the plan is drawn; with the holes at 4.0 mm
/// instead of 4.5, with a far sphere added, or with its `made_for` removed it is refused by
/// name (it was drawn without a word).
#[test]
fn a_plan_read_with_another_robot_or_other_obstacles_is_refused_by_name() {
    let model = Model::from_toml_str(&model_text(0.0045)).expect("model");
    let text = plan_text(&model);
    let shapes = read_plan(&text, &model.robot, &model.scene).expect("its own robot reads");
    assert!(shapes.len() >= 2);
    let other = Model::from_toml_str(&model_text(0.0040)).expect("model");
    refused_as(
        read_plan(&text, &other.robot, &model.scene),
        "plan.made_for.robot_fingerprint",
        "make it again for this robot",
    );
    let mut more = model.scene.clone();
    let far = scratch("plan-files-lib").join("far.toml");
    std::fs::write(&far, FAR).expect("write");
    more.merge(Scene::from_file(&far).expect("scene"));
    refused_as(
        read_plan(&text, &model.robot, &more),
        "plan.made_for.scene_fingerprint",
        "with this scene",
    );
    let mut v: serde_json::Value = serde_json::from_str(&text).expect("JSON");
    v.as_object_mut().expect("object").remove("made_for");
    refused_as(
        read_plan(&v.to_string(), &model.robot, &model.scene),
        "plan.made_for",
        "plan again",
    );
}

/// The same through the command line: `view` with the plan's model draws it, with another
/// robot's model or an added `--scene` it exits 1 naming the field.
#[test]
fn view_refuses_a_plan_made_for_another_robot_or_scene() {
    let dir = scratch("plan-files");
    let model = Model::from_toml_str(&model_text(0.0045)).expect("model");
    std::fs::write(dir.join("M.toml"), model_text(0.0045)).expect("write");
    std::fs::write(dir.join("M4.toml"), model_text(0.0040)).expect("write");
    std::fs::write(dir.join("far.toml"), FAR).expect("write");
    std::fs::write(dir.join("p.json"), plan_text(&model)).expect("write");
    let ok = ccrkit_in(
        &dir,
        &["view", "M.toml", "--plan", "p.json", "--out", "v.html"],
    );
    assert!(
        ok.status.success(),
        "{}",
        String::from_utf8_lossy(&ok.stderr)
    );
    for (args, field) in [
        (
            vec!["view", "M4.toml", "--plan", "p.json", "--out", "v4.html"],
            "plan.made_for.robot_fingerprint",
        ),
        (
            vec![
                "view", "M.toml", "--plan", "p.json", "--scene", "far.toml", "--out", "w.html",
            ],
            "plan.made_for.scene_fingerprint",
        ),
    ] {
        let out = ccrkit_in(&dir, &args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{args:?}: {err}");
        assert!(err.contains(field), "{args:?}: {err}");
    }
}

/// A plan whose waypoint was edited — a rotation of `5·I`, a mirror (det −1), a disk at
/// 1e300 m, a backbone point or a cable hole there, a cable with more holes than disks or
/// slack in a section the shape does not have — is refused by the waypoint's field and the
/// reason (each was drawn); a NaN cannot be written in JSON and is refused as the parse error,
/// and by field where a shape is built in memory.
#[test]
fn a_plan_with_rotations_that_are_not_rotations_or_points_far_away_is_refused_by_field() {
    let model = Model::from_toml_str(&model_text(0.0045)).expect("model");
    let text = plan_text(&model);
    let plan: serde_json::Value = serde_json::from_str(&text).expect("JSON");
    let five = serde_json::json!([[5.0, 0.0, 0.0], [0.0, 5.0, 0.0], [0.0, 0.0, 5.0]]);
    let mirror = serde_json::json!([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, -1.0]]);
    let far = serde_json::json!([1e300, 0.0, 0.0]);
    type Edit = Box<dyn Fn(&mut serde_json::Value)>;
    let edits: Vec<(Edit, &str, &str)> = vec![
        (
            Box::new(move |s| s["disks"][2]["rotation"] = five.clone()),
            "disks[2].rotation",
            "det = 125",
        ),
        (
            Box::new(move |s| s["disks"][2]["rotation"] = mirror.clone()),
            "disks[2].rotation",
            "det = -1",
        ),
        (
            Box::new({
                let far = far.clone();
                move |s| s["disks"][3]["position"] = far.clone()
            }),
            "disks[3].position",
            "a coordinate of 1e300 m",
        ),
        (
            Box::new({
                let far = far.clone();
                move |s| s["backbone"][0] = far.clone()
            }),
            "backbone[0]",
            "within ±2100 m",
        ),
        (
            Box::new(move |s| s["cables"][0]["points"][1] = far.clone()),
            "cables[0].points[1]",
            "within ±2100 m",
        ),
        (
            Box::new(|s| {
                let p = s["cables"][1]["points"][0].clone();
                let pts = s["cables"][1]["points"].as_array_mut().expect("points");
                pts.extend(std::iter::repeat_n(p, 40));
            }),
            "cables[1].points",
            "a cable passes 1 to",
        ),
        (
            Box::new(|s| s["cables"][0]["slack_sections"] = serde_json::json!([99])),
            "cables[0].slack_sections",
            "section 99",
        ),
    ];
    for (edit, field, says) in &edits {
        let mut p = plan.clone();
        edit(&mut p["waypoints"][1]["shape"]);
        refused_as(
            read_plan(&p.to_string(), &model.robot, &model.scene),
            &format!("waypoints[1].shape.{field}"),
            says,
        );
    }
    // NaN: JSON cannot hold it (the parse refuses), a shape built in memory names the field.
    let nan = text.replacen("\"rotation\":[[1.0", "\"rotation\":[[NaN", 1);
    assert_ne!(nan, text);
    refused_as(
        read_plan(&nan, &model.robot, &model.scene),
        "plan",
        "expected",
    );
    let mut s: ccrkit::shape::ShapeJson =
        serde_json::from_value(plan["waypoints"][1]["shape"].clone()).expect("shape");
    s.disks[2].rotation[0][0] = f64::NAN;
    let e = s.into_shape("shape").expect_err("refused");
    assert_eq!(e.field(), Some("shape.disks[2]"), "{e}");
}

/// A waypoint whose cable passes fewer disks than the robot's cable is refused by the view
/// (the robot's count, by name), not drawn short.
#[test]
fn a_waypoint_cable_with_fewer_holes_than_the_robots_is_refused_by_the_view() {
    let model = Model::from_toml_str(&model_text(0.0045)).expect("model");
    let mut plan: serde_json::Value = serde_json::from_str(&plan_text(&model)).expect("JSON");
    let pts = plan["waypoints"][1]["shape"]["cables"][0]["points"]
        .as_array_mut()
        .expect("points");
    pts.truncate(pts.len() - 1);
    let shapes = read_plan(&plan.to_string(), &model.robot, &model.scene).expect("reads");
    let mut view = ccrkit::export::view::View::new("t", &model.robot, &model.scene);
    let e = view
        .add_path("plan", &shapes)
        .expect_err("refused")
        .to_string();
    assert!(e.contains("cable `A` has") && e.contains("passes"), "{e}");
    assert!(e.contains("waypoint 1:"), "{e}");
}
