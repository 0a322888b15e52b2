//! How long a solid's signed-distance grid takes to prepare and to read back from the cache,
//! on a generated airway (`free = "inside"`): the build (no cache), the build and write, the
//! read from the cache in a fresh scene — each the first `Obstacle::field` of its scene.
//!
//! `cargo run --release --example field_timing [SEED] [GENERATIONS] [CELL]`
//! (e.g. `3 8 0.0006` for about 10⁶ triangles; the cache goes to `target/field_timing/cache`)

use anyhow::Result;
use ccrkit::anatomy::{generate, AirwayOptions};
use ccrkit::model::field_cache::{FieldCache, FieldOrigin};
use ccrkit::prelude::*;
use std::path::PathBuf;
use std::time::Instant;

fn main() -> Result<()> {
    let arg = |k: usize| std::env::args().nth(k);
    let opts = AirwayOptions {
        seed: arg(1).map_or(Ok(3), |s| s.parse())?,
        generations: arg(2).map_or(Ok(5), |s| s.parse())?,
        cell: arg(3).map(|s| s.parse()).transpose()?,
        ..AirwayOptions::default()
    };
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("target/field_timing");
    let t0 = Instant::now();
    let airway = generate(&opts)?;
    let mesh = dir.join(format!("airway-{}-{}.stl", opts.seed, opts.generations));
    ccrkit::mesh::write(&mesh, &airway.vertices, &airway.triangles)?;
    let made = t0.elapsed();
    let toml = dir.join("airway.toml");
    ccrkit::output::write_file(
        &toml,
        format!(
            "[[obstacles]]\nname = \"airway\"\nshape = \"mesh\"\npath = \"{}\"\nfree = \"inside\"\n",
            mesh.file_name().and_then(|n| n.to_str()).unwrap_or("airway.stl")
        ),
    )?;
    let t0 = Instant::now();
    let scene = Scene::from_file(&toml)?;
    let read = t0.elapsed();
    let cache = FieldCache::Dir(dir.join("cache"));
    let _ = std::fs::remove_dir_all(dir.join("cache"));
    let time = |s: &Scene| {
        let t0 = Instant::now();
        let _ = s.obstacles[0].field();
        (t0.elapsed(), s.obstacles[0].field_origin().cloned())
    };
    let (build, _) = time(&scene.with_field_cache(&FieldCache::Off));
    let (write, o1) = time(&scene.with_field_cache(&cache));
    let (load, o2) = time(&scene.with_field_cache(&cache));
    let name = |o: &Option<FieldOrigin>| match o {
        Some(FieldOrigin::Written(_)) => "written".to_string(),
        Some(FieldOrigin::Loaded(_)) => "loaded".to_string(),
        other => format!("{other:?}"),
    };
    let bytes = match &o2 {
        Some(FieldOrigin::Loaded(p)) => std::fs::metadata(p)?.len(),
        _ => 0,
    };
    println!(
        "seed {} generations {} cell {:.2e} m: {} triangles (made and written {made:.2?}, scene read {read:.2?}); grid built {build:.2?}; built and {} {write:.2?}; {} from the cache {load:.2?} ({:.1} MiB)",
        opts.seed,
        opts.generations,
        airway.cell,
        airway.triangles.len(),
        name(&o1),
        name(&o2),
        bytes as f64 / (1u64 << 20) as f64
    );
    Ok(())
}
