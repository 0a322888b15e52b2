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

/// A data CSV whose tip or cable lies beyond a kilometre (`1e308` mm, or `2e3` in metres) is
/// refused naming its row and column: a tip at `1e308` mm was read and made `predict`'s
/// summary print `rmse inf` with exit 0. A kilometre itself is read.
#[test]
fn a_data_csv_with_a_tip_or_a_cable_beyond_a_kilometre_is_refused_by_row_and_column() {
    let header = "servo_1,servo_2,tip_x,tip_y,tip_z";
    let mm = DataOptions::default();
    let metres = DataOptions {
        unit: 1.0,
        ..DataOptions::default()
    };
    for (row, opts, column) in [
        ("1,2,3,4,1e308", &mm, "tip_z"),
        ("1,2,-1e308,4,5", &mm, "tip_x"),
        ("1e308,2,3,4,5", &mm, "servo_1"),
        ("1,-1e7,3,4,5", &mm, "servo_2"),
        ("1,2,3,2e3,5", &metres, "tip_y"),
    ] {
        let text = format!("{header}\n0,0,0,0,0\n{row}\n");
        match Dataset::from_csv_str(&text, "d.csv", opts) {
            Err(ModelError::Invalid { field, reason }) => {
                assert_eq!(field, format!("d.csv row 2 column {column}"), "{reason}");
                assert!(reason.contains("beyond"), "{row}: {reason}");
            }
            other => panic!("{row}: expected a named refusal, got {other:?}"),
        }
    }
    let at_the_edge = format!("{header}\n1e6,-1e6,1e6,-1e6,1e6\n");
    let ds = Dataset::from_csv_str(&at_the_edge, "d.csv", &mm).expect("a kilometre is read");
    assert_eq!(ds.tips.map(|t| t[0].x), Some(1e3));
}

/// A workspace sweep whose tip lies beyond where a shape can lie (`1e308` m) is refused by
/// `view --sweep` naming its line and column (it was drawn, the page's view box with it); a
/// tip at the edge is read.
#[test]
fn a_sweep_with_a_tip_beyond_any_shape_is_refused_by_line_and_column() {
    use ccrkit::export::view::read_sweep;
    let edge = ccrkit::shape::MAX_EXTENT;
    let text =
        |x: f64| format!("sample,tip_x_m,tip_y_m,tip_z_m,status\n0,0,0,0.1,ok\n1,{x:e},0,0.1,ok\n");
    for x in [1e308, -1e308, 2.0 * edge] {
        match read_sweep(&text(x)) {
            Err(ccrkit::export::ExportError::Input { field, reason }) => {
                assert_eq!(field, "sweep line 3, column `tip_x_m`", "{reason}");
            }
            other => panic!("{x:e}: expected a named refusal, got {other:?}"),
        }
    }
    let read = read_sweep(&text(-edge)).expect("a tip at the edge is read");
    assert_eq!(read.tips[1][0], -edge);
}

/// Every column of a sweep is range-checked by name, not only the tip: a `NaN`, `1e308`,
/// empty or fractional value in the sample, an input, the iterations or another number column
/// was read (`NaN`, the colour scale's `inf` span, on the page) by `view --sweep` and passed
/// into the merged file by `study merge`; each is refused naming its line and column.
#[test]
fn a_sweep_with_a_bad_value_in_any_column_is_refused_by_line_and_column() {
    use ccrkit::export::view::read_sweep;
    let header =
        "sample,A_shortening_fraction,B_tension_n,tip_x_m,tip_y_m,tip_z_m,status,iterations,score";
    let good = "0,0.01,1,0,0,0.1,converged,5,0.5";
    let row = |col: usize, v: &str| {
        let mut f: Vec<&str> = "1,0.02,2,0,0,0.1,converged,6,0.25".split(',').collect();
        f[col] = v;
        format!("{header}\n{good}\n{}\n", f.join(","))
    };
    let bad = [
        (0, "NaN", "sample"),
        (0, "1.5", "sample"),
        (0, "1e308", "sample"),
        (1, "NaN", "A_shortening_fraction"),
        (1, "1e308", "A_shortening_fraction"),
        (1, "", "A_shortening_fraction"),
        (2, "-1", "B_tension_n"),
        (2, "inf", "B_tension_n"),
        (7, "NaN", "iterations"),
        (7, "lots", "iterations"),
        (8, "1e308", "score"),
        (8, "NaN", "score"),
    ];
    let dir = crate::common::adversarial_harness::scratch("lies-sweep");
    let model = crate::common::cli::paper_path(1);
    for (col, v, name) in bad {
        let text = row(col, v);
        match read_sweep(&text) {
            Err(ccrkit::export::ExportError::Input { field, reason }) => {
                assert_eq!(
                    field,
                    format!("sweep line 3, column `{name}`"),
                    "`{v}`: {reason}"
                );
            }
            other => panic!("`{v}` in `{name}`: expected a named refusal, got {other:?}"),
        }
        let merged = ccrkit::study::merge_csv(std::slice::from_ref(&text));
        let e = merged
            .expect_err(&format!("`{v}` in `{name}` merged"))
            .to_string();
        assert!(
            e.contains("line 3") && e.contains(&format!("`{name}`")),
            "{e}"
        );
        std::fs::write(dir.join("s.csv"), &text).expect("written");
        let out = crate::common::cli::ccrkit_in(
            &dir,
            &["view", &model, "--sweep", "s.csv", "--out", "v.html"],
        );
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "`{v}` in `{name}`: {err}");
        assert!(err.contains(&format!("column `{name}`")), "{err}");
    }
    let read = read_sweep(&row(8, "-1e9")).expect("a number column at its edge is read");
    assert_eq!(
        read.columns.iter().find(|c| c.0 == "score").map(|c| c.1[1]),
        Some(-1e9)
    );
    assert!(ccrkit::study::merge_csv(&[row(8, "-1e9")]).is_ok());
}

/// `--columns` naming one column for two cables was read (both cables took its displacement,
/// the other cable's column was never read), and a tip column or the label as a cable too;
/// each is refused naming `columns` and the column.
#[test]
fn data_columns_named_twice_or_off_the_cables_are_refused_by_name() {
    let text = "pattern_label,servo_1,servo_2,tip_x,tip_y,tip_z\nplain,1,2,3,4,5\n";
    let with = |cols: &[&str]| DataOptions {
        columns: cols.iter().map(|c| c.to_string()).collect(),
        ..DataOptions::default()
    };
    for (cols, says) in [
        (&["servo_1", "servo_1"][..], "`servo_1` is named twice"),
        (
            &["servo_2", "servo_1", "servo_2"][..],
            "`servo_2` is named twice",
        ),
        (&["servo_1", "tip_x"][..], "`tip_x` is not a cable's column"),
        (
            &["pattern_label", "servo_1"][..],
            "`pattern_label` is not a cable's column",
        ),
    ] {
        match Dataset::from_csv_str(text, "d.csv", &with(cols)) {
            Err(ModelError::Invalid { field, reason }) => {
                assert_eq!(field, "columns", "{reason}");
                assert!(reason.contains(says), "{cols:?}: {reason}");
            }
            other => panic!("{cols:?}: expected a named refusal, got {other:?}"),
        }
    }
    let ds = Dataset::from_csv_str(text, "d.csv", &with(&["servo_2", "servo_1"])).expect("read");
    assert_eq!(ds.commands[0], vec![2e-3, 1e-3]);
}

/// RFC 4180 quoting: a quoted label holding a comma and doubled quotes, a quoted number, are
/// one field each (they were split at the comma and the row refused as ragged); a column named
/// twice is still refused when one of the two is quoted.
#[test]
fn a_data_csv_with_quoted_fields_reads_and_a_quoted_duplicate_is_refused() {
    let text = "pattern_label,servo_1,servo_2,tip_x,tip_y,tip_z\n\
                \"rep1_all3, \"\"same\"\"\",1,\"2.5\",3,4,5\n\
                \n\
                plain,0,0,3,4,5\n";
    let ds = Dataset::from_csv_str(text, "d.csv", &DataOptions::default()).expect("parses");
    assert_eq!(
        ds.labels.as_deref(),
        Some(&["rep1_all3, \"same\"".to_string(), "plain".to_string()][..])
    );
    assert_eq!(ds.commands[0], vec![1.0 * 1e-3, 2.5 * 1e-3]);
    assert_eq!(ds.len(), 2, "the blank line is no row");
    let twice = "servo_1,\"tip_x\",tip_x,tip_z\n1,2,3,4\n";
    match Dataset::from_csv_str(twice, "d.csv", &DataOptions::default()) {
        Err(ModelError::Invalid { field, reason }) => {
            assert_eq!(field, "d.csv: header", "{reason}");
            assert!(reason.contains("`tip_x` twice"), "{reason}");
        }
        other => panic!("expected a named refusal, got {other:?}"),
    }
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

/// Paper case 1 with a ball in the way of the straight path from A-only to B-only shortening
/// (as in `tests/inverse/plan.rs`), its holes at `radius` \[m\].
fn ball_model(radius: f64) -> Model {
    let text = std::fs::read_to_string(root().join("models/paper/case1.toml")).expect("case 1");
    let text = text.replace("radius = 0.008", &format!("radius = {radius}"));
    let ball = "[[obstacles]]\nname = \"ball\"\nshape = \"sphere\"\n\
                position = [0.064, 0.111, 0.104]\nradius = 0.012\n";
    Model::from_toml_str(&format!("clearance = 0.0005\n{text}\n{ball}")).expect("ball model")
}

fn ball_roadmap(model: &Model) -> ccrkit::plan::roadmap::Roadmap {
    use ccrkit::plan::roadmap::{build, BuildOptions};
    let opts = BuildOptions {
        samples: 60,
        expand: 60,
        ..BuildOptions::default()
    };
    build(model, &energy(), &opts).expect("a roadmap")
}

fn energy() -> ccrkit::method::run::SolveRequest {
    ccrkit::method::run::SolveRequest::new(ccrkit::method::MethodKind::Energy)
}

fn ball_query(
    model: &Model,
    rm: &ccrkit::plan::roadmap::Roadmap,
) -> Result<ccrkit::plan::Plan, ccrkit::SolveError> {
    use ccrkit::plan::{plan, Goal, PlanOptions};
    plan(
        model,
        &energy(),
        Some(vec![0.014, 0.0]),
        &Goal::Actuation(vec![0.0, 0.014]),
        &PlanOptions::default(),
        Some(rm),
    )
}

/// A roadmap built for another robot — the same cable names and limits, the holes at 4.0 mm
/// from the backbone instead of 4.5 — is refused by name (it was accepted, and its plan
/// reported clearances of the other robot's shapes).
#[test]
fn a_roadmap_built_for_another_robot_is_refused_by_name() {
    let built_for = ball_model(0.0040);
    let used_with = ball_model(0.0045);
    let rm = ball_roadmap(&built_for);
    ball_query(&built_for, &rm).expect("its own robot plans");
    match ball_query(&used_with, &rm) {
        Err(ccrkit::SolveError::InvalidInput { field, reason }) => {
            assert_eq!(field, "roadmap.robot_fingerprint", "{reason}");
            assert!(
                reason.contains("build a roadmap for this robot"),
                "{reason}"
            );
        }
        other => panic!("expected a named refusal, got {:?}", other.map(|p| p.stats)),
    }
    // Through the file, too: the fingerprint is written and read back.
    let path = scratch("lies").join("ball_roadmap.json");
    rm.save(&path).expect("saves");
    let back = ccrkit::plan::roadmap::Roadmap::load(&path).expect("loads");
    assert_eq!(back.robot_fingerprint, rm.robot_fingerprint);
    assert!(ball_query(&used_with, &back).is_err());
    // A roadmap of the older format names no robot: refused when read, saying why.
    let text = std::fs::read_to_string(&path).expect("reads");
    let old = text.replace(ccrkit::plan::roadmap::FORMAT, "ccrkit-roadmap-2");
    std::fs::write(&path, old).expect("writes");
    match ccrkit::plan::roadmap::Roadmap::load(&path) {
        Err(ModelError::Invalid { field, reason }) => {
            assert_eq!(field, "format");
            assert!(reason.contains("build it again"), "{reason}");
        }
        other => panic!("expected the old format refused, got {other:?}"),
    }
}

/// Node and edge clearances edited to 0.5 m in a roadmap do not come back: every clearance a
/// plan reports is measured in the query (the edited file once gave "≥ 228 mm certified").
#[test]
fn clearances_in_a_roadmap_file_are_measured_again_never_believed() {
    let model = ball_model(0.008);
    let rm = ball_roadmap(&model);
    let honest = ball_query(&model, &rm).expect("plans");
    let mut lying = rm.clone();
    for n in &mut lying.nodes {
        n.clearance = Some(0.5);
    }
    for c in &mut lying.edge_clearance {
        *c = [Some(0.5), Some(0.5)];
    }
    let p = ball_query(&model, &lying).expect("plans");
    assert!(
        p.certified_clearance_m < 0.05 && p.min_clearance_m < 0.05,
        "certified {} m, measured {} m: taken from the file",
        p.certified_clearance_m,
        p.min_clearance_m
    );
    assert!(p.certified_clearance_m <= p.min_clearance_m);
    assert!(p.certified_clearance_m >= model.scene.clearance);
    // Each waypoint's clearance is the one its actuation's shape has, solved here afresh.
    let space = ccrkit::reach::Space::new(&model, &energy(), false).expect("space");
    let mut ck = ccrkit::plan::Checker::new(&space, 0.0);
    for w in &p.waypoints {
        let fresh = ck.node(&w.u, Some(&w.shape)).expect("admissible");
        assert!(
            (fresh.clearance - w.clearance).abs() < 1e-6,
            "a waypoint's clearance {} m, its shape's {} m",
            w.clearance,
            fresh.clearance
        );
    }
    // The honest roadmap's plan measures the same kind of numbers.
    assert!(honest.min_clearance_m < 0.05);
}

/// A roadmap shard that says it is one of 10¹⁸ is refused by name when read (`shard`), and a
/// merge of such a shard built in code is refused too: the merge allocated one flag per shard
/// and aborted the process (`memory allocation of 1000000000000000000 bytes failed`).
#[test]
fn a_shard_of_an_absurd_count_is_refused_by_name() {
    use ccrkit::plan::roadmap::{build, BuildOptions, Roadmap, Shard};
    use ccrkit::plan::roadmap_shard::merge;
    let model = ball_model(0.008);
    let tiny = |count| BuildOptions {
        samples: 2,
        expand: 0,
        neighbours: 1,
        shard: Some(Shard { index: 0, count }),
        ..BuildOptions::default()
    };
    let part = build(&model, &energy(), &tiny(2)).expect("a shard");
    let text = part.to_json("part").expect("json");
    let huge = text.replace("\"count\":2", "\"count\":1000000000000000000");
    assert_ne!(huge, text, "the shard count is in the file");
    let says_shard = |e: ModelError| match e {
        ModelError::Invalid { field, reason } => {
            assert_eq!(field, "shard", "{reason}");
            assert!(reason.contains("10000"), "{reason}");
        }
        other => panic!("expected the shard refused by name, got {other:?}"),
    };
    says_shard(Roadmap::from_json(&huge, "part").expect_err("refused"));
    let mut lie = part.clone();
    lie.shard = Some(Shard {
        index: 0,
        count: 1_000_000_000_000_000_000,
    });
    says_shard(merge(vec![lie]).expect_err("refused"));
    // A build asked for it is refused before any solve.
    match build(&model, &energy(), &tiny(1_000_000_000_000_000_000)) {
        Err(ccrkit::SolveError::InvalidInput { field, .. }) => assert_eq!(field, "shard"),
        other => panic!("expected `shard` refused, got {:?}", other.map(|r| r.shard)),
    }
}
