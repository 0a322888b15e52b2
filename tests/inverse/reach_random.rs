//! The reach measurement on seeded random robots with a port, on a small count
//! (`examples/common/reach_measure.rs`; the timing on more robots:
//! `cargo run --release --example reach_random_ports`): 2–6 cables, straight and helical,
//! tied at the tip or at inner disks, targets made by shortenings or by tensions at a random
//! insertion and rotation. Every target is reachable by construction; a reach counts when it
//! says reached and its answer, solved forward, puts the tip within 1e-6 m of the target.

#[path = "../../examples/common/reach_measure.rs"]
pub(crate) mod reach_measure;

/// At least 29 of the first 30 admissible robots are reached (measured: 30 of 30; 39 of the
/// first 40), both kinds of target among them, and every miss ends with the closest answer,
/// its distance and its reason.
#[test]
fn random_robots_through_a_port_are_reached() {
    let mut out = Vec::new();
    let mut seed = 0;
    while out.len() < 30 {
        seed += 1;
        out.extend(reach_measure::measure(seed));
    }
    let ok = out.iter().filter(|o| o.ok).count();
    let tension = out.iter().filter(|o| o.tension_driven).count();
    assert!(
        (5..=25).contains(&tension),
        "{tension} tension-made targets of 30"
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
    assert!(ok >= 29, "reached {ok} of 30");
}
