//! A study's statement ([`StudySpec`]) built through a front end's
//! [`Files`]: the robot, priority matrix and data files it names are read
//! beside the study file (or in the served folder for the web page's JSON),
//! and a field at fault is named by its study file's line, or by its path in
//! the request (`study.measurements[0].sigma`).
//!
//! Every set's configurations count against one bound for the whole study
//! ([`Files::max_samples`]): four sets naming one large file hold four times
//! its rows.

use std::path::Path;

use crate::{SpecField, StudyData, StudyFile, StudyFiles, StudySpec, StudyText};
use gecaro_calib::study::DataColumn;
use gecaro_core::{FrameType, PriorityMatrix, Robot};
use gecaro_io::{DataFile, DataFormat, RobotFile};

use crate::error::{AppError, ErrorKind};
use crate::files::Files;
use crate::sources::{DataSource, RobotSource};

/// Where a study was stated: a study file (its text, for lines) or a
/// request's JSON.
enum Statement<'a> {
    File(&'a StudyText),
    Request,
}

/// The files of a study through a front end's [`Files`].
struct StudyThroughFiles<'a> {
    files: &'a dyn Files,
    /// The study file's folder (names are relative to it), or "".
    folder: &'a Path,
    statement: Statement<'a>,
    /// The robot of a request's study that does not name one.
    given: Option<&'a RobotFile>,
}

impl StudyThroughFiles<'_> {
    fn name(&self, name: &str) -> String {
        self.folder.join(name).to_string_lossy().into_owned()
    }
}

impl StudyFiles for StudyThroughFiles<'_> {
    type Error = AppError;

    fn given_robot(&self) -> Option<RobotFile> {
        self.given.cloned()
    }

    fn robot(&self, name: &str) -> Result<RobotFile, AppError> {
        let beside = self.name(name);
        let name = if self.files.is_file(&beside) {
            beside
        } else {
            name.to_owned()
        };
        RobotSource::Named(name).load(self.files)
    }

    fn priority(&self, name: &str, robot: &Robot) -> Result<PriorityMatrix, AppError> {
        let (path, text) = self.files.read_text(&self.name(name), &["toml"])?;
        Ok(gecaro_io::parse_priority_file(&text, &path, robot)?)
    }

    fn samples(
        &self,
        name: &str,
        joint_types: &[FrameType],
        columns: &[DataColumn],
        format: &DataFormat,
    ) -> Result<(DataFile, String), AppError> {
        let read =
            DataSource::File(self.name(name)).read(self.files, joint_types, columns, format)?;
        let label = read.label.clone();
        Ok((
            DataFile {
                samples: read.samples,
                unused_columns: read.unused_columns,
                notes: read.notes,
            },
            label,
        ))
    }

    fn max_configurations(&self) -> usize {
        self.files.max_samples()
    }

    fn too_large(&self, _: &str, message: String) -> AppError {
        AppError::plain(ErrorKind::TooLarge, message)
    }

    fn text(&self, name: &str) -> Result<(String, String), AppError> {
        let (path, text) = self.files.read_text(&self.name(name), &["csv"])?;
        Ok((text, path.display().to_string()))
    }

    fn misplaced(&self, field: &SpecField, message: String) -> AppError {
        match self.statement {
            Statement::File(text) => text.misplaced(field, message).into(),
            Statement::Request => {
                AppError::plain(ErrorKind::Input, format!("study.{field}: {message}"))
            }
        }
    }
}

/// The study file `name`, read through `files` with what it names.
///
/// # Errors
/// The file's line at fault, or the errors of the files it names.
pub(crate) fn read_study(
    files: &dyn Files,
    name: &str,
    data: StudyData,
) -> Result<StudyFile, AppError> {
    let (path, text) = files.read_text(name, &["toml"])?;
    let text = StudyText::parse(text, &path)?;
    text.spec.build(
        &StudyThroughFiles {
            files,
            folder: Path::new(name).parent().unwrap_or(Path::new("")),
            statement: Statement::File(&text),
            given: None,
        },
        data,
    )
}

/// A request's study, its files read through `files` (in the served folder
/// for the web page), with `given` as its robot when it names none (the
/// page's table).
///
/// # Errors
/// The field at fault, or the errors of the files it names.
pub(crate) fn build_study(
    files: &dyn Files,
    spec: &StudySpec,
    data: StudyData,
    given: Option<&RobotFile>,
) -> Result<StudyFile, AppError> {
    spec.build(
        &StudyThroughFiles {
            files,
            folder: Path::new(""),
            statement: Statement::Request,
            given,
        },
        data,
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::files::{LocalFiles, Opened};

    /// The file system, taking at most 50 configurations per data set.
    struct Small;

    impl Files for Small {
        fn open(&self, name: &str, extensions: &[&str]) -> Result<Opened, AppError> {
            LocalFiles.open(name, extensions)
        }
        fn read_text(
            &self,
            name: &str,
            extensions: &[&str],
        ) -> Result<(std::path::PathBuf, String), AppError> {
            LocalFiles.read_text(name, extensions)
        }
        fn is_file(&self, name: &str) -> bool {
            LocalFiles.is_file(name)
        }
        fn check_output(
            &self,
            name: &str,
            extension: &str,
            overwrite: bool,
        ) -> Result<(), AppError> {
            LocalFiles.check_output(name, extension, overwrite)
        }
        fn write(
            &self,
            name: &str,
            extension: &str,
            bytes: &[u8],
            overwrite: bool,
        ) -> Result<std::path::PathBuf, AppError> {
            LocalFiles.write(name, extension, bytes, overwrite)
        }
        fn remove(&self, name: &str) {
            LocalFiles.remove(name);
        }
        fn max_samples(&self) -> usize {
            50
        }
    }

    #[test]
    fn the_bound_on_configurations_holds_for_the_whole_study() {
        let folder = tempfile::tempdir().expect("folder");
        let cell = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/tracker-cell");
        // The file holds 25 configurations: two sets are taken, three are not.
        let rows: Vec<String> = std::fs::read_to_string(cell.join("smr_a_1.csv"))
            .expect("data")
            .lines()
            .take(31)
            .map(str::to_owned)
            .collect();
        std::fs::write(folder.path().join("a.csv"), rows.join("\n")).expect("data");
        let study = |sets: usize| {
            let mut text = String::from(
                "robot = \"industrial6\"\nlength_unit = \"mm\"\nangle_unit = \"deg\"\n",
            );
            for _ in 0..sets {
                text += "[[measurements]]\nmethod = \"position\"\ndata = \"a.csv\"\nsigma = 0.02\n";
            }
            let path = folder.path().join(format!("study{sets}.toml"));
            std::fs::write(&path, text).expect("study");
            path.to_string_lossy().into_owned()
        };
        let two = read_study(&Small, &study(2), StudyData::Measured).expect("two sets");
        assert_eq!(two.study.sets[1].samples.len(), 25);
        let error = read_study(&Small, &study(3), StudyData::Measured).expect_err("three sets");
        assert_eq!(error.kind(), ErrorKind::TooLarge);
        assert!(
            error.to_string().contains("75 configurations together"),
            "{error}"
        );
    }
}
