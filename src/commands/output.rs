//! What `--json` prints: a result document as pretty JSON on stdout.

use crate::failure::Failure;

/// Prints a value as pretty JSON on stdout.
pub(crate) fn print_json(value: &impl serde::Serialize) -> Result<(), Failure> {
    let text = serde_json::to_string_pretty(value).map_err(|error| {
        Failure::numerical(format!("cannot encode the result as JSON: {error}"))
    })?;
    println!("{text}");
    Ok(())
}
