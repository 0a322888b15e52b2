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
