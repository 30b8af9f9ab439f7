//! Shared formatting of numbers and tables for human output.

use comfy_table::presets::UTF8_FULL_CONDENSED;
use comfy_table::{CellAlignment, ContentArrangement, Table};

/// A table with gecaro's look; the first `left` columns are left-aligned, the
/// rest (numbers) right-aligned.
pub(crate) fn table(header: &[&str], left: usize) -> Table {
    let mut table = Table::new();
    table
        .load_style(UTF8_FULL_CONDENSED.with_rounded_corners())
        .set_content_arrangement(ContentArrangement::Disabled)
        .set_header(header.iter().copied());
    for index in left..header.len() {
        if let Some(column) = table.column_mut(index) {
            column.set_cell_alignment(CellAlignment::Right);
        }
    }
    table
}

/// `text` from a file (a robot's, a joint's or a file's name) as it may be
/// printed: every hidden character escaped as `\u{1b}`.
pub(crate) fn shown(text: &str) -> std::borrow::Cow<'_, str> {
    shown_keeping(text, false)
}

/// A message as it may be printed: hidden characters escaped, its own line
/// breaks kept.
pub(crate) fn shown_lines(text: &str) -> std::borrow::Cow<'_, str> {
    shown_keeping(text, true)
}

fn shown_keeping(text: &str, newlines: bool) -> std::borrow::Cow<'_, str> {
    let hidden = |c: char| gecaro_io::is_hidden_character(c) && !(newlines && c == '\n');
    if !text.chars().any(hidden) {
        return std::borrow::Cow::Borrowed(text);
    }
    std::borrow::Cow::Owned(
        text.chars()
            .map(|c| {
                if hidden(c) {
                    c.escape_unicode().to_string()
                } else {
                    c.to_string()
                }
            })
            .collect(),
    )
}

/// A number with up to `decimals` decimals and no trailing zeros ("0.1", "-1.570796", "0").
pub(crate) fn number(value: f64, decimals: usize) -> String {
    // Below this, a value is rounding noise (a rotation entry of 1e-17), not information.
    if value.abs() < 1e-12 {
        return "0".into();
    }
    // Beyond this, fixed notation is a wall of digits.
    if value.abs() >= 1e15 || !value.is_finite() {
        return gecaro_core::Compact(value).to_string();
    }
    let text = format!("{value:.decimals$}");
    let text = if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.').to_owned()
    } else {
        text
    };
    if text == "-0" || text == "0" {
        format!("{value:.1e}")
    } else {
        text
    }
}

/// A comma-separated list of numbers for messages.
pub(crate) fn list(values: &[f64]) -> String {
    values
        .iter()
        .map(|v| number(*v, 6))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The observability indices as one line (see docs/planning.md).
pub(crate) fn observability(
    indices: &gecaro_calib::observability::Observability,
    of: &str,
) -> String {
    format!(
        "Observability of {of} (W_b scaled to 1 cm, 1°, 1 %; larger is better): \
         O1 {:.3e}, O2 {:.3e}, O3 {:.3e}, O4 {:.3e}, O5 {:.3e}",
        indices.o1, indices.o2, indices.o3, indices.o4, indices.o5
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_short_and_honest() {
        assert_eq!(number(0.0, 6), "0");
        assert_eq!(number(0.1, 6), "0.1");
        assert_eq!(number(-std::f64::consts::FRAC_PI_2, 6), "-1.570796");
        assert_eq!(number(1e-9, 6), "1.0e-9");
        assert_eq!(number(12.0, 6), "12");
        assert_eq!(number(7e-17, 6), "0");
        assert_eq!(number(1e308, 6), "1e308");
    }

    #[test]
    fn hidden_characters_are_escaped() {
        assert_eq!(shown("arm"), "arm");
        assert_eq!(shown("a\u{1b}[31mb\u{7}"), "a\\u{1b}[31mb\\u{7}");
        assert_eq!(shown("x\u{202e}y\nz"), "x\\u{202e}y\\u{a}z");
        assert_eq!(shown("a\u{61c}b\u{feff}"), "a\\u{61c}b\\u{feff}");
        assert_eq!(shown_lines("one\ntwo\r"), "one\ntwo\\u{d}");
    }
}
