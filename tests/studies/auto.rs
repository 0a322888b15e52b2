//! `ccrkit study auto`'s promise on seeded random robots: answers within their tolerance of
//! the converged rod, estimates that bound the true error, and most answers in one solve. Its
//! cost in time (median within 1.5× the cheapest rung that met the tolerance in hindsight) is
//! shown by the study command's own timing (`ccrkit study auto`, the methods chapter of the
//! guide), never by a timed test.

use ccrkit::study::{auto_study, summarize, AutoStudyOptions};

/// On 60 robots not tuned on (the guide's numbers are 200 robots): true error ≤ T in ≥ 99 %,
/// estimate ≥ error in ≥ 95 %; and most answers take one solve (the a-priori estimate: no
/// extra solve), a count that machine load cannot blur.
#[test]
fn auto_keeps_its_tolerance_and_mostly_needs_one_solve() {
    let opts = AutoStudyOptions {
        robots: 60,
        first_seed: 3000,
        repeats: 3,
        ..AutoStudyOptions::default()
    };
    let rows = auto_study(&opts).expect("study runs");
    for s in summarize(&rows) {
        println!("{s:?}");
        assert!(s.answers >= 55, "{s:?}");
        assert!(s.within >= 0.99, "{s:?}");
        assert!(s.bounded >= 0.95, "{s:?}");
    }
    let at_1mm: Vec<_> = rows.iter().filter(|r| r.tolerance == 1e-3).collect();
    let one_solve = at_1mm.iter().filter(|r| r.solves == 1).count();
    assert!(
        2 * one_solve > at_1mm.len(),
        "{one_solve} of {} answers in one solve",
        at_1mm.len()
    );
}
