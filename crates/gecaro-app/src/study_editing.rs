//! A study's statement opened for editing and saved again: the web page's
//! study editor works on the [`StudySpec`] (a study file's keys as JSON), and
//! the file it saves is the statement as TOML, read back before it is
//! written (so every file saved here opens again, to the same statement).

use gecaro_io::{StudySpec, StudyText};
use serde::Deserialize;

use crate::error::{AppError, ErrorKind};
use crate::files::Files;
use crate::measurements::Unknown;

/// The statement of the study file `name`, its keys and types checked (a
/// key at fault is named by its line); the files it names are not read.
///
/// # Errors
/// A file that cannot be read, or is not a study file.
pub fn open_study(files: &dyn Files, name: &str) -> Result<StudySpec, AppError> {
    let (path, text) = files.read_text(name, &["toml"])?;
    Ok(StudyText::parse(text, &path)?.spec)
}

/// A study statement to save as a study file.
#[derive(Clone, Debug, Deserialize)]
pub struct SaveStudyRequest {
    /// The study file to write (`.toml`).
    pub name: String,
    /// What it states.
    pub study: StudySpec,
    /// Replace a file that exists.
    #[serde(default)]
    pub overwrite: bool,
    #[serde(flatten)]
    unknown: Unknown,
}

impl SaveStudyRequest {
    /// The study file's text: the statement as TOML, checked to read back
    /// to the same statement.
    ///
    /// # Errors
    /// A statement TOML cannot hold (never for one read from JSON).
    pub fn text(&self) -> Result<String, AppError> {
        let failed = |what: &str| {
            AppError::plain(
                ErrorKind::Numerical,
                format!("the study could not be written as a study file ({what})"),
            )
        };
        let text = toml::to_string(&self.study).map_err(|error| failed(&error.to_string()))?;
        let again = StudyText::parse(text.clone(), std::path::Path::new(&self.name))?;
        let same = toml::to_string(&again.spec).map_err(|error| failed(&error.to_string()))?;
        if same != text {
            return Err(failed("it does not read back to the same statement"));
        }
        Ok(text)
    }

    /// Writes the study file (never over one unless `overwrite`; a failed
    /// write leaves nothing behind); the path written.
    ///
    /// # Errors
    /// As [`text`](Self::text), and the file's own errors.
    pub fn run(&self, files: &dyn Files) -> Result<std::path::PathBuf, AppError> {
        self.unknown.check()?;
        let text = self.text()?;
        files.write(&self.name, "toml", text.as_bytes(), self.overwrite)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_saved_study_reads_back_to_the_same_statement() {
        let cell = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../examples/tracker-cell/study.toml"
        );
        let text = std::fs::read_to_string(cell).expect("study");
        let spec = StudyText::parse(text, std::path::Path::new(cell))
            .expect("parses")
            .spec;
        let request: SaveStudyRequest = serde_json::from_value(serde_json::json!({
            "name": "copy.toml",
            "study": serde_json::to_value(&spec).expect("json"),
        }))
        .expect("request");
        let written = request.text().expect("text");
        let again = StudyText::parse(written.clone(), std::path::Path::new("copy.toml"))
            .expect("reads back");
        assert_eq!(again.spec.measurements.len(), 6);
        assert_eq!(again.spec.tools.len(), 3);
        assert_eq!(toml::to_string(&again.spec).expect("toml"), written);
    }
}
