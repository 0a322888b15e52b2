//! How long a solid mesh takes to prepare, stage by stage, on a generated airway
//! (`free = "inside"`): the STL read from disk, parsed (vertices merged), checked (finite,
//! indices, degenerate), checked as a solid (closed, manifold, oriented), made into parry's
//! oriented mesh (pseudo-normals, tree), the whole scene read; then its signed-distance grid
//! built (no cache), built and written, and read from the cache in a fresh scene — each the
//! first `Obstacle::field` of its scene. Each stage prints its wall time and the CPU time of
//! the whole process (all threads) over it, which a loaded machine inflates less.
//!
//! `cargo run --release --example field_timing [SEED] [GENERATIONS] [CELL]`
//! (e.g. `3 7 0.0007` for about 10⁶ triangles; files go to `target/field_timing`)

use anyhow::Result;
use ccrkit::anatomy::{generate, AirwayOptions};
use ccrkit::model::field_cache::{FieldCache, FieldOrigin};
use ccrkit::model::mesh_check;
use ccrkit::prelude::*;
use std::path::PathBuf;
use std::time::{Duration, Instant};

/// CPU time of this process so far (user + system, all threads; Linux only, else zero).
fn cpu() -> Duration {
    let stat = std::fs::read_to_string("/proc/self/stat").unwrap_or_default();
    let after = stat.rsplit(") ").next().unwrap_or("");
    let f: Vec<u64> = after
        .split(' ')
        .skip(11)
        .take(2)
        .filter_map(|s| s.parse().ok())
        .collect();
    // Clock ticks of 10 ms (USER_HZ = 100 on Linux).
    Duration::from_millis(10 * f.iter().sum::<u64>())
}

/// Runs `f`, printing its wall and CPU time under `name`.
fn stage<T>(name: &str, f: impl FnOnce() -> T) -> T {
    let (t0, c0) = (Instant::now(), cpu());
    let out = f();
    println!(
        "  {name:<34} wall {:>9.3?}  cpu {:>9.3?}",
        t0.elapsed(),
        cpu().saturating_sub(c0)
    );
    out
}

fn main() -> Result<()> {
    let arg = |k: usize| std::env::args().nth(k);
    let opts = AirwayOptions {
        seed: arg(1).map_or(Ok(3), |s| s.parse())?,
        generations: arg(2).map_or(Ok(5), |s| s.parse())?,
        cell: arg(3).map(|s| s.parse()).transpose()?,
        ..AirwayOptions::default()
    };
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("target/field_timing");
    let mesh = dir.join(format!("airway-{}-{}.stl", opts.seed, opts.generations));
    let airway = stage("airway generated and written", || -> Result<_> {
        let airway = generate(&opts)?;
        ccrkit::mesh::write(&mesh, &airway.vertices, &airway.triangles)?;
        Ok(airway)
    })?;
    println!(
        "seed {} generations {} cell {:.2e} m: {} triangles",
        opts.seed,
        opts.generations,
        airway.cell,
        airway.triangles.len()
    );
    drop(airway);
    let bytes = stage("STL read from disk", || {
        ccrkit::model::read::read_capped(&mesh, ccrkit::model::read::MAX_MESH_BYTES, "mesh")
    })?;
    let (v, t) = stage("STL parsed, vertices merged", || {
        ccrkit::mesh::parse("STL", bytes)
    })?;
    stage("checked (finite, indices, area)", || {
        mesh_check::basic(&v, &t)
    })?;
    let t = stage("checked as a solid", || mesh_check::solid(&v, &t))?;
    let free = Some(ccrkit::mesh::Free::Inside);
    let tm = stage("parry mesh (pseudo-normals, tree)", || {
        ccrkit::mesh::trimesh(&v, &t, free)
    })?;
    drop((v, t, tm));
    let toml = dir.join("airway.toml");
    ccrkit::output::write_file(
        &toml,
        format!(
            "[[obstacles]]\nname = \"airway\"\nshape = \"mesh\"\npath = \"{}\"\nfree = \"inside\"\n",
            mesh.file_name().and_then(|n| n.to_str()).unwrap_or("airway.stl")
        ),
    )?;
    let scene = stage("scene read (all of the above)", || Scene::from_file(&toml))?;
    let cache = FieldCache::Dir(dir.join("cache"));
    let _ = std::fs::remove_dir_all(dir.join("cache"));
    let field = |s: Scene| {
        let _ = s.obstacles[0].field();
        s.obstacles[0].field_origin().cloned()
    };
    stage("grid built (no cache)", || {
        field(scene.with_field_cache(&FieldCache::Off))
    });
    let o1 = stage("grid built and written", || {
        field(scene.with_field_cache(&cache))
    });
    let o2 = stage("grid read from the cache", || {
        field(scene.with_field_cache(&cache))
    });
    let name = |o: &Option<FieldOrigin>| match o {
        Some(FieldOrigin::Written(_)) => "written".to_string(),
        Some(FieldOrigin::Loaded(_)) => "loaded".to_string(),
        other => format!("{other:?}"),
    };
    let size = match &o2 {
        Some(FieldOrigin::Loaded(p)) => std::fs::metadata(p)?.len(),
        _ => 0,
    };
    println!(
        "grid {}, then {} ({:.1} MiB)",
        name(&o1),
        name(&o2),
        size as f64 / (1u64 << 20) as f64
    );
    Ok(())
}
