//! A generator of large obstacle scenes, shared by the contact and file tests
//! (`obstacles`, `scene_json`), the TOML scene reader's unit tests and `benches/scene.rs`.

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
