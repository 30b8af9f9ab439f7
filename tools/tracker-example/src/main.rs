//! Writes `examples/tracker/`: the KUKA KR 16-2 of its URDF, a simulated
//! "real" one (±3 mm, ±0.3°, ±0.3 % off the URDF), and what a calibration
//! cell would give: a laser-tracker export of the flange point (millimetres,
//! with time stamps and point names) beside the controller's joint angles
//! (degrees, KUKA's A1..A6), a held-out check set, and a job of joint targets
//! to correct.
//!
//! ```sh
//! cargo run -p tracker-example -- tests/data/urdf examples/tracker examples/owner-base
//! ```
//!
//! The third folder, when given, receives the same robot in its owner's
//! cell ([`owner`]).

use gecaro_calib::simulation::{Sampler, perturbed_robot};
use gecaro_core::{Robot, terminal_pose};
use gecaro_io::{
    ImportOptions, OutputPolicy, RobotFile, format_robot_file, import_robot, write_atomically,
};
use std::error::Error;
use std::fmt::Write as _;
use std::path::Path;

mod owner;

type Result<T> = std::result::Result<T, Box<dyn Error>>;

/// The tracker's standard deviation per axis (m).
const TRACKER_SIGMA: f64 = 2e-5;
/// Error level of the simulated real robot (1 = ±1 cm, ±1°, ±1 %).
const ERROR_LEVEL: f64 = 0.3;

/// A configuration in the working region of the arm (degrees), away from
/// the folded and singular ones: what a calibration plan visits.
fn working_configuration(sampler: &mut Sampler) -> [f64; 6] {
    let wrist = if sampler.uniform(0.0, 1.0) < 0.5 {
        1.0
    } else {
        -1.0
    };
    [
        sampler.uniform(-70.0, 70.0),
        sampler.uniform(-120.0, -45.0),
        sampler.uniform(30.0, 120.0),
        sampler.uniform(-150.0, 150.0),
        wrist * sampler.uniform(20.0, 110.0),
        sampler.uniform(-170.0, 170.0),
    ]
}

fn radians(degrees: &[f64; 6]) -> Vec<f64> {
    degrees.iter().map(|d| d.to_radians()).collect()
}

/// Rows as the tracker software exports them, joined with the controller's angles.
fn tracker_file(
    real: &Robot,
    count: usize,
    sampler: &mut Sampler,
    first_point: usize,
) -> Result<String> {
    let mut text = String::from(
        "# Laser tracker export (positions in mm, tracker frame) joined with the controller log (A1..A6 in degrees)\n\
         Time_s,Point,A1,A2,A3,A4,A5,A6,X,Y,Z\n",
    );
    for index in 0..count {
        let angles = working_configuration(sampler).map(|a| (a * 1e4).round() / 1e4);
        let point = terminal_pose(real, &radians(&angles))?.translation.vector
            + sampler.gaussian_vector(TRACKER_SIGMA);
        let time = 6.5 * index as f64 + sampler.uniform(0.0, 0.5);
        let _ = writeln!(
            text,
            "{time:.2},P{:03},{},{:.4},{:.4},{:.4}",
            first_point + index,
            angles.map(|a| format!("{a:.4}")).join(","),
            point.x * 1e3,
            point.y * 1e3,
            point.z * 1e3
        );
    }
    Ok(text)
}

/// Points whose measurement went wrong in `tracker_corrupted.csv`, with the
/// error (mm): the beam broken and the tracker re-locked on a reflector
/// elsewhere, or a point taken while the arm still moved.
const GROSS_ERRORS: [(&str, [f64; 3]); 4] = [
    ("P009", [24.0, -11.5, 6.0]),
    ("P027", [-3.5, 18.0, -9.0]),
    ("P044", [0.8, -0.6, 31.0]),
    ("P068", [-12.0, -7.5, -4.0]),
];

/// `tracker` with the [`GROSS_ERRORS`] added to their rows (other rows unchanged).
fn corrupted(tracker: &str) -> String {
    let mut text = String::new();
    for line in tracker.lines() {
        let fields: Vec<&str> = line.split(',').collect();
        let error = fields
            .get(1)
            .and_then(|point| GROSS_ERRORS.iter().find(|(name, _)| name == point));
        match error {
            Some((_, offset)) if fields.len() == 11 => {
                let moved: Vec<String> = fields[8..]
                    .iter()
                    .zip(offset)
                    .map(|(value, offset)| {
                        format!("{:.4}", value.parse::<f64>().unwrap_or(f64::NAN) + offset)
                    })
                    .collect();
                let _ = writeln!(text, "{},{}", fields[..8].join(","), moved.join(","));
            }
            _ => {
                let _ = writeln!(text, "{line}");
            }
        }
    }
    text
}

fn main() -> Result<()> {
    let arguments: Vec<String> = std::env::args().collect();
    let (source, output, owner) = match arguments.as_slice() {
        [_, source, output] => (source, output, None),
        [_, source, output, owner] => (source, output, Some(owner)),
        _ => {
            eprintln!("usage: tracker-example URDF_FOLDER OUTPUT_FOLDER [OWNER_FOLDER]");
            std::process::exit(2);
        }
    };
    let (source, output) = (Path::new(source), Path::new(output));
    std::fs::create_dir_all(output)?;
    let write = |name: &str, text: &str| {
        write_atomically(&output.join(name), text.as_bytes(), OutputPolicy::Overwrite)
    };
    let urdf = std::fs::read_to_string(source.join("kuka_kr16_2.urdf"))?;
    write("kr16_2.urdf", &urdf)?;
    write(
        "LICENSE-kuka_experimental-Apache-2.0",
        &std::fs::read_to_string(source.join("LICENSE-kuka_experimental-Apache-2.0"))?,
    )?;
    let nominal = import_robot(&output.join("kr16_2.urdf"), &ImportOptions::default())?
        .file
        .robot;
    let mut sampler = Sampler::new(11);
    let real = perturbed_robot(&nominal, ERROR_LEVEL, &mut sampler)?;
    write(
        "real.toml",
        &format_robot_file(&RobotFile {
            description: Some(format!(
                "the simulated real KR 16-2 behind tracker.csv (error level {ERROR_LEVEL}, seed 11): the truth, for checking"
            )),
            ..RobotFile::of(real.clone())
        }),
    )?;
    let tracker = tracker_file(&real, 80, &mut sampler, 1)?;
    write("tracker.csv", &tracker)?;
    write("tracker_corrupted.csv", &corrupted(&tracker))?;
    write("check.csv", &tracker_file(&real, 40, &mut sampler, 101)?)?;
    let mut job = String::from(
        "# A job of joint targets (degrees), as taught on the nominal model\nPoint,A1,A2,A3,A4,A5,A6,Speed_pct\n",
    );
    for index in 0..30 {
        let angles = working_configuration(&mut sampler);
        let _ = writeln!(
            job,
            "J{:02},{},{}",
            index + 1,
            angles.map(|a| format!("{a:.3}")).join(","),
            [20, 50, 100][index % 3]
        );
    }
    write("job.csv", &job)?;
    println!("wrote {}", output.display());
    if let Some(owner) = owner {
        let owner = Path::new(owner);
        std::fs::create_dir_all(owner)?;
        let write_owner = |name: &str, text: &str| -> Result<()> {
            Ok(write_atomically(
                &owner.join(name),
                text.as_bytes(),
                OutputPolicy::Overwrite,
            )?)
        };
        write_owner("kr16_2.urdf", &urdf)?;
        write_owner(
            "LICENSE-kuka_experimental-Apache-2.0",
            &std::fs::read_to_string(source.join("LICENSE-kuka_experimental-Apache-2.0"))?,
        )?;
        owner::write_owner_cell(&nominal, &write_owner)?;
        println!("wrote {}", owner.display());
    }
    Ok(())
}
