//! Self-contact and bounds (issue 11, items 6 and 8), checked on the output shape by
//! independent geometry (`ccrkit::check`, parry3d distances between disks and backbone
//! capsules), and the physical ranges of model inputs.

use ccrkit::check::{first_non_finite, self_contact};
use ccrkit::method::run::SolveRequest;
use ccrkit::method::MethodKind;
use ccrkit::{Model, ModelError, SolveError};
use nalgebra::{Matrix3, Vector3};

fn case_text(n: usize) -> String {
    std::fs::read_to_string(format!("models/paper/case{n}.toml")).expect("paper case")
}

#[test]
fn the_paper_cases_do_not_touch_themselves_under_any_method() {
    for n in 1..=3 {
        let model = Model::from_toml_str(&case_text(n)).expect("case");
        for k in MethodKind::ALL {
            let Ok(s) = SolveRequest::new(k).run(&model) else {
                continue;
            };
            assert_eq!(first_non_finite(&s.shape), None, "case {n} {k}");
            assert_eq!(self_contact(&model.robot, &s.shape), None, "case {n} {k}");
        }
    }
}

/// A shape folded onto itself by hand: the upper disks of the straight robot turned back down
/// onto the lower ones (half a turn about a horizontal axis through the middle disk). The
/// check must see the overlap and name two disks; the straight robot itself is clean.
#[test]
fn a_shape_folded_onto_itself_is_flagged() {
    // Case I with both cables released: the straight robot.
    let text = case_text(1)
        .replace("shorten_percent = 4.0", "shorten_percent = 0.0")
        .replace("shorten_percent = 3.0", "shorten_percent = 0.0");
    let model = Model::from_toml_str(&text).expect("case");
    let mut s = SolveRequest::new(MethodKind::Geometric)
        .run(&model)
        .expect("solves")
        .shape;
    assert_eq!(self_contact(&model.robot, &s), None);
    let mid = s.disks[4].position;
    // Half a turn about the x axis through the middle disk, shifted by 1 mm sideways so the
    // fold is not exactly onto the same points.
    let flip = Matrix3::new(1.0, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, -1.0);
    for d in s.disks.iter_mut().skip(6) {
        d.position = mid + flip * (d.position - mid) + Vector3::new(0.001, 0.0, 0.0);
        d.rotation = flip * d.rotation;
    }
    s.backbone = s.disks.iter().map(|d| d.position).collect();
    let c = self_contact(&model.robot, &s).expect("folded shape overlaps");
    assert!(c.depth > 0.0, "{c:?}");
    // The disks alone (no backbone polyline) are seen too: disk 6 sits on disk 2 (coaxial,
    // 1 mm apart sideways), the case where EPA's depth fails and GJK's test decides.
    s.backbone.clear();
    let c = self_contact(&model.robot, &s).expect("folded disks overlap");
    assert!(c.what.starts_with("disks "), "{}", c.what);
}

/// 99.99 % shortening: whatever a method answers, it is never a shape through itself with
/// exit 0 — it is a named error (self-contact is `obstructed by self`).
#[test]
fn extreme_shortening_is_refused_or_flagged_never_silent() {
    let text = case_text(1).replace("shorten_percent = 4.0", "shorten_percent = 99.99");
    let model = Model::from_toml_str(&text).expect("99.99 % is a valid percentage");
    for k in MethodKind::ALL {
        match SolveRequest::new(k).run(&model) {
            Ok(s) => {
                assert_eq!(self_contact(&model.robot, &s.shape), None, "{k}");
                assert_eq!(first_non_finite(&s.shape), None, "{k}");
            }
            Err(SolveError::Obstructed {
                obstacle, reason, ..
            }) => {
                assert_eq!(obstacle, "self", "{k}: {reason}");
                assert!(reason.contains("passes through itself"), "{reason}");
            }
            Err(e) => assert!(!e.to_string().is_empty(), "{k}"),
        }
    }
}

#[test]
fn absurd_model_values_are_refused_by_field() {
    let base = case_text(1);
    for (from, to, field) in [
        (
            "section_length = 0.020",
            "section_length = 1e308",
            "robot.section_length",
        ),
        (
            "section_length = 0.020",
            "section_length = 11.0",
            "robot.section_length",
        ),
        (
            "shorten_percent = 4.0",
            "shorten = -1e300",
            "cables[0].shorten",
        ),
        (
            "shorten_percent = 4.0",
            "shorten = 1e300",
            "cables[0].shorten",
        ),
        ("tension = 4.169250", "tension = 1e300", "cables[0].tension"),
        ("tension = 4.169250", "tension = -1.0", "cables[0].tension"),
        (
            "youngs_modulus = 1.1e9",
            "youngs_modulus = 1e300",
            "robot.backbone.youngs_modulus",
        ),
        (
            "disk_radius = 0.012",
            "disk_radius = 1e300",
            "robot.disk_radius",
        ),
        (
            "angles = { straight = 0.0 }",
            "angles = { straight = 1e300 }",
            "cables[0].angles.straight",
        ),
    ] {
        assert!(base.contains(from), "{from}");
        let text = base.replacen(from, to, 1);
        match Model::from_toml_str(&text) {
            Err(ModelError::Invalid { field: f, reason }) => {
                assert_eq!(f, field, "{to}: {reason}");
            }
            other => panic!("{to}: expected Invalid({field}), got {other:?}"),
        }
    }
    // Each section in range, the whole backbone not: 300 × 0.5 m = 150 m.
    let text = base
        .replace("sections = 9", "sections = 300")
        .replace("section_length = 0.020", "section_length = 0.5");
    match Model::from_toml_str(&text) {
        Err(ModelError::Invalid { field, reason }) => {
            assert_eq!(field, "robot.section_length", "{reason}");
            assert!(reason.contains("1.5e2 m"), "{reason}");
        }
        other => panic!("expected a length error, got {other:?}"),
    }
}
