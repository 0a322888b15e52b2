//! The method registry: every registered method builds, honours or refuses each setting by
//! name, parses its own name back, and solves (or refuses by name) a paper case through the
//! one solve path. A method added to the registry is covered here without editing this file.

use ccrkit::method::run::SolveRequest;
use ccrkit::method::{MethodKind, Settings, METHOD_NAMES};
use ccrkit::{Model, SolveError};

fn case(n: usize) -> Model {
    Model::from_file(format!("models/paper/case{n}.toml")).expect("paper case")
}

#[test]
fn names_parse_back_and_are_unique() {
    assert_eq!(METHOD_NAMES.len(), MethodKind::ALL.len());
    for (k, name) in MethodKind::ALL.iter().zip(METHOD_NAMES) {
        assert_eq!(k.name(), *name);
        assert_eq!(name.parse::<MethodKind>().expect("parses"), *k);
        assert_eq!(k.info().kind, *k);
    }
    let mut names = METHOD_NAMES.to_vec();
    names.sort_unstable();
    names.dedup();
    assert_eq!(names.len(), METHOD_NAMES.len());
    match "no-such-method".parse::<MethodKind>() {
        Err(SolveError::InvalidInput { field, reason }) => {
            assert_eq!(field, "method");
            assert!(reason.contains("energy"), "{reason}");
        }
        other => panic!("expected InvalidInput, got {other:?}"),
    }
}

#[test]
fn every_setting_is_taken_by_its_methods_and_refused_by_the_others() {
    for k in MethodKind::ALL {
        let m = k.build(&Settings::new()).expect("defaults build");
        assert_eq!(m.kind(), k);
        for s in k.info().settings {
            // The documented default is accepted ("off" for optional ones).
            k.build(&Settings::new().with(s.name, s.default))
                .unwrap_or_else(|e| panic!("{k} {}={}: {e}", s.name, s.default));
            // Every other method that does not list it refuses it, naming the takers.
            for other in MethodKind::ALL {
                if other.info().settings.iter().any(|o| o.name == s.name) {
                    continue;
                }
                match other.build(&Settings::new().with(s.name, s.default)) {
                    Err(SolveError::InvalidInput { field, reason }) => {
                        assert_eq!(field, s.name);
                        assert!(reason.contains(k.name()), "{reason}");
                    }
                    Ok(_) => panic!("{other} accepted {}", s.name),
                    Err(e) => panic!("{other} {}: wrong error {e:?}", s.name),
                }
            }
        }
        assert!(k
            .build(&Settings::new().with("no-such-setting", "1"))
            .is_err());
    }
}

#[test]
fn resolution_ladders_build() {
    for k in MethodKind::ALL {
        assert!(!k.info().resolutions.is_empty(), "{k}");
        for (label, pairs) in k.info().resolutions {
            let mut s = Settings::new();
            for (n, v) in *pairs {
                s.push(*n, *v);
            }
            k.build(&s).unwrap_or_else(|e| panic!("{k} {label}: {e}"));
        }
    }
}

#[test]
fn every_method_solves_or_refuses_by_name_through_the_one_path() {
    let model = case(1);
    for k in MethodKind::ALL {
        match SolveRequest::new(k).run(&model) {
            Ok(s) => {
                assert_eq!(s.shape.method, k.name());
                assert!(s.shape.report.converged);
                assert!(s.shape.tip().iter().all(|x| x.is_finite()));
            }
            Err(e) => panic!("{k} on paper case I: {e}"),
        }
    }
}

#[test]
fn bad_numbers_in_settings_are_refused_before_solving() {
    let cases = [
        (MethodKind::Cosserat, "rk4-steps", "4000000000"),
        (MethodKind::Cosserat, "rk4-steps", "0"),
        (MethodKind::Cosserat, "adaptive", "nan"),
        (MethodKind::Energy, "sub-arcs", "-1"),
        (MethodKind::Energy, "tolerance", "inf"),
        (MethodKind::Energy, "control", "sideways"),
        (
            MethodKind::Geometric,
            "max-iterations",
            "18446744073709551615",
        ),
    ];
    for (k, name, value) in cases {
        match k.build(&Settings::new().with(name, value)) {
            Err(SolveError::InvalidInput { field, .. }) => assert_eq!(field, name),
            other => panic!(
                "{k} {name}={value}: {:?}",
                other.map(|m| m.name().to_string())
            ),
        }
    }
}
