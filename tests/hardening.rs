//! The command line under a careless user and a hostile file system: outputs
//! onto devices and FIFOs, FIFOs as inputs, signals in the middle of a write,
//! the temporary files of a killed process, robots whose limits stand for
//! "unlimited", and simulated data that stay within the joint limits. (The
//! bad inputs with a message of their own are rows of docs/errors.md, run by
//! tests/errors.rs.)

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::Duration;

use crate::util::gecaro_process as gecaro;

fn temporaries(folder: &Path) -> Vec<String> {
    std::fs::read_dir(folder)
        .expect("list")
        .map(|entry| {
            entry
                .expect("entry")
                .file_name()
                .to_string_lossy()
                .into_owned()
        })
        .filter(|name| name.starts_with(".gecaro-"))
        .collect()
}

#[cfg(unix)]
fn mkfifo(path: &Path) {
    let status = Command::new("mkfifo")
        .arg(path)
        .status()
        .expect("mkfifo runs");
    assert!(status.success());
}

/// Runs `command` with its output captured, for at most 30 s.
fn run_bounded(command: &mut Command) -> std::process::Output {
    let child = command
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("runs");
    wait_bounded(child, Duration::from_secs(30))
}

/// Waits for `child` at most `limit`; kills it and fails when it hangs.
fn wait_bounded(mut child: std::process::Child, limit: Duration) -> std::process::Output {
    let start = std::time::Instant::now();
    while child.try_wait().expect("wait").is_none() {
        if start.elapsed() > limit {
            let _ = child.kill();
            panic!("gecaro hung for {limit:?}");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().expect("output")
}

/// `-o -` (the standard output, to many tools) is refused with a sentence
/// naming what to do, and leaves no file named `-` behind.
#[test]
fn a_dash_output_is_refused_not_written_as_a_file() {
    let folder = tempfile::tempdir().expect("folder");
    for args in [
        &["robot", "new", "--joints", "RR", "-o", "-"][..],
        &[
            "generate", "stanford", "--method", "position", "--count", "20", "-o", "-",
        ][..],
    ] {
        let output = gecaro()
            .current_dir(folder.path())
            .args(args)
            .output()
            .expect("runs");
        assert!(!output.status.success(), "{args:?}: {output:?}");
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(stderr.contains("/dev/stdout"), "{args:?}: {stderr}");
        assert!(!folder.path().join("-").exists(), "{args:?} wrote `-`");
    }
}

#[cfg(unix)]
#[test]
fn a_device_output_is_written_to_not_replaced() {
    use std::os::unix::fs::FileTypeExt as _;
    let output = gecaro()
        .args(["robot", "new", "--joints", "RR", "-o", "/dev/null"])
        .output()
        .expect("runs");
    assert!(output.status.success(), "{output:?}");
    let kind = std::fs::metadata("/dev/null").expect("exists").file_type();
    assert!(kind.is_char_device(), "/dev/null is no longer a device");
}

#[cfg(unix)]
#[test]
fn a_fifo_output_receives_the_file() {
    let folder = tempfile::tempdir().expect("folder");
    let fifo = folder.path().join("robot.toml");
    mkfifo(&fifo);
    let reader = {
        let fifo = fifo.clone();
        std::thread::spawn(move || std::fs::read_to_string(fifo).expect("read the FIFO"))
    };
    let output = run_bounded(
        gecaro()
            .args(["robot", "new", "--joints", "RR", "-o"])
            .arg(&fifo),
    );
    assert!(output.status.success(), "{output:?}");
    assert!(reader.join().expect("reader").contains("[[frame]]"));
    use std::os::unix::fs::FileTypeExt as _;
    assert!(
        std::fs::symlink_metadata(&fifo)
            .expect("still there")
            .file_type()
            .is_fifo()
    );
}

#[cfg(unix)]
#[test]
fn a_fifo_input_is_refused_without_waiting_for_a_writer() {
    let folder = tempfile::tempdir().expect("folder");
    let fifo = folder.path().join("data.csv");
    mkfifo(&fifo);
    let output = run_bounded(
        gecaro()
            .args(["evaluate", "stanford", "--method", "position", "--data"])
            .arg(&fifo),
    );
    assert_eq!(output.status.code(), Some(3));
    assert!(
        String::from_utf8_lossy(&output.stderr).contains("not a regular file"),
        "{output:?}"
    );
}

#[cfg(target_os = "linux")]
#[test]
fn the_temporary_files_of_a_dead_process_are_removed_by_the_next_write() {
    let folder = tempfile::tempdir().expect("folder");
    // No process has this number (above the kernel's largest pid).
    let stale = folder.path().join(".gecaro-4194399-0.tmp");
    std::fs::write(&stale, "half a file").expect("plant");
    let live = folder
        .path()
        .join(format!(".gecaro-{}-0.tmp", std::process::id()));
    std::fs::write(&live, "a living process's file").expect("plant");
    let output = gecaro()
        .args(["robot", "new", "--joints", "RR", "-o"])
        .arg(folder.path().join("arm.toml"))
        .output()
        .expect("runs");
    assert!(output.status.success(), "{output:?}");
    assert!(!stale.exists(), "a dead process's temporary file stayed");
    assert!(
        live.exists(),
        "a running process's temporary file was removed"
    );
}

/// Writes interrupted by SIGINT and SIGTERM at moments spread over their
/// length leave no temporary file.
#[cfg(unix)]
#[test]
fn signals_during_writes_leave_no_temporary_file() {
    let folder = tempfile::tempdir().expect("folder");
    // The run takes ~0.2 s (debug build), the write of its 5 MB the last
    // part of it: signals land from 10 ms to 0.4 s after the start.
    let mut interrupted = 0;
    for attempt in 0..40u64 {
        let child = gecaro()
            .args([
                "generate", "panda", "--method", "frame", "--count", "20000", "--force", "-o",
            ])
            .arg(folder.path().join("data.csv"))
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .expect("runs");
        std::thread::sleep(Duration::from_millis(10 + 10 * attempt));
        let signal = if attempt % 2 == 0 { "-INT" } else { "-TERM" };
        let _ = Command::new("kill")
            .args([signal, &child.id().to_string()])
            .status();
        let output = wait_bounded(child, Duration::from_secs(60));
        if !output.status.success() {
            interrupted += 1;
        }
        assert_eq!(
            temporaries(folder.path()),
            Vec::<String>::new(),
            "attempt {attempt} ({signal})"
        );
    }
    assert!(interrupted > 0, "no run was interrupted");
}

#[test]
fn an_imported_urdf_whose_limits_stand_for_unlimited_generates() {
    let folder = tempfile::tempdir().expect("folder");
    let urdf = folder.path().join("arm.urdf");
    std::fs::write(
        &urdf,
        r#"<robot name="arm"><link name="a"/><link name="b"/><link name="c"/>
<joint name="j1" type="revolute"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/>
<limit lower="-1e308" upper="1e308" effort="1" velocity="1"/></joint>
<joint name="j2" type="revolute"><parent link="b"/><child link="c"/><origin xyz="0.4 0 0"/>
<axis xyz="0 1 0"/><limit lower="-2" upper="2" effort="1" velocity="1"/></joint></robot>"#,
    )
    .expect("write");
    let robot = folder.path().join("arm.toml");
    let output = gecaro()
        .args(["robot", "import"])
        .arg(&urdf)
        .arg("-o")
        .arg(&robot)
        .output()
        .expect("runs");
    assert!(output.status.success(), "{output:?}");
    assert!(
        String::from_utf8_lossy(&output.stderr).contains("stands for no limit"),
        "{output:?}"
    );
    let output = gecaro()
        .arg("generate")
        .arg(&robot)
        .args(["--method", "position", "--count", "50", "-o"])
        .arg(folder.path().join("data.csv"))
        .output()
        .expect("runs");
    assert!(output.status.success(), "{output:?}");
}

/// Simulated measurements are taken where the nominal robot reads joint
/// values within its limits: identifying them warns of nothing.
#[test]
fn generated_configurations_lie_within_the_nominal_limits() {
    let folder = tempfile::tempdir().expect("folder");
    let data = folder.path().join("data.csv");
    for robot in [
        "stanford",
        "puma560",
        "industrial6",
        "scara",
        "panda",
        "ur10e",
    ] {
        let output = gecaro()
            .args(["generate", robot, "--method", "frame", "--count", "5000"])
            .args(["--error-level", "2", "--noise", "1e-5", "--force", "-o"])
            .arg(&data)
            .output()
            .expect("runs");
        assert!(output.status.success(), "{robot}: {output:?}");
        let output = gecaro()
            .args(["evaluate", robot, "--method", "frame", "--data"])
            .arg(&data)
            .output()
            .expect("runs");
        let printed = String::from_utf8_lossy(&output.stderr);
        assert!(output.status.success(), "{robot}: {printed}");
        assert!(
            !printed.contains("outside the joint limits"),
            "{robot}: {printed}"
        );
    }
}

/// Names from files reach the terminal escaped: a robot named with an
/// escape sequence and a right-to-left override, and a URDF joint with a
/// newline and a tab in its name.
#[test]
fn hidden_characters_in_names_are_printed_escaped() {
    let folder = tempfile::tempdir().expect("folder");
    let robot = folder.path().join("robot.toml");
    std::fs::write(
        &robot,
        "name = \"arm\\u001b[2J\\u0007\\u202e\"\n[[frame]]\nsigma = 2\n[[frame]]\nsigma = 0\n\
         [[frame]]\nsigma = 2\nd = 0.4\n",
    )
    .expect("write");
    let output = gecaro()
        .args(["robot", "show"])
        .arg(&robot)
        .output()
        .expect("runs");
    let printed = String::from_utf8_lossy(&output.stdout);
    assert!(output.status.success(), "{output:?}");
    assert!(printed.contains(r"arm\u{1b}[2J\u{7}\u{202e}"), "{printed}");
    assert!(
        !printed.contains(['\u{1b}', '\u{7}', '\u{202e}']),
        "{printed}"
    );

    let urdf = folder.path().join("arm.urdf");
    std::fs::write(
        &urdf,
        "<robot name=\"r&#xA;x\"><link name=\"a\"/><link name=\"b\"/>\
         <joint name=\"j&#xA;&#x9;&#x202E;\" type=\"revolute\"><parent link=\"a\"/>\
         <child link=\"b\"/><axis xyz=\"0 0 1\"/></joint></robot>",
    )
    .expect("write");
    let output = gecaro()
        .args(["robot", "import"])
        .arg(&urdf)
        .arg("-o")
        .arg(folder.path().join("imported.toml"))
        .output()
        .expect("runs");
    assert!(output.status.success(), "{output:?}");
    let printed = format!(
        "{}{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    );
    assert!(printed.contains(r"j\u{a}\u{9}\u{202e}"), "{printed}");
    assert!(printed.contains(r"r\u{a}x"), "{printed}");
    assert!(!printed.contains(['\t', '\u{202e}']), "{printed}");
}

/// Numbers in messages are short whatever their size.
#[test]
fn tiny_and_huge_numbers_are_printed_in_scientific_notation() {
    let folder = tempfile::tempdir().expect("folder");
    let robot = folder.path().join("robot.toml");
    std::fs::write(
        &robot,
        "name = \"arm\"\n[[frame]]\nsigma = 2\n[[frame]]\nsigma = 0\nqmin = 2e-320\n\
         qmax = 1e-320\n[[frame]]\nsigma = 2\nd = 0.4\n",
    )
    .expect("write");
    let output = gecaro()
        .args(["robot", "check"])
        .arg(&robot)
        .output()
        .expect("runs");
    let printed = String::from_utf8_lossy(&output.stderr);
    assert!(
        printed.contains("qmin = 2e-320 is greater than qmax = 1e-320"),
        "{printed}"
    );
    assert!(printed.len() < 400, "{printed}");
}

/// A 24 KB study naming 200 reflectors over one small file is refused with
/// a message, before any matrix is allocated (it aborted allocating 6 GB).
#[test]
fn a_study_of_two_hundred_tools_is_refused_with_a_message() {
    let folder = tempfile::tempdir().expect("folder");
    let data = folder.path().join("smr.csv");
    let generated = gecaro()
        .args([
            "generate",
            "industrial6",
            "--method",
            "position",
            "--count",
            "40",
            "-o",
        ])
        .arg(&data)
        .output()
        .expect("runs");
    assert!(generated.status.success(), "{generated:?}");
    let mut study = String::from("robot = \"industrial6\"\n");
    for k in 0..200 {
        study += &format!(
            "[tools.t{k}]\nposition = [0, 0, {}]\n",
            0.05 + 1e-4 * f64::from(k)
        );
    }
    for k in 0..200 {
        study += &format!(
            "[[measurements]]\nmethod = \"position\"\ndata = \"smr.csv\"\ntool = \"t{k}\"\nsigma = 2e-5\n"
        );
    }
    let path = folder.path().join("study.toml");
    std::fs::write(&path, study).expect("study");
    for command in ["identify", "identifiable"] {
        let output = run_bounded(gecaro().args([command, "--study"]).arg(&path));
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(3), "{command}: {stderr}");
        assert!(
            stderr.contains("200 tools and stations: a study names at most 64"),
            "{command}: {stderr}"
        );
    }
}

/// A 64-joint robot asked for 100 positions: 300 equations for 319 base
/// parameters is known before the search (it searched 66–112 s).
#[test]
fn too_few_equations_for_a_plan_are_said_before_the_search() {
    let folder = tempfile::tempdir().expect("folder");
    let robot = folder.path().join("r64.toml");
    let made = gecaro()
        .args(["robot", "new", "--joints", &"R".repeat(64), "-o"])
        .arg(&robot)
        .output()
        .expect("runs");
    assert!(made.status.success(), "{made:?}");
    let output = run_bounded(
        gecaro()
            .arg("plan")
            .arg(&robot)
            .args([
                "--method", "position", "--count", "100", "--pool", "2000", "-o",
            ])
            .arg(folder.path().join("plan.csv")),
    );
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(4), "{stderr}");
    assert!(
        stderr.contains("300 independent equations for 319 unknowns"),
        "{stderr}"
    );
}

/// A cell that admits nothing (a floor 100 m up): the first configuration's
/// search fails and the rest are not searched (20,000 of them ran 18
/// minutes); nothing is written.
#[test]
fn a_cell_that_admits_nothing_fails_fast() {
    let folder = tempfile::tempdir().expect("folder");
    let output_file = folder.path().join("data.csv");
    let output = run_bounded(
        gecaro()
            .args([
                "generate",
                "industrial6",
                "--method",
                "position",
                "--count",
                "20000",
            ])
            .args(["--floor", "100", "-o"])
            .arg(&output_file),
    );
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(4), "{stderr}");
    assert!(
        stderr.contains("the cell leaves next to nothing to measure: 20000 configuration(s)"),
        "{stderr}"
    );
    assert!(!output_file.exists());
}

/// `gecaro serve` stopped by SIGINT while a request computes for tens of
/// seconds: it stops within the grace for requests under way (5 s), not
/// when the computation ends (it lived 151 s); SIGTERM likewise.
#[cfg(unix)]
#[test]
fn the_server_stops_on_a_signal_while_work_runs() {
    use std::io::{BufRead, BufReader, Write};
    for signal in ["-INT", "-TERM"] {
        let folder = tempfile::tempdir().expect("folder");
        let mut server = gecaro()
            .args(["serve", "--port", "0", "--dir"])
            .arg(folder.path())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("serves");
        let mut line = String::new();
        BufReader::new(server.stdout.take().expect("stdout"))
            .read_line(&mut line)
            .expect("banner");
        let address = line
            .split("http://")
            .nth(1)
            .and_then(|rest| rest.split(['/', ' ']).next())
            .unwrap_or_else(|| panic!("no address in {line:?}"))
            .to_owned();
        // A plan of 1,500 configurations from 20,000: long in a debug build.
        let body = r#"{"robot": "stanford", "method": {"name": "position"}, "count": 1500}"#;
        let mut stream = std::net::TcpStream::connect(&address).expect("connects");
        write!(
            stream,
            "POST /api/plan HTTP/1.1\r\nHost: {address}\r\nContent-Type: application/json\r\n\
             Content-Length: {}\r\n\r\n{body}",
            body.len()
        )
        .expect("request");
        std::thread::sleep(Duration::from_millis(1500));
        let stopped = std::time::Instant::now();
        let status = Command::new("kill")
            .arg(signal)
            .arg(server.id().to_string())
            .status()
            .expect("kill");
        assert!(status.success());
        let output = wait_bounded(server, Duration::from_secs(15));
        assert!(
            stopped.elapsed() < Duration::from_secs(10),
            "{signal}: stopped after {:?}",
            stopped.elapsed()
        );
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(stderr.contains("stopping"), "{signal}: {stderr}");
        assert!(temporaries(folder.path()).is_empty());
    }
}
