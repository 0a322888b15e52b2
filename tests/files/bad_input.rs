//! Bad model files: one test per validation rule, each asserting the error names the field.

use ccrkit::{Model, ModelError};

const GOOD: &str = r#"
name = "t"
[robot]
sections = 4
section_length = 0.02
disk_radius = 0.012
disk_thickness = 0.002
backbone = { youngs_modulus = 1.1e9, poisson_ratio = 0.3, diameter = 0.003 }
[[cables]]
name = "A"
radius = 0.008
angles = { straight = 0.0 }
shorten_percent = 2.0
tension = 1.0
"#;

/// Replace `from` by `to` in the good file and expect an error naming `field`.
fn rejects(from: &str, to: &str, field: &str) {
    assert!(
        GOOD.contains(from),
        "test setup: `{from}` not in the good file"
    );
    let text = GOOD.replacen(from, to, 1);
    match Model::from_toml_str(&text) {
        Ok(_) => panic!("accepted a file with {to}"),
        Err(e) => {
            let msg = e.to_string();
            assert!(msg.contains(field), "error `{msg}` does not name `{field}`");
        }
    }
}

#[test]
fn the_good_file_is_accepted() {
    let m = Model::from_toml_str(GOOD).unwrap();
    assert_eq!(m.robot.sections(), 4);
    assert_eq!(m.robot.cables[0].angle.len(), 5);
}

#[test]
fn unparsable_text() {
    let e = Model::from_toml_str("name = ").unwrap_err();
    assert!(matches!(e, ModelError::Parse { .. }));
}

#[test]
fn missing_file_names_the_path() {
    let e = Model::from_file("no/such/file.toml").unwrap_err();
    assert!(e.to_string().contains("no/such/file.toml"));
}

#[test]
fn unknown_field() {
    rejects(
        "disk_thickness = 0.002",
        "disk_thickness = 0.002\ncolour = 3",
        "colour",
    );
}

#[test]
fn unknown_cable_field() {
    rejects("tension = 1.0", "tension = 1.0\nfriction = 0.1", "friction");
}

#[test]
fn zero_sections() {
    rejects("sections = 4", "sections = 0", "robot.sections");
}

#[test]
fn negative_section_length() {
    rejects(
        "section_length = 0.02",
        "section_length = -0.02",
        "robot.section_length",
    );
}

#[test]
fn zero_section_length() {
    rejects(
        "section_length = 0.02",
        "section_length = 0.0",
        "robot.section_length",
    );
}

#[test]
fn section_lengths_of_wrong_count() {
    rejects(
        "section_length = 0.02",
        "section_lengths = [0.02, 0.02]",
        "robot.section_lengths",
    );
}

#[test]
fn both_section_length_forms() {
    rejects(
        "section_length = 0.02",
        "section_length = 0.02\nsection_lengths = [0.02, 0.02, 0.02, 0.02]",
        "robot.section_lengths",
    );
}

#[test]
fn nan_disk_radius() {
    rejects(
        "disk_radius = 0.012",
        "disk_radius = nan",
        "robot.disk_radius",
    );
}

#[test]
fn infinite_youngs_modulus() {
    rejects(
        "youngs_modulus = 1.1e9",
        "youngs_modulus = inf",
        "robot.backbone.youngs_modulus",
    );
}

#[test]
fn negative_disk_thickness() {
    rejects(
        "disk_thickness = 0.002",
        "disk_thickness = -0.002",
        "robot.disk_thickness",
    );
}

#[test]
fn disk_thicker_than_a_section() {
    rejects(
        "disk_thickness = 0.002",
        "disk_thickness = 0.05",
        "robot.disk_thickness",
    );
}

#[test]
fn poisson_ratio_out_of_range() {
    rejects(
        "poisson_ratio = 0.3",
        "poisson_ratio = 0.7",
        "robot.backbone.poisson_ratio",
    );
}

#[test]
fn backbone_wider_than_the_disk() {
    rejects(
        "diameter = 0.003",
        "diameter = 0.03",
        "robot.backbone.diameter",
    );
}

#[test]
fn hole_beyond_the_disk() {
    rejects("radius = 0.008", "radius = 0.013", "cables[0].radius");
}

#[test]
fn hole_inside_the_backbone() {
    rejects("radius = 0.008", "radius = 0.001", "cables[0].radius");
}

#[test]
fn radius_list_of_wrong_length() {
    rejects(
        "radius = 0.008",
        "radius = [0.008, 0.008]",
        "cables[0].radius",
    );
}

#[test]
fn angle_list_of_wrong_length() {
    rejects(
        "angles = { straight = 0.0 }",
        "angles = [0.0, 0.1, 0.2]",
        "cables[0].angles",
    );
}

#[test]
fn nan_angle() {
    rejects(
        "angles = { straight = 0.0 }",
        "angles = [0.0, 0.1, nan, 0.3, 0.4]",
        "cables[0].angles[2]",
    );
}

#[test]
fn ends_at_out_of_range() {
    rejects(
        "tension = 1.0",
        "tension = 1.0\nends_at = 5",
        "cables[0].ends_at",
    );
}

#[test]
fn ends_at_zero() {
    rejects(
        "tension = 1.0",
        "tension = 1.0\nends_at = 0",
        "cables[0].ends_at",
    );
}

#[test]
fn shortening_of_a_hundred_percent() {
    rejects(
        "shorten_percent = 2.0",
        "shorten_percent = 100.0",
        "cables[0].shorten_percent",
    );
}

#[test]
fn shortening_longer_than_the_cable() {
    rejects(
        "shorten_percent = 2.0",
        "shorten = 0.5",
        "cables[0].shorten",
    );
}

#[test]
fn both_shortening_forms() {
    rejects(
        "shorten_percent = 2.0",
        "shorten_percent = 2.0\nshorten = 0.001",
        "cables[0].shorten_percent",
    );
}

#[test]
fn negative_tension() {
    rejects("tension = 1.0", "tension = -1.0", "cables[0].tension");
}

#[test]
fn two_cables_with_one_name() {
    let text = format!(
        "{GOOD}\n[[cables]]\nname = \"A\"\nradius = 0.008\nangles = {{ straight = 1.0 }}\n"
    );
    let e = Model::from_toml_str(&text).unwrap_err();
    assert_eq!(e.field(), Some("cables[1].name"));
}

#[test]
fn empty_name() {
    rejects("name = \"t\"", "name = \"\"", "name");
}

#[test]
fn nan_gravity() {
    let text = format!("{GOOD}\n[loads]\ngravity = [0.0, nan, 0.0]\n");
    let e = Model::from_toml_str(&text).unwrap_err();
    assert_eq!(e.field(), Some("loads.gravity[1]"));
}

#[test]
fn toml_errors_keep_line_column_and_caret() {
    // `sections` on line 4 of GOOD (line 1 is empty) given as a string.
    let text = GOOD.replace("sections = 4", "sections = \"four\"");
    let e = Model::from_toml_str(&text).unwrap_err().to_string();
    assert!(e.contains("line 4, column 12"), "{e}");
    let lines: Vec<&str> = e.lines().collect();
    let src = lines
        .iter()
        .position(|l| l.starts_with("4 | sections = \"four\""))
        .unwrap_or_else(|| panic!("no source line in {e}"));
    // The caret line below the source points at the value's first character.
    let caret = lines[src + 1];
    let col = caret.find('^').unwrap_or_else(|| panic!("no caret in {e}"));
    assert_eq!(col, lines[src].find("\"four\"").unwrap(), "{e}");
}
