//! The 3-D view: one self-contained HTML page that turns a solved robot in any browser,
//! offline.
//!
//! ```no_run
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! use ccrkit::export::view::View;
//! use ccrkit::method::{run::SolveRequest, MethodKind};
//! let model = ccrkit::Model::from_file("models/paper/case1.toml")?;
//! let solved = SolveRequest::new(MethodKind::Energy).run(&model)?;
//! let mut view = View::new("case 1", &model.robot, &solved.scene);
//! view.add_shape("energy", &solved.shape)?;
//! view.write(std::path::Path::new("case1.html"))?;
//! # Ok(()) }
//! ```
//!
//! The page holds the document built here as JSON (`window.CCRKIT_DATA`, metres, the robot's
//! base frame) and the script `assets/viewer/viewer.min.js` (three.js 0.187 from npm and
//! `assets/viewer/src/viewer.js`, bundled by `assets/viewer/build.sh` with esbuild; three.js's
//! MIT licence is kept in the bundle's header), inlined at compile time: nothing is fetched.
//! It draws the backbone as a tube, every disk with its cable holes (at a nominal diameter: the
//! model gives none), the cables, the obstacles (semi-transparent primitives and meshes), the
//! contacts as arrows along the contact normal whose length is the reaction (one scale for the
//! page, stated in the legend with the method's unit: N for energy, rad/m for the geometric
//! methods), the base frame, a scale bar, a legend, and orbit / zoom / pan. Several shapes are
//! overlaid in distinct colours; a path of shapes (a plan's waypoints) gets a slider and a play
//! button; a workspace sweep is drawn as the cloud of tips coloured by a chosen column.
//!
//! After drawing, the page sets `window.ccrkitScene` to the counts it drew (per layer: disks,
//! cables, contacts, backbone points; obstacles; frames; cloud points) and mirrors it as JSON
//! into `<pre id="ccrkit-scene">`; [`View::expected`] gives the same summary from the data, so
//! a browser test can compare the two.

mod page;
mod plan;
mod sweep;

pub use plan::read_plan;
pub use sweep::{read_sweep, Sweep};

use super::ExportError;
use crate::method::MethodKind;
use crate::model::robot::Robot;
use crate::model::scene::{ObstacleKind, Scene};
use crate::shape::Shape;
use nalgebra::Vector3;
use serde::Serialize;
use std::path::Path;

/// Colours of overlaid layers, in order (matplotlib's first six).
pub const LAYER_COLORS: [&str; 6] = [
    "#1f77b4", "#ff7f0e", "#2ca02c", "#9467bd", "#8c564b", "#e377c2",
];

/// A 3-D view being assembled: the robot, its obstacles, shapes, paths and a tip cloud.
#[derive(Debug, Clone, Serialize)]
pub struct View {
    title: String,
    robot: RobotDoc,
    obstacles: Vec<ObstacleDoc>,
    layers: Vec<LayerDoc>,
    #[serde(skip_serializing_if = "Option::is_none")]
    cloud: Option<sweep::CloudDoc>,
    #[serde(skip)]
    cables: Vec<(String, usize)>,
}

#[derive(Debug, Clone, Serialize)]
struct RobotDoc {
    name: String,
    length: f64,
    disk_radius: f64,
    disk_thickness: f64,
    backbone_radius: f64,
    hole_radius: f64,
    /// Hole centres `(x, y)` in each disk's frame, disks `0..=n`.
    holes: Vec<Vec<[f64; 2]>>,
    /// The entry port the robot is deployed through, if any.
    #[serde(skip_serializing_if = "Option::is_none")]
    port: Option<PortDoc>,
}

/// The port's frame in the scene: the robot comes out along its +z.
#[derive(Debug, Clone, Serialize)]
struct PortDoc {
    position: [f64; 3],
    /// `[x, y, z, w]` (three.js order).
    quaternion: [f64; 4],
}

#[derive(Debug, Clone, Serialize)]
struct ObstacleDoc {
    name: String,
    kind: &'static str,
    position: [f64; 3],
    /// `[x, y, z, w]` (three.js order).
    quaternion: [f64; 4],
    #[serde(skip_serializing_if = "Option::is_none")]
    radius: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    half_height: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    half_extents: Option<[f64; 3]>,
    #[serde(skip_serializing_if = "Option::is_none")]
    vertices: Option<Vec<f64>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    triangles: Option<Vec<u32>>,
}

#[derive(Debug, Clone, Serialize)]
struct LayerDoc {
    label: String,
    method: String,
    color: String,
    contact_unit: String,
    frames: Vec<FrameDoc>,
}

#[derive(Debug, Clone, Serialize)]
struct FrameDoc {
    /// Per disk `[px, py, pz, r00, r01, r02, r10, …, r22]` (rotation row-major).
    disks: Vec<[f64; 12]>,
    /// Backbone samples, flat `x, y, z, …`.
    backbone: Vec<f64>,
    cables: Vec<CableDoc>,
    contacts: Vec<ContactDoc>,
    /// `[insertion d [m], rotation ψ [rad]]` of a shape solved through a port (the page
    /// shows them beside the waypoint and moves the robot through the port with them).
    #[serde(skip_serializing_if = "Option::is_none")]
    port: Option<[f64; 2]>,
}

#[derive(Debug, Clone, Serialize)]
struct CableDoc {
    name: String,
    points: Vec<f64>,
    slack: bool,
    #[serde(skip_serializing_if = "Option::is_none")]
    tension: Option<f64>,
}

#[derive(Debug, Clone, Serialize)]
struct ContactDoc {
    obstacle: String,
    feature: String,
    point: [f64; 3],
    normal: [f64; 3],
    reaction: f64,
}

/// What a page draws, per layer; the page reports the same as `window.ccrkitScene.layers`.
#[derive(Debug, Clone, PartialEq, Serialize, serde::Deserialize)]
pub struct LayerCounts {
    /// Layer label.
    pub label: String,
    /// Method name.
    pub method: String,
    /// Disks drawn (in the first frame).
    pub disks: usize,
    /// Cables drawn.
    pub cables: usize,
    /// Contact arrows drawn.
    pub contacts: usize,
}

/// What a page draws: the page reports the same in `window.ccrkitScene`.
#[derive(Debug, Clone, PartialEq, Serialize, serde::Deserialize)]
pub struct ViewCounts {
    /// Per layer, first frame.
    pub layers: Vec<LayerCounts>,
    /// Obstacles drawn.
    pub obstacles: usize,
    /// Frames (waypoints) of the longest layer (1 without a path).
    pub frames: usize,
    /// Tips in the sweep cloud.
    pub points: usize,
}

/// Round to `1e-7` (0.1 µm for lengths in metres) so the page stays small.
fn r7(x: f64) -> f64 {
    (x * 1e7).round() / 1e7
}

fn flat(points: &[Vector3<f64>]) -> Vec<f64> {
    points
        .iter()
        .flat_map(|p| [r7(p.x), r7(p.y), r7(p.z)])
        .collect()
}

impl View {
    /// A view of `robot` among the obstacles of `scene`, with no shape yet.
    pub fn new(title: impl Into<String>, robot: &Robot, scene: &Scene) -> View {
        let n = robot.disk_s.len();
        let r = robot.disk_radius;
        let mut holes = vec![Vec::new(); n];
        for c in &robot.cables {
            for (k, disk_holes) in holes.iter_mut().enumerate().take(c.ends_at.min(n - 1) + 1) {
                let h = c.hole(k);
                disk_holes.push([h.x, h.y]);
            }
        }
        // Nominal hole radius: 6 % of the disk's, smaller where a hole sits near the rim.
        let mut hole_radius = 0.06 * r;
        for h in holes.iter().flatten() {
            let rim = r - h[0].hypot(h[1]);
            if rim > 0.0 {
                hole_radius = hole_radius.min(0.6 * rim);
            }
        }
        // Holes on or past the rim cannot be cut out of the disk: drawn as cables only.
        for disk_holes in &mut holes {
            disk_holes.retain(|h| h[0].hypot(h[1]) + hole_radius < r);
        }
        View {
            title: title.into(),
            robot: RobotDoc {
                name: robot.name.clone(),
                length: robot.length(),
                disk_radius: r,
                disk_thickness: robot.disk_thickness,
                backbone_radius: robot.body_radius(),
                hole_radius,
                holes,
                port: robot.port.as_ref().map(|p| {
                    let t = p.pose.translation.vector;
                    let q = p.pose.rotation.coords;
                    PortDoc {
                        position: [t.x, t.y, t.z],
                        quaternion: [q.x, q.y, q.z, q.w],
                    }
                }),
            },
            obstacles: scene.obstacles.iter().map(obstacle_doc).collect(),
            layers: Vec::new(),
            cloud: None,
            cables: robot
                .cables
                .iter()
                .map(|c| (c.name.clone(), c.ends_at.min(n - 1) + 1))
                .collect(),
        }
    }

    /// Overlay one shape, drawn in the next colour and named `label` in the legend.
    pub fn add_shape(&mut self, label: &str, shape: &Shape) -> Result<(), ExportError> {
        self.add_path(label, std::slice::from_ref(shape))
    }

    /// Overlay a path of shapes (e.g. a plan's waypoints), shown one at a time with a slider.
    pub fn add_path(&mut self, label: &str, shapes: &[Shape]) -> Result<(), ExportError> {
        let first = shapes.first().ok_or_else(|| ExportError::InvalidOption {
            option: "path".into(),
            reason: format!("`{label}` has no shape"),
        })?;
        let frames = shapes
            .iter()
            .enumerate()
            .map(|(k, s)| self.frame(s).map_err(|e| at_waypoint(e, k, shapes.len())))
            .collect::<Result<Vec<_>, _>>()?;
        let unit = MethodKind::from_name(&first.method).map_or("", |k| k.info().contact_unit);
        self.layers.push(LayerDoc {
            label: label.to_string(),
            method: first.method.clone(),
            color: LAYER_COLORS[self.layers.len() % LAYER_COLORS.len()].to_string(),
            contact_unit: unit.to_string(),
            frames,
        });
        Ok(())
    }

    /// Draw a workspace sweep's tips, coloured by column `color_by` (default: the first input
    /// column).
    pub fn set_sweep(&mut self, sweep: &Sweep, color_by: Option<&str>) -> Result<(), ExportError> {
        self.cloud = Some(sweep.cloud(color_by)?);
        Ok(())
    }

    fn frame(&self, s: &Shape) -> Result<FrameDoc, ExportError> {
        let mismatch = |reason: String| ExportError::ShapeMismatch {
            robot: self.robot.name.clone(),
            reason,
        };
        if s.disks.len() != self.robot.holes.len() {
            return Err(mismatch(format!(
                "the shape has {} disks, the robot {}",
                s.disks.len(),
                self.robot.holes.len()
            )));
        }
        if s.cables.len() != self.cables.len() {
            return Err(mismatch(format!(
                "the shape has {} cables, the robot {}",
                s.cables.len(),
                self.cables.len()
            )));
        }
        for (c, (name, holes)) in s.cables.iter().zip(&self.cables) {
            if c.name != *name || c.points.len() != *holes {
                return Err(mismatch(format!(
                    "cable `{}` has {} holes; the robot's cable `{name}` passes {holes} disks",
                    c.name,
                    c.points.len()
                )));
            }
        }
        self.check_port(s).map_err(mismatch)?;
        let disks = s
            .disks
            .iter()
            .map(|d| {
                let (p, m) = (d.position, d.rotation);
                let mut a = [0.0; 12];
                a[..3].copy_from_slice(&[r7(p.x), r7(p.y), r7(p.z)]);
                for i in 0..3 {
                    for j in 0..3 {
                        a[3 + 3 * i + j] = r7(m[(i, j)]);
                    }
                }
                a
            })
            .collect();
        let backbone = if s.backbone.len() >= 2 {
            flat(&s.backbone)
        } else {
            flat(&s.disks.iter().map(|d| d.position).collect::<Vec<_>>())
        };
        Ok(FrameDoc {
            disks,
            backbone,
            cables: s
                .cables
                .iter()
                .map(|c| CableDoc {
                    name: c.name.clone(),
                    points: flat(&c.points),
                    slack: c.slack,
                    tension: c.tension,
                })
                .collect(),
            contacts: s
                .contacts
                .iter()
                .map(|c| ContactDoc {
                    obstacle: c.obstacle.clone(),
                    feature: c.feature.clone(),
                    point: c.point_robot.map(r7),
                    normal: c.normal,
                    reaction: c.multiplier,
                })
                .collect(),
            port: s.port.as_ref().map(|p| [p.insertion, p.rotation]),
        })
    }

    /// Why the shape's place in a port does not fit the robot (`Err(reason)`): a port on one
    /// side only, another port pose, an insertion outside `[0, L]` or a non-finite rotation.
    fn check_port(&self, s: &Shape) -> Result<(), String> {
        match (&self.robot.port, &s.port) {
            (None, None) => Ok(()),
            (Some(_), None) => Err("the robot has a port, the shape none".into()),
            (None, Some(_)) => {
                Err("the shape was solved through a port, the robot has none".into())
            }
            (Some(doc), Some(p)) => {
                let t = p.pose.translation.vector;
                let q = p.pose.rotation.coords;
                let same = [t.x, t.y, t.z]
                    .iter()
                    .zip(&doc.position)
                    .chain([q.x, q.y, q.z, q.w].iter().zip(&doc.quaternion))
                    .all(|(a, b)| (a - b).abs() <= 1e-9);
                // The same rotation is q or −q.
                let flipped = [q.x, q.y, q.z, q.w]
                    .iter()
                    .zip(&doc.quaternion)
                    .all(|(a, b)| (a + b).abs() <= 1e-9);
                if !(same
                    || flipped
                        && (0..3).all(|i| ([t.x, t.y, t.z][i] - doc.position[i]).abs() <= 1e-9))
                {
                    return Err("the shape's port pose is not the robot's".into());
                }
                let len = self.robot.length;
                if !(p.insertion.is_finite() && (-1e-9..=len + 1e-9).contains(&p.insertion)) {
                    return Err(format!(
                        "insertion {} m outside [0, {len}] m (the robot's length)",
                        p.insertion
                    ));
                }
                if !p.rotation.is_finite() {
                    return Err(format!("rotation {} rad is not finite", p.rotation));
                }
                Ok(())
            }
        }
    }

    /// The counts the page reports once drawn (its `window.ccrkitScene`).
    pub fn expected(&self) -> ViewCounts {
        ViewCounts {
            layers: self
                .layers
                .iter()
                .map(|l| LayerCounts {
                    label: l.label.clone(),
                    method: l.method.clone(),
                    disks: l.frames[0].disks.len(),
                    cables: l.frames[0].cables.len(),
                    contacts: l.frames[0].contacts.len(),
                })
                .collect(),
            obstacles: self.obstacles.len(),
            frames: self
                .layers
                .iter()
                .map(|l| l.frames.len())
                .max()
                .unwrap_or(1),
            points: self.cloud.as_ref().map_or(0, |c| c.points.len() / 3),
        }
    }

    /// The page: HTML with the document and the viewer script inlined.
    pub fn to_html(&self) -> String {
        page::html(&self.title, self)
    }

    /// Write the page to `path` atomically ([`crate::output`]).
    pub fn write(&self, path: &Path) -> Result<(), ExportError> {
        Ok(crate::output::write_file(path, self.to_html().as_bytes())?)
    }
}

fn at_waypoint(e: ExportError, k: usize, n: usize) -> ExportError {
    match e {
        ExportError::ShapeMismatch { robot, reason } if n > 1 => ExportError::ShapeMismatch {
            robot,
            reason: format!("waypoint {k}: {reason}"),
        },
        e => e,
    }
}

fn obstacle_doc(o: &crate::model::scene::Obstacle) -> ObstacleDoc {
    let t = o.pose.translation.vector;
    let q = o.pose.rotation;
    let mut d = ObstacleDoc {
        name: o.name.clone(),
        kind: "sphere",
        position: [t.x, t.y, t.z],
        quaternion: [q.i, q.j, q.k, q.w],
        radius: None,
        half_height: None,
        half_extents: None,
        vertices: None,
        triangles: None,
    };
    match &o.kind {
        ObstacleKind::Sphere { radius } => d.radius = Some(*radius),
        ObstacleKind::Box { half_extents } => {
            d.kind = "box";
            d.half_extents = Some([half_extents.x, half_extents.y, half_extents.z]);
        }
        ObstacleKind::Capsule {
            radius,
            half_height,
        } => {
            d.kind = "capsule";
            d.radius = Some(*radius);
            d.half_height = Some(*half_height);
        }
        ObstacleKind::Cylinder {
            radius,
            half_height,
        } => {
            d.kind = "cylinder";
            d.radius = Some(*radius);
            d.half_height = Some(*half_height);
        }
        ObstacleKind::Mesh {
            vertices,
            triangles,
            ..
        } => {
            d.kind = "mesh";
            d.vertices = Some(flat(vertices));
            d.triangles = Some(triangles.iter().flatten().copied().collect());
        }
    }
    d
}
