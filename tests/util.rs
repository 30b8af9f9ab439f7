//! What the command line's tests share.

use assert_cmd::Command;

/// The `gecaro` binary of this build, as a user runs it.
pub(crate) fn gecaro() -> Command {
    Command::cargo_bin("gecaro").expect("the gecaro binary is built")
}

/// The `gecaro` binary as a process of the standard library, to spawn,
/// signal and wait on (assert_cmd's `Command` runs to its end).
pub(crate) fn gecaro_process() -> std::process::Command {
    std::process::Command::new(assert_cmd::cargo::cargo_bin("gecaro"))
}

/// The JSON `gecaro args…` prints, the run required to succeed (its
/// error output shown when it does not).
pub(crate) fn json_output(args: &[&str]) -> serde_json::Value {
    let output = gecaro().args(args).output().expect("runs");
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    serde_json::from_slice(&output.stdout).expect("valid JSON")
}

/// `gecaro` with the arguments of a command line as a user types it
/// (`"identify industrial6 --method position"`; words split at spaces, so
/// a path or a value with a space is added by `.arg`).
pub(crate) fn command(line: &str) -> Command {
    let mut command = gecaro();
    command.args(line.split_whitespace());
    command
}
