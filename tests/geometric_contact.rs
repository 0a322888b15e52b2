//! `geometric-squared` next to obstacles: it keeps the contact tolerance of before issue 16
//! (1e-7 on the step), because with the literal method's 1e-11 its pillar solve certified no
//! candidate in section 5. Both contact scenes must solve, with the contacts of before.

use ccrkit::method::geometric::Geometric;
use ccrkit::{Method, Model, Scene};
use std::path::Path;

fn file(rel: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(rel)
}

#[test]
fn squared_objective_solves_the_contact_scenes() {
    let model = Model::from_file(file("models/paper/case1.toml")).unwrap();
    for (scene, disks) in [("wall", vec![8, 9]), ("pillar", vec![5, 6])] {
        let scene_model = Scene::from_file(file(&format!("models/scenes/{scene}.toml"))).unwrap();
        let s = Geometric::squared()
            .solve(&model.robot, &model.actuation, &scene_model, None)
            .unwrap_or_else(|e| panic!("{scene}: {e}"));
        let touching: Vec<usize> = s.contacts.iter().filter_map(|c| c.disk).collect();
        assert_eq!(touching, disks, "{scene}");
    }
}
