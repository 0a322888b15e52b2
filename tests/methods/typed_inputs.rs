//! Robots and method settings written in code are held to the rules a model file and
//! `--set` are held to: a robot built or edited by hand breaking a rule, or a typed setting
//! out of its registry range, is refused by field before any work — through the one way in
//! (`SolveRequest` → `Solver`) and through a method called directly — with the field and the
//! range `--set` and the model file give.

use ccrkit::method::cosserat::Cosserat;
use ccrkit::method::energy::Energy;
use ccrkit::method::geometric::Geometric;
use ccrkit::method::run::SolveRequest;
use ccrkit::method::{Method, MethodKind, Settings};
use ccrkit::prelude::*;
use nalgebra::{Isometry3, Quaternion, Translation3, Unit, UnitQuaternion, Vector3};

/// A rule a robot edit breaks: the field named, and the edit.
type Edit = (&'static str, Box<dyn Fn(&mut Robot)>);
/// A typed setting out of range: the method, its kind, the setting, the same value as text,
/// and the range its message names.
type TypedCase = (
    Box<dyn Method>,
    MethodKind,
    &'static str,
    &'static str,
    &'static str,
);

fn case1() -> Model {
    Model::from_file("models/paper/case1.toml").expect("case 1")
}

fn invalid_field(r: Result<Shape, SolveError>) -> String {
    match r {
        Err(SolveError::InvalidInput { field, .. }) => field,
        Err(other) => panic!("expected an invalid input, got {other}"),
        Ok(_) => panic!("expected an invalid input, got a shape"),
    }
}

/// Each edit breaks one rule of a model file's robot; the solve path names the file's field.
#[test]
fn a_robot_edited_in_code_is_refused_by_the_files_field_on_every_solve_path() {
    let edits: Vec<Edit> = vec![
        ("robot.disk_radius", Box::new(|r| r.disk_radius = -0.012)),
        ("robot.disk_thickness", Box::new(|r| r.disk_thickness = 0.5)),
        (
            "robot.backbone.diameter",
            Box::new(|r| r.backbone.diameter = f64::NAN),
        ),
        (
            "robot.backbone.youngs_modulus",
            Box::new(|r| r.backbone.youngs_modulus = 1e300),
        ),
        (
            "robot.backbone.poisson_ratio",
            Box::new(|r| r.backbone.poisson_ratio = 0.7),
        ),
        (
            "robot.section_lengths[4]",
            Box::new(|r| r.disk_s[5] = r.disk_s[4]),
        ),
        ("robot.sections", Box::new(|r| r.disk_s.truncate(1))),
        (
            "cables[0].radius[3]",
            Box::new(|r| r.cables[0].radius[3] = 0.5),
        ),
        (
            "cables[1].radius[0]",
            Box::new(|r| r.cables[1].radius[0] = 0.001),
        ),
        (
            "cables[1].angles[2]",
            Box::new(|r| r.cables[1].angle[2] = f64::INFINITY),
        ),
        (
            "cables[0].radius",
            Box::new(|r| {
                r.cables[0].radius.pop();
            }),
        ),
        ("cables[1].ends_at", Box::new(|r| r.cables[1].ends_at = 99)),
        (
            "cables[1].name",
            Box::new(|r| r.cables[1].name = r.cables[0].name.clone()),
        ),
        (
            "cables[0].stiffness",
            Box::new(|r| r.cables[0].stiffness = Some(0.0)),
        ),
        (
            "cables[0].pretension",
            Box::new(|r| r.cables[0].pretension = 1.0),
        ),
        (
            "loads.gravity[2]",
            Box::new(|r| r.loads.gravity = Vector3::new(0.0, 0.0, -1e9)),
        ),
        ("loads.disk_mass", Box::new(|r| r.loads.disk_mass = -1.0)),
        (
            "port.orientation",
            Box::new(|r| {
                let q = Unit::new_unchecked(Quaternion::new(2.0, 0.0, 0.0, 0.0));
                r.port = Some(ccrkit::model::port::Port {
                    pose: Isometry3::from_parts(Translation3::identity(), q),
                });
            }),
        ),
        (
            "port.position[0]",
            Box::new(|r| {
                r.port = Some(ccrkit::model::port::Port {
                    pose: Isometry3::from_parts(
                        Translation3::new(1e9, 0.0, 0.0),
                        UnitQuaternion::identity(),
                    ),
                });
            }),
        ),
    ];
    let m = case1();
    assert!(m.robot.check().is_ok());
    for (field, edit) in &edits {
        let mut robot = m.robot.clone();
        edit(&mut robot);
        assert_eq!(robot.check().unwrap_err().field(), Some(*field));
        for kind in MethodKind::ALL {
            let solver = SolveRequest::new(kind).solver().expect("defaults");
            let got = invalid_field(solver.solve(&robot, &m.actuation, &m.scene, None));
            assert_eq!(&got, field, "{kind} solve");
            let got = solver.prepare(&robot).map(|_| ()).unwrap_err();
            assert!(
                matches!(&got, SolveError::InvalidInput { field: f, .. } if f == field),
                "{kind} prepare: {got}"
            );
            let method = kind.build(&Settings::new()).expect("defaults");
            let got = invalid_field(method.solve(&robot, &m.actuation, &m.scene, None));
            assert_eq!(&got, field, "{kind} Method::solve");
        }
    }
}

/// A typed setting out of its registry range is refused by the same field as `--set` of the
/// same value, on the method called directly and on a request; in range, it solves.
#[test]
fn typed_settings_out_of_range_are_refused_like_set() {
    let m = case1();
    let solve = |method: &dyn Method| method.solve(&m.robot, &m.actuation, &m.scene, None);
    let set = |kind: MethodKind, name: &str, value: &str| match kind
        .build(&Settings::new().with(name, value))
    {
        Err(SolveError::InvalidInput { field, reason }) => (field, reason),
        Err(other) => panic!("{other}"),
        Ok(_) => panic!("--set {name}={value} accepted"),
    };
    let cases: Vec<TypedCase> = vec![
        (
            Box::new(Energy::default().with_sub_arcs(65)),
            MethodKind::Energy,
            "sub-arcs",
            "65",
            "1 to 64",
        ),
        (
            Box::new(Energy {
                max_iterations: usize::MAX,
                ..Energy::default()
            }),
            MethodKind::Energy,
            "max-iterations",
            "18446744073709551615",
            "1 to 100000",
        ),
        (
            Box::new(Energy {
                tolerance: f64::NAN,
                ..Energy::default()
            }),
            MethodKind::Energy,
            "tolerance",
            "NaN",
            "(0e0, 1e0]",
        ),
        (
            Box::new(Energy {
                samples_per_sub_arc: 0,
                ..Energy::default()
            }),
            MethodKind::Energy,
            "samples-per-sub-arc",
            "0",
            "1 to 64",
        ),
        (
            Box::new(Cosserat::full().with_steps(5000)),
            MethodKind::Cosserat,
            "rk4-steps",
            "5000",
            "1 to 1000",
        ),
        (
            Box::new(Cosserat::full().with_adaptive(Some(0.0))),
            MethodKind::Cosserat,
            "adaptive",
            "0",
            "(1e-14, 1e0]",
        ),
        (
            Box::new(Cosserat {
                bend_refine: -1.0,
                ..Cosserat::full()
            }),
            MethodKind::Cosserat,
            "bend-refine",
            "-1",
            "(0e0, 1e6]",
        ),
        (
            Box::new(Geometric {
                zero_angle: 0.5,
                ..Geometric::literal()
            }),
            MethodKind::Geometric,
            "zero-angle",
            "0.5",
            "(0e0, 1e-3]",
        ),
    ];
    for (method, kind, name, value, range) in cases {
        let (set_field, set_reason) = set(kind, name, value);
        assert_eq!(set_field, name);
        assert!(set_reason.contains(range), "--set {name}: {set_reason}");
        match solve(&*method) {
            Err(SolveError::InvalidInput { field, reason }) => {
                assert_eq!(field, name);
                assert!(reason.contains(range), "typed {name}: {reason}");
            }
            other => panic!("typed {name} = {value}: {other:?}"),
        }
        assert!(method.prepare(&m.robot).is_err(), "{name}: prepare");
    }
    // The two settings together: sub-arcs ≤ 4 with the chord length, whichever way given.
    let chord = Energy::default()
        .with_cable_length(ccrkit::actuation::LengthMeasure::Chord)
        .with_sub_arcs(6);
    let e = solve(&chord).unwrap_err();
    assert!(
        matches!(&e, SolveError::InvalidInput { field, .. } if field == "sub-arcs"),
        "{e}"
    );
    let named = SolveRequest::new(MethodKind::Energy)
        .with_settings(Settings::new().with("length", "chord").with("sub-arcs", 6))
        .solver()
        .unwrap_err();
    assert_eq!(named, e);
    // In range, typed and named settings give the same shape to the bit.
    let typed = solve(&Energy::default().with_sub_arcs(6)).expect("solves");
    let by_name = SolveRequest::new(MethodKind::Energy)
        .with_settings(Settings::new().with("sub-arcs", 6))
        .run(&m)
        .expect("solves")
        .shape;
    assert_eq!(typed.disks, by_name.disks);
    // Off, where the range has an off word: adaptive none, bend refinement infinite.
    let off = Cosserat {
        bend_refine: f64::INFINITY,
        ..Cosserat::full().with_adaptive(None)
    };
    assert!(solve(&off).is_ok());
}
