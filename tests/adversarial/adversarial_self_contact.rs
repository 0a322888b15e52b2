//! Self-contact and bounds, checked on the output shape by
//! independent geometry (`ccrkit::check`, parry3d distances between disks and backbone
//! capsules), and the physical ranges of model inputs.

use ccrkit::check::{first_non_finite, self_contact, self_contact_exhaustive};
use ccrkit::method::run::SolveRequest;
use ccrkit::method::MethodKind;
use ccrkit::{Model, ModelError, SolveError};
use nalgebra::{Matrix3, Rotation3, Unit, Vector3};
use std::time::{Duration, Instant};

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

/// A small deterministic generator (xorshift64*), uniform in [0, 1).
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// A random shape of `model`'s robot: a walk whose frame turns at each backbone sample about a
/// bending axis fixed in the body, wobbling at random (gently on some shapes, coiling tightly
/// through itself on others), disks at every section end with the walk's frame.
fn random_shape(model: &Model, rng: &mut Rng) -> ccrkit::Shape {
    let robot = &model.robot;
    let mut shape = SolveRequest::new(MethodKind::ConstantCurvature)
        .run(model)
        .expect("the straight robot solves")
        .shape;
    let per_section = 1 + (rng.next() * 8.0) as usize;
    let turn = rng.next() * 1.5 / per_section as f64;
    let bend = Vector3::new(rng.next() - 0.5, rng.next() - 0.5, 0.0);
    let (mut p, mut r) = (Vector3::zeros(), Rotation3::identity());
    let (mut points, mut disks) = (vec![p], shape.disks.clone());
    disks[0].position = p;
    disks[0].rotation = *r.matrix();
    for (k, w) in robot.disk_s.windows(2).enumerate() {
        let step = (w[1] - w[0]) / per_section as f64;
        for _ in 0..per_section {
            let wobble = Vector3::new(rng.next() - 0.5, rng.next() - 0.5, rng.next() - 0.5);
            let axis = Unit::new_normalize(r * (bend + 0.3 * wobble));
            r = Rotation3::from_axis_angle(&axis, turn * rng.next()) * r;
            p += r * Vector3::z() * step;
            points.push(p);
        }
        disks[k + 1].position = p;
        disks[k + 1].rotation = *r.matrix();
    }
    shape.backbone = points;
    shape.disks = disks;
    shape
}

/// The broad phase (parry's bounding-volume hierarchy, stopping at the first part along the
/// arc found overlapping) answers exactly as testing every pair: same verdict, same parts,
/// same depth, on random shapes clear of themselves and coiled through themselves alike.
#[test]
fn the_broad_phase_answers_as_every_pair_does_on_random_shapes() {
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    let (mut clear, mut through) = (0, 0);
    for case in 0..300 {
        let n = 3 + (rng.next() * 40.0) as usize;
        let text = case_text(1)
            .replace("sections = 9", &format!("sections = {n}"))
            .replace("shorten_percent = 4.0", "shorten_percent = 0.0")
            .replace("shorten_percent = 3.0", "shorten_percent = 0.0");
        let model = Model::from_toml_str(&text).expect("model");
        let shape = random_shape(&model, &mut rng);
        let fast = self_contact(&model.robot, &shape);
        assert_eq!(
            fast,
            self_contact_exhaustive(&model.robot, &shape),
            "case {case}"
        );
        match fast {
            None => clear += 1,
            Some(_) => through += 1,
        }
    }
    assert!(
        clear > 50 && through > 50,
        "clear {clear}, through {through}"
    );
}

/// A legal 60 m robot of 3000 sections curled through itself many times: the check after the
/// solve names the overlap within seconds (every turn against every other took 2.4 s at 250
/// sections, 41 s at 1000, and did not finish at 3000).
#[test]
fn a_robot_of_3000_sections_coiled_through_itself_is_named_fast() {
    let text = case_text(1).replace("sections = 9", "sections = 3000");
    let model = Model::from_toml_str(&text).expect("60 m is a legal robot");
    let t = Instant::now();
    match SolveRequest::new(MethodKind::ConstantCurvature).run(&model) {
        Err(SolveError::Obstructed { obstacle, .. }) => assert_eq!(obstacle, "self"),
        other => panic!(
            "expected obstructed by self, got {:?}",
            other.map(|s| s.shape.report)
        ),
    }
    assert!(t.elapsed() < Duration::from_secs(10), "{:?}", t.elapsed());
}
