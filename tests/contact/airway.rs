//! The generated airway: one closed solid through a binary STL and the scene loader, its
//! volume against a Monte Carlo estimate of the swept spheres it meshes, its diameters by
//! generation against Weibel's law measured on the triangles, its angles against Murray's,
//! the same mesh from the same seed, and bad options refused by name.

use crate::common;

use ccrkit::anatomy::{airway::murray_angle, generate, Airway, AirwayOptions};
use ccrkit::mesh::{self, Free};
use ccrkit::model::mesh_check;
use ccrkit::Scene;
use nalgebra::Vector3;
use parry3d::math::Vector as PVec;
use parry3d::query::PointQuery;

fn airway(seed: u64) -> Airway {
    generate(&AirwayOptions {
        seed,
        ..AirwayOptions::default()
    })
    .expect("default options are valid")
}

/// Inside the union of the branches' swept spheres (the generator's own description, not
/// its mesh).
fn inside(a: &Airway, p: &Vector3<f64>) -> bool {
    a.branches.iter().any(|b| b.axis_distance(p) < b.radius)
}

#[test]
fn airways_are_closed_solids_through_stl_and_the_scene_loader() {
    let dir = common::cli::scratch("airway");
    for seed in [11, 12, 13] {
        let a = airway(seed);
        assert!(
            (80_000..400_000).contains(&a.triangles.len()),
            "{}",
            a.triangles.len()
        );
        let path = dir.join(format!("airway{seed}.stl"));
        mesh::write(&path, &a.vertices, &a.triangles).expect("written");
        let (v, t) = mesh::load(&path).expect("the STL reads back");
        assert_eq!(t.len(), a.triangles.len());
        let outward = mesh_check::solid(&v, &t).expect("closed, manifold, oriented");
        assert_eq!(outward, t, "wound outward as written");
        let scene = format!(
            "[[obstacles]]\nname = \"airway\"\nshape = \"mesh\"\npath = \"airway{seed}.stl\"\nfree = \"inside\"\n"
        );
        let file = common::scene_file("airway", &format!("airway{seed}.toml"), &scene);
        Scene::from_file(file).expect("a lumen scene");
        assert!(mesh::trimesh(&v, &t, Some(Free::Inside)).is_ok());
    }
}

#[test]
fn volume_matches_a_monte_carlo_estimate_of_the_swept_spheres() {
    let a = airway(21);
    let volume = mesh_check::enclosed_volume(&a.vertices, &a.triangles);
    let (lo, hi) = a.vertices.iter().fold(
        (Vector3::repeat(f64::MAX), Vector3::repeat(f64::MIN)),
        |(lo, hi), v| (lo.inf(v), hi.sup(v)),
    );
    let mut rng = common::rng::Rng(0x5eed);
    let n = 200_000;
    let hits = (0..n)
        .filter(|_| {
            let p = Vector3::from_fn(|i, _| rng.range(lo[i], hi[i]));
            inside(&a, &p)
        })
        .count();
    let estimate = (hi - lo).product() * hits as f64 / n as f64;
    // 1/sqrt(hits) ≈ 1.2 % standard error (about 7 000 hits), and the facets cut inside by
    // about h²/(8r) on the thinnest tubes.
    let rel = (volume - estimate).abs() / estimate;
    assert!(
        rel < 0.05,
        "mesh {volume:e} m³, Monte Carlo {estimate:e} m³"
    );
}

#[test]
fn diameters_halve_in_cube_root_steps_by_generation() {
    let a = airway(31);
    let mesh = mesh::trimesh(&a.vertices, &a.triangles, None).expect("a mesh");
    let opts = AirwayOptions::default();
    let mut by_gen = vec![vec![]; opts.generations as usize + 1];
    for b in &a.branches {
        let mid = b.centreline[b.centreline.len() / 2];
        let r = mesh.distance_to_local_point(PVec::new(mid.x, mid.y, mid.z), true);
        by_gen[b.generation as usize].push(2.0 * r);
    }
    let mut fit = (0.0, 0.0, 0.0, 0.0, 0.0);
    for (n, ds) in by_gen.iter().enumerate() {
        assert!(!ds.is_empty(), "generation {n} has branches");
        let mean = ds.iter().sum::<f64>() / ds.len() as f64;
        let law = opts.trachea_diameter * 2f64.powf(-(n as f64) / 3.0);
        // The facets of a tube of radius r meshed with cell h are chords of it: a tetrahedron's
        // longest edge (the cell's diagonal, h√3) cuts inside by at most 3h²/(8r), so the
        // diameter to the nearest facet is short of the law's by at most 3h²/(2d).
        let short = 1.5 * a.cell * a.cell / law;
        assert!(
            mean < law * 1.01 && mean > law - short,
            "generation {n}: measured {mean:e} m, Weibel {law:e} m, facets within {short:e} m"
        );
        let (x, y) = (n as f64, mean.log2());
        fit = (
            fit.0 + 1.0,
            fit.1 + x,
            fit.2 + y,
            fit.3 + x * x,
            fit.4 + x * y,
        );
    }
    let slope = (fit.0 * fit.4 - fit.1 * fit.2) / (fit.0 * fit.3 - fit.1 * fit.1);
    assert!(
        (slope + 1.0 / 3.0).abs() < 0.02,
        "log2 d per generation {slope}"
    );
}

#[test]
fn children_leave_at_murrays_angle() {
    let a = airway(41);
    // Symmetric: each child 37.47° off its parent (cos θ = 2^(−1/3)).
    let theta = murray_angle(1.0, 0.5f64.cbrt(), 0.5f64.cbrt());
    assert!((theta.cos() - 0.5f64.cbrt()).abs() < 1e-12);
    for b in a.branches.iter().filter(|b| b.parent.is_some()) {
        let p = &a.branches[b.parent.unwrap_or(0)];
        let chord = (b.end() - b.centreline[0]).normalize();
        let angle = chord.dot(&p.end_direction()).clamp(-1.0, 1.0).acos();
        // The drawn sideways offset (≤ 10 % of the length) turns the chord by ≤ 5.8°.
        assert!(
            (angle - theta).abs() < 6f64.to_radians(),
            "{:.1}° vs {:.1}°",
            angle.to_degrees(),
            theta.to_degrees()
        );
    }
}

#[test]
fn the_same_seed_gives_the_same_mesh_and_bad_options_are_named() {
    let small = |seed| AirwayOptions {
        seed,
        generations: 3,
        ..AirwayOptions::default()
    };
    let (a, b, c) = (
        generate(&small(5)).expect("valid"),
        generate(&small(5)).expect("valid"),
        generate(&small(6)).expect("valid"),
    );
    assert_eq!(a.vertices, b.vertices);
    assert_eq!(a.triangles, b.triangles);
    assert_ne!(a.vertices, c.vertices);
    for (opts, field) in [
        (
            AirwayOptions {
                generations: 13,
                ..small(1)
            },
            "generations",
        ),
        (
            AirwayOptions {
                asymmetry: 0.5,
                ..small(1)
            },
            "asymmetry",
        ),
        (
            AirwayOptions {
                cell: Some(0.0),
                ..small(1)
            },
            "cell",
        ),
        (
            AirwayOptions {
                cell: Some(1e-5),
                ..small(1)
            },
            "cell",
        ),
        // Coarser than the narrowest branch: every branch drawn as one 24-triangle box.
        (
            AirwayOptions {
                cell: Some(1.0),
                ..small(1)
            },
            "cell",
        ),
        (
            AirwayOptions {
                cell: Some(1e300),
                ..small(1)
            },
            "cell",
        ),
        (
            AirwayOptions {
                cell: Some(1e-300),
                ..small(1)
            },
            "cell",
        ),
        (
            AirwayOptions {
                trachea_diameter: f64::NAN,
                ..small(1)
            },
            "trachea_diameter",
        ),
    ] {
        let e = generate(&opts).expect_err("refused").to_string();
        assert!(e.contains(&format!("`{field}`")), "{e}");
    }
}

#[test]
fn lumen_points_are_inside_the_triangles_and_in_their_branch() {
    use ccrkit::anatomy::tasks::{branch_of, entrance, inside_mesh, lumen_points};
    let a = generate(&AirwayOptions {
        seed: 51,
        generations: 3,
        ..AirwayOptions::default()
    })
    .expect("valid");
    let pts = lumen_points(&a, 3, 12, 7);
    assert_eq!(pts.len(), 12);
    let mesh = mesh::trimesh(&a.vertices, &a.triangles, Some(Free::Outside)).expect("solid");
    for p in &pts {
        assert_eq!(p.generation, 3);
        assert_eq!(a.branches[p.branch].generation, 3);
        assert_eq!(
            branch_of(&a, &p.point).map(|k| a.branches[k].generation),
            Some(3)
        );
        // parry's pseudo-normal side test agrees with the ray parity.
        let q = PVec::new(p.point.x, p.point.y, p.point.z);
        assert!(mesh.project_local_point(q, false).is_inside);
    }
    // A point far outside is outside by both tests; the port is inside the trachea.
    let far = Vector3::new(1.0, 1.0, 1.0);
    assert!(!inside_mesh(&a.vertices, &a.triangles, &far));
    let (port, axis) = entrance(&a, 0.01);
    assert!(inside_mesh(&a.vertices, &a.triangles, &port));
    assert!(axis.z > 0.99);
    assert!(lumen_points(&a, 9, 3, 1).is_empty());
}
