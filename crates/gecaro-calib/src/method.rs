//! The shared trait of the calibration methods (eq. 5–6), and of their
//! simulated sensors.
//!
//! A [`CalibrationMethod`] describes a method (its names, data columns,
//! auxiliary unknowns) and writes its linearised equations `Δy = W Δη` (eq. 6)
//! through a [`RowWriter`]; its [`Sensor`] simulates the measuring session
//! (points generation, measurements at planned configurations). The methods
//! themselves are in [`crate::methods`]; identifiability, identification and
//! points generation are written once against these traits.

use std::fmt;

use gecaro_core::{JacobianRows, OrientationDifference, Robot};

use crate::error::{Error, Setting};
use crate::plane::Plane;
use crate::progress::Observer;
use crate::rows::RowWriter;
use crate::sample::{DataColumn, Sample};
use crate::sampler::Sampler;
use crate::samples::SampleSlice;
use crate::states::TerminalState;

/// One calibration method; see the module docs.
pub trait CalibrationMethod: CloneMethod + fmt::Debug + Send + Sync {
    /// The method's entry in [`METHODS`](crate::methods::METHODS): its names and how it is built.
    fn info(&self) -> &'static MethodInfo;

    /// The name used in files and on the command line (`point-link`).
    fn name(&self) -> &'static str {
        self.info().name
    }

    /// The menu title of paper §4 (`Point link`).
    fn title(&self) -> &'static str {
        self.info().title
    }

    /// The data columns beyond `qm1..qmn` ([`MethodInfo::columns`]).
    fn data_columns(&self) -> &'static [DataColumn] {
        self.info().columns
    }

    /// Checks the structure of a data set (set and pair sizes). The presence
    /// of the [`data_columns`](Self::data_columns) fields is checked by the caller.
    ///
    /// # Errors
    /// [`Error::InvalidData`] naming the first line at fault.
    fn check_samples(&self, _samples: SampleSlice<'_>) -> Result<(), Error> {
        Ok(())
    }

    /// Number of rows of W that `samples` give: by default
    /// [`MethodInfo::rows_per_configuration`] per sample.
    fn row_count(&self, samples: SampleSlice<'_>) -> usize {
        self.info().rows_per_configuration * samples.len()
    }

    /// Rows that carry no independent information (one per set and dimension
    /// for mean-centred sets): independent equations = rows − dependent rows.
    fn dependent_rows(&self, _samples: SampleSlice<'_>) -> usize {
        0
    }

    /// Independent equations per configuration, roughly (to size random
    /// data): by default the rows per configuration.
    fn equations_per_configuration(&self) -> f64 {
        self.info().rows_per_configuration as f64
    }

    /// Whether the method's constraint still holds for the robot scaled about
    /// any point, i.e. it measures no length (link and plane methods): such
    /// data cannot observe the robot's scale (Table 2 loses it).
    fn scale_invariant(&self) -> bool {
        self.info().scale_invariant
    }

    /// Names of the method's own unknowns, identified with η (plane coefficients).
    fn auxiliary_names(&self) -> Vec<String> {
        Vec::new()
    }

    /// Initial values of the auxiliary unknowns, from the states at the
    /// starting parameters (e.g. the best-fit plane of the nominal points).
    /// Only the poses of `states` are evaluated ([`crate::observation::evaluate_poses`]).
    ///
    /// # Errors
    /// When they cannot be determined from these data.
    fn initial_auxiliary(&self, _states: &[TerminalState]) -> Result<Vec<f64>, Error> {
        Ok(Vec::new())
    }

    /// Whether [`initial_auxiliary`](Self::initial_auxiliary) or
    /// [`Sensor::generate_like`] read the poses of the data at
    /// the starting parameters; when not, they are not evaluated and those
    /// functions get no states. By default, when the method has auxiliary
    /// unknowns (the plane methods fit the data's plane only then).
    fn uses_starting_poses(&self) -> bool {
        !self.auxiliary_names().is_empty()
    }

    /// The rows of the parameter Jacobian that [`linearise`](Self::linearise)
    /// reads ([`MethodInfo::jacobian_rows`]); methods that measure no
    /// orientation say [`JacobianRows::Position`] and the model skips the
    /// rotation rows.
    fn jacobian_rows(&self) -> JacobianRows {
        self.info().jacobian_rows
    }

    /// Whether the rows of configuration i depend on nothing but its state,
    /// its sample and the auxiliary values, and belong to observation i
    /// (position, frame, plane-equation rows; not sets or pairs). Such a set
    /// is evaluated and linearised block by block, in parallel: `linearise`
    /// is then called on consecutive blocks of the samples
    /// ([`MethodInfo::independent`]).
    fn independent_configurations(&self) -> bool {
        self.info().independent
    }

    /// The samples of each observation, in the numbering `linearise` gives
    /// its rows, when an observation is not one configuration (a distance's
    /// pair); `None` (the default) when observation `k` is sample `k`
    /// (position, frame, plane, and the link methods, whose configurations
    /// are each compared with their set's mean), which lets large data sets
    /// be located without a list per sample.
    fn grouped_observations(&self, _samples: SampleSlice<'_>) -> Option<Vec<Vec<usize>>> {
        None
    }

    /// Writes the rows `Δy = W Δη` at the current parameters (whose poses and
    /// Jacobians are `states`, one per sample) and auxiliary values.
    fn linearise(
        &self,
        samples: SampleSlice<'_>,
        states: &[TerminalState],
        auxiliary: &[f64],
        rows: &mut RowWriter<'_>,
    );

    /// The measuring session of this method, simulated: points generation
    /// and measurements at planned configurations ([`Sensor`]).
    fn sensor(&self) -> &dyn Sensor;
}
/// A method's measuring session, simulated: what points generation (paper
/// §4) and measurements at planned configurations produce. Position and frame
/// sensors read the terminal frame; link, plane and distance sessions move
/// the robot onto their constraint first.
pub trait Sensor: fmt::Debug + Send + Sync {
    /// Generates about `count` configurations of `robot` that satisfy the
    /// method's constraint, with what a sensor would measure there, perturbed
    /// by Gaussian noise of standard deviation `noise` (metres; radians for
    /// orientations). `observer` hears of the configurations done
    /// ([`Progress::Step`](crate::Progress::Step)) and may stop the work.
    ///
    /// # Errors
    /// [`Error::Generation`] when configurations cannot be found,
    /// [`Error::Interrupted`] when the observer stops the work.
    fn generate(
        &self,
        robot: &Robot,
        count: usize,
        noise: f64,
        sampler: &mut Sampler,
        observer: &mut dyn Observer,
    ) -> Result<Vec<Sample>, Error>;

    /// Simulated measurements of `real` at planned configurations (`planned`:
    /// configurations with their set or pair ids, as `gecaro plan` writes
    /// them): the measuring session as it would run. Methods that measure at
    /// a configuration (position, frame, distance) measure there; methods
    /// whose configurations must satisfy a constraint (links, planes) move
    /// each to a configuration that satisfies it on `real`, starting from the
    /// planned one, as the operator does when seating the ball or touching
    /// the plane. Noise as in [`generate`](Self::generate).
    ///
    /// # Errors
    /// [`Error::InvalidData`] for sets or pairs that do not fit the method,
    /// [`Error::Generation`] when a configuration cannot be brought to the
    /// constraint, [`Error::Interrupted`] when `observer` stops the work.
    fn measure_at(
        &self,
        real: &Robot,
        planned: SampleSlice<'_>,
        noise: f64,
        sampler: &mut Sampler,
        observer: &mut dyn Observer,
    ) -> Result<Vec<Sample>, Error>;

    /// Whether [`measure_at`](Self::measure_at) reads an elastic robot where
    /// it settles under each planned sample's loads ([`Sample::torques`]):
    /// sensors that read the terminal frame do; those that first move the
    /// robot onto a constraint measure it rigid (docs/elastic.md).
    fn yields_to_loads(&self) -> bool {
        false
    }

    /// Noise-free random data of the same kind as `samples` (whose states at
    /// `robot` are `states`, poses only), for the structural identifiability
    /// of a data set. By default [`generate`](Self::generate); the plane methods use the
    /// best-fit plane of the data when they were given no plane.
    ///
    /// # Errors
    /// As [`generate`](Self::generate).
    fn generate_like(
        &self,
        robot: &Robot,
        _samples: SampleSlice<'_>,
        _states: &[TerminalState],
        count: usize,
        sampler: &mut Sampler,
        observer: &mut dyn Observer,
    ) -> Result<Vec<Sample>, Error> {
        self.generate(robot, count, 0.0, sampler, observer)
    }
}

/// Options that some methods take.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MethodOptions {
    /// The plane of the plane methods (needed to generate points; for
    /// identification it is the known plane, or the start for an unknown one).
    pub plane: Option<Plane>,
    /// Whether the plane (plane1) or its normal (plane2) is unknown and identified.
    pub plane_unknown: bool,
    /// How orientation differences are computed (Appendix I).
    pub orientation: OrientationDifference,
    /// Configurations per set when generating link data (default: 4 for
    /// point link, 2 for frame link).
    pub set_size: Option<usize>,
}

impl MethodOptions {
    /// The plane options from what a user said: `plane` if given, and whether
    /// it is unknown (`None`: known when given; without a plane only an
    /// unknown one makes sense).
    ///
    /// # Errors
    /// [`Error::InvalidOption`] when the plane is said to be known but not given.
    pub fn plane_choice(
        plane: Option<Plane>,
        unknown: Option<bool>,
    ) -> Result<(Option<Plane>, bool), Error> {
        match (unknown, plane) {
            (Some(false), None) => Err(Error::InvalidOption {
                setting: Setting::Plane,
                message: "a known plane needs its normal and a point".into(),
            }),
            (Some(unknown), plane) => Ok((plane, unknown)),
            (None, plane) => Ok((plane, plane.is_none())),
        }
    }

    /// Set sizes below 2 cannot make a link set.
    ///
    /// # Errors
    /// [`Error::InvalidOption`] for a size below 2.
    pub fn check_set_size(size: Option<usize>) -> Result<Option<usize>, Error> {
        match size {
            Some(size) if size < 2 => Err(Error::InvalidOption {
                setting: Setting::SetSize,
                message: format!("{size}: a set needs at least 2 configurations"),
            }),
            other => Ok(other),
        }
    }
}

/// Boxed copies of methods, for every method that is `Clone` (all of them):
/// a supertrait of [`CalibrationMethod`], so that no method writes it.
pub trait CloneMethod {
    /// A boxed copy of this method with the same options.
    fn clone_method(&self) -> Box<dyn CalibrationMethod>;
}

impl<T: CalibrationMethod + Clone + 'static> CloneMethod for T {
    fn clone_method(&self) -> Box<dyn CalibrationMethod> {
        Box::new(self.clone())
    }
}

/// A method in the registry: its names, the shape of its equations and how
/// to build it from options. The provided methods of [`CalibrationMethod`]
/// read the shape from here, so that a method states it once:
///
/// ```
/// use gecaro_calib::methods::method_info;
/// use gecaro_core::JacobianRows;
///
/// let position = method_info("position").unwrap();
/// assert_eq!(position.rows_per_configuration, 3);
/// assert_eq!(position.jacobian_rows, JacobianRows::Position);
/// assert!(position.independent && !position.scale_invariant);
/// ```
#[derive(Copy, Clone)]
pub struct MethodInfo {
    /// Command-line name.
    pub name: &'static str,
    /// Menu title.
    pub title: &'static str,
    /// Whether the method uses a plane.
    pub uses_plane: bool,
    /// The data columns beyond `qm1..qmn`.
    pub columns: &'static [DataColumn],
    /// The rows of the parameter Jacobian the equations read.
    pub jacobian_rows: JacobianRows,
    /// Rows of W per configuration (a pair's one row counts for none here:
    /// the distance method counts its rows itself).
    pub rows_per_configuration: usize,
    /// Whether configurations give rows of their own (see
    /// [`CalibrationMethod::independent_configurations`]).
    pub independent: bool,
    /// Whether the data measure no length (see
    /// [`CalibrationMethod::scale_invariant`]).
    pub scale_invariant: bool,
    build: fn(&MethodOptions) -> Result<Box<dyn CalibrationMethod>, Error>,
}

impl fmt::Debug for MethodInfo {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("MethodInfo")
            .field("name", &self.name)
            .finish()
    }
}

impl MethodInfo {
    /// A registry entry: names and builder, and the shape of the equations:
    /// `rows_per_configuration` rows that read `jacobian_rows`, from data
    /// with `columns`. Configurations share rows and the data measure
    /// lengths unless said otherwise ([`independent`](Self::independent),
    /// [`scale_invariant`](Self::scale_invariant)).
    pub const fn new(
        name: &'static str,
        title: &'static str,
        columns: &'static [DataColumn],
        jacobian_rows: JacobianRows,
        rows_per_configuration: usize,
        build: fn(&MethodOptions) -> Result<Box<dyn CalibrationMethod>, Error>,
    ) -> Self {
        MethodInfo {
            name,
            title,
            uses_plane: false,
            columns,
            jacobian_rows,
            rows_per_configuration,
            independent: false,
            scale_invariant: false,
            build,
        }
    }

    /// The rows of each configuration depend on it alone.
    pub const fn independent(self) -> Self {
        MethodInfo {
            independent: true,
            ..self
        }
    }

    /// The data measure no length (links and planes).
    pub const fn scale_invariant(self) -> Self {
        MethodInfo {
            scale_invariant: true,
            ..self
        }
    }

    /// The method uses a plane (given, or its start when unknown).
    pub const fn with_plane(self) -> Self {
        MethodInfo {
            uses_plane: true,
            ..self
        }
    }

    /// Builds the method with these options.
    ///
    /// # Errors
    /// When the options do not suit the method.
    pub fn build(&self, options: &MethodOptions) -> Result<Box<dyn CalibrationMethod>, Error> {
        (self.build)(options)
    }
}
