//! Print random robot SEED's model file (`ccrkit::study::random`): the robots the auto study
//! and the estimate's calibration run on, to solve one by hand.
//! `cargo run --release --example random_robot -- 105 > robot.toml`

fn main() {
    let seed = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(0);
    print!("{}", ccrkit::study::random::random_robot_toml(seed));
}
