//! The port in the solve path: every method solves the robot beyond the port
//! ([`crate::model::port::beyond`]) in its own frame, and the answer is placed in the scene by
//! `T_port · Rz(ψ)` with the straight part behind the port added. Written once here, so every
//! method, and everything that solves through [`super::Method::solve`] or
//! [`super::Prepared::solve`] (the CLI, studies, reach, plan, batch, Python), has the port.
//!
//! What is mapped between the two frames: the scene (obstacles posed into the bending part's
//! frame), the loads (gravity and the tip wrench, scene frame, turned into it), a warm start
//! (only from a shape whose port cut the robot the same way: same first disk out, same
//! snapping); back: disks, backbone, cable holes, contacts (points, normals, disk and section
//! numbers), the per-section reports, the base wrench (now at the port: the wrench the port's
//! clamp exerts, scene frame) and the tip Jacobian's columns (turned into the scene frame).

use super::{MethodKind, Prepared, SolveInput};
use crate::error::SolveError;
use crate::model::actuation::{Actuation, CableDrive, Shortening};
use crate::model::port::{self, Beyond, Port};
use crate::model::robot::Robot;
use crate::shape::{CablePath, Contact, DiskFrame, PortState, Shape, SolveReport};
use nalgebra::{Isometry3, Matrix3, Point3, Translation3, Vector3};

/// The port's part of one solve: the robot beyond, its actuation and the frames.
struct Cut {
    beyond: Option<Beyond>,
    /// Frame of the robot inside the port: `T_port · Rz(ψ)`; material coordinate `s` sits at
    /// `z = s − s_port` in it.
    straight: Isometry3<f64>,
    /// Frame of the beyond-robot's disk 0: `straight · Tz(snapped piece)`.
    base: Isometry3<f64>,
    /// Material coordinate at the port, `L − d`.
    s_port: f64,
    state: PortState,
}

/// Solve `input` (a robot with `port`) by `solve`, which solves a robot without a port:
/// derive the robot beyond the port, solve it in its frame, place the answer (module docs).
pub(super) fn solve_through(
    kind: MethodKind,
    port: &Port,
    input: SolveInput<'_>,
    solve: impl FnOnce(SolveInput<'_>) -> Result<Shape, SolveError>,
) -> Result<Shape, SolveError> {
    let robot = input.robot;
    let (d, psi) = input
        .act
        .port_command(robot)?
        .ok_or_else(|| SolveError::InvalidInput {
            field: "port".into(),
            reason: "the robot has a port but no port command resolved (a bug in ccrkit)".into(),
        })?;
    let beyond = port::beyond(robot, d)?;
    let straight = port.base_frame(psi);
    let piece = beyond.as_ref().map_or(0.0, |b| b.straight);
    let base = straight * Translation3::new(0.0, 0.0, piece);
    let s_port = (robot.length() - d).max(0.0);
    let first_disk = match &beyond {
        Some(b) => b.first_disk(),
        None => robot.disk_s.len(),
    };
    let cut = Cut {
        straight,
        base,
        s_port,
        state: PortState {
            pose: port.pose,
            insertion: d,
            rotation: psi,
            first_disk,
        },
        beyond,
    };
    let behind = behind_cables(kind, robot, input.act, &cut)?;
    let Some(b) = &cut.beyond else {
        return Ok(place(kind, robot, &cut, None, &behind));
    };
    let sub = posed(robot, b, &cut.base);
    let act = sub_actuation(robot, input.act, b);
    let scene = input.scene.transformed(&cut.base.inverse());
    kind.check_support(&sub, &scene)?;
    let warm = input.warm.and_then(|w| warm_in(robot, w, b, &sub));
    let shape = solve(SolveInput {
        robot: &sub,
        act: &act,
        scene: &scene,
        warm: warm.as_ref(),
    })?;
    Ok(place(kind, robot, &cut, Some((b, shape)), &behind))
}

/// The robot beyond the port as the methods solve it: `b`'s robot with `robot`'s loads (scene
/// frame) turned into the frame `base` of its disk 0.
fn posed(robot: &Robot, b: &Beyond, base: &Isometry3<f64>) -> Robot {
    let mut sub = b.robot.clone();
    let r_inv = base.rotation.inverse();
    sub.loads.gravity = r_inv * robot.loads.gravity;
    sub.loads.tip_force = r_inv * robot.loads.tip_force;
    sub.loads.tip_moment = r_inv * robot.loads.tip_moment;
    sub
}

/// The cut and the robot that was solved (its loads in its own frame, [`posed`]) for an
/// answer of `robot` through `port` at the insertion and rotation it reports (`state`);
/// `None` when nothing beyond the port bends.
pub(crate) fn solved_beyond(
    robot: &Robot,
    port: &Port,
    state: &PortState,
) -> Result<Option<(Beyond, Robot)>, SolveError> {
    let Some(b) = port::beyond(robot, state.insertion)? else {
        return Ok(None);
    };
    // The snapped piece is a translation along the port axis: the base turns as the port.
    let sub = posed(robot, &b, &port.base_frame(state.rotation));
    Ok(Some((b, sub)))
}

/// Payouts beyond this fraction of the exposed cable's length are taken as this fraction:
/// the cable is slack either way (a hole at radius `r` on an arc of curvature `κ` runs
/// `1 + rκ` times the arc, and `rκ = 0.9` presses the disks into each other long before).
const MAX_PAYOUT: f64 = 0.9;

/// The actuation of the robot beyond the port: each of its cables' drive, a shortening given
/// as a fraction turned into metres of the whole cable (the same shortening: the straight part
/// behind the port does not change length); a payout longer than [`MAX_PAYOUT`] of the
/// exposed cable is taken as that (slack either way).
fn sub_actuation(robot: &Robot, act: &Actuation, b: &Beyond) -> Actuation {
    let mut out = Actuation::free(&b.robot);
    for (c, j) in b.cables.iter().enumerate() {
        if let (Some(j), Some(d)) = (j, act.cables.get(c)) {
            let most = MAX_PAYOUT * b.robot.undeformed_chord_length(*j);
            out.cables[*j] = CableDrive {
                shorten: act
                    .shortening_length(robot, c)
                    .map(|u| Shortening::Length(if u.is_finite() { u.max(-most) } else { u })),
                tension: d.tension,
                capstan: d.capstan,
            };
        }
    }
    out
}

/// A cable held straight in the port: its tension (where known), whether it is slack, and its
/// shortening (its path does not change: the stretch `T/k − T₀/k` of a compliant cable, else
/// 0).
type Held = (Option<f64>, bool, f64);

/// What a cable tied at or behind the port reports: its tension and whether it is slack
/// (module docs of [`crate::model::port`], "Cables behind the port"). A positive shortening
/// of an inextensible cable that the method would honour is refused by name.
fn behind_cables(
    kind: MethodKind,
    robot: &Robot,
    act: &Actuation,
    cut: &Cut,
) -> Result<Vec<Option<Held>>, SolveError> {
    let mut out = vec![None; robot.cables.len()];
    for (c, cable) in robot.cables.iter().enumerate() {
        if cut.beyond.as_ref().is_some_and(|b| b.cables[c].is_some()) {
            continue;
        }
        let Some(drive) = act.cables.get(c) else {
            continue;
        };
        if let Some(t) = drive.tension {
            if !(t.is_finite() && t >= 0.0) {
                return Err(SolveError::InvalidInput {
                    field: format!("cables[{c}].tension"),
                    reason: format!("must be finite and ≥ 0 (cables pull), got {t}"),
                });
            }
        }
        let short = act.shortening_length(robot, c);
        if let Some(u) = short {
            if !u.is_finite() {
                return Err(SolveError::InvalidInput {
                    field: format!("cables[{c}].shorten"),
                    reason: format!("must be finite, got {u}"),
                });
            }
        }
        let by_tension =
            drive.tension.is_some() && kind.accepts(crate::model::actuation::Input::Tension);
        let (tension, slack) = match (short, by_tension) {
            (_, true) => (drive.tension, drive.tension == Some(0.0)),
            (Some(u), false) => match cable.stiffness {
                Some(k) => {
                    let t = (k * (u + cable.pretension_stretch())).max(0.0);
                    (Some(t), t == 0.0)
                }
                None if u > 0.0 => {
                    return Err(SolveError::Infeasible {
                        cable: cable.name.clone(),
                        section: cable.ends_at,
                        reason: format!(
                            "the cable is tied at disk {}, at or behind the port at insertion \
                             {:.6} m: its whole length lies straight in the port, and a \
                             shortening of {u:e} m would stretch it (give it a tension, or a \
                             shortening ≤ 0)",
                            cable.ends_at, cut.state.insertion
                        ),
                    });
                }
                None => (None, u < 0.0),
            },
            (None, false) => (None, false),
        };
        let stretch = tension.map_or(0.0, |t| t * cable.compliance() - cable.pretension_stretch());
        out[c] = Some((tension, slack, stretch));
    }
    Ok(out)
}

/// A warm start for the robot beyond the port from a shape of the whole robot, when the port
/// cut that shape's robot the same way (same first disk out, same snapping).
fn warm_in(robot: &Robot, w: &Shape, b: &Beyond, sub: &Robot) -> Option<Shape> {
    let ws = w.port.as_ref()?;
    let wb = port::beyond(robot, ws.insertion).ok()??;
    if (wb.offset, wb.snapped) != (b.offset, b.snapped) || w.disks.len() != robot.disk_s.len() {
        return None;
    }
    // The warm shape's own frame of the beyond-robot's base, to bring its disks there.
    let w_base =
        Port { pose: ws.pose }.base_frame(ws.rotation) * Translation3::new(0.0, 0.0, wb.straight);
    let inv = w_base.inverse();
    let rot = inv.rotation.to_rotation_matrix().into_inner();
    let disks = (0..sub.disk_s.len())
        .map(|j| match b.disk(j) {
            Some(k) => DiskFrame {
                s: sub.disk_s[j],
                position: (inv * Point3::from(w.disks[k].position)).coords,
                rotation: rot * w.disks[k].rotation,
            },
            None => DiskFrame {
                s: 0.0,
                position: Vector3::zeros(),
                rotation: Matrix3::identity(),
            },
        })
        .collect();
    let cables = b
        .cables
        .iter()
        .enumerate()
        .filter(|(_, j)| j.is_some())
        .map(|(c, _)| CablePath {
            points: vec![],
            ..w.cables[c].clone()
        })
        .collect();
    Some(Shape {
        method: w.method.clone(),
        disks,
        backbone: vec![],
        cables,
        contacts: vec![],
        report: w.report.clone(),
        port: None,
    })
}

impl Cut {
    /// A point of the beyond-robot's frame in the scene frame.
    fn at_base(&self, p: &Vector3<f64>) -> Vector3<f64> {
        (self.base * Point3::from(*p)).coords
    }

    /// The point at material coordinate `s` (behind the port), offset by `local` in the
    /// cross-section, in the scene frame.
    fn in_port(&self, s: f64, local: Vector3<f64>) -> Vector3<f64> {
        let p = local + Vector3::new(0.0, 0.0, s - self.s_port);
        (self.straight * Point3::from(p)).coords
    }

    /// The base frame's rotation (beyond-robot frame → scene frame).
    fn r_base(&self) -> Matrix3<f64> {
        self.base.rotation.to_rotation_matrix().into_inner()
    }
}

/// The whole robot in the scene frame: the straight part behind the port, and the solved
/// robot beyond it placed by `cut.base` (module docs).
fn place(
    kind: MethodKind,
    robot: &Robot,
    cut: &Cut,
    solved: Option<(&Beyond, Shape)>,
    behind: &[Option<Held>],
) -> Shape {
    let r_s = cut.straight.rotation.to_rotation_matrix().into_inner();
    let r_b = cut.r_base();
    let first = cut.state.first_disk;
    let solved = solved.as_ref().map(|(b, s)| (*b, s));
    let offset = solved.map_or(0, |(b, _)| b.offset);
    let disks: Vec<DiskFrame> = (0..robot.disk_s.len())
        .map(|k| match solved {
            Some((_, s)) if k >= first => {
                let f = &s.disks[k - offset];
                DiskFrame {
                    s: robot.disk_s[k],
                    position: cut.at_base(&f.position),
                    rotation: r_b * f.rotation,
                }
            }
            _ => DiskFrame {
                s: robot.disk_s[k],
                position: cut.in_port(robot.disk_s[k], Vector3::zeros()),
                rotation: r_s,
            },
        })
        .collect();
    // Backbone: the disks behind the port, the port, the snapped piece, the bending part.
    let mut backbone: Vec<Vector3<f64>> = disks[..first].iter().map(|f| f.position).collect();
    let mut push = |p: Vector3<f64>| {
        if backbone.last() != Some(&p) {
            backbone.push(p);
        }
    };
    push(cut.in_port(cut.s_port, Vector3::zeros()));
    match solved {
        Some((_, s)) => s.backbone.iter().for_each(|p| push(cut.at_base(p))),
        None => push(cut.in_port(robot.length(), Vector3::zeros())),
    }
    let cables = place_cables(robot, cut, solved, behind);
    let (contacts, report) = place_answer(cut, solved);
    Shape {
        method: solved.map_or_else(|| kind.name().to_string(), |(_, s)| s.method.clone()),
        disks,
        backbone,
        cables,
        contacts,
        report,
        port: Some(cut.state.clone()),
    }
}

/// Every cable's path in the scene frame: holes behind the port on the straight part, the
/// solved path beyond it; a cable that ends behind the port keeps its held state.
fn place_cables(
    robot: &Robot,
    cut: &Cut,
    solved: Option<(&Beyond, &Shape)>,
    behind: &[Option<Held>],
) -> Vec<CablePath> {
    let first = cut.state.first_disk;
    let offset = solved.map_or(0, |(b, _)| b.offset);
    robot
        .cables
        .iter()
        .enumerate()
        .map(|(c, cable)| {
            let hole = |k: usize| cut.in_port(robot.disk_s[k], cable.hole(k));
            match solved.and_then(|(b, s)| b.cables[c].map(|j| &s.cables[j])) {
                Some(p) => CablePath {
                    name: cable.name.clone(),
                    points: (0..=cable.ends_at)
                        .map(|k| {
                            if k >= first {
                                cut.at_base(&p.points[k - offset])
                            } else {
                                hole(k)
                            }
                        })
                        .collect(),
                    slack: p.slack,
                    slack_sections: p.slack_sections.iter().map(|i| i + offset).collect(),
                    tension: p.tension,
                    // The straight part behind the port does not change length.
                    shortening: p.shortening,
                },
                None => {
                    let (tension, slack, shortening) = behind[c].unwrap_or((None, false, 0.0));
                    CablePath {
                        name: cable.name.clone(),
                        points: (0..=cable.ends_at).map(hole).collect(),
                        slack,
                        slack_sections: if slack {
                            (1..=cable.ends_at).collect()
                        } else {
                            vec![]
                        },
                        tension,
                        shortening: Some(shortening),
                    }
                }
            }
        })
        .collect()
}

/// The contacts and the report in the scene frame: points placed, normals, the base wrench
/// and the Jacobian's columns turned, disk and section numbers shifted past the port; with
/// nothing beyond the port, a converged report that says so.
fn place_answer(cut: &Cut, solved: Option<(&Beyond, &Shape)>) -> (Vec<Contact>, SolveReport) {
    let note = format!(
        "port: insertion {:.6} m, rotation {:.6} rad; disks 0..{} lie straight behind the port",
        cut.state.insertion, cut.state.rotation, cut.state.first_disk
    );
    let Some((b, s)) = solved else {
        let report = SolveReport {
            converged: true,
            notes: vec![
                note,
                "nothing beyond the port bends: the robot lies straight along the port axis".into(),
            ],
            ..SolveReport::default()
        };
        return (vec![], report);
    };
    let r_b = cut.r_base();
    let turn = |v: &[f64; 3]| arr(r_b * Vector3::from(*v));
    let contacts = s
        .contacts
        .iter()
        .map(|c| {
            let mut c = c.clone();
            c.point_robot = arr(cut.at_base(&Vector3::from(c.point_robot)));
            c.point_obstacle = arr(cut.at_base(&Vector3::from(c.point_obstacle)));
            c.normal = turn(&c.normal);
            c.disk = c.disk.and_then(|j| b.disk(j));
            c.section = c.section.map(|i| i + b.offset);
            c
        })
        .collect();
    let mut r = s.report.clone();
    for sec in &mut r.sections {
        sec.section += b.offset;
    }
    r.base_wrench = r.base_wrench.map(|w| {
        let (f, m) = (turn(&[w[0], w[1], w[2]]), turn(&[w[3], w[4], w[5]]));
        [f[0], f[1], f[2], m[0], m[1], m[2]]
    });
    if let Some(j) = &mut r.jacobian {
        j.position.iter_mut().for_each(|v| *v = turn(v));
        j.tangent.iter_mut().for_each(|v| *v = turn(v));
    }
    r.notes.push(note);
    (contacts, r)
}

fn arr(v: Vector3<f64>) -> [f64; 3] {
    [v.x, v.y, v.z]
}

/// [`super::Method::prepare`] for a robot with a port: the robot beyond the port changes with
/// every insertion, so each solve readies the method for the robot it derives (what
/// [`super::Method::prepare_fixed`] caches is per robot).
pub(super) struct PortPrepared<'a, M: ?Sized> {
    pub(super) method: &'a M,
    pub(super) robot: &'a Robot,
}

impl<M: super::Method + ?Sized> Prepared for PortPrepared<'_, M> {
    fn kind(&self) -> MethodKind {
        self.method.kind()
    }
    fn robot(&self) -> &Robot {
        self.robot
    }
    fn solve_supported(&self, input: SolveInput<'_>) -> Result<Shape, SolveError> {
        self.method
            .prepare_fixed(input.robot)?
            .solve_supported(input)
    }
}
