//! A study's statement opened for editing and saved again: the web page's
//! study editor works on the [`StudySpec`] (a study file's keys as JSON), and
//! the file it saves is the statement as TOML, read back before it is
//! written (so every file saved here opens again, to the same statement).

use std::path::Path;

use crate::{SetData, StudySpec, StudyText};
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
    let mut spec = StudyText::parse(text, &path)?.spec;
    // A study names its files relative to its own folder; a statement, as
    // the page runs it, relative to the front end's (issue 75: a study in
    // a subfolder read the root's files of the same names).
    let folder = folder_of(name);
    if !folder.is_empty() {
        // A set's data file may not be measured yet (a planned cell).
        rename_files(&mut spec, |name, always_a_file| {
            let joined = format!("{folder}/{name}");
            Ok(
                (!Path::new(name).is_absolute() && (always_a_file || files.is_file(&joined)))
                    .then_some(joined),
            )
        })?;
    }
    Ok(spec)
}

/// The folder part of a front end's file name (`cell` of
/// `cell/study.toml`; empty at the root).
fn folder_of(name: &str) -> &str {
    name.rsplit_once('/').map_or("", |(folder, _)| folder)
}

/// Renames every file `spec` names by `rename(name, always_a_file)`
/// (`None`: kept): its sets' data (always files, measured or not yet), and
/// its robot, priority and model (files, or a ready robot's or a model's
/// name).
///
/// # Errors
/// `rename`'s.
fn rename_files(
    spec: &mut StudySpec,
    rename: impl Fn(&str, bool) -> Result<Option<String>, AppError>,
) -> Result<(), AppError> {
    for set in &mut spec.measurements {
        if let SetData::File(name) = &mut set.data
            && !name.is_empty()
            && let Some(renamed) = rename(name.as_str(), true)?
        {
            *name = renamed;
        }
    }
    for name in [&mut spec.robot, &mut spec.priority, &mut spec.model]
        .into_iter()
        .flatten()
    {
        if let Some(renamed) = rename(name.as_str(), false)? {
            *name = renamed;
        }
    }
    Ok(())
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
        // Saved into a subfolder, the study names its files from there.
        let folder = folder_of(&self.name);
        let mut request = self.clone();
        if !folder.is_empty() {
            let prefix = format!("{folder}/");
            rename_files(&mut request.study, |name, always_a_file| {
                if let Some(inside) = name.strip_prefix(&prefix) {
                    return Ok(Some(inside.to_owned()));
                }
                if Path::new(name).is_absolute() || !(always_a_file || files.is_file(name)) {
                    // A ready robot's name, a model's, an absolute path.
                    return Ok(None);
                }
                Err(AppError::setting(
                    "name",
                    format!(
                        "{name} is outside the study's folder {folder}: a study names its files \
                         from its own folder; save it beside its files, or above them"
                    ),
                ))
            })?;
        }
        let text = request.text()?;
        files.write(&self.name, "toml", text.as_bytes(), self.overwrite)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A planned study in a subfolder names its set files from there even
    /// before they are measured; a ready robot's name stays a name.
    #[test]
    fn a_study_s_files_not_measured_yet_are_named_from_its_folder() {
        let folder = tempfile::tempdir().expect("folder");
        let cell = folder.path().join("cell");
        std::fs::create_dir(&cell).expect("cell");
        std::fs::write(
            cell.join("study.toml"),
            "robot = \"industrial6\"\n[[measurements]]\nmethod = \"position\"\ndata = \"s1.csv\"\nsigma = \"20um\"\n",
        )
        .expect("study");
        let name = cell.join("study.toml").display().to_string();
        let spec = open_study(&crate::files::LocalFiles, &name).expect("opened");
        let SetData::File(data) = &spec.measurements[0].data else {
            panic!("a file");
        };
        assert_eq!(Path::new(data), cell.join("s1.csv"));
        assert_eq!(spec.robot.as_deref(), Some("industrial6"));
    }

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
