//! Errors in CSV files name the line of the record at fault, whatever the
//! line ends (`\n`, `\r\n`) and however many comment and blank lines come
//! before it.

use std::path::Path;

use gecaro_calib::study::DataColumn;
use gecaro_core::FrameType;
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
    for end in ["\n", "\r\n"] {
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
