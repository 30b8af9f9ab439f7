//! The identifiable (base) parameters of a study, Appendix III.
//!
//! W is built at the robot's parameters, its columns ordered by priority
//! (auxiliary unknowns first, then the robot parameters by decreasing priority,
//! ties in column-major order of the priority matrix; priority 0 is left out).
//! A QR factorisation without pivoting of the ordered W (eq. 33) gives |R_ii|,
//! the distance of column i from the span of the columns before it, so taking
//! the columns greedily and keeping those with |R_ii| > τ yields the
//! highest-priority independent set. The numerical zero is eq. 34 with a floor
//! (NOTES.md), `τ = max(c·ε, 1e-9) · max|R_ii|`: columns of W built from a
//! numerical inverse model can show |R_ii| ≈ 1e-13 where the theory says 0.
//!
//! Every parameter is then *identifiable*, *regrouped* ('n': its column is a
//! combination of kept ones), *no effect* ('0': its column is ~0) or
//! *excluded* (priority 0). The regrouping relations come from
//! `W2 = W1·β`, `β = R1⁻¹R2` (eq. 35–37), from one QR of the kept and the
//! regrouped columns; the base parameters are `Δη_b = Δη_1 + β Δη_2` (eq. 32).
//! The relations and the condition number of W_b are computed when first read
//! ([`RankReport::relations`], [`RankReport::condition_number`]).

use std::sync::OnceLock;

use faer::Mat;
use gecaro_core::{ParameterId, PriorityMatrix, Robot};

use crate::Error;
use crate::fold::{DEFAULT_STREAMED_ROWS, FoldKind};
use crate::linalg::{
    column_geometry, condition_number, greedy_rank, largest_column_norm, regrouping_relations,
    select_columns, singular_values, view,
};
use crate::method::CalibrationMethod;
use crate::observability::{AUXILIARY_UNIT, Observability, column_unit};
use crate::observation::ObservationSystem;
use crate::progress::{Observer, Quiet};
use crate::rows::ColumnLayout;
use crate::sample::Sample;
use crate::sampler::Sampler;
use crate::samples::{SampleRef, SampleSlice};
use crate::study::{Study, StudyStates};

/// The floor of the numerical zero, relative to max|R_ii| (NOTES.md).
pub const RELATIVE_ZERO_FLOOR: f64 = 1e-9;

/// Independent equations per unknown in random data for identifiability.
const RANDOM_EQUATIONS_PER_UNKNOWN: f64 = 2.5;

/// What the study can say about one parameter.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub enum ParameterStatus {
    /// In the base set: identified.
    Identifiable,
    /// 'n': its effect is regrouped onto identifiable parameters.
    Regrouped,
    /// '0': it has no effect on these measurements.
    NoEffect,
    /// Priority 0: not identified by the user's choice.
    Excluded,
}

impl ParameterStatus {
    /// The name used in JSON: `identifiable`, `regrouped`, `no_effect`, `excluded`.
    pub fn as_str(self) -> &'static str {
        match self {
            ParameterStatus::Identifiable => "identifiable",
            ParameterStatus::Regrouped => "regrouped",
            ParameterStatus::NoEffect => "no_effect",
            ParameterStatus::Excluded => "excluded",
        }
    }

    /// The cell of the paper's Table 2: blank, `n`, `0`; `-` for excluded.
    pub fn symbol(self) -> &'static str {
        match self {
            ParameterStatus::Identifiable => "",
            ParameterStatus::Regrouped => "n",
            ParameterStatus::NoEffect => "0",
            ParameterStatus::Excluded => "-",
        }
    }
}

/// One parameter (or auxiliary unknown) and its status.
#[derive(Clone, Debug, PartialEq)]
pub struct Classified {
    /// `theta0`, `alpha3`, `K2`, or an auxiliary name such as `a`.
    pub name: String,
    /// The robot parameter, `None` for an auxiliary unknown.
    pub parameter: Option<ParameterId>,
    /// Its priority (0 for auxiliary unknowns, which always come first).
    pub priority: u32,
    /// What the study says of it.
    pub status: ParameterStatus,
    /// |R_ii| of its column in the ordered QR (`None` when excluded).
    pub diagonal: Option<f64>,
}

/// A base parameter and the non-identifiable parameters it absorbs:
/// `Δη_base + Σ coefficient·Δη_absorbed` is what gets identified (eq. 32).
#[derive(Clone, Debug, PartialEq)]
pub struct Relation {
    /// The base parameter.
    pub base: String,
    /// Absorbed parameters with their coefficients β.
    pub absorbed: Vec<(String, f64)>,
}

/// The result of Appendix III for a study.
#[derive(Clone, Debug)]
pub struct RankReport {
    /// The study's methods, joined with `+`.
    pub method: String,
    /// Every robot parameter, in vocabulary order.
    pub parameters: Vec<Classified>,
    /// Every auxiliary unknown, in order.
    pub auxiliary: Vec<Classified>,
    /// Vocabulary indices of the identifiable robot parameters, in column order.
    pub base_parameters: Vec<usize>,
    /// Indices of the identifiable auxiliary unknowns.
    pub base_auxiliary: Vec<usize>,
    /// The numerical zero τ used.
    pub tolerance: f64,
    /// Smallest |R_ii| among kept columns.
    pub smallest_kept: f64,
    /// Largest |R_ii| among rejected columns (0 if none).
    pub largest_rejected: f64,
    /// Rows of W.
    pub rows: usize,
    /// Independent equations.
    pub equations: usize,
    /// The input priority matrix with the non-identifiable parameters set to 0.
    pub priority: PriorityMatrix,
    /// The regrouping relations and the condition number, when first read.
    conditioning: Conditioning,
}

/// The parts of a [`RankReport`] that its base set does not depend on — the
/// regrouping relations and the condition number of W_b — computed from the
/// column geometry of W when first read: an identification, for one, needs
/// neither from its structural analysis unless its report is shown.
#[derive(Clone, Debug)]
struct Conditioning {
    /// R̃ of the ordered W (`R̃ᵀR̃ = WᵀW`, see [`column_geometry`]).
    geometry: Mat<f64>,
    /// The kept and the regrouped columns, in column order.
    kept: Vec<usize>,
    regrouped: Vec<usize>,
    /// What each column of W stands for.
    columns: Vec<Column>,
    relations: OnceLock<(Vec<Relation>, f64)>,
    condition_number: OnceLock<f64>,
    /// The error unit of each column (see [`crate::observability::Observability`]) and the
    /// configurations of the data, for the observability indices.
    units: Vec<f64>,
    configurations: usize,
    observability: OnceLock<Observability>,
}

/// A column of W: an entry of [`RankReport::auxiliary`] or of [`RankReport::parameters`].
#[derive(Copy, Clone, Debug)]
enum Column {
    Auxiliary(usize),
    Parameter(usize),
}

impl RankReport {
    /// Regrouping relations `W2 = W1·β` (eq. 36–37), one per base parameter
    /// that absorbs something (coefficients below 1e-8 left out).
    pub fn relations(&self) -> &[Relation] {
        &self.regrouping().0
    }

    /// Largest relative residual of the regrouping relations,
    /// ‖W2 − W1β‖/‖W2‖ per column (0 when nothing is regrouped).
    pub fn relation_residual(&self) -> f64 {
        self.regrouping().1
    }

    /// Condition number σ_max/σ_min of W_b (kept columns, weighted rows): 1
    /// when nothing is kept, NaN if the singular value decomposition fails
    /// (which it does not for the finite W that a rank test accepts).
    pub fn condition_number(&self) -> f64 {
        let conditioning = &self.conditioning;
        *conditioning.condition_number.get_or_init(|| {
            let kept = select_columns(conditioning.geometry.as_ref(), &conditioning.kept);
            condition_number(kept.as_ref()).unwrap_or(f64::NAN)
        })
    }

    /// The observability indices O1–O5 of W_b, its columns scaled by their
    /// error units (see [`crate::observability::Observability`]).
    pub fn observability(&self) -> Observability {
        let conditioning = &self.conditioning;
        *conditioning.observability.get_or_init(|| {
            let mut kept = select_columns(conditioning.geometry.as_ref(), &conditioning.kept);
            for (position, column) in conditioning.kept.iter().enumerate() {
                let unit = conditioning.units[*column];
                for row in 0..kept.nrows() {
                    kept[(row, position)] *= unit;
                }
            }
            let values = singular_values(kept.as_ref()).unwrap_or_default();
            Observability::from_singular_values(&values, conditioning.configurations)
        })
    }

    fn regrouping(&self) -> &(Vec<Relation>, f64) {
        let conditioning = &self.conditioning;
        conditioning.relations.get_or_init(|| {
            let (kept, regrouped) = (&conditioning.kept, &conditioning.regrouped);
            if kept.is_empty() || regrouped.is_empty() {
                return (Vec::new(), 0.0);
            }
            let name = |column: usize| match conditioning.columns[column] {
                Column::Auxiliary(index) => self.auxiliary[index].name.clone(),
                Column::Parameter(index) => self.parameters[index].name.clone(),
            };
            let (beta, misfits) =
                regrouping_relations(conditioning.geometry.as_ref(), kept, regrouped);
            let relations = kept
                .iter()
                .enumerate()
                .filter_map(|(k, &base)| {
                    let absorbed: Vec<(String, f64)> = regrouped
                        .iter()
                        .enumerate()
                        .filter(|(j, _)| beta[(k, *j)].abs() > 1e-8)
                        .map(|(j, &column)| (name(column), beta[(k, j)]))
                        .collect();
                    (!absorbed.is_empty()).then(|| Relation {
                        base: name(base),
                        absorbed,
                    })
                })
                .collect();
            (relations, misfits.iter().copied().fold(0.0, f64::max))
        })
    }

    /// Number of identifiable robot parameters (auxiliary unknowns not counted).
    pub fn count(&self) -> usize {
        self.base_parameters.len()
    }

    /// The status of the parameter called `name`.
    pub fn status(&self, name: &str) -> Option<ParameterStatus> {
        self.parameters
            .iter()
            .chain(&self.auxiliary)
            .find(|classified| classified.name == name)
            .map(|classified| classified.status)
    }

    /// What the set-up itself keeps from being identified, before any data
    /// are taken: a revolute joint whose gain has no effect turns about the
    /// measured point (at the nominal geometry the point lies on its axis:
    /// a reflector on the flange axis, a base frame on axis 1), so neither
    /// its angle nor its gain is observed, and at the real robot, a little
    /// off that axis, they matter to second order. In words, one warning per
    /// such joint.
    pub fn set_up_warnings(&self, robot: &Robot) -> Vec<String> {
        robot
            .joints()
            .iter()
            .enumerate()
            .filter(|(index, _)| {
                robot.frames()[index + 1].frame_type == gecaro_core::FrameType::Revolute
            })
            .filter(|(index, _)| self.status(&format!("K{}", index + 1)) == Some(ParameterStatus::NoEffect))
            .map(|(index, _)| {
                let joint = index + 1;
                format!(
                    "joint {joint} turns about the measured point (at the nominal geometry the point \
                     lies on its axis): θ{joint} and K{joint} are not observed by these measurements; \
                     put the tool point (reflector) off that axis, or measure frames"
                )
            })
            .collect()
    }
}

/// The identifiable parameters of `study` on `robot` with `priority` (Appendix III).
///
/// # Errors
/// Invalid data (see [`Study::check`]), or [`Error::TooFewEquations`] when the
/// data give fewer independent equations than candidate columns.
pub fn identifiable_parameters(
    robot: &Robot,
    study: &Study,
    priority: &PriorityMatrix,
) -> Result<RankReport, Error> {
    study.check(robot)?;
    priority.validate(robot.parameters())?;
    let mut states = StudyStates::default();
    study.evaluate_poses(robot, &mut states)?;
    let auxiliary = study.initial_auxiliary(&states)?;
    analyse(
        robot,
        study,
        priority,
        None,
        DEFAULT_STREAMED_ROWS,
        |layout, system| study.linearise(robot, &auxiliary, layout, &mut states, system),
    )
    .map(|(report, _)| report)
}

/// Appendix III on the system that `write` writes in the layout it is given
/// (columns: the auxiliary candidates, then the candidates in priority
/// order), also returning that system. Only the auxiliary unknowns listed in
/// `auxiliary_candidates` (all when `None`) are candidates; the others are
/// reported as excluded.
fn analyse(
    robot: &Robot,
    study: &Study,
    priority: &PriorityMatrix,
    auxiliary_candidates: Option<&[usize]>,
    streamed_rows: usize,
    mut write: impl FnMut(&ColumnLayout, &mut ObservationSystem) -> Result<(), Error>,
) -> Result<(RankReport, ObservationSystem), Error> {
    let space = robot.parameters();
    let candidates: Vec<ParameterId> = priority.ordered_candidates(space);
    let candidate_indices: Vec<usize> = candidates
        .iter()
        .map(|id| space.index_of(*id).expect("candidates are parameters"))
        .collect();
    let all_auxiliary_names = study.auxiliary_names();
    let all_auxiliary: Vec<usize> = (0..all_auxiliary_names.len()).collect();
    let auxiliary_indices = auxiliary_candidates.unwrap_or(&all_auxiliary).to_vec();
    let auxiliary_names: Vec<String> = auxiliary_indices
        .iter()
        .map(|i| all_auxiliary_names[*i].clone())
        .collect();
    let layout = ColumnLayout::with_auxiliary(
        space.len(),
        &candidate_indices,
        all_auxiliary_names.len(),
        &auxiliary_indices,
    );
    let columns = layout.columns();
    let equations = study.equation_count();
    if equations < columns {
        return Err(Error::TooFewEquations {
            equations,
            unknowns: columns,
        });
    }
    // Everything below depends only on the column geometry of W (norms,
    // distances, relations, singular values), which one QR of the tall W
    // hands to a small c×c matrix. Tall data are folded as they are written
    // ([`crate::fold`]): into the normal equations, whose Cholesky factor
    // is that geometry where they are well conditioned, else (written
    // again) into the R of a QR.
    let mut system = ObservationSystem::default();
    system.set_folding(study.is_streamed(streamed_rows).then_some(FoldKind::Gram));
    write(&layout, &mut system)?;
    let finite = |system: &ObservationSystem| {
        if system.is_finite() {
            Ok(())
        } else {
            Err(Error::Numerical {
                message: "the observation matrix has non-finite entries".into(),
            })
        }
    };
    finite(&system)?;
    let reduced = match system.folded_geometry() {
        Some(reduced) => reduced,
        None if system.is_folded() => {
            system.set_folding(Some(FoldKind::Factor));
            write(&layout, &mut system)?;
            finite(&system)?;
            system.folded_geometry().expect("a factor fold has its R")
        }
        None => column_geometry(view(system.matrix(), system.rows(), columns)),
    };
    let geometry = reduced.as_ref();
    // Eq. 34 with the floor of NOTES.md. max|R_ii| of an unpivoted QR is at
    // most the largest column norm (R_11 is a column norm), which is used as
    // the scale so that τ is known before the greedy pass.
    let tolerance =
        (columns as f64 * f64::EPSILON).max(RELATIVE_ZERO_FLOOR) * largest_column_norm(geometry);
    let rank = greedy_rank(geometry, tolerance);
    let diagonal = &rank.diagonal;
    let statuses: Vec<ParameterStatus> = (0..columns)
        .map(|column| {
            if rank.norms[column] <= tolerance {
                ParameterStatus::NoEffect
            } else if rank.kept.contains(&column) {
                ParameterStatus::Identifiable
            } else {
                ParameterStatus::Regrouped
            }
        })
        .collect();
    let kept = rank.kept.clone();
    let regrouped: Vec<usize> = (0..columns)
        .filter(|c| statuses[*c] == ParameterStatus::Regrouped)
        .collect();

    // Reports in vocabulary order.
    let auxiliary_count = auxiliary_names.len();
    let mut parameters: Vec<Classified> = space
        .ids()
        .iter()
        .map(|id| Classified {
            name: id.to_string(),
            parameter: Some(*id),
            priority: priority.get(*id),
            status: ParameterStatus::Excluded,
            diagonal: None,
        })
        .collect();
    for (position, id) in candidates.iter().enumerate() {
        let column = auxiliary_count + position;
        let entry = &mut parameters[candidate_indices[position]];
        debug_assert_eq!(entry.parameter, Some(*id));
        entry.status = statuses[column];
        entry.diagonal = Some(diagonal[column]);
    }
    let auxiliary: Vec<Classified> = all_auxiliary_names
        .iter()
        .enumerate()
        .map(|(index, name)| {
            let column = auxiliary_indices.iter().position(|i| *i == index);
            Classified {
                name: name.clone(),
                parameter: None,
                priority: 0,
                status: column.map_or(ParameterStatus::Excluded, |c| statuses[c]),
                diagonal: column.map(|c| diagonal[c]),
            }
        })
        .collect();
    let mut new_priority = priority.clone();
    for entry in &parameters {
        if let (Some(id), false) = (
            entry.parameter,
            entry.status == ParameterStatus::Identifiable,
        ) {
            new_priority.set(id, 0);
        }
    }
    let rejected = statuses
        .iter()
        .zip(diagonal)
        .filter(|(s, _)| **s != ParameterStatus::Identifiable);
    let report = RankReport {
        method: study.method_names(),
        base_parameters: kept
            .iter()
            .filter(|c| **c >= auxiliary_count)
            .map(|c| candidate_indices[c - auxiliary_count])
            .collect(),
        // Columns of the auxiliary candidates, as indices into all auxiliary unknowns.
        base_auxiliary: kept
            .iter()
            .filter(|c| **c < auxiliary_count)
            .map(|c| auxiliary_indices[*c])
            .collect(),
        parameters,
        auxiliary,
        tolerance,
        smallest_kept: kept
            .iter()
            .map(|c| diagonal[*c])
            .fold(f64::INFINITY, f64::min),
        largest_rejected: rejected.map(|(_, d)| *d).fold(0.0, f64::max),
        rows: system.rows(),
        equations,
        priority: new_priority,
        conditioning: Conditioning {
            geometry: reduced,
            kept,
            regrouped,
            columns: auxiliary_indices
                .iter()
                .map(|index| Column::Auxiliary(*index))
                .chain(
                    candidate_indices
                        .iter()
                        .map(|index| Column::Parameter(*index)),
                )
                .collect(),
            relations: OnceLock::new(),
            condition_number: OnceLock::new(),
            units: vec![AUXILIARY_UNIT; auxiliary_count]
                .into_iter()
                .chain(
                    candidates
                        .iter()
                        .map(|id| column_unit(id.kind, robot.parameter(*id))),
                )
                .collect(),
            configurations: study.sets.iter().map(|set| set.samples.len()).sum(),
            observability: OnceLock::new(),
        },
    };
    Ok((report, system))
}

/// A study of noise-free random data of the same kind as `study` on `robot`:
/// each set regenerated by its method (constraint satisfied exactly), with
/// about 2.5 independent equations per unknown — enough for the rank test,
/// whatever the size of the data.
///
/// # Errors
/// When a method cannot generate such data (e.g. no distinct inverse-model solution).
pub fn random_counterpart(robot: &Robot, study: &Study, seed: u64) -> Result<Study, Error> {
    let mut states = StudyStates::default();
    study.evaluate_poses(robot, &mut states)?;
    random_counterpart_at(robot, study, &states, seed)
}

/// [`random_counterpart`] with the study's states (poses) at `robot` already evaluated.
pub(crate) fn random_counterpart_at(
    robot: &Robot,
    study: &Study,
    states: &StudyStates,
    seed: u64,
) -> Result<Study, Error> {
    let unknowns = robot.parameters().len() + study.auxiliary_names().len();
    let mut sampler = Sampler::new(seed);
    let mut sets = Vec::with_capacity(study.sets.len());
    for (index, set) in study.sets.iter().enumerate() {
        let needed = (RANDOM_EQUATIONS_PER_UNKNOWN * unknowns as f64
            / set.method.equations_per_configuration())
        .ceil() as usize;
        let mut samples = set.method.sensor().generate_like(
            robot,
            set.samples.as_slice(),
            states.set(index),
            needed,
            &mut sampler,
            // About 2.5 equations per unknown: quick, whatever the data.
            &mut Quiet,
        )?;
        lend_loads(set.samples.as_slice(), &mut samples, &mut sampler);
        let mut random = set.with_samples(samples);
        random.label = format!("random configurations like {}", set.label);
        sets.push(random);
    }
    Ok(Study {
        sets,
        frames: study.frames.clone(),
    })
}

/// Gives each random sample the joint torques of a data sample drawn at
/// random, when the data carry loads (an elastic robot, issue 38): loads of
/// the data's size and pattern (a joint no load reaches, such as a vertical
/// first axis, gets none), independent of the configuration. On them a
/// compliance's column `J_j·τ_j` is generic, so the structure says which
/// compliances any loads could reveal; whether the data's own loads tell
/// them from the geometry is the excitation check's question. The tilts'
/// torques go with them.
fn lend_loads(data: SampleSlice<'_>, random: &mut [Sample], sampler: &mut Sampler) {
    let loaded: Vec<SampleRef<'_>> = data.iter().filter(|s| s.torques().is_some()).collect();
    if loaded.is_empty() {
        return;
    }
    for sample in random {
        let drawn = (sampler.uniform(0.0, loaded.len() as f64) as usize).min(loaded.len() - 1);
        let lent = sample.loads_mut();
        lent.torques = loaded[drawn].torques().map(<[f64]>::to_vec);
        lent.tilt_torques = loaded[drawn].tilt_torques().map(<[f64]>::to_vec);
    }
}

/// The structural identifiable parameters of a study: Appendix III on
/// random, noise-free data of the same kind ([`random_counterpart`]).
///
/// For methods whose equations are constraints (link and plane methods), W
/// evaluated on data at parameters that do not satisfy the constraints has
/// small but non-zero columns that vanish once the constraints hold: an
/// analysis of such data at the nominal parameters would call parameters
/// identifiable that are not. The paper determines the base parameters
/// "beforehand, on random configurations"; the data then only have to excite
/// them ([`excitation`]).
///
/// # Errors
/// As [`random_counterpart`] and [`identifiable_parameters`].
pub fn structural_parameters(
    robot: &Robot,
    study: &Study,
    priority: &PriorityMatrix,
    seed: u64,
) -> Result<RankReport, Error> {
    study.check(robot)?;
    let mut states = StudyStates::default();
    study.evaluate_poses(robot, &mut states)?;
    structural_parameters_at(robot, study, &states, priority, seed)
}

/// [`structural_parameters`] with the study's states (poses) at `robot` already evaluated.
pub(crate) fn structural_parameters_at(
    robot: &Robot,
    study: &Study,
    states: &StudyStates,
    priority: &PriorityMatrix,
    seed: u64,
) -> Result<RankReport, Error> {
    let random = random_counterpart_at(robot, study, states, seed)?;
    identifiable_parameters(robot, &random, priority)
}

/// How well a data set excites the structural base parameters (paper §4's
/// excitation check).
#[derive(Clone, Debug)]
pub struct Excitation {
    /// The rank test of the data on the structural base columns only, in
    /// priority order: the kept ones are excited.
    pub report: RankReport,
    /// Structural base parameters that the data do not excite (they stay at nominal).
    pub not_excited: Vec<String>,
    /// The observation system of the data on those columns (at the states given).
    pub(crate) system: Option<ObservationSystem>,
}

/// The excitation check of paper §4: which structural base parameters the data
/// excite, and the condition number of the data's W_b.
///
/// # Errors
/// Invalid data or too few equations.
pub fn excitation(
    robot: &Robot,
    study: &Study,
    structural: &RankReport,
) -> Result<Excitation, Error> {
    study.check(robot)?;
    let mut states = StudyStates::default();
    study.evaluate_poses(robot, &mut states)?;
    let auxiliary = study.initial_auxiliary(&states)?;
    excitation_at(
        robot,
        study,
        &mut states,
        &auxiliary,
        structural,
        DEFAULT_STREAMED_ROWS,
    )
}

/// [`excitation`] with these auxiliary values (`states` is storage for
/// [`Study::linearise`]).
pub(crate) fn excitation_at(
    robot: &Robot,
    study: &Study,
    states: &mut StudyStates,
    auxiliary: &[f64],
    structural: &RankReport,
    streamed_rows: usize,
) -> Result<Excitation, Error> {
    let (report, system) = analyse(
        robot,
        study,
        &structural.priority,
        Some(&structural.base_auxiliary),
        streamed_rows,
        |layout, system| study.linearise(robot, auxiliary, layout, states, system),
    )?;
    let not_excited = structural
        .parameters
        .iter()
        .chain(&structural.auxiliary)
        .filter(|p| p.status == ParameterStatus::Identifiable)
        .filter(|p| report.status(&p.name) != Some(ParameterStatus::Identifiable))
        .map(|p| p.name.clone())
        .collect();
    Ok(Excitation {
        report,
        not_excited,
        system: Some(system),
    })
}

/// Noise-free random data for `method` on `robot`: configurations satisfying
/// the method's constraint, enough for about 2.5 independent equations per
/// unknown unless `count` is given. `observer` hears of the configurations
/// drawn and may stop the work.
///
/// # Errors
/// When configurations cannot be generated (see [`Sensor::generate`](crate::methods::Sensor::generate)),
/// [`Error::Interrupted`] when the observer stops the work.
pub fn random_samples(
    robot: &Robot,
    method: &dyn CalibrationMethod,
    count: Option<usize>,
    seed: u64,
    observer: &mut dyn Observer,
) -> Result<Vec<Sample>, Error> {
    let unknowns = robot.parameters().len() + method.auxiliary_names().len();
    let count = count.unwrap_or_else(|| {
        let needed =
            RANDOM_EQUATIONS_PER_UNKNOWN * unknowns as f64 / method.equations_per_configuration();
        needed.ceil() as usize + 2
    });
    method
        .sensor()
        .generate(robot, count, 0.0, &mut Sampler::new(seed), observer)
}

/// The paper's "Identifiable parameters" function for a study, and what it
/// was computed on.
#[derive(Clone, Debug)]
pub struct Identifiability {
    /// The base parameters, regrouping relations and new priority matrix.
    pub report: RankReport,
    /// What the rank test ran on, in words.
    pub source: String,
    /// Configurations of the data (measured, or random when there were none).
    pub configurations: usize,
    /// For measured data: how well they excite the base parameters.
    pub excitation: Option<Excitation>,
}

/// Identifiable parameters of `study` (Appendix III). A study without samples
/// is analysed on `count` random configurations (default: about 2.5
/// equations per unknown) drawn with `seed`. A study with measured samples is
/// analysed structurally, on random configurations like the data (their
/// constraints exactly satisfied), followed by the excitation check of §4 on
/// the data themselves. `observer` hears of the random configurations drawn
/// (the long part of an analysis of many) and may stop the work.
///
/// # Errors
/// Invalid data, configurations that cannot be generated, or too few
/// equations; [`Error::Interrupted`] when the observer stops the work.
pub fn identifiability(
    robot: &Robot,
    study: &Study,
    priority: &PriorityMatrix,
    count: Option<usize>,
    seed: u64,
    observer: &mut dyn Observer,
) -> Result<Identifiability, Error> {
    let has_data = !study.sets.is_empty() && study.sets.iter().all(|set| !set.samples.is_empty());
    if has_data {
        let report = structural_parameters(robot, study, priority, seed)?;
        let checked = excitation(robot, study, &report)?;
        let labels: Vec<&str> = study.sets.iter().map(|set| set.label.as_str()).collect();
        return Ok(Identifiability {
            report,
            source: format!("random configurations like {}", labels.join(", ")),
            configurations: study.sets.iter().map(|set| set.samples.len()).sum(),
            excitation: Some(checked),
        });
    }
    let set = study.sets.first().ok_or_else(|| Error::InvalidData {
        line: None,
        message: "the study has no measurement set".into(),
    })?;
    let samples = random_samples(robot, set.method.as_ref(), count, seed, observer)?;
    let configurations = samples.len();
    let random = Study::single(set.method.clone_method(), samples, "random configurations");
    Ok(Identifiability {
        report: identifiable_parameters(robot, &random, priority)?,
        source: format!("{configurations} random configurations (seed {seed})"),
        configurations,
        excitation: None,
    })
}
