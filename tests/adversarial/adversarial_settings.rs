//! Adversarial settings, read from the registry so that a setting added later is covered
//! without editing this file: every setting of every method at each end of its range (a
//! count's smallest and largest, a number's largest and the smallest above its excluded
//! bound, every word), alone and with every count at its largest at once; each solve of the
//! built binary on paper case I (with the wall for the methods that keep clear of obstacles)
//! under a wall-time budget, judged by `adversarial_harness` (no panic, no hang, no exit 0
//! with a non-finite number, every failure named).

use crate::common::adversarial_harness::{root, run_all, scratch};
use ccrkit::method::settings::Range;
use ccrkit::method::MethodKind;
use std::time::Duration;

const BUDGET: Duration = Duration::from_secs(30);

/// The values at the ends of a range.
fn ends(r: &Range) -> Vec<String> {
    match *r {
        Range::Count { min, max, .. } => vec![min.to_string(), max.to_string()],
        Range::Number { lo, hi, off } => {
            let mut v = vec![format!("{hi:e}"), format!("{:e}", lo.next_up())];
            v.extend(off.iter().map(|w| w.to_string()));
            v
        }
        Range::Choice(words) => words.iter().map(|(w, _)| w.to_string()).collect(),
    }
}

#[test]
fn every_setting_at_the_ends_of_its_range_ends_named_and_bounded() {
    let dir = scratch("settings");
    let case1 = root().join("models/paper/case1.toml").display().to_string();
    let wall = root().join("models/scenes/wall.toml").display().to_string();
    let mut jobs = vec![];
    for k in MethodKind::ALL {
        let base = |sets: &[(String, String)]| {
            let mut a = vec!["solve".to_string(), case1.clone()];
            a.extend(["--method".into(), k.name().into()]);
            if k.info().obstacles {
                a.extend(["--scene".into(), wall.clone()]);
            }
            for (n, v) in sets {
                a.extend(["--set".into(), format!("{n}={v}")]);
            }
            (a, None)
        };
        let mut largest = vec![];
        for s in k.info().settings {
            for v in ends(&s.values) {
                jobs.push(base(&[(s.name.to_string(), v)]));
            }
            if let Range::Count { max, .. } = s.values {
                largest.push((s.name.to_string(), max.to_string()));
            }
        }
        if !largest.is_empty() {
            jobs.push(base(&largest));
        }
    }
    assert!(jobs.len() > 80, "{} runs", jobs.len());
    let t = run_all(&dir, jobs, BUDGET);
    t.report_and_assert("settings at the ends of their ranges");
}
