//! Planning in a generated airway, on a small count (`examples/common/airway_tasks.rs`; more
//! airways and targets: `cargo run --release --example airway_benchmark`): the 3 mm
//! two-segment catheter through a port in the lower trachea, targets beyond the trachea
//! labelled reachable by a clear forward solve; each reached (forward-checked to 1e-6 m) and
//! its actuation planned to cold from the retracted catheter; every answer and waypoint
//! checked by the independent dense check against the exact triangles.

#[path = "../../examples/common/airway_tasks.rs"]
pub(crate) mod airway_tasks;

use airway_tasks::{measure, GENERATIONS};

/// In the airway of seed 31 (not tuned on), 3 reachable targets: every one reached and
/// planned to (measured: 3 of 3 each), every answer and waypoint inside the lumen by the
/// dense check, failures named.
#[test]
fn a_catheter_reaches_and_plans_in_a_generated_airway() {
    let dir = std::env::temp_dir().join(format!("ccrkit-airway-plan-{}", std::process::id()));
    let out = measure(31, GENERATIONS, 3, 1, &dir).expect("the airway and the catheter load");
    std::fs::remove_dir_all(&dir).ok();
    assert_eq!(out.len(), 3, "3 reachable targets drawn");
    for o in &out {
        assert!(o.generation >= 1);
        if o.reached {
            assert!(o.reach_dense >= 0.0);
        }
        if o.planned {
            assert!(o.plan_dense >= 0.0 && o.waypoints >= 2);
        }
        if !(o.reached && o.planned) {
            assert!(!o.reason.is_empty(), "a failure names its reason");
        }
    }
    let reached = out.iter().filter(|o| o.reached).count();
    let planned = out.iter().filter(|o| o.planned).count();
    assert!(reached >= 3, "reached {reached} of 3: {out:?}");
    assert!(planned >= 3, "planned {planned} of 3: {out:?}");
}
