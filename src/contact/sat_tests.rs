use super::*;
use crate::contact::features::{self, disk_pose};
use crate::contact::primitives::Convex;
use crate::contact::{nvec, ppose, pvec};
use crate::numeric::test_rng::Rng;
use parry3d::math::Pose as PPose;
use parry3d::shape::{Cuboid, Cylinder, Shape as PShape};

/// A random rotation.
fn rotation(rng: &mut Rng) -> Matrix3<f64> {
    let w = Vector3::new(
        rng.range(-3.0, 3.0),
        rng.range(-3.0, 3.0),
        rng.range(-3.0, 3.0),
    );
    nalgebra::Rotation3::new(w).into_inner()
}

/// A sampled pair: the feature (convex set, parry shape and pose) and the obstacle (parry
/// shape and pose).
type Sample = (Convex, Box<dyn PShape>, PPose, Box<dyn PShape>, PPose);

/// The support maps of a sampled feature and obstacle, `(feature, obstacle)`: every shape
/// [`sample`] draws has one.
fn supports(feature: &Convex, oshape: &dyn PShape, opose: &PPose) -> (SupportShape, SupportShape) {
    match (feature_support(feature), obstacle_support(oshape, opose)) {
        (Some(f), Some(o)) => (f, o),
        _ => panic!("a sampled shape without a support map"),
    }
}

/// The separating-axis value along `m` (normalized) by parry's support maps, independent of
/// `sat.rs`: `m · (s_f(−m) − s_o(m))`, the feature's extent towards the obstacle's; the
/// signed distance is its maximum over directions.
pub(crate) fn separation(
    fshape: &dyn PShape,
    fpose: &PPose,
    oshape: &dyn PShape,
    opose: &PPose,
    m: &Vector3<f64>,
) -> f64 {
    let (Some(fs), Some(os)) = (fshape.as_support_map(), oshape.as_support_map()) else {
        panic!("a sampled shape without parry's support map");
    };
    let m = m.normalize();
    let sf = nvec(fs.support_point(fpose, pvec(&-m)));
    let so = nvec(os.support_point(opose, pvec(&m)));
    m.dot(&(sf - so))
}

/// Pair `n` of the sample: a box (even `n`) or cylinder at a random pose and a disk,
/// capsule or chord (`n % 3`) centred on a sphere around it at about its size (edges,
/// corners, rims and faces; apart, touching and overlapping).
fn sample(n: usize, rng: &mut Rng) -> Sample {
    let orot = rotation(rng);
    let oc = Vector3::new(rng.range(-0.05, 0.05), 0.0, rng.range(-0.05, 0.05));
    let opose = ppose(&orot, &oc);
    let (oshape, size): (Box<dyn PShape>, f64) = if n.is_multiple_of(2) {
        let e = Vector3::new(
            rng.range(0.004, 0.02),
            rng.range(0.004, 0.02),
            rng.range(0.004, 0.06),
        );
        (Box::new(Cuboid::new(pvec(&e))), e.norm())
    } else {
        let (r, h) = (rng.range(0.004, 0.015), rng.range(0.01, 0.05));
        (Box::new(Cylinder::new(h, r)), r.hypot(h))
    };
    // A feature centre on a sphere around the obstacle, at about its size.
    let dir = rotation(rng).column(0).into_owned();
    let frot = rotation(rng);
    let fc = oc + dir * rng.range(0.6, 1.3) * (size + 0.006);
    let (feature, fshape, fpose): (Convex, Box<dyn PShape>, PPose) = match n % 3 {
        0 => {
            let (rd, ht) = (0.006, 0.001);
            (
                Convex::Disk(frot, fc, rd, ht),
                Box::new(Cylinder::new(ht, rd)),
                disk_pose(&frot, &fc),
            )
        }
        k => {
            let r = if k == 1 { 0.0008 } else { 0.0 };
            let d = frot.column(0) * rng.range(0.002, 0.02);
            let (a, b) = (fc - d, fc + d);
            let s: Box<dyn PShape> = if r > 0.0 {
                Box::new(features::backbone(&a, &b, r))
            } else {
                Box::new(features::chord(&a, &b))
            };
            (Convex::Segment(a, b, r), s, PPose::IDENTITY)
        }
    };
    (feature, fshape, fpose, oshape, opose)
}

/// How far the witnesses `w` of a pair apart are from a closest pair, by parry's exact point
/// projections (independent of the separating-axis maximum): each witness's distance from its
/// surface, `|a − b|` against the distance, `a − b` against the normal (times the distance),
/// and each witness against its projection from the other.
fn closest_pair_errors(
    fshape: &dyn PShape,
    fpose: &PPose,
    oshape: &dyn PShape,
    opose: &PPose,
    w: &Witness,
) -> [f64; 6] {
    let on_obstacle = oshape.distance_to_point(opose, pvec(&w.obstacle), false);
    let on_feature = fshape.distance_to_point(fpose, pvec(&w.robot), false);
    let back_o = nvec(oshape.project_point(opose, pvec(&w.robot), true).point);
    let back_f = nvec(fshape.project_point(fpose, pvec(&w.obstacle), true).point);
    let gap = w.robot - w.obstacle;
    [
        on_obstacle.abs(),
        on_feature.abs(),
        (gap.norm() - w.dist).abs(),
        (gap / gap.norm() - w.normal).amax() * w.dist,
        (back_o - w.obstacle).amax(),
        (back_f - w.robot).amax(),
    ]
}

/// On random disks, capsules and chords near randomly posed boxes and cylinders (their
/// edges, corners, rims and faces; apart, touching and overlapping), every decided answer is
/// checked against parry's exact point projections, independent of the maximum: apart, the
/// witnesses lie on the two surfaces, `|a − b|` is the distance and `a − b` the normal, and
/// each witness is the other's projection (the closest pair is a fixed point); apart or
/// overlapping, the separating-axis value from parry's support maps is the distance at the
/// normal and no larger at 200 directions near it and anywhere. Decided answers agree with parry's (the start) to its accuracy by
/// construction; the sample reaches box edges and corners and cylinder rims.
#[test]
fn exact_witnesses_are_closest_pairs() {
    let mut rng = Rng(0x0005_a70f_ba11_c0de);
    let (mut decided, mut edges, mut corners, mut rims, mut apart, mut over) = (0, 0, 0, 0, 0, 0);
    let mut worst = 0.0f64;
    for n in 0..6000 {
        let (feature, fshape, fpose, oshape, opose) = sample(n, &mut rng);
        let axis = |v: Vector3<f64>| nvec(opose.rotation * pvec(&v));
        let orot =
            Matrix3::from_columns(&[axis(Vector3::x()), axis(Vector3::y()), axis(Vector3::z())]);
        let margin = 0.01;
        let Some((rough, _)) = features::witness(&*fshape, &fpose, &*oshape, &opose, margin, None)
        else {
            continue;
        };
        let (f, o) = supports(&feature, &*oshape, &opose);
        let Some(w) = sat_witness(&f, &o, &rough) else {
            continue;
        };
        decided += 1;
        let local = orot.transpose() * w.normal;
        let zeros = (0..3).filter(|&i| local[i].abs() < 1e-9).count();
        if n % 2 == 0 {
            edges += usize::from(zeros == 1);
            corners += usize::from(zeros == 0);
        } else {
            rims += usize::from(local.y.abs() > 1e-9 && local.xz().norm() > 1e-9);
        }
        if w.dist > 1e-6 {
            apart += 1;
            let err = closest_pair_errors(&*fshape, &fpose, &*oshape, &opose, &w);
            let e = err.iter().fold(0.0f64, |m, x| m.max(*x));
            assert!(e < 1e-12, "{n}: {err:?} {w:?}");
            worst = worst.max(e);
        } else if w.dist < -1e-6 {
            over += 1;
        }
        // The separating-axis value by parry's support maps: at the normal it is the
        // distance, and no direction near it or anywhere gives more.
        let phi = |m: &Vector3<f64>| separation(&*fshape, &fpose, &*oshape, &opose, m);
        assert!((phi(&w.normal) - w.dist).abs() < 1e-13, "{n}: {w:?}");
        for k in 0..200 {
            let r = Vector3::new(
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
            );
            let m = if k < 100 {
                w.normal + r * 10f64.powi(-2 - k % 6)
            } else {
                r
            };
            assert!(phi(&m) <= w.dist + 1e-13, "{n}: {} > {}", phi(&m), w.dist);
        }
    }
    eprintln!(
        "decided {decided}: box edges {edges}, corners {corners}, cylinder rims {rims}; apart {apart} (worst {worst:.1e}), overlapping {over}"
    );
    assert!(
        edges >= 100 && corners >= 50 && rims >= 100 && apart >= 300 && over >= 30,
        "{decided} {edges} {corners} {rims} {apart} {over}"
    );
}

/// Apart, the separating-axis maximum from the cold start of [`apart_witness`] (no GJK) is
/// the pair's distance: on the sample of [`sample`], every decided answer is a closest
/// pair by parry's exact point projections (independent of the maximum), agrees with
/// parry's distance to its accuracy and with the maximum started from parry's answer
/// ([`sat_witness`]) to round-off; it decides most pairs apart (91 %), and never one that
/// overlaps or touches.
#[test]
fn apart_witnesses_need_no_gjk() {
    let mut rng = Rng(0x00a9_a27f_5eed_0001);
    let (mut apart, mut decided, mut overlapping) = (0, 0, 0);
    for n in 0..4000 {
        let (feature, fshape, fpose, oshape, opose) = sample(n, &mut rng);
        let Some((rough, _)) = features::witness(&*fshape, &fpose, &*oshape, &opose, 0.01, None)
        else {
            continue;
        };
        let got = apart_witness(&*oshape, &opose, &feature);
        if rough.dist <= 1e-9 {
            overlapping += usize::from(rough.dist < -1e-9);
            assert!(got.is_none(), "{n}: {rough:?} decided apart as {got:?}");
            continue;
        }
        apart += 1;
        let Some(w) = got else {
            continue;
        };
        decided += 1;
        assert!((w.dist - rough.dist).abs() < 1e-6, "{n}: {w:?} {rough:?}");
        let (f, o) = supports(&feature, &*oshape, &opose);
        if let Some(warm) = sat_witness(&f, &o, &rough) {
            assert!((warm.dist - w.dist).abs() < 1e-14, "{n}: {warm:?} {w:?}");
            assert!(
                (warm.normal - w.normal).amax() < 1e-9,
                "{n}: {warm:?} {w:?}"
            );
        }
        let err = closest_pair_errors(&*fshape, &fpose, &*oshape, &opose, &w);
        assert!(err.iter().all(|e| *e < 1e-11), "{n}: {err:?} {w:?}");
    }
    eprintln!("apart {apart}: decided without GJK {decided}; overlapping {overlapping}");
    assert!(apart >= 1000 && overlapping >= 100, "{apart} {overlapping}");
    // 1143 of 1259 when written; the rest go to parry (a cap seen face on, witnesses it
    // cannot place, no convergence).
    assert!(
        decided as f64 >= 0.85 * apart as f64,
        "{decided} of {apart}"
    );
}

/// Touching or overlapping, the exact witness from a normal of a moment ago
/// ([`near_witness`]: the feature moved clear along it, no parry) is the one parry's route
/// ends in (EPA, the shifted GJK, then [`sat_witness`]): on the sample of [`sample`], hints
/// the route's normal turned by up to 0.03 rad and its distance off by up to 0.1 mm, every
/// pair both decide agrees to 1e-12 m and 1e-9 in the normal; the separating-axis value by
/// parry's support maps is the distance at its normal and no larger near it. It decides most
/// of the pairs parry's route does (427 of 559 when written, all deeper than 1 µm; the rest
/// go to parry, as in the solvers).
#[test]
fn near_witnesses_are_parrys_without_parry() {
    let mut rng = Rng(0x6e65_6172_0005_a700);
    let (mut both, mut route, mut overlapping) = (0, 0, 0);
    for n in 0..6000 {
        let (feature, fshape, fpose, oshape, opose) = sample(n, &mut rng);
        let Some((rough, _)) = features::witness(&*fshape, &fpose, &*oshape, &opose, 0.01, None)
        else {
            continue;
        };
        if rough.dist > 1e-9 {
            continue;
        }
        let (f, o) = supports(&feature, &*oshape, &opose);
        let Some(old) = sat_witness(&f, &o, &rough) else {
            continue;
        };
        route += 1;
        overlapping += usize::from(old.dist < -1e-6);
        let turn = Vector3::new(
            rng.range(-0.03, 0.03),
            rng.range(-0.03, 0.03),
            rng.range(-0.03, 0.03),
        );
        let hint = nalgebra::Rotation3::new(turn) * old.normal;
        let Some(w) = near_witness(&f, &o, (&hint, old.dist + rng.range(-1e-4, 1e-4))) else {
            continue;
        };
        both += 1;
        assert!((w.dist - old.dist).abs() < 1e-12, "{n}: {w:?} {old:?}");
        assert!((w.normal - old.normal).amax() < 1e-9, "{n}: {w:?} {old:?}");
        assert!((w.robot - old.robot).amax() < 1e-9, "{n}: {w:?} {old:?}");
        let phi = |m: &Vector3<f64>| separation(&*fshape, &fpose, &*oshape, &opose, m);
        assert!((phi(&w.normal) - w.dist).abs() < 1e-13, "{n}: {w:?}");
        for k in 0..60 {
            let r = Vector3::from_fn(|_, _| rng.range(-1.0, 1.0));
            let m = w.normal + r * 10f64.powi(-3 - k % 5);
            assert!(phi(&m) <= w.dist + 1e-13, "{n}: {} > {}", phi(&m), w.dist);
        }
    }
    eprintln!("parry's route decided {route} touching or overlapping ({overlapping} deeper than 1 µm); the hinted route {both}");
    assert!(route >= 100 && overlapping >= 30, "{route} {overlapping}");
    assert!(both as f64 >= 0.7 * route as f64, "{both} of {route}");
}
