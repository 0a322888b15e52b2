//! What `ccrkit solve` prints: the shape's summary, its error estimate and its uniqueness
//! check, as text.

use ccrkit::method::MethodKind;
use ccrkit::{Model, Shape};

/// The summary of one solve: tip, port, sections, contacts, cables, residual and the reports
/// asked for (auto, error estimate, uniqueness).
pub(crate) fn print_summary(model: &Model, shape: &Shape, median: f64, repeat: usize) {
    let tip = shape.tip() * 1000.0;
    println!("model   {}", model.robot.name);
    println!("method  {}", shape.method);
    println!("tip     [{:.3}, {:.3}, {:.3}] mm", tip.x, tip.y, tip.z);
    if let Some(p) = &shape.port {
        println!(
            "port    insertion {:.3} mm, rotation {:.4} rad; disks from {} out of the port",
            p.insertion * 1e3,
            p.rotation,
            p.first_disk
        );
    }
    for s in &shape.report.sections {
        println!(
            "section {:>2}: residual {:.1e} m, {:>3} iterations, zero terms [{}]{}",
            s.section,
            s.residual,
            s.iterations,
            s.zero_terms.join(", "),
            if s.slack.is_empty() {
                String::new()
            } else {
                format!(", slack [{}]", s.slack.join(", "))
            }
        );
    }
    let unit = MethodKind::from_name(&shape.method)
        .map(|k| k.info().contact_unit)
        .unwrap_or("");
    for c in &shape.contacts {
        let p = [
            c.point_robot[0] * 1e3,
            c.point_robot[1] * 1e3,
            c.point_robot[2] * 1e3,
        ];
        let feature = match (c.disk, c.section) {
            (Some(d), _) => format!("disk {d}"),
            (None, Some(s)) => format!("{} in section {s}", c.feature),
            (None, None) => c.feature.clone(),
        };
        println!(
            "contact `{}` – {feature}: at [{:.3}, {:.3}, {:.3}] mm, distance {:.2e} m, reaction {:.4} {unit}",
            c.obstacle, p[0], p[1], p[2], c.distance, c.multiplier
        );
    }
    // Each cable's tension and path-length change, whatever drove the solve (the
    // shortening of a tension-driven solve drives the same shape back).
    for c in &shape.cables {
        let t = c
            .tension
            .map_or_else(|| "tension —".to_string(), |t| format!("tension {t:.4} N"));
        let u = c.shortening.map_or_else(
            || "shortening —".to_string(),
            |u| format!("shortening {:.6} mm", u * 1e3),
        );
        println!(
            "cable {}: {t}, {u}{}",
            c.name,
            if c.slack { " (slack)" } else { "" }
        );
    }
    println!(
        "residual {:.2e}, iterations {}, time {:.1} µs (median of {repeat})",
        shape.report.residual,
        shape.report.iterations,
        median * 1e6
    );
    if let Some(a) = &shape.report.auto {
        println!(
            "auto    {} {} for tolerance {}{}: {} solves in {:.1} µs",
            a.method,
            a.setting,
            ccrkit::method::auto::mm(a.tolerance_m),
            if a.met { "" } else { " (NOT met)" },
            a.solves,
            a.cost_s * 1e6
        );
    }
    if let Some(e) = &shape.report.error_estimate {
        println!("{}", error_line(e));
    }
    if let Some(u) = &shape.report.unique {
        print!("{}", unique_lines(u));
    }
}

/// The lines of a uniqueness check: the verdict, each path tried, the other model.
fn unique_lines(u: &ccrkit::method::unique::UniqueReport) -> String {
    let stable = |s: Option<bool>| match s {
        Some(true) => "stable",
        Some(false) => "UNSTABLE",
        None => "stability unknown",
    };
    let mut s = if u.only {
        format!(
            "unique  the only equilibrium found ({} of {} paths converged; {} solves, {:.1} ms)\n",
            u.converged_tries,
            u.tries.len(),
            u.solves,
            u.time_s * 1e3
        )
    } else if u.converged_tries == 0 {
        format!(
            "unique  NOT CHECKED: no other path converged ({} solves, {:.1} ms)\n",
            u.solves,
            u.time_s * 1e3
        )
    } else {
        format!(
            "unique  NO: {} equilibria found for this input ({} solves, {:.1} ms)\n",
            u.equilibria,
            u.solves,
            u.time_s * 1e3
        )
    };
    for t in &u.tries {
        let what = match (t.tip_distance_m, &t.error) {
            (Some(d), _) => format!(
                "tip {:.3} mm away, {}{}",
                d * 1e3,
                stable(t.stable),
                if t.distinct {
                    "  ANOTHER EQUILIBRIUM"
                } else {
                    ""
                }
            ),
            (None, Some(e)) => format!("failed: {e}"),
            (None, None) => "failed".to_string(),
        };
        s += &format!("        {}: {what}\n", t.start);
    }
    if let Some(o) = &u.other_model {
        let d = o.tip_distance_m.map_or_else(String::new, |d| {
            format!("tip {:.3} mm away, {}: ", d * 1e3, stable(o.stable))
        });
        s += &format!("        other model {}: {d}{}\n", o.method, o.verdict);
    }
    s
}

/// One line of an error estimate: the bound and its parts, in mm.
fn error_line(e: &ccrkit::method::estimate::ErrorEstimate) -> String {
    let mm = |x: f64| format!("{:.4} mm", x * 1e3);
    let model = e.model_m.map_or_else(|| "unknown".to_string(), mm);
    let against = if e.against.is_empty() {
        String::new()
    } else {
        format!(" against {}", e.against)
    };
    let mut s = format!(
        "error   ≤ {} from the converged rod (discretization {}{against}, model {model}; estimate took {:.1} µs)",
        e.bound_m.map_or_else(|| "?".to_string(), mm),
        e.discretization_m.map_or_else(|| "unknown".to_string(), mm),
        e.cost_s * 1e6
    );
    for line in std::iter::once(&e.fallback)
        .chain(&e.failed)
        .chain(std::iter::once(&e.note))
    {
        if !line.is_empty() {
            s += &format!("\n        {line}");
        }
    }
    s
}
