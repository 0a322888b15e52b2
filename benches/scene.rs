//! Reading a scene of 1000 obstacles: the parse, every obstacle validated, its
//! parry shape and bounds built — all `Scene::from_file` does before a method sees it — for
//! the same scene as TOML and as JSON, beside an empty scene file. The scenes are written by
//! the generator the tests use.
//!
//! `cargo bench --bench scene`

use ccrkit::Scene;
use criterion::{criterion_group, criterion_main, Criterion};
use std::hint::black_box;

use ccrkit_test_support::scenes;

fn bench(c: &mut Criterion) {
    let dir = std::env::temp_dir().join(format!("ccrkit-bench-scene-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut grp = c.benchmark_group("scene_read");
    for n in [0, 1000] {
        for (ext, text) in [
            ("toml", scenes::scene_text(n, 7)),
            ("json", scenes::scene_json(n, 7)),
        ] {
            let path = dir.join(format!("scene{n}.{ext}"));
            std::fs::write(&path, text).unwrap();
            assert_eq!(Scene::from_file(&path).unwrap().obstacles.len(), n);
            grp.bench_function(format!("{n}_obstacles_{ext}"), |b| {
                b.iter(|| black_box(Scene::from_file(&path).unwrap()))
            });
        }
    }
    grp.finish();
    let _ = std::fs::remove_dir_all(&dir);
}

criterion_group!(benches, bench);
criterion_main!(benches);
