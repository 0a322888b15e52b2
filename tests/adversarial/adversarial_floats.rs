//! Every number flag of the command line at huge, tiny and non-finite values: refused by name
//! beyond its documented range (`docs/guide/errors.md`), or answered with every number
//! printed as a number — never `inf`, `NaN`, `0.0000 mm` for a tolerance that is not zero, or a
//! value of three hundred digits, on standard output or in the error.

use crate::common::adversarial_harness::{args, scratch};
use crate::common::cli::{ccrkit_in, paper_path};

/// A `NaN` or `inf` token, or a run of 40 digits (a huge number printed whole), in `text`.
fn unprintable(text: &str) -> Option<String> {
    let token = text
        .split(|c: char| !c.is_ascii_alphanumeric())
        .find(|t| matches!(*t, "NaN" | "nan" | "inf" | "Inf" | "infinity"));
    if let Some(t) = token {
        return Some(t.to_string());
    }
    text.split(|c: char| !c.is_ascii_digit())
        .find(|d| d.len() >= 40)
        .map(|d| format!("{}… ({} digits)", &d[..12], d.len()))
}

/// `ccrkit ARGS` ends with exit 1 and an error naming `field`, printing only numbers (or the
/// `NaN` it was given, quoted back).
fn refused(dir: &std::path::Path, a: &[&str], field: &str) {
    let out = ccrkit_in(dir, &args(a));
    let err = String::from_utf8_lossy(&out.stderr);
    let given_nan = a.iter().any(|x| x.ends_with("NaN"));
    let text = format!("{}{err}", String::from_utf8_lossy(&out.stdout));
    let text = if given_nan {
        text.replace("NaN", "")
    } else {
        text
    };
    assert_eq!(out.status.code(), Some(1), "{a:?} was not refused:\n{text}");
    assert!(
        err.contains(&format!("`{field}`")),
        "{a:?}: the error does not name `{field}`: {err}"
    );
    assert!(
        unprintable(&text).is_none(),
        "{a:?} printed {:?}:\n{text}",
        unprintable(&text)
    );
}

/// `ccrkit ARGS` succeeds, printing only numbers; its standard output.
fn answered(dir: &std::path::Path, a: &[&str]) -> String {
    let out = ccrkit_in(dir, &args(a));
    let stdout = String::from_utf8_lossy(&out.stdout).to_string();
    let text = format!("{stdout}{}", String::from_utf8_lossy(&out.stderr));
    assert!(out.status.success(), "{a:?} failed:\n{text}");
    assert!(
        unprintable(&text).is_none(),
        "{a:?} printed {:?}:\n{text}",
        unprintable(&text)
    );
    stdout
}

/// The tolerances and margins (`solve --method auto --tolerance 1e308` printed `tolerance inf
/// mm`, `compare --tolerance 1e308` `beyond inf mm`, `study auto --tolerance 1e-300` `0.0000 mm`
/// and `NaN×`), targets (`reach --tip 1e308,0,0.17` printed the target in 309 digits and its
/// distance as `inf m`) and margins (`--margin 1e308` searched, then said unreachable).
#[test]
fn tolerances_targets_and_margins_beyond_their_range_are_refused_by_name() {
    let dir = scratch("floats");
    let case3 = paper_path(3);
    let m = case3.as_str();
    for t in ["1e308", "1e-300", "1e3"] {
        refused(
            &dir,
            &["solve", m, "--method", "auto", "--tolerance", t],
            "tolerance",
        );
        refused(&dir, &["compare", m, "--tolerance", t], "tolerance");
        refused(
            &dir,
            &["reach", m, "--tip", "0.01,0.03,0.17", "--tolerance", t],
            "tolerance",
        );
        let out = dir.join("auto-study").display().to_string();
        refused(
            &dir,
            &[
                "study",
                "auto",
                "--robots",
                "1",
                "--tolerance",
                t,
                "--out",
                &out,
            ],
            "tolerances",
        );
    }
    refused(&dir, &["reach", m, "--tip", "1e308,0,0.17"], "tip[0]");
    refused(&dir, &["plan", m, "--to-tip", "0,-1e5,0.17"], "tip[1]");
    for margin in ["1e308", "2", "NaN"] {
        let flag = format!("--margin={margin}");
        refused(
            &dir,
            &["reach", m, "--tip", "0.01,0.03,0.17", &flag],
            "margin",
        );
        refused(
            &dir,
            &["plan", m, "--to-tip", "0.01,0.03,0.17", &flag],
            "margin",
        );
        let out = dir.join("rm.json").display().to_string();
        refused(
            &dir,
            &[
                "roadmap",
                "build",
                m,
                "--samples",
                "4",
                "--out",
                &out,
                &flag,
            ],
            "margin",
        );
    }
}

/// The smallest tolerance accepted prints as what it is, not `0.0000 mm`.
#[test]
fn a_picometre_tolerance_prints_as_one() {
    let dir = scratch("floats-small");
    let case3 = paper_path(3);
    let out = answered(
        &dir,
        &["solve", &case3, "--method", "auto", "--tolerance", "1e-12"],
    );
    assert!(out.contains("for tolerance 1.000e-9 mm (NOT met)"), "{out}");
    let out = answered(&dir, &["compare", &case3, "--tolerance", "1e-12"]);
    assert!(out.contains("beyond 1.000e-9 mm at the tip"), "{out}");
}

/// `anatomy airway --cell`: a grid coarser than the narrowest branch wrote a 24-triangle box
/// as the airway; a cell of `1e-300` printed 300 digits and `inf` grid points.
#[test]
fn an_airway_cell_beyond_its_range_is_refused_by_name() {
    let dir = scratch("floats-airway");
    let out = dir.join("a.stl").display().to_string();
    for cell in ["1", "1e300", "1e-300", "NaN", "0"] {
        refused(
            &dir,
            &["anatomy", "airway", "--out", &out, "--cell", cell],
            "cell",
        );
    }
    assert!(!dir.join("a.stl").exists(), "a refused airway was written");
}
