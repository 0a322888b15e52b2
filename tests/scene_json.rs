//! JSON scene files (issue 16 #5): the same fields and checks as TOML, read into the same
//! scene. Checked against the TOML reader on a generated scene of 1000 obstacles (every
//! field equal to the bit), on the committed wall scene through a whole solve, and on bad
//! input, where every error names the field.

use ccrkit::method::run::SolveRequest;
use ccrkit::{Model, Scene};
use std::path::PathBuf;

#[path = "common/scenes.rs"]
mod scenes;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// `body` written as `name` in the test's own temporary folder.
fn file(name: &str, body: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("ccrkit-scene-json-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join(name);
    std::fs::write(&p, body).unwrap();
    p
}

fn json_err(name: &str, body: &str) -> String {
    match Scene::from_file(file(&format!("{name}.json"), body)) {
        Ok(_) => panic!("scene `{name}` was accepted"),
        Err(e) => e.to_string(),
    }
}

fn assert_names(msg: &str, what: &str) {
    assert!(msg.contains(what), "error `{msg}` does not name `{what}`");
}

#[test]
fn a_json_scene_of_1000_obstacles_equals_its_toml_twin() {
    let toml = Scene::from_file(file("s1000.toml", &scenes::scene_text(1000, 7))).unwrap();
    let json = Scene::from_file(file("s1000.json", &scenes::scene_json(1000, 7))).unwrap();
    assert_eq!(toml.clearance, json.clearance);
    assert_eq!(toml.obstacles.len(), 1000);
    assert_eq!(json.obstacles.len(), 1000);
    for (a, b) in toml.obstacles.iter().zip(&json.obstacles) {
        assert_eq!(a.name, b.name);
        assert_eq!(a.kind, b.kind, "{}", a.name);
        assert_eq!(a.pose, b.pose, "{}", a.name);
        assert_eq!(a.aabb, b.aabb, "{}", a.name);
    }
}

#[test]
fn the_wall_as_json_gives_the_same_solve_as_the_wall_as_toml() {
    let model = Model::from_file(root().join("models/paper/case1.toml")).unwrap();
    let wall = |p: &str| Scene::from_file(root().join(p)).unwrap();
    let (toml, json) = (
        wall("models/scenes/wall.toml"),
        wall("models/scenes/wall.json"),
    );
    let solve = |scene: Scene| {
        SolveRequest::new("energy".parse().unwrap())
            .with_scene(Some(scene))
            .run(&model)
            .unwrap()
            .shape
    };
    let (a, b) = (solve(toml), solve(json));
    assert!(!a.contacts.is_empty(), "the wall is touched");
    assert_eq!(a.tip(), b.tip());
    assert_eq!(a.disks, b.disks);
    assert_eq!(a.contacts, b.contacts);
}

#[test]
fn a_wrong_type_names_its_path() {
    let e = json_err(
        "type",
        r#"{"obstacles": [{"shape": "sphere", "radius": 0.01}, {"shape": "sphere", "radius": "big"}]}"#,
    );
    assert_names(&e, "obstacles[1].radius");
    assert_names(&e, "invalid type");
}

#[test]
fn an_unknown_field_is_refused_by_name() {
    let e = json_err(
        "unknown",
        r#"{"obstacles": [{"shape": "sphere", "radus": 0.01}]}"#,
    );
    assert_names(&e, "obstacles[0]");
    assert_names(&e, "radus");
    let e = json_err("top", r#"{"clearence": 0.01}"#);
    assert_names(&e, "clearence");
}

#[test]
fn values_are_checked_as_in_toml() {
    let e = json_err(
        "neg",
        r#"{"obstacles": [{"shape": "sphere", "radius": -0.01}]}"#,
    );
    assert_names(&e, "obstacles[0].radius");
    let e = json_err(
        "shape",
        r#"{"obstacles": [{"shape": "cone", "radius": 0.01}]}"#,
    );
    assert_names(&e, "obstacles[0].shape");
    assert_names(&e, "cone");
    let e = json_err(
        "quat",
        r#"{"obstacles": [{"shape": "sphere", "radius": 0.01, "rotation": {"quaternion": [0, 0, 0, 0]}}]}"#,
    );
    assert_names(&e, "obstacles[0].rotation.quaternion");
    let e = json_err("clear", r#"{"clearance": -1.0}"#);
    assert_names(&e, "clearance");
    let e = json_err(
        "dup",
        r#"{"obstacles": [{"name": "a", "shape": "sphere", "radius": 0.01},
                          {"name": "a", "shape": "sphere", "radius": 0.01}]}"#,
    );
    assert_names(&e, "obstacles[1].name");
}

#[test]
fn broken_json_is_refused_with_its_place() {
    let e = json_err("trailing", r#"{"obstacles": []} extra"#);
    assert_names(&e, "trailing characters");
    let e = json_err("cut", r#"{"obstacles": [{"shape": "sphere""#);
    assert_names(&e, "line 1");
    // A TOML body in a `.json` file is JSON that does not parse, not a TOML scene.
    let e = json_err("toml_in_json", "clearance = 0.0\n");
    assert_names(&e, "line 1");
}
