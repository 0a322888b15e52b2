//! The error estimate ([`ccrkit::method::estimate`]) against the truth: the orders it assumes,
//! measured on robots, and how often its bound holds against the converged rod on seeded
//! random robots ([`ccrkit::study::random`]).

mod a_priori;
mod calibration;
mod on_solve;
mod orders;

/// The command line prints the estimate and writes it into the JSON.
#[test]
fn solve_estimate_prints_and_writes_the_bound() {
    let dir = std::env::temp_dir().join(format!("ccrkit-estimate-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("scratch dir");
    let json = dir.join("case2.json");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_ccrkit"))
        .args(["solve", "models/paper/case2.toml", "--estimate", "--json"])
        .arg(&json)
        .output()
        .expect("runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("error   ≤ "), "{text}");
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).expect("json")).expect("parses");
    let e = &v["report"]["error_estimate"];
    let bound = e["bound_m"].as_f64().expect("a bound");
    let parts =
        e["discretization_m"].as_f64().expect("disc") + e["model_m"].as_f64().expect("model");
    assert!((bound - parts).abs() <= 1e-15 && bound > 0.0, "{e}");
    assert_eq!(e["against"], "the answer's own strains");
    assert!(e.get("fallback").is_none(), "{e}");
}
