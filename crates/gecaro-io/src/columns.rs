//! Columns of CSV files as other programs write them: found by name in any
//! order, renamed by the user (`--columns x=X_mm,y=Y_mm`), in millimetres
//! and degrees, next to columns gecaro does not use (time stamps, point
//! names) which are left alone; separated by commas, semicolons or tabs
//! ([`Delimiter`], found from the header line), with decimal points or, where
//! the separator is not a comma, decimal commas.

use gecaro_core::{FrameType, Robot};

use crate::robot_file::AngleUnit;
use crate::units::LengthUnit;

/// The field separator of a CSV file.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub enum Delimiter {
    /// Found from the header line: the most frequent of `,`, `;` and tab
    /// (a comma on a tie).
    #[default]
    Detect,
    /// `,`
    Comma,
    /// `;` (spreadsheets in locales whose decimal mark is a comma)
    Semicolon,
    /// a tab
    Tab,
}

impl Delimiter {
    /// Names a user may give: `auto`, `comma` or `,`, `semicolon` or `;`,
    /// `tab` or `\t`.
    pub const NAMES: [&'static str; 4] = ["auto", "comma", "semicolon", "tab"];

    /// The separator of a name (see [`NAMES`](Self::NAMES)).
    pub fn from_name(name: &str) -> Option<Self> {
        match name.trim() {
            "auto" | "detect" => Some(Delimiter::Detect),
            "comma" | "," => Some(Delimiter::Comma),
            "semicolon" | ";" => Some(Delimiter::Semicolon),
            "tab" | "\\t" | "\t" => Some(Delimiter::Tab),
            _ => None,
        }
    }

    /// The byte separating the fields of a file whose header line is `header`.
    pub(crate) fn byte(self, header: &[u8]) -> u8 {
        match self {
            Delimiter::Comma => b',',
            Delimiter::Semicolon => b';',
            Delimiter::Tab => b'\t',
            Delimiter::Detect => {
                let count = |byte: u8| header.iter().filter(|b| **b == byte).count();
                let (comma, semicolon, tab) = (count(b','), count(b';'), count(b'\t'));
                if semicolon > comma && semicolon >= tab {
                    b';'
                } else if tab > comma && tab > semicolon {
                    b'\t'
                } else {
                    b','
                }
            }
        }
    }
}

/// The column names of a CSV file that begins with `head` (its first bytes;
/// `whole` when they are the whole file): its first line that is neither
/// blank nor a `#` comment, split at the separator [`Delimiter::Detect`]
/// finds, each name trimmed of spaces and quotes. `None` when `head` ends
/// before that line does.
///
/// ```
/// use gecaro_io::header_names;
/// let head = b"# gecaro generate: ...\nqm1;qm2;X_mm;Y_mm;Z_mm\n0.1;0.2;1;2;3\n";
/// assert_eq!(header_names(head, true).unwrap(), ["qm1", "qm2", "X_mm", "Y_mm", "Z_mm"]);
/// assert_eq!(header_names(b"qm1,qm2,x", false), None);
/// ```
pub fn header_names(head: &[u8], whole: bool) -> Option<Vec<String>> {
    let mut rest = head;
    loop {
        let (line, after) = match rest.iter().position(|b| *b == b'\n') {
            Some(end) => (&rest[..end], Some(&rest[end + 1..])),
            None if whole => (rest, None),
            None => return None,
        };
        let text = String::from_utf8_lossy(line);
        let text = text.trim_start_matches('\u{feff}').trim();
        if !text.is_empty() && !text.starts_with('#') {
            let separator = char::from(Delimiter::Detect.byte(text.as_bytes()));
            return Some(
                text.split(separator)
                    .map(|name| name.trim().trim_matches('"').trim().to_owned())
                    .collect(),
            );
        }
        rest = after?;
    }
}

/// Reads a number of a CSV field: a decimal point, or a decimal comma
/// where `decimal_comma` says so.
pub(crate) fn parse_number(text: &str, decimal_comma: bool) -> Option<f64> {
    if decimal_comma && text.contains(',') {
        text.replacen(',', ".", 1).parse().ok()
    } else {
        text.parse().ok()
    }
}

/// [`parse_number`] of a field's bytes (`None`: no number, or not UTF-8
/// text): ASCII blanks around it trimmed and the bytes parsed at once
/// (`fast-float2`, correctly rounded as the standard library is, so the same
/// double for every number, without the text's UTF-8 check); anything it
/// refuses (a decimal comma, a no-break space pasted from a spreadsheet, a
/// field that is no number) goes the text route, which has the last word.
pub(crate) fn field_number(bytes: &[u8], decimal_comma: bool) -> Option<f64> {
    let bytes = bytes.trim_ascii();
    if (!decimal_comma || !bytes.contains(&b','))
        && let Ok(number) = fast_float2::parse::<f64, _>(bytes)
    {
        return Some(number);
    }
    parse_number(std::str::from_utf8(bytes).ok()?.trim(), decimal_comma)
}

/// The words of a message about a field that is not a number.
pub(crate) fn not_a_number(text: &str, decimal_comma: bool) -> String {
    if !decimal_comma && text.contains(',') && parse_number(text, true).is_some() {
        format!(
            "`{text}` is not a number: a decimal comma needs fields separated by `;` or tabs \
             (the file's fields are separated by commas)"
        )
    } else {
        format!("`{text}` is not a number")
    }
}

/// gecaro's column names mapped to a file's (`x=X_mm`): the file's name is
/// looked up instead of gecaro's.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ColumnMap {
    pairs: Vec<(String, String)>,
}

impl ColumnMap {
    /// A map from `gecaro=file` pairs separated by commas (`x=X_mm,y=Y_mm`).
    ///
    /// # Errors
    /// A pair without `=`, an empty name, or a gecaro name given twice.
    pub fn parse(text: &str) -> Result<Self, String> {
        let mut pairs: Vec<(String, String)> = Vec::new();
        for pair in text
            .split(',')
            .map(str::trim)
            .filter(|pair| !pair.is_empty())
        {
            let Some((ours, theirs)) = pair.split_once('=') else {
                return Err(format!("`{pair}` is not NAME=COLUMN (e.g. x=X_mm)"));
            };
            let (ours, theirs) = (ours.trim(), theirs.trim());
            if ours.is_empty() || theirs.is_empty() {
                return Err(format!("`{pair}` has an empty name"));
            }
            if pairs.iter().any(|(name, _)| name == ours) {
                return Err(format!("`{ours}` is mapped twice"));
            }
            if let Some((other, _)) = pairs.iter().find(|(_, column)| column == theirs) {
                return Err(format!(
                    "`{other}` and `{ours}` are both mapped to the column `{theirs}`: a column \
                     is read as one thing"
                ));
            }
            pairs.push((ours.to_owned(), theirs.to_owned()));
        }
        Ok(ColumnMap { pairs })
    }

    /// The map of `(gecaro, file)` pairs.
    pub fn from_pairs(pairs: impl IntoIterator<Item = (String, String)>) -> Self {
        ColumnMap {
            pairs: pairs.into_iter().collect(),
        }
    }

    /// Whether nothing is renamed.
    pub fn is_empty(&self) -> bool {
        self.pairs.is_empty()
    }

    /// The file's name of gecaro's column `name`.
    pub(crate) fn file_name<'a>(&'a self, name: &'a str) -> &'a str {
        self.pairs
            .iter()
            .find(|(ours, _)| ours == name)
            .map_or(name, |(_, theirs)| theirs.as_str())
    }

    /// Two of `wanted` (gecaro names) read from one column of the file —
    /// `qm1=qm2` leaves `qm2` reading its own column too — as an error
    /// message (issue 75: accepted, and 818 mm off on exact data).
    pub(crate) fn clash(&self, wanted: &[String]) -> Option<String> {
        wanted.iter().enumerate().find_map(|(i, first)| {
            wanted[i + 1..]
                .iter()
                .find(|second| self.file_name(first) == self.file_name(second))
                .map(|second| {
                    format!(
                        "`{first}` and `{second}` would both read the column `{}`: a column is \
                         read as one thing (check the columns' renames)",
                        self.file_name(first)
                    )
                })
        })
    }

    /// gecaro names mapped to nothing the file has, as an error message.
    pub(crate) fn unused(&self, header: &[String], known: &[String]) -> Option<String> {
        self.pairs.iter().find_map(|(ours, theirs)| {
            if !known.contains(ours) {
                Some(format!(
                    "columns: `{ours}` is not a column of this file's kind ({})",
                    known.join(",")
                ))
            } else if !header.contains(theirs) {
                Some(format!(
                    "columns: `{ours}` maps to `{theirs}`, which is not in the header"
                ))
            } else {
                None
            }
        })
    }
}

/// The units of the lengths and angles of a data or program file.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub struct DataUnits {
    /// Positions, distances, prismatic joint values.
    pub length: LengthUnit,
    /// Revolute joint values.
    pub angle: AngleUnit,
}

impl DataUnits {
    /// The factor from the file's unit of joint `j` (0-based) to gecaro's.
    pub(crate) fn joint_scale(&self, robot_types: &[FrameType], j: usize) -> f64 {
        match robot_types.get(j) {
            Some(FrameType::Prismatic) => self.length.to_metres(),
            _ => self.angle.to_radians(),
        }
    }

    /// A configuration `qm` given in these units, in gecaro's (radians for
    /// revolute joints, metres for prismatic ones); `robot_types` from
    /// [`joint_types`].
    pub fn configuration_to_si(&self, robot_types: &[FrameType], qm: &[f64]) -> Vec<f64> {
        qm.iter()
            .enumerate()
            .map(|(j, q)| q * self.joint_scale(robot_types, j))
            .collect()
    }

    /// A configuration in gecaro's units, in these (the inverse of
    /// [`configuration_to_si`](Self::configuration_to_si)).
    pub fn configuration_from_si(&self, robot_types: &[FrameType], qm: &[f64]) -> Vec<f64> {
        qm.iter()
            .enumerate()
            .map(|(j, q)| q / self.joint_scale(robot_types, j))
            .collect()
    }

    /// Whether both units are gecaro's own (metres, radians).
    pub fn is_si(&self) -> bool {
        *self == DataUnits::default()
    }
}

/// The joint types 1..n of a robot (what the unit of each joint value is).
pub fn joint_types(robot: &Robot) -> Vec<FrameType> {
    robot.frames()[1..=robot.joint_count()]
        .iter()
        .map(|frame| frame.frame_type)
        .collect()
}

/// Where gecaro's columns are in a header, and what else is there.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct Layout {
    /// Position in the header of each wanted column that is present.
    pub(crate) positions: Vec<Option<usize>>,
    /// Header columns nobody asked for, in order.
    pub(crate) unused: Vec<String>,
}

/// Finds `wanted` (gecaro names) in `header` through `map`.
pub(crate) fn locate(header: &[String], wanted: &[String], map: &ColumnMap) -> Layout {
    let positions: Vec<Option<usize>> = wanted
        .iter()
        .map(|name| {
            let file_name = map.file_name(name);
            header.iter().position(|column| column == file_name)
        })
        .collect();
    let used: Vec<usize> = positions.iter().flatten().copied().collect();
    let unused = header
        .iter()
        .enumerate()
        .filter(|(index, _)| !used.contains(index))
        .map(|(_, name)| name.clone())
        .collect();
    Layout { positions, unused }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn maps_parse_and_refuse_what_is_not_one() {
        let map = ColumnMap::parse("x=X_mm, y = Y_mm,z=Z_mm").expect("valid");
        assert_eq!(map.file_name("y"), "Y_mm");
        assert_eq!(map.file_name("qm1"), "qm1");
        assert!(ColumnMap::parse("x").is_err());
        assert!(ColumnMap::parse("x=A,x=B").is_err());
        assert!(
            ColumnMap::parse("x=A,y=A")
                .expect_err("one column")
                .contains("both mapped")
        );
        let wanted: Vec<String> = ["qm1", "qm2", "x"].map(String::from).to_vec();
        let renamed = ColumnMap::parse("qm1=qm2").expect("valid");
        assert!(
            renamed
                .clash(&wanted)
                .expect("clash")
                .contains("`qm1` and `qm2`")
        );
        assert!(
            ColumnMap::parse("qm1=A1")
                .expect("valid")
                .clash(&wanted)
                .is_none()
        );
        assert!(ColumnMap::parse("=A").is_err());
    }

    #[test]
    fn columns_are_found_by_name_and_the_rest_is_left() {
        let header: Vec<String> = ["time", "X_mm", "qm1", "point"].map(String::from).to_vec();
        let map = ColumnMap::parse("x=X_mm").expect("valid");
        let wanted: Vec<String> = ["qm1", "x", "y"].map(String::from).to_vec();
        let layout = locate(&header, &wanted, &map);
        assert_eq!(layout.positions, [Some(2), Some(1), None]);
        assert_eq!(layout.unused, ["time", "point"]);
    }

    /// What the text route alone says of a field (the reading before the
    /// byte route): the standard library's number of the trimmed text.
    fn text_route(bytes: &[u8], decimal_comma: bool) -> Option<f64> {
        let text = std::str::from_utf8(bytes).ok()?;
        parse_number(text.trim(), decimal_comma)
    }

    #[test]
    fn fields_read_as_the_text_route_reads_them() {
        let fields: [&[u8]; 18] = [
            b"0.1",
            b" -0.7447739661598641 ",
            b"\t1e-5",
            b"+3",
            b"1.",
            b".5",
            b"-0",
            b"1E+300",
            b"4.9e-324",
            b"NaN",
            b"inf",
            b"-Infinity",
            b"1,5",
            b"\xc2\xa02.5\xc2\xa0",
            b"",
            b"1e",
            b"0x10",
            b"\xff1",
        ];
        for decimal_comma in [false, true] {
            for field in fields {
                let read = field_number(field, decimal_comma);
                let expected = text_route(field, decimal_comma);
                assert_eq!(
                    read.map(f64::to_bits),
                    expected.map(f64::to_bits),
                    "{:?} (decimal comma: {decimal_comma})",
                    String::from_utf8_lossy(field)
                );
            }
        }
        assert_eq!(field_number(b"1,5", true), Some(1.5));
        assert_eq!(field_number(b"1,5", false), None);
        assert_eq!(field_number("\u{a0}2.5".as_bytes(), false), Some(2.5));
    }

    proptest! {
        /// Every double, printed the shortest way or with 17 digits and
        /// padded with blanks, is read back bit for bit, as the text route
        /// reads it.
        #[test]
        fn printed_doubles_read_back_bit_for_bit(bits in any::<u64>(), padded in any::<bool>()) {
            let value = f64::from_bits(bits);
            prop_assume!(value.is_finite());
            for printed in [format!("{value}"), format!("{value:.17e}")] {
                let field = if padded { format!("  {printed} ") } else { printed };
                prop_assert_eq!(field_number(field.as_bytes(), false).map(f64::to_bits), Some(bits));
                prop_assert_eq!(
                    text_route(field.as_bytes(), false).map(f64::to_bits),
                    Some(bits)
                );
            }
        }
    }
}
