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
