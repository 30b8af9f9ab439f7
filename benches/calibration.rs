//! Benchmarks of gecaro's calibration functions (`cargo bench`).
//! Figures and how to read them: docs/performance.md.

use gecaro_calib::{Plane, STANFORD_PLANE_POINT, TABLE2_PLANE_NORMAL, table2};
use nalgebra::Vector3;

fn main() {
    divan::main();
}

/// The paper's Table 2 for the Stanford arm: all nine columns, random
/// configurations (including the inverse-model solves of the link and plane
/// methods) and nine rank analyses.
#[divan::bench]
fn table2_stanford(bencher: divan::Bencher) {
    let robot = gecaro_io::load_robot("stanford")
        .expect("ready robot")
        .robot;
    let plane = Plane::new(
        Vector3::from(TABLE2_PLANE_NORMAL),
        Vector3::from(STANFORD_PLANE_POINT),
    )
    .expect("plane");
    let priority = robot.priority();
    bencher.bench_local(|| table2(&robot, plane, &priority, 1).expect("table 2"));
}
