//! Figures: three orthogonal views (x–z, y–z, x–y) of one or more shapes, as SVG or PNG.
//!
//! Pure Rust (plotters with its SVG and bitmap backends); text uses the DejaVu Sans font shipped
//! in `assets/` (Bitstream Vera licence, `assets/DejaVu-LICENSE.txt`). Lengths are drawn in mm.

use crate::model::robot::Robot;
use crate::model::scene::Scene;
use crate::shape::Shape;
use nalgebra::Vector3;
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;
use std::sync::Once;

static FONT: Once = Once::new();
static FONT_BYTES: &[u8] = include_bytes!("../assets/DejaVuSans.ttf");

/// Register the shipped DejaVu Sans font as `sans-serif` (once; every figure calls it).
pub(crate) fn register_font() {
    FONT.call_once(|| {
        // The font is compiled in; registration only fails on a corrupt font file.
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, FONT_BYTES);
    });
}

/// A plotting failure (unwritable path, unknown extension).
#[derive(Debug, thiserror::Error)]
#[error("cannot plot to `{path}`: {reason}")]
pub struct PlotError {
    /// Output path.
    pub path: String,
    /// Why.
    pub reason: String,
}

/// Colours used for successive shapes in a panel.
pub const PALETTE: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
    RGBColor(255, 127, 14),
    RGBColor(23, 190, 207),
];

/// One row of a figure: a robot and the shapes to overlay (each with a legend label).
pub struct Row<'a> {
    /// Row title.
    pub title: String,
    /// The robot (for disk radius).
    pub robot: &'a Robot,
    /// Shapes with their labels.
    pub shapes: Vec<(&'a Shape, String)>,
    /// Obstacles drawn behind the shapes (and contact points in red).
    pub scene: Option<&'a Scene>,
}

#[derive(Clone, Copy)]
enum View {
    Xz,
    Yz,
    Xy,
}

impl View {
    fn project(self, p: &Vector3<f64>) -> (f64, f64) {
        let m = 1000.0;
        match self {
            View::Xz => (p.x * m, p.z * m),
            View::Yz => (p.y * m, p.z * m),
            View::Xy => (p.x * m, p.y * m),
        }
    }
    fn labels(self) -> (&'static str, &'static str) {
        match self {
            View::Xz => ("x [mm]", "z [mm]"),
            View::Yz => ("y [mm]", "z [mm]"),
            View::Xy => ("x [mm]", "y [mm]"),
        }
    }
}

/// Draw one robot shape in three views.
pub fn plot_shape(shape: &Shape, robot: &Robot, path: &Path) -> Result<(), PlotError> {
    plot_scene(shape, robot, &Scene::empty(), path)
}

/// Draw one robot shape with its obstacles and contacts in three views.
pub fn plot_scene(
    shape: &Shape,
    robot: &Robot,
    scene: &Scene,
    path: &Path,
) -> Result<(), PlotError> {
    plot_rows(
        &[Row {
            title: format!("{} — {}", robot.name, shape.method),
            robot,
            shapes: vec![(shape, shape.method.clone())],
            scene: Some(scene),
        }],
        path,
    )
}

/// Check that a figure can be written to `path` (a `.svg` or `.png` extension), before any
/// work is done for it.
pub fn check_path(path: &Path) -> Result<(), PlotError> {
    match path.extension().and_then(|e| e.to_str()) {
        Some("svg") | Some("png") => Ok(()),
        other => Err(PlotError {
            path: path.display().to_string(),
            reason: format!(
                "unknown image format {:?}: use .svg or .png",
                other.unwrap_or("")
            ),
        }),
    }
}

/// Draw a grid: one row per [`Row`], three views per row. The format follows the extension
/// (`.svg` or `.png`).
pub fn plot_rows(rows: &[Row], path: &Path) -> Result<(), PlotError> {
    register_font();
    let err = |reason: String| PlotError {
        path: path.display().to_string(),
        reason,
    };
    check_path(path)?;
    let size = (1500u32, 480 * rows.len().max(1) as u32);
    match path.extension().and_then(|e| e.to_str()) {
        Some("svg") => {
            let root = SVGBackend::new(path, size).into_drawing_area();
            draw(&root, rows).map_err(err)?;
            root.present().map_err(|e| err(e.to_string()))
        }
        Some("png") => {
            let root = BitMapBackend::new(path, size).into_drawing_area();
            draw(&root, rows).map_err(err)?;
            root.present().map_err(|e| err(e.to_string()))
        }
        other => Err(err(format!(
            "unknown image format {:?}: use .svg or .png",
            other.unwrap_or("")
        ))),
    }
}

fn draw<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, rows: &[Row]) -> Result<(), String> {
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let areas = root.split_evenly((rows.len().max(1), 3));
    for (r, row) in rows.iter().enumerate() {
        for (v, view) in [View::Xz, View::Yz, View::Xy].into_iter().enumerate() {
            draw_view(&areas[r * 3 + v], row, view, v == 0).map_err(|e| e.to_string())?;
        }
    }
    Ok(())
}

/// A chart on `area` with equal scales on both axes (a square window of side `span` around
/// `center`), light grid and the given axis labels: the frame of every projected view.
pub(crate) fn square_chart<'a, DB: DrawingBackend + 'a>(
    area: &'a DrawingArea<DB, Shift>,
    caption: String,
    caption_size: u32,
    center: (f64, f64),
    span: f64,
    labels: (&str, &str),
) -> Result<
    ChartContext<
        'a,
        DB,
        Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
    >,
    Box<dyn std::error::Error + 'a>,
> {
    let (cx, cy) = center;
    let mut chart = ChartBuilder::on(area)
        .caption(caption, ("sans-serif", caption_size))
        .margin(8)
        .x_label_area_size(32)
        .y_label_area_size(44)
        .build_cartesian_2d(
            (cx - span / 2.0)..(cx + span / 2.0),
            (cy - span / 2.0)..(cy + span / 2.0),
        )?;
    chart
        .configure_mesh()
        .x_desc(labels.0)
        .y_desc(labels.1)
        .label_style(("sans-serif", 12))
        .light_line_style(RGBColor(235, 235, 235))
        .draw()?;
    Ok(chart)
}

fn disk_outline(shape: &Shape, k: usize, radius: f64) -> Vec<Vector3<f64>> {
    let d = &shape.disks[k];
    (0..=32)
        .map(|j| {
            let a = j as f64 / 32.0 * std::f64::consts::TAU;
            d.position + d.rotation * Vector3::new(radius * a.cos(), radius * a.sin(), 0.0)
        })
        .collect()
}

fn draw_view<'a, DB: DrawingBackend + 'a>(
    area: &'a DrawingArea<DB, Shift>,
    row: &Row,
    view: View,
    with_title: bool,
) -> Result<(), Box<dyn std::error::Error + 'a>> {
    let rad = row.robot.disk_radius;
    // Square bounds over everything drawn.
    let mut pts: Vec<(f64, f64)> = vec![];
    for (s, _) in &row.shapes {
        for k in 0..s.disks.len() {
            pts.extend(disk_outline(s, k, rad).iter().map(|p| view.project(p)));
        }
        pts.extend(s.backbone.iter().map(|p| view.project(p)));
    }
    if pts.is_empty() {
        pts.push((0.0, 0.0));
    }
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for (x, y) in &pts {
        x0 = x0.min(*x);
        x1 = x1.max(*x);
        y0 = y0.min(*y);
        y1 = y1.max(*y);
    }
    let span = (x1 - x0).max(y1 - y0).max(1.0) * 1.08;
    let (cx, cy) = ((x0 + x1) / 2.0, (y0 + y1) / 2.0);
    // Obstacles near the robot enlarge the view a little, not to their full extent.
    let wires: Vec<Vec<(f64, f64)>> = row
        .scene
        .map(|sc| {
            sc.obstacles
                .iter()
                .flat_map(|o| o.wireframe())
                .map(|w| w.iter().map(|p| view.project(p)).collect())
                .collect()
        })
        .unwrap_or_default();
    let (xl, yl) = view.labels();
    let caption = if with_title {
        row.title.clone()
    } else {
        String::new()
    };
    let mut chart = square_chart(area, caption, 18, (cx, cy), span, (xl, yl))?;
    for w in wires {
        chart.draw_series(LineSeries::new(
            w,
            RGBColor(120, 120, 120).mix(0.6).stroke_width(1),
        ))?;
    }
    for (si, (shape, label)) in row.shapes.iter().enumerate() {
        let color = PALETTE[si % PALETTE.len()];
        let bb: Vec<(f64, f64)> = shape.backbone.iter().map(|p| view.project(p)).collect();
        let series = chart.draw_series(LineSeries::new(bb, color.stroke_width(3)))?;
        if !label.is_empty() {
            series.label(label.clone()).legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 16, y)], color.stroke_width(3))
            });
        }
        for k in 0..shape.disks.len() {
            let o: Vec<(f64, f64)> = disk_outline(shape, k, rad)
                .iter()
                .map(|p| view.project(p))
                .collect();
            chart.draw_series(LineSeries::new(o, color.mix(0.5).stroke_width(1)))?;
        }
        for cable in &shape.cables {
            let c: Vec<(f64, f64)> = cable.points.iter().map(|p| view.project(p)).collect();
            let style = if cable.slack {
                color.mix(0.35).stroke_width(1)
            } else {
                color.mix(0.8).stroke_width(1)
            };
            chart.draw_series(LineSeries::new(c, style))?;
        }
        for c in &shape.contacts {
            let p = view.project(&Vector3::from(c.point_robot));
            let q = view.project(&Vector3::from(c.point_obstacle));
            chart.draw_series(std::iter::once(PathElement::new(
                vec![p, q],
                RED.stroke_width(2),
            )))?;
            chart.draw_series(std::iter::once(Circle::new(p, 4, RED.filled())))?;
        }
    }
    if with_title && row.shapes.iter().any(|(_, l)| !l.is_empty()) {
        chart
            .configure_series_labels()
            .label_font(("sans-serif", 13))
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .position(SeriesLabelPosition::UpperLeft)
            .draw()?;
    }
    Ok(())
}
