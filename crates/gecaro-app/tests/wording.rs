//! The libraries beneath the application layer describe problems in their
//! own terms ("noise must be finite"), never in a front end's ("--noise"):
//! the application layer words every error for each front end (Dialect).

use std::path::Path;

/// Strings of the libraries that may hold `--`: not options.
const ALLOWED: &[&str] = &[
    // A comment written into robot files, naming the command that uses it.
    "gecaro robot export --to urdf",
    // XML comments may not hold `--`.
    "replace(\"--\", \"- -\")",
];

fn sources(folder: &Path, out: &mut Vec<std::path::PathBuf>) {
    for entry in std::fs::read_dir(folder).expect("folder") {
        let path = entry.expect("entry").path();
        if path.is_dir() {
            sources(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

#[test]
fn library_messages_name_no_command_line_option() {
    let crates = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut files = Vec::new();
    for library in ["gecaro-core", "gecaro-calib", "gecaro-io"] {
        sources(&crates.join(library).join("src"), &mut files);
    }
    assert!(files.len() > 40, "{} files", files.len());
    let mut found = Vec::new();
    for file in files {
        let text = std::fs::read_to_string(&file).expect("text");
        // Unit tests may name options; the library's code may not.
        let code = text.split("#[cfg(test)]").next().unwrap_or_default();
        for (number, line) in code.lines().enumerate() {
            let trimmed = line.trim_start();
            if trimmed.starts_with("//") || ALLOWED.iter().any(|allowed| line.contains(allowed)) {
                continue;
            }
            let mut rest = line;
            while let Some(at) = rest.find("--") {
                let after = &rest[at + 2..];
                if after.starts_with(|c: char| c.is_ascii_lowercase()) && line.contains('"') {
                    found.push(format!(
                        "{}:{}: {}",
                        file.display(),
                        number + 1,
                        line.trim()
                    ));
                    break;
                }
                rest = after;
            }
        }
    }
    assert!(
        found.is_empty(),
        "options named in library code:\n{}",
        found.join("\n")
    );
}
