//! The seven calibration methods of paper §3, as observation models.
//!
//! Every method is the paper's eq. 5, `0 = f(q, X, η)`, linearised as eq. 6,
//! `Δy = Ψ Δη`: given the current parameters it writes the residuals Δy and the
//! rows of W for a data set ([`CalibrationMethod::linearise`]), and it can
//! generate configurations that satisfy its constraint
//! ([`CalibrationMethod::generate`]). Identifiability, identification and
//! points generation are written once against this trait.
//!
//! | name | method | rows | paper |
//! |---|---|---|---|
//! | `position` | position measure | 3 per configuration | eq. 7, rows 1–3 |
//! | `frame` | frame (location) measure | 6 per configuration | eq. 7 |
//! | `point-link` | point link | 3 per configuration | eq. 12, rows 1–3 |
//! | `frame-link` | frame link | 6 per configuration | eq. 12 |
//! | `plane1` | plane link 1, plane equation | 1 per configuration | eq. 15 |
//! | `plane2` | plane link 2, plane normal | 1 per configuration | eq. 17 |
//! | `distance` | distance measure | 1 per pair | eq. 19–20 |
//!
//! Link and plane-normal equations hold between configurations. Instead of
//! one reference pair per configuration, each configuration is compared with
//! the mean of its set: `(J_i − J̄)Δη = −(y_i − ȳ)`. Since
//! `Σ_{i<j} ‖e_i − e_j‖² = k·Σ_i ‖e_i − ē‖²` for a set of k, this is eq. 12
//! (or 17) written for *every* pair of the set at once, in k rows instead of
//! k(k−1)/2, and it treats every configuration alike. The centring uses up one
//! equation per set and per dimension ([`CalibrationMethod::dependent_rows`]).
//!
//! To add an eighth method: write one file with a type implementing
//! [`CalibrationMethod`] and its [`MethodInfo`], and list it in [`METHODS`].
//! Two provided methods only make it faster and are safe to leave alone:
//! [`jacobian_rows`](CalibrationMethod::jacobian_rows) (say
//! [`JacobianRows::Position`] when no orientation row is read) and
//! [`independent_configurations`](CalibrationMethod::independent_configurations)
//! (rows of one configuration depend on it alone: evaluated and written in
//! parallel blocks). A method whose `generate_like` reads the data's poses
//! without having auxiliary unknowns must say so in
//! [`uses_starting_poses`](CalibrationMethod::uses_starting_poses).

mod distance;
mod frame;
mod frame_link;
mod link;
mod plane;
mod plane_equation;
mod plane_normal;
mod point_link;
mod position;
mod sensor;

use std::collections::HashMap;
use std::fmt;

use gecaro_core::{JacobianRows, OrientationDifference, Robot};

use crate::Error;
use crate::observation::{RowWriter, TerminalState};
use crate::sample::{DataColumn, Sample};
use crate::sampler::Sampler;

pub use plane::Plane;

/// One calibration method; see the module docs.
pub trait CalibrationMethod: CloneMethod + fmt::Debug + Send + Sync {
    /// The method's entry in [`METHODS`]: its names and how it is built.
    fn info(&self) -> &'static MethodInfo;

    /// The name used in files and on the command line (`point-link`).
    fn name(&self) -> &'static str {
        self.info().name
    }

    /// The menu title of paper §4 (`Point link`).
    fn title(&self) -> &'static str {
        self.info().title
    }

    /// The data columns beyond `qm1..qmn`.
    fn data_columns(&self) -> &'static [DataColumn];

    /// Checks the structure of a data set (set and pair sizes). The presence
    /// of the [`data_columns`](Self::data_columns) fields is checked by the caller.
    ///
    /// # Errors
    /// [`Error::InvalidData`] naming the first line at fault.
    fn check_samples(&self, _samples: &[Sample]) -> Result<(), Error> {
        Ok(())
    }

    /// Number of rows of W that `samples` give.
    fn row_count(&self, samples: &[Sample]) -> usize;

    /// Rows that carry no independent information (one per set and dimension
    /// for mean-centred sets): independent equations = rows − dependent rows.
    fn dependent_rows(&self, _samples: &[Sample]) -> usize {
        0
    }

    /// Independent equations per configuration, roughly (to size random data).
    fn equations_per_configuration(&self) -> f64;

    /// Whether the method's constraint still holds for the robot scaled about
    /// any point, i.e. it measures no length (link and plane methods): such
    /// data cannot observe the robot's scale (Table 2 loses it).
    fn scale_invariant(&self) -> bool {
        false
    }

    /// Names of the method's own unknowns, identified with η (plane coefficients).
    fn auxiliary_names(&self) -> Vec<String> {
        Vec::new()
    }

    /// Initial values of the auxiliary unknowns, from the states at the
    /// starting parameters (e.g. the best-fit plane of the nominal points).
    /// Only the poses of `states` are evaluated ([`crate::evaluate_poses`]).
    ///
    /// # Errors
    /// When they cannot be determined from these data.
    fn initial_auxiliary(&self, _states: &[TerminalState]) -> Result<Vec<f64>, Error> {
        Ok(Vec::new())
    }

    /// Whether [`initial_auxiliary`](Self::initial_auxiliary) or
    /// [`generate_like`](Self::generate_like) read the poses of the data at
    /// the starting parameters; when not, they are not evaluated and those
    /// functions get no states. By default, when the method has auxiliary
    /// unknowns (the plane methods fit the data's plane only then).
    fn uses_starting_poses(&self) -> bool {
        !self.auxiliary_names().is_empty()
    }

    /// The rows of the parameter Jacobian that [`linearise`](Self::linearise)
    /// reads: all six by default; methods that measure no orientation say
    /// [`JacobianRows::Position`] and the model skips the rotation rows.
    fn jacobian_rows(&self) -> JacobianRows {
        JacobianRows::Full
    }

    /// Whether the rows of configuration i depend on nothing but its state,
    /// its sample and the auxiliary values, and belong to observation i
    /// (position, frame, plane-equation rows; not sets or pairs). Such a set
    /// is evaluated and linearised block by block, in parallel: `linearise`
    /// is then called on consecutive blocks of the samples.
    fn independent_configurations(&self) -> bool {
        false
    }

    /// The samples of each observation, in the numbering `linearise` gives
    /// its rows: one observation per configuration by default (position,
    /// frame, plane, and the link methods, whose configurations are each
    /// compared with their set's mean).
    fn observation_samples(&self, samples: &[Sample]) -> Vec<Vec<usize>> {
        (0..samples.len()).map(|index| vec![index]).collect()
    }

    /// Writes the rows `Δy = W Δη` at the current parameters (whose poses and
    /// Jacobians are `states`, one per sample) and auxiliary values.
    fn linearise(
        &self,
        samples: &[Sample],
        states: &[TerminalState],
        auxiliary: &[f64],
        rows: &mut RowWriter<'_>,
    );

    /// Generates about `count` configurations of `robot` that satisfy the
    /// method's constraint, with what a sensor would measure there, perturbed
    /// by Gaussian noise of standard deviation `noise` (metres; radians for
    /// orientations).
    ///
    /// # Errors
    /// [`Error::Generation`] when configurations cannot be found.
    fn generate(
        &self,
        robot: &Robot,
        count: usize,
        noise: f64,
        sampler: &mut Sampler,
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
    /// constraint.
    fn measure_at(
        &self,
        real: &Robot,
        planned: &[Sample],
        noise: f64,
        sampler: &mut Sampler,
    ) -> Result<Vec<Sample>, Error>;

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
        _samples: &[Sample],
        _states: &[TerminalState],
        count: usize,
        sampler: &mut Sampler,
    ) -> Result<Vec<Sample>, Error> {
        self.generate(robot, count, 0.0, sampler)
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
                option: "--plane known",
                message:
                    "a known plane needs its normal and a point (--plane-normal, --plane-point)"
                        .into(),
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
                option: "--set-size",
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

/// A method in the registry: its names and how to build it from options.
#[derive(Copy, Clone)]
pub struct MethodInfo {
    /// Command-line name.
    pub name: &'static str,
    /// Menu title.
    pub title: &'static str,
    /// Whether the method uses a plane.
    pub uses_plane: bool,
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
    /// Builds the method with these options.
    ///
    /// # Errors
    /// When the options do not suit the method.
    pub fn build(&self, options: &MethodOptions) -> Result<Box<dyn CalibrationMethod>, Error> {
        (self.build)(options)
    }
}

/// The seven methods, in the order of the paper's menus.
pub const METHODS: &[MethodInfo] = &[
    position::INFO,
    frame::INFO,
    point_link::INFO,
    frame_link::INFO,
    plane_equation::INFO,
    plane_normal::INFO,
    distance::INFO,
];

/// The method called `name`, built with `options`.
///
/// # Errors
/// [`Error::UnknownMethod`] (listing the methods) or the method's option errors.
pub fn method(name: &str, options: &MethodOptions) -> Result<Box<dyn CalibrationMethod>, Error> {
    method_info(name)?.build(options)
}

/// The registry entry of the method called `name`.
///
/// # Errors
/// [`Error::UnknownMethod`] listing the methods.
pub fn method_info(name: &str) -> Result<&'static MethodInfo, Error> {
    METHODS
        .iter()
        .find(|info| info.name == name)
        .ok_or_else(|| Error::UnknownMethod {
            name: name.to_owned(),
            available: METHODS.iter().map(|info| info.name).collect(),
        })
}

// ---------------------------------------------------------------------------
// Helpers shared by several methods.

/// Sample indices grouped by their `group` id, groups in order of first appearance.
///
/// Linear in the number of samples (a file of 10⁶ rows may hold 5·10⁵ pairs).
pub(crate) fn groups(samples: &[Sample]) -> Vec<Vec<usize>> {
    let mut position_of: HashMap<u64, usize> = HashMap::new();
    let mut members: Vec<Vec<usize>> = Vec::new();
    for (index, sample) in samples.iter().enumerate() {
        let id = sample.group.unwrap_or(0);
        let position = *position_of.entry(id).or_insert_with(|| {
            members.push(Vec::new());
            members.len() - 1
        });
        members[position].push(index);
    }
    members
}

/// The units of `samples` for `method`: the sample indices of each set or
/// pair (link and distance methods, grouped as the methods group them, in
/// order of first appearance), single samples otherwise.
pub fn units(method: &dyn CalibrationMethod, samples: &[Sample]) -> Vec<Vec<usize>> {
    let grouped = method
        .data_columns()
        .iter()
        .any(|c| matches!(c, DataColumn::Set | DataColumn::Pair));
    if grouped {
        groups(samples)
    } else {
        (0..samples.len()).map(|index| vec![index]).collect()
    }
}

/// Checks that every group has between `min` and `max` members.
pub(crate) fn check_group_sizes(
    samples: &[Sample],
    min: usize,
    max: usize,
    what: &str,
) -> Result<(), Error> {
    for members in groups(samples) {
        if members.len() < min || members.len() > max {
            let first = &samples[members[0]];
            let expected = if min == max {
                format!("exactly {min}")
            } else {
                format!("at least {min}")
            };
            return Err(Error::InvalidData {
                line: first.line,
                message: format!(
                    "{what} {} has {} configuration(s); it needs {expected}",
                    first.group.unwrap_or(0),
                    members.len()
                ),
            });
        }
    }
    Ok(())
}

/// Mean-centres, in place, the per-member blocks of one set: `buffer` holds
/// one equal block per member (values, or rows of coefficients), and each
/// entry of a block loses its mean over the members, weighted by `weights`
/// (one per member: the robust weights of their observations, all 1 in plain
/// least squares; the plain mean if they sum to 0). See the module docs.
pub(crate) fn centre(buffer: &mut [f64], weights: &[f64]) {
    let members = weights.len();
    let stride = buffer.len() / members.max(1);
    let total: f64 = weights.iter().sum();
    // Equal weights (least squares): the plain mean, as without weights.
    let uniform = total <= 0.0 || weights.iter().all(|w| *w == weights[0]);
    for offset in 0..stride {
        let values = (0..members).map(|m| (weights[m], buffer[m * stride + offset]));
        let mean = if uniform {
            values.map(|(_, value)| value).sum::<f64>() / members as f64
        } else {
            values.map(|(weight, value)| weight * value).sum::<f64>() / total
        };
        for m in 0..members {
            buffer[m * stride + offset] -= mean;
        }
    }
}

/// Sizes of the sets of generated link data: about `count` configurations
/// in sets of `size` (at least 2 each); the remainder is spread over the sets.
pub(crate) fn set_sizes(count: usize, size: usize) -> Vec<usize> {
    let count = count.max(2);
    let sets = (count / size.max(2)).max(1);
    let mut sizes = vec![count / sets; sets];
    for size in sizes.iter_mut().take(count % sets) {
        *size += 1;
    }
    sizes
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn centring_removes_the_mean() {
        let mut values = vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0];
        centre(&mut values, &[1.0; 3]);
        assert_eq!(values, [-2.0, -2.0, 0.0, 0.0, 2.0, 2.0]);
        // Weighted: the first member does not count in the mean (3, 4 → 4, 5).
        let mut values = vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0];
        centre(&mut values, &[0.0, 1.0, 1.0]);
        assert_eq!(values, [-3.0, -3.0, -1.0, -1.0, 1.0, 1.0]);
    }

    #[test]
    fn groups_keep_the_order_of_first_appearance_at_any_size() {
        let with_group = |group: u64| Sample {
            group: Some(group),
            ..Sample::new(vec![0.0])
        };
        let small: Vec<Sample> = [7, 3, 7, 9, 3].into_iter().map(with_group).collect();
        assert_eq!(groups(&small), [vec![0, 2], vec![1, 4], vec![3]]);
        // 10⁵ pairs, ids in descending order: one pass (this was quadratic).
        let pairs: Vec<Sample> = (0..200_000_u64)
            .map(|row| with_group(1_000_000 - row / 2))
            .collect();
        let grouped = groups(&pairs);
        assert_eq!(grouped.len(), 100_000);
        assert!(
            grouped
                .iter()
                .enumerate()
                .all(|(k, members)| members == &[2 * k, 2 * k + 1])
        );
    }

    #[test]
    fn set_sizes_cover_the_count() {
        assert_eq!(set_sizes(10, 4), [5, 5]);
        assert_eq!(set_sizes(3, 4), [3]);
        assert_eq!(set_sizes(8, 2).iter().sum::<usize>(), 8);
    }

    #[test]
    fn unknown_methods_list_the_seven() {
        let error = method("plane3", &MethodOptions::default()).expect_err("no such method");
        let message = error.to_string();
        for info in METHODS {
            assert!(message.contains(info.name), "{message}");
        }
        assert_eq!(METHODS.len(), 7);
    }
}
