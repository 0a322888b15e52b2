//! Whether a trial step of the energy solver can have carried a robot feature through an
//! obstacle (distances to open meshes are unsigned, so a feature that jumped through a thin
//! wall would look clear at the trial point).
//!
//! As everywhere in the solver, a step moves each point of the robot along the straight line
//! from its place at the iterate to its place at the trial point. Each feature (backbone
//! capsule, disk, cable chord of `energy/contacts.rs`) moves by at most `m` (a bound from its
//! end points, or its centre plus radius times the change of its frame). A feature–obstacle
//! pair is clear along the step when one of these holds:
//!
//! 1. **Distances:** `m ≤ d₀ + d₁`, with `d₀`, `d₁` lower bounds on the feature's distance
//!    to the obstacle before and after (the queried distance of a pair within the margin,
//!    else the largest of the margin, the distance to the obstacle's bounds and, for the
//!    shapes whose point distance is closed-form, the distance from the centre of the
//!    feature's bounding ball to the solid obstacle less the ball's radius: the distance to
//!    a set is 1-Lipschitz, so no point of the ball is closer). A point inside the obstacle
//!    on the way would be at least `d₀` from its start and `d₁` from its end, so the straight
//!    path would be longer than `m`. The bounds of a round or rotated obstacle hold empty
//!    space round its surface: next to the pillar (a cylinder) only the exact distances show
//!    the first full steps clear (5 iterations instead of 7, where they were halved).
//! 2. **Separating plane (convex obstacles):** the plane through the obstacle's witness point
//!    with the pair's normal has the whole obstacle on its far side. If the feature lies
//!    entirely on the near side of the plane found *before* the step at the trial point (or
//!    of the plane found *after* the step at the start), every straight path stays on that
//!    side: the plane's signed distance is affine along a straight path. This lets a feature
//!    in contact slide along a face by more than its distance.
//! 3. **Visible penetration (convex obstacles):** parry's distance to a convex shape is signed,
//!    so a feature that ends inside the obstacle is seen by the merit and the residual; it has
//!    not passed through unseen.
//!
//! Non-convex obstacles (meshes) use rule 1 only. The solver also keeps the older, looser test
//! (every point moves by at most the robot's distance to the obstacles, or half the pair margin
//! when closer) as an alternative, so no step it used to accept is refused.

use super::contacts::{Feat, Kin, Pair, World};
use crate::contact::features;
use nalgebra::{Matrix3, Vector3};

/// Where a feature is at one state.
enum Geom {
    /// Segment between two points, swept by a ball of this radius.
    Segment(Vector3<f64>, Vector3<f64>, f64),
    /// A disk (thin cylinder about the frame's z axis) at this frame.
    Disk(Matrix3<f64>, Vector3<f64>),
}

impl World<'_> {
    /// The place of `feat` at the frames `kin`.
    fn geom(&self, kin: &Kin, feat: Feat) -> Geom {
        let robot = self.robot;
        match feat {
            Feat::Backbone(j) => Geom::Segment(kin.pos[j - 1], kin.pos[j], robot.body_radius()),
            Feat::Disk(k) => {
                let f = self.first[k];
                Geom::Disk(kin.rot[f], kin.pos[f])
            }
            Feat::Cable(c, i) => {
                let cable = &robot.cables[c];
                let (fa, fb) = (self.first[i - 1], self.first[i]);
                Geom::Segment(
                    kin.pos[fa] + kin.rot[fa] * cable.hole(i - 1),
                    kin.pos[fb] + kin.rot[fb] * cable.hole(i),
                    0.0,
                )
            }
        }
    }

    /// Largest distance from a disk's centre to its points \[m\].
    fn disk_reach(&self) -> f64 {
        let (rd, ht) = (self.robot.disk_radius, 0.5 * self.robot.disk_thickness);
        (rd * rd + ht * ht).sqrt()
    }

    /// Bounding ball (centre, radius) of a feature.
    fn ball(&self, g: &Geom) -> (Vector3<f64>, f64) {
        match g {
            Geom::Segment(a, b, r) => (0.5 * (a + b), 0.5 * (b - a).norm() + r),
            Geom::Disk(_, p) => (*p, self.disk_reach()),
        }
    }

    /// Bound on how far any point of a feature moves between two places \[m\]: a point at
    /// fraction t of a segment moves by `(1 − t) Δa + t Δb`; a disk point `p + R l`, `|l| ≤ ρ`,
    /// by at most `|Δp| + ρ |ΔR|_F`.
    fn moved(&self, g0: &Geom, g1: &Geom) -> f64 {
        match (g0, g1) {
            (Geom::Segment(a0, b0, _), Geom::Segment(a1, b1, _)) => {
                (a1 - a0).norm().max((b1 - b0).norm())
            }
            (Geom::Disk(r0, p0), Geom::Disk(r1, p1)) => {
                (p1 - p0).norm() + self.disk_reach() * (r1 - r0).norm()
            }
            _ => f64::INFINITY,
        }
    }

    /// Lowest value of `n · (x − w)` over the points `x` of a feature: its distance to the
    /// plane through `w` with unit normal `n` (negative when it reaches behind the plane). A
    /// disk's support along `−n` is `rd |u_xy| + ht |u_z|`, `u = Rᵀ n`.
    fn low_side(&self, g: &Geom, n: &Vector3<f64>, w: &Vector3<f64>) -> f64 {
        match g {
            Geom::Segment(a, b, r) => n.dot(&(a - w)).min(n.dot(&(b - w))) - r,
            Geom::Disk(rot, p) => {
                let u = rot.tr_mul(n);
                let (rd, ht) = (self.robot.disk_radius, 0.5 * self.robot.disk_thickness);
                n.dot(&(p - w)) - (rd * (u.x * u.x + u.y * u.y).sqrt() + ht * u.z.abs())
            }
        }
    }

    /// Every feature of the robot, as in [`World::pairs`].
    fn features(&self) -> Vec<Feat> {
        let robot = self.robot;
        let nsub = self.first[robot.sections()];
        let mut out: Vec<Feat> = (1..=nsub).map(Feat::Backbone).collect();
        let disks = if robot.has_disks() {
            robot.sections()
        } else {
            0
        };
        out.extend((1..=disks).map(Feat::Disk));
        let exposed = robot.body.cables_exposed();
        for (c, cable) in robot.cables.iter().enumerate().filter(|_| exposed) {
            out.extend((1..=cable.ends_at).map(|i| Feat::Cable(c, i)));
        }
        out
    }

    /// Whether the step from the frames `k0` (pairs `p0`, distance lower bound `clear0`) to
    /// `k1` (`p1`, `clear1`) moves no feature through an obstacle (module docs).
    pub fn step_is_clear(
        &self,
        (k0, p0, clear0): (&Kin, &[Pair], f64),
        (k1, p1, clear1): (&Kin, &[Pair], f64),
    ) -> bool {
        let floor = clear0.max(0.0) + clear1.max(0.0);
        for feat in self.features() {
            let (g0, g1) = (self.geom(k0, feat), self.geom(k1, feat));
            let mv = self.moved(&g0, &g1);
            // Every pair's distance is at least the robot's lower bound at either end.
            if mv <= floor {
                continue;
            }
            let (ball0, ball1) = (self.ball(&g0), self.ball(&g1));
            for &o in &self.near {
                let a = p0.iter().find(|p| p.key() == (o, feat));
                let b = p1.iter().find(|p| p.key() == (o, feat));
                // No pair: farther than the margin (and than the obstacle's bounds; with
                // `exact`, than the distance from the feature's ball to a simple shape).
                let ob = &self.scene.obstacles[o];
                let lower =
                    |p: Option<&Pair>, (c, r): (Vector3<f64>, f64), clear: f64, exact: bool| {
                        p.map_or_else(
                            || {
                                let gap = exact
                                    .then(|| features::ball_gap(&*ob.shape, &ob.parry_pose, &c, r))
                                    .flatten()
                                    .unwrap_or(f64::NEG_INFINITY);
                                (self.scene.bounds_distance(o, &c) - r)
                                    .max(gap)
                                    .max(self.margin)
                                    .max(clear)
                            },
                            |p| p.dist.max(0.0),
                        )
                    };
                let apart =
                    |exact| mv <= lower(a, ball0, clear0, exact) + lower(b, ball1, clear1, exact);
                // The exact distances only when the bounds do not settle it (they cost a
                // query each).
                if apart(false) || ((a.is_none() || b.is_none()) && apart(true)) {
                    continue;
                }
                if !self.scene.obstacles[o].shape.is_convex() {
                    return false;
                }
                let before =
                    a.is_some_and(|p| self.low_side(&g1, &p.normal, &p.point_obstacle) >= 0.0);
                let after = b.is_some_and(|p| {
                    p.dist < 0.0 || self.low_side(&g0, &p.normal, &p.point_obstacle) >= 0.0
                });
                if !(before || after) {
                    return false;
                }
            }
        }
        true
    }
}

#[cfg(test)]
mod tests {
    /// The start of every section at four sub-arcs per section.
    fn four(robot: &crate::model::robot::Robot) -> Vec<usize> {
        (0..=robot.sections()).map(|k| 4 * k).collect()
    }
    use super::*;
    use crate::method::energy::contacts::kinematics;
    use crate::method::energy::test_fixture::sub_arc_lengths;
    use crate::model::Model;

    /// Case 1 (straight) beside a thin wall (2 mm thick box) whose face is at `x = face`.
    fn straight_beside_wall(face: f64) -> (Model, Vec<f64>) {
        let model = case1_with(&format!(
            "name = \"sheet\"\nshape = \"box\"\n\
             position = [{}, 0.0, 0.1]\nhalf_extents = [0.001, 0.3, 0.3]\n",
            face + 0.001
        ));
        let ell = sub_arc_lengths(&model.robot, 4);
        (model, ell)
    }

    /// Paper case 1 with one obstacle (`obstacle`: the body of its `[[obstacles]]` table).
    fn case1_with(obstacle: &str) -> Model {
        let text = std::fs::read_to_string(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/models/paper/case1.toml"
        ))
        .expect("case 1");
        Model::from_toml_str(&format!("{text}\n[[obstacles]]\n{obstacle}")).expect("model")
    }

    /// Case 1 (straight) beside a thin rod (cylinder, radius 3 mm) lying across the robot's
    /// side at mid-height, along `(−1, 1, 0)`, its axis 42 mm from the robot's: its
    /// axis-aligned bounds reach to within 3 mm of the robot's axis, the rod itself to 17 mm
    /// of the robot.
    fn straight_beside_rod() -> (Model, Vec<f64>) {
        let model = case1_with(&format!(
            "name = \"rod\"\nshape = \"cylinder\"\n\
             position = [0.03, 0.03, 0.09]\nrotation = {{ rpy = [0.0, 0.0, {}] }}\n\
             radius = 0.003\nhalf_height = 0.04\n",
            std::f64::consts::FRAC_PI_4
        ));
        let ell = sub_arc_lengths(&model.robot, 4);
        (model, ell)
    }

    /// Soundness with the exact distances of rule 1: of 400 seeded rigid steps of up to 0.1 m
    /// next to the rod, starting and ending clear of it, every one the guard takes keeps every
    /// feature out of the rod at 200 points along the way (the rod is 6 mm thick, the step
    /// between two points ≤ 0.5 mm); both verdicts occur, and steps farther than the robot's
    /// clearance at both ends (the case rule 1 decides) are among those taken.
    #[test]
    fn taken_steps_beside_a_rod_never_cross_it() {
        let (model, ell) = straight_beside_rod();
        let wd =
            World::new(&model.robot, &model.scene, vec![0], four(&model.robot)).expect("world");
        let k0 = kinematics(&vec![0.0; 4 * ell.len()], &ell, false);
        let (p0, c0) = wd.pairs(&k0);
        assert!(c0 > 0.015 && c0 < 0.02, "clearance {c0}");
        let mut seed = 0x2545_f491_4f6c_dd1d_u64;
        let mut uniform = || {
            seed = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let (mut taken, mut refused, mut far) = (0, 0, 0);
        for _ in 0..400 {
            let d = Vector3::new(uniform() - 0.5, uniform() - 0.5, uniform() - 0.5);
            let d = d.normalize() * 0.1 * uniform();
            match checked_step(&wd, (&k0, &p0, c0), d, 200, 1e-9) {
                None => {}
                Some(None) => refused += 1,
                Some(Some(c1)) => {
                    taken += 1;
                    far += usize::from(wd.max_move(&k0, &shifted(&k0, d)) > c0 + c1);
                }
            }
        }
        assert!(
            taken > 0 && refused > 0 && far > 0,
            "{taken} {refused} {far}"
        );
    }

    /// The guard's verdict on the rigid step `d` from `k0` (pairs `p0`, clearance `c0`): `None`
    /// when the step ends inside an obstacle (not a trial the solver makes), `Some(None)` when
    /// the guard refuses it, `Some(Some(c1))` (the end's clearance) when it takes it — after
    /// checking that every pair keeps a distance above `−tol` at `samples` points along the
    /// step. No distance is NaN at the end.
    fn checked_step(
        wd: &World,
        (k0, p0, c0): (&Kin, &[Pair], f64),
        d: Vector3<f64>,
        samples: usize,
        tol: f64,
    ) -> Option<Option<f64>> {
        let k1 = shifted(k0, d);
        let (p1, c1) = wd.pairs(&k1);
        assert!(
            p1.iter().all(|p| !p.dist.is_nan()) && !c1.is_nan(),
            "NaN after {d:?}"
        );
        if c1 < 0.0 {
            return None;
        }
        if !wd.step_is_clear((k0, p0, c0), (&k1, &p1, c1)) {
            return Some(None);
        }
        for i in 1..samples {
            let (ps, _) = wd.pairs(&shifted(k0, d * (i as f64 / samples as f64)));
            assert!(
                ps.iter().all(|p| p.dist > -tol),
                "step {d:?} crosses an obstacle"
            );
        }
        Some(Some(c1))
    }

    /// The same frames moved rigidly by `d`.
    fn shifted(k: &Kin, d: Vector3<f64>) -> Kin {
        Kin {
            rot: k.rot.clone(),
            pos: k.pos.iter().map(|p| p + d).collect(),
            m_int: vec![],
            n_int: vec![],
        }
    }

    /// A jump of the whole robot through the thin wall is refused, although it ends clear of
    /// it; the same distance moved along the wall (the disks 7 mm from it, within the pair
    /// margin) is taken, where the old test (every point moves less than the clearance or
    /// half the margin) refused it.
    #[test]
    fn refuses_a_jump_through_a_wall_and_takes_a_slide_along_it() {
        let (model, ell) = straight_beside_wall(0.019);
        let wd =
            World::new(&model.robot, &model.scene, vec![0], four(&model.robot)).expect("world");
        let k0 = kinematics(&vec![0.0; 4 * ell.len()], &ell, false);
        let (p0, c0) = wd.pairs(&k0);
        assert!(p0.iter().any(|p| matches!(p.feat, Feat::Disk(_))));
        assert!((c0 - 0.007).abs() < 1e-9, "clearance {c0}");
        let through = shifted(&k0, Vector3::new(0.07, 0.0, 0.0));
        let (p1, c1) = wd.pairs(&through);
        assert!(c1 > 0.0, "the jump ends clear of the wall: {c1}");
        assert!(!wd.step_is_clear((&k0, &p0, c0), (&through, &p1, c1)));
        let slide = shifted(&k0, Vector3::new(0.0, 0.0, 0.02));
        let (p1, c1) = wd.pairs(&slide);
        assert!(wd.max_move(&k0, &slide) > c0.max(0.5 * wd.margin()));
        assert!(wd.step_is_clear((&k0, &p0, c0), (&slide, &p1, c1)));
        // Towards the wall by more than the clearance: the disks would end inside it (seen by
        // the signed distance), the backbone and the cables still short of it.
        let into = shifted(&k0, Vector3::new(0.009, 0.0, 0.0));
        let (p1, c1) = wd.pairs(&into);
        assert!(c1 < 0.0);
        assert!(wd.step_is_clear((&k0, &p0, c0), (&into, &p1, c1)));
    }

    /// A scene of case 1 and one simple obstacle of kind `k % 8`: a ball, a box, a capsule, a
    /// cylinder of ordinary sizes, then degenerate ones — a capsule of zero length (a ball), a
    /// cylinder of radius 1e-9 m (a segment), a 1e-9 m thin plate, a slab 2 km wide — at a
    /// random pose near the robot (the slab and plate upright, beside it).
    fn odd_obstacle(k: usize, u: &mut impl FnMut() -> f64) -> Model {
        let yaw = std::f64::consts::TAU * u();
        let (c, s) = (yaw.cos(), yaw.sin());
        let (rpy, pos, shape) = match k % 8 {
            6 | 7 => {
                let half = if k % 8 == 6 { 1e-9 } else { 0.002 };
                let wide = if k % 8 == 6 { 0.05 } else { 1e3 };
                let off = 0.02 + 0.03 * u() + half;
                (
                    [0.0, 0.0, yaw],
                    [off * c, off * s, 0.1],
                    format!("shape = \"box\"\nhalf_extents = [{half}, {wide}, {wide}]"),
                )
            }
            kind => {
                let r = [0.01, 0.008, 0.004, 0.003, 0.006, 1e-9][kind];
                let shape = match kind {
                    0 => format!("shape = \"sphere\"\nradius = {r}"),
                    1 => "shape = \"box\"\nhalf_extents = [0.004, 0.02, 0.01]".to_string(),
                    2 | 4 => format!(
                        "shape = \"capsule\"\nradius = {r}\nhalf_height = {}",
                        if kind == 4 { 1e-9 } else { 0.02 }
                    ),
                    _ => format!("shape = \"cylinder\"\nradius = {r}\nhalf_height = 0.03"),
                };
                let off = 0.02 + 0.04 * u();
                (
                    [u() * 6.0, u() * 6.0, u() * 6.0],
                    [off * c, off * s, 0.2 * u()],
                    shape,
                )
            }
        };
        case1_with(&format!(
            "name = \"odd\"\n{shape}\nposition = {pos:?}\nrotation = {{ rpy = {rpy:?} }}\n"
        ))
    }

    /// Rule 1's exact distances next to degenerate and touching obstacles ([`odd_obstacle`]):
    /// the straight robot moved against the obstacle until its closest pair is 0, 1e-12, 1e-9
    /// or 1e-6 m away, then 30 seeded rigid steps of up to 5 cm; every step the guard takes
    /// keeps every pair's distance ≥ −2e-6 m (the query's accuracy) at 400 points along the way (spacing ≤ 0.125 mm:
    /// a crossing shows wherever the backbone (3 mm) or a disk (2 mm thick) crosses; a cable
    /// chord crossing a 1e-9 m obstacle would pass unseen), and no distance is NaN.
    #[test]
    fn taken_steps_beside_odd_obstacles_never_cross_them() {
        const QUERY_NOISE: f64 = 2e-6;
        let mut seed = 0x9E37_79B9_7F4A_7C15_u64;
        let mut u = || {
            seed = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let (mut scenes, mut taken, mut refused) = (0, 0, 0);
        for k in 0..160 {
            let model = odd_obstacle(k, &mut u);
            let ell = sub_arc_lengths(&model.robot, 4);
            let Some(wd) = World::new(&model.robot, &model.scene, vec![0], four(&model.robot))
            else {
                continue;
            };
            // Towards the obstacle (level) by half the pair margin until a pair is found.
            let mut straight = kinematics(&vec![0.0; 4 * ell.len()], &ell, false);
            let o = model.scene.obstacles[0].parry_pose.translation;
            let toward = Vector3::new(o.x, o.y, 0.0).normalize() * (0.5 * wd.margin());
            let (mut p, mut c) = wd.pairs(&straight);
            for _ in 0..40 {
                if !p.is_empty() || c < 0.0 {
                    break;
                }
                straight = shifted(&straight, toward);
                (p, c) = wd.pairs(&straight);
            }
            let Some(near) = p.iter().min_by(|a, b| a.dist.total_cmp(&b.dist)) else {
                continue;
            };
            if c < 0.0 {
                continue;
            }
            let target = [0.0, 1e-12, 1e-9, 1e-6][k % 4];
            let k0 = shifted(&straight, -near.normal * (near.dist - target));
            let (p0, c0) = wd.pairs(&k0);
            assert!(p0.iter().all(|p| !p.dist.is_nan()) && !c0.is_nan(), "{k}");
            // The query places a rotated cylinder's or box's distance to ~1e-6 m only
            // (`features::witness_near`), so "inside" means deeper than QUERY_NOISE.
            assert!(
                p0.iter().all(|p| p.dist > -QUERY_NOISE),
                "{k}: start inside"
            );
            scenes += 1;
            for _ in 0..30 {
                let d = Vector3::new(u() - 0.5, u() - 0.5, u() - 0.5).normalize() * 0.05 * u();
                match checked_step(&wd, (&k0, &p0, c0), d, 400, QUERY_NOISE) {
                    None => {}
                    Some(None) => refused += 1,
                    Some(Some(_)) => taken += 1,
                }
            }
        }
        assert!(
            scenes > 100 && taken > 500 && refused > 100,
            "{scenes} scenes, {taken} taken, {refused} refused"
        );
    }
}
