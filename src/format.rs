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

/// A number with up to `decimals` decimals and no trailing zeros ("0.1", "-1.570796", "0").
pub(crate) fn number(value: f64, decimals: usize) -> String {
    // Below this, a value is rounding noise (a rotation entry of 1e-17), not information.
    if value.abs() < 1e-12 {
        return "0".into();
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
    use super::number;

    #[test]
    fn numbers_are_short_and_honest() {
        assert_eq!(number(0.0, 6), "0");
        assert_eq!(number(0.1, 6), "0.1");
        assert_eq!(number(-std::f64::consts::FRAC_PI_2, 6), "-1.570796");
        assert_eq!(number(1e-9, 6), "1.0e-9");
        assert_eq!(number(12.0, 6), "12");
        assert_eq!(number(7e-17, 6), "0");
    }
}
