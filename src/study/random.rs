//! Seeded random robots: soft (silicone-like, E 2–5 MPa) and stiff (NiTi to steel) backbones,
//! 4–12 sections, 1–4 straight or helical cables (some tied at an inner disk), driven by
//! tensions or by one cable's shortening, some sagging sideways under gravity. The same seed
//! gives the same model file on every machine (xorshift64), so studies and tests over "random robots" are
//! repeatable. The bending each draws is aimed at 0.2–1.5 rad over the robot, where every
//! method should give an answer.

use crate::error::ModelError;
use crate::model::Model;
use std::fmt::Write;

/// Xorshift64 draws in [0, 1).
struct Draw(u64);

impl Draw {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.next()
    }
    fn below(&mut self, n: usize) -> usize {
        ((self.next() * n as f64) as usize).min(n - 1)
    }
}

/// The model file (TOML) of random robot `seed`.
pub fn random_robot_toml(seed: u64) -> String {
    let mut d = Draw(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1);
    for _ in 0..4 {
        d.next();
    }
    let sections = 4 + d.below(9);
    let h = d.range(0.008, 0.025);
    let soft = d.next() < 0.4;
    let (e, nu, dia) = if soft {
        (
            d.range(2e6, 5e6),
            d.range(0.45, 0.49),
            d.range(0.003, 0.006),
        )
    } else {
        (d.range(50e9, 200e9), 0.3, d.range(0.0006, 0.0015))
    };
    let rb = dia / 2.0;
    let disk_radius = rb + d.range(0.002, 0.008);
    let ei = e * std::f64::consts::PI * dia.powi(4) / 64.0;
    let length = sections as f64 * h;
    let mut t = String::new();
    let _ = writeln!(
        t,
        "name = \"random-{seed}\"\n[robot]\nsections = {sections}\nsection_length = {h:e}\n\
         disk_radius = {disk_radius:e}\ndisk_thickness = 0.001\n\
         backbone = {{ youngs_modulus = {e:e}, poisson_ratio = {nu:e}, diameter = {dia:e} }}"
    );
    let by_tension = d.next() < 0.6;
    let bend = d.range(0.2, 1.5);
    let cables = 1 + d.below(4);
    for k in 0..cables {
        let r = d.range(
            rb + 0.4 * (disk_radius - rb),
            disk_radius - 0.2 * (disk_radius - rb),
        );
        let start = d.range(0.0, std::f64::consts::TAU);
        let _ = writeln!(t, "[[cables]]\nname = \"c{k}\"\nradius = {r:e}");
        if d.next() < 0.6 {
            let _ = writeln!(t, "angles = {{ straight = {start:e} }}");
        } else {
            let per = d.range(-0.4, 0.4);
            let _ = writeln!(
                t,
                "angles = {{ helix = {{ start = {start:e}, per_disk = {per:e} }} }}"
            );
        }
        let ends = if d.next() < 0.25 {
            1 + d.below(sections)
        } else {
            sections
        };
        if ends < sections {
            let _ = writeln!(t, "ends_at = {ends}");
        }
        let reach = ends as f64 * h;
        if by_tension {
            // T r L / EI ≈ the bend, shared out among the cables.
            let share = if k == 0 { 1.0 } else { d.range(0.0, 0.6) };
            let tension = share * bend * ei / (r * reach) / cables as f64;
            let _ = writeln!(t, "tension = {tension:e}");
        } else if k == 0 {
            let percent = 100.0 * r * bend / length * reach / length;
            let _ = writeln!(t, "shorten_percent = {percent:e}");
        }
    }
    if d.next() < 0.25 {
        // Disks whose weight alone would bend the robot by 0.05–0.3 rad sideways
        // (θ ≈ w L² / 6EI for a load w per metre): a sag, never a second equilibrium.
        let sag = d.range(0.05, 0.3);
        let mass = sag * 6.0 * ei / (9.81 * length * sections as f64);
        let _ = writeln!(
            t,
            "[loads]\ngravity = [0.0, 9.81, 0.0]\ndisk_mass = {mass:e}"
        );
    }
    t
}

/// Random robot `seed` ([`random_robot_toml`]) as a model.
pub fn random_model(seed: u64) -> Result<Model, ModelError> {
    Model::from_toml_str(&random_robot_toml(seed))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_seed_gives_a_valid_model_and_the_same_one_twice() {
        for seed in 0..200 {
            let a = random_robot_toml(seed);
            assert_eq!(a, random_robot_toml(seed));
            if let Err(e) = random_model(seed) {
                panic!("seed {seed}: {e}\n{a}");
            }
        }
    }
}
