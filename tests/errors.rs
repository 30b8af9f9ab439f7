//! Every row of the table of bad inputs in `docs/errors.md`, run exactly as
//! written there: the command, from a copy of the repository's
//! `tests/errors/` folder, must exit with the documented code and print the
//! documented message, and must leave no file new or changed.

use std::collections::BTreeMap;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

/// One documented bad input.
#[derive(Debug)]
struct Row {
    id: String,
    command: String,
    message: String,
    exit: i32,
}

/// The content of a markdown table cell: the text of its code span, if any.
fn cell_text(cell: &str) -> String {
    let cell = cell.trim();
    let ticks = cell.chars().take_while(|c| *c == '`').count();
    if ticks == 0 {
        return cell.to_owned();
    }
    let inner = &cell[ticks..cell.len() - ticks];
    if ticks > 1 {
        inner.trim().to_owned()
    } else {
        inner.to_owned()
    }
}

fn rows() -> Vec<Row> {
    let doc = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/errors.md"))
        .expect("docs/errors.md");
    doc.lines()
        .filter_map(|line| {
            let cells: Vec<&str> = line.trim().trim_matches('|').split(" | ").collect();
            let id = cells.first()?.trim();
            let is_row = id.len() == 3
                && "RDPCIH".contains(&id[..1])
                && id[1..].chars().all(|c| c.is_ascii_digit());
            if !is_row {
                return None;
            }
            assert_eq!(cells.len(), 5, "row {id} needs 5 cells: {line}");
            Some(Row {
                id: id.to_owned(),
                command: cell_text(cells[2]),
                message: cell_text(cells[3]),
                exit: cells[4].trim().parse().expect("exit code"),
            })
        })
        .collect()
}

fn row(id: &str) -> Row {
    rows()
        .into_iter()
        .find(|row| row.id == id)
        .unwrap_or_else(|| panic!("docs/errors.md has no row {id}"))
}

/// Whitespace collapsed, miette's decoration dropped.
fn normalise(text: &str) -> String {
    text.replace('×', " ")
        .replace("╰─▶", " ")
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ")
}

/// Every file below `folder` with its bytes.
fn snapshot(folder: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    let mut files = BTreeMap::new();
    let mut pending = vec![folder.to_owned()];
    while let Some(current) = pending.pop() {
        for entry in std::fs::read_dir(&current).expect("list").flatten() {
            let path = entry.path();
            if path.is_dir() {
                pending.push(path);
            } else {
                let bytes = std::fs::read(&path).expect("read");
                files.insert(path.strip_prefix(folder).expect("inside").to_owned(), bytes);
            }
        }
    }
    files
}

/// A copy of `tests/errors/` under `tests/errors/` of a fresh folder.
fn workspace() -> tempfile::TempDir {
    let root = tempfile::tempdir().expect("folder");
    let target = root.path().join("tests/errors");
    std::fs::create_dir_all(&target).expect("mkdir");
    let source = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/errors");
    for entry in std::fs::read_dir(source).expect("fixtures").flatten() {
        std::fs::copy(entry.path(), target.join(entry.file_name())).expect("copy");
    }
    root
}

/// Endless valid rows for a 2-joint position data set.
fn endless(mut stdin: std::process::ChildStdin) {
    let mut block = String::from("qm1,qm2,x,y,z\n");
    let row = "0.1,0.2,0.85,0.13,0\n";
    if stdin.write_all(block.as_bytes()).is_err() {
        return;
    }
    block = row.repeat(4096);
    while stdin.write_all(block.as_bytes()).is_ok() {}
}

fn check(id: &str) {
    let row = row(id);
    let folder = workspace();
    let before = snapshot(folder.path());
    let mut words = row.command.split_whitespace();
    assert_eq!(
        words.next(),
        Some("gecaro"),
        "{id}: commands start with gecaro"
    );
    let arguments: Vec<&str> = words.collect();
    let mut command = Command::new(assert_cmd::cargo::cargo_bin("gecaro"));
    command
        .args(&arguments)
        .current_dir(folder.path())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    let streams = arguments.contains(&"/dev/stdin");
    command.stdin(if streams {
        Stdio::piped()
    } else {
        Stdio::null()
    });
    let mut child = command.spawn().expect("gecaro runs");
    let feeder = child
        .stdin
        .take()
        .map(|stdin| std::thread::spawn(move || endless(stdin)));
    let output = child.wait_with_output().expect("gecaro ends");
    if let Some(feeder) = feeder {
        feeder.join().expect("feeder");
    }
    let printed = normalise(&format!(
        "{}\n{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    ));
    assert_eq!(
        output.status.code(),
        Some(row.exit),
        "{id}: `{}` exit code; printed:\n{printed}",
        row.command
    );
    let expected = normalise(&row.message);
    let mut rest = printed.as_str();
    for part in expected.split('…').map(str::trim).filter(|p| !p.is_empty()) {
        match rest.find(part) {
            Some(at) => rest = &rest[at + part.len()..],
            None => panic!(
                "{id}: `{}` should print\n  {expected}\nbut printed\n  {printed}",
                row.command
            ),
        }
    }
    assert_eq!(
        snapshot(folder.path()),
        before,
        "{id}: files were created or changed"
    );
}

macro_rules! rows {
    ($($name:ident => $id:literal),* $(,)?) => {
        $(#[test] fn $name() { check($id); })*

        #[test]
        fn every_documented_row_has_a_test() {
            let tested: Vec<&str> = vec![$($id),*];
            let documented: Vec<String> = rows().into_iter().map(|row| row.id).collect();
            assert_eq!(documented, tested, "docs/errors.md and tests/errors.rs list the same rows");
            assert!(documented.len() >= 25);
        }
    };
}

rows! {
    r01_not_toml => "R01",
    r02_unknown_key => "R02",
    r03_sigma_not_a_frame_type => "R03",
    r04_base_not_fixed => "R04",
    r05_tool_not_fixed => "R05",
    r06_fixed_frame_between_joints => "R06",
    r07_too_few_frames => "R07",
    r08_nan => "R08",
    r09_infinite => "R09",
    r10_qmin_above_qmax => "R10",
    r11_coupling_size => "R11",
    r12_coupling_singular => "R12",
    r13_priority_shape => "R13",
    r14_priority_negative => "R14",
    r15_degrees_in_radians => "R15",
    r16_gain_underflow => "R16",
    r17_gain_huge => "R17",
    r18_coupling_huge => "R18",
    d01_missing_header => "D01",
    d02_columns_of_another_method => "D02",
    d03_short_row => "D03",
    d04_not_a_number => "D04",
    d05_nan => "D05",
    d06_single_configuration_set => "D06",
    d07_pair_used_once => "D07",
    d08_pair_used_three_times => "D08",
    d09_quaternion_not_unit => "D09",
    d10_outside_limits_warns => "D10",
    d11_outside_limits_refused => "D11",
    d12_empty => "D12",
    d13_not_utf8 => "D13",
    d14_endless_stream => "D14",
    d15_missing_file => "D15",
    d16_unused_columns_noted => "D16",
    d17_column_map_that_does_not_fit => "D17",
    d18_rounded_quaternions_noted => "D18",
    d19_semicolon_separated_file => "D19",
    d20_duplicate_key => "D20",
    d21_huge_measured_value => "D21",
    i01_not_well_formed_xml => "I01",
    i02_unknown_link => "I02",
    i03_branch_without_tip => "I03",
    i04_mimic_outside_the_chain => "I04",
    i05_xacro => "I05",
    i06_zero_axis => "I06",
    i07_floating_joint => "I07",
    i08_nan_in_a_table => "I08",
    i09_short_table_row => "I09",
    i10_table_without_convention => "I10",
    i11_beta_into_dh => "I11",
    i12_import_over_an_existing_file => "I12",
    p01_too_few_equations => "P01",
    p02_poorly_excited => "P02",
    p03_iteration_limit => "P03",
    p04_unreachable_target => "P04",
    p05_residuals_above_the_stated_noise => "P05",
    p06_copies_of_one_configuration => "P06",
    p07_sigma_not_a_standard_deviation => "P07",
    p08_metres_read_as_millimetres => "P08",
    p09_sigma_far_too_large => "P09",
    p10_a_joint_that_never_moved => "P10",
    p11_barely_more_equations_than_unknowns => "P11",
    p12_millimetres_read_as_metres => "P12",
    c01_unknown_method => "C01",
    c02_unknown_ready_robot => "C02",
    c03_output_in_missing_folder => "C03",
    c04_output_exists => "C04",
    c05_configuration_length => "C05",
    c06_not_a_number_option => "C06",
    c07_unknown_joint_type => "C07",
    h01_error_level_beyond_the_bound => "H01",
    h02_noise_beyond_the_bound => "H02",
    h03_count_beyond_the_cap => "H03",
    h04_pool_beyond_the_cap => "H04",
    h05_curve_count_beyond_the_cap => "H05",
    h06_monte_carlo_beyond_the_cap => "H06",
    h07_joint_limit_standing_for_unlimited => "H07",
    h08_robot_of_a_hundred_joints => "H08",
    h09_urdf_nested_too_deep => "H09",
    h10_urdf_of_too_many_links => "H10",
    h11_urdf_without_links => "H11",
    h12_output_that_is_an_input => "H12",
    h13_report_over_its_data => "H13",
    h14_two_outputs_in_one_file => "H14",
    h15_sigma_no_instrument_has => "H15",
    h16_prior_beyond_reason => "H16",
    h17_world_frame_far_away => "H17",
    h18_robot_rebased_onto_another => "H18",
}
