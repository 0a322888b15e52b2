//! Files that lie: an input file that parses but says something the tool would otherwise
//! believe or silently ignore — an actuation naming a cable the robot does not have, an
//! actuation file too large for what it can hold, a data CSV naming a column twice — is
//! refused by name.

use crate::common::adversarial_harness::{root, scratch};
use ccrkit::calibrate::data::{DataOptions, Dataset};
use ccrkit::{Model, ModelError};

fn two_segment() -> Model {
    Model::from_file(root().join("models/plan/two_segment.toml")).expect("model")
}

/// An actuation file of the two-segment robot with `entries` as its list.
fn actuation_file(name: &str, entries: &[(&str, f64)]) -> std::path::PathBuf {
    let list: Vec<String> = entries
        .iter()
        .map(|(c, x)| format!("{{\"cable\": \"{c}\", \"shorten\": {x}}}"))
        .collect();
    let path = scratch("lies").join(name);
    std::fs::write(&path, format!("{{\"actuation\": [{}]}}", list.join(", "))).expect("write");
    path
}

const CABLES: [&str; 6] = ["s0t0", "s0t1", "s0t2", "s1t0", "s1t1", "s1t2"];

#[test]
fn an_actuation_naming_an_unknown_or_repeated_cable_is_refused_by_name() {
    let model = two_segment();
    let all: Vec<(&str, f64)> = CABLES.iter().map(|c| (*c, 0.0)).collect();
    let ok = actuation_file("ok.json", &all);
    assert_eq!(
        ccrkit::plan::read_actuation(&ok, &model).expect("reads"),
        vec![0.0; 6]
    );
    let mut unknown = all.clone();
    unknown.push(("zzz", 0.001));
    let mut twice = all.clone();
    twice.push(("s0t1", 0.002));
    for (file, list, says) in [
        ("zzz.json", unknown, "`zzz`"),
        ("twice.json", twice, "twice"),
    ] {
        let path = actuation_file(file, &list);
        match ccrkit::plan::read_actuation(&path, &model) {
            Err(ModelError::Invalid { field, reason }) => {
                assert_eq!(field, "actuation[6].cable", "{reason}");
                assert!(reason.contains(says), "{reason}");
            }
            other => panic!("{file}: expected a named refusal, got {other:?}"),
        }
    }
}

/// A goal file of 2 MB (padded with whitespace) is refused by its size before it is parsed
/// (a 37 MB goal file took 794 MB of memory).
#[test]
fn an_oversized_actuation_file_is_refused_before_parsing() {
    let model = two_segment();
    let all: Vec<(&str, f64)> = CABLES.iter().map(|c| (*c, 0.0)).collect();
    let path = actuation_file("big.json", &all);
    let mut text = std::fs::read_to_string(&path).expect("read");
    text.push_str(&" ".repeat(2 << 20));
    std::fs::write(&path, text).expect("write");
    match ccrkit::plan::read_actuation(&path, &model) {
        Err(ModelError::Io { reason, .. }) => assert!(reason.contains("1 MiB"), "{reason}"),
        other => panic!("expected a size refusal, got {other:?}"),
    }
}

#[test]
fn a_data_csv_naming_a_column_twice_or_part_of_the_tip_is_refused_by_name() {
    let row = "1,2,3,4,5";
    for (header, says) in [
        ("servo_1,servo_2,tip_x,tip_x,tip_z", "`tip_x` twice"),
        ("servo_1,servo_1,tip_x,tip_y,tip_z", "`servo_1` twice"),
        ("servo_1,servo_2,tip_x,tip_z,other", "tip_y"),
    ] {
        let text = format!("{header}\n{row}\n");
        match Dataset::from_csv_str(&text, "d.csv", &DataOptions::default()) {
            Err(ModelError::Invalid { field, reason }) => {
                assert_eq!(field, "d.csv: header", "{reason}");
                assert!(reason.contains(says), "{header}: {reason}");
            }
            other => panic!("{header}: expected a named refusal, got {other:?}"),
        }
    }
    let fine = "servo_1,servo_2,tip_x,tip_y,tip_z\n1,2,3,4,5\n";
    let ds = Dataset::from_csv_str(fine, "d.csv", &DataOptions::default()).expect("parses");
    assert_eq!(ds.tips.map(|t| t.len()), Some(1));
}

/// Roadmap nodes edited by hand — actuations of 3, 0 or 7 values for 6 cables, or outside the
/// limits, a non-finite clearance — are refused by the node's index before the roadmap is
/// used.
#[test]
fn roadmap_nodes_of_the_wrong_length_or_outside_the_limits_are_refused() {
    use ccrkit::method::run::SolveRequest;
    use ccrkit::method::MethodKind;
    use ccrkit::plan::roadmap::{build, BuildOptions};
    use ccrkit::plan::{plan, Goal, PlanOptions};
    let model = two_segment();
    let request = SolveRequest::new(MethodKind::Energy);
    let opts = BuildOptions {
        samples: 12,
        expand: 0,
        ..BuildOptions::default()
    };
    let rm = build(&model, &request, &opts).expect("a small roadmap");
    assert!(!rm.nodes.is_empty());
    let goal = Goal::Actuation(rm.nodes[0].u.clone());
    let query = |r: &ccrkit::plan::roadmap::Roadmap| {
        plan(
            &model,
            &request,
            None,
            &goal,
            &PlanOptions::default(),
            Some(r),
        )
    };
    let hi = rm.hi[0];
    type Edit = Box<dyn Fn(&mut ccrkit::plan::roadmap::RoadmapNode)>;
    let edits: Vec<Edit> = vec![
        Box::new(|n| n.u.truncate(3)),
        Box::new(|n| n.u.clear()),
        Box::new(|n| n.u.push(0.0)),
        Box::new(move |n| n.u[0] = hi + 0.01),
        Box::new(|n| n.clearance = Some(f64::NAN)),
    ];
    for (k, edit) in edits.iter().enumerate() {
        let mut bad = rm.clone();
        edit(&mut bad.nodes[0]);
        match query(&bad) {
            Err(ccrkit::SolveError::InvalidInput { field, reason }) => {
                assert_eq!(field, "roadmap.nodes[0]", "edit {k}: {reason}");
            }
            other => panic!(
                "edit {k}: expected a named refusal, got {:?}",
                other.map(|p| p.stats)
            ),
        }
    }
}
