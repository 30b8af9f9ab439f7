//! A delimited text table as instruments and controllers export them: a
//! header, then rows, fields separated by commas, semicolons or tabs
//! (found from the header unless stated), decimal commas where the
//! separator is not a comma, `#` lines and blank lines skipped, fields
//! trimmed of blanks and quotes. A leaf beneath the readers of named
//! points and of joins, which give the columns their meaning.

use std::path::Path;

use crate::Error;
use crate::columns::parse_number;
use crate::data_file::DataFormat;

/// A table's header and rows, as text, with how its numbers are written.
#[derive(Clone, Debug)]
pub(crate) struct TextTable {
    /// The header's names.
    pub(crate) names: Vec<String>,
    /// Each row's line (1-based) and fields, as many as the header's.
    pub(crate) rows: Vec<(usize, Vec<String>)>,
    /// Whether numbers have a decimal comma.
    pub(crate) decimal_comma: bool,
}

impl TextTable {
    /// The table of `text` (the file `path`), at most `most` rows; `hint`
    /// says what the file should hold when it has no header.
    ///
    /// # Errors
    /// No header, a decimal comma asked for in a comma-separated file, a
    /// row of another length than the header (with its line), more than
    /// `most` rows.
    pub(crate) fn parse(
        text: &str,
        path: &Path,
        format: &DataFormat,
        most: usize,
        hint: &str,
    ) -> Result<TextTable, Error> {
        let format_error = |message: String| Error::Format {
            path: path.to_owned(),
            message,
        };
        let mut lines = text
            .lines()
            .enumerate()
            .map(|(index, line)| (index + 1, line.trim_end_matches('\r')))
            .filter(|(_, line)| !line.trim().is_empty() && !line.trim_start().starts_with('#'));
        let Some((_, header)) = lines.next() else {
            return Err(format_error(format!("no header: {hint}")));
        };
        let separator = format.delimiter.byte(header.as_bytes());
        let decimal_comma = format.decimal_comma(separator).map_err(format_error)?;
        let split = |line: &str| -> Vec<String> {
            line.split(char::from(separator))
                .map(|field| field.trim().trim_matches('"').to_owned())
                .collect()
        };
        let names = split(header);
        let mut rows = Vec::new();
        for (line, row) in lines {
            if rows.len() == most {
                return Err(Error::Parse {
                    path: path.to_owned(),
                    line,
                    field: None,
                    message: format!("more than {most} rows: {hint}"),
                });
            }
            let fields = split(row);
            if fields.len() != names.len() {
                return Err(Error::Parse {
                    path: path.to_owned(),
                    line,
                    field: None,
                    message: format!(
                        "{} fields where the header has {}",
                        fields.len(),
                        names.len()
                    ),
                });
            }
            rows.push((line, fields));
        }
        Ok(TextTable {
            names,
            rows,
            decimal_comma,
        })
    }

    /// The column of the file named `name` in gecaro's names (renamed by
    /// `format`'s columns).
    pub(crate) fn column(&self, format: &DataFormat, name: &str) -> Option<usize> {
        let file_name = format.columns.file_name(name);
        self.names.iter().position(|column| column == file_name)
    }

    /// The number in `field` of the row at `line`, named `name` in
    /// messages.
    ///
    /// # Errors
    /// A field that is not a number.
    pub(crate) fn number(
        &self,
        path: &Path,
        (line, field): (usize, &str),
        name: &str,
    ) -> Result<f64, Error> {
        parse_number(field, self.decimal_comma).ok_or_else(|| Error::Parse {
            path: path.to_owned(),
            line,
            field: Some(name.to_owned()),
            message: format!("`{field}` is not a number"),
        })
    }
}
