//! The command line, declared with clap.

use std::path::PathBuf;

use clap::{Parser, Subcommand};

mod calibration_args;
mod cell_args;
mod common;
mod iso9283_args;
mod robot_args;

pub(crate) use calibration_args::*;
pub(crate) use cell_args::*;
pub(crate) use common::*;
pub(crate) use iso9283_args::*;
pub(crate) use robot_args::*;

/// Geometric calibration of serial robots (GECARO, Khalil et al.).
///
/// ROBOT arguments are a robot file (TOML) or the name of a ready robot:
/// stanford, puma560, industrial6, scara, panda, ur10e.
#[derive(Debug, Parser)]
#[command(name = "gecaro", version, about, long_about = None, propagate_version = true)]
pub(crate) struct Cli {
    #[command(subcommand)]
    pub(crate) command: Command,
}

// Each command's arguments are built when it runs (`defer`): building all
// of them is a visible part of a short run (docs/performance.md). The argument structs carry `//` comments, not doc comments:
// built after the command, a struct's doc comment would replace its description
// (`every_command_keeps_its_own_description` checks).
#[derive(Debug, Subcommand)]
#[command(defer = true)]
pub(crate) enum Command {
    /// Show, check, create, convert or re-express robot files.
    #[command(subcommand)]
    Robot(RobotCommand),
    /// Direct geometric model: the end-effector frame at a configuration (eq. 1).
    Fk(ConfigurationArgs),
    /// The 6×Np Jacobian of the end-effector w.r.t. every parameter (Appendix II).
    Jacobian(ConfigurationArgs),
    /// Inverse geometric model: a configuration that puts the end-effector at a target.
    Ik(IkArgs),
    /// Identifiable (base) parameters of a method: QR of W (Appendix III).
    Identifiable(IdentifiableArgs),
    /// The paper's Table 2: identifiable parameters of all methods for a robot.
    Table2(Table2Args),
    /// Points generation: simulated measurements of a "real" robot for a method.
    Generate(GenerateArgs),
    /// Plan a calibration: the configurations to measure, chosen from a pool
    /// (D-, A-, E-optimal, O4, O5 or test-pose accuracy), or how many are enough (--curve).
    Plan(PlanArgs),
    /// Predict, before measuring, the precision of every identifiable
    /// parameter and the calibrated robot's error at test poses.
    Predict(PredictArgs),
    /// Identification: the robot's parameters from measurements (eq. 10, iterated).
    Identify(IdentifyArgs),
    /// Identify and write a self-contained HTML report with plots.
    Report(ReportArgs),
    /// Rank candidate models (which parameters may be identified) by their
    /// cross-validated held-out error.
    CompareModels(CompareModelsArgs),
    /// Error statistics of a (calibrated) robot on measurements.
    Evaluate(EvaluateArgs),
    /// Correct a robot program for the calibrated robot: the joint values
    /// that reach what the nominal program meant ("program filtering").
    Compensate(CompensateArgs),
    /// Teach a tool point by pivoting: the joint values of N ≥ 4 orientations with the tool's
    /// tip on one fixed point give the tip in frame n+1 (tool0) and the fixed point.
    Tcp(TcpArgs),
    /// A user frame from measured points: origin, x and xy (three points), or any number of
    /// points with their place in the frame (frame_x, frame_y, frame_z; least squares).
    Frame(FrameArgs),
    /// Join an instrument's export (x,y,z[,qw,qx,qy,qz]) with a controller's log
    /// (qm1..qmn) into one data file, by a key column or by row order; a shifted join is
    /// refused with its direction.
    Join(JoinArgs),
    /// ISO 9283's acceptance test: plan its program, evaluate what was measured
    /// (pose accuracy and repeatability, multi-directional variation, distance accuracy).
    #[command(subcommand)]
    Iso9283(Iso9283Command),
    /// Generate data for the Stanford arm and identify it with every method.
    Demo(DemoArgs),
    /// Serve the GECARO main page (robot table, seven method menus) on 127.0.0.1.
    Serve(ServeArgs),
}

#[derive(Debug, Subcommand)]
#[command(defer = true)]
pub(crate) enum RobotCommand {
    /// Print the robot's table (j, σ, α, d, θ, r, β, K), limits and priority matrix.
    Show {
        /// Robot file or ready robot name.
        robot: String,
        /// Show angles in degrees.
        #[arg(long)]
        deg: bool,
    },
    /// Validate a robot file and explain every problem (file, line, key).
    Check {
        /// Robot file or ready robot name.
        robot: String,
    },
    /// Re-express a robot in another world frame and/or with another tool
    /// frame (frames 0, 1 and n, n+1 rewritten; same motion otherwise).
    Reframe {
        /// Robot file or ready robot name.
        robot: String,
        /// The robot's current world frame in the new one: position (metres)
        /// and unit quaternion, or the 16 numbers of its 4×4 matrix, row by row.
        #[arg(
            long,
            value_delimiter = ',',
            allow_hyphen_values = true,
            value_name = "X,Y,Z,QW,QX,QY,QZ"
        )]
        world: Option<Vec<f64>>,
        /// The new tool frame in the current one (frame n+1): position
        /// (metres) and unit quaternion, or the 16 numbers of its 4×4 matrix, row by row.
        #[arg(
            long,
            value_delimiter = ',',
            allow_hyphen_values = true,
            value_name = "X,Y,Z,QW,QX,QY,QZ"
        )]
        tool: Option<Vec<f64>>,
        /// Output robot file.
        #[arg(short, long)]
        output: PathBuf,
        /// Overwrite the output file if it exists.
        #[arg(long)]
        force: bool,
    },
    /// Re-express a robot calibrated in a measurement frame (a tracker's) in
    /// its own base frame, the nominal robot's: prints the measurement
    /// frame's pose in the robot's frame, writes the robot.
    Rebase(RebaseArgs),
    /// Convert a URDF, a DH / modified-DH table or a SYMORO .par file into a
    /// robot file (same joint variables: sign and zero).
    Import(ImportArgs),
    /// Write a robot as a URDF or a DH / modified-DH table (gains and
    /// couplings that the format cannot carry go to FILE's
    /// .joint_calibration.yaml beside it).
    Export(ExportArgs),
    /// Write a template robot file to edit.
    New {
        /// Joint types from joint 1 to n: R revolute, P prismatic (e.g. RRPRRR).
        #[arg(long)]
        joints: String,
        /// Output file.
        #[arg(short, long)]
        output: PathBuf,
        /// Overwrite the output file if it exists.
        #[arg(long)]
        force: bool,
    },
}

#[cfg(test)]
mod tests {
    use clap::CommandFactory;

    /// Every command, deferred ones included (their arguments are built
    /// when they run), passes clap's checks: no two arguments with the same
    /// name or flag, defaults among their possible values.
    #[test]
    fn the_command_line_is_well_formed() {
        super::Cli::command().debug_assert();
    }

    /// Every command keeps its own description once its deferred arguments
    /// are built: a doc comment on an argument struct, applied after the
    /// command's, would replace it.
    #[test]
    fn every_command_keeps_its_own_description() {
        fn descriptions(command: &clap::Command) -> Vec<(String, String, String)> {
            let text = |about: Option<&clap::builder::StyledStr>| {
                about.map(ToString::to_string).unwrap_or_default()
            };
            let own = (
                command.get_name().to_owned(),
                text(command.get_about()),
                text(command.get_long_about()),
            );
            // Building adds clap's own `help` commands.
            std::iter::once(own)
                .chain(
                    command
                        .get_subcommands()
                        .filter(|sub| sub.get_name() != "help")
                        .flat_map(descriptions),
                )
                .collect()
        }
        let declared = super::Cli::command();
        let mut built = super::Cli::command();
        built.build();
        let declared = descriptions(&declared);
        assert!(declared.len() > 20, "{} commands", declared.len());
        assert_eq!(declared, descriptions(&built));
    }
}
