//! Figures of the studies (plotters, the same DejaVu font and palette as [`crate::plot`]):
//! speed against accuracy (log–log, Pareto front marked), stability maps (one panel per mode),
//! the workspace tip cloud (three views). The format follows the extension (`.svg`, `.png`).

use super::{speed_accuracy_front, SpeedAccuracyRow, Stability, Workspace, AUTO};
use crate::plot::{register_font, PlotError, PALETTE};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

type Drawn = Result<(), Box<dyn std::error::Error>>;

/// Render with the backend the extension asks for.
fn render(
    path: &Path,
    size: (u32, u32),
    draw: impl Fn(&DrawingArea<SVGBackend, Shift>) -> Drawn,
    draw_png: impl Fn(&DrawingArea<BitMapBackend, Shift>) -> Drawn,
) -> Result<(), PlotError> {
    register_font();
    let err = |reason: String| PlotError {
        path: path.display().to_string(),
        reason,
    };
    match path.extension().and_then(|e| e.to_str()) {
        Some("svg") => Ok(crate::output::write_with(path, |tmp| {
            let root = SVGBackend::new(tmp, size).into_drawing_area();
            draw(&root).map_err(|e| e.to_string())?;
            root.present().map_err(|e| e.to_string())
        })?),
        Some("png") => Ok(crate::output::write_with(path, |tmp| {
            let root = BitMapBackend::new(tmp, size).into_drawing_area();
            draw_png(&root).map_err(|e| e.to_string())?;
            root.present().map_err(|e| e.to_string())
        })?),
        other => Err(err(format!(
            "unknown image format {:?}: use .svg or .png",
            other.unwrap_or("")
        ))),
    }
}

/// Log time against log RMS error, one colour per method, the Pareto front joined in black.
pub fn speed_accuracy_figure(
    rows: &[SpeedAccuracyRow],
    title: &str,
    path: &Path,
) -> Result<(), PlotError> {
    render(
        path,
        (1100, 750),
        |a| draw_speed(a, rows, title),
        |a| draw_speed(a, rows, title),
    )
}

fn log_range(v: impl Iterator<Item = f64>) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::MAX, f64::MIN);
    for x in v.filter(|x| x.is_finite() && *x > 0.0) {
        lo = lo.min(x);
        hi = hi.max(x);
    }
    if lo > hi {
        return (1e-6, 1.0);
    }
    (lo / 2.0, hi * 2.0)
}

/// Errors below this are drawn at it (a log axis has no zero).
const ERROR_FLOOR: f64 = 1e-12;

/// The share of the speed chart's error decades added below the lowest point, kept free for
/// the legend: 8 rows of ~17 px on a plot ~640 px high need ~21 % of its height, and
/// 0.35 more decades leave the lowest 0.35/1.35 = 26 % free.
const LEGEND_BAND: f64 = 0.35;

fn draw_speed<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    rows: &[SpeedAccuracyRow],
    title: &str,
) -> Drawn
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    let ok: Vec<&SpeedAccuracyRow> = rows
        .iter()
        .filter(|r| r.median_time_s.is_finite() && r.rms_error_m.is_finite())
        .collect();
    let err = |r: &SpeedAccuracyRow| r.rms_error_m.max(ERROR_FLOOR);
    let (x0, x1) = log_range(ok.iter().map(|r| r.median_time_s));
    let (y0, y1) = log_range(ok.iter().map(|r| err(r)));
    // The legend sits in the lower right, below every point: the error axis is extended
    // downwards by a band of LEGEND_BAND of its decades (one legend row a method and a front).
    let y0 = y0 / (y1 / y0).powf(LEGEND_BAND);
    let mut chart = ChartBuilder::on(root)
        .caption(title, ("sans-serif", 20))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())?;
    chart
        .configure_mesh()
        .x_desc("median solve time [s]")
        .y_desc("RMS disk error vs converged rod [m]")
        .x_label_formatter(&|x| format!("{x:.0e}"))
        .y_label_formatter(&|y| format!("{y:.0e}"))
        .label_style(("sans-serif", 13))
        .light_line_style(RGBColor(235, 235, 235))
        .draw()?;
    let front = speed_accuracy_front(rows);
    // One front per reference (force- and displacement-driven errors are not comparable).
    for (reference, style) in [
        ("force", BLACK.stroke_width(2)),
        ("displacement", RGBColor(110, 110, 110).stroke_width(2)),
    ] {
        let mut fp: Vec<(f64, f64)> = rows
            .iter()
            .zip(&front)
            .filter(|(r, f)| **f && r.reference == reference)
            .map(|(r, _)| (r.median_time_s, err(r)))
            .collect();
        if fp.is_empty() {
            continue;
        }
        fp.sort_by(|a, b| a.0.total_cmp(&b.0));
        chart
            .draw_series(LineSeries::new(fp.clone(), style))?
            .label(format!(
                "Pareto front, {reference}-driven (vs the rod driven alike)"
            ))
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], style));
        chart.draw_series(fp.iter().map(|&p| Circle::new(p, 9, style)))?;
    }
    // Labels are placed where no earlier label sits (in decades of the log axes).
    let mut placed: Vec<(f64, f64)> = vec![];
    let mut methods: Vec<&str> = vec![];
    for r in &ok {
        if r.method != AUTO && !methods.contains(&r.method.as_str()) {
            methods.push(&r.method);
        }
    }
    for (k, m) in methods.iter().enumerate() {
        let color = PALETTE[k % PALETTE.len()];
        let pts: Vec<&&SpeedAccuracyRow> = ok.iter().filter(|r| r.method == *m).collect();
        chart
            .draw_series(
                pts.iter()
                    .map(|r| Circle::new((r.median_time_s, err(r)), 5, color.filled())),
            )?
            .label(m.to_string())
            .legend(move |(x, y)| Circle::new((x + 8, y), 5, color.filled()));
        // Label the front and single-setting methods only (the rest would overlap).
        let on_front = |r: &SpeedAccuracyRow| {
            rows.iter()
                .zip(&front)
                .any(|(x, f)| *f && x.method == r.method && x.setting == r.setting)
        };
        for r in pts
            .into_iter()
            .filter(|r| r.setting == "default" || on_front(r))
        {
            let at = (r.median_time_s.log10(), err(r).log10());
            if placed
                .iter()
                .any(|p| (p.0 - at.0).abs() < 0.35 && (p.1 - at.1).abs() < 0.25)
            {
                continue;
            }
            placed.push(at);
            let label = if r.setting == "default" {
                r.method.clone()
            } else {
                r.setting.clone()
            };
            let style = ("sans-serif", 12).into_font().color(&color.mix(0.95));
            chart.draw_series(std::iter::once(
                EmptyElement::at((r.median_time_s, err(r))) + Text::new(label, (12, -6), style),
            ))?;
        }
    }
    // auto's choices: a black triangle each, labelled with its tolerance.
    let autos: Vec<&&SpeedAccuracyRow> = ok.iter().filter(|r| r.method == AUTO).collect();
    if !autos.is_empty() {
        chart
            .draw_series(
                autos
                    .iter()
                    .map(|r| TriangleMarker::new((r.median_time_s, err(r)), 9, BLACK.filled())),
            )?
            .label("auto's choice at a tolerance (its search's whole time)")
            .legend(|(x, y)| TriangleMarker::new((x + 8, y), 7, BLACK.filled()));
        let style = ("sans-serif", 12).into_font().color(&BLACK);
        chart.draw_series(autos.iter().map(|r| {
            let label = r.setting.split(':').next().unwrap_or("").to_string();
            EmptyElement::at((r.median_time_s, err(r))) + Text::new(label, (-10, 10), style.clone())
        }))?;
    }
    chart
        .configure_series_labels()
        .label_font(("sans-serif", 13))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .position(SeriesLabelPosition::LowerRight)
        .draw()?;
    Ok(())
}

/// Colour of a stability status.
pub fn status_color(status: &str) -> RGBColor {
    match status {
        "ok" => RGBColor(120, 200, 120),
        "not_converged" => RGBColor(214, 39, 40),
        "infeasible" => RGBColor(255, 160, 60),
        "obstructed" => RGBColor(0, 0, 0),
        "unsupported" => RGBColor(170, 170, 170),
        "invalid_input" => RGBColor(148, 103, 189),
        _ => RGBColor(100, 100, 100),
    }
}

/// One method's stability map: cold solves (left) and continuation (right).
pub fn stability_figure(st: &Stability, method: &str, path: &Path) -> Result<(), PlotError> {
    render(
        path,
        (1300, 620),
        |a| draw_stability(a, st, method),
        |a| draw_stability(a, st, method),
    )
}

fn draw_stability<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    st: &Stability,
    method: &str,
) -> Drawn
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    let panels = root.split_evenly((1, 2));
    for (k, continuation) in [false, true].into_iter().enumerate() {
        let pts: Vec<_> = st
            .points
            .iter()
            .filter(|p| p.method == method && p.continuation == continuation)
            .collect();
        let Some(first) = pts.first() else { continue };
        let input = first.input;
        let scale = match input {
            super::Input::Shortening => 100.0,
            super::Input::Tension => 1.0,
        };
        let amax = pts.iter().map(|p| p.a).fold(0.0, f64::max) * scale;
        let bmax = pts.iter().map(|p| p.b).fold(0.0, f64::max) * scale;
        let n = st.grid.max(2) as f64;
        let (da, db) = (amax / (n - 1.0), bmax / (n - 1.0));
        let ok = pts.iter().filter(|p| p.status == "ok").count();
        let title = format!(
            "{method} — {} ({ok}/{} converged)",
            if continuation {
                "continuation along rows"
            } else {
                "cold start"
            },
            pts.len()
        );
        let mut chart = ChartBuilder::on(&panels[k])
            .caption(title, ("sans-serif", 17))
            .margin(10)
            .x_label_area_size(40)
            .y_label_area_size(55)
            .build_cartesian_2d(
                (-da / 2.0)..(amax + da / 2.0),
                (-db / 2.0)..(bmax + db / 2.0),
            )?;
        chart
            .configure_mesh()
            .disable_mesh()
            .x_desc(input.label(&st.cables[0]))
            .y_desc(input.label(&st.cables[1]))
            .label_style(("sans-serif", 12))
            .draw()?;
        chart.draw_series(pts.iter().map(|p| {
            let (x, y) = (p.a * scale, p.b * scale);
            Rectangle::new(
                [(x - da / 2.0, y - db / 2.0), (x + da / 2.0, y + db / 2.0)],
                status_color(p.status.name()).filled(),
            )
        }))?;
        let mut kinds: Vec<&str> = vec![];
        for p in &pts {
            if !kinds.contains(&p.status.name()) {
                kinds.push(p.status.name());
            }
        }
        for kind in kinds {
            let c = status_color(kind);
            chart
                .draw_series(std::iter::empty::<Circle<(f64, f64), i32>>())?
                .label(kind.to_string())
                .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 12, y + 5)], c.filled()));
        }
        chart
            .configure_series_labels()
            .label_font(("sans-serif", 13))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .position(SeriesLabelPosition::UpperRight)
            .draw()?;
    }
    Ok(())
}

/// The tip cloud of a workspace sweep in three views (x–z, y–z, x–y), in mm.
pub fn workspace_figure(ws: &Workspace, title: &str, path: &Path) -> Result<(), PlotError> {
    render(
        path,
        (1500, 520),
        |a| draw_workspace(a, ws, title),
        |a| draw_workspace(a, ws, title),
    )
}

fn draw_workspace<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    ws: &Workspace,
    title: &str,
) -> Drawn
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    let tips: Vec<[f64; 3]> = ws
        .samples
        .iter()
        .filter_map(|s| s.tip.map(|t| [t.x * 1e3, t.y * 1e3, t.z * 1e3]))
        .collect();
    let areas = root.split_evenly((1, 3));
    let views = [
        (0usize, 2usize, "x [mm]", "z [mm]"),
        (1, 2, "y [mm]", "z [mm]"),
        (0, 1, "x [mm]", "y [mm]"),
    ];
    for (k, (ix, iy, xl, yl)) in views.into_iter().enumerate() {
        let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
        for t in &tips {
            x0 = x0.min(t[ix]);
            x1 = x1.max(t[ix]);
            y0 = y0.min(t[iy]);
            y1 = y1.max(t[iy]);
        }
        if tips.is_empty() {
            (x0, x1, y0, y1) = (-1.0, 1.0, -1.0, 1.0);
        }
        let span = (x1 - x0).max(y1 - y0).max(1.0) * 1.1;
        let (cx, cy) = ((x0 + x1) / 2.0, (y0 + y1) / 2.0);
        let caption = if k == 0 {
            format!(
                "{title} — {} of {} samples ok",
                tips.len(),
                ws.samples.len()
            )
        } else {
            String::new()
        };
        let mut chart = crate::plot::square_chart(&areas[k], caption, 17, (cx, cy), span, (xl, yl))
            .map_err(|e| e.to_string())?;
        chart.draw_series(
            tips.iter()
                .map(|t| Circle::new((t[ix], t[iy]), 2, PALETTE[0].mix(0.6).filled())),
        )?;
    }
    Ok(())
}
