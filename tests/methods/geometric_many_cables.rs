//! The literal method with many cables is bounded. Generated robots with 11, 16
//! and 30 cables (helically routed, two shortened, the rest paid out or at their length) each
//! end in a shape that meets its constraints or a named error, within the documented
//! iteration budget ([`SECTION_BUDGET`] Newton iterations per section; the complete taut-set
//! search only up to `MAX_ENUMERATED_CABLES` cables per section).

use ccrkit::method::geometric::{Geometric, SECTION_BUDGET};
use ccrkit::{Method, Model, Scene, SolveError};

fn robot(n: usize, rest_percent: f64) -> Model {
    let mut s = String::from(
        "name = \"many\"\n[robot]\nsections = 4\nsection_length = 0.02\ndisk_radius = 0.012\ndisk_thickness = 0.002\nbackbone = { youngs_modulus = 1.1e9, poisson_ratio = 0.3, diameter = 0.003 }\n",
    );
    for k in 0..n {
        let shorten = match k {
            0 => 3.0,
            1 => 2.0,
            _ => rest_percent,
        };
        s += &format!(
            "[[cables]]\nname = \"c{k}\"\nradius = 0.008\nangles = {{ helix = {{ start = {}, per_disk = 0.1 }} }}\nshorten_percent = {shorten}\n",
            std::f64::consts::TAU * k as f64 / n as f64
        );
    }
    Model::from_toml_str(&s).expect("valid by construction")
}

#[test]
fn many_cables_end_within_the_budget() {
    for n in [11, 16, 30] {
        for rest in [-5.0, 0.0] {
            let m = robot(n, rest);
            let sections = m.robot.sections();
            match Geometric::literal().solve(&m.robot, &m.actuation, &Scene::empty(), None) {
                Ok(s) => {
                    assert!(s.report.iterations <= sections * (SECTION_BUDGET + 1000));
                    for i in 1..=sections {
                        let seg = (s.disks[i].position - s.disks[i - 1].position).norm();
                        assert!((seg - m.robot.section_length(i)).abs() < 1e-9);
                        for c in 0..n {
                            let f = m
                                .actuation
                                .shortening_fraction(&m.robot, c)
                                .expect("driven");
                            let p = &s.cables[c].points;
                            let target = (1.0 - f) * m.robot.undeformed_chord(c, i);
                            assert!(
                                (p[i] - p[i - 1]).norm() <= target + 1e-9,
                                "n {n} c {c} i {i}"
                            );
                        }
                    }
                }
                Err(SolveError::NotConverged { iterations, .. }) => {
                    assert!(iterations <= SECTION_BUDGET + 1000, "n {n}: {iterations}");
                }
                Err(SolveError::Infeasible { .. }) => {}
                Err(e) => panic!("n {n} rest {rest}: unexpected {e}"),
            }
        }
    }
}

/// Within the complete search's reach the budget is not the answer: the 11- and 16-cable
/// robots with the other cables paid out 5 % are solved, not ended by a named error. (A faster
/// start rule once left the 16-cable robot `NotConverged` in section 1 while the test above
/// still passed, since it accepts named errors; the section's former search now backs it up.)
#[test]
fn eleven_and_sixteen_cables_are_solved() {
    for n in [11, 16] {
        let m = robot(n, -5.0);
        let r = Geometric::literal().solve(&m.robot, &m.actuation, &Scene::empty(), None);
        assert!(r.is_ok(), "n {n}: {:?}", r.err().map(|e| e.to_string()));
    }
}
