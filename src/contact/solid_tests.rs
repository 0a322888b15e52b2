//! Signed distances to solid meshes against closed forms (a box) and an independent inside
//! test (ray parity on a faceted sphere); a feature beyond a thin wall is seen.

use super::*;
use crate::contact::{pvec, query};
use crate::model::mesh::trimesh as solid_trimesh;
use crate::model::mesh::Free;
use crate::numeric::test_rng::Rng;
use nalgebra::Vector3;
use parry3d::shape::{Ball, Capsule};

/// The box `[-h, h]³` as 12 outward triangles.
fn cube(h: f64) -> (Vec<Vector3<f64>>, Vec<[u32; 3]>) {
    crate::model::mesh_check::test_box(-h, h)
}

/// The signed distance from `p` to the box `[-h, h]³` (negative inside), in closed form.
fn box_sd(p: &Vector3<f64>, h: f64) -> f64 {
    let q = p.abs() - Vector3::repeat(h);
    q.sup(&Vector3::zeros()).norm() + q.max().min(0.0)
}

/// A ball's signed distance to the box as an organ (`outside` free) and as a lumen (`inside`
/// free), where a face decides it: `sd(c) − r` and `−sd(c) − r`, inside, across and outside.
#[test]
fn a_ball_against_a_box_matches_the_closed_form() {
    let h = 0.02;
    let (v, t) = cube(h);
    let mut rng = Rng(0x5EED_0001);
    let pose = PPose::IDENTITY;
    let mut seen = [0usize; 3];
    for k in 0..600 {
        let r = rng.range(0.0005, 0.003);
        // A point over the middle of a face (a face decides), at a depth either side.
        let axis = k % 3;
        let sign = if k % 2 == 0 { 1.0 } else { -1.0 };
        let mut c = Vector3::new(
            rng.range(-0.5, 0.5),
            rng.range(-0.5, 0.5),
            rng.range(-0.5, 0.5),
        ) * h;
        c[axis] = sign * (h + rng.range(-0.008, 0.008));
        let sd = box_sd(&c, h);
        for free in [Free::Outside, Free::Inside] {
            let mesh = solid_trimesh(&v, &t, Some(free)).unwrap();
            let want = match free {
                Free::Outside => sd - r,
                Free::Inside => -sd - r,
            };
            let ball = Ball::new(r);
            let bpose = PPose::from_translation(pvec(&c));
            let got = query(&bpose, &ball, &pose, &mesh, 0.05, None).expect("within the margin");
            assert!(
                (got.dist - want).abs() < 1e-9,
                "{k} {free:?}: {} vs {want} (c = {c:?}, r = {r})",
                got.dist
            );
            // The normal (from the obstacle towards the robot) is the distance's gradient:
            // along the face's axis, towards the free side.
            let n = -nvec(got.normal1);
            let out = sign * if free == Free::Outside { 1.0 } else { -1.0 };
            assert!((n[axis] - out).abs() < 1e-9, "{k} {free:?}: normal {n:?}");
            seen[usize::from(want > 0.0) + usize::from(want > -2.0 * r)] += 1;
        }
    }
    // Inside, across and apart all happened.
    assert!(seen.iter().all(|&n| n > 50), "{seen:?}");
}

/// A sphere of radius `r` faceted as a subdivided octahedron (`n` subdivisions), outward.
fn sphere(r: f64, n: u32) -> (Vec<Vector3<f64>>, Vec<[u32; 3]>) {
    let mut v = vec![];
    let mut t = vec![];
    let mut index = std::collections::HashMap::new();
    let corners = [Vector3::x(), Vector3::y(), Vector3::z()];
    for oct in 0..8 {
        let s = Vector3::new(
            if oct & 1 == 0 { 1.0 } else { -1.0 },
            if oct & 2 == 0 { 1.0 } else { -1.0 },
            if oct & 4 == 0 { 1.0 } else { -1.0 },
        );
        let [a, b, c] = corners.map(|e| e.component_mul(&s));
        let flip = s.x * s.y * s.z < 0.0;
        let mut id = |i: u32, j: u32| -> u32 {
            let p = (a * (n - i - j) as f64 + b * i as f64 + c * j as f64) / n as f64;
            let key = p.map(|x| (x * 1e9).round() as i64);
            *index.entry((key.x, key.y, key.z)).or_insert_with(|| {
                v.push(p.normalize() * r);
                (v.len() - 1) as u32
            })
        };
        for i in 0..n {
            for j in 0..n - i {
                let mut tri = [id(i, j), id(i + 1, j), id(i, j + 1)];
                let mut push = |tri: &mut [u32; 3]| {
                    if flip {
                        tri.swap(1, 2);
                    }
                    t.push(*tri);
                };
                push(&mut tri);
                if i + j + 1 < n {
                    let mut tri = [id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)];
                    push(&mut tri);
                }
            }
        }
    }
    (v, t)
}

/// Ray parity: how many triangles the ray from `p` along `d` crosses (Möller–Trumbore), odd
/// inside a closed mesh. Independent of parry and of the pseudo-normals.
fn inside_by_parity(
    p: &Vector3<f64>,
    d: &Vector3<f64>,
    v: &[Vector3<f64>],
    t: &[[u32; 3]],
) -> bool {
    let mut hits = 0;
    for tri in t {
        let [a, b, c] = tri.map(|i| v[i as usize]);
        let (e1, e2) = (b - a, c - a);
        let pv = d.cross(&e2);
        let det = e1.dot(&pv);
        if det.abs() < 1e-18 {
            continue;
        }
        let s = p - a;
        let u = s.dot(&pv) / det;
        let q = s.cross(&e1);
        let w = d.dot(&q) / det;
        if u < 0.0 || w < 0.0 || u + w > 1.0 {
            continue;
        }
        if e2.dot(&q) / det > 0.0 {
            hits += 1;
        }
    }
    hits % 2 == 1
}

#[test]
fn the_side_agrees_with_ray_parity_and_point_distances_with_the_facets() {
    let r = 0.015;
    let (v, t) = sphere(r, 12);
    crate::model::mesh_check::solid(&v, &t).expect("the faceted sphere is a solid");
    let mut rng = Rng(0x5EED_0002);
    let pose = PPose::from_translation(pvec(&Vector3::new(0.01, -0.02, 0.03)));
    // The facets lie between the inscribed and the circumscribed sphere.
    let inner = v.iter().map(|p| p.norm()).fold(f64::INFINITY, f64::min) * (1.0 - 0.02);
    for free in [Free::Outside, Free::Inside] {
        let mesh = solid_trimesh(&v, &t, Some(free)).unwrap();
        let mut disagree = 0;
        for _ in 0..2000 {
            let p = Vector3::new(
                rng.range(-1.5, 1.5),
                rng.range(-1.5, 1.5),
                rng.range(-1.5, 1.5),
            ) * r;
            let dir = Vector3::new(
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
            );
            let inside = inside_by_parity(&p, &dir.normalize(), &v, &t);
            let world = pose.transform_point(pvec(&p));
            let obstacle = in_obstacle(&mesh, &pose, world);
            disagree += usize::from(obstacle != (inside == (free == Free::Outside)));
            // A point (a ball of radius 0): signed distance against the spheres that bound
            // the facets.
            let ball = Ball::new(0.0);
            let got = query(
                &PPose::from_translation(world),
                &ball,
                &pose,
                &mesh,
                1.0,
                None,
            )
            .expect("within the margin")
            .dist;
            let sd = match free {
                Free::Outside => p.norm() - r,
                Free::Inside => r - p.norm(),
            };
            assert!(
                got.signum() == sd.signum() || sd.abs() < r - inner,
                "{free:?} {p:?}: {got} vs {sd}"
            );
            assert!(
                (got - sd).abs() <= r - inner,
                "{free:?} {p:?}: {got} vs {sd}"
            );
        }
        // Ray parity is exact away from the surface; a ray grazing an edge may double count.
        assert!(disagree <= 2, "{free:?}: {disagree} of 2000 disagree");
    }
}

/// A capsule that has passed through the wall of a lumen: parry's surface distance says 1 mm
/// apart, the solid says it is beyond the wall by its width and more; across, negative too.
#[test]
fn a_feature_beyond_a_thin_wall_is_seen() {
    let h = 0.02;
    let (v, t) = cube(h);
    let surface = solid_trimesh(&v, &t, None).unwrap();
    let lumen = solid_trimesh(&v, &t, Some(Free::Inside)).unwrap();
    let pose = PPose::IDENTITY;
    let rb = 0.0015;
    // Along y, 1 mm beyond the wall x = h.
    let x = h + 0.001 + rb;
    let cap = Capsule::new(
        pvec(&Vector3::new(x, -0.005, 0.0)),
        pvec(&Vector3::new(x, 0.005, 0.0)),
        rb,
    );
    let unsigned = query(&pose, &cap, &pose, &surface, 0.01, None)
        .unwrap()
        .dist;
    assert!((unsigned - 0.001).abs() < 1e-9, "{unsigned}");
    let signed = query(&pose, &cap, &pose, &lumen, 0.01, None).unwrap();
    assert!(
        (signed.dist + 0.001 + 2.0 * rb).abs() < 1e-9,
        "{}",
        signed.dist
    );
    // The way back is along −x, into the lumen.
    assert!((nvec(signed.normal1).x - 1.0).abs() < 1e-9);
    // Across the wall (tilted through it): negative, the depth of its far end.
    let cap = Capsule::new(
        pvec(&Vector3::new(h - 0.004, 0.0, 0.0)),
        pvec(&Vector3::new(h + 0.002, 0.0, 0.001)),
        rb,
    );
    let across = query(&pose, &cap, &pose, &lumen, 0.01, None).unwrap().dist;
    assert!((across + 0.002 + rb).abs() < 1e-9, "{across}");
}

/// The branch and bound of `closest_triangle` finds parry's closest triangle against the whole
/// mesh (its distance to round-off, its witness to GJK's accuracy) on a 25 088-triangle sphere,
/// for capsules, disks and chords touching it (where many triangles are within a hair of the best),
/// near it, across its wall and deep inside, seen from either side, and nothing beyond the
/// margin alike.
#[test]
fn closest_triangle_is_parrys_on_a_dense_sphere() {
    let (v, t) = sphere(0.03, 56);
    assert_eq!(t.len(), 25_088);
    let mut rng = Rng(0xB0B5_1DE5);
    let unit = |rng: &mut Rng| {
        Vector3::new(
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
        )
        .normalize()
    };
    let (mut found, mut none, mut touching) = (0, 0, 0);
    for free in [Free::Inside, Free::Outside] {
        let m = solid_trimesh(&v, &t, Some(free)).unwrap();
        let opose = PPose::from_translation(PVec::new(0.01, -0.02, 0.03));
        for k in 0..200 {
            let dir = unit(&mut rng);
            let axis = unit(&mut rng);
            // Distance of the feature's nearest point from the sphere: touching (a third of
            // them), near, across the wall, or far inside / outside.
            let gap = match k % 6 {
                0 | 1 => 0.0,
                2 => rng.range(0.0, 0.004),
                3 => -rng.range(0.0, 0.003),
                4 => rng.range(-0.03, 0.03),
                _ => rng.range(0.004, 0.02),
            };
            let margin = [0.002, 0.01, 0.05][k % 3];
            let radius = 0.0015;
            let cap_centre = dir * (0.03 + gap + radius);
            let cap = Capsule::new(
                pvec(&(cap_centre - 0.004 * axis)),
                pvec(&(cap_centre + 0.004 * axis)),
                radius,
            );
            let disk = parry3d::shape::Cylinder::new(0.001, 0.008);
            let rot = nalgebra::Rotation3::rotation_between(&Vector3::y(), &axis)
                .unwrap_or_else(nalgebra::Rotation3::identity);
            let dpose = crate::contact::ppose(rot.matrix(), &(dir * (0.03 + gap + 0.008)));
            let shift = |p: &PPose| PPose::from_translation(opose.translation) * *p;
            // A chord: the capsule's axis, touching or crossing where the capsule does.
            let chord = parry3d::shape::Segment::new(cap.segment.a, cap.segment.b);
            let shapes: [(&dyn PShape, PPose); 3] = [
                (&cap, shift(&PPose::IDENTITY)),
                (&disk, shift(&dpose)),
                (&chord, shift(&PPose::IDENTITY)),
            ];
            for (g, gpose) in shapes {
                let want = parry3d::query::contact(&gpose, g, &opose, &m, margin).unwrap();
                let got = closest_triangle(&gpose, g, &opose, &m, margin, None);
                // Started from any triangle — the answer's, its neighbour, one far away, one
                // out of range — the search returns the cold answer, to the bit.
                let near = got.map_or(0, |c| c.subshape2);
                for hint in [near, near + 1, near / 2, 7 * k as u32, u32::MAX] {
                    let warm = closest_triangle(&gpose, g, &opose, &m, margin, Some(hint));
                    let bits = |c: Option<PContact>| {
                        c.map(|c| (c.dist.to_bits(), c.point1, c.point2, c.normal1, c.subshape2))
                    };
                    assert_eq!(bits(warm), bits(got), "{free:?} {k}: hint {hint}");
                }
                match (want, got) {
                    (None, None) => none += 1,
                    (Some(a), Some(b)) => {
                        let scale = 1e-12 * (1.0 + a.dist.abs());
                        assert!((a.dist - b.dist).abs() <= scale, "{} {}", a.dist, b.dist);
                        assert!((a.point1 - b.point1).length() <= 1e-6);
                        assert!((a.point2 - b.point2).length() <= 1e-6);
                        touching += usize::from(a.dist.abs() < 5e-4);
                        found += 1;
                    }
                    (a, b) => panic!("{free:?} {k}: {a:?} against {b:?}"),
                }
            }
        }
    }
    eprintln!("found {found}, none {none}, touching {touching}");
    assert!(
        found > 400 && none > 40 && touching > 60,
        "{found} {none} {touching}"
    );
}
