//! JSON scene files: the same fields and checks as TOML, read into the same
//! scene. Checked against the TOML reader on a generated scene of 1000 obstacles (every
//! field equal to the bit), on the committed wall scene through a whole solve, and on bad
//! input, where every error names the field.

use ccrkit::method::run::SolveRequest;
use ccrkit::{Model, Scene};
use std::path::PathBuf;

use crate::common::scenes;

use crate::common;
use crate::common::cli::{paper_path, root};

/// `body` written as `name` in the test's own temporary folder.
fn file(name: &str, body: &str) -> PathBuf {
    common::scene_file("scene-json", name, body)
}

/// The JSON scene `body` (written as `name.json`) is refused with an error naming each of
/// `what`.
fn refused_naming(name: &str, body: &str, what: &[&str]) {
    common::scene_refused_naming("scene-json", &format!("{name}.json"), body, what);
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
    let model = Model::from_file(paper_path(1)).unwrap();
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
    refused_naming(
        "type",
        r#"{"obstacles": [{"shape": "sphere", "radius": 0.01}, {"shape": "sphere", "radius": "big"}]}"#,
        &["obstacles[1].radius", "invalid type"],
    );
}

#[test]
fn an_unknown_field_is_refused_by_name() {
    refused_naming(
        "unknown",
        r#"{"obstacles": [{"shape": "sphere", "radus": 0.01}]}"#,
        &["obstacles[0]", "radus"],
    );
    refused_naming("top", r#"{"clearence": 0.01}"#, &["clearence"]);
}

#[test]
fn values_are_checked_as_in_toml() {
    refused_naming(
        "neg",
        r#"{"obstacles": [{"shape": "sphere", "radius": -0.01}]}"#,
        &["obstacles[0].radius"],
    );
    refused_naming(
        "shape",
        r#"{"obstacles": [{"shape": "cone", "radius": 0.01}]}"#,
        &["obstacles[0].shape", "cone"],
    );
    refused_naming(
        "quat",
        r#"{"obstacles": [{"shape": "sphere", "radius": 0.01, "rotation": {"quaternion": [0, 0, 0, 0]}}]}"#,
        &["obstacles[0].rotation.quaternion"],
    );
    refused_naming("clear", r#"{"clearance": -1.0}"#, &["clearance"]);
    refused_naming(
        "dup",
        r#"{"obstacles": [{"name": "a", "shape": "sphere", "radius": 0.01},
                          {"name": "a", "shape": "sphere", "radius": 0.01}]}"#,
        &["obstacles[1].name"],
    );
}

#[test]
fn broken_json_is_refused_with_its_place() {
    refused_naming(
        "trailing",
        r#"{"obstacles": []} extra"#,
        &["trailing characters"],
    );
    refused_naming("cut", r#"{"obstacles": [{"shape": "sphere""#, &["line 1"]);
    // A TOML body in a `.json` file is JSON that does not parse, not a TOML scene.
    refused_naming("toml_in_json", "clearance = 0.0\n", &["line 1"]);
}
