//! Outputs that would clobber inputs: every command's output named as one of the same run's
//! inputs — directly, through a symbolic or a hard link, or as another output of the run — is
//! refused by name before any work, and the input is left byte for byte as it was; so is an
//! output onto a file a model or a scene names (a scene file, a mesh).

use crate::common::adversarial_harness::cli::ccrkit_in;
use crate::common::adversarial_harness::{root, scratch};
use std::path::{Path, PathBuf};

/// A scratch folder holding a copy of paper case 1 (`M.toml`), the wall scene (`wall.toml`), a
/// copy of it named `scene.svg`, a plan file (`plan.json`) and two rows of hardware data (`d.csv`).
fn fixtures(name: &str) -> PathBuf {
    let dir = scratch(&format!("outputs-{name}"));
    let copy = |from: &str, to: &str| {
        std::fs::copy(root().join(from), dir.join(to)).expect("copy fixture");
    };
    copy("models/paper/case1.toml", "M.toml");
    copy("models/scenes/wall.toml", "wall.toml");
    copy("models/scenes/wall.toml", "scene.svg");
    copy("models/hardware/ftdcr_v4.toml", "v4.toml");
    std::fs::write(dir.join("plan.json"), "{\"waypoints\": []}").expect("plan");
    let data = std::fs::read_to_string(
        root().join("models/hardware/data/v4/tdcr_sysid_20260511-183002_train.csv"),
    )
    .expect("hardware data");
    let rows: Vec<&str> = data.lines().take(3).collect();
    std::fs::write(dir.join("d.csv"), rows.join("\n")).expect("data");
    dir
}

/// Run `args` in `dir`: it must exit 1 with an error naming the refusal (`says`), and every file
/// of `dir` must be unchanged.
fn refused(dir: &Path, args: &[&str], says: &str) {
    let before = snapshot(dir);
    let out = ccrkit_in(dir, args);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{args:?}: {err}");
    assert!(
        err.contains("cannot write") && err.contains(says),
        "{args:?}: {err}"
    );
    assert_eq!(snapshot(dir), before, "{args:?} changed a file");
}

/// Every file of `dir` and its subfolders with its bytes, sorted by path.
fn snapshot(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut v = Vec::new();
    for e in std::fs::read_dir(dir)
        .expect("lists")
        .filter_map(|e| e.ok())
    {
        let p = e.path();
        let name = e.file_name().to_string_lossy().into_owned();
        if p.is_dir() {
            let inner = snapshot(&p).into_iter();
            v.extend(inner.map(|(n, b)| (format!("{name}/{n}"), b)));
        } else if p.is_file() {
            v.push((name, std::fs::read(&p).expect("reads")));
        }
    }
    v.sort();
    v
}

const OVER: &str = "would be overwritten";

#[test]
fn an_output_onto_an_input_of_the_same_run_is_refused_by_name() {
    let dir = fixtures("inputs");
    refused(&dir, &["view", "M.toml", "--out", "M.toml"], OVER);
    let cases: &[&[&str]] = &[
        &["export", "urdf", "M.toml", "--out", "M.toml"],
        &[
            "export", "urdf", "M.toml", "--mode", "fixed", "--out", "M.toml",
        ],
        &["solve", "--json", "M.toml", "M.toml"],
        &[
            "solve",
            "M.toml",
            "--plot",
            "scene.svg",
            "--scene",
            "scene.svg",
        ],
        &[
            "view",
            "M.toml",
            "--scene",
            "wall.toml",
            "--out",
            "wall.toml",
        ],
        &[
            "view",
            "M.toml",
            "--plan",
            "plan.json",
            "--out",
            "plan.json",
        ],
        &["view", "M.toml", "--out", "./sub/../M.toml"],
        &[
            "compare",
            "M.toml",
            "--plot",
            "scene.svg",
            "--scene",
            "scene.svg",
        ],
        &["reach", "M.toml", "--tip", "0,0,0.1", "--json", "M.toml"],
        &["plan", "M.toml", "--to-tip", "0,0,0.1", "--json", "M.toml"],
        &[
            "plan",
            "M.toml",
            "--to-actuation",
            "plan.json",
            "--trajectory",
            "plan.json",
        ],
        &[
            "roadmap",
            "build",
            "M.toml",
            "--scene",
            "wall.toml",
            "--out",
            "wall.toml",
        ],
        &["predict", "v4.toml", "--data", "d.csv", "--out", "d.csv"],
        &["predict", "v4.toml", "--data", "d.csv", "--out", "v4.toml"],
        &[
            "calibrate",
            "v4.toml",
            "--data",
            "d.csv",
            "--out",
            "v4.toml",
        ],
        &["study", "merge", "d.csv", "d.csv"],
        // A roadmap or an actuation file the planner reads, a shard a merge reads.
        &[
            "plan",
            "M.toml",
            "--to-tip",
            "0,0,0.1",
            "--roadmap",
            "plan.json",
            "--json",
            "plan.json",
        ],
        &[
            "plan",
            "M.toml",
            "--to-tip",
            "0,0,0.1",
            "--from-actuation",
            "plan.json",
            "--trajectory",
            "./plan.json",
        ],
        &[
            "roadmap",
            "merge",
            "wall.toml",
            "plan.json",
            "--out",
            "plan.json",
        ],
    ];
    for args in cases {
        refused(&dir, args, OVER);
    }
}

#[cfg(unix)]
#[test]
fn links_to_an_input_are_the_input() {
    let dir = fixtures("links");
    std::os::unix::fs::symlink(dir.join("M.toml"), dir.join("sym.toml")).expect("symlink");
    std::fs::hard_link(dir.join("d.csv"), dir.join("hard.csv")).expect("hard link");
    refused(&dir, &["view", "M.toml", "--out", "sym.toml"], OVER);
    refused(&dir, &["solve", "sym.toml", "--json", "M.toml"], OVER);
    refused(
        &dir,
        &["predict", "v4.toml", "--data", "d.csv", "--out", "hard.csv"],
        OVER,
    );
}

/// `--out a.srdf` in articulated mode would put the URDF and the SRDF on one file: refused
/// before either is written (the URDF was lost and `wrote a.srdf` printed twice).
#[test]
fn two_outputs_of_one_run_on_one_file_are_refused() {
    let dir = fixtures("twice");
    refused(
        &dir,
        &["export", "urdf", "M.toml", "--out", "a.srdf"],
        "same file as the URDF",
    );
    refused(
        &dir,
        &["solve", "M.toml", "--json", "s.svg", "--plot", "s.svg"],
        "same file",
    );
    assert!(!dir.join("a.srdf").exists() && !dir.join("s.svg").exists());
    // Fixed mode writes the URDF alone: `a.srdf` is then a fine name.
    let out = ccrkit_in(
        &dir,
        &[
            "export", "urdf", "M.toml", "--mode", "fixed", "--out", "a.srdf",
        ],
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// Every output creates its missing folders alike (`export` did, `view` refused them), and
/// leaves no temporary file beside it.
#[test]
fn every_output_creates_its_folder_and_leaves_no_temporary_file() {
    let dir = fixtures("folders");
    for (args, file) in [
        (
            vec!["view", "M.toml", "--out", "new1/v.html"],
            "new1/v.html",
        ),
        (
            vec!["solve", "M.toml", "--json", "new2/s.json"],
            "new2/s.json",
        ),
        (
            vec!["export", "urdf", "M.toml", "--out", "new3/a.urdf"],
            "new3/a.urdf",
        ),
        (
            vec!["solve", "M.toml", "--plot", "new4/s.svg"],
            "new4/s.svg",
        ),
    ] {
        let out = ccrkit_in(&dir, &args);
        assert!(
            out.status.success(),
            "{args:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let p = dir.join(file);
        assert!(p.metadata().expect("written").len() > 0, "{file}");
        let folder = p.parent().expect("folder");
        for e in std::fs::read_dir(folder).expect("lists") {
            let name = e.expect("entry").file_name().to_string_lossy().into_owned();
            assert!(!name.starts_with(".ccrkit-"), "{name} left in {folder:?}");
        }
    }
}

/// A tetrahedron 1 m from the robot, as ASCII STL, OBJ and PLY.
fn tetrahedron(dir: &Path) {
    let v = [
        [1.0, 1.0, 1.0],
        [1.1, 1.0, 1.0],
        [1.0, 1.1, 1.0],
        [1.0, 1.0, 1.1],
    ];
    let f = [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]];
    let mut stl = String::from("solid t\n");
    for t in f {
        stl += "facet normal 0 0 0\nouter loop\n";
        for k in t {
            let p = v[k];
            stl += &format!("vertex {} {} {}\n", p[0], p[1], p[2]);
        }
        stl += "endloop\nendfacet\n";
    }
    stl += "endsolid t\n";
    let vs: String = v
        .iter()
        .map(|p| format!("{} {} {}\n", p[0], p[1], p[2]))
        .collect();
    let obj = v.iter().map(|p| format!("v {} {} {}\n", p[0], p[1], p[2]));
    let obj: String = obj
        .chain(
            f.iter()
                .map(|t| format!("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1)),
        )
        .collect();
    let ply = format!(
        "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n\
         element face 4\nproperty list uchar int vertex_indices\nend_header\n{vs}{}",
        f.iter().map(|t| format!("3 {} {} {}\n", t[0], t[1], t[2])).collect::<String>()
    );
    std::fs::create_dir_all(dir.join("meshes")).expect("dir");
    std::fs::write(dir.join("meshes/tet.stl"), stl).expect("stl");
    std::fs::write(dir.join("meshes/tet.obj"), obj).expect("obj");
    std::fs::write(dir.join("meshes/tet.ply"), ply).expect("ply");
}

/// [`fixtures`] plus files a model or a scene names: `N.toml` is case 1 naming
/// `scenes/room.toml` (whose obstacle is the mesh `../meshes/tet.obj`) and holding an obstacle
/// of its own, the mesh `meshes/tet.stl`; `extra.toml` is a scene of the mesh `meshes/tet.ply`.
fn named_fixtures(name: &str) -> PathBuf {
    let dir = fixtures(name);
    tetrahedron(&dir);
    std::fs::create_dir_all(dir.join("scenes")).expect("dir");
    let mesh = |name: &str, path: &str| {
        format!("[[obstacles]]\nname = \"{name}\"\nshape = \"mesh\"\npath = \"{path}\"\n")
    };
    std::fs::write(
        dir.join("scenes/room.toml"),
        mesh("room", "../meshes/tet.obj"),
    )
    .expect("scene");
    std::fs::write(dir.join("extra.toml"), mesh("extra", "meshes/tet.ply")).expect("scene");
    let case1 = std::fs::read_to_string(dir.join("M.toml")).expect("model");
    let model = format!(
        "scene = \"scenes/room.toml\"\n{case1}\n{}",
        mesh("own", "meshes/tet.stl")
    );
    std::fs::write(dir.join("N.toml"), model).expect("model");
    dir
}

/// The files a model or a scene names — the scene file a model names, the STL/OBJ/PLY meshes
/// its obstacles or a `--scene` file's name — are inputs of the run too: an output onto one of
/// them (directly, through `..` or a link) is refused by naming the file and what it is, and
/// nothing is written (they were overwritten, exit 0).
#[test]
fn an_output_onto_a_file_the_model_or_scene_names_is_refused_by_name() {
    let dir = named_fixtures("named");
    let ok = ccrkit_in(&dir, &["solve", "N.toml", "--scene", "extra.toml"]);
    assert!(
        ok.status.success(),
        "{}",
        String::from_utf8_lossy(&ok.stderr)
    );
    let own = "the mesh file of obstacle `own`";
    let room = "the mesh file of obstacle `room`";
    let scene = "the scene file named in the model";
    let cases: &[(&[&str], &str)] = &[
        (&["view", "N.toml", "--out", "meshes/tet.stl"], own),
        (&["view", "N.toml", "--out", "scenes/room.toml"], scene),
        (
            &["view", "N.toml", "--out", "scenes/../meshes/tet.obj"],
            room,
        ),
        (
            &["export", "urdf", "N.toml", "--out", "meshes/tet.obj"],
            room,
        ),
        (
            &[
                "export",
                "urdf",
                "N.toml",
                "--mode",
                "fixed",
                "--out",
                "./scenes/room.toml",
            ],
            scene,
        ),
        (&["solve", "N.toml", "--json", "meshes/tet.stl"], own),
        (&["solve", "N.toml", "--json", "./scenes/room.toml"], scene),
        (
            &[
                "solve",
                "M.toml",
                "--scene",
                "extra.toml",
                "--json",
                "meshes/tet.ply",
            ],
            "obstacle `extra`",
        ),
        (
            &[
                "view",
                "M.toml",
                "--scene",
                "extra.toml",
                "--out",
                "meshes/../meshes/tet.ply",
            ],
            "obstacle `extra`",
        ),
        (&["compare", "N.toml", "--json", "meshes/tet.stl"], own),
        (
            &[
                "reach",
                "N.toml",
                "--tip",
                "0,0,0.1",
                "--json",
                "scenes/room.toml",
            ],
            scene,
        ),
        (
            &[
                "plan",
                "N.toml",
                "--to-tip",
                "0,0,0.1",
                "--trajectory",
                "meshes/tet.obj",
            ],
            room,
        ),
        (
            &["roadmap", "build", "N.toml", "--out", "meshes/tet.stl"],
            own,
        ),
    ];
    for (args, says) in cases {
        refused(&dir, args, says);
        refused(&dir, args, OVER);
    }
    #[cfg(unix)]
    {
        std::os::unix::fs::symlink(dir.join("meshes/tet.stl"), dir.join("link.stl")).expect("link");
        refused(&dir, &["view", "N.toml", "--out", "link.stl"], own);
    }
}

/// Generated: every command that writes (`view`, `export urdf` in both modes, `solve --json`,
/// `compare --json`, `reach --json`, `plan --json`, `plan --trajectory`, `roadmap build`) ×
/// every file the run reads (the model, a `--scene` file, the scene file the model names, the
/// STL/OBJ/PLY meshes named inline, in that scene and in `--scene`) × every spelling of it (as
/// given, `./`, through a folder and `..`, absolute, a symbolic link, a hard link): each run
/// is refused with `would be overwritten` before anything is written, under a budget, and no
/// file of the folder changes.
#[test]
fn every_writer_onto_every_input_in_every_spelling_is_refused() {
    use crate::common::adversarial_harness::run_all;
    let dir = named_fixtures("matrix");
    let writers: &[&[&str]] = &[
        &["view", "N.toml", "--scene", "extra.toml", "--out"],
        &["export", "urdf", "N.toml", "--scene", "extra.toml", "--out"],
        &[
            "export",
            "urdf",
            "N.toml",
            "--scene",
            "extra.toml",
            "--mode",
            "fixed",
            "--out",
        ],
        &["solve", "N.toml", "--scene", "extra.toml", "--json"],
        &["compare", "N.toml", "--scene", "extra.toml", "--json"],
        &[
            "reach",
            "N.toml",
            "--tip",
            "0,0,0.1",
            "--scene",
            "extra.toml",
            "--json",
        ],
        &[
            "plan",
            "N.toml",
            "--to-tip",
            "0,0,0.1",
            "--scene",
            "extra.toml",
            "--json",
        ],
        &[
            "plan",
            "N.toml",
            "--to-tip",
            "0,0,0.1",
            "--scene",
            "extra.toml",
            "--trajectory",
        ],
        &[
            "roadmap",
            "build",
            "N.toml",
            "--scene",
            "extra.toml",
            "--out",
        ],
    ];
    let inputs = [
        "N.toml",
        "extra.toml",
        "scenes/room.toml",
        "meshes/tet.stl",
        "meshes/tet.obj",
        "meshes/tet.ply",
    ];
    std::fs::create_dir_all(dir.join("links")).expect("dir");
    let mut spellings = Vec::new();
    for (k, f) in inputs.iter().enumerate() {
        let abs = dir.join(f).display().to_string();
        let link = format!("links/s{k}");
        let hard = format!("links/h{k}");
        #[cfg(unix)]
        {
            std::os::unix::fs::symlink(dir.join(f), dir.join(&link)).expect("symlink");
            std::fs::hard_link(dir.join(f), dir.join(&hard)).expect("hard link");
        }
        spellings.extend([
            f.to_string(),
            format!("./{f}"),
            format!("links/../{f}"),
            abs,
        ]);
        if cfg!(unix) {
            spellings.extend([link, hard]);
        }
    }
    let before = snapshot(&dir);
    let mut jobs = Vec::new();
    for w in writers {
        for out in &spellings {
            let mut a: Vec<String> = w.iter().map(|s| s.to_string()).collect();
            a.push(out.clone());
            jobs.push((a, None));
        }
    }
    let n = jobs.len();
    let t = run_all(&dir, jobs.clone(), std::time::Duration::from_secs(60));
    t.report_and_assert("outputs onto inputs");
    assert_eq!((t.runs, t.named), (n, n), "every run refused: {t:?}");
    assert_eq!(snapshot(&dir), before, "a refused run changed a file");
    // Named, and named as this refusal (not another error on the way).
    for (a, _) in jobs.iter().step_by(7) {
        let out = ccrkit_in(&dir, a);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains(OVER), "{a:?}: {err}");
    }
    println!(
        "outputs onto inputs: {n} runs ({} writers × {} spellings)",
        writers.len(),
        spellings.len()
    );
}

/// The studies write fixed names into their `--out` folder (`workspace.csv`, `stability.csv`,
/// `stability_METHOD.svg`, `speed_accuracy.png`, …): a model file, or the scene file a model
/// names, that is one of those files — directly, through `..`, a symbolic link to the folder or
/// a hard link — or an `--out` folder that is the model file itself, is refused by name before
/// any work, and nothing changes (the study overwrote the model with its CSV, exit 0).
#[test]
fn a_study_folder_onto_an_input_is_refused_by_name() {
    let dir = fixtures("studies");
    std::fs::create_dir_all(dir.join("st")).expect("dir");
    std::fs::copy(dir.join("M.toml"), dir.join("st/workspace.csv")).expect("model");
    std::fs::copy(dir.join("M.toml"), dir.join("st/speed_accuracy.svg")).expect("model");
    std::fs::copy(dir.join("wall.toml"), dir.join("st/stability.csv")).expect("scene");
    let case1 = std::fs::read_to_string(dir.join("M.toml")).expect("model");
    std::fs::write(
        dir.join("S.toml"),
        format!("scene = \"st/stability.csv\"\n{case1}"),
    )
    .expect("model naming a scene");
    let ws = ["--samples", "2", "--method", "geometric"];
    let model = "the model file";
    let scene = "the scene file named in the model";
    let mut cases: Vec<(Vec<&str>, &str)> = vec![
        (
            vec!["study", "workspace", "st/workspace.csv", "--out", "st"],
            model,
        ),
        (
            vec!["study", "workspace", "st/workspace.csv", "--out", "x/../st"],
            model,
        ),
        (
            vec!["study", "workspace", "M.toml", "--out", "M.toml"],
            model,
        ),
        (
            vec![
                "study",
                "stability",
                "S.toml",
                "--out",
                "st",
                "--grid",
                "2",
                "--methods",
                "geometric",
            ],
            scene,
        ),
        (
            vec![
                "study",
                "speed-accuracy",
                "st/speed_accuracy.svg",
                "--out",
                "./st/",
                "--repeats",
                "1",
                "--methods",
                "geometric",
            ],
            model,
        ),
    ];
    #[cfg(unix)]
    {
        std::os::unix::fs::symlink(dir.join("st"), dir.join("lnk")).expect("symlink");
        std::fs::create_dir_all(dir.join("hl")).expect("dir");
        std::fs::hard_link(dir.join("M.toml"), dir.join("hl/stability_geometric.svg"))
            .expect("hard link");
        cases.push((
            vec!["study", "workspace", "st/workspace.csv", "--out", "lnk"],
            model,
        ));
        cases.push((
            vec![
                "study",
                "stability",
                "M.toml",
                "--out",
                "hl",
                "--grid",
                "2",
                "--methods",
                "geometric",
            ],
            model,
        ));
    }
    for (mut args, says) in cases {
        if args[1] == "workspace" {
            args.extend(ws);
        }
        refused(&dir, &args, says);
        refused(&dir, &args, OVER);
    }
}
