//! The robot: disks along a backbone, cables through holes in the disks.
//!
//! Pure data plus derived quantities. Files are parsed and validated in [`crate::model`];
//! once a [`Robot`] exists its fields are valid (positive lengths, holes inside the disks,
//! one hole per cable per disk it passes).
//!
//! Conventions: SI units; disk 0 is the base at the origin, z along the undeformed backbone;
//! a hole of cable `c` at disk `k` sits at `radius[k]·(cos angle[k], sin angle[k], 0)` in the
//! disk's own frame (angles counter-clockwise positive, unwrapped as the file gives them).

use nalgebra::Vector3;
use std::f64::consts::PI;

/// Elastic backbone: a solid rod of circular cross-section, or a tube (an annulus between
/// [`Backbone::inner_diameter`] and [`Backbone::diameter`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Backbone {
    /// Young's modulus E \[Pa\].
    pub youngs_modulus: f64,
    /// Poisson's ratio ν [-].
    pub poisson_ratio: f64,
    /// Rod (outer) diameter d \[m\].
    pub diameter: f64,
    /// Inner diameter dᵢ of a tube \[m\] (0: a solid rod, the default). The section is the
    /// annulus: `A = π (d² − dᵢ²)/4`, `I = π (d⁴ − dᵢ⁴)/64`.
    pub inner_diameter: f64,
    /// Density [kg/m³] (0 when the file gives none: weightless backbone).
    pub density: f64,
    /// Curvature stiffening `β` \[m²\] (0: linear elastic, the default): the bending energy
    /// per length is `½ EI κ² (1 + β κ²)`, so a constant-curvature arc under a pure moment has
    /// `M = EI κ (1 + 2 β κ²)` (a bending stiffness that rises with curvature, e.g. a backbone
    /// whose spacer disks start to touch). The energy model honours it
    /// (`method/energy/problem.rs`); every other method refuses a robot with `β > 0` by name.
    pub stiffening: f64,
}

/// Largest curvature stiffening `β` a model file may give \[m²\]: at 1 m² the stiffness has
/// doubled at κ = 1 m⁻¹ (a bend radius of 1 m), beyond any physical backbone.
pub const MAX_STIFFENING: f64 = 1.0;

impl Backbone {
    /// Shear modulus G = E / (2(1 + ν)) \[Pa\].
    pub fn shear_modulus(&self) -> f64 {
        self.youngs_modulus / (2.0 * (1.0 + self.poisson_ratio))
    }
    /// Cross-section area A = π (d² − dᵢ²) / 4 \[m²\] (the annulus; `π d²/4` for a solid rod).
    pub fn area(&self) -> f64 {
        let (d, di) = (self.diameter, self.inner_diameter);
        PI * (d - di) * (d + di) / 4.0
    }
    /// Second moment of area I = π (d⁴ − dᵢ⁴) / 64 \[m⁴\] (`π d⁴/64` for a solid rod).
    pub fn second_moment(&self) -> f64 {
        PI * (self.diameter.powi(4) - self.inner_diameter.powi(4)) / 64.0
    }
    /// Bending stiffness EI [N m²].
    pub fn ei(&self) -> f64 {
        self.youngs_modulus * self.second_moment()
    }
    /// Torsional stiffness GJ with J = 2I (circular section or annulus) [N m²].
    pub fn gj(&self) -> f64 {
        self.shear_modulus() * 2.0 * self.second_moment()
    }
    /// Axial stiffness EA \[N\].
    pub fn ea(&self) -> f64 {
        self.youngs_modulus * self.area()
    }
    /// Shear stiffness GA \[N\] (no shear correction factor, as in Rucker & Webster 2011).
    pub fn ga(&self) -> f64 {
        self.shear_modulus() * self.area()
    }
    /// Backbone (outer) radius \[m\].
    pub fn radius(&self) -> f64 {
        self.diameter / 2.0
    }
    /// Inner radius of a tube \[m\] (0 for a solid rod).
    pub fn inner_radius(&self) -> f64 {
        self.inner_diameter / 2.0
    }
}

/// Where the cables run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Tendons {
    /// Through holes in spacer disks, outside the backbone, free between disks (the default).
    #[default]
    Disks,
    /// In channels inside the backbone rod (a soft rod, a tube's wall): each hole lies between
    /// the rod's inner and outer radius and the cable follows the rod; spacer disks optional.
    Inside,
}

impl Tendons {
    /// The model file's word for it (`robot.tendons`).
    pub fn name(self) -> &'static str {
        match self {
            Tendons::Disks => "disks",
            Tendons::Inside => "inside",
        }
    }
}

/// The robot's body as it meets the world: where its tendons run, whether it carries spacer
/// disks, and the radius its backbone collides with.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Body {
    /// Where the cables run (model file `robot.tendons`).
    pub tendons: Tendons,
    /// `false`: a rod without spacer disks (only with [`Tendons::Inside`]); the disks are then
    /// stations along the rod (sections, cable ends), with no body of their own: no disk takes
    /// part in contact. Model file `robot.spacer_disks` (default `true`).
    pub no_spacer_disks: bool,
    /// Radius of the body about the backbone for obstacle contact and self-contact \[m\]
    /// (`None`: the backbone's radius, the default). Model file `robot.collision_radius`.
    pub collision_radius: Option<f64>,
}

impl Body {
    /// Whether the cables' runs between disks are features of their own for contact: yes
    /// through spacer disks, no inside the rod (the body covers them).
    pub fn cables_exposed(&self) -> bool {
        self.tendons == Tendons::Disks
    }
}

/// One cable (tendon): its hole at every disk it passes, and where it is tied.
#[derive(Debug, Clone, PartialEq)]
pub struct Cable {
    /// Unique name (e.g. `A`).
    pub name: String,
    /// Disk where the cable is tied (1..=n). It passes disks `0..=ends_at`.
    pub ends_at: usize,
    /// Hole radius at disks `0..=ends_at` \[m\].
    pub radius: Vec<f64>,
    /// Hole angle at disks `0..=ends_at` \[rad\], unwrapped as given.
    pub angle: Vec<f64>,
    /// The rule the file declared the angles by (`straight` or `helix`; `None`: a per-disk
    /// table), so the rod can route the cable by its closed form ([`crate::model::routing`]).
    pub helix: Option<crate::model::routing::Helix>,
    /// Axial stiffness `k` of the cable in series with its actuator \[N/m\] (`None`:
    /// inextensible). Under displacement control the commanded shortening is taken up by the
    /// path change plus the stretch `T/k` ([`Cable::compliance`]); methods that cannot honour
    /// it refuse the model by name.
    pub stiffness: Option<f64>,
    /// Pretension `T₀` \[N\] (≥ 0; only with a stiffness): the tension the cable would carry
    /// at zero command on the straight, undeformed robot. Physically the cable was tied (or the
    /// servo zeroed) stretched by `T₀/k`: its unstretched length is the undeformed path length
    /// minus `T₀/k`, so it acts as a shortening of `T₀/k` added to every command.
    pub pretension: f64,
}

impl Cable {
    /// `1/k` \[m/N\]: stretch per newton of tension (0 when inextensible).
    pub fn compliance(&self) -> f64 {
        self.stiffness.map_or(0.0, |k| 1.0 / k)
    }

    /// The shortening the pretension stands for, `T₀/k` \[m\] (0 when inextensible).
    pub fn pretension_stretch(&self) -> f64 {
        self.pretension * self.compliance()
    }

    /// The rate `ω` \[rad/m\] of the declared helix (0 for a straight run) when the holes
    /// follow it: one radius, and the angle at disk `k` equal to `angle[0] + ω (s_k − s_0)`
    /// to 1e-12 relative (`disk_s` the disks' arc lengths). `None` for a per-disk table, or
    /// holes changed after parsing so that they no longer follow the rule (the holes are the
    /// truth).
    pub fn helix_rate(&self, disk_s: &[f64]) -> Option<f64> {
        let h = self.helix?;
        let (a0, r0) = (self.angle[0], self.radius[0]);
        let follows = (1..=self.ends_at).all(|k| {
            let a = a0 + h.per_metre * (disk_s[k] - disk_s[0]);
            self.radius[k] == r0 && (self.angle[k] - a).abs() <= 1e-12 * (1.0 + a.abs())
        });
        follows.then_some(h.per_metre)
    }

    /// Hole position at disk `k` in that disk's own frame (z = 0).
    pub fn hole(&self, k: usize) -> Vector3<f64> {
        let (r, a) = (self.radius[k], self.angle[k]);
        Vector3::new(r * a.cos(), r * a.sin(), 0.0)
    }

    /// Whether the cable passes section `i` (between disks `i-1` and `i`).
    pub fn reaches_section(&self, i: usize) -> bool {
        i >= 1 && i <= self.ends_at
    }
}

/// Loads other than cables, for force-based methods.
#[derive(Debug, Clone, PartialEq)]
pub struct Loads {
    /// Gravity vector in the base frame [m/s²] (zero: no gravity).
    pub gravity: Vector3<f64>,
    /// Mass of each disk except the base \[kg\].
    pub disk_mass: f64,
    /// External force at the tip, base frame \[N\].
    pub tip_force: Vector3<f64>,
    /// External moment at the tip, base frame [N m].
    pub tip_moment: Vector3<f64>,
}

impl Default for Loads {
    fn default() -> Self {
        Loads {
            gravity: Vector3::zeros(),
            disk_mass: 0.0,
            tip_force: Vector3::zeros(),
            tip_moment: Vector3::zeros(),
        }
    }
}

/// A validated robot.
#[derive(Debug, Clone, PartialEq)]
pub struct Robot {
    /// Model name.
    pub name: String,
    /// Arc length of each disk along the undeformed backbone, `disk_s[0] = 0`, `n + 1` values.
    pub disk_s: Vec<f64>,
    /// Disk radius \[m\].
    pub disk_radius: f64,
    /// Disk thickness \[m\].
    pub disk_thickness: f64,
    /// Backbone rod.
    pub backbone: Backbone,
    /// Cables, in file order.
    pub cables: Vec<Cable>,
    /// Where the cables run, spacer disks, collision radius ([`Body`]).
    pub body: Body,
    /// External loads (gravity, tip wrench) for force-based methods.
    pub loads: Loads,
    /// The entry port the robot is deployed through (`None`: its base is fixed at the scene
    /// origin, z along the backbone). With a port, insertion and rotation are part of the
    /// actuation ([`crate::model::port`]).
    pub port: Option<crate::model::port::Port>,
}

impl Robot {
    /// Number of sections n (disks are numbered `0..=n`).
    pub fn sections(&self) -> usize {
        self.disk_s.len() - 1
    }
    /// Backbone length L \[m\].
    pub fn length(&self) -> f64 {
        self.disk_s[self.disk_s.len() - 1]
    }
    /// Length of section `i` (1-based) \[m\].
    pub fn section_length(&self, i: usize) -> f64 {
        self.disk_s[i] - self.disk_s[i - 1]
    }
    /// Undeformed position of cable `c`'s hole at disk `k` in the base frame.
    pub fn undeformed_hole(&self, c: usize, k: usize) -> Vector3<f64> {
        self.cables[c].hole(k) + Vector3::new(0.0, 0.0, self.disk_s[k])
    }
    /// Undeformed straight chord of cable `c` in section `i` (between its holes at disks
    /// `i-1` and `i`) \[m\]. For a hole that turns by π/6 per disk this is longer than l0.
    pub fn undeformed_chord(&self, c: usize, i: usize) -> f64 {
        (self.undeformed_hole(c, i) - self.undeformed_hole(c, i - 1)).norm()
    }
    /// Undeformed length of cable `c` from the base to the disk where it ends, measured as
    /// straight chords between consecutive holes \[m\].
    pub fn undeformed_chord_length(&self, c: usize) -> f64 {
        (1..=self.cables[c].ends_at)
            .map(|i| self.undeformed_chord(c, i))
            .sum()
    }
    /// Radius of the body about the backbone for contact \[m\]: the collision radius when the
    /// model gives one, else the backbone's radius.
    pub fn body_radius(&self) -> f64 {
        self.body
            .collision_radius
            .unwrap_or_else(|| self.backbone.radius())
    }
    /// Whether the disks are spacer disks that take part in contact (false for a rod without
    /// spacer disks, [`Body::no_spacer_disks`]).
    pub fn has_disks(&self) -> bool {
        !self.body.no_spacer_disks
    }
    /// Index of the cable with this name.
    pub fn cable_index(&self, name: &str) -> Option<usize> {
        self.cables.iter().position(|c| c.name == name)
    }
}
