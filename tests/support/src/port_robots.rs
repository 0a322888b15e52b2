//! Seeded random robots deployed through a port, for the reach measurement
//! (`tests/inverse/reach_random.rs`, `examples/reach_random_ports.rs`): 2–6 cables, straight
//! or helical (±1–6 rad/m), each tied at the tip or at an inner disk (at least half-way out),
//! 6–12 sections of 10–20 mm, a stiff (NiTi-like) or softer (polymer-like) backbone, a port at
//! the origin with insertion limits `[0.4 L, L]` and rotation limits `[−π, π]`, started 70 %
//! out. Half of the robots are *tension-driven*: their targets are made by tensions (the
//! `energy` method under `control = force`). The same seed gives the same file everywhere.

use crate::rng::Rng;
use std::fmt::Write;

/// A random robot with a port: its model file, and how its targets are driven.
pub struct PortRobot {
    /// The model file (TOML).
    pub toml: String,
    /// True when its targets are made by tensions (else by shortenings).
    pub tension_driven: bool,
    /// Largest tension drawn for a target \[N\].
    pub max_tension: f64,
}

/// Random robot `seed` (module docs).
pub fn port_robot(seed: u64) -> PortRobot {
    let mut r = Rng(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1);
    for _ in 0..4 {
        r.next();
    }
    let below = |r: &mut Rng, n: usize| ((r.next() * n as f64) as usize).min(n - 1);
    let cables = 2 + below(&mut r, 5);
    let sections = 6 + below(&mut r, 7);
    let h = r.range(0.010, 0.020);
    let disk = r.range(0.008, 0.012);
    let stiff = r.next() < 0.5;
    let (e, dia) = if stiff { (5.0e10, 0.001) } else { (1.1e9, 0.003) };
    let len = sections as f64 * h;
    let mut t = String::new();
    let _ = writeln!(t, "name = \"port-robot-{seed}\"\n[robot]");
    let _ = writeln!(t, "sections = {sections}\nsection_length = {h}");
    let _ = writeln!(t, "disk_radius = {disk}\ndisk_thickness = 0.0015");
    let _ = writeln!(
        t,
        "backbone = {{ youngs_modulus = {e}, poisson_ratio = 0.3, diameter = {dia} }}"
    );
    let phase = r.range(0.0, std::f64::consts::TAU);
    for c in 0..cables {
        let angle = phase + std::f64::consts::TAU * c as f64 / cables as f64 + r.range(-0.2, 0.2);
        let radius = disk * r.range(0.55, 0.8);
        let helix = r.next() < 0.5;
        let rate = if helix {
            r.range(1.0, 6.0) * if r.next() < 0.5 { -1.0 } else { 1.0 }
        } else {
            0.0
        };
        let angles = if helix {
            format!("{{ helix = {{ start = {angle}, per_metre = {rate} }} }}")
        } else {
            format!("{{ straight = {angle} }}")
        };
        let end = if r.next() < 0.35 {
            sections / 2 + below(&mut r, sections - sections / 2)
        } else {
            sections
        };
        let _ = writeln!(
            t,
            "[[cables]]\nname = \"c{c}\"\nradius = {radius}\nangles = {angles}\nends_at = {}",
            end.max(1)
        );
    }
    let _ = writeln!(
        t,
        "[port]\ninsertion = {}\nlimits = {{ insertion = [{}, {len}], rotation = [-3.141592653589793, 3.141592653589793] }}",
        0.7 * len,
        0.4 * len
    );
    PortRobot {
        toml: t,
        tension_driven: r.next() < 0.5,
        max_tension: if stiff { 8.0 } else { 3.0 },
    }
}
