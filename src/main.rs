//! `gecaro`: geometric calibration of serial robots, from the terminal.
//!
//! The binary only parses arguments, calls the libraries and prints; see
//! `gecaro --help` and the README for the commands.

mod cli;
mod commands;
mod failure;
mod format;

use std::process::ExitCode;

use clap::Parser;

fn main() -> ExitCode {
    miette::set_hook(Box::new(|_| {
        Box::new(
            miette::MietteHandlerOpts::new()
                .terminal_links(false)
                .wrap_lines(false)
                .build(),
        )
    }))
    .ok();
    let cli = cli::Cli::parse();
    match commands::run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(failure) => {
            let code = failure.exit_code();
            eprintln!("{:?}", miette::Report::new(failure));
            ExitCode::from(code)
        }
    }
}
