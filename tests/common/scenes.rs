//! A generator of large obstacle scenes, shared by `tests/obstacles.rs` and
//! `benches/scene.rs` (included with `#[path]`, so it depends on nothing but std).
#![allow(dead_code)]

/// The text of a scene file with `n` obstacles, cycling sphere, box, capsule and cylinder, at
/// deterministic pseudo-random places (xorshift64, `seed`) in a shell of radii 1–2 m around
/// the base, each with a roll–pitch–yaw rotation and full-precision numbers — the file a
/// program that exports a cluttered environment would write. Names are `o0`, `o1`, …
pub fn scene_text(n: usize, seed: u64) -> String {
    let mut state = seed | 1;
    let mut rnd = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut text = String::from("clearance = 0.0\n");
    for k in 0..n {
        let (th, rad, z) = (
            rnd() * std::f64::consts::TAU,
            1.0 + rnd(),
            3.0 * rnd() - 1.0,
        );
        let rpy = [rnd(), rnd(), rnd()];
        let size = match k % 4 {
            0 => "shape = \"sphere\"\nradius = 0.01".to_string(),
            1 => "shape = \"box\"\nhalf_extents = [0.01, 0.02, 0.03]".to_string(),
            2 => "shape = \"capsule\"\nradius = 0.01\nhalf_height = 0.02".to_string(),
            _ => "shape = \"cylinder\"\nradius = 0.01\nhalf_height = 0.02".to_string(),
        };
        text += &format!(
            "[[obstacles]]\nname = \"o{k}\"\n{size}\nposition = [{:?}, {:?}, {z:?}]\n\
             rotation = {{ rpy = [{:?}, {:?}, {:?}] }}\n",
            rad * th.cos(),
            rad * th.sin(),
            rpy[0],
            rpy[1],
            rpy[2]
        );
    }
    text
}
