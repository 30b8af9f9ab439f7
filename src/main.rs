//! `gecaro`: geometric calibration of serial robots, from the terminal.
//!
//! The binary only parses arguments, calls the libraries and prints; see
//! `gecaro --help` and the README for the commands.

// The arguments' doc comments are clap's help text, not Markdown: `[prior]`
// there is a TOML table's name, not a link.
#![allow(rustdoc::broken_intra_doc_links)]

mod cli;
mod commands;
mod failure;
mod format;

use std::process::ExitCode;

use clap::Parser;

#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

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
        remove_temporaries_on_signals();
    }
    gecaro_io::roles::protect_inputs();
    match commands::run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(failure) => {
            let code = failure.exit_code();
            eprintln!("{:?}", miette::Report::new(failure));
            ExitCode::from(code)
        }
    }
}

/// On SIGINT, SIGTERM or SIGHUP, removes the temporary files of outputs
/// being written and exits as the signal would (128 + its number). The web
/// server stops on its own terms (it finishes the requests under way).
///
/// Set up at once, even for a run that writes nothing: set up with the
/// first output instead, an `identify` of 5,000 positions (which writes
/// none) was no faster (docs/performance.md, "Workers kept").
fn remove_temporaries_on_signals() {
    use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
    let Ok(mut signals) = signal_hook::iterator::Signals::new([SIGINT, SIGTERM, SIGHUP]) else {
        return;
    };
    std::thread::spawn(move || {
        if let Some(signal) = signals.forever().next() {
            gecaro_io::remove_temporary_files();
            std::process::exit(128 + signal);
        }
    });
}
