//! Every setting's printed range is what its parser enforces. The walk reads each range from
//! its *printed* text (what `ccrkit methods` shows), independently of the typed `Range` it
//! comes from, and checks through `MethodKind::build` (the one path every command takes):
//! the default parses, the boundary values are accepted, one beyond each boundary is refused
//! with the setting named, and every listed word is taken.

use ccrkit::method::{MethodKind, Settings};
use ccrkit::SolveError;

/// Build `k` with `name = value`; `Ok(())` or the error.
fn build(k: MethodKind, name: &str, value: &str) -> Result<(), SolveError> {
    k.build(&Settings::new().with(name, value)).map(|_| ())
}

fn accepted(k: MethodKind, name: &str, value: &str) {
    if let Err(e) = build(k, name, value) {
        panic!("{k} {name}={value} refused: {e}");
    }
}

/// Refused as `InvalidInput` naming `name`; returns the reason.
fn refused(k: MethodKind, name: &str, value: &str) -> String {
    match build(k, name, value) {
        Err(SolveError::InvalidInput { field, reason }) => {
            assert_eq!(field, name, "{k} {name}={value}: {reason}");
            reason
        }
        Ok(()) => panic!("{k} {name}={value} accepted"),
        Err(e) => panic!("{k} {name}={value}: wrong error {e:?}"),
    }
}

/// A whole-number range printed `a..=b` (then an optional `(note)`).
fn walk_count(k: MethodKind, name: &str, text: &str) {
    let range = text.split(" (").next().unwrap_or(text);
    let (a, b) = range.split_once("..=").expect("a..=b");
    let (a, b): (u64, u64) = (a.parse().expect("min"), b.parse().expect("max"));
    accepted(k, name, &a.to_string());
    accepted(k, name, &b.to_string());
    let r = refused(k, name, &(b + 1).to_string());
    assert!(r.contains(&format!("from {a} to {b}")), "{r}");
    if a > 0 {
        refused(k, name, &(a - 1).to_string());
    }
    for bad in ["1.5", "-1", "x", ""] {
        refused(k, name, bad);
    }
}

/// A number range printed `(lo, hi]`, then ` | word` for each word that turns it off.
fn walk_number(k: MethodKind, name: &str, text: &str) {
    let mut parts = text.split(" | ");
    let range = parts.next().expect("range");
    let inner = range
        .strip_prefix('(')
        .and_then(|r| r.strip_suffix(']'))
        .expect("(lo, hi]");
    let (lo, hi) = inner.split_once(", ").expect("lo, hi");
    let (lo, hi): (f64, f64) = (lo.parse().expect("lo"), hi.parse().expect("hi"));
    assert!(lo < hi && hi.is_finite(), "{k} {name}: {text}");
    accepted(k, name, &format!("{hi:e}"));
    accepted(k, name, &format!("{:e}", lo.next_up()));
    accepted(k, name, &format!("{:e}", 0.5 * (lo + hi)));
    refused(k, name, &format!("{lo:e}"));
    refused(k, name, &format!("{:e}", hi.next_up()));
    refused(k, name, &format!("{:e}", lo.next_down()));
    for bad in ["nan", "NaN", "-inf", "x", ""] {
        refused(k, name, bad);
    }
    let words: Vec<&str> = parts.collect();
    for w in &words {
        accepted(k, name, w);
    }
    if !words.contains(&"inf") {
        refused(k, name, "inf");
    }
}

/// A choice printed `a | b`: every word taken (any case), another word refused naming them.
fn walk_choice(k: MethodKind, name: &str, text: &str) {
    let words: Vec<&str> = text.split(" | ").collect();
    assert!(words.len() >= 2, "{k} {name}: {text}");
    for w in &words {
        accepted(k, name, w);
        accepted(k, name, &w.to_ascii_uppercase());
    }
    let r = refused(k, name, "no-such-word");
    for w in &words {
        assert!(r.contains(w), "{k} {name}: `{r}` does not list {w}");
    }
}

#[test]
fn every_printed_range_is_what_its_parser_enforces() {
    let mut walked = 0;
    for k in MethodKind::ALL {
        for s in k.info().settings {
            accepted(k, s.name, s.default);
            let text = s.values.to_string();
            if text.contains("..=") {
                walk_count(k, s.name, &text);
            } else if text.starts_with('(') {
                walk_number(k, s.name, &text);
            } else {
                walk_choice(k, s.name, &text);
            }
            walked += 1;
        }
    }
    // 3 geometric settings twice, 11 energy, 10 for each rod, 1 constant-curvature.
    assert_eq!(walked, 3 + 3 + 11 + 10 + 10 + 1);
}

/// The printed ranges, pinned: the text `ccrkit methods` and Python's `methods()` show.
#[test]
fn printed_ranges_read_as_before() {
    let text = |k: MethodKind, name: &str| {
        k.setting(name)
            .unwrap_or_else(|e| panic!("{k} {name}: {e}"))
            .values
            .to_string()
    };
    let e = MethodKind::Energy;
    assert_eq!(
        text(e, "sub-arcs"),
        "1..=64 (≤ 4 with length = chord; or one per section, base first: 1,2,4)"
    );
    assert_eq!(text(e, "tolerance"), "(0, 1]");
    assert_eq!(text(e, "max-iterations"), "1..=100000");
    assert_eq!(text(e, "control"), "force | displacement");
    assert_eq!(text(e, "contact-sensitivity"), "on | off");
    assert_eq!(text(MethodKind::Geometric, "zero-angle"), "(0, 1e-3]");
    let c = MethodKind::Cosserat;
    assert_eq!(text(c, "adaptive"), "(1e-14, 1] | off | none");
    assert_eq!(text(c, "bend-refine"), "(0, 1e6] | inf | off");
    assert_eq!(text(c, "stability"), "check | skip");
    assert_eq!(text(c, "routing"), "spline | fourier8");
}

/// The aliases a choice takes beside its printed words, and the note of `sub-arcs` (a limit
/// the energy model checks against `length`).
#[test]
fn aliases_and_the_sub_arcs_note_hold() {
    for k in [MethodKind::Energy, MethodKind::Cosserat] {
        accepted(k, "control", "tension");
        accepted(k, "control", "shortening");
        let r = refused(k, "control", "sideways");
        assert!(
            r.contains("one of: force, tension, displacement, shortening"),
            "{r}"
        );
    }
    let chord = Settings::new()
        .with("length", "chord")
        .with("sub-arcs", "5");
    let model = ccrkit::Model::from_file("models/paper/case1.toml").expect("case I");
    let req = ccrkit::method::run::SolveRequest::new(MethodKind::Energy).with_settings(chord);
    match req.run(&model) {
        // Named as `--set` spells it (it said `sub_arcs`, the Rust field, until 2026-11-27).
        Err(SolveError::InvalidInput { field, .. }) => assert_eq!(field, "sub-arcs"),
        other => panic!("5 chord sub-arcs: {:?}", other.map(|_| ())),
    }
}

/// A method that reads a setting as another kind than the registry lists gets a named error,
/// not a panic (a bug in ccrkit caught by the walk above, never a silently ignored value).
#[test]
fn a_range_read_as_another_kind_is_a_named_error() {
    use ccrkit::method::settings::Range;
    let named = |r: Result<(), SolveError>| match r {
        Err(SolveError::InvalidInput { field, reason }) => {
            assert_eq!(field, "x");
            assert!(reason.contains("a bug in ccrkit"), "{reason}");
        }
        other => panic!("{other:?}"),
    };
    named(Range::whole(1, 2).real("x", "1").map(|_| ()));
    named(Range::interval(0.0, 1.0).count("x", "1").map(|_| ()));
    named(Range::whole(1, 2).pick("x", "1", [1]).map(|_| ()));
    // A choice with more values than the method supplies.
    named(
        Range::Choice(&[("a", 0), ("b", 1)])
            .pick("x", "a", [1])
            .map(|_| ()),
    );
    // An off word where the method takes no off.
    named(
        Range::Number {
            lo: 0.0,
            hi: 1.0,
            off: &["off"],
        }
        .real("x", "off")
        .map(|_| ()),
    );
    named(Err(MethodKind::Energy.unapplied("x")));
}
