//! `Shape::from_json_str` inverts `Shape::to_json`: a shape read back from the command line's
//! JSON has the same disks, backbone, cables, contacts and report (warm-start state aside).

use ccrkit::method::run::SolveRequest;
use ccrkit::method::MethodKind;
use ccrkit::{Model, Scene, Shape};

fn round_trip(shape: &Shape) -> Shape {
    let text = shape.to_json_string();
    Shape::from_json_str(&text).expect("reads back")
}

/// Equal to the last bit (serde_json's `float_roundtrip` parser reads back exactly the
/// shortest representation its writer printed).
fn close(a: f64, b: f64) -> bool {
    a == b
}

fn check(shape: &Shape) {
    let back = round_trip(shape);
    let mut expect = shape.clone();
    expect.report.warm = None;
    assert_eq!(back.method, expect.method);
    assert_eq!(back.disks.len(), expect.disks.len());
    for (a, b) in back.disks.iter().zip(&expect.disks) {
        assert!(close(a.s, b.s));
        for i in 0..3 {
            assert!(close(a.position[i], b.position[i]));
        }
        for i in 0..9 {
            assert!(close(a.rotation[i], b.rotation[i]));
        }
    }
    assert_eq!(back.backbone.len(), expect.backbone.len());
    assert_eq!(back.cables.len(), expect.cables.len());
    for (a, b) in back.cables.iter().zip(&expect.cables) {
        assert_eq!(
            (&a.name, a.slack, &a.slack_sections),
            (&b.name, b.slack, &b.slack_sections)
        );
        assert_eq!(a.tension.is_some(), b.tension.is_some());
    }
    assert_eq!(back.contacts.len(), expect.contacts.len());
    assert_eq!(back.report.converged, expect.report.converged);
    assert_eq!(back.report.iterations, expect.report.iterations);
    assert_eq!(back.report.stable, expect.report.stable);
    assert_eq!(back.report.notes, expect.report.notes);
    assert_eq!(back.report.sections.len(), expect.report.sections.len());
    assert_eq!(
        back.report.jacobian.is_some(),
        expect.report.jacobian.is_some()
    );
    assert_eq!(back.contacts, expect.contacts);
    assert_eq!(back.report, expect.report);
    // And the JSON of the read-back shape is the same text.
    assert_eq!(back.to_json_string(), shape.to_json_string());
}

#[test]
fn energy_geometric_and_rod_shapes_round_trip() {
    let model = Model::from_file("models/paper/case1.toml").expect("case 1");
    for kind in [
        MethodKind::Energy,
        MethodKind::Geometric,
        MethodKind::Cosserat,
    ] {
        let s = SolveRequest::new(kind).run(&model).expect("solves").shape;
        check(&s);
    }
}

#[test]
fn shapes_with_contacts_round_trip() {
    let model = Model::from_file("models/paper/case1.toml").expect("case 1");
    let wall = Scene::from_file("models/scenes/wall.toml").expect("wall");
    let s = SolveRequest::new(MethodKind::Energy)
        .with_scene(Some(wall))
        .run(&model)
        .expect("solves against the wall")
        .shape;
    assert!(!s.contacts.is_empty(), "the wall is touched");
    check(&s);
}
