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
/// mesh on a 25 088-triangle sphere (its distance to round-off, its witness to GJK's accuracy;
/// for a capsule or chord apart, the exact distance — never above parry's GJK — with witnesses
/// on the triangle and the feature), for capsules, disks and chords touching it (where many
/// triangles are within a hair of the best), near it, across its wall and deep inside, seen
/// from either side, and nothing beyond the margin alike.
#[test]
fn closest_triangle_is_parrys_on_a_dense_sphere() {
    let (v, t) = sphere(0.03, 56);
    assert_eq!(t.len(), 25_088);
    let mut rng = Rng(0xB0B5_1DE5);
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
                let got = closest_triangle(&gpose, g, &opose, &m, (margin, None), true);
                // Started from any triangle — the answer's, its neighbour, one far away, one
                // out of range — the search returns the cold answer, to the bit.
                let near = got.map_or(0, |c| c.subshape2);
                for hint in [near, near + 1, near / 2, 7 * k as u32, u32::MAX] {
                    let warm = closest_triangle(&gpose, g, &opose, &m, (margin, Some(hint)), true);
                    let bits = |c: Option<PContact>| {
                        c.map(|c| (c.dist.to_bits(), c.point1, c.point2, c.normal1, c.subshape2))
                    };
                    assert_eq!(bits(warm), bits(got), "{free:?} {k}: hint {hint}");
                }
                match (want, got) {
                    (None, None) => none += 1,
                    (Some(a), Some(b)) => {
                        // A capsule or chord apart: the exact distance (below GJK's by up to
                        // its tolerance); otherwise parry's.
                        let exact = g.as_capsule().map_or(0.0, |c| c.radius);
                        let exact = (g.shape_type() != parry3d::shape::ShapeType::Cylinder)
                            .then(|| {
                                // (The feature's pose is the mesh's shift: its points are
                                // in the mesh's frame.)
                                exact_distance(&m, cap.segment.a, cap.segment.b, exact, b.dist)
                            })
                            .filter(|d| *d > 1e-6);
                        let (want, close) = exact.map_or((a.dist, 1e-6), |d| (d, 1e-15));
                        let scale = 1e-12 * (1.0 + want.abs());
                        assert!((want - b.dist).abs() <= scale, "{} {}", want, b.dist);
                        assert!(b.dist <= a.dist + scale, "{} {}", a.dist, b.dist);
                        if exact.is_some() {
                            // The exact witnesses (GJK's lie within the square root of its
                            // tolerance along a capsule tangent to the sphere): on the
                            // triangle, on the capsule, the distance apart.
                            use parry3d::query::PointQuery;
                            let on = m.triangle(b.subshape2);
                            let shift = opose.translation;
                            assert!(on.distance_to_local_point(b.point2 - shift, true) <= close);
                            let r = g.as_capsule().map_or(0.0, |c| c.radius);
                            let core = parry3d::shape::Segment::new(cap.segment.a, cap.segment.b);
                            let off = core.distance_to_local_point(b.point1 - shift, true);
                            assert!((off - r).abs() <= close, "{off} {r}");
                            assert!(((b.point1 - b.point2).length() - b.dist).abs() <= close);
                        } else {
                            assert!((a.point1 - b.point1).length() <= 1e-6);
                            assert!((a.point2 - b.point2).length() <= 1e-6);
                        }
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

/// A closed double cone: `n` ring vertices of radius `rho` at height 0 and two apexes of
/// valence `n`, at `-low` and `high` on z, outward; coordinates rounded to 1e-9 m as an OBJ
/// file holds them (so the fan's triangles tie only to round-off). With `low = 0.0157 rho` the
/// low apex is a UV sphere's pole seen from inside.
fn bicone(n: u32, rho: f64, low: f64, high: f64) -> (Vec<Vector3<f64>>, Vec<[u32; 3]>) {
    let round = |v: Vector3<f64>| v.map(|x| (x * 1e9).round() / 1e9);
    let mut v: Vec<Vector3<f64>> = (0..n)
        .map(|i| {
            let p = std::f64::consts::TAU * f64::from(i) / f64::from(n);
            round(Vector3::new(rho * p.cos(), rho * p.sin(), 0.0))
        })
        .collect();
    v.push(Vector3::new(0.0, 0.0, high));
    v.push(Vector3::new(0.0, 0.0, -low));
    let mut t = vec![];
    for i in 0..n {
        let j = (i + 1) % n;
        t.push([i, j, n]);
        t.push([j, i, n + 1]);
    }
    (v, t)
}

/// The minimum of a convex function on `[0, 1]` by golden-section search (to ~1e-15 in the
/// argument): the oracle for the closed-form distances below.
fn convex_min(f: impl Fn(f64) -> f64) -> f64 {
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    let g = (5f64.sqrt() - 1.0) / 2.0;
    for _ in 0..80 {
        let (x, y) = (hi - g * (hi - lo), lo + g * (hi - lo));
        if f(x) <= f(y) {
            hi = y;
        } else {
            lo = x;
        }
    }
    f(0.0).min(f(1.0)).min(f((lo + hi) / 2.0))
}

/// The distance from the segment `pq` (radius `r` about it) to the triangle, searched along
/// the segment (convex along it) with parry's point projection: the oracle for the closed form.
fn searched(p: PVec, q: PVec, r: f64, tri: &parry3d::shape::Triangle) -> f64 {
    use parry3d::query::PointQuery;
    convex_min(|s| tri.distance_to_local_point(p + s * (q - p), true)) - r
}

/// The exact distance from the capsule about `pq` (radius `r`, mesh frame) to `mesh`, given
/// that it is at most `upto`: the least over the triangles within reach of the distance
/// searched along the core.
pub(crate) fn exact_distance(mesh: &TriMesh, p: PVec, q: PVec, r: f64, upto: f64) -> f64 {
    use parry3d::bounding_volume::{Aabb, BoundingVolume};
    let reach = Aabb::new(p.min(q), p.max(q)).loosened(r + upto.max(0.0) + 1e-6);
    mesh.bvh()
        .leaves(|node| node.aabb().intersects(&reach))
        .map(|t| searched(p, q, r, &mesh.triangle(t)))
        .fold(f64::MAX, f64::min)
}

/// The closed forms of `segment_pair` and `core_contact` are the minimum found by searching
/// along the segment, to round-off: near-parallel segments (or parallel: left to GJK), crossing
/// ones, segments ending on an edge; the witnesses are that far apart, on the triangle and
/// on the capsule.
#[test]
fn the_core_contact_is_the_searched_distance() {
    use parry3d::query::PointQuery;
    let mut rng = Rng(0x07A1_10E5);
    let point = |rng: &mut Rng, s: f64| {
        pvec(&Vector3::new(
            rng.range(-s, s),
            rng.range(-s, s),
            rng.range(-s, s),
        ))
    };
    let (mut pairs, mut closed, mut left) = (0, 0, 0);
    for k in 0..3000 {
        let (p, u, v) = (
            point(&mut rng, 0.01),
            point(&mut rng, 0.01),
            point(&mut rng, 0.01),
        );
        let mut q = point(&mut rng, 0.01);
        if k % 5 == 0 {
            // Parallel to a few parts in 10⁴, or exactly.
            let tilt = [0.0, 1e-4, 3e-3][k % 3];
            q = p + (v - u) * rng.range(0.2, 2.0) + point(&mut rng, tilt * 0.01);
        }
        let along = |a: PVec, b: PVec, x: PVec| {
            let ab = b - a;
            let t = ((x - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0);
            (x - (a + t * ab)).length()
        };
        if let Some((x, y)) = segment_pair(p, q, u, v) {
            let want = convex_min(|s| along(u, v, p + s * (q - p)));
            assert!(
                ((x - y).length() - want).abs() <= 1e-13,
                "{k}: {x} {y} {want}"
            );
            assert!(along(p, q, x) <= 1e-15 && along(u, v, y) <= 1e-15);
            pairs += 1;
        }
        // A triangle with `uv` as an edge, and a capsule about `pq`.
        let tri = parry3d::shape::Triangle::new(u, v, point(&mut rng, 0.01));
        let Some(n) = tri.normal() else { continue };
        let r = [0.0, 0.001][k % 2];
        let rel = PPose::from_translation(PVec::new(0.1, 0.2, -0.3));
        match core_contact((p, q, r), &tri, (n, n.dot(u)), &rel) {
            Some(ct) => {
                let want = searched(p, q, r, &tri);
                assert!(
                    (ct.dist - want).abs() <= 1e-13,
                    "{k}: {} vs {want}",
                    ct.dist
                );
                let on_capsule = rel.transform_point(ct.point2);
                assert!(tri.distance_to_local_point(ct.point1, true) <= 1e-15);
                assert!((along(p, q, on_capsule) - r).abs() <= 1e-15);
                assert!(((on_capsule - ct.point1).length() - ct.dist).abs() <= 1e-15);
                assert!((on_capsule - ct.point1).dot(ct.normal1) > 0.0);
                closed += 1;
            }
            None => left += 1,
        }
    }
    assert!(
        pairs > 2000 && closed > 1000 && left > 300,
        "{pairs} {closed} {left}"
    );
}

/// Over fans of 3 to 512 triangles sharing an apex (a UV sphere's pole from inside, a sharp
/// cone's tip from outside), capsules and chords whose nearest point is on or beside the apex,
/// on a ring vertex, on an apex edge, or across the wall: the search's distance is the exact
/// one (searched along the core, triangle by triangle) to round-off where apart, never above
/// parry's whole-mesh query (GJK, a micrometre above it on some fans) and parry's to round-off
/// where touching or across; the witnesses are on the answer's triangle and the feature,
/// that far apart; started from any triangle the search returns the cold answer, to the bit.
#[test]
fn fans_give_the_exact_distance() {
    use parry3d::query::PointQuery;
    let mut rng = Rng(0xFA_0A9E);
    let (mut apart, mut across, mut ties) = (0, 0, 0);
    for n in [3, 8, 128, 512] {
        let rho = 0.01;
        for (low, high, free) in [
            (0.0157 * rho, 30.0 * rho, Free::Inside),
            (3.0 * rho, 3.0 * rho, Free::Outside),
        ] {
            let (v, t) = bicone(n, rho, low, high);
            let m = solid_trimesh(&v, &t, Some(free)).unwrap();
            let opose = PPose::from_translation(PVec::new(0.01, -0.02, 0.03));
            let shift = |p: Vector3<f64>| p + nvec(opose.translation);
            for k in 0..60 {
                // Where the nearest point is: the low apex, beside it by a hair, a ring
                // vertex, a point of an apex edge.
                let apex = Vector3::new(0.0, 0.0, -low);
                let ring = v[k % n as usize];
                let target = match k % 4 {
                    0 => apex,
                    1 => apex + Vector3::new(rng.range(-1e-9, 1e-9), rng.range(-1e-9, 1e-9), 0.0),
                    2 => ring,
                    _ => apex + rng.range(0.0, 1.0) * (ring - apex),
                };
                // Towards the free side: up into the cone from the low apex inside, down
                // away from it outside; tilted, or straight along the axis.
                let mut dir = if k % 3 == 0 {
                    Vector3::z()
                } else {
                    unit(&mut rng)
                };
                dir.z = match free {
                    Free::Inside => dir.z.abs() + 0.5,
                    Free::Outside => -dir.z.abs() - 0.5,
                };
                let dir = dir.normalize();
                let gap = match k % 5 {
                    0 | 1 => rng.range(0.0, 0.002),
                    2 => 0.0,
                    3 => -rng.range(0.0, 0.0005),
                    _ => rng.range(0.002, 0.01),
                };
                let radius = [0.0015, 0.0004][k % 2];
                let axis = unit(&mut rng);
                let centre = target + dir * (gap + radius);
                let ends = if k % 2 == 0 {
                    (
                        centre,
                        centre + 0.006 * axis.cross(&dir).normalize() + 0.006 * dir,
                    )
                } else {
                    (centre - 0.003 * axis, centre + 0.003 * axis)
                };
                let cap = Capsule::new(pvec(&shift(ends.0)), pvec(&shift(ends.1)), radius);
                let chord = parry3d::shape::Segment::new(cap.segment.a, cap.segment.b);
                let shapes: [(&dyn PShape, f64); 2] = [(&cap, radius), (&chord, 0.0)];
                for (g, r) in shapes {
                    let gpose = PPose::IDENTITY;
                    let margin = 0.02;
                    let bits = |c: Option<PContact>| {
                        c.map(|c| (c.dist.to_bits(), c.point1, c.point2, c.normal1, c.subshape2))
                    };
                    let got = closest_triangle(&gpose, g, &opose, &m, (margin, None), true);
                    let near = got.map_or(0, |c| c.subshape2);
                    for hint in [near, near ^ 1, 2 * n - 1] {
                        let warm =
                            closest_triangle(&gpose, g, &opose, &m, (margin, Some(hint)), true);
                        assert_eq!(bits(warm), bits(got), "{n} {free:?} {k}: hint {hint}");
                    }
                    let want = parry3d::query::contact(&gpose, g, &opose, &m, margin).unwrap();
                    let (Some(a), Some(b)) = (want, got) else {
                        panic!("{n} {free:?} {k}: {want:?} against {got:?}");
                    };
                    // The exact distance, triangle by triangle (mesh frame: less the shift).
                    let (p, q) = (
                        cap.segment.a - opose.translation,
                        cap.segment.b - opose.translation,
                    );
                    let dists: Vec<f64> = (0..m.indices().len() as u32)
                        .map(|t| searched(p, q, r, &m.triangle(t)))
                        .collect();
                    let exact = dists.iter().copied().fold(f64::MAX, f64::min);
                    if exact > 1e-6 {
                        assert!(
                            (b.dist - exact).abs() <= 1e-12,
                            "{n} {free:?} {k}: {} vs {exact}",
                            b.dist
                        );
                        assert!(
                            b.dist <= a.dist + 1e-12,
                            "{n} {free:?} {k}: {} vs {}",
                            b.dist,
                            a.dist
                        );
                        let tri = m.triangle(b.subshape2);
                        let on_mesh = b.point2 - opose.translation;
                        assert!(tri.distance_to_local_point(on_mesh, true) <= 1e-15);
                        assert!(((b.point1 - b.point2).length() - b.dist).abs() <= 1e-15);
                        apart += 1;
                        ties +=
                            usize::from(dists.iter().filter(|d| **d < exact + 1e-9).count() >= 8);
                    } else {
                        assert!((a.dist - b.dist).abs() <= 1e-12 * (1.0 + a.dist.abs()));
                        assert!((a.point1 - b.point1).length() <= 1e-6);
                        assert!((a.point2 - b.point2).length() <= 1e-6);
                        across += 1;
                    }
                }
            }
        }
    }
    eprintln!("apart {apart}, touching or across {across}, fans tied {ties}");
    assert!(
        apart > 400 && across > 100 && ties > 100,
        "{apart} {across} {ties}"
    );
}

/// A random unit vector (normalized from the cube `[-1, 1]³`).
fn unit(rng: &mut Rng) -> Vector3<f64> {
    Vector3::new(
        rng.range(-1.0, 1.0),
        rng.range(-1.0, 1.0),
        rng.range(-1.0, 1.0),
    )
    .normalize()
}
