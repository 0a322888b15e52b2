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
    fn name(self) -> &'static str {
        match self {
            View::Xz => "front (x–z)",
            View::Yz => "side (y–z)",
            View::Xy => "top (x–y)",
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
        Some("svg") => Ok(crate::output::write_with(path, |tmp| {
            let root = SVGBackend::new(tmp, size).into_drawing_area();
            draw(&root, rows)?;
            root.present().map_err(|e| e.to_string())
        })?),
        Some("png") => Ok(crate::output::write_with(path, |tmp| {
            let root = BitMapBackend::new(tmp, size).into_drawing_area();
            draw(&root, rows)?;
            root.present().map_err(|e| e.to_string())
        })?),
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

/// A smooth curve through `pts` for drawing (centripetal-free uniform Catmull–Rom, `k`
/// points per span): the backbone samples of a method can be sparse (the energy model gives
/// one per sub-arc), and a thick polyline through them looks beaded. Drawing only.
fn smooth(pts: &[(f64, f64)], k: usize) -> Vec<(f64, f64)> {
    if pts.len() < 3 {
        return pts.to_vec();
    }
    let at = |i: isize| pts[i.clamp(0, pts.len() as isize - 1) as usize];
    let mut out = Vec::with_capacity(pts.len() * k);
    for i in 0..pts.len() as isize - 1 {
        let (p0, p1, p2, p3) = (at(i - 1), at(i), at(i + 1), at(i + 2));
        for j in 0..k {
            let t = j as f64 / k as f64;
            let (t2, t3) = (t * t, t * t * t);
            let f = |a: f64, b: f64, c: f64, d: f64| {
                0.5 * (2.0 * b
                    + (-a + c) * t
                    + (2.0 * a - 5.0 * b + 4.0 * c - d) * t2
                    + (-a + 3.0 * b - 3.0 * c + d) * t3)
            };
            out.push((f(p0.0, p1.0, p2.0, p3.0), f(p0.1, p1.1, p2.1, p3.1)));
        }
    }
    out.push(pts[pts.len() - 1]);
    out
}

/// The corner of a square window `(center, span)` whose quarter holds the fewest points: where
/// the legend hides the least.
fn emptiest_corner(pts: &[(f64, f64)], center: (f64, f64)) -> SeriesLabelPosition {
    let mut count = [0usize; 4];
    for &(x, y) in pts {
        let k = usize::from(x > center.0) + 2 * usize::from(y < center.1);
        count[k] += 1;
    }
    match (0..4).min_by_key(|&k| (count[k], k)).unwrap_or(0) {
        0 => SeriesLabelPosition::UpperLeft,
        1 => SeriesLabelPosition::UpperRight,
        2 => SeriesLabelPosition::LowerLeft,
        _ => SeriesLabelPosition::LowerRight,
    }
}

/// Bounds of everything drawn in one view: a square window (center, span) in mm.
fn view_window(row: &Row, view: View) -> ((f64, f64), f64, Vec<(f64, f64)>) {
    let rad = row.robot.disk_radius;
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
    // Room for the legend: the window is a quarter larger than the robot.
    let span = (x1 - x0).max(y1 - y0).max(1.0) * 1.25;
    (((x0 + x1) / 2.0, (y0 + y1) / 2.0), span, pts)
}

fn draw_view<'a, DB: DrawingBackend + 'a>(
    area: &'a DrawingArea<DB, Shift>,
    row: &Row,
    view: View,
    with_legend: bool,
) -> Result<(), Box<dyn std::error::Error + 'a>> {
    let rad = row.robot.disk_radius;
    let (center, span, pts) = view_window(row, view);
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
    let caption = format!("{} — {}", row.title, view.name());
    let mut chart = square_chart(area, caption, 16, center, span, view.labels())?;
    let grey = RGBColor(120, 120, 120);
    for (k, w) in wires.into_iter().enumerate() {
        let s = chart.draw_series(LineSeries::new(w, grey.mix(0.6).stroke_width(1)))?;
        if k == 0 {
            s.label("obstacles").legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 16, y)], grey.stroke_width(1))
            });
        }
    }
    let mut contact_legend = false;
    for (si, (shape, label)) in row.shapes.iter().enumerate() {
        let color = PALETTE[si % PALETTE.len()];
        let bb: Vec<(f64, f64)> = shape.backbone.iter().map(|p| view.project(p)).collect();
        // With several shapes the first is a wide translucent band (the reference), so a
        // shape lying on it stays visible on top.
        let style = if si == 0 && row.shapes.len() > 1 {
            color.mix(0.45).stroke_width(7)
        } else {
            color.stroke_width(2)
        };
        let series = chart.draw_series(LineSeries::new(smooth(&bb, 6), style))?;
        if !label.is_empty() {
            series
                .label(label.clone())
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], style));
        }
        for k in 0..shape.disks.len() {
            let o: Vec<(f64, f64)> = disk_outline(shape, k, rad)
                .iter()
                .map(|p| view.project(p))
                .collect();
            chart.draw_series(LineSeries::new(o, color.mix(0.5).stroke_width(1)))?;
        }
        for (ci, cable) in shape.cables.iter().enumerate() {
            let c: Vec<(f64, f64)> = cable.points.iter().map(|p| view.project(p)).collect();
            let style = if cable.slack {
                color.mix(0.35).stroke_width(1)
            } else {
                color.mix(0.8).stroke_width(1)
            };
            let s = chart.draw_series(LineSeries::new(c, style))?;
            if si == 0 && ci == 0 {
                s.label("cables (faint: slack), disks")
                    .legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + 16, y)], color.mix(0.6).stroke_width(1))
                    });
            }
        }
        if si == 0 {
            draw_disk_numbers(&mut chart, shape, view)?;
        }
        let unit = crate::method::MethodKind::from_name(&shape.method)
            .map(|k| k.info().contact_unit)
            .unwrap_or("");
        for c in &shape.contacts {
            let p = view.project(&Vector3::from(c.point_robot));
            let q = view.project(&Vector3::from(c.point_obstacle));
            chart.draw_series(std::iter::once(PathElement::new(
                vec![p, q],
                RED.stroke_width(2),
            )))?;
            let dot = chart.draw_series(std::iter::once(Circle::new(p, 4, RED.filled())))?;
            if !contact_legend {
                contact_legend = true;
                dot.label("contacts (reaction)")
                    .legend(|(x, y)| Circle::new((x + 8, y), 4, RED.filled()));
            }
            let text = format!("{:.3} {unit}", c.multiplier);
            let style = ("sans-serif", 11).into_font().color(&RED);
            chart.draw_series(std::iter::once(
                EmptyElement::at(p) + Text::new(text, (6, 4), style),
            ))?;
        }
    }
    if with_legend && row.shapes.iter().any(|(_, l)| !l.is_empty()) {
        chart
            .configure_series_labels()
            .label_font(("sans-serif", 12))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .position(emptiest_corner(&pts, center))
            .draw()?;
    }
    Ok(())
}

/// Disk numbers next to the disks of a shape (base, tip and about four in between).
fn draw_disk_numbers<'a, DB: DrawingBackend + 'a>(
    chart: &mut ChartContext<
        'a,
        DB,
        Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
    >,
    shape: &Shape,
    view: View,
) -> Result<(), Box<dyn std::error::Error + 'a>> {
    let n = shape.disks.len().saturating_sub(1);
    let every = n.div_ceil(5).max(1);
    let style = ("sans-serif", 11).into_font().color(&RGBColor(80, 80, 80));
    for (k, d) in shape.disks.iter().enumerate() {
        if k % every != 0 && k != n {
            continue;
        }
        let p = view.project(&d.position);
        chart.draw_series(std::iter::once(
            EmptyElement::at(p) + Text::new(format!("{k}"), (-14, -6), style.clone()),
        ))?;
    }
    Ok(())
}
