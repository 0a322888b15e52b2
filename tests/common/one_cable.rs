//! Robots with compliant cables, shared by the method tests `compliance` (energy model) and
//! `cosserat_compliance` (rods) and the hardware test `hardware`:
//! the straight one-cable robot, three symmetric pretensioned cables on it, and FTDCR v4 with
//! every cable compliant.
#![allow(dead_code)]

use ccrkit::actuation::{Actuation, Shortening};
use ccrkit::{Model, Shape};

/// A straight robot of `sections` sections of `section_length` (disks of `disk_radius`, 2 mm
/// thick; backbone of Young's modulus `youngs_modulus`, Poisson ratio 0.3, 2 mm diameter) with
/// one straight cable `A` at `cable_radius`, tied at the tip. SI units.
pub struct OneCable {
    pub sections: usize,
    pub section_length: f64,
    pub disk_radius: f64,
    pub youngs_modulus: f64,
    pub cable_radius: f64,
}

impl OneCable {
    /// The compliance tests' robot: 10 sections of 10 mm, disks of 12 mm, the cable at 8 mm,
    /// a backbone of modulus `e`.
    pub fn compliance(e: f64) -> Self {
        OneCable {
            sections: 10,
            section_length: 0.01,
            disk_radius: 0.012,
            youngs_modulus: e,
            cable_radius: 0.008,
        }
    }

    /// The model file up to its cables.
    pub fn head(&self) -> String {
        format!(
            "name = \"one\"\n[robot]\nsections = {}\nsection_length = {:?}\ndisk_radius = {:?}\n\
             disk_thickness = 0.002\nbackbone = {{ youngs_modulus = {:e}, poisson_ratio = 0.3, \
             diameter = 0.002 }}\n",
            self.sections, self.section_length, self.disk_radius, self.youngs_modulus
        )
    }

    /// The model file with cable `A`, its table ending in the lines `cable` (its drive,
    /// stiffness, …; a caller may go on with other tables).
    pub fn toml(&self, cable: &str) -> String {
        format!(
            "{}[[cables]]\nname = \"A\"\nradius = {:?}\nangles = {{ straight = 0.0 }}\n{cable}",
            self.head(),
            self.cable_radius
        )
    }
}

/// The compliance robot of modulus `e`, cable `A` shortened by 2 mm, with the cable lines
/// `extra`.
pub fn one_cable(e: f64, extra: &str) -> String {
    OneCable::compliance(e).toml(&format!("shorten = 0.002\n{extra}\n"))
}

/// The series-spring cases `(E, k, T₀)` [Pa, N/m, N]: a stiff backbone with and without
/// pretension, and a soft one.
pub const SPRING_CASES: [(f64, f64, f64); 3] =
    [(2e11, 2000.0, 0.0), (2e11, 500.0, 1.5), (5e9, 3000.0, 0.4)];

/// The series-spring identity on every case of [`SPRING_CASES`], for the method `solve` (named
/// `name` in messages): the compliant cable shortened by `d = 2 mm` ends with tension `T`; the
/// inextensible cable shortened by `d + T₀/k − T/k` gives the same tip (1e-9 m) and tension
/// (1e-6 relative); without pretension the rigid cable at `d` bends the robot more (the
/// stretch takes up part of the command).
pub fn assert_series_springs(name: &str, solve: impl Fn(&Model, &Actuation) -> Shape) {
    for (e, k, t0) in SPRING_CASES {
        let soft = Model::from_toml_str(&one_cable(e, &spring(k, t0))).expect("compliant model");
        let s = solve(&soft, &soft.actuation);
        let t = tension(&s, 0);
        assert!(t > 0.1, "{name}: the cable pulls: {t}");
        let rigid = Model::from_toml_str(&one_cable(e, "")).expect("rigid model");
        let mut act = rigid.actuation.clone();
        act.cables[0].shorten = Some(Shortening::Length(0.002 + t0 / k - t / k));
        let r = solve(&rigid, &act);
        let d = (s.tip() - r.tip()).norm();
        let dt = (tension(&r, 0) - t).abs();
        eprintln!(
            "{name} E {e:e} k {k} T0 {t0}: T = {t:.6} N, tips differ by {d:.2e} m, tensions by \
             {dt:.2e} N"
        );
        assert!(d < 1e-9, "{name}: tips differ by {d:e} m");
        assert!(dt < 1e-6 * t, "{name}: {} vs {t}", tension(&r, 0));
        if t0 == 0.0 {
            let full = solve(&rigid, &rigid.actuation);
            assert!(full.tip().x.abs() > s.tip().x.abs() + 1e-4, "{name}");
        }
    }
}

/// The cable lines of stiffness `k` and, when positive, pretension `t0`.
pub fn spring(k: f64, t0: f64) -> String {
    if t0 > 0.0 {
        format!("stiffness = {k}\npretension = {t0}")
    } else {
        format!("stiffness = {k}")
    }
}

/// The compliance robot of modulus `e` with three straight cables `C0`–`C2` at 120°, each of
/// stiffness `k` and pretension `t0`, none commanded.
pub fn three_pretensioned(e: f64, k: f64, t0: f64) -> String {
    let mut file = OneCable::compliance(e).head();
    for (i, a) in [0.0, 2.0943951023931953, 4.1887902047863905]
        .iter()
        .enumerate()
    {
        file.push_str(&format!(
            "[[cables]]\nname = \"C{i}\"\nradius = 0.008\nangles = {{ straight = {a} }}\n\
             shorten = 0.0\nstiffness = {k}\npretension = {t0}\n"
        ));
    }
    file
}

/// FTDCR v4 (`models/hardware/ftdcr_v4.toml`) with every cable compliant and pretensioned:
/// `k = 3000 + 200 c` N/m for cable `c`, `T₀ = 0.3` N.
pub fn compliant_v4() -> Model {
    let path = format!(
        "{}/models/hardware/ftdcr_v4.toml",
        env!("CARGO_MANIFEST_DIR")
    );
    let mut m = Model::from_file(path).expect("v4");
    for (c, cable) in m.robot.cables.iter_mut().enumerate() {
        cable.stiffness = Some(3000.0 + 200.0 * c as f64);
        cable.pretension = 0.3;
    }
    m
}

/// A bending command of [`compliant_v4`] (one entry a cable, as `Hardware::actuation`
/// takes it) under which some cables go slack and some stay taut.
pub const V4_BEND: [f64; 9] = [4e-3, -2e-3, 0.0, -1e-3, 3e-3, 1e-3, 2e-3, -1e-3, 1.5e-3];

/// The tension of cable `c` of a solved shape [N].
pub fn tension(s: &Shape, c: usize) -> f64 {
    s.cables[c].tension.expect("tension reported")
}
