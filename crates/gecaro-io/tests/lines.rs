//! Errors in CSV files name the line of the record at fault, whatever the
//! line ends (`\n`, `\r\n`, `\r` for data files) and however many comment
//! and blank lines come before it.

use std::path::Path;

use gecaro_core::FrameType;
use gecaro_data::sample::DataColumn;
use gecaro_io::{DataFormat, load_robot, parse_program, parse_samples};

/// `lines`, each ended by `end`.
fn file(lines: &[&str], end: &str) -> String {
    let mut text = lines.join(end);
    text.push_str(end);
    text
}

const DATA: [&str; 7] = [
    "# exported by the tracker",
    "qm1,qm2,x,y,z",
    "0,0,1,2,3",
    "",
    "# second station",
    "0,0,1,2,oops",
    "0,0,1,2,3",
];

#[test]
fn data_errors_name_the_record_s_line() {
    // "\r" alone: Excel's "CSV (Macintosh)" (issue 75).
    for end in ["\n", "\r\n", "\r"] {
        let error = parse_samples(
            file(&DATA, end).as_bytes(),
            Path::new("d.csv"),
            &[FrameType::Revolute; 2],
            &[DataColumn::Position],
            &DataFormat::default(),
        )
        .expect_err("bad value")
        .to_string();
        assert!(error.starts_with("d.csv:6: z: `oops`"), "{end:?}: {error}");
        let good = file(&[&DATA[..5], &DATA[6..]].concat(), end);
        let read = parse_samples(
            good.as_bytes(),
            Path::new("d.csv"),
            &[FrameType::Revolute; 2],
            &[DataColumn::Position],
            &DataFormat::default(),
        )
        .expect("good file");
        let lines: Vec<Option<usize>> = read.samples.iter().map(|s| s.line()).collect();
        assert_eq!(lines, [Some(3), Some(6)], "{end:?}");
    }
}

#[test]
fn program_errors_name_the_record_s_line() {
    let robot = load_robot("stanford").expect("ready robot").robot;
    let lines = [
        "qm1,qm2,qm3,qm4,qm5,qm6",
        "# approach",
        "0,0,0.5,0,0,0",
        "",
        "0,0,0.5,0,zero,0",
    ];
    for end in ["\n", "\r\n"] {
        let error = parse_program(
            file(&lines, end).as_bytes(),
            Path::new("p.csv"),
            &robot,
            &DataFormat::default(),
        )
        .expect_err("bad value")
        .to_string();
        assert!(error.starts_with("p.csv:5: qm5"), "{end:?}: {error}");
    }
}

/// A data file whose lines end in a carriage return alone reads as the
/// same file with line feeds, short or longer than what is read at once
/// (issue 75: "more records than lines … a bug of gecaro's reader").
#[test]
fn carriage_returns_alone_end_lines() {
    for rows in [3, 400_000] {
        let mut text = String::from("# cr\nqm1,qm2,x,y,z\n");
        for i in 0..rows {
            // 60 bytes a row: 400,000 rows are 24 MB, beyond the 16 MB read
            // at once, so the rest is read through the stream.
            text += &format!(
                "{:.9},{:.9},1.000000000,2.000000000,{:.9}\n",
                (i % 7) as f64,
                (i % 5) as f64,
                (i % 997) as f64 * 0.25
            );
        }
        let read = |text: &str| {
            parse_samples(
                text.as_bytes(),
                Path::new("d.csv"),
                &[FrameType::Revolute; 2],
                &[DataColumn::Position],
                &DataFormat::default(),
            )
            .expect("read")
            .samples
            .to_rows()
        };
        let (lf, cr) = (read(&text), read(&text.replace('\n', "\r")));
        assert_eq!(lf.len(), rows);
        assert!(rows < 1000 || text.len() > 16 << 20, "{}", text.len());
        assert_eq!(lf, cr, "{rows} rows");
    }
}

/// A line too long to be a record names its own line, in a short data
/// file, in one read in chunks and in a program (issue 75: line 2 for line
/// 102, 997,533 for 1,000,002).
#[test]
fn a_line_too_long_names_its_line() {
    let long = "1".repeat(1100 << 10);
    for rows in [100, 500_000] {
        let mut text = String::from("qm1,qm2,x,y,z\n");
        for _ in 0..rows {
            text += "0.100000000,0.200000000,0.100000000,0.200000000,0.300000000\n";
        }
        text += &long;
        text += "\n";
        let error = parse_samples(
            text.as_bytes(),
            Path::new("d.csv"),
            &[FrameType::Revolute; 2],
            &[DataColumn::Position],
            &DataFormat::default(),
        )
        .expect_err("long line")
        .to_string();
        let line = rows + 2;
        assert!(
            error.starts_with(&format!("d.csv:{line}: a line longer than")),
            "{rows}: {error}"
        );
    }
    let robot = load_robot("stanford").expect("robot").robot;
    let program = format!(
        "qm1,qm2,qm3,qm4,qm5,qm6\n{}{long}\n",
        "0,0,0.5,0,0,0\n".repeat(100)
    );
    let error = parse_program(
        program.as_bytes(),
        Path::new("p.csv"),
        &robot,
        &DataFormat::default(),
    )
    .expect_err("long line")
    .to_string();
    assert!(
        error.starts_with("p.csv:102: a line longer than"),
        "{error}"
    );
}
