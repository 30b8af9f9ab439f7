//! The command line, declared with clap.

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand};

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

#[derive(Debug, Subcommand)]
pub(crate) enum Command {
    /// Show, check or create robot files.
    #[command(subcommand)]
    Robot(RobotCommand),
    /// Direct geometric model: the end-effector frame at a configuration (eq. 1).
    Fk(ConfigurationArgs),
    /// The 6×Np Jacobian of the end-effector w.r.t. every parameter (Appendix II).
    Jacobian(ConfigurationArgs),
}

#[derive(Debug, Subcommand)]
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

#[derive(Debug, Args)]
pub(crate) struct ConfigurationArgs {
    /// Robot file or ready robot name.
    pub(crate) robot: String,
    /// Motor variables qm1..qmn, comma separated (radians or metres).
    #[arg(
        long,
        value_delimiter = ',',
        allow_hyphen_values = true,
        required = true
    )]
    pub(crate) qm: Vec<f64>,
    /// Print JSON instead of a table.
    #[arg(long)]
    pub(crate) json: bool,
}
