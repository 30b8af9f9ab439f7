//! One module per command family; each turns parsed arguments into library
//! calls and prints the result.

mod calibration;
mod compensation;
mod frames;
mod identifiability;
mod interchange;
mod iso9283;
mod kinematics;
mod options;
mod output;
mod parallel;
mod planning;
mod progress;
mod robot;
mod robustness;
mod serve;
mod validation;

use crate::cli::{Cli, Command};
use crate::failure::Failure;

/// Whether the robot a command names is a parallel one (its own commands
/// in [`parallel`]).
fn is_parallel(robot: Option<&str>) -> bool {
    robot.is_some_and(|robot| {
        gecaro_app::parallel::RobotKind::of(robot, &gecaro_app::LocalFiles)
            == gecaro_app::parallel::RobotKind::Parallel
    })
}

/// Runs one command line.
pub(crate) fn run(cli: Cli) -> Result<(), Failure> {
    match cli.command {
        Command::Robot(command) => robot::run(command),
        Command::Identifiable(args) if is_parallel(args.source.robot.as_deref()) => {
            parallel::identifiable(&args, args.source.robot.as_deref().unwrap_or_default())
        }
        Command::Generate(args) if is_parallel(Some(&args.robot)) => parallel::generate(&args),
        Command::Plan(args) if is_parallel(args.robot.as_deref()) => {
            parallel::plan(&args, args.robot.as_deref().unwrap_or_default())
        }
        Command::Identify(args) if is_parallel(args.run.source.robot.as_deref()) => {
            parallel::identify(&args, args.run.source.robot.as_deref().unwrap_or_default())
        }
        Command::Report(args) if is_parallel(args.run.source.robot.as_deref()) => {
            parallel::report(&args, args.run.source.robot.as_deref().unwrap_or_default())
        }
        Command::Evaluate(args) if is_parallel(Some(&args.robot)) => parallel::evaluate(&args),
        Command::Predict(args) if is_parallel(args.robot.as_deref()) => {
            parallel::predict(&args, args.robot.as_deref().unwrap_or_default())
        }
        Command::Compensate(args) if is_parallel(Some(&args.calibrated)) => {
            parallel::compensate(&args)
        }
        Command::Fk(args) => kinematics::forward(&args),
        Command::Jacobian(args) => kinematics::jacobian(&args),
        Command::Ik(args) => kinematics::inverse(&args),
        Command::Identifiable(args) => identifiability::identifiable(&args),
        Command::Table2(args) => identifiability::table2(&args),
        Command::Generate(args) => calibration::generate(&args),
        Command::Plan(args) => planning::plan(&args),
        Command::Predict(args) => planning::predict_accuracy(&args),
        Command::Identify(args) => calibration::identify(&args),
        Command::Report(args) => calibration::report(&args),
        Command::CompareModels(args) => validation::compare(&args),
        Command::Evaluate(args) => calibration::evaluate(&args),
        Command::Compensate(args) => compensation::compensate(&args),
        Command::Tcp(args) => frames::tcp(&args),
        Command::Frame(args) => frames::frame(&args),
        Command::Join(args) => frames::join(&args),
        Command::Iso9283(command) => iso9283::run(&command),
        Command::Demo(args) => calibration::demo(&args),
        Command::Serve(args) => serve::serve(&args),
    }
}
