//! Unit tests of `energy/contacts.rs`: distance gradients against finite differences, and
//! the stopped pair query of the line search.

use super::*;
use crate::method::energy::test_fixture::{
    bent_state, case2_beside, sub_arc_lengths, world, Third,
};

/// `pairs_until` with a rule that never fires is `pairs_near` to the bit; with the rule
/// "violation above `t`" it gives up exactly when the full violation of those pairs
/// (summed as the line search's merit sums it) is above `t`.
#[test]
fn stopped_query_gives_up_only_on_a_rejected_sum() {
    let model = case2_beside(Third::Capsule);
    let m = 2;
    let ell = sub_arc_lengths(&model.robot, m);
    let nsub = ell.len();
    let world = world(&model, m);
    // A clearance that puts many pairs in violation, the bent state and a copy of it
    // pushed further (whose query starts from the first's normals, as a trial does).
    let clearance = 0.02;
    let xi = bent_state(4 * nsub);
    let kin = kinematics(&xi, &ell, false);
    let (hints, _) = world.pairs(&kin);
    let pushed: Vec<f64> = xi.iter().map(|v| 1.1 * v).collect();
    let kin = kinematics(&pushed, &ell, false);
    let (all, clear) = world.pairs_near(&kin, &hints);
    let terms: Vec<f64> = all.iter().map(|p| (clearance - p.dist).max(0.0)).collect();
    let total = terms.iter().fold(0.25, |v, t| v + t);
    assert!(terms.iter().filter(|&&t| t > 0.0).count() >= 3, "{terms:?}");
    let never = |_: &[Pair]| false;
    let stop = Stop {
        clearance,
        rejects: &never,
    };
    let (same, same_clear) = world.pairs_until(&kin, &hints, Some(stop)).expect("kept");
    assert_eq!(same_clear.to_bits(), clear.to_bits());
    assert_eq!(same.len(), all.len());
    for (a, b) in same.iter().zip(&all) {
        assert_eq!(a.key(), b.key());
        assert_eq!(a.dist.to_bits(), b.dist.to_bits());
        assert_eq!(a.normal, b.normal);
        assert_eq!(a.point_robot, b.point_robot);
    }
    // Thresholds below, at and above every partial sum: gives up iff the total is above.
    let sum = |ps: &[Pair]| {
        ps.iter()
            .fold(0.25, |v, p| v + (clearance - p.dist).max(0.0))
    };
    let mut partial = vec![0.25];
    for t in &terms {
        partial.push(partial.last().expect("start") + t);
    }
    for &t in partial.iter().chain(&[0.0, total * 2.0]) {
        for t in [t, t * (1.0 - 1e-15), t * (1.0 + 1e-15)] {
            let above = move |ps: &[Pair]| sum(ps) > t;
            let stop = Stop {
                clearance,
                rejects: &above,
            };
            let gave_up = world.pairs_until(&kin, &hints, Some(stop)).is_none();
            // A threshold below the cables' part alone is not seen before a pair violates.
            let expect = total > t && terms.iter().any(|&x| x > 0.0);
            assert_eq!(gave_up, expect, "threshold {t}, total {total}");
        }
    }
}

/// The analytic `∂d/∂ξ` of every pair matches central differences of parry's distance on
/// a bent, twisted, stretched state next to a box, a sphere and a capsule.
#[test]
fn distance_gradients_match_finite_differences() {
    let model = case2_beside(Third::Capsule);
    let m = 2;
    let ell = sub_arc_lengths(&model.robot, m);
    let nsub = ell.len();
    let world = world(&model, m);
    let xi = bent_state(4 * nsub);
    let (pairs, _) = world.pairs(&kinematics(&xi, &ell, true));
    let kinds: Vec<Feat> = pairs.iter().map(|p| p.feat).collect();
    assert!(kinds.iter().any(|f| matches!(f, Feat::Backbone(_))));
    assert!(kinds.iter().any(|f| matches!(f, Feat::Disk(_))));
    assert!(kinds.iter().any(|f| matches!(f, Feat::Cable(..))));
    let dist_at = |x: &[f64], key: PairKey| -> f64 {
        super::super::test_fixture::pair_dist(&world, &kinematics(x, &ell, false), key)
    };
    let h = 1e-4;
    let mut checked = 0;
    for p in &pairs {
        // Skip pairs whose witness sits on an edge/vertex switch (nonsmooth distance).
        for i in (0..4 * nsub).step_by(3) {
            let (mut xp, mut xm) = (xi.clone(), xi.clone());
            // Steps that move the points by ~1e-8 m, far above GJK's noise.
            let hi = if i % 4 == 3 { 1e-5 } else { h };
            xp[i] += hi;
            xm[i] -= hi;
            let fd = (dist_at(&xp, p.key()) - dist_at(&xm, p.key())) / (2.0 * hi);
            let scale = p.grad.iter().fold(0.0f64, |m, g| m.max(g.abs()));
            // The polished normals are good to ~1e-5 where the alternating projections
            // converge slowly (a segment nearly parallel to a capsule); GJK alone: ~5e-5 (the
            // distance itself is stationary in the normal, so the differences are better):
            // an error of that size times the pair's largest lever.
            assert!(
                (fd - p.grad[i]).abs() <= 2e-5 * scale,
                "{:?} vs {} at {:e} m: ∂d/∂ξ[{i}] analytic {} fd {}",
                p.feat,
                p.obstacle,
                p.dist,
                p.grad[i],
                fd
            );
            checked += 1;
        }
    }
    assert!(checked > 100, "{checked}");
}
