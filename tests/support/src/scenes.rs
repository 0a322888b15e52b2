//! Generators of obstacle scenes: large scenes shared by the contact and file tests
//! (`obstacles`, `scene_json`), the TOML scene reader's unit tests and `benches/scene.rs`;
//! scenes beside a robot's path that it presses on ([`near_path`]), for the speed measurement
//! on scenes nobody tuned for (`examples/scene_speed.rs`).

/// One generated obstacle: its shape's `(key, value)` lines, position and roll–pitch–yaw.
struct Item {
    sizes: &'static [(&'static str, &'static str)],
    position: [f64; 3],
    rpy: [f64; 3],
}

/// `n` obstacles cycling sphere, box, capsule and cylinder, at deterministic pseudo-random
/// places (xorshift64, `seed`) in a shell of radii 1–2 m around the base, each with a
/// roll–pitch–yaw rotation.
fn items(n: usize, seed: u64) -> Vec<Item> {
    let mut state = seed | 1;
    let mut rnd = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    (0..n)
        .map(|k| {
            let (th, rad, z) = (
                rnd() * std::f64::consts::TAU,
                1.0 + rnd(),
                3.0 * rnd() - 1.0,
            );
            let rpy = [rnd(), rnd(), rnd()];
            let sizes: &'static [(&str, &str)] = match k % 4 {
                0 => &[("shape", "\"sphere\""), ("radius", "0.01")],
                1 => &[("shape", "\"box\""), ("half_extents", "[0.01, 0.02, 0.03]")],
                2 => &[
                    ("shape", "\"capsule\""),
                    ("radius", "0.01"),
                    ("half_height", "0.02"),
                ],
                _ => &[
                    ("shape", "\"cylinder\""),
                    ("radius", "0.01"),
                    ("half_height", "0.02"),
                ],
            };
            Item {
                sizes,
                position: [rad * th.cos(), rad * th.sin(), z],
                rpy,
            }
        })
        .collect()
}

/// The text of a TOML scene file with the `n` obstacles of [`items`] and full-precision
/// numbers — the file a program that exports a cluttered environment would write. Names are
/// `o0`, `o1`, …
pub fn scene_text(n: usize, seed: u64) -> String {
    let mut text = String::from("clearance = 0.0\n");
    for (k, it) in items(n, seed).iter().enumerate() {
        text += &format!("[[obstacles]]\nname = \"o{k}\"\n");
        for (key, value) in it.sizes {
            text += &format!("{key} = {value}\n");
        }
        let (p, r) = (it.position, it.rpy);
        text += &format!(
            "position = [{:?}, {:?}, {:?}]\nrotation = {{ rpy = [{:?}, {:?}, {:?}] }}\n",
            p[0], p[1], p[2], r[0], r[1], r[2]
        );
    }
    text
}

/// The same scene as [`scene_text`], written as JSON (one obstacle a line).
pub fn scene_json(n: usize, seed: u64) -> String {
    let lines: Vec<String> = items(n, seed)
        .iter()
        .enumerate()
        .map(|(k, it)| {
            let sizes: String = it
                .sizes
                .iter()
                .map(|(key, value)| format!("\"{key}\": {value}, "))
                .collect();
            let (p, r) = (it.position, it.rpy);
            format!(
                "  {{\"name\": \"o{k}\", {sizes}\"position\": [{:?}, {:?}, {:?}], \
                 \"rotation\": {{\"rpy\": [{:?}, {:?}, {:?}]}}}}",
                p[0], p[1], p[2], r[0], r[1], r[2]
            )
        })
        .collect();
    format!(
        "{{\"clearance\": 0.0, \"obstacles\": [\n{}\n]}}\n",
        lines.join(",\n")
    )
}

/// One obstacle [`near_path`] placed.
#[derive(Debug, Clone, Copy)]
pub struct Placed {
    /// `wall`, `pillar` or `box`.
    pub kind: &'static str,
    /// The index of the path point it is placed beside.
    pub anchor: usize,
    /// Its distance from that point \[m\].
    pub gap: f64,
}

/// The kinds of obstacle [`near_path`] places.
const NEAR_KINDS: [&str; 3] = ["wall", "pillar", "box"];

/// The rotation `Rz(yaw) Ry(pitch) Rx(roll)` of a roll–pitch–yaw triple (the scene file's
/// convention), as rows.
fn rpy_matrix(r: [f64; 3]) -> [[f64; 3]; 3] {
    let (sr, cr) = r[0].sin_cos();
    let (sp, cp) = r[1].sin_cos();
    let (sy, cy) = r[2].sin_cos();
    [
        [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
        [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
        [-sp, cp * sr, cp * cr],
    ]
}

/// Roll–pitch–yaw of a rotation given by its rows (the inverse of [`rpy_matrix`] for a pitch
/// inside ±π/2).
fn matrix_rpy(m: [[f64; 3]; 3]) -> [f64; 3] {
    [
        m[2][1].atan2(m[2][2]),
        (-m[2][0]).clamp(-1.0, 1.0).asin(),
        m[1][0].atan2(m[0][0]),
    ]
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// Paper case I's base disk: radius and half thickness \[m\].
const BASE_DISK: (f64, f64) = (0.012, 0.001);

/// Spacing of the grid over the base disk's mid-plane that [`meets_base`] samples \[m\].
const BASE_GRID: f64 = 2.5e-4;

/// Whether a generated obstacle may meet the base disk (paper case I's: centre `path[0]`,
/// normal along `path[1] − path[0]`): some point of a polar grid over the disk's mid-plane
/// (rings and arcs at most [`BASE_GRID`] apart) is within `half thickness + BASE_GRID` of it.
/// Every point of the disk lies within that of a grid point, so an obstacle that meets the disk
/// is always caught (a few that pass within 1.25 mm are too).
fn meets_base(path: &[[f64; 3]], sizes: &str, rows: [[f64; 3]; 3], centre: [f64; 3]) -> bool {
    let (radius, half) = BASE_DISK;
    let (c, n) = (path[0], unit(sub(path[1], path[0])));
    let helper = if n[0].abs() < 0.9 { [1.0, 0.0, 0.0] } else { [0.0, 1.0, 0.0] };
    let e1 = unit(cross(n, helper));
    let e2 = cross(n, e1);
    let rings = (radius / BASE_GRID).ceil() as usize;
    (0..=rings).any(|k| {
        let r = radius * k as f64 / rings as f64;
        let arcs = ((std::f64::consts::TAU * r / BASE_GRID).ceil() as usize).max(1);
        (0..arcs).any(|j| {
            let (sn, cs) = (std::f64::consts::TAU * j as f64 / arcs as f64).sin_cos();
            let p = [0, 1, 2].map(|i| c[i] + r * (cs * e1[i] + sn * e2[i]));
            base_distance(p, sizes, rows, centre) <= half + BASE_GRID
        })
    })
}

/// The distance from `p` to a generated obstacle — a box (`half_extents` in `sizes`) or a
/// cylinder along its local z (`radius`, `half_height`) — with axes the columns of `rows` and
/// centre `centre`, in closed form (0 inside).
fn base_distance(p: [f64; 3], sizes: &str, rows: [[f64; 3]; 3], centre: [f64; 3]) -> f64 {
    let q = sub(p, centre);
    let l = [0, 1, 2].map(|c| (0..3).map(|r| rows[r][c] * q[r]).sum::<f64>());
    let num = |key: &str| -> Vec<f64> {
        let rest = sizes.split(key).nth(1).unwrap_or("");
        let line = rest.lines().next().unwrap_or("");
        line.trim_start_matches([' ', '=', '['])
            .trim_end_matches(']')
            .split(',')
            .filter_map(|x| x.trim().parse().ok())
            .collect()
    };
    if sizes.contains("half_extents") {
        let e = num("half_extents");
        let d = [0, 1, 2].map(|j| (l[j].abs() - e[j]).max(0.0));
        dot(d, d).sqrt()
    } else {
        let (r, h) = (num("radius")[0], num("half_height")[0]);
        let radial = (l[0].hypot(l[1]) - r).max(0.0);
        radial.hypot((l[2].abs() - h).max(0.0))
    }
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn unit(a: [f64; 3]) -> [f64; 3] {
    let l = dot(a, a).sqrt();
    [a[0] / l, a[1] / l, a[2] / l]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// A scene of one to three obstacles — walls (large thin boxes), pillars (cylinders) and small
/// boxes — near a robot's path: the polyline `path` of its backbone points (base first) in its
/// free shape. Each obstacle is placed beside a point `p` of the path's upper half (the tip
/// included), in a random direction `d` across the path, with its point nearest to `p` at a
/// gap of 4–18 mm from it, so that a robot whose body reaches ~12 mm from its backbone presses
/// on it where it would pass freely:
///
/// * a wall turns a face to `p` (its thin axis along `d`, turned about it at random), the foot
///   of the perpendicular from `p` inside the face;
/// * a box or a pillar is turned at random and moved so that its support point in `−d` (a
///   corner, an edge or a rim point) is `p + gap·d`: it lies beyond the plane through that
///   point across `d`, so that point is its nearest to `p`.
///
/// No obstacle meets paper case I's base disk at the path's first point (one that may is drawn
/// again, `meets_base`), so that no wall passes through it: every scene is a valid input.
///
/// Deterministic in `seed` (xorshift64). Returns the TOML text and what was placed, in the
/// file's order.
pub fn near_path(path: &[[f64; 3]], seed: u64) -> (String, Vec<Placed>) {
    let mut rng = crate::rng::Rng(seed.wrapping_mul(0x9e37_79b9_7f4a_7c15) | 1);
    for _ in 0..4 {
        rng.next();
    }
    let n = 1 + (rng.next() * 3.0) as usize;
    let mut text = String::from("clearance = 0.0\n");
    let mut placed = vec![];
    for k in 0..n {
        // Drawn again (the same stream, so scenes that never redraw are unchanged) while the
        // obstacle may meet the base disk: a wall long enough to pass through it makes the scene
        // an invalid input (`Obstructed` in section 0).
        let (kind, i, gap, sizes, rows, centre) = loop {
            let kind = NEAR_KINDS[(rng.next() * 3.0) as usize % 3];
            let half = path.len() / 2;
            let i = (half + (rng.next() * (path.len() - half) as f64) as usize).min(path.len() - 1);
            let p = path[i];
            let t = unit(sub(p, path[i - 1]));
            // A random direction across the path at `p`.
            let mut d = [rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)];
            let along = dot(d, t);
            d = unit([d[0] - along * t[0], d[1] - along * t[1], d[2] - along * t[2]]);
            let gap = rng.range(0.004, 0.018);
            let (sizes, rows, centre) = match kind {
                "wall" => {
                    let e = [
                        rng.range(0.003, 0.006),
                        rng.range(0.04, 0.12),
                        rng.range(0.04, 0.12),
                    ];
                    // Columns d, y, z: y a random direction across d.
                    let spin = rng.range(0.0, std::f64::consts::TAU);
                    let (sn, cs) = spin.sin_cos();
                    let y = unit([
                        t[0] * cs + cross(d, t)[0] * sn,
                        t[1] * cs + cross(d, t)[1] * sn,
                        t[2] * cs + cross(d, t)[2] * sn,
                    ]);
                    let z = cross(d, y);
                    let rows = [0, 1, 2].map(|r| [d[r], y[r], z[r]]);
                    let (u, v) = (rng.range(-0.6, 0.6) * e[1], rng.range(-0.6, 0.6) * e[2]);
                    let c = [0, 1, 2].map(|j| p[j] + d[j] * (gap + e[0]) + y[j] * u + z[j] * v);
                    (format!("shape = \"box\"\nhalf_extents = {e:?}\n"), rows, c)
                }
                _ => {
                    let rpy = [
                        rng.range(-3.2, 3.2),
                        rng.range(-1.5, 1.5),
                        rng.range(-3.2, 3.2),
                    ];
                    let rows = rpy_matrix(rpy);
                    // `−d` in the obstacle's frame (Rᵀ(−d)) and the support point there.
                    let w = [0, 1, 2].map(|c| -(0..3).map(|r| rows[r][c] * d[r]).sum::<f64>());
                    let (sizes, s) = if kind == "box" {
                        let e = [0; 3].map(|_| rng.range(0.004, 0.02));
                        (
                            format!("shape = \"box\"\nhalf_extents = {e:?}\n"),
                            [0, 1, 2].map(|j| e[j] * w[j].signum()),
                        )
                    } else {
                        let (r, h) = (rng.range(0.004, 0.015), rng.range(0.02, 0.06));
                        let wxy = w[0].hypot(w[1]);
                        (
                            format!("shape = \"cylinder\"\nradius = {r:?}\nhalf_height = {h:?}\n"),
                            [r * w[0] / wxy, r * w[1] / wxy, h * w[2].signum()],
                        )
                    };
                    let rs = [0, 1, 2].map(|r| dot(rows[r], s));
                    let c = [0, 1, 2].map(|j| p[j] + d[j] * gap - rs[j]);
                    (sizes, rows, c)
                }
            };
            if !meets_base(path, &sizes, rows, centre) {
                break (kind, i, gap, sizes, rows, centre);
            }
        };
        let rpy = matrix_rpy(rows);
        text += &format!(
            "[[obstacles]]\nname = \"{kind}{k}\"\n{sizes}position = [{:?}, {:?}, {:?}]\nrotation = {{ rpy = [{:?}, {:?}, {:?}] }}\n",
            centre[0], centre[1], centre[2], rpy[0], rpy[1], rpy[2]
        );
        placed.push(Placed {
            kind,
            anchor: i,
            gap,
        });
    }
    (text, placed)
}

/// A sphere of radius `r` about `c` as `stacks` × `slices` quads, poles as fans, wound outward,
/// as OBJ text: a closed mesh of `2 slices (stacks − 1)` triangles (100 × 128: 25 344), the
/// organ or lumen of the concave-wall tests and of the `obstacles` bench's 25k-mesh rows.
pub fn uv_sphere_obj(r: f64, c: [f64; 3], stacks: usize, slices: usize) -> String {
    use std::f64::consts::{PI, TAU};
    use std::fmt::Write;
    let mut v = vec![[c[0], c[1], c[2] + r]];
    for i in 1..stacks {
        let t = PI * i as f64 / stacks as f64;
        for j in 0..slices {
            let p = TAU * j as f64 / slices as f64;
            let d = [t.sin() * p.cos(), t.sin() * p.sin(), t.cos()];
            v.push([c[0] + r * d[0], c[1] + r * d[1], c[2] + r * d[2]]);
        }
    }
    v.push([c[0], c[1], c[2] - r]);
    let south = v.len() - 1;
    let at = |i: usize, j: usize| 1 + (i - 1) * slices + j % slices;
    let mut t = vec![];
    for j in 0..slices {
        t.push([0, at(1, j), at(1, j + 1)]);
    }
    for i in 1..stacks - 1 {
        for j in 0..slices {
            let (a, b, cc, d) = (at(i, j), at(i, j + 1), at(i + 1, j), at(i + 1, j + 1));
            t.push([a, cc, d]);
            t.push([a, d, b]);
        }
    }
    for j in 0..slices {
        t.push([south, at(stacks - 1, j + 1), at(stacks - 1, j)]);
    }
    let mut s = String::new();
    for p in &v {
        let _ = writeln!(s, "v {:.9} {:.9} {:.9}", p[0], p[1], p[2]);
    }
    for f in &t {
        let _ = writeln!(s, "f {} {} {}", f[0] + 1, f[1] + 1, f[2] + 1);
    }
    s
}
