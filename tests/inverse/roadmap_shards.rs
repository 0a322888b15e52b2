//! Roadmaps built in shards: the merged shards are the roadmap one build gives (nodes, edges
//! and their clearances, bit for bit), whatever the threads; a shard is never queried, and a
//! merge of shards that do not make one build is refused by name.

use ccrkit::method::run::SolveRequest;
use ccrkit::method::MethodKind;
use ccrkit::plan::roadmap::{build, BuildOptions, Roadmap, Shard};
use ccrkit::plan::roadmap_shard::merge;
use ccrkit::plan::{plan, Goal, PlanOptions};
use ccrkit::Model;

const ROOT: &str = env!("CARGO_MANIFEST_DIR");

/// Paper case 1 beside a ball the straight paths between samples often cross.
fn ball_model() -> Model {
    let text = std::fs::read_to_string(format!("{ROOT}/models/paper/case1.toml")).unwrap();
    let ball = "[[obstacles]]\nname = \"ball\"\nshape = \"sphere\"\nposition = [0.064, 0.111, 0.104]\nradius = 0.012\n";
    Model::from_toml_str(&format!("clearance = 0.0005\n{text}\n{ball}")).unwrap()
}

fn options(shard: Option<Shard>) -> BuildOptions {
    BuildOptions {
        samples: 40,
        expand: 40,
        neighbours: 5,
        shard,
        ..BuildOptions::default()
    }
}

fn shard(index: usize, count: usize) -> Option<Shard> {
    Some(Shard { index, count })
}

/// Everything a query reads: the statistics (solves, time) legitimately differ.
fn same(a: &Roadmap, b: &Roadmap) {
    assert_eq!(a.nodes, b.nodes);
    assert_eq!(a.edges, b.edges);
    let bits = |r: &Roadmap| -> Vec<[Option<u64>; 2]> {
        r.edge_clearance
            .iter()
            .map(|c| c.map(|x| x.map(f64::to_bits)))
            .collect()
    };
    assert_eq!(bits(a), bits(b));
    assert_eq!(
        (
            &a.robot_fingerprint,
            &a.scene,
            &a.lo,
            &a.hi,
            a.seed,
            a.shard
        ),
        (
            &b.robot_fingerprint,
            &b.scene,
            &b.lo,
            &b.hi,
            b.seed,
            b.shard
        )
    );
}

#[test]
fn merged_shards_equal_one_build_on_any_threads() {
    let model = ball_model();
    let request = SolveRequest::new(MethodKind::Energy);
    let whole = build(&model, &request, &options(None)).unwrap();
    assert!(whole.edges.len() > 20, "{} edges", whole.edges.len());
    assert!(
        whole.edges.windows(2).all(|w| w[0] < w[1]),
        "edges sorted, once each"
    );
    // Some candidate pairs are blocked by the ball, so the shards' edge sets matter.
    let one_thread = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap()
        .install(|| build(&model, &request, &options(None)).unwrap());
    same(&whole, &one_thread);
    let parts: Vec<Roadmap> = [2, 0, 1]
        .iter()
        .map(|&k| build(&model, &request, &options(shard(k, 3))).unwrap())
        .collect();
    assert!(parts.iter().all(|p| p.edges.len() < whole.edges.len()));
    let merged = merge(parts.clone()).unwrap();
    same(&whole, &merged);
    assert_eq!(
        merged.build_solves,
        parts.iter().map(|p| p.build_solves).sum::<usize>()
    );
    // Saved and loaded, a shard is refused by a query and merged the same way.
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("roadmap-shards");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("part0.json");
    parts[1].save(&path).unwrap();
    let back = Roadmap::load(&path).unwrap();
    assert_eq!(back.shard, shard(0, 3));
    let goal = Goal::Actuation(whole.nodes[0].u.clone());
    let err = plan(
        &model,
        &request,
        None,
        &goal,
        &PlanOptions::default(),
        Some(&back),
    )
    .unwrap_err()
    .to_string();
    assert!(err.contains("shard 0/3") && err.contains("merge"), "{err}");
    // A whole roadmap answers.
    plan(
        &model,
        &request,
        None,
        &goal,
        &PlanOptions::default(),
        Some(&merged),
    )
    .unwrap();
}

#[test]
fn shards_of_different_builds_are_refused_by_name() {
    let model = ball_model();
    let request = SolveRequest::new(MethodKind::Energy);
    let small = |k: usize, seed: u64| {
        let opts = BuildOptions {
            samples: 8,
            expand: 0,
            seed,
            ..options(shard(k, 2))
        };
        build(&model, &request, &opts).unwrap()
    };
    let (a, b) = (small(0, 1), small(1, 1));
    let err = |parts: Vec<Roadmap>| merge(parts).unwrap_err().to_string();
    assert!(err(vec![a.clone()]).contains("shard 1/2 is missing"));
    assert!(err(vec![a.clone(), a.clone()]).contains("given twice"));
    assert!(err(vec![a.clone(), small(1, 2)]).contains("another robot, scene"));
    // Other `--neighbours`: the same nodes but another candidate list, each shard's share of
    // it taken from a list the other does not have (refused only by chance before, when two
    // shares happened to hold one edge).
    let fewer = build(
        &model,
        &request,
        &BuildOptions {
            samples: 8,
            expand: 0,
            neighbours: 2,
            ..options(shard(1, 2))
        },
    )
    .unwrap();
    assert_eq!((fewer.neighbours, a.neighbours), (2, 5));
    assert!(err(vec![a.clone(), fewer]).contains("another robot, scene"));
    let mut whole = b.clone();
    whole.shard = None;
    assert!(err(vec![a.clone(), whole]).contains("whole roadmap"));
    assert!(err(vec![]).contains("no roadmap shard"));
    merge(vec![b, a]).unwrap();
}

/// The command line: two shards built and merged equal one build; a shard that cannot be
/// (`2/2`) and a plan on a shard are refused by name.
#[test]
fn command_line_shards_and_merge() {
    use crate::common::cli::{ccrkit_in, root, scratch};
    let dir = scratch("roadmap-shards-cli");
    let scene = dir.join("wall.toml");
    std::fs::copy(root().join("models/scenes/wall.toml"), &scene).unwrap();
    let model = root().join("models/paper/case1.toml");
    let run = |extra: &[&str]| {
        let mut args = vec![
            "roadmap".to_string(),
            "build".into(),
            model.display().to_string(),
            "--scene".into(),
            scene.display().to_string(),
            "--samples".into(),
            "12".into(),
            "--expand".into(),
            "12".into(),
        ];
        args.extend(extra.iter().map(|s| s.to_string()));
        ccrkit_in(&dir, &args)
    };
    for (out, shard) in [
        ("whole.json", None),
        ("a.json", Some("0/2")),
        ("b.json", Some("1/2")),
    ] {
        let mut extra = vec!["--out", out];
        if let Some(s) = shard {
            extra.extend(["--shard", s]);
        }
        let o = run(&extra);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
    let bad = run(&["--out", "c.json", "--shard", "2/2"]);
    assert!(!bad.status.success());
    assert!(String::from_utf8_lossy(&bad.stderr).contains("shard `2/2`"));
    let o = ccrkit_in(
        &dir,
        &["roadmap", "merge", "b.json", "a.json", "--out", "m.json"],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let read = |f: &str| Roadmap::load(&dir.join(f)).unwrap();
    same(&read("whole.json"), &read("m.json"));
    let o = ccrkit_in(
        &dir,
        &[
            "plan",
            &model.display().to_string(),
            "--scene",
            "wall.toml",
            "--to-tip",
            "0.03,0,0.19",
            "--roadmap",
            "a.json",
        ],
    );
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("merge the shards"));
}
