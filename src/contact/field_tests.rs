use super::*;
use crate::contact::solid::tests::exact_distance;
use crate::model::mesh::{trimesh, BentTube, Free};
use crate::numeric::test_rng::Rng;
use nalgebra::Vector3;
use parry3d::query::PointQueryWithLocation;
use parry3d::shape::TriMesh;

/// The generalized winding number of the closed mesh about `p` (sum of the triangles' solid
/// angles over 4π, Van Oosterom and Strackee): ±1 enclosed, 0 outside. Independent of parry
/// and of the pseudo-normals.
fn winding(v: &[Vector3<f64>], t: &[[u32; 3]], p: &Vector3<f64>) -> f64 {
    let mut sum = 0.0;
    for tri in t {
        let [a, b, c] = tri.map(|i| v[i as usize] - p);
        let (la, lb, lc) = (a.norm(), b.norm(), c.norm());
        let num = a.dot(&b.cross(&c));
        let den = la * lb * lc + a.dot(&b) * lc + b.dot(&c) * la + c.dot(&a) * lb;
        sum += 2.0 * num.atan2(den);
    }
    sum / (4.0 * std::f64::consts::PI)
}

/// The committed vessel's bend closed at both ends, coarse (60 rings × 24): the lumen of
/// these tests and the cache's.
pub(crate) fn tube() -> (Vec<Vector3<f64>>, Vec<[u32; 3]>) {
    BentTube {
        bend_radius: 0.11,
        tube_radius: 0.02,
        theta0: -0.1,
        theta1: 1.8,
        rings: 60,
        segments: 24,
    }
    .capped()
}

fn solid(free: Free) -> (TriMesh, Vec<Vector3<f64>>, Vec<[u32; 3]>) {
    let (v, t) = tube();
    let m = trimesh(&v, &t, Some(free)).unwrap();
    (m, v, t)
}

/// Random points in the mesh's bounds grown by 2 cm (also the cache tests').
pub(crate) fn points(m: &TriMesh, n: usize, seed: u64) -> Vec<[f64; 3]> {
    let b = m.local_aabb();
    let mut rng = Rng(0x5EED_0000 ^ seed);
    (0..n)
        .map(|_| {
            [0, 1, 2].map(|a| {
                let (lo, hi) = (b.mins[a] - 0.02, b.maxs[a] + 0.02);
                lo + (hi - lo) * rng.next()
            })
        })
        .collect()
}

/// The grid's bounds contain the exact signed distance (parry's projection, signed by the
/// side), and are no wider than the stated bound: `h √3` plus `LOOSE h` where a loose node
/// enters.
#[test]
fn bounds_contain_the_exact_signed_distance() {
    let mut tighter = 0;
    for free in [Free::Inside, Free::Outside] {
        let (m, _, _) = solid(free);
        let f = SolidField::build(&m, 1 << 16);
        for p in points(&m, 4000, 7) {
            let q = PVec::new(p[0], p[1], p[2]);
            let (proj, _) = m.project_local_point_and_get_location(q, false);
            let d = (q - proj.point).length();
            let exact = if proj.is_inside { -d } else { d };
            let (lo, hi) = f.point_bounds(p);
            assert!(
                lo <= exact + 1e-12 && exact <= hi + 1e-12,
                "{free:?} {p:?}: {lo} {exact} {hi}"
            );
            // The corner-by-corner bound: below the truth, at or above the interpolated one.
            let below = f.point_below(p);
            assert!(below <= exact + 1e-12, "{free:?} {p:?}: {below} {exact}");
            assert!(below >= lo - 1e-9 * (1.0 + lo.abs()), "{below} {lo}");
            tighter += usize::from(below > lo + 0.1 * f.h);
            let inside_grid = (0..3)
                .all(|a| p[a] >= f.origin[a] && p[a] <= f.origin[a] + (f.n[a] - 1) as f64 * f.h);
            if inside_grid {
                let width = hi - lo;
                assert!(
                    width <= f.h * (2.0 * HALF_DIAG + LOOSE) + 1e-6 * lo.abs(),
                    "{width} {} {p:?} {lo} {hi}",
                    f.h
                );
            }
        }
    }
    // Over a third of the points gain more than a tenth of a cell from the corner-by-corner
    // bound (3776 of 8000 when written).
    assert!(tighter > 3000, "{tighter} of 8000");
}

/// Where the grid decides the side (both bounds of one sign), it is the side the winding
/// number gives: free inside a lumen, free outside an organ.
#[test]
fn side_agrees_with_the_winding_number() {
    for free in [Free::Inside, Free::Outside] {
        let (m, v, t) = solid(free);
        let f = SolidField::build(&m, 1 << 16);
        let (mut decided, mut n) = (0, 0);
        for p in points(&m, 1500, 11) {
            let (lo, hi) = f.point_bounds(p);
            let enclosed = winding(&v, &t, &Vector3::new(p[0], p[1], p[2])).abs() > 0.5;
            let free_side = enclosed == (free == Free::Inside);
            n += 1;
            if lo > 0.0 {
                assert!(free_side, "{free:?} {p:?}: free by the grid ({lo})");
                decided += 1;
            } else if hi < 0.0 {
                assert!(!free_side, "{free:?} {p:?}: obstacle by the grid ({hi})");
                decided += 1;
            }
        }
        // Most points are farther from the wall than the grid's error.
        assert!(decided * 10 > 8 * n, "{decided} of {n}");
    }
}

/// A capsule's and a disk's bounds contain their exact clearance from the lumen's wall
/// (parry against the triangles), for features inside the lumen.
#[test]
fn feature_bounds_contain_the_exact_clearance() {
    let (m, _, _) = solid(Free::Inside);
    let f = SolidField::build(&m, 1 << 16);
    let mut rng = Rng(0x5EED_0000 + 3);
    let id = PPose::IDENTITY;
    let mut checked = 0;
    for _ in 0..400 {
        // A point on the centreline, moved off it by up to 1.5 cm.
        let th = -0.1 + 1.9 * rng.next();
        let c = Vector3::new(0.11 * (1.0 - th.cos()), 0.0, 0.11 * th.sin());
        let off = Vector3::new(rng.next() - 0.5, rng.next() - 0.5, rng.next() - 0.5);
        let c = c + 0.03 * off;
        let dir = Vector3::new(rng.next() - 0.5, rng.next() - 0.5, rng.next() - 0.5).normalize();
        let a = crate::contact::pvec(&(c - 0.004 * dir));
        let b = crate::contact::pvec(&(c + 0.004 * dir));
        let cap = parry3d::shape::Capsule::new(a, b, 0.0015);
        let disk = parry3d::shape::Cylinder::new(0.001, 0.006);
        let rot = nalgebra::Rotation3::rotation_between(&Vector3::y(), &dir)
            .unwrap_or_else(nalgebra::Rotation3::identity);
        let dpose = crate::contact::ppose(rot.matrix(), &c);
        let shapes: [(&dyn PShape, PPose); 2] = [(&cap, id), (&disk, dpose)];
        for (g, gpose) in shapes {
            let Ok(Some(ct)) = parry3d::query::contact(&gpose, g, &id, &m, 1.0) else {
                continue;
            };
            let exact = crate::contact::solid::signed(ct, g, &gpose, &m, &id).dist;
            if exact <= 0.0 {
                continue;
            }
            let mut lows = vec![];
            for refine in [false, true] {
                let (lo, hi) = f.feature_bounds(g, &gpose, &id, refine).unwrap();
                assert!(
                    lo <= exact + 1e-12 && exact <= hi + 1e-12,
                    "{lo} {exact} {hi}"
                );
                lows.push(lo);
            }
            // Refined is never looser.
            assert!(lows[1] >= lows[0], "{lows:?}");
            checked += 1;
        }
    }
    assert!(checked > 200, "{checked}");
}

/// A feature's signed contact through the grid and the filtered triangle walk is parry's
/// against the whole mesh (`None` alike), for features inside, across and beyond the wall of
/// a lumen and beside an organ, over margins from 1 mm to 5 cm.
#[test]
fn query_with_the_grid_is_parrys() {
    for free in [Free::Inside, Free::Outside] {
        let (m, _, _) = solid(free);
        let f = SolidField::build(&m, 1 << 16);
        let opose = PPose::from_translation(PVec::new(0.01, -0.02, 0.03));
        let mut rng = Rng(0x5EED_0044);
        let (mut found, mut none) = (0, 0);
        for _ in 0..300 {
            let th = -0.1 + 1.9 * rng.next();
            let c = Vector3::new(0.11 * (1.0 - th.cos()), 0.0, 0.11 * th.sin());
            let off = Vector3::new(rng.next() - 0.5, rng.next() - 0.5, rng.next() - 0.5);
            let c = c + 0.06 * off + Vector3::new(0.01, -0.02, 0.03);
            let dir =
                Vector3::new(rng.next() - 0.5, rng.next() - 0.5, rng.next() - 0.5).normalize();
            let cap = parry3d::shape::Capsule::new(
                crate::contact::pvec(&(c - 0.005 * dir)),
                crate::contact::pvec(&(c + 0.005 * dir)),
                0.0015,
            );
            let disk = parry3d::shape::Cylinder::new(0.001, 0.008);
            let rot = nalgebra::Rotation3::rotation_between(&Vector3::y(), &dir)
                .unwrap_or_else(nalgebra::Rotation3::identity);
            let dpose = crate::contact::ppose(rot.matrix(), &c);
            let margin = 0.001 * 50f64.powf(rng.next());
            let shapes: [(&dyn PShape, PPose); 2] = [(&cap, PPose::IDENTITY), (&disk, dpose)];
            for (k, (g, gpose)) in shapes.into_iter().enumerate() {
                // The capsule (first), apart and on the free side by the grid.
                let free_cap = |c: &parry3d::query::Contact| {
                    k == 0
                        && c.dist > 0.0
                        && f.feature_bounds(g, &gpose, &opose, true)
                            .is_some_and(|b| b.0 > 0.0)
                };
                let want = crate::contact::query(&gpose, g, &opose, &m, margin, None);
                let got = crate::contact::query(&gpose, g, &opose, &m, margin, Some(&f));
                match (want, got) {
                    (None, None) => none += 1,
                    (Some(a), Some(b)) if free_cap(&b) => {
                        // A capsule wholly free is measured in closed form with the grid, by
                        // GJK without, which stops within its tolerance (micrometres above
                        // over ties): both against the distance searched along the core
                        // (`solid`'s oracle); GJK's is between two points of the shapes, so
                        // never below it.
                        let (p, q) = (cap.segment.a, cap.segment.b);
                        let (p, q) = (
                            opose.inverse_transform_point(p),
                            opose.inverse_transform_point(q),
                        );
                        let exact = exact_distance(&m, p, q, cap.radius, b.dist);
                        assert!((b.dist - exact).abs() <= 1e-12, "{} {exact}", b.dist);
                        assert!(a.dist >= exact - 1e-12, "{} {exact}", a.dist);
                        // Its witnesses (tied triangles may hold others): one on the capsule,
                        // one on the mesh, `dist` apart.
                        use parry3d::query::PointQuery;
                        let on_cap = cap.distance_to_point(&gpose, b.point1, false);
                        let on_mesh = m.distance_to_point(&opose, b.point2, false);
                        let apart = (b.point1 - b.point2).length();
                        assert!(on_mesh <= 1e-12 && on_cap <= 1e-12, "{on_mesh} {on_cap}");
                        assert!((apart - b.dist).abs() <= 1e-12, "{apart} {}", b.dist);
                        found += 1;
                    }
                    (Some(a), Some(b)) => {
                        assert!((a.dist - b.dist).abs() <= 1e-9, "{} {}", a.dist, b.dist);
                        assert!((a.point1 - b.point1).length() <= 1e-6);
                        found += 1;
                    }
                    (a, b) => panic!("{free:?} margin {margin}: {a:?} against {b:?}"),
                }
            }
        }
        assert!(found > 100 && none > 50, "{found} {none}");
    }
}
