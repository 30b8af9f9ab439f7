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
    // `gecaro robot show … | head`: end quietly when the reader goes away, as
    // Unix tools do, instead of panicking on a failed print. Not for the web
    // server, whose sockets must not raise the signal.
    if !matches!(cli.command, cli::Command::Serve(_)) {
        sigpipe::reset();
    }
    match commands::run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(failure) => {
            let code = failure.exit_code();
            eprintln!("{:?}", miette::Report::new(failure));
            ExitCode::from(code)
        }
    }
}
