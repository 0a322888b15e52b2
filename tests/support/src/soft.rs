//! The soft lung rod (`models/soft/lung_rod.toml`) at another station count and with its
//! three tendons pulled: the 24-section, tension-driven robot the unloaded rod is measured on
//! (`tests/methods/cosserat_unloaded.rs`, `benches/cosserat.rs`).

/// The lung rod's model file with `sections` stations over its 0.12 m, its port removed
/// (the rod alone), and the tensions `[straight, helix_plus, helix_minus]` \[N\].
pub fn lung_rod_toml(sections: usize, tensions: [f64; 3]) -> String {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../models/soft/lung_rod.toml");
    let text = std::fs::read_to_string(path).expect("the committed lung rod");
    let mut out = String::new();
    let mut cable = 0;
    for line in text.lines() {
        if line.starts_with("[port]") {
            break;
        }
        let line = if line.starts_with("sections =") {
            format!("sections = {sections}")
        } else if line.starts_with("section_length =") {
            format!("section_length = {:e}", 0.12 / sections as f64)
        } else if line.starts_with("tension =") && !line.contains('[') {
            cable += 1;
            format!("tension = {:e}", tensions[cable - 1])
        } else {
            line.to_string()
        };
        out.push_str(&line);
        out.push('\n');
    }
    out
}
