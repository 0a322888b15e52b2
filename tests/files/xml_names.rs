//! Every URDF and SRDF ccrkit writes is well-formed XML, checked by an XML parser independent
//! of the writers (roxmltree): names with XML's special characters are escaped and come back
//! unchanged; names with a character XML 1.0 cannot hold (U+0001, NUL, U+FFFE) are refused by
//! name when the model is read and when a shape is exported, never written.

use crate::common::paper;
use ccrkit::export::{export_urdf, ExportError, UrdfMode, UrdfOptions};
use ccrkit::method::run::SolveRequest;
use ccrkit::method::MethodKind;
use ccrkit::{Model, ModelError};

fn solved(model: &Model) -> ccrkit::Shape {
    SolveRequest::new(MethodKind::Geometric)
        .run(model)
        .expect("solves")
        .shape
}

/// The `name` attribute of the XML document's root element, after roxmltree parsed it.
fn root_name(xml: &str, what: &str) -> String {
    let doc = roxmltree::Document::parse(xml).unwrap_or_else(|e| panic!("{what}: {e}"));
    doc.root_element()
        .attribute("name")
        .unwrap_or_else(|| panic!("{what}: no name"))
        .to_string()
}

#[test]
fn names_with_xml_special_characters_are_escaped_and_round_trip() {
    let mut model = paper(3);
    let name = "a&b<c>\"d'e é カ";
    model.robot.name = name.into();
    model.robot.cables[0].name = "<&\">".into();
    let shape = solved(&model);
    for mode in [UrdfMode::Articulated, UrdfMode::Fixed] {
        let opts = UrdfOptions {
            mode,
            cables: true,
            name: None,
        };
        let e = export_urdf(&shape, &model.robot, &opts).expect("exports");
        assert_eq!(root_name(&e.urdf, "URDF"), name);
        let doc = roxmltree::Document::parse(&e.urdf).expect("URDF parses");
        assert!(
            doc.descendants()
                .any(|n| n.attribute("name").is_some_and(|s| s.contains("<&\">"))),
            "the cable's name comes back unescaped from its links"
        );
        if let Some(srdf) = &e.srdf {
            assert_eq!(root_name(srdf, "SRDF"), name);
        }
    }
}

#[test]
fn names_xml_cannot_hold_are_refused_by_name() {
    let bad = ["a\u{1}b", "nul\0", "x\u{FFFE}"];
    // In a model file: refused when it is read, naming the field.
    let text = std::fs::read_to_string(crate::common::cli::root().join("models/paper/case1.toml"))
        .expect("case 1");
    for b in bad {
        let escaped: String = b.chars().map(|c| format!("\\U{:08X}", c as u32)).collect();
        for (from, field) in [
            ("name = \"paper-case-1\"", "name"),
            ("name = \"A\"", "cables[0].name"),
        ] {
            let key = &from[..from.find('"').expect("quoted")];
            let edited = text.replacen(from, &format!("{key}\"{escaped}\""), 1);
            assert_ne!(edited, text, "{from} in case 1");
            match Model::from_toml_str(&edited) {
                Err(ModelError::Invalid { field: f, reason }) => {
                    assert_eq!(f, field, "{reason}");
                    assert!(reason.contains("U+"), "{reason}");
                }
                other => panic!("{b:?} as {field}: expected a named refusal, got {other:?}"),
            }
        }
    }
    // Given to the exporter directly (an API caller's robot or option): refused, not written.
    let model = paper(1);
    let shape = solved(&model);
    for b in bad {
        let mut robot = model.robot.clone();
        robot.name = b.into();
        let opts = UrdfOptions::default();
        match export_urdf(&shape, &robot, &opts) {
            Err(ExportError::Input { field, reason }) => {
                assert_eq!(field, "name", "{reason}");
                assert!(reason.contains("U+"), "{reason}");
            }
            other => panic!(
                "{b:?}: expected a named refusal, got {:?}",
                other.map(|e| e.urdf)
            ),
        }
        let opts = UrdfOptions {
            name: Some(b.into()),
            ..UrdfOptions::default()
        };
        assert!(matches!(
            export_urdf(&shape, &model.robot, &opts),
            Err(ExportError::Input { .. })
        ));
    }
}
