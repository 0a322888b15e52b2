use super::super::field::tests::{points, tube};
use super::super::field::SolidField;
use crate::model::mesh::{trimesh, Free};
use crate::numeric::test_rng::Rng;
use nalgebra::Vector3;
use parry3d::math::{Pose as PPose, Vector as PVec};
use parry3d::query::PointQueryWithLocation;
use parry3d::shape::Shape as PShape;

/// The corner-by-corner interval contains the exact signed distance (parry's projection,
/// signed by the side) and is never looser than the trilinear one.
#[test]
fn point_interval_contains_the_exact_signed_distance() {
    for free in [Free::Inside, Free::Outside] {
        let (v, t) = tube();
        let m = trimesh(&v, &t, Some(free)).unwrap();
        let f = SolidField::build(&m, 1 << 16);
        for p in points(&m, 4000, 17) {
            let q = PVec::new(p[0], p[1], p[2]);
            let (proj, _) = m.project_local_point_and_get_location(q, false);
            let d = (q - proj.point).length();
            let exact = if proj.is_inside { -d } else { d };
            let (lo, hi) = f.point_interval(p);
            assert!(
                lo <= exact + 1e-12 && exact <= hi + 1e-12,
                "{lo} {exact} {hi}"
            );
            let (tl, th) = f.point_bounds(p);
            let tol = 1e-9 * (1.0 + tl.abs() + th.abs());
            assert!(lo >= tl - tol && hi <= th + tol, "{lo} {hi} vs {tl} {th}");
        }
    }
}

/// A capsule's, a segment's and a disk's grid interval holds for features inside, across and
/// beyond a lumen's wall, against parry's signed contact on the triangles: a positive lower
/// bound is below the exact clearance (and then the feature is clear), the exact clearance
/// is at most `max(upper, 0)`; and the interval is narrow (its mean width measured).
#[test]
fn feature_interval_contains_the_exact_clearance() {
    let (v, t) = tube();
    let m = trimesh(&v, &t, Some(Free::Inside)).unwrap();
    let f = SolidField::build(&m, 1 << 16);
    let mut rng = Rng(0x5EED_1A7E);
    let id = PPose::IDENTITY;
    let (mut checked, mut clear, mut across, mut width) = (0, 0, 0, 0.0);
    for _ in 0..600 {
        // A point on the centreline, moved off it by up to 2.5 cm (the tube's radius: 2 cm).
        let th = -0.1 + 1.9 * rng.next();
        let c = Vector3::new(0.11 * (1.0 - th.cos()), 0.0, 0.11 * th.sin());
        let off = Vector3::new(rng.next() - 0.5, rng.next() - 0.5, rng.next() - 0.5);
        let c = c + 0.05 * off;
        let dir = Vector3::new(rng.next() - 0.5, rng.next() - 0.5, rng.next() - 0.5).normalize();
        let a = crate::contact::pvec(&(c - 0.004 * dir));
        let b = crate::contact::pvec(&(c + 0.004 * dir));
        let cap = parry3d::shape::Capsule::new(a, b, 0.0015);
        let seg = parry3d::shape::Segment::new(a, b);
        let disk = parry3d::shape::Cylinder::new(0.001, 0.006);
        let rot = nalgebra::Rotation3::rotation_between(&Vector3::y(), &dir)
            .unwrap_or_else(nalgebra::Rotation3::identity);
        let dpose = crate::contact::ppose(rot.matrix(), &c);
        let shapes: [(&dyn PShape, PPose); 3] = [(&cap, id), (&seg, id), (&disk, dpose)];
        for (g, gpose) in shapes {
            let Ok(Some(ct)) = parry3d::query::contact(&gpose, g, &id, &m, 1.0) else {
                continue;
            };
            let exact = crate::contact::solid::signed(ct, g, &gpose, &m, &id).dist;
            let (lo, hi) = f.feature_interval(g, &gpose, &id).unwrap();
            assert!(exact <= hi.max(0.0) + 1e-12, "{exact} {hi}");
            if lo > 0.0 {
                assert!(lo <= exact + 1e-12, "{lo} {exact}");
            }
            if exact > 0.0 {
                clear += 1;
                width += hi - lo;
            } else {
                across += 1;
            }
            checked += 1;
        }
    }
    assert!(
        clear > 400 && across > 100,
        "{clear} clear, {across} across"
    );
    // Mean width under two cells (1.79 cells when written).
    let mean = width / clear as f64;
    println!("mean width {:.3} cells over {clear}", mean / f.h);
    assert!(mean < 2.0 * f.h, "mean width {mean} for h = {}", f.h);
    assert!(checked > 1000, "{checked}");
}
