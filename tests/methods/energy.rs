//! The whole-robot energy model against independent truths: the closed-form arc of one straight
//! cable (shape, tension from the multiplier, axial strain), cable lengths recomputed
//! independently from the solved strains, the KKT residual, rotational symmetry of the routing,
//! slack / free / inner-disk cables, warm starts, errors, and agreement with the Cosserat rod
//! driven by the same cable lengths.

use crate::common::{arc_point, paper, solve};
use ccrkit::actuation::{Input, LengthMeasure};
use ccrkit::method::cosserat::Cosserat;
use ccrkit::method::energy::Energy;
use ccrkit::method::WarmState;
use ccrkit::routing::Route;
use ccrkit::{Actuation, Method, Model, Robot, Scene, Shape, Shortening, SolveError};
use nalgebra::{Matrix4, Rotation3, Vector3, Vector4};

const E: f64 = 1.1e9;
const D: f64 = 0.003;
const R_HOLE: f64 = 0.008;

/// Closed forms: relative error allowed (round-off and solver tolerance only).
const EXACT_REL: f64 = 1e-9;
/// Cable lengths must meet their targets to this [m].
const LENGTH_TOL: f64 = 1e-9;
/// Agreement with the Cosserat rod under displacement control [m].
const RMS_BOUND: f64 = 0.3e-3;
/// Relative tension agreement with the rod.
const TENSION_REL: f64 = 0.02;
/// Tensions below this are "zero" when comparing relative errors [N].
const TENSION_FLOOR: f64 = 1e-3;

fn ei() -> f64 {
    E * std::f64::consts::PI * D.powi(4) / 64.0
}
fn ea() -> f64 {
    E * std::f64::consts::PI * D * D / 4.0
}

fn model(cables: &str) -> Model {
    model_with_density(cables, 0.0)
}

/// The test robot with a backbone density [kg/m³] (its weight under gravity).
fn model_with_density(cables: &str, density: f64) -> Model {
    let text = format!(
        r#"
name = "test"
[robot]
sections = 9
section_length = 0.020
disk_radius = 0.012
disk_thickness = 0.002
backbone = {{ youngs_modulus = {E}, poisson_ratio = 0.3, diameter = {D}, density = {density} }}
{cables}
"#
    );
    Model::from_toml_str(&text).expect("test model parses")
}

/// The rod under displacement control, tight tolerance, 20 RK4 steps per section.
fn rod(length: LengthMeasure) -> Cosserat {
    Cosserat {
        tolerance: 1e-11,
        ..Cosserat::full()
            .with_control(Input::Shortening)
            .with_length(length)
            .with_steps(20)
    }
}

fn twist(x: &[f64]) -> Matrix4<f64> {
    let (kx, ky, t, e) = (x[0], x[1], x[2], x[3]);
    Matrix4::new(
        0.0,
        -t,
        ky,
        0.0,
        t,
        0.0,
        -kx,
        0.0,
        -ky,
        kx,
        0.0,
        1.0 + e,
        0.0,
        0.0,
        0.0,
        0.0,
    )
}

/// Routed path length of cable `c` recomputed independently of the solver: frames by the
/// matrix exponential of the solved strains, the cable point `p + R r(s)` on a fine polyline,
/// Richardson-extrapolated (error O(h⁴)).
fn independent_path_length(robot: &Robot, sub_arcs: usize, state: &[f64], c: usize) -> f64 {
    let route = Route::new(robot, c, Default::default()).expect("route");
    let polyline = |pieces: usize| -> f64 {
        let mut g: Matrix4<f64> = Matrix4::identity();
        let mut total = 0.0;
        for j in 0..robot.cables[c].ends_at * sub_arcs {
            let sec = j / sub_arcs + 1;
            let ell = robot.section_length(sec) / sub_arcs as f64;
            let s0 = robot.disk_s[sec - 1] + (j % sub_arcs) as f64 * ell;
            let xh = twist(&state[4 * j..4 * j + 4]);
            let point = |sig: f64| -> Vector3<f64> {
                let r = route.eval(s0 + sig, sec - 1).r;
                let e: Matrix4<f64> = (xh * sig).exp();
                let q: Vector4<f64> = g * e * Vector4::new(r.x, r.y, r.z, 1.0);
                Vector3::new(q.x, q.y, q.z)
            };
            let mut prev = point(0.0);
            for k in 1..=pieces {
                let p = point(ell * k as f64 / pieces as f64);
                total += (p - prev).norm();
                prev = p;
            }
            let e: Matrix4<f64> = (xh * ell).exp();
            g *= e;
        }
        total
    };
    let (a, b) = (polyline(100), polyline(200));
    (4.0 * b - a) / 3.0
}

fn chord_length(points: &[Vector3<f64>]) -> f64 {
    points.windows(2).map(|w| (w[1] - w[0]).norm()).sum()
}

/// The energy model's warm state as one vector: strains, then cable multipliers.
fn state(shape: &Shape) -> Vec<f64> {
    match &shape.report.warm {
        Some(WarmState::Energy(e)) => e.strains.iter().chain(&e.multipliers).copied().collect(),
        other => panic!("energy shapes carry their state, got {other:?}"),
    }
}

#[test]
fn one_straight_cable_is_the_closed_form_arc() {
    let delta = 0.004;
    let m = model(&format!(
        "[[cables]]\nname = \"A\"\nradius = {R_HOLE}\nangles = {{ straight = 0.0 }}\nshorten = {delta}"
    ));
    let len = m.robot.length();
    // min ½L(EI κ² + EA ε²) s.t. L(1 + ε − κ r) = L − δ:
    // λ = (δ/L) / (1/EA + r²/EI), κ = λ r / EI, ε = −λ / EA.
    let lam = (delta / len) / (1.0 / ea() + R_HOLE * R_HOLE / ei());
    let kappa = lam * R_HOLE / ei();
    let eps = -lam / ea();
    for length in [LengthMeasure::Path, LengthMeasure::Chord] {
        let e = Energy::default().with_cable_length(length);
        let shape = solve(&e, &m);
        if length == LengthMeasure::Path {
            let t = shape.cables[0].tension.expect("tension");
            assert!((t - lam).abs() <= EXACT_REL * lam, "tension {t} vs {lam}");
            // The multiplier is the tension: EI κ / r and −EA ε.
            let st = state(&shape);
            let nsub = (st.len() - 1) / 4;
            for j in 0..nsub {
                assert!((st[4 * j + 1] - kappa).abs() <= EXACT_REL * kappa);
                assert!((st[4 * j + 3] - eps).abs() <= EXACT_REL * eps.abs());
                assert!(st[4 * j].abs() < 1e-9 && st[4 * j + 2].abs() < 1e-9);
            }
            // Inextensible reading: the hole shortens by r κ L (plus the axial part −ε L).
            assert!((len * (R_HOLE * kappa - eps) - delta).abs() < 1e-15);
            // p' = R (0, 0, 1 + ε), R' = R û per undeformed length: the arc turns by κ s and
            // has radius (1 + ε) / κ.
            for d in &shape.disks {
                let s = d.s;
                let exact = arc_point(kappa, s) * (1.0 + eps);
                assert!(
                    (d.position - exact).norm() <= EXACT_REL * len,
                    "disk at {}: {:?} vs {:?}",
                    d.s,
                    d.position,
                    exact
                );
            }
        } else {
            // A chord cable loads the disks only, so curvature varies inside a section, but
            // every section bends alike (the disks lie on one circle), and the chord lengths
            // meet their target.
            let target = m.robot.undeformed_chord_length(0) - delta;
            assert!((chord_length(&shape.cables[0].points) - target).abs() <= LENGTH_TOL);
            let st = state(&shape);
            let per = 4 * e.sub_arcs;
            for j in per..m.robot.sections() * per {
                assert!((st[j] - st[j % per]).abs() <= 1e-6 * st[1].abs());
            }
        }
    }
}

#[test]
fn cable_lengths_meet_their_targets() {
    for n in 1..=3 {
        let m = paper(n);
        for length in [LengthMeasure::Path, LengthMeasure::Chord] {
            let e = Energy::default().with_cable_length(length);
            let shape = solve(&e, &m);
            assert!(shape.report.converged);
            assert!(
                shape.report.residual <= 1e-10,
                "KKT residual {}",
                shape.report.residual
            );
            for c in 0..m.robot.cables.len() {
                let short = m.actuation.shortening_length(&m.robot, c).expect("driven");
                assert!(!shape.cables[c].slack);
                let got = match length {
                    LengthMeasure::Path => {
                        let l0 = independent_path_length(
                            &m.robot,
                            e.sub_arcs,
                            &vec![0.0; 4 * e.sub_arcs * m.robot.sections()],
                            c,
                        );
                        independent_path_length(&m.robot, e.sub_arcs, &state(&shape), c) - l0
                    }
                    LengthMeasure::Chord => {
                        chord_length(&shape.cables[c].points) - m.robot.undeformed_chord_length(c)
                    }
                };
                assert!(
                    (got + short).abs() <= LENGTH_TOL,
                    "case {n} {length:?} cable {c}: length change {got} vs −{short}"
                );
            }
        }
    }
}

#[test]
fn rotating_the_routing_rotates_the_shape() {
    let m = paper(2);
    let phi = 0.7;
    let mut turned = m.clone();
    for c in &mut turned.robot.cables {
        for a in &mut c.angle {
            *a += phi;
        }
        // The declared rule (closed-form helix route) turns with the holes.
        if let Some(h) = &mut c.helix {
            h.start += phi;
        }
    }
    let rz = Rotation3::from_axis_angle(&Vector3::z_axis(), phi);
    for length in [LengthMeasure::Path, LengthMeasure::Chord] {
        let e = Energy::default().with_cable_length(length);
        let a = solve(&e, &m);
        let b = solve(&e, &turned);
        for (da, db) in a.disks.iter().zip(&b.disks) {
            assert!((rz * da.position - db.position).norm() < 1e-10);
        }
        for (ca, cb) in a.cables.iter().zip(&b.cables) {
            let (ta, tb) = (ca.tension.unwrap_or(0.0), cb.tension.unwrap_or(0.0));
            assert!((ta - tb).abs() < 1e-9 * ta.max(1.0));
        }
    }
}

/// Energy vs rod: RMS over the disks and relative tension errors.
fn agreement(m: &Model, length: LengthMeasure) -> (f64, Vec<f64>) {
    let cos = solve(&rod(length), m);
    let en = solve(&Energy::default().with_cable_length(length), m);
    let rms = en.rms_distance(&cos).expect("same disks");
    let errs = en
        .cables
        .iter()
        .zip(&cos.cables)
        .map(|(a, b)| {
            let (ta, tb) = (a.tension.unwrap_or(0.0), b.tension.unwrap_or(0.0));
            if tb.abs() < TENSION_FLOOR {
                (ta - tb).abs() / TENSION_FLOOR
            } else {
                (ta - tb).abs() / tb.abs()
            }
        })
        .collect();
    (rms, errs)
}

fn assert_agrees(name: &str, m: &Model) {
    let (rms, errs) = agreement(m, LengthMeasure::Path);
    eprintln!("{name}: RMS {:.4} mm, tension errors {:?}", rms * 1e3, errs);
    assert!(rms <= RMS_BOUND, "{name}: RMS {rms}");
    for (c, e) in errs.iter().enumerate() {
        assert!(*e <= TENSION_REL, "{name}: cable {c} tension error {e}");
    }
    // The chord measure, reported only: the rod's "chord" mode loads the rod along the routed
    // path and measures chords, while the energy model's chord cable runs straight between the
    // holes and loads only the disks, so tensions differ by construction (user's guide, methods).
    let (rms, errs) = agreement(m, LengthMeasure::Chord);
    eprintln!(
        "{name} (chord): RMS {:.4} mm, tension errors {:?}",
        rms * 1e3,
        errs
    );
}

#[test]
fn agrees_with_cosserat_on_the_paper_cases() {
    for n in 1..=3 {
        assert_agrees(&format!("paper case {n}"), &paper(n));
    }
}

const THREE: &str = r#"
[[cables]]
name = "A"
radius = 0.008
angles = { helix = { start = 0.0, per_disk = 0.2 } }
shorten_percent = 2.0
[[cables]]
name = "B"
radius = 0.007
angles = { straight = 2.0943951023931953 }
shorten_percent = 1.0
[[cables]]
name = "C"
radius = 0.008
angles = { helix = { start = 4.18879, per_disk = -0.15 } }
shorten_percent = 0.5
"#;

const FOUR: &str = r#"
[[cables]]
name = "A"
radius = 0.008
angles = { helix = { start = 0.0, per_disk = 0.3 } }
shorten_percent = 2.5
[[cables]]
name = "B"
radius = 0.008
angles = { straight = 1.5707963267948966 }
shorten_percent = 1.0
[[cables]]
name = "C"
radius = 0.008
angles = { helix = { start = 3.14159, per_disk = 0.3 } }
shorten_percent = 0.2
[[cables]]
name = "D"
radius = 0.006
angles = { straight = 4.71238898038469 }
shorten_percent = 0.5
"#;

/// A helical cable tied at disk 5, alone.
const INNER_HELIX: &str = r#"
[[cables]]
name = "A"
radius = 0.008
angles = { helix = { start = 0.0, per_disk = 0.25 } }
ends_at = 5
shorten_percent = 3.0
"#;

/// Straight cables tied at disks 5 and 7 with a full-length one.
const INNER_STRAIGHT: &str = r#"
[[cables]]
name = "A"
radius = 0.008
angles = { straight = 0.0 }
ends_at = 5
shorten_percent = 3.0
[[cables]]
name = "B"
radius = 0.008
angles = { straight = 2.5 }
shorten_percent = 2.0
[[cables]]
name = "C"
radius = 0.008
angles = { straight = 4.0 }
ends_at = 7
shorten_percent = 1.0
"#;

/// A helical cable passing a disk where another cable is tied.
const INNER_MIXED: &str = r#"
[[cables]]
name = "A"
radius = 0.008
angles = { helix = { start = 0.0, per_disk = 0.25 } }
shorten_percent = 3.0
[[cables]]
name = "C"
radius = 0.008
angles = { straight = 4.0 }
ends_at = 7
shorten_percent = 1.0
"#;

#[test]
fn agrees_with_cosserat_with_three_and_four_cables() {
    assert_agrees("three cables", &model(THREE));
    assert_agrees("four cables", &model(FOUR));
}

#[test]
fn agrees_with_cosserat_with_cables_tied_at_inner_disks() {
    assert_agrees("helix tied at disk 5", &model(INNER_HELIX));
    assert_agrees(
        "straight cables tied at disks 5 and 7",
        &model(INNER_STRAIGHT),
    );
}

/// Where cable C ends at disk 7 the rod's strain u jumps, so the helical cable A passing
/// through disk 7 kinks there (`w = v + u × r + r'` changes direction when `r' ≠ 0`) and,
/// frictionless, loads the disk with `τ (t⁺ − t⁻)`. The energy model contains that force
/// implicitly (it varies the whole path length); the rod adds it as a point force at the disk
/// (`cosserat.rs` `shoot`). Before the rod had it the two disagreed by 2.4 mm RMS.
#[test]
fn agrees_with_cosserat_with_a_helix_passing_a_termination_disk() {
    assert_agrees("helix passing a termination disk", &model(INNER_MIXED));
}

#[test]
fn paid_out_cable_is_slack_with_zero_tension() {
    let two = model(&format!(
        r#"
[[cables]]
name = "A"
radius = {R_HOLE}
angles = {{ straight = 0.0 }}
shorten_percent = 3.0
[[cables]]
name = "B"
radius = {R_HOLE}
angles = {{ straight = 3.14159 }}
shorten = -0.01
"#
    ));
    let one = model(&format!(
        "[[cables]]\nname = \"A\"\nradius = {R_HOLE}\nangles = {{ straight = 0.0 }}\nshorten_percent = 3.0"
    ));
    for length in [LengthMeasure::Path, LengthMeasure::Chord] {
        let e = Energy::default().with_cable_length(length);
        let s2 = solve(&e, &two);
        let s1 = solve(&e, &one);
        assert_eq!(s2.cables[1].tension, Some(0.0));
        assert!(s2.cables[1].slack && !s2.cables[0].slack);
        assert!(s2.rms_distance(&s1).expect("same disks") < 1e-12);
        if length == LengthMeasure::Chord {
            let allowed = two.robot.undeformed_chord_length(1) + 0.01;
            assert!(chord_length(&s2.cables[1].points) < allowed);
        }
    }
    // The rod agrees, slack included.
    let (rms, errs) = agreement(&two, LengthMeasure::Path);
    assert!(rms <= RMS_BOUND && errs.iter().all(|e| *e <= TENSION_REL));
}

#[test]
fn free_cable_is_reported_and_constrains_nothing() {
    let with_free = model(&format!(
        r#"
[[cables]]
name = "A"
radius = {R_HOLE}
angles = {{ straight = 0.0 }}
shorten_percent = 2.0
[[cables]]
name = "F"
radius = {R_HOLE}
angles = {{ helix = {{ start = 1.0, per_disk = 0.4 }} }}
"#
    ));
    let alone = model(&format!(
        "[[cables]]\nname = \"A\"\nradius = {R_HOLE}\nangles = {{ straight = 0.0 }}\nshorten_percent = 2.0"
    ));
    let e = Energy::default();
    let a = solve(&e, &with_free);
    let b = solve(&e, &alone);
    assert!(a.rms_distance(&b).expect("same disks") < 1e-12);
    assert_eq!(a.cables[1].tension, None);
    assert_eq!(a.cables[1].points.len(), with_free.robot.sections() + 1);
}

#[test]
fn warm_start_from_the_solution_needs_no_iteration() {
    let m = paper(3);
    let e = Energy::default();
    let cold = solve(&e, &m);
    let warm = e
        .solve(&m.robot, &m.actuation, &Scene::empty(), Some(&cold))
        .expect("warm");
    assert_eq!(warm.report.iterations, 0);
    assert!(warm.tip_distance(&cold) < 1e-12);
    // A nearby actuation from the previous shape converges too, to the cold answer.
    let next = m.actuation.clone().with_fraction(0, 0.032);
    let w = e
        .solve(&m.robot, &next, &Scene::empty(), Some(&cold))
        .expect("warm, moved");
    let c = e
        .solve(&m.robot, &next, &Scene::empty(), None)
        .expect("cold, moved");
    assert!(w.tip_distance(&c) < 1e-9);
    assert!(w.report.iterations <= c.report.iterations);
}

#[test]
fn unreachable_lengths_are_named_errors() {
    // Longer shortening than the cable (the file parser rejects it; the library may not).
    let m = model(&format!(
        "[[cables]]\nname = \"A\"\nradius = {R_HOLE}\nangles = {{ straight = 0.0 }}\nshorten = 0.01"
    ));
    let mut act = m.actuation.clone();
    act.cables[0].shorten = Some(Shortening::Length(0.5));
    match Energy::default().solve(&m.robot, &act, &Scene::empty(), None) {
        Err(SolveError::Infeasible { cable, .. }) => assert_eq!(cable, "A"),
        other => panic!("expected Infeasible, got {other:?}"),
    }
    // Opposite cables both pulled 60 %: only axial crushing could reach that.
    let m = model(&format!(
        r#"
[[cables]]
name = "A"
radius = {R_HOLE}
angles = {{ straight = 0.0 }}
shorten_percent = 60.0
[[cables]]
name = "B"
radius = {R_HOLE}
angles = {{ straight = 3.141592653589793 }}
shorten_percent = 60.0
"#
    ));
    match Energy::default().solve(&m.robot, &m.actuation, &Scene::empty(), None) {
        Err(SolveError::Infeasible { cable, .. }) => assert!(cable == "A" || cable == "B"),
        other => panic!("expected Infeasible, got {other:?}"),
    }
}

#[test]
fn non_convergence_is_an_error_not_a_shape() {
    let m = paper(3);
    let e = Energy {
        max_iterations: 1,
        ..Energy::default()
    };
    match e.solve(&m.robot, &m.actuation, &Scene::empty(), None) {
        Err(SolveError::NotConverged {
            iterations,
            residual,
            ..
        }) => {
            assert_eq!(iterations, 1);
            assert!(residual.is_finite() && residual > 0.0);
        }
        other => panic!("expected NotConverged, got {other:?}"),
    }
}

#[test]
fn tension_input_matches_the_rod_under_force_control() {
    // Cables with only a tension are force-driven: potential T·L added to the energy.
    let m = paper(2);
    let mut act = Actuation::free(&m.robot);
    for c in 0..m.robot.cables.len() {
        act = act.with_tension(c, m.actuation.tension(c).expect("paper tensions"));
    }
    let cos = Cosserat::full()
        .with_steps(20)
        .solve(&m.robot, &act, &Scene::empty(), None)
        .expect("rod");
    let en = Energy::default()
        .solve(&m.robot, &act, &Scene::empty(), None)
        .expect("energy");
    let rms = en.rms_distance(&cos).expect("same disks");
    assert!(rms <= RMS_BOUND, "RMS {rms}");
}

#[test]
fn equilibrium_holds_by_finite_differences() {
    // Stationarity of E + Σ λ_c L_c checked with central differences of the public length
    // function (independent of the solver's analytic derivatives).
    use ccrkit::method::energy::cable_lengths;
    let m = paper(3);
    let e = Energy::default();
    let shape = solve(&e, &m);
    let st = state(&shape);
    let nc = m.robot.cables.len();
    let nv = st.len() - nc;
    let (xi, lam) = (&st[..nv], &st[nv..]);
    let bb = &m.robot.backbone;
    let ell = m.robot.section_length(1) / e.sub_arcs as f64;
    let k = [bb.ei(), bb.ei(), bb.gj(), bb.ea()];
    let h = 1e-6;
    let mut worst = 0.0f64;
    let mut scale = 0.0f64;
    for i in 0..nv {
        let (mut xp, mut xm) = (xi.to_vec(), xi.to_vec());
        xp[i] += h;
        xm[i] -= h;
        let lp = cable_lengths(&m.robot, &e, &xp).expect("lengths");
        let lm = cable_lengths(&m.robot, &e, &xm).expect("lengths");
        let de = ell * k[i % 4] * xi[i];
        let dl: f64 = (0..nc).map(|c| lam[c] * (lp[c] - lm[c]) / (2.0 * h)).sum();
        worst = worst.max((de + dl).abs());
        scale = scale.max(de.abs());
    }
    assert!(
        worst <= 1e-6 * scale,
        "stationarity {worst:e} vs scale {scale:e}"
    );
}

/// A cantilever with a small tip force and one unactuated cable (free): the tip deflects by
/// `F L³ / (3 EI)` (Euler–Bernoulli) within 1 %.
#[test]
fn cantilever_tip_force_matches_beam_theory() {
    let f = 0.005; // N: ≈ 2.2 mm on 180 mm
    let m = model(&format!(
        "[[cables]]\nname = \"A\"\nradius = {R_HOLE}\nangles = {{ straight = 0.0 }}\n\
         [loads]\ntip_force = [{f}, 0.0, 0.0]"
    ));
    let s = solve(&Energy::default(), &m);
    let len = m.robot.length();
    let expected = f * len.powi(3) / (3.0 * ei());
    let got = s.tip().x;
    eprintln!("cantilever: tip {got:.6e} m, F L³/3EI {expected:.6e} m");
    assert!(
        ((got - expected) / expected).abs() < 0.01,
        "tip {got} vs {expected}"
    );
}

/// Gravity sideways (backbone weight and disk masses) on a displacement-driven robot, and a
/// tip force on top: the energy model against the rod driven by the same cable lengths, with
/// the same loads (≤ 0.3 mm, tensions within 2 %).
#[test]
fn agrees_with_cosserat_under_gravity_and_a_tip_force() {
    let loads =
        "[loads]\ngravity = [-9.81, 0.0, 0.0]\ndisk_mass = 0.005\ntip_force = [0.0, 0.02, -0.01]";
    let text = format!(
        "[[cables]]\nname = \"A\"\nradius = {R_HOLE}\nangles = {{ straight = 0.0 }}\nshorten = 0.003\n\
         [[cables]]\nname = \"B\"\nradius = {R_HOLE}\nangles = {{ straight = 2.0944 }}\nshorten = 0.002\n\
         {loads}"
    );
    // A dense backbone (steel, 3 mm: 0.54 N/m) so its weight matters next to the disks'.
    let m = model_with_density(&text, 7800.0);
    let (rms, errs) = agreement(&m, LengthMeasure::Path);
    eprintln!(
        "gravity + tip force: RMS {:.4} mm, tension errors {errs:?}",
        rms * 1e3
    );
    assert!(rms <= RMS_BOUND, "RMS {rms}");
    for e in errs {
        assert!(e <= TENSION_REL, "tension error {e}");
    }
    // The loads matter: without them the shape is elsewhere.
    let free = solve(
        &Energy::default(),
        &model_with_density(&text.replace(loads, ""), 7800.0),
    );
    let loaded = solve(&Energy::default(), &m);
    assert!(free.rms_distance(&loaded).unwrap() > 10.0 * RMS_BOUND);
}

#[test]
fn a_tip_moment_is_unsupported_not_ignored() {
    let m = model(&format!(
        "[[cables]]\nname = \"A\"\nradius = {R_HOLE}\nangles = {{ straight = 0.0 }}\nshorten = 0.002\n\
         [loads]\ntip_moment = [0.0, 0.001, 0.0]"
    ));
    match Energy::default().solve(&m.robot, &m.actuation, &Scene::empty(), None) {
        Err(SolveError::Unsupported { reason, .. }) => assert!(reason.contains("moment")),
        other => panic!("expected Unsupported, got {other:?}"),
    }
}

/// Any method's shape is a start: the strains are fitted to its disk frames. From the literal
/// geometric method's shape (4–5 mm away) the solve lands on the cold solution.
#[test]
fn a_shape_from_another_method_is_a_warm_start() {
    for n in 1..=3 {
        let m = paper(n);
        let e = Energy::default();
        let cold = solve(&e, &m);
        let geo = solve(&ccrkit::method::geometric::Geometric::literal(), &m);
        let warm = e
            .solve(&m.robot, &m.actuation, &Scene::empty(), Some(&geo))
            .expect("solves from the geometric shape");
        let d = warm.rms_distance(&cold).unwrap();
        assert!(d < 1e-9, "case {n}: {d} m from the cold solution");
    }
}
