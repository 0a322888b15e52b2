//! `auto` ([`ccrkit::method::auto`]): its answers keep their tolerance against the converged
//! rod on seeded random robots, say what they chose, and requests that solve many actuations
//! settle the choice first.

use ccrkit::prelude::*;
use ccrkit::study::random::random_model;

fn truth(model: &Model) -> Option<ccrkit::Shape> {
    SolveRequest::new(MethodKind::Cosserat)
        .with_settings(
            Settings::new()
                .with("control", "displacement")
                .with("rk4-steps", 80)
                .with("tolerance", 1e-11),
        )
        .run(model)
        .ok()
        .map(|s| s.shape)
}

#[test]
fn answers_are_within_their_tolerance_of_the_converged_rod() {
    let mut checked = 0;
    for seed in 100..130 {
        let model = random_model(seed).expect("valid by construction");
        let Some(truth) = truth(&model) else { continue };
        for t in [1e-4, 1e-3] {
            let s = SolveRequest::auto(t)
                .run(&model)
                .expect("auto answers")
                .shape;
            let a = s.report.auto.as_ref().expect("auto's report");
            assert!(a.met, "seed {seed}: {a:?}");
            assert_eq!(a.method, s.method);
            let err = s.tip_distance(&truth);
            assert!(err <= t, "seed {seed} T {t}: error {err:e} with {a:?}");
            let e = s.report.error_estimate.as_ref().expect("estimate");
            assert!(e.known_parts_m() <= t);
            checked += 1;
        }
    }
    assert!(checked >= 50, "{checked}");
}

#[test]
fn a_tighter_tolerance_never_chooses_a_less_accurate_answer() {
    let model = Model::from_file("models/paper/case3.toml").expect("case III");
    let truth = truth(&model).expect("reference");
    let mut last = f64::INFINITY;
    for t in [1e-3, 1e-4, 1e-5, 1e-6] {
        let s = SolveRequest::auto(t).run(&model).expect("auto").shape;
        let err = s.tip_distance(&truth);
        assert!(err <= t, "T {t}: {err:e}");
        assert!(err <= last * 1.5 + 1e-9, "T {t}: {err:e} after {last:e}");
        last = err;
    }
}

#[test]
fn many_solve_requests_settle_the_choice_first() {
    let model = Model::from_file("models/paper/case1.toml").expect("case I");
    let auto = SolveRequest::auto(1e-4);
    let e = auto.solver().expect_err("auto has no one solver");
    assert!(e.to_string().contains("resolved"), "{e}");
    let settled = auto.resolved(&model).expect("settles");
    assert!(settled.auto.is_none());
    let chosen = auto.run(&model).expect("auto").shape;
    let again = settled.run(&model).expect("settled").shape;
    assert_eq!(chosen.method, again.method);
    assert!(chosen.tip_distance(&again) < 1e-9);
    let bad = SolveRequest::auto(-1.0)
        .run(&model)
        .expect_err("negative tolerance");
    assert!(bad.to_string().contains("tolerance"), "{bad}");
}

#[test]
fn the_command_line_chooses_and_says_so() {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_ccrkit"))
        .args([
            "solve",
            "models/paper/case2.toml",
            "--method",
            "auto",
            "--tolerance",
            "1e-4",
        ])
        .output()
        .expect("runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("auto    energy sub-arcs="), "{text}");
    assert!(text.contains("for tolerance 0.1000 mm"), "{text}");
    let refused = std::process::Command::new(env!("CARGO_BIN_EXE_ccrkit"))
        .args(["solve", "models/paper/case2.toml", "--tolerance", "1e-4"])
        .output()
        .expect("runs");
    assert!(!refused.status.success());
    assert!(String::from_utf8_lossy(&refused.stderr).contains("--method auto"));
}
