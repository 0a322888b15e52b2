//! The one-pass reader against the `toml` crate: wherever [`plain_scene`] gives a scene,
//! `toml::from_str` gives the same one to the bit (compared through `Debug`, whose `f64` text
//! is the shortest that reads back to the same bits), and wherever `toml` refuses a text the
//! one-pass reader gives `None` (so `toml`'s message is the one the user sees).

use super::super::FileScene;
use super::{plain_number, plain_scene};

use ccrkit_test_support::scenes;

use crate::numeric::test_rng as rng;

/// Checks the rule on `text`; `Some(true)` when the one-pass reader read it.
fn agrees(text: &str) -> bool {
    let fast = plain_scene(text);
    let typed = toml::from_str::<FileScene>(text);
    match (&fast, &typed) {
        (Some(a), Ok(b)) => assert_eq!(format!("{a:?}"), format!("{b:?}"), "{text}"),
        (Some(a), Err(e)) => panic!("read {a:?} where toml says {e}:\n{text}"),
        (None, _) => {}
    }
    fast.is_some()
}

#[test]
fn every_toml_file_in_models_reads_as_toml_reads_it() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("models");
    let mut dirs = vec![root.clone()];
    let (mut files, mut read) = (0, vec![]);
    while let Some(dir) = dirs.pop() {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let p = entry.unwrap().path();
            if p.is_dir() {
                dirs.push(p);
            } else if p.extension().is_some_and(|e| e == "toml") {
                files += 1;
                if agrees(&std::fs::read_to_string(&p).unwrap()) {
                    let rel = p.strip_prefix(&root).unwrap();
                    read.push(rel.to_string_lossy().into_owned());
                }
            }
        }
    }
    assert!(files >= 10, "{files} TOML files found");
    read.sort();
    // Every scene file is read in one pass; the robot files are not scenes (toml refuses
    // them as a `FileScene` too).
    assert_eq!(
        read,
        [
            "plan/vessel.toml",
            "scenes/pillar.toml",
            "scenes/vessel.toml",
            "scenes/wall.toml",
            "soft/nodule.toml"
        ]
    );
}

#[test]
fn generated_scenes_read_as_toml_reads_them() {
    for n in [0, 1, 2, 3, 4, 5, 17, 1000] {
        for seed in [1, 7, 12345] {
            assert!(
                agrees(&scenes::scene_text(n, seed)),
                "{n} obstacles, seed {seed}"
            );
        }
    }
}

/// One obstacle line `line` after a plain sphere: read in one pass (`true`) or not.
fn one(line: &str) -> bool {
    agrees(&format!(
        "clearance = 0.0\n[[obstacles]]\nname = \"a\"\nshape = \"sphere\"\n{line}\n"
    ))
}

#[test]
fn the_plain_shape_in_all_its_spellings_is_read_in_one_pass() {
    for line in [
        "radius = 1",
        "radius = 0.01 # a comment",
        "radius = 1_0.0_1",
        "radius = 1e-2",
        "radius = 1E+2",
        "radius = +0.5",
        "radius = -0.0",
        "radius = 9007199254740993",
        "radius = 0.1000000000000000055511151231257827",
        "radius = inf",
        "radius = -nan",
        "\"radius\" = 0.01",
        "'radius' = 0.01",
        "position = [1, 2.5, -3e0]",
        "position = [\n  1.0, # x\n  2.0,\n  3.0,\n]",
        "rotation = { rpy = [0.1, 0.2, 0.3] }",
        "rotation = {rpy=[0.1,0.2,0.3]}",
        "rotation = { quaternion = [1, 0, 0, 0] }",
        "half_extents = [0.1, 0.2, 0.3]",
        "half_height = 0.2",
        "path = 'a\\b.obj'",
        "path = \"caf\\u00e9.obj\"",
        "path = \"\"\"x.obj\"\"\"",
        "scale = 2",
        "scale = [1.0, 2.0, 3.0]",
    ] {
        assert!(one(line), "{line}");
    }
    assert!(agrees(""));
    assert!(agrees("# nothing\n\nclearance = 1\n"));
    assert!(agrees(
        "[[obstacles]]\nshape = 'box'\n[[ obstacles ]]\nshape = 'x'\n"
    ));
    assert!(agrees("[[\"obstacles\"]]\nshape = \"box\"\r\n"));
}

#[test]
fn anything_else_is_left_to_toml() {
    for line in [
        "radius = 0x10",
        "radius = 0o7",
        "radius = 1e400",
        "radius = 99999999999999999999",
        "radius = 01.5",
        "radius = 1__0",
        "radius = true",
        "radius = 1979-05-27",
        "radius = \"big\"",
        "radius = [1.0]",
        "radius = 0.01\nradius = 0.02",
        "name = \"b\"",
        "nme = \"b\"",
        "position = [1.0, 2.0]",
        "position = [1.0, 2.0, 3.0, 4.0]",
        "position = [[1.0], 2.0, 3.0]",
        "position = [1.0, \"2\", 3.0]",
        "position = {}",
        "rotation = { rpy = [0.1, 0.2] }",
        "rotation = { quaternion = [1, 0, 0] }",
        "rotation = { rpy = [0.1, 0.2, 0.3], quaternion = [1, 0, 0, 0] }",
        "rotation = { Rpy = [0.1, 0.2, 0.3] }",
        "rotation = {}",
        "rotation = [0.1, 0.2, 0.3]",
        "rotation.rpy = [0.1, 0.2, 0.3]",
        "[obstacles.rotation]\nrpy = [0.1, 0.2, 0.3]",
        "[[obstacles.more]]\nshape = 'box'",
        "[other]",
        "clearance = 0.1",
        "scale = [1.0, 2.0]",
        "scale = 'big'",
        "radius = ",
        "radius = 0.01 0.02",
        "radius = 0.01\u{7}",
        "# \u{0}",
    ] {
        assert!(!one(line), "{line}");
    }
    for text in [
        "obstacles = []\n",
        "clearance = 0.1\nclearance = 0.2\n",
        "clearance = 'x'\n",
        "[[obstacles]]\nname = 'no shape'\n",
        "[[obstacles]]\n",
        "[[obstacles]]\nshape = 'box'\n[obstacles]\n",
        "[[obstacles]\nshape = 'box'\n",
        "x.y = 1\n",
    ] {
        assert!(!agrees(text), "{text}");
    }
}

#[test]
fn random_edits_of_a_scene_read_as_toml_reads_them() {
    let base = format!(
        "{}[[obstacles]]\nname = 'v'\nshape = \"mesh\"\npath = \"m.obj\"\nscale = [1, 2e0, 3.5]\n\
         rotation = {{ quaternion = [1.0, 0, 0, 0.5] }} # q\n",
        scenes::scene_text(4, 3)
    );
    assert!(agrees(&base));
    let palette = b"=[]{},.\"'#\n\r\t _-+0123456789eExinfabo:";
    let mut rng = rng::Rng(0x9e37_79b9_7f4a_7c15);
    let mut pick = |n: usize| ((rng.next() * n as f64) as usize).min(n - 1);
    let (mut read, mut left) = (0, 0);
    for _ in 0..4000 {
        let mut bytes = base.clone().into_bytes();
        for _ in 0..1 + pick(3) {
            let at = pick(bytes.len());
            let c = palette[pick(palette.len())];
            match pick(3) {
                0 => bytes[at] = c,
                1 => bytes.insert(at, c),
                _ => {
                    bytes.remove(at);
                }
            }
        }
        let text = String::from_utf8(bytes).expect("ASCII edits of ASCII text");
        if agrees(&text) {
            read += 1;
        } else {
            left += 1;
        }
    }
    // Both ways are exercised: edits that keep the plain shape, and edits that leave it.
    assert!(
        read > 500 && left > 500,
        "{read} read in one pass, {left} left to toml"
    );
}

#[test]
fn plainly_written_numbers_are_the_decoders_numbers() {
    #[derive(serde::Deserialize)]
    struct X {
        x: f64,
    }
    let toml_value = |s: &str| toml::from_str::<X>(&format!("x = {s}")).ok().map(|v| v.x);
    let mut texts: Vec<String> = [
        "0",
        "-0",
        "7",
        "-7",
        "00",
        "01",
        "-01",
        "0.5",
        "-0.0",
        "1.",
        ".5",
        "1e5",
        "1E-05",
        "1e+5",
        "1e",
        "1e+",
        "+1",
        "1_0",
        "1.5e400",
        "-1e400",
        "9223372036854775807",
        "9223372036854775808",
        "-9223372036854775808",
        "0.1e-400",
        "1.2.3",
        "--1",
        "1-2",
    ]
    .map(String::from)
    .to_vec();
    let mut rng = rng::Rng(12345);
    let alphabet = b"0123456789.-+eE_";
    for _ in 0..20_000 {
        let n = 1 + (rng.next() * 9.0) as usize;
        let t: Vec<u8> = (0..n)
            .map(|_| alphabet[((rng.next() * 16.0) as usize).min(15)])
            .collect();
        texts.push(String::from_utf8(t).unwrap());
        texts.push(format!(
            "{:?}",
            rng.range(-1e3, 1e3) * 10f64.powi((rng.next() * 40.0) as i32 - 20)
        ));
    }
    let mut plain = 0;
    for s in &texts {
        if let Some(x) = plain_number(s) {
            plain += 1;
            assert_eq!(toml_value(s).map(f64::to_bits), Some(x.to_bits()), "{s}");
        }
    }
    assert!(plain > 20_000, "{plain} of {} texts plain", texts.len());
}
