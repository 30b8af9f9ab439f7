//! What the command line's tests share.

use assert_cmd::Command;

/// The `gecaro` binary of this build, as a user runs it.
pub(crate) fn gecaro() -> Command {
    Command::cargo_bin("gecaro").expect("the gecaro binary is built")
}
