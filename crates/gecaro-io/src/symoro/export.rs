//! A robot as a SYMORO `.par` file (issue 74: every `--to` listed works),
//! read back by [`super::import_symoro`] to the same model.
//!
//! Frames 1..n are the joints, frame n+1 a fixed frame (σ = 2) on the last
//! joint; gecaro's frame 0 (θ0, r0) is frame 1's γ1, b1. A joint's variable
//! stands in its θ (revolute, `thj`) or r (prismatic, `rj`) with its
//! constant beside it: `th2 + 1.5707963267948966` is θ2 + offset2. What a
//! `.par` file cannot carry is said: Hayati's β is refused (no place in
//! eq. 3's parameters), gains and couplings go to the joint calibration
//! file, and joint limits are dropped with a note.

use std::fmt::Write as _;

use gecaro_core::FrameType;

use crate::conversion::Exported;
use crate::joint_calibration::numbered_joint_calibration;
use crate::robot_file::RobotFile;

/// A number as SYMORO reads it back to the same bits.
fn number(value: f64) -> String {
    format!("{value:?}")
}

/// `symbol + constant`, the constant left out when 0.
fn with_variable(symbol: &str, constant: f64) -> String {
    match constant {
        0.0 => symbol.to_owned(),
        c if c < 0.0 => format!("{symbol} - {}", number(-c)),
        c => format!("{symbol} + {}", number(c)),
    }
}

/// The `.par` text of `file`'s robot (see the module docs).
///
/// # Errors
/// A frame with β ≠ 0, naming it.
pub(crate) fn export_symoro(file: &RobotFile) -> Result<Exported, String> {
    let robot = &file.robot;
    let frames = robot.frames();
    let n = robot.joint_count();
    if let Some((j, frame)) = frames.iter().enumerate().find(|(_, f)| f.beta != 0.0) {
        return Err(format!(
            "frame {j} has beta = {} rad: Hayati's β has no place in a SYMORO file; export to \
             URDF instead",
            frame.beta
        ));
    }
    let list = |values: Vec<String>| format!("{{{}}}", values.join(","));
    let mut columns: [Vec<String>; 9] = Default::default();
    let [ant, sigma, b, d, r, gamma, alpha, mu, theta] = &mut columns;
    for j in 1..=n + 1 {
        let frame = &frames[j];
        ant.push((j - 1).to_string());
        sigma.push(frame.frame_type.sigma().to_string());
        // gecaro's frame 0 stands in front of frame 1 (γ1, b1).
        let (g, bb) = if j == 1 {
            (frames[0].theta, frames[0].r)
        } else {
            (0.0, 0.0)
        };
        gamma.push(number(g));
        b.push(number(bb));
        alpha.push(number(frame.alpha));
        d.push(number(frame.d));
        let offset = (j <= n).then(|| robot.joints()[j - 1].offset);
        match (frame.frame_type, offset) {
            (FrameType::Revolute, Some(offset)) => {
                theta.push(with_variable(&format!("th{j}"), frame.theta + offset));
                r.push(number(frame.r));
            }
            (FrameType::Prismatic, Some(offset)) => {
                theta.push(number(frame.theta));
                r.push(with_variable(&format!("r{j}"), frame.r + offset));
            }
            _ => {
                theta.push(number(frame.theta));
                r.push(number(frame.r));
            }
        }
        mu.push(u8::from(j <= n).to_string());
    }
    let mut text = String::new();
    let _ = writeln!(
        text,
        "(* Robotname = '{}' *)\n(* Written by gecaro robot export: Khalil–Kleinfinger \
         parameters, frame n+1 the end-effector (sigma = 2). *)",
        robot.name().replace("*)", "* )")
    );
    let _ = writeln!(
        text,
        "NL = {n}\nNJ = {n}\nNF = {}\nType = 0\nis_floating = 0\nis_mobile = 0\n",
        n + 1
    );
    let _ = writeln!(text, "(* Geometric parameters *)");
    for (name, values) in [
        "ant", "sigma", "b", "d", "r", "gamma", "alpha", "mu", "theta",
    ]
    .iter()
    .zip(columns)
    {
        let _ = writeln!(text, "{name} = {}", list(values));
    }
    let _ = writeln!(
        text,
        "\n(* Transformation of 0 frame position fT0 *)\nZ = {{1,0,0,0,0,1,0,0,0,0,1,0,0,0,0,1}}\n\n\
         (* End of definition *)"
    );
    let mut notes = vec![
        "a .par file has no joint limits: they are not written (import gives the defaults)"
            .to_owned(),
    ];
    let joint_calibration =
        numbered_joint_calibration(robot, ("SYMORO file", "a SYMORO file"), &mut notes);
    Ok(Exported {
        text,
        joint_calibration,
        notes,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    /// Every ready robot without β, written and read back: the same poses.
    #[test]
    fn a_written_par_file_reads_back_to_the_same_robot() {
        let mut written = Vec::new();
        for name in ["stanford", "puma560", "industrial6", "scara", "ur10e"] {
            let file = crate::load_robot(name).expect("ready");
            if file.robot.frames().iter().any(|frame| frame.beta != 0.0) {
                assert!(export_symoro(&file).expect_err("β").contains("Hayati"));
                continue;
            }
            written.push(name);
            let exported = export_symoro(&file).expect("written");
            let imported =
                super::super::import_symoro(&exported.text, Path::new("robot.par")).expect("read");
            let back = imported.file.robot;
            let n = file.robot.joint_count();
            for k in 0..5 {
                let qm: Vec<f64> = (0..n)
                    .map(|j| 0.3 * f64::from(k) - 0.2 * j as f64)
                    .collect();
                let (a, b) = (
                    gecaro_core::terminal_pose(&file.robot, &qm).expect("pose"),
                    gecaro_core::terminal_pose(&back, &qm).expect("pose"),
                );
                assert!(
                    (a.to_homogeneous() - b.to_homogeneous()).norm() < 1e-12,
                    "{name}: {}",
                    exported.text
                );
            }
        }
        assert!(written.len() >= 3, "{written:?}");
    }
}
