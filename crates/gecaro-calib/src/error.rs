//! The one error type of `gecaro-calib`.

/// Errors of the calibration methods, identifiability and identification.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// An error of the robot model or the kinematics.
    #[error(transparent)]
    Model(#[from] gecaro_core::Error),
    /// No method has this name.
    #[error("unknown method `{name}`; the methods are: {}", .available.join(", "))]
    UnknownMethod {
        /// The name as given.
        name: String,
        /// The method names.
        available: Vec<&'static str>,
    },
    /// A setting is missing or impossible (a zero plane normal, a negative
    /// noise, ...).
    #[error("{setting}: {message}")]
    InvalidOption {
        /// The setting at fault.
        setting: Setting,
        /// What is wrong.
        message: String,
    },
    /// The measurements do not fit the method (a set of one configuration, a
    /// pair used three times, a missing column, ...).
    #[error("{}{message}", line_prefix(.line))]
    InvalidData {
        /// The line of the data file, when the samples came from one.
        line: Option<usize>,
        /// What is wrong.
        message: String,
    },
    /// The data's values are in another unit than the one they are read in
    /// (joint angles in degrees read as radians), named before any fitting.
    #[error("{message}")]
    WrongUnit {
        /// What is in the wrong unit: `angle` or `length`.
        quantity: &'static str,
        /// The unit the values look like they are in: `deg`, `mm`, …
        unit: &'static str,
        /// What is wrong, with the set.
        message: String,
    },
    /// Fewer independent equations than unknowns.
    #[error(
        "too few equations: the data give {equations} independent equations for {unknowns} \
         unknowns; add configurations (at least {unknowns} equations are needed, several \
         times more for a good identification)"
    )]
    TooFewEquations {
        /// Independent equations available.
        equations: usize,
        /// Unknowns to determine.
        unknowns: usize,
    },
    /// Configurations satisfying the method's constraint could not be found.
    #[error("points generation failed: {message}")]
    Generation {
        /// What could not be satisfied.
        message: String,
    },
    /// The caller's progress hook asked to stop (a user's Ctrl-C).
    #[error("interrupted")]
    Interrupted,
    /// A dense factorisation failed (only with non-finite input).
    #[error("numerical failure: {message}")]
    Numerical {
        /// What failed.
        message: String,
    },
}

fn line_prefix(line: &Option<usize>) -> String {
    match line {
        Some(line) => format!("line {line}: "),
        None => String::new(),
    }
}

/// A setting of a calibration job, named in the library's terms; each front
/// end words it its own way (`--error-level` on the command line,
/// `error_level=` in Python) from its [`key`](Setting::key).
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Setting {
    /// The error level of a simulated real robot (1 = ±1 cm, ±1°, ±1 %).
    ErrorLevel,
    /// A number of configurations to generate or choose.
    Count,
    /// The standard deviation of simulated sensor noise.
    Noise,
    /// The smallest joint-space distance between planned configurations.
    MinDistance,
    /// The poses a calibrated robot is judged at.
    TestPoses,
    /// The loss of identification.
    Loss,
    /// The scale of a robust loss.
    LossScale,
    /// The folds of a cross-validation.
    Folds,
    /// Which parameters may be identified.
    Model,
    /// The outlier threshold.
    OutlierThreshold,
    /// The plane of the plane methods (known or not, given or not).
    Plane,
    /// The normal of that plane.
    PlaneNormal,
    /// A point of that plane.
    PlanePoint,
    /// The configurations per set of generated link data.
    SetSize,
    /// A Gaussian prior around the nominal values.
    Prior,
    /// The floor of the measuring cell.
    Floor,
    /// The tracker station of the measuring cell.
    Station,
    /// The reflector's acceptance half-angle.
    MaxIncidence,
    /// The region of the joint space a calibrated robot is used in.
    WorkRegion,
    /// What a sensor measures (a method).
    Method,
    /// A measuring leg's gain.
    LegGain,
}

impl Setting {
    /// The setting's key, in snake case (`error_level`): what front ends
    /// name it after.
    pub fn key(self) -> &'static str {
        match self {
            Setting::ErrorLevel => "error_level",
            Setting::Count => "count",
            Setting::Noise => "noise",
            Setting::MinDistance => "min_distance",
            Setting::TestPoses => "test_poses",
            Setting::Loss => "loss",
            Setting::LossScale => "loss_scale",
            Setting::Folds => "cv",
            Setting::Model => "model",
            Setting::OutlierThreshold => "outlier_threshold",
            Setting::Plane => "plane",
            Setting::PlaneNormal => "plane_normal",
            Setting::PlanePoint => "plane_point",
            Setting::SetSize => "set_size",
            Setting::Prior => "prior",
            Setting::Floor => "floor",
            Setting::Station => "station",
            Setting::WorkRegion => "work_region",
            Setting::MaxIncidence => "max_incidence",
            Setting::Method => "method",
            Setting::LegGain => "leg_gain",
        }
    }
}

impl std::fmt::Display for Setting {
    /// The setting in words: `error level`, `plane normal`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let words = match self {
            Setting::Folds => "folds",
            Setting::MinDistance => "minimum distance",
            other => return f.write_str(&other.key().replace('_', " ")),
        };
        f.write_str(words)
    }
}
