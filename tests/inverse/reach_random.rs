//! The reach measurement on seeded random robots with a port, on a small count
//! (`examples/common/reach_measure.rs`; the timing on more robots:
//! `cargo run --release --example reach_random_ports`): 2–6 cables, straight and helical,
//! tied at the tip or at inner disks, targets made by shortenings or by tensions at a random
//! insertion and rotation. Every target is reachable by construction; a reach counts when it
//! says reached and its answer, solved forward, puts the tip within 1e-6 m of the target.

#[path = "../../examples/common/reach_measure.rs"]
pub(crate) mod reach_measure;

/// At least 59 of the first 60 admissible robots are reached (measured: 60 of 60; on seeds
/// 1001–1200 198 of 200, on 2001–2200 199 of 200: `examples/reach_random_ports.rs`), both
/// kinds of target among them, and every miss ends with the closest answer, its distance and
/// its reason.
#[test]
fn random_robots_through_a_port_are_reached() {
    let mut out = Vec::new();
    let mut seed = 0;
    while out.len() < 60 {
        seed += 1;
        out.extend(reach_measure::measure(seed));
    }
    let ok = out.iter().filter(|o| o.ok).count();
    let tension = out.iter().filter(|o| o.tension_driven).count();
    assert!(
        (10..=50).contains(&tension),
        "{tension} tension-made targets of 60"
    );
    assert!(out.iter().any(|o| o.cables == 2) && out.iter().any(|o| o.cables >= 5));
    for o in &out {
        assert!(o.seconds > 0.0);
        assert!(
            !o.ok || o.solves > 0,
            "robot {}: reached without a solve",
            o.seed
        );
        if !o.ok {
            // A miss still ends with the closest answer, its distance and a reason.
            assert!(
                o.distance.is_finite() && !o.reason.is_empty(),
                "robot {}",
                o.seed
            );
        }
    }
    assert!(ok >= 59, "reached {ok} of 60");
}
