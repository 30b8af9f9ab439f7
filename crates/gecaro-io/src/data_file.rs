//! Measurement data files: CSV with a header, one configuration per row.
//!
//! Columns: `qm1..qmn` (motor variables) always, then the method's own
//! columns ([`DataColumn`]): `x,y,z` for a position, `qw,qx,qy,qz` (unit
//! quaternion) for an orientation, `set` (link methods: rows with the same id
//! reach the same point/frame), `pair` and `distance` (distance method: two
//! rows per pair, the measured distance on both).
//!
//! Any file may also state the payload the robot carried at each row, for
//! elastic joints (issue 38): `payload_mass` (kg) and, optionally,
//! `payload_x,payload_y,payload_z`, its centre in frame n+1 (a length, in
//! the file's length unit; frame n+1's origin when omitted).
//!
//! A file may state each row's uncertainty, as instruments export it
//! (issue 74): `sigma`, the σ of the row's lengths (positions, distances;
//! in the file's length unit), and `sigma_angle`, the σ of its orientation
//! angles (in the file's angle unit); an empty field states none (the
//! set's σ holds there). Such a row counts by its own σ in the fit and in
//! its verdict ([`gecaro_data::sample::RowSigma`]).
//!
//! Files are read as instruments and controllers write them ([`DataFormat`]):
//! columns come in any order and are found by name, or under other names
//! given by a [`ColumnMap`] (`x=X_mm`); lengths (positions, distances,
//! prismatic joints) may be in millimetres and joint angles in degrees;
//! columns gecaro does not use (time stamps, point names) are left alone and
//! reported in [`DataFile::unused_columns`]. Lines starting with `#` are
//! comments. Files up to 16 MiB are read whole and their rows in parts on
//! all cores; longer ones record by record, with a limit on the length of a
//! line and on the number of rows, so memory stays bounded whatever the
//! input.
//!
//! Every error names the file, the line and the column.

use gecaro_core::{FrameType, LinkMass};
use gecaro_data::sample::DataColumn;
use gecaro_data::samples::{SampleRef, SampleSlice, Samples};
use std::borrow::Cow;
use std::io::Read;
use std::path::Path;

use crate::Error;
use crate::columns::{ColumnMap, DataUnits, Delimiter, locate};
use crate::data_rows::{
    CHUNK_BYTES, Chunking, Fields, MAX_CONFIGURATIONS, PayloadColumns, RowReader, Rows,
};
use crate::input::{csv_error, csv_reader, open_regular, record_line};
use crate::line_chunks::{CarriageReturnLines, carriage_returns_only};
use crate::output::{OutputPolicy, write_with};
use crate::pose::{NORMALISED_TOLERANCE, SILENT_TOLERANCE};
use crate::rotation::RotationFormat;
use crate::stated_units::{stated_units, units_line, units_to_read};
use crate::whole::{Content, map_small};

/// Files up to this size are read whole, and their rows in parts on all
/// cores; longer ones (or endless streams) record by record.
const IN_MEMORY_BYTES: usize = 16 << 20;
// A file small enough to be mapped is parsed whole where it lies.
const _: () = assert!(crate::whole::MAPPED_MAX_BYTES == IN_MEMORY_BYTES as u64);

/// How a data file is written: the units of its lengths and angles, and
/// other names of its columns. The default is gecaro's own (metres,
/// radians, `qm1,…,x,y,z`).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct DataFormat {
    /// Units of positions, distances and joint values.
    pub units: DataUnits,
    /// Columns under other names.
    pub columns: ColumnMap,
    /// The field separator (found from the header line by default).
    pub delimiter: Delimiter,
    /// Whether numbers have a decimal comma: `None` (default) allows it
    /// where fields are not separated by commas, `Some(true)` requires such
    /// a separator, `Some(false)` refuses decimal commas.
    pub decimal_comma: Option<bool>,
    /// How orientations are written ([`RotationFormat`]): quaternions by
    /// default, or Euler angles or a rotation vector in the angle unit.
    pub rotation: RotationFormat,
}

impl DataFormat {
    /// Whether numbers are read with a decimal comma in a file whose fields
    /// are separated by `separator`.
    ///
    /// # Errors
    /// A decimal comma asked for in a comma-separated file.
    pub(crate) fn decimal_comma(&self, separator: u8) -> Result<bool, String> {
        match (self.decimal_comma, separator) {
            (Some(true), b',') => Err(
                "a decimal comma needs fields separated by `;` or tabs, and this file's are \
                 separated by commas (give the separator)"
                    .into(),
            ),
            (Some(wanted), _) => Ok(wanted),
            (None, separator) => Ok(separator != b','),
        }
    }
}

/// A data file read.
#[derive(Clone, Debug, PartialEq)]
pub struct DataFile {
    /// The configurations, in metres and radians.
    pub samples: Samples,
    /// Columns of the file that the method does not use (left alone).
    pub unused_columns: Vec<String>,
    /// What the reader changed that a user should know (quaternions
    /// normalised).
    pub notes: Vec<String>,
}

/// The header a data file for `joint_count` joints and these columns must have.
pub fn data_headers(joint_count: usize, columns: &[DataColumn]) -> Vec<String> {
    (1..=joint_count)
        .map(|j| format!("qm{j}"))
        .chain(
            columns
                .iter()
                .flat_map(|c| c.headers().iter().map(|h| (*h).to_owned())),
        )
        .collect()
}

/// Reads a data file for a robot with these joint types (1..n): mapped
/// into memory when small ([`map_small`]), else read in chunks.
///
/// # Errors
/// [`Error::Read`] when it cannot be opened or is not a regular file,
/// [`Error::Parse`] with line and column for any problem of content.
pub fn read_samples(
    path: &Path,
    joint_types: &[FrameType],
    columns: &[DataColumn],
    format: &DataFormat,
) -> Result<DataFile, Error> {
    let (file, length) = open_regular(path)?;
    let whole = map_small(&file, length);
    let mut reader = std::io::BufReader::with_capacity(1 << 16, file);
    let content = match &whole {
        Some(whole) => Content::Whole(whole),
        None => Content::Stream(&mut reader, Some(length)),
    };
    parse_samples_from(content, path, (joint_types, columns), format)
}

/// Parses data from any reader; `path` only names it in messages.
///
/// # Errors
/// [`Error::Parse`] with line and column.
pub fn parse_samples(
    mut reader: impl Read,
    path: &Path,
    joint_types: &[FrameType],
    columns: &[DataColumn],
    format: &DataFormat,
) -> Result<DataFile, Error> {
    parse_samples_from(
        Content::Stream(&mut reader, None),
        path,
        (joint_types, columns),
        format,
    )
}

/// [`parse_samples`] of a file's content: read where it lies when it is in
/// memory whole (up to 16 MiB; beyond, as a stream). Of a stream whose
/// length is known (a file's), the samples of a long one are given room for
/// all its rows at once, from the rows of its first chunk, instead of
/// growing (and being copied) as they are read. The samples are the same;
/// a wrong length costs only memory or a copy.
///
/// # Errors
/// [`Error::Parse`] with line and column.
pub fn parse_samples_from(
    content: Content<'_>,
    path: &Path,
    (joint_types, columns): (&[FrameType], &[DataColumn]),
    format: &DataFormat,
) -> Result<DataFile, Error> {
    let (mut head, mut unread, length): (Cow<'_, [u8]>, _, _) = match content {
        Content::Whole(bytes) if bytes.len() <= IN_MEMORY_BYTES => (bytes.into(), None, None),
        mut content => {
            let length = match &content {
                Content::Whole(bytes) => u64::try_from(bytes.len()).ok(),
                Content::Stream(_, length) => *length,
            };
            // Room for the whole head at once: a long file's head becomes
            // the buffer of its first chunk.
            let mut head = Vec::with_capacity(IN_MEMORY_BYTES + 1);
            content
                .reader()
                .take(IN_MEMORY_BYTES as u64 + 1)
                .read_to_end(&mut head)
                .map_err(|cause| Error::Read {
                    path: path.to_owned(),
                    cause,
                })?;
            (head.into(), Some(content), length)
        }
    };
    // Lines ended by a carriage return alone (Excel's "CSV (Macintosh)")
    // are read as lines (issue 75: "more records than lines").
    let carriage_returns = carriage_returns_only(&head);
    if carriage_returns {
        for byte in head.to_mut() {
            if *byte == b'\r' {
                *byte = b'\n';
            }
        }
    }
    // A file that states its units (`gecaro plan --angle-unit deg`) is read
    // in them where the request leaves gecaro's own.
    let format = &match stated_units(&head)
        .map_err(|(line, message)| Error::parse(path, line, None, message))?
    {
        Some((line, stated)) => DataFormat {
            units: units_to_read(format.units, stated)
                .map_err(|message| Error::parse(path, line, None, message))?,
            ..format.clone()
        },
        None => format.clone(),
    };
    // The rest of a file longer than its head, lines ended as the head's.
    let mut translated;
    let rest: Option<&mut dyn Read> = match unread.as_mut() {
        Some(unread) if head.len() > IN_MEMORY_BYTES => {
            if carriage_returns {
                translated = CarriageReturnLines(unread.reader());
                Some(&mut translated)
            } else {
                Some(unread.reader())
            }
        }
        _ => None,
    };
    parse_from(
        (head, rest),
        path,
        (joint_types, columns),
        format,
        Chunking {
            bytes: CHUNK_BYTES,
            limit: MAX_CONFIGURATIONS,
            length,
        },
    )
}

/// [`parse_samples`] of the bytes `head` and then `rest`, when the file is
/// longer than [`IN_MEMORY_BYTES`] (its rows are then read in chunks, see
/// [`Chunking`]; those of a file in memory in parts on all cores).
fn parse_from(
    (head, rest): (Cow<'_, [u8]>, Option<&mut dyn Read>),
    path: &Path,
    (joint_types, columns): (&[FrameType], &[DataColumn]),
    format: &DataFormat,
    chunking: Chunking,
) -> Result<DataFile, Error> {
    // Orientations in the file's own form: its columns in place of qw…qz.
    let mut expected = data_headers(joint_types.len(), columns);
    if format.rotation != RotationFormat::Quaternion
        && let Some(at) = expected.iter().position(|name| name == "qw")
    {
        expected.splice(
            at..at + 4,
            format
                .rotation
                .columns()
                .iter()
                .map(|name| (*name).to_owned()),
        );
    }
    let (mut csv, separator) = csv_reader(&head[..], format.delimiter);
    let decimal_comma = format
        .decimal_comma(separator)
        .map_err(|message| Error::parse(path, 1, None, message))?;
    let fail = |line: usize, field: Option<&str>, message: String| {
        Error::parse(path, line, field.map(str::to_owned), message)
    };
    let mut record = csv::StringRecord::new();
    if !csv
        .read_record(&mut record)
        .map_err(|error| csv_error(path, &error))?
    {
        return Err(fail(
            1,
            None,
            format!(
                "the file is empty; it needs a header line: {}",
                expected.join(",")
            ),
        ));
    }
    let header_line = record_line(&mut csv);
    let names: Vec<String> = record.iter().map(|name| name.trim().to_owned()).collect();
    if names.iter().all(|name| name.parse::<f64>().is_ok()) {
        return Err(fail(
            header_line,
            None,
            format!(
                "missing header: the first line holds numbers; it must name the columns: {}",
                expected.join(",")
            ),
        ));
    }
    let layout = resolve_header(&names, &expected, &format.columns)
        .map_err(|message| fail(header_line, None, message))?;
    // A motor column beyond the robot's joints: data of another robot (a
    // 7-joint arm's file opened with a 6-joint robot), not a column to ignore.
    if let Some(extra) = layout.unused.iter().find(|name| {
        name.strip_prefix("qm")
            .and_then(|index| index.parse::<usize>().ok())
            .is_some_and(|index| index > joint_types.len())
    }) {
        return Err(fail(
            header_line,
            None,
            format!(
                "the file has a column `{extra}`, and the robot has {} joints: these data are \
                 not of this robot (or map its columns to the robot's)",
                joint_types.len()
            ),
        ));
    }
    let at = |name: &str| {
        expected
            .iter()
            .position(|e| e == name)
            .and_then(|i| layout.positions[i])
            .unwrap_or(0)
    };
    let mut unused = layout.unused;
    let payload = payload_columns(&names, &mut unused, &format.columns)
        .map_err(|message| fail(header_line, None, message))?;
    let sigma = sigma_columns(&mut unused, &format.columns, &names);
    let units = format.units;
    let length = units.length.to_metres();
    let fields = Fields {
        joints: (1..=joint_types.len())
            .map(|j| (at(&format!("qm{j}")), units.joint_scale(joint_types, j - 1)))
            .collect(),
        position: columns
            .contains(&DataColumn::Position)
            .then(|| [at("x"), at("y"), at("z")]),
        orientation: columns
            .contains(&DataColumn::Orientation)
            .then(|| match format.rotation {
                RotationFormat::Quaternion => [at("qw"), at("qx"), at("qy"), at("qz")],
                _ => [at("rx"), at("ry"), at("rz"), 0],
            }),
        rotation: format.rotation,
        group: columns.iter().find_map(|column| match column {
            DataColumn::Set => Some(at("set")),
            DataColumn::Pair => Some(at("pair")),
            _ => None,
        }),
        distance: columns
            .contains(&DataColumn::Distance)
            .then(|| at("distance")),
        payload,
        sigma,
    };
    let rows = RowReader {
        path,
        names: &names,
        fields,
        decimal_comma,
        length,
        angle: units.angle.to_radians(),
    };
    // The rows start after the header's last byte, with the lines before.
    let start = (csv.position().byte() as usize).min(head.len());
    let lines_before = memchr::memchr_iter(b'\n', &head[..start]).count();
    let Rows {
        samples,
        normalised,
        error,
    } = match rest {
        None => rows.read_all(&head[start..], lines_before, separator),
        Some(rest) if memchr::memchr(b'"', &head).is_none() => rows.read_chunks(
            (head.into_owned(), start, rest),
            lines_before,
            separator,
            chunking,
        ),
        // Quoted fields may hold line breaks: one pass over the stream.
        Some(rest) => {
            let (mut csv, _) = csv_reader((&head[..]).chain(rest), format.delimiter);
            csv.read_record(&mut record)
                .map_err(|error| csv_error(path, &error))?;
            rows.read(&mut csv, 0)
        }
    };
    if let Some(error) = error {
        return Err(error);
    }
    if samples.is_empty() {
        return Err(fail(
            header_line + 1,
            None,
            "the file has a header but no configurations".into(),
        ));
    }
    let mut notes = Vec::new();
    if normalised.count > 0 {
        notes.push(format!(
            "{}: {} quaternion(s) with a norm off 1 by more than {SILENT_TOLERANCE:e} were \
             normalised (largest: {:.1e}, line {}; up to {NORMALISED_TOLERANCE:e} is taken \
             as rounding)",
            path.display(),
            normalised.count,
            normalised.largest,
            normalised.line
        ));
    }
    Ok(DataFile {
        samples: samples.into(),
        unused_columns: unused,
        notes,
    })
}

/// gecaro's names of the columns of a row's σ (see the module docs): of
/// its lengths, and of its angles.
const SIGMA_COLUMNS: [&str; 2] = ["sigma", "sigma_angle"];

/// The columns of a row's σ among the header's `names` (taken out of
/// `unused`), when the file has either.
fn sigma_columns(
    unused: &mut Vec<String>,
    map: &ColumnMap,
    names: &[String],
) -> Option<[Option<usize>; 2]> {
    let found = SIGMA_COLUMNS.map(|name| {
        let file_name = map.file_name(name);
        names.iter().position(|column| column == file_name)
    });
    unused.retain(|name| {
        !SIGMA_COLUMNS
            .iter()
            .any(|column| map.file_name(column) == name)
    });
    found.iter().any(Option::is_some).then_some(found)
}

/// The σ columns a file of `samples` has: both when any sample states
/// its σ, none otherwise.
fn sigma_columns_of(samples: SampleSlice<'_>) -> &'static [&'static str] {
    if samples.iter().any(|sample| sample.sigma().is_some()) {
        &SIGMA_COLUMNS
    } else {
        &[]
    }
}

/// A row's σ fields in units of `length` metres and `angle` radians:
/// empty where the row states none.
fn sigma_fields(sample: SampleRef<'_>, (length, angle): (f64, f64)) -> [Option<f64>; 2] {
    let sigma = sample.sigma().unwrap_or_default();
    [
        sigma.length.map(|value| value / length),
        sigma.angle.map(|value| value / angle),
    ]
}

/// gecaro's names of the payload columns (see the module docs).
const PAYLOAD_COLUMNS: [&str; 4] = ["payload_mass", "payload_x", "payload_y", "payload_z"];

/// The payload columns a file of `samples` has: all of them when any sample
/// carries a payload, none otherwise.
fn payload_columns_of(samples: SampleSlice<'_>) -> &'static [&'static str] {
    if samples.iter().any(|sample| sample.payload().is_some()) {
        &PAYLOAD_COLUMNS
    } else {
        &[]
    }
}

/// A row's payload columns: its mass (kg) and centre in units of `length`
/// metres; 0 kg at the origin for a row that carried none.
fn payload_values(sample: SampleRef<'_>, length: f64) -> [f64; 4] {
    let payload = sample.payload().copied().unwrap_or(LinkMass {
        mass: 0.0,
        com: nalgebra::Vector3::zeros(),
    });
    [
        payload.mass,
        payload.com.x / length,
        payload.com.y / length,
        payload.com.z / length,
    ]
}

/// The payload's columns among the header's `names` (taken out of
/// `unused`): the mass's, and the centre's when all three are there.
///
/// # Errors
/// A centre without its mass, or only part of the centre.
fn payload_columns(
    names: &[String],
    unused: &mut Vec<String>,
    map: &ColumnMap,
) -> Result<Option<PayloadColumns>, String> {
    let found: Vec<Option<usize>> = PAYLOAD_COLUMNS
        .iter()
        .map(|name| {
            let file_name = map.file_name(name);
            names.iter().position(|column| column == file_name)
        })
        .collect();
    if found.iter().all(Option::is_none) {
        return Ok(None);
    }
    let Some(mass) = found[0] else {
        return Err(
            "the file gives a payload's centre (payload_x, payload_y, payload_z) without its \
             mass: add a column payload_mass (kg)"
                .into(),
        );
    };
    let centre = match (found[1], found[2], found[3]) {
        (Some(x), Some(y), Some(z)) => Some([x, y, z]),
        (None, None, None) => None,
        _ => {
            return Err(
                "the payload's centre needs the three columns payload_x, payload_y, payload_z"
                    .into(),
            );
        }
    };
    unused.retain(|name| {
        !PAYLOAD_COLUMNS
            .iter()
            .any(|column| map.file_name(column) == name)
    });
    Ok(Some(PayloadColumns { mass, centre }))
}

/// What a header was read as, for a message about a missing column: the
/// names (the first 200 characters), and the separator when the header is
/// one column that another separator would split.
fn header_read(names: &[String]) -> String {
    let mut read = names.join(",");
    if read.chars().count() > 200 {
        read = format!("{}…", read.chars().take(200).collect::<String>());
    }
    let read = read.escape_debug();
    let separator = match names {
        [one] if one.contains(';') => Some("`;`"),
        [one] if one.contains('\t') => Some("tabs"),
        _ => None,
    };
    match separator {
        Some(separator) => format!(
            " (the header read is one column, `{read}`: its fields seem separated by \
             {separator}; give that separator, or let it be found)"
        ),
        None => format!(" (the header read: `{read}`)"),
    }
}

/// The positions of the expected columns in a header; every one must be
/// there once, the rest is left alone.
fn resolve_header(
    names: &[String],
    expected: &[String],
    map: &ColumnMap,
) -> Result<crate::columns::Layout, String> {
    // The optional columns any file may have (a payload, a row's σ) may
    // be renamed too.
    let known: Vec<String> = expected
        .iter()
        .cloned()
        .chain(
            PAYLOAD_COLUMNS
                .iter()
                .chain(&SIGMA_COLUMNS)
                .map(|name| (*name).to_owned()),
        )
        .collect();
    if let Some(message) = map.unused(names, &known).or_else(|| map.clash(&known)) {
        return Err(format!("{message}{}", header_read(names)));
    }
    let layout = locate(names, expected, map);
    // A renamed column that is missing is caught above, by its map entry.
    for (wanted, position) in expected.iter().zip(&layout.positions) {
        let Some(position) = position else {
            return Err(format!(
                "missing column `{wanted}`; this method's data need the columns {}{}",
                expected.join(","),
                header_read(names)
            ));
        };
        if names
            .iter()
            .filter(|name| *name == &names[*position])
            .count()
            > 1
        {
            return Err(format!("column `{}` appears twice", names[*position]));
        }
    }
    Ok(layout)
}

/// The field separator a file written as `format` asks has, and how it
/// writes a number: shortest round-trip digits, with a decimal comma where
/// the format asks for one (and its separator is not a comma).
pub(crate) fn written_numbers(format: &DataFormat) -> (char, impl Fn(f64) -> String + Copy) {
    let separator = match format.delimiter {
        Delimiter::Semicolon => ';',
        Delimiter::Tab => '\t',
        Delimiter::Comma | Delimiter::Detect => ',',
    };
    let decimal_comma = format.decimal_comma == Some(true) && separator != ',';
    let number = move |value: f64| {
        let text = format!("{value:?}");
        if decimal_comma {
            text.replacen('.', ",", 1)
        } else {
            text
        }
    };
    (separator, number)
}

/// The CSV text of configurations (and their set or pair ids: `columns` of
/// [`DataColumn::grouping`](gecaro_data::sample::DataColumn::grouping)) as
/// `format` reads them back: joint values in its units (`joint_types` from
/// [`crate::joint_types`]), columns under its names, its separator (`;` or
/// a tab when it names one) and, when it asks for one, a decimal comma. A
/// plan for a teach pendant in degrees, say.
pub fn format_configurations(
    joint_types: &[FrameType],
    columns: &[DataColumn],
    samples: SampleSlice<'_>,
    format: &DataFormat,
) -> String {
    let (separator, number) = written_numbers(format);
    // A plan for an elastic robot states each row's payload.
    let payload_columns = payload_columns_of(samples);
    let mut names = data_headers(joint_types.len(), columns);
    names.extend(payload_columns.iter().map(|name| (*name).to_owned()));
    let header: Vec<String> = names
        .iter()
        .map(|name| format.columns.file_name(name).to_owned())
        .collect();
    // Written in other units than gecaro's own, the file says so, and reads
    // back in them.
    let mut text = units_line(&format.units).unwrap_or_default();
    text.push_str(&header.join(&separator.to_string()));
    text.push('\n');
    let length = format.units.length.to_metres();
    for sample in samples {
        let motors = format
            .units
            .configuration_from_si(joint_types, sample.motor_positions());
        let mut fields: Vec<String> = motors.into_iter().map(number).collect();
        for column in columns {
            if matches!(column, DataColumn::Set | DataColumn::Pair) {
                fields.push(sample.group().unwrap_or(0).to_string());
            }
        }
        if !payload_columns.is_empty() {
            fields.extend(payload_values(sample, length).map(number));
        }
        text.push_str(&fields.join(&separator.to_string()));
        text.push('\n');
    }
    text
}

/// The CSV text of a data set.
///
/// When a sample carries a payload, every row states one (0 kg where none
/// was carried), in the payload columns of the module docs.
pub fn format_samples(
    joint_count: usize,
    columns: &[DataColumn],
    samples: SampleSlice<'_>,
) -> String {
    let payload_columns = payload_columns_of(samples);
    let sigma_columns = sigma_columns_of(samples);
    let mut header = data_headers(joint_count, columns);
    header.extend(payload_columns.iter().map(|name| (*name).to_owned()));
    header.extend(sigma_columns.iter().map(|name| (*name).to_owned()));
    let mut text = header.join(",");
    text.push('\n');
    for sample in samples {
        let mut fields: Vec<String> = sample
            .motor_positions()
            .iter()
            .map(|v| format!("{v:?}"))
            .collect();
        for column in columns {
            match column {
                DataColumn::Position => {
                    let position = sample.position().unwrap_or_default();
                    fields.extend(position.iter().map(|v| format!("{v:?}")));
                }
                DataColumn::Orientation => {
                    let q = sample.orientation().unwrap_or_default();
                    fields.extend([q.w, q.i, q.j, q.k].iter().map(|v| format!("{v:?}")));
                }
                DataColumn::Set | DataColumn::Pair => {
                    fields.push(sample.group().unwrap_or(0).to_string())
                }
                DataColumn::Distance => {
                    fields.push(format!("{:?}", sample.distance().unwrap_or(0.0)))
                }
            }
        }
        if !payload_columns.is_empty() {
            fields.extend(payload_values(sample, 1.0).map(|v| format!("{v:?}")));
        }
        if !sigma_columns.is_empty() {
            fields.extend(
                sigma_fields(sample, (1.0, 1.0))
                    .map(|v| v.map_or_else(String::new, |v| format!("{v:?}"))),
            );
        }
        text.push_str(&fields.join(","));
        text.push('\n');
    }
    text
}

/// Writes a data set atomically (see [`crate::write_atomically`]).
///
/// # Errors
/// As [`crate::write_atomically`].
pub fn write_samples(
    path: &Path,
    joint_count: usize,
    columns: &[DataColumn],
    samples: SampleSlice<'_>,
    policy: OutputPolicy,
) -> Result<(), Error> {
    let text = format_samples(joint_count, columns, samples);
    write_with(path, policy, |file| {
        std::io::Write::write_all(file, text.as_bytes())
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use gecaro_data::sample::Sample;
    use nalgebra::{UnitQuaternion, Vector3};

    const TWO_REVOLUTE: [FrameType; 2] = [FrameType::Revolute; 2];

    fn parse(text: &str, columns: &[DataColumn]) -> Result<Vec<Sample>, Error> {
        parse_samples(
            text.as_bytes(),
            Path::new("data.csv"),
            &TWO_REVOLUTE,
            columns,
            &DataFormat::default(),
        )
        .map(|file| file.samples.to_rows())
    }

    fn error_of(text: &str, columns: &[DataColumn]) -> String {
        parse(text, columns).expect_err("invalid").to_string()
    }

    /// Bytes in memory longer than a file read whole (an upload, a served
    /// folder's text) are read in chunks from where they lie, as the same
    /// bytes streamed.
    #[test]
    fn long_bytes_in_memory_read_as_streamed() {
        let mut text = String::from("qm1,qm2,x,y,z\n");
        let mut row = 0;
        while text.len() <= IN_MEMORY_BYTES + 1000 {
            text.push_str(&format!("{}.5,0.25,1,2,{}\n", row % 7, row % 997));
            row += 1;
        }
        let columns = [DataColumn::Position];
        let path = Path::new("long.csv");
        let whole = parse_samples_from(
            Content::Whole(text.as_bytes()),
            path,
            (&TWO_REVOLUTE, &columns),
            &DataFormat::default(),
        )
        .expect("whole");
        let streamed = parse_samples(
            text.as_bytes(),
            path,
            &TWO_REVOLUTE,
            &columns,
            &DataFormat::default(),
        )
        .expect("streamed");
        assert_eq!(whole.samples.len(), row);
        assert_eq!(whole.samples, streamed.samples);
        let last = whole.samples.get(row - 1);
        assert_eq!(last.line(), Some(row + 1));
        assert_eq!(last.position().map(|p| p.z), Some(((row - 1) % 997) as f64));
    }

    /// A data file mapped into memory ([`read_samples`] of a small file)
    /// reads as the same bytes streamed: its samples and line numbers, its
    /// carriage-return lines, stated units, quoted fields, and its errors
    /// (with their lines).
    #[test]
    fn a_mapped_file_reads_as_its_bytes_streamed() {
        let folder = tempfile::tempdir().expect("a folder");
        let texts = [
            "qm1,qm2,x,y,z\n0.1,0.2,1,2,3\n# a note\n0.3,0.4,4,5,6",
            "qm1,qm2,x,y,z\r0.1,0.2,1,2,3\r0.3,0.4,4,5,6\r",
            "# units: angle_unit = deg, length_unit = mm\nqm1,qm2,x,y,z\n10,20,100,200,300\n",
            "qm1,qm2,x,y,\"z\"\n0.1,0.2,1,2,\"3\"\n",
            "qm1,qm2,x,y,z\n0.1,0.2,1,2,3\n0.3,nan,4,5,6\n",
            "qm1,qm2,x,y,z\n",
        ];
        for (index, text) in texts.iter().enumerate() {
            let path = folder.path().join(format!("d{index}.csv"));
            std::fs::write(&path, text).expect("written");
            let file = std::fs::File::open(&path).expect("opened");
            assert!(map_small(&file, text.len() as u64).is_some(), "{text:?}");
            let columns = [DataColumn::Position];
            let mapped = read_samples(&path, &TWO_REVOLUTE, &columns, &DataFormat::default());
            let streamed = parse_samples(
                text.as_bytes(),
                &path,
                &TWO_REVOLUTE,
                &columns,
                &DataFormat::default(),
            );
            match (mapped, streamed) {
                (Ok(mapped), Ok(streamed)) => {
                    assert_eq!(mapped.samples, streamed.samples, "{text:?}");
                    let lines = |file: &DataFile| {
                        (0..file.samples.len())
                            .map(|i| file.samples.get(i).line())
                            .collect::<Vec<_>>()
                    };
                    assert_eq!(lines(&mapped), lines(&streamed), "{text:?}");
                    assert_eq!(mapped.notes, streamed.notes);
                }
                (Err(mapped), Err(streamed)) => {
                    assert_eq!(mapped.to_string(), streamed.to_string());
                }
                (mapped, streamed) => panic!("{text:?}: {mapped:?} against {streamed:?}"),
            }
        }
    }

    /// A row's σ (issue 74): `sigma` in the file's length unit and
    /// `sigma_angle` in its angle unit, an empty field stating none, a
    /// decimal comma read as such; written back in metres and radians and
    /// read again the same; a σ that is no standard deviation is refused
    /// naming its line and column.
    #[test]
    fn a_row_s_sigma_reads_in_the_file_s_units_and_round_trips() {
        let text = "qm1;qm2;x;y;z;qw;qx;qy;qz;sigma;sigma_angle\n\
                    10;20;100;200;300;1;0;0;0;0,015;0,002\n\
                    30;40;100;200;300;1;0;0;0;0,2;\n\
                    50;60;100;200;300;1;0;0;0;;\n";
        let columns = [DataColumn::Position, DataColumn::Orientation];
        let file = parse_samples(
            text.as_bytes(),
            Path::new("probe.csv"),
            &TWO_REVOLUTE,
            &columns,
            &DataFormat {
                units: DataUnits {
                    length: crate::LengthUnit::Millimetres,
                    angle: crate::AngleUnit::Degrees,
                },
                ..DataFormat::default()
            },
        )
        .expect("valid");
        assert!(file.unused_columns.is_empty(), "{:?}", file.unused_columns);
        let sigma = file.samples.get(0).sigma().expect("σ");
        assert!((sigma.length.expect("length") - 15e-6).abs() < 1e-18);
        assert!((sigma.angle.expect("angle") - 0.002f64.to_radians()).abs() < 1e-15);
        let second = file.samples.get(1).sigma().expect("σ");
        assert_eq!((second.length, second.angle), (Some(2e-4), None));
        assert_eq!(file.samples.get(2).sigma(), None);
        let written = format_samples(2, &columns, file.samples.as_slice());
        assert!(written.starts_with("qm1,qm2,x,y,z,qw,qx,qy,qz,sigma,sigma_angle\n"));
        assert_eq!(parse(&written, &columns).expect("reads back"), file.samples);
        for (row, column) in [("0,0,1,2,3,-0.1", "sigma"), ("0,0,1,2,3,0", "sigma")] {
            let message = error_of(
                &format!("qm1,qm2,x,y,z,sigma\n0,0,1,2,3,1e-5\n{row}\n"),
                &[DataColumn::Position],
            );
            assert!(
                message.contains("data.csv:3")
                    && message.contains(column)
                    && message.contains("standard deviation"),
                "{message}"
            );
        }
        let message = error_of(
            "qm1,qm2,x,y,z,sigma_angle\n0,0,1,2,3,4\n",
            &[DataColumn::Position],
        );
        assert!(message.contains("sigma_angle"), "{message}");
    }

    /// The payload columns: read in the file's length unit, written back
    /// and read again; a centre without its mass, part of a centre and a
    /// negative mass are refused, naming the line and column.
    #[test]
    fn payloads_read_in_the_file_s_units_and_round_trip() {
        let text = "qm1,qm2,x,y,z,payload_mass,payload_x,payload_y,payload_z\n\
                    0.1,0.2,100,200,300,10,0,0,120\n\
                    0.3,0.4,100,200,300,0,0,0,0\n";
        let format = DataFormat {
            units: DataUnits {
                length: crate::LengthUnit::Millimetres,
                angle: crate::AngleUnit::Radians,
            },
            ..DataFormat::default()
        };
        let file = parse_samples(
            text.as_bytes(),
            Path::new("data.csv"),
            &TWO_REVOLUTE,
            &[DataColumn::Position],
            &format,
        )
        .expect("valid");
        assert!(file.unused_columns.is_empty(), "{:?}", file.unused_columns);
        let payload = *file.samples.get(0).payload().expect("payload");
        assert_eq!(payload.mass, 10.0);
        assert!((payload.com - Vector3::new(0.0, 0.0, 0.12)).norm() < 1e-15);
        let written = format_samples(2, &[DataColumn::Position], file.samples.as_slice());
        assert!(written.starts_with("qm1,qm2,x,y,z,payload_mass,payload_x,payload_y,payload_z\n"));
        let again = parse(&written, &[DataColumn::Position]).expect("reads back");
        assert_eq!(again, file.samples);
        // The mass alone: the centre at frame n+1's origin.
        let alone = parse(
            "qm1,qm2,x,y,z,payload_mass\n0,0,1,2,3,5\n",
            &[DataColumn::Position],
        )
        .expect("valid");
        assert_eq!(alone[0].payload().expect("payload").com, Vector3::zeros());
        // Without a payload, nothing is written.
        let none = format_samples(2, &[DataColumn::Position], SampleSlice::empty());
        assert_eq!(none, "qm1,qm2,x,y,z\n");
        let message = error_of("qm1,qm2,payload_x,payload_y,payload_z\n0,0,0,0,0\n", &[]);
        assert!(message.contains("without its mass"), "{message}");
        let message = error_of("qm1,qm2,payload_mass,payload_z\n0,0,1,0\n", &[]);
        assert!(message.contains("three columns"), "{message}");
        let message = error_of("qm1,qm2,payload_mass\n0,0,1\n0,0,-2\n", &[]);
        assert!(
            message.contains("data.csv:3") && message.contains("payload_mass"),
            "{message}"
        );
        // A mass no arm carries, a centre 80 m away (issue 75 item 6, 74).
        let message = error_of("qm1,qm2,payload_mass\n0,0,1\n0,0,1e300\n", &[]);
        assert!(
            message.contains("data.csv:3") && message.contains("payload_mass"),
            "{message}"
        );
        let message = error_of(
            "qm1,qm2,payload_mass,payload_x,payload_y,payload_z\n0,0,12,0,0,80\n",
            &[],
        );
        assert!(
            message.contains("data.csv:2") && message.contains("80 m from the tool frame"),
            "{message}"
        );
    }

    /// A file too long to hold is read in chunks (here of 4 kB) with the
    /// samples, line numbers, first error and limit of a single pass.
    #[test]
    fn long_files_are_read_in_chunks_as_in_one_pass() {
        let mut text = String::from("# a comment\nqm1,qm2,x,y,z\n");
        for row in 0..3000 {
            text.push_str(&format!("{row}e-4,{}e-4,1,2,{row}e-3\n", 2 * row));
            if row % 700 == 0 {
                text.push_str("# a comment between rows\n");
            }
        }
        let columns = [DataColumn::Position];
        let read = |text: &str, limit: usize, length: Option<u64>| {
            let (head, mut rest) = text.as_bytes().split_at(1000);
            parse_from(
                (head.into(), Some(&mut rest)),
                Path::new("data.csv"),
                (&TWO_REVOLUTE, &columns),
                &DataFormat::default(),
                Chunking {
                    bytes: 4096,
                    limit,
                    length,
                },
            )
            .map(|file| file.samples)
        };
        let chunked = |text: &str, limit: usize| read(text, limit, None);
        let whole = parse(&text, &columns).expect("valid");
        assert_eq!(whole.len(), 3000);
        assert_eq!(chunked(&text, usize::MAX).expect("valid"), whole);
        // The file's length only makes room: right, short or long, the
        // samples are the same.
        let length = text.len() as u64;
        for stated in [length, 10, 10 * length, u64::MAX] {
            assert_eq!(read(&text, usize::MAX, Some(stated)).expect("valid"), whole);
        }
        // The first error, in the fifth chunk or so: the same line.
        let broken = text.replacen(",1,2,2200e-3\n", ",1,2,x\n", 1);
        let expected = error_of(&broken, &columns);
        assert!(expected.contains("data.csv:2207"), "{expected}");
        let found = chunked(&broken, usize::MAX)
            .expect_err("invalid")
            .to_string();
        assert_eq!(found, expected);
        // The limit falls inside a chunk: its line is named.
        let message = chunked(&text, 2500).expect_err("too many").to_string();
        assert!(message.contains("data.csv:2507"), "{message}");
        let message = read(&text, 2500, Some(length))
            .expect_err("too many")
            .to_string();
        assert!(message.contains("data.csv:2507"), "{message}");
    }

    #[test]
    fn round_trip_of_every_column() {
        let columns = [
            DataColumn::Position,
            DataColumn::Orientation,
            DataColumn::Pair,
            DataColumn::Distance,
        ];
        let sample = Sample {
            position: Some(Vector3::new(0.1, -0.2, 1.0 / 3.0)),
            orientation: Some(UnitQuaternion::from_euler_angles(0.1, 0.2, 0.3)),
            group: Some(7),
            distance: Some(0.05),
            ..Sample::new(vec![0.5, -1.25])
        };
        let text = format_samples(2, &columns, Samples::from(vec![sample.clone()]).as_slice());
        let read = parse(&text, &columns).expect("valid");
        assert_eq!(read[0].motor_positions, sample.motor_positions);
        assert_eq!(read[0].position, sample.position);
        assert_eq!(read[0].group, Some(7));
        assert!(
            read[0]
                .orientation
                .expect("read")
                .angle_to(&sample.orientation.expect("set"))
                < 1e-15
        );
        assert_eq!(read[0].line, Some(2));
    }

    #[test]
    fn columns_may_come_in_any_order_with_comments() {
        let text = "# exported from the tracker\nz,qm2,x,qm1,y\n3,2,1,0.5,2\n";
        let read = parse(text, &[DataColumn::Position]).expect("valid");
        assert_eq!(read[0].motor_positions.as_slice(), [0.5, 2.0]);
        assert_eq!(read[0].position, Some(Vector3::new(1.0, 2.0, 3.0)));
    }

    #[test]
    fn bad_files_name_line_and_column() {
        let position = [DataColumn::Position];
        assert!(error_of("", &position).contains("data.csv:1: the file is empty"));
        assert!(error_of("0,0,1,2,3\n", &position).contains("missing header"));
        assert!(error_of("qm1,qm2,x,y\n0,0,1,2\n", &position).contains("missing column `z`"));
        assert!(
            error_of("qm1,qm2,x,y,x,z\n0,0,1,2,3,4\n", &position)
                .contains("column `x` appears twice")
        );
        assert!(
            error_of("qm1,qm2,x,y,z\n0,0,1,2\n", &position)
                .contains("data.csv:2: 4 values for 5 columns")
        );
        assert!(
            error_of("qm1,qm2,x,y,z\n0,0,1,2,3\n0,abc,1,2,3\n", &position)
                .contains("data.csv:3: qm2: `abc` is not a number")
        );
        assert!(
            error_of("qm1,qm2,x,y,z\n0,0,NaN,2,3\n", &position)
                .contains("x: `NaN` is not a finite number")
        );
        assert!(error_of("qm1,qm2,x,y,z\n", &position).contains("no configurations"));
        // A third motor column for a two-joint robot: another robot's data.
        let error = error_of("qm1,qm2,qm3,x,y,z\n0,0,0,1,2,3\n", &position);
        assert!(
            error.contains("data.csv:1") && error.contains("`qm3`, and the robot has 2 joints"),
            "{error}"
        );
        let frame = [DataColumn::Position, DataColumn::Orientation];
        assert!(
            error_of("qm1,qm2,x,y,z,qw,qx,qy,qz\n0,0,0,0,0,1,1,0,0\n", &frame)
                .contains("not a unit quaternion")
        );
        assert!(
            error_of("qm1,qm2,set\n0,0,1.5\n", &[DataColumn::Set])
                .contains("set: `1.5` is not an id")
        );
    }

    #[test]
    fn separators_are_found_and_decimal_commas_read() {
        let read = |text: &str, format: &DataFormat| {
            parse_samples(
                text.as_bytes(),
                Path::new("t.csv"),
                &TWO_REVOLUTE,
                &[DataColumn::Position],
                format,
            )
        };
        let plain =
            read("qm1,qm2,x,y,z\n0.5,1,2.25,3,4\n", &DataFormat::default()).expect("commas");
        for text in [
            "qm1;qm2;x;y;z\n0,5;1;2,25;3;4\n",
            "# exported by a spreadsheet\nqm1\tqm2\tx\ty\tz\n0,5\t1\t2.25\t3\t4\n",
            "qm1;qm2;x;y;z\n0.5;1;2.25;3;4\n",
        ] {
            let found =
                read(text, &DataFormat::default()).unwrap_or_else(|e| panic!("{text}: {e}"));
            let values = |file: &DataFile| {
                file.samples
                    .iter()
                    .map(|sample| (sample.motor_positions().to_vec(), sample.position()))
                    .collect::<Vec<_>>()
            };
            assert_eq!(values(&found), values(&plain), "{text}");
        }
        let refused = DataFormat {
            decimal_comma: Some(false),
            ..DataFormat::default()
        };
        let error = read("qm1;qm2;x;y;z\n0,5;1;2;3;4\n", &refused).expect_err("refused");
        assert!(
            error.to_string().contains("`0,5` is not a number"),
            "{error}"
        );
        let contradiction = DataFormat {
            delimiter: Delimiter::Comma,
            decimal_comma: Some(true),
            ..DataFormat::default()
        };
        let error = read("qm1,qm2,x,y,z\n0,1,2,3,4\n", &contradiction).expect_err("no");
        assert!(
            error.to_string().contains("needs fields separated by"),
            "{error}"
        );
    }

    #[test]
    fn instruments_files_in_millimetres_and_degrees_with_their_own_columns() {
        // A tracker export: time stamps and point names around the values,
        // positions in mm, a revolute joint in degrees and a prismatic one in mm.
        let text = "time,point,A1,Z_mm,X_mm,Y_mm,A2\n\
                    12.5,P1,90,300,100,-200,250\n";
        let format = DataFormat {
            units: DataUnits {
                length: crate::LengthUnit::Millimetres,
                angle: crate::AngleUnit::Degrees,
            },
            columns: ColumnMap::parse("qm1=A1,qm2=A2,x=X_mm,y=Y_mm,z=Z_mm").expect("valid"),
            ..DataFormat::default()
        };
        let joints = [FrameType::Revolute, FrameType::Prismatic];
        let file = parse_samples(
            text.as_bytes(),
            Path::new("tracker.csv"),
            &joints,
            &[DataColumn::Position],
            &format,
        )
        .expect("valid");
        let sample = &file.samples.get(0);
        assert!((sample.motor_positions()[0] - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
        assert!((sample.motor_positions()[1] - 0.25).abs() < 1e-15);
        let position = sample.position().expect("read");
        assert!((position - Vector3::new(0.1, -0.2, 0.3)).norm() < 1e-15);
        assert_eq!(file.unused_columns, ["time", "point"]);
        // A renamed column that is not there, and a map to a wrong name.
        let missing = parse_samples(
            "A1,A2,X_mm,Y_mm\n0,0,1,2\n".as_bytes(),
            Path::new("t.csv"),
            &joints,
            &[DataColumn::Position],
            &format,
        )
        .expect_err("missing")
        .to_string();
        assert!(
            missing.contains("t.csv:1: columns: `z` maps to `Z_mm`, which is not in the header"),
            "{missing}"
        );
        let wrong = DataFormat {
            columns: ColumnMap::parse("x=X").expect("valid"),
            ..DataFormat::default()
        };
        let error = parse_samples(
            "qm1,qm2,x,y,z\n0,0,1,2,3\n".as_bytes(),
            Path::new("t.csv"),
            &TWO_REVOLUTE,
            &[DataColumn::Position],
            &wrong,
        )
        .expect_err("unknown")
        .to_string();
        assert!(
            error.contains("columns: `x` maps to `X`, which is not in the header"),
            "{error}"
        );
    }

    /// A long file is read in parts on all cores (no quote in it), the same
    /// text with a quote in a comment in one pass: the same samples, lines,
    /// notes and errors.
    #[test]
    fn a_long_file_read_in_parts_reads_as_in_one_pass() {
        let columns = [DataColumn::Position, DataColumn::Orientation];
        let mut text = String::from("# from a tracker\r\nqm1,qm2,x,y,z,qw,qx,qy,qz\r\n");
        for row in 0..4000 {
            if row % 700 == 0 {
                text.push_str("# a comment between rows\r\n\r\n");
            }
            // Every 500th quaternion is off unit norm by a growing amount.
            let qw = if row % 500 == 7 {
                1.0 + 1e-7 * row as f64
            } else {
                1.0
            };
            text.push_str(&format!(
                "{},{},{},{},{},{qw},0,0,0\r\n",
                row as f64 * 1e-3,
                -(row as f64) * 2e-3,
                0.1 + row as f64 * 1e-4,
                0.2,
                0.3
            ));
        }
        assert!(text.len() > crate::data_rows::PART_MIN_BYTES);
        let read = |text: &str| {
            parse_samples(
                text.as_bytes(),
                Path::new("long.csv"),
                &TWO_REVOLUTE,
                &columns,
                &DataFormat::default(),
            )
        };
        let in_parts = read(&text).expect("in parts");
        let one_pass = read(&format!("{text}# a \"quoted\" comment\n")).expect("one pass");
        assert_eq!(in_parts.samples.len(), 4000);
        assert_eq!(in_parts.samples, one_pass.samples);
        assert_eq!(in_parts.notes, one_pass.notes);
        assert_eq!(in_parts.samples.get(0).line(), Some(5));
        assert_eq!(in_parts.samples.get(3999).line(), Some(4000 + 4 + 2 * 5));
        // Row r is on line r + 3 + 2 (r / 700 + 1): a comment, the header, and
        // a comment and a blank line before every 700 rows.
        let line_of_row = |row: usize| row + 3 + 2 * (row / 700 + 1);
        assert_eq!(in_parts.samples.get(3507).line(), Some(line_of_row(3507)));
        assert!(
            in_parts.notes[0].contains("line 3522"),
            "{:?}",
            in_parts.notes
        );
        // The first error in the file, wherever the parts are cut.
        for (first, second) in [(100, 3900), (2100, 2101), (3998, 3999)] {
            let mut lines: Vec<&str> = text.split("\r\n").collect();
            let (a, b) = (line_of_row(first), line_of_row(second));
            lines[a - 1] = "1,2,3,4,5,1,0,0,oops";
            lines[b - 1] = "1,2,3";
            let broken = lines.join("\r\n");
            let expected = format!("long.csv:{a}: qz: `oops` is not a number");
            for variant in [broken.clone(), format!("{broken}\"")] {
                let error = read(&variant).expect_err("broken").to_string();
                assert!(
                    error.starts_with(&expected),
                    "{error} (expected {expected})"
                );
            }
        }
    }

    /// A long plain file (no quote, comment or blank line; `\r\n` line
    /// ends) read in chunks and parts by the plain route
    /// ([`crate::plain_body`]) gives the samples, lines and first error of
    /// a single pass of the `csv` crate (forced by a quote at its end).
    #[test]
    fn a_long_plain_file_reads_as_in_one_pass() {
        let columns = [DataColumn::Position];
        let mut text = String::from("qm1,qm2,x,y,z\r\n");
        for row in 0..9000 {
            text.push_str(&format!(
                "{}, {} ,0.1,0.2,{}\r\n",
                row as f64 * 1e-3,
                -(row as f64) * 2e-3,
                0.3 + row as f64 * 1e-5
            ));
        }
        let chunk_bytes = crate::data_rows::PART_MIN_BYTES + 1000;
        assert!(text.len() > 2 * chunk_bytes);
        let limited = |text: &str, limit: usize| {
            let (head, mut rest) = text.as_bytes().split_at(1000);
            parse_from(
                (head.into(), Some(&mut rest)),
                Path::new("plain.csv"),
                (&TWO_REVOLUTE, &columns),
                &DataFormat::default(),
                Chunking {
                    bytes: chunk_bytes,
                    limit,
                    length: None,
                },
            )
            .map(|file| file.samples)
        };
        let chunked = |text: &str| limited(text, usize::MAX);
        // A limit inside a part of a later chunk names the line of the
        // sample one too many; the last sample within it is read.
        for limit in [5000, 8999] {
            let message = limited(&text, limit).expect_err("too many").to_string();
            assert!(
                message.starts_with(&format!("plain.csv:{}:", limit + 2)),
                "{message}"
            );
        }
        assert_eq!(limited(&text, 9000).expect("within").len(), 9000);
        let one_pass = |text: &str| {
            parse_samples(
                format!("{text}\"").as_bytes(),
                Path::new("plain.csv"),
                &TWO_REVOLUTE,
                &columns,
                &DataFormat::default(),
            )
            .map(|file| file.samples)
        };
        // The quote makes a last record of its own in the single pass.
        let mut expected = one_pass(&text).expect_err("a quote alone").to_string();
        assert!(expected.contains("plain.csv:9002"), "{expected}");
        let read = chunked(&text).expect("plain");
        assert_eq!(read.len(), 9000);
        assert_eq!(read.get(8999).line(), Some(9001));
        let whole = parse(&text, &columns).expect("in parts");
        assert_eq!(read.to_rows(), whole);
        assert_eq!(whole[4321].motor_positions[1], -4321.0 * 2e-3);
        for (first, second) in [(10, 8000), (3333, 3334), (8998, 8999)] {
            let mut lines: Vec<&str> = text.split("\r\n").collect();
            lines[first + 1] = "1,2,3,4,oops";
            lines[second + 1] = "1,2";
            let broken = lines.join("\r\n");
            expected = one_pass(&broken).expect_err("broken").to_string();
            let line = first + 2;
            assert!(
                expected.starts_with(&format!("plain.csv:{line}: z: `oops`")),
                "{expected}"
            );
            assert_eq!(chunked(&broken).expect_err("broken").to_string(), expected);
            assert_eq!(
                error_of(&broken, &columns),
                expected.replace("plain.csv", "data.csv")
            );
        }
    }

    #[test]
    fn a_file_without_line_breaks_stops_in_bounded_memory() {
        let endless = std::io::repeat(b'7');
        let error = parse_samples(
            endless,
            Path::new("blob.csv"),
            &TWO_REVOLUTE,
            &[DataColumn::Position],
            &DataFormat::default(),
        )
        .expect_err("stops")
        .to_string();
        assert!(
            error.contains("blob.csv:1:") && error.contains("longer than"),
            "{error}"
        );
    }
}
