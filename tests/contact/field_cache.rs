//! The solid's grid cached on disk through the scene: the same clearances cold and cached, to
//! the bit; a damaged cache file refused and rebuilt.

use crate::common;

use ccrkit::mesh::{to_obj, BentTube};
use ccrkit::model::field_cache::{FieldCache, FieldOrigin, MIN_CACHED_TRIANGLES};
use ccrkit::prelude::*;
use ccrkit::reach::clearance;
use nalgebra::{Isometry3, Vector3};

#[test]
fn clearances_are_the_same_cold_and_cached_and_a_bad_file_is_rebuilt() {
    let (v, t) = BentTube {
        bend_radius: 0.11,
        tube_radius: 0.02,
        theta0: -0.1,
        theta1: 1.8,
        rings: 180,
        segments: 32,
    }
    .capped();
    assert!(t.len() >= MIN_CACHED_TRIANGLES, "{} triangles", t.len());
    common::scene_file("field_cache", "lumen.obj", &to_obj(&v, &t));
    let path = common::scene_file(
        "field_cache",
        "lumen.toml",
        "[[obstacles]]\nname = \"lumen\"\nshape = \"mesh\"\npath = \"lumen.obj\"\n\
         rotation = { rpy = [0.0, 0.0, 0.964] }\nfree = \"inside\"\n",
    );
    let scene = Scene::from_file(&path).unwrap();
    let dir = path.with_file_name("cache");
    let _ = std::fs::remove_dir_all(&dir);
    let cache = FieldCache::Dir(dir.clone());
    let cold = scene.with_field_cache(&FieldCache::Off);
    let first = scene.with_field_cache(&cache);
    let cached = scene.with_field_cache(&cache);
    assert!(cold.obstacles[0].field().is_some());
    assert_eq!(cold.obstacles[0].field_origin(), Some(&FieldOrigin::Built));
    first.obstacles[0].field();
    let Some(FieldOrigin::Written(file)) = first.obstacles[0].field_origin().cloned() else {
        panic!("{:?}", first.obstacles[0].field_origin());
    };
    assert!(file.starts_with(&dir));
    cached.obstacles[0].field();
    assert_eq!(
        cached.obstacles[0].field_origin(),
        Some(&FieldOrigin::Loaded(file.clone()))
    );
    assert!(cold.obstacles[0].field() == cached.obstacles[0].field());

    let model = common::paper(1);
    let shape = SolveRequest::new(MethodKind::Geometric)
        .solver()
        .unwrap()
        .solve(&model.robot, &model.actuation, &Scene::empty(), None)
        .unwrap();
    // The robot moved about in the lumen: in it, near its wall and across it.
    let same = |a: &Scene, b: &Scene| {
        for k in 0..24 {
            let s = f64::from(k) / 24.0;
            let iso = Isometry3::new(
                Vector3::new(
                    0.02 * (7.0 * s).sin(),
                    0.03 * s - 0.015,
                    0.01 * (3.0 * s).cos(),
                ),
                Vector3::new(0.0, 0.0, 0.3 * (s - 0.5)),
            );
            let c0 = clearance(&model.robot, &shape, &a.transformed(&iso)).unwrap();
            let c1 = clearance(&model.robot, &shape, &b.transformed(&iso)).unwrap();
            assert_eq!(c0.distance.to_bits(), c1.distance.to_bits(), "pose {k}");
            assert_eq!(c0.feature, c1.feature, "pose {k}");
        }
    };
    same(&cold, &cached);

    // A truncated file: refused by name, rebuilt, written whole again.
    let bytes = std::fs::read(&file).unwrap();
    std::fs::write(&file, &bytes[..bytes.len() - 100]).unwrap();
    let again = scene.with_field_cache(&cache);
    again.obstacles[0].field();
    match again.obstacles[0].field_origin() {
        Some(FieldOrigin::Rebuilt { reason, .. }) => assert!(reason.contains("size"), "{reason}"),
        other => panic!("{other:?}"),
    }
    assert_eq!(std::fs::read(&file).unwrap(), bytes);
    same(&cold, &again);
    let _ = std::fs::remove_dir_all(&dir);
}
