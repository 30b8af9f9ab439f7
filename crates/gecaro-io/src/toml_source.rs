//! Where a TOML text came from ([`Source`]): a problem's line found from a
//! document location, and a TOML error worded with the closest known key.
//! Beneath every TOML reader (robot files, parallel robot files, priority
//! files).

use std::path::Path;

use crate::Error;
use crate::problem::{DocumentError, Location};

/// Where a text came from, to name it in messages.
pub(crate) struct Source<'a> {
    pub(crate) path: &'a Path,
    pub(crate) text: &'a str,
}

impl Source<'_> {
    pub(crate) fn line_of(&self, offset: usize) -> usize {
        let offset = offset.min(self.text.len());
        crate::error::line_at(self.text, offset)
    }

    /// The line of a document location: the key's line inside its table, or
    /// the table's header (a text scan of the file as written).
    pub(crate) fn line_of_location(&self, location: &Location) -> usize {
        let lines: Vec<&str> = self.text.lines().collect();
        let key_of = |line: &str| {
            line.split('=')
                .next()
                .map(str::trim)
                .unwrap_or_default()
                .to_owned()
        };
        let is_header = |line: &str| line.trim_start().starts_with('[') && !line.contains('=');
        // (start, end) of the table whose header satisfies `matches`.
        let table = |matches: &dyn Fn(&str) -> bool, occurrence: usize| -> Option<(usize, usize)> {
            let start = lines
                .iter()
                .enumerate()
                .filter(|(_, line)| matches(line.trim()))
                .nth(occurrence)
                .map(|(index, _)| index)?;
            let end = lines[start + 1..]
                .iter()
                .position(|line| is_header(line))
                .map_or(lines.len(), |p| start + 1 + p);
            Some((start, end))
        };
        let find = |range: (usize, usize), key: &str| -> usize {
            (range.0..range.1)
                .find(|i| key_of(lines[*i]) == key)
                .unwrap_or(range.0)
                + 1
        };
        match location {
            Location::Frame { frame, key } => table(&|line| line.starts_with("[[frame]]"), *frame)
                .map_or(1, |range| find(range, key)),
            Location::Leg { leg, key } => {
                table(&|line| line.starts_with("[[leg]]"), leg.saturating_sub(1))
                    .map_or(1, |range| find(range, key))
            }
            Location::Arm { arm, key } => {
                table(&|line| line.starts_with("[[arm]]"), arm.saturating_sub(1))
                    .map_or(1, |range| find(range, key))
            }
            Location::Coupling { matrix } => table(&|line| line.starts_with("[coupling]"), 0)
                .map_or(1, |range| find(range, matrix)),
            Location::Priority { row } => {
                table(&|line| line.starts_with("[priority]"), 0).map_or(1, |range| {
                    let matrix_line = find(range, "matrix");
                    match row {
                        // One row per line after `matrix = [`, as gecaro writes it.
                        Some(row) => (matrix_line..range.1)
                            .filter(|i| lines[*i].trim_start().starts_with('['))
                            .nth(*row)
                            .map_or(matrix_line, |i| i + 1),
                        None => matrix_line,
                    }
                })
            }
            Location::Key { key } => (0..lines.len())
                .find(|i| key_of(lines[*i]) == *key || lines[*i].trim() == format!("[{key}]"))
                .map_or(1, |i| i + 1),
            Location::Document => {
                table(&|line| line.starts_with("[[frame]]"), 0).map_or(1, |(start, _)| start + 1)
            }
        }
    }

    pub(crate) fn document_error(&self, error: DocumentError) -> Error {
        Error::parse(
            self.path,
            self.line_of_location(&error.location),
            Some(error.location.to_string()),
            error.message,
        )
    }
}

impl Source<'_> {
    /// A TOML error at its line; an unknown key named with the closest of
    /// `known`.
    pub(crate) fn toml_error(&self, error: &toml::de::Error, known: &[&[&str]]) -> Error {
        let source = self;
        let message = crate::error::toml_message(error, source.text);
        let message = match unknown_key(&message) {
            Some(key) => {
                let known = known.iter().flat_map(|keys| keys.iter());
                let closest = known
                    .map(|candidate| (strsim::levenshtein(&key, candidate), *candidate))
                    .filter(|(distance, _)| *distance <= 2.max(key.len() / 3))
                    .min_by_key(|(distance, _)| *distance);
                match closest {
                    Some((_, candidate)) => {
                        format!("unknown key `{key}` (did you mean `{candidate}`?)")
                    }
                    None => format!("unknown key `{key}`; {}", expected_list(&message)),
                }
            }
            None => message,
        };
        Error::parse(
            source.path,
            error.span().map_or(1, |span| source.line_of(span.start)),
            None,
            message,
        )
    }
}

/// The key of serde's "unknown field `x`, expected ..." message.
fn unknown_key(message: &str) -> Option<String> {
    let rest = message.strip_prefix("unknown field `")?;
    Some(rest[..rest.find('`')?].to_owned())
}

fn expected_list(message: &str) -> String {
    message
        .split_once(", ")
        .map_or_else(String::new, |(_, expected)| {
            expected.replace("expected", "known keys are")
        })
}
