//! Choosing the configurations to measure before measuring: an optimal
//! subset of a candidate pool.
//!
//! The pool is cut into *units*, what a measurement session takes whole: a
//! configuration (position, frame and plane methods), a set (point and frame
//! link) or a pair (distance). Unit u contributes the rows X_u of the base
//! columns W_b at the nominal robot (Appendix III), its columns scaled by the
//! error units as for the observability indices ([`crate::observability::Observability`]),
//! and so the information X_uᵀX_u. A design S is judged on its information
//! M = Σ_{u∈S} X_uᵀX_u by a [`Criterion`]: D(S) = log det M by default (the
//! smallest confidence ellipsoid of the parameters; O1 is exp(D/2L)/√m), or
//! A, E, O4, O5, or the predicted error at test poses (`planning::criteria`).
//!
//! Units with a configuration outside the joint limits are never chosen, nor
//! (with a minimum distance) units closer than it in joint space to a chosen
//! or kept one. The D-optimal design is built by a deterministic greedy pass
//! then improved by Mitchell's DETMAX exchange with rank-r updates
//! (`planning::detmax`); the other criteria continue from it by a shortlisted
//! exchange of pairs (`planning::criteria`). A ridge of 1e-9 of the mean diagonal of
//! a unit's information keeps M invertible while the design is short.

use std::ops::Range;

use gecaro_core::{PriorityMatrix, Robot};
use nalgebra::{DMatrix, DVector};

use crate::Error;
use crate::error::Setting;
use crate::method::CalibrationMethod;
use crate::methods::units;
use crate::observability::Observability;
use crate::progress::{Observer, Progress, report};
use crate::sample::Sample;
use crate::sampler::Sampler;
use crate::samples::{SampleRef, SampleSlice, Samples};

mod columns;
mod continuous;
mod criteria;
mod detmax;
mod spacing;

use crate::study::Study;
pub(crate) use columns::{BaseColumns, nominal_study};
use columns::{Blocks, contiguous};
pub use criteria::Criterion;
use criteria::Objective;
use spacing::Spacing;

/// What to plan: how many configurations, by which criterion, around which
/// measured ones.
#[derive(Clone, Debug)]
pub struct PlanRequest<'a> {
    /// Configurations wanted in all (rows of the data file, kept ones
    /// included); rounded to whole sets and pairs.
    pub count: usize,
    /// Configurations measured already: part of the design, never dropped.
    pub kept: SampleSlice<'a>,
    /// What the design optimises.
    pub criterion: Criterion,
    /// The smallest joint-space distance (Euclidean, radians and metres)
    /// between two chosen units, and between a chosen and a kept one; 0 for
    /// none.
    pub min_distance: f64,
}

impl<'a> PlanRequest<'a> {
    /// `count` configurations, D-optimal, nothing kept, no minimum distance.
    pub fn new(count: usize) -> Self {
        PlanRequest {
            count,
            kept: SampleSlice::empty(),
            criterion: Criterion::D,
            min_distance: 0.0,
        }
    }
}

/// How good a design is, in the scaled base columns of its pool.
#[derive(Clone, Debug, PartialEq)]
pub struct DesignQuality {
    /// D = log det M.
    pub log_det: f64,
    /// The observability indices of the design's scaled W_b.
    pub observability: Observability,
    /// The value of the criterion asked (see [`Criterion::meaning`]).
    pub value: f64,
}

/// A chosen design.
#[derive(Clone, Debug)]
pub struct Plan {
    /// The chosen configurations, kept ones first, then the chosen units
    /// (whole sets and pairs) in the order of [`units`] of the pool.
    pub samples: Vec<Sample>,
    /// The chosen units: indices into [`units`] of the pool, ascending.
    pub chosen: Vec<usize>,
    /// The design's quality (kept units included).
    pub quality: DesignQuality,
    /// Exchanges made after the greedy pass.
    pub exchanges: usize,
    /// Names of the base parameters (columns), auxiliary unknowns first.
    pub columns: Vec<String>,
}

/// A candidate pool, cut into units, with the rows each contributes to the
/// scaled base columns: built once (the structural base set and W_b of every
/// candidate), then planned from and judged against as often as needed.
pub struct CandidatePool<'a> {
    robot: &'a Robot,
    method: &'a dyn CalibrationMethod,
    /// The pool's samples, unit by unit.
    samples: Samples,
    /// Each unit's range in `samples`, in the order of [`units`] of the pool.
    ranges: Vec<Range<usize>>,
    columns: BaseColumns,
    candidates: Blocks,
}

impl<'a> CandidatePool<'a> {
    /// The pool `pool` of `method` on `robot`, base columns as `priority` says.
    ///
    /// # Errors
    /// Invalid samples, or too few equations for the base set.
    pub fn new(
        robot: &'a Robot,
        method: &'a dyn CalibrationMethod,
        pool: SampleSlice<'_>,
        priority: &PriorityMatrix,
    ) -> Result<Self, Error> {
        let (samples, ranges) = contiguous(pool, &units(method, pool));
        let columns = BaseColumns::of(robot, method, samples.as_slice(), priority)?;
        let candidates = columns.blocks(robot, method, samples.as_slice(), &ranges)?;
        Ok(CandidatePool {
            robot,
            method,
            samples,
            ranges,
            columns,
            candidates,
        })
    }

    /// The robot, the method and the base columns the pool is judged in.
    pub(crate) fn parts(&self) -> (&'a Robot, &'a dyn CalibrationMethod, &BaseColumns) {
        (self.robot, self.method, &self.columns)
    }

    /// The robot planned for.
    pub fn robot(&self) -> &'a Robot {
        self.robot
    }

    /// The method planned for.
    pub fn method(&self) -> &'a dyn CalibrationMethod {
        self.method
    }

    /// Configurations in the pool.
    pub fn len(&self) -> usize {
        self.samples.len()
    }

    /// Whether the pool has no configuration.
    pub fn is_empty(&self) -> bool {
        self.samples.is_empty()
    }

    /// Units (configurations, sets or pairs) in the pool.
    pub fn unit_count(&self) -> usize {
        self.ranges.len()
    }

    /// A random design to compare a plan with: `kept`, then `count` units of
    /// the pool drawn at random (whole sets and pairs).
    pub fn random_design(
        &self,
        kept: SampleSlice<'_>,
        count: usize,
        sampler: &mut Sampler,
    ) -> Samples {
        let mut design = kept.to_rows();
        for unit in sampler.subset(self.ranges.len(), count.min(self.ranges.len())) {
            design.extend(self.samples.slice(self.ranges[unit].clone()).to_rows());
        }
        design.into()
    }

    /// Σ X_uᵀX_u of `design` (any samples, whole units) in these columns.
    fn information_of(&self, design: SampleSlice<'_>) -> Result<DMatrix<f64>, Error> {
        let width = self.columns.layout.columns();
        let zero = DMatrix::zeros(width, width);
        if design.is_empty() {
            return Ok(zero);
        }
        let (design, ranges) = contiguous(design, &units(self.method, design));
        let blocks = self
            .columns
            .blocks(self.robot, self.method, design.as_slice(), &ranges)?;
        Ok(blocks.information(&zero, 0..ranges.len()))
    }

    /// The criterion made concrete in these columns.
    fn objective(&self, criterion: &Criterion) -> Result<Objective, Error> {
        let poses = match criterion {
            Criterion::TestPoses(poses) => poses.as_slice(),
            _ => &[],
        };
        Objective::of(criterion, || {
            if poses.is_empty() {
                return Err(no_test_poses());
            }
            let width = self.columns.layout.columns();
            let mut weight = DMatrix::zeros(width, width);
            for jacobian in self.columns.pose_jacobians(self.robot, poses, true)? {
                let position = jacobian.rows(0, 3);
                weight += position.transpose() * position;
            }
            Ok((weight, poses.len()))
        })
    }

    /// The quality of any set of samples (whole units) for `criterion`, in
    /// the pool's scaled base columns: for comparing designs (random subsets,
    /// a plan, measured data).
    ///
    /// # Errors
    /// Invalid samples, or no test poses for the test criterion.
    pub fn assess(
        &self,
        design: SampleSlice<'_>,
        criterion: &Criterion,
    ) -> Result<DesignQuality, Error> {
        let objective = self.objective(criterion)?;
        let information = self.information_of(design)?;
        Ok(quality(&information, &objective, design.len()))
    }

    /// Chooses about `request.count` configurations from the pool (whole
    /// units), optimising `request.criterion` (see the module docs).
    /// `observer` hears of the steps ([`Progress::Step`]) and stops the work with
    /// [`Error::Interrupted`] on [`ControlFlow::Break`](std::ops::ControlFlow::Break).
    ///
    /// # Errors
    /// Invalid kept samples, a pool with fewer admissible units than asked
    /// (or than lie `min_distance` apart), [`Error::TooFewEquations`] when the
    /// design has fewer equations than base parameters, no test poses for the
    /// test criterion, or [`Error::Interrupted`].
    pub fn plan(
        &self,
        request: &PlanRequest<'_>,
        observer: &mut dyn Observer,
    ) -> Result<Plan, Error> {
        let (robot, method, pool, ranges) = (self.robot, self.method, &self.samples, &self.ranges);
        let kept = request.kept;
        let joint_positions = |sample: SampleRef<'_>| {
            robot
                .joint_positions(sample.motor_positions())
                .ok()
                .filter(|q| robot.within_limits(q.as_slice()))
        };
        // Joint variables of every unit; None when one is outside the limits.
        let configurations: Vec<Option<Vec<DVector<f64>>>> = ranges
            .iter()
            .map(|range| {
                pool.slice(range.clone())
                    .iter()
                    .map(joint_positions)
                    .collect()
            })
            .collect();
        let admissible: Vec<bool> = configurations.iter().map(Option::is_some).collect();
        let admissible_count = admissible.iter().filter(|a| **a).count();
        let unit_size = pool.len().max(1) as f64 / ranges.len().max(1) as f64;
        let wanted =
            ((request.count.saturating_sub(kept.len())) as f64 / unit_size).round() as usize;
        if wanted > admissible_count {
            return Err(Error::InvalidOption {
                setting: Setting::Count,
                message: format!(
                    "{} configurations asked; the pool has {} ({admissible_count} of its {} units within the joint limits)",
                    request.count,
                    pool.len(),
                    ranges.len()
                ),
            });
        }
        if !(request.min_distance >= 0.0 && request.min_distance.is_finite()) {
            return Err(Error::InvalidOption {
                setting: Setting::MinDistance,
                message: format!("{} is not a distance (≥ 0)", request.min_distance),
            });
        }
        let mut spacing = Spacing::new(
            configurations
                .into_iter()
                .map(Option::unwrap_or_default)
                .collect(),
            request.min_distance,
        );
        for sample in kept {
            if let Ok(q) = robot.joint_positions(sample.motor_positions()) {
                spacing.keep(&[q]);
            }
        }
        let objective = self.objective(&request.criterion)?;
        let candidates = &self.candidates;
        let width = candidates.width;
        // Too few equations is known before any search: the pool's
        // equations per unit times the units asked, with the kept ones.
        let equations_of = |samples: SampleSlice<'_>| {
            method
                .row_count(samples)
                .saturating_sub(method.dependent_rows(samples))
        };
        let pool_equations = equations_of(pool.as_slice());
        let expected = (pool_equations as f64 / ranges.len().max(1) as f64 * wanted as f64).floor()
            as usize
            + equations_of(kept);
        if expected < width {
            return Err(Error::TooFewEquations {
                equations: expected,
                unknowns: width,
            });
        }
        let kept_information = self.information_of(kept)?;
        let ridge = candidates.ridge();
        let base = &kept_information + DMatrix::<f64>::identity(width, width) * ridge;
        let total = steps_of(&objective, wanted);
        let mut steps = 0;
        let (chosen, exchanges) = optimise(
            candidates,
            &base,
            ridge,
            wanted,
            &admissible,
            &mut spacing,
            &objective,
            || {
                steps += 1;
                report(
                    observer,
                    Progress::Step {
                        done: steps.min(total),
                        total,
                    },
                )
            },
        )?;
        // The exchanges stop once nothing improves, mostly well before the
        // steps allowed: the part is done.
        report(observer, Progress::Step { done: total, total })?;
        let chosen: Vec<usize> = (0..ranges.len()).filter(|u| chosen[*u]).collect();
        let mut samples = kept.to_rows();
        for unit in &chosen {
            samples.extend(pool.slice(ranges[*unit].clone()).to_rows());
        }
        let equations = equations_of(Samples::from(samples.as_slice()).as_slice());
        if equations < width {
            return Err(Error::TooFewEquations {
                equations,
                unknowns: width,
            });
        }
        let information = candidates.information(&kept_information, chosen.iter().copied());
        Ok(Plan {
            quality: quality(&information, &objective, samples.len()),
            samples,
            chosen,
            exchanges,
            columns: self.columns.names.clone(),
        })
    }
}

/// The steps [`optimise`] reports at most for `wanted` units: D's
/// exchanges, and as many again for the other criteria's.
fn steps_of(objective: &Objective, wanted: usize) -> usize {
    let d_only = matches!(objective, Objective::D);
    (if d_only { 3 } else { 6 }) * wanted.max(1)
}

/// `wanted` units of `candidates` chosen for `objective` on top of the
/// information `base` (what is kept, and the ridge `ridge` that keeps it
/// invertible): the D-optimal designs of the exchange ([`detmax`]), then,
/// for another criterion, each continued by its own exchange
/// ([`criteria::exchange`]) and the best kept. Returns which units are
/// chosen and the exchanges made; `step` hears of each step and may stop
/// the work.
///
/// # Errors
/// A design whose information is not positive definite, or the error
/// `step` returns.
#[allow(clippy::too_many_arguments)]
fn optimise(
    candidates: &Blocks,
    base: &DMatrix<f64>,
    ridge: f64,
    wanted: usize,
    admissible: &[bool],
    spacing: &mut Spacing,
    objective: &Objective,
    mut step: impl FnMut() -> Result<(), Error>,
) -> Result<(Vec<bool>, usize), Error> {
    let mut designs = detmax::detmax(
        candidates,
        base.clone(),
        ridge,
        wanted,
        admissible,
        spacing,
        &mut step,
    )?
    .into_iter();
    let (mut chosen, mut exchanges) = designs.next().ok_or_else(|| Error::Numerical {
        message: "planning: no design".into(),
    })?;
    if !matches!(objective, Objective::D) {
        // The other criteria continue from each D-optimal design; the
        // better result is kept (the exchange stops in local optima).
        exchanges += criteria::exchange(
            candidates,
            base,
            &mut chosen,
            admissible,
            spacing,
            objective,
            &mut step,
        )?;
        for (mut other, other_exchanges) in designs {
            let more = criteria::exchange(
                candidates, base, &mut other, admissible, spacing, objective, &mut step,
            )?;
            let value = |flags: &[bool]| {
                objective
                    .value(&candidates.information(base, (0..flags.len()).filter(|u| flags[*u])))
            };
            if value(&other) > value(&chosen) {
                chosen = other;
                exchanges = other_exchanges + more;
            }
        }
    }
    Ok((chosen, exchanges))
}

/// Units chosen by [`choose_units`], with the criterion's value (as
/// [`DesignQuality::value`] reports it) of the design and of another
/// design of the same units to compare with.
#[derive(Clone, Debug)]
pub(crate) struct ChosenUnits {
    /// The chosen units' indices, in increasing order.
    pub(crate) chosen: Vec<usize>,
    /// The criterion's value of the chosen design.
    pub(crate) value: f64,
    /// Its value of the design compared with.
    pub(crate) compared: f64,
}

/// `wanted` of `units` — each a unit's rows on the base columns, scaled as
/// the caller judges them — chosen for `criterion` by the exchanges a
/// serial plan makes ([`optimise`], no unit kept, no minimum distance);
/// the test criterion's `T = Σ D_tᵀD_t` of `test_rows` (its poses' error
/// rows in the same columns: the structure's own test poses, not the
/// criterion's joint values). The value of the design `compared` (unit
/// indices) is reported beside the plan's.
///
/// # Errors
/// No test rows for the test criterion, a design whose information is
/// not positive definite.
pub(crate) fn choose_units(
    units: Vec<DMatrix<f64>>,
    wanted: usize,
    criterion: &Criterion,
    test_rows: &[DMatrix<f64>],
    compared: &[usize],
) -> Result<ChosenUnits, Error> {
    let width = units.first().map_or(0, DMatrix::ncols);
    let objective = Objective::of(criterion, || {
        if test_rows.is_empty() {
            return Err(no_test_poses());
        }
        let weight = test_rows
            .iter()
            .fold(DMatrix::zeros(width, width), |weight, rows| {
                weight + rows.transpose() * rows
            });
        Ok((weight, test_rows.len()))
    })?;
    let count = units.len();
    let candidates = Blocks { units, width };
    let ridge = candidates.ridge();
    let base = DMatrix::<f64>::identity(width, width) * ridge;
    let mut spacing = Spacing::new(vec![Vec::new(); count], 0.0);
    let (flags, _) = optimise(
        &candidates,
        &base,
        ridge,
        wanted,
        &vec![true; count],
        &mut spacing,
        &objective,
        || Ok(()),
    )?;
    let chosen: Vec<usize> = (0..count).filter(|unit| flags[*unit]).collect();
    let zero = DMatrix::zeros(width, width);
    let value_of = |indices: &[usize]| {
        objective.reported(objective.value(&candidates.information(&zero, indices.iter().copied())))
    };
    Ok(ChosenUnits {
        value: value_of(&chosen),
        compared: value_of(compared),
        chosen,
    })
}

/// The error of the test criterion without test poses.
fn no_test_poses() -> Error {
    Error::InvalidOption {
        setting: Setting::TestPoses,
        message: "no test poses".into(),
    }
}

/// The quality of information `information` (kept units included, no ridge)
/// of a design of `configurations` configurations.
fn quality(
    information: &DMatrix<f64>,
    objective: &Objective,
    configurations: usize,
) -> DesignQuality {
    let eigenvalues = information.symmetric_eigenvalues();
    let values: Vec<f64> = eigenvalues.iter().map(|v| v.max(0.0).sqrt()).collect();
    DesignQuality {
        log_det: eigenvalues.iter().map(|v| v.max(0.0).ln()).sum(),
        observability: Observability::from_singular_values(&values, configurations),
        value: objective.reported(objective.value(information)),
    }
}

/// [`CandidatePool::plan`] on a pool built for this one plan.
///
/// # Errors
/// As [`CandidatePool::new`] and [`CandidatePool::plan`].
pub fn plan_configurations(
    robot: &Robot,
    method: &dyn CalibrationMethod,
    pool: SampleSlice<'_>,
    request: &PlanRequest<'_>,
    priority: &PriorityMatrix,
    observer: &mut dyn Observer,
) -> Result<Plan, Error> {
    CandidatePool::new(robot, method, pool, priority)?.plan(request, observer)
}

/// A D-optimal plan for a whole cell ([`plan_study`]): the configurations
/// of every measurement set, chosen as one design.
#[derive(Clone, Debug)]
pub struct StudyPlan {
    /// The chosen configurations of each set (joint values and set or pair
    /// ids; no readings), in the study's order of sets.
    pub sets: Vec<Vec<Sample>>,
    /// The design's quality in the study's scaled base columns.
    pub quality: DesignQuality,
    /// A random choice of as many units from the same pools, for comparison.
    pub random: DesignQuality,
    /// Exchanges made after the greedy pass.
    pub exchanges: usize,
    /// Names of the base parameters (columns), the named frames' unknowns
    /// first.
    pub columns: Vec<String>,
}

/// Chooses about `count` configurations in all from the candidate pools of
/// a study's sets (`candidates`: each set's samples are its pool) as one
/// D-optimal design: the units of every set (configurations, link sets,
/// pairs) are candidates of one information matrix, each set's rows read
/// through its tool and station and weighted by 1/σ of its sensor, the named
/// frames' unknowns among the columns — so a reflector or a station gets the
/// configurations the whole cell needs, not those it would need alone
/// (DETMAX from a greedy and a continuous start, as [`CandidatePool::plan`];
/// no minimum distance, no kept configurations). `seed` draws the random
/// comparison design.
///
/// # Errors
/// Invalid samples, too few equations for the base set, more units asked
/// than the pools hold within the joint limits, or [`Error::Interrupted`].
pub fn plan_study(
    robot: &Robot,
    candidates: &Study,
    count: usize,
    priority: &PriorityMatrix,
    seed: u64,
    observer: &mut dyn Observer,
) -> Result<StudyPlan, Error> {
    // Every set's pool unit by unit; the units of all sets in one list.
    let mut ordered = nominal_study(robot, candidates)?;
    let mut ranges: Vec<(usize, Range<usize>)> = Vec::new();
    for (index, set) in ordered.sets.iter_mut().enumerate() {
        let (samples, set_ranges) = contiguous(
            set.samples.as_slice(),
            &units(set.method.as_ref(), set.samples.as_slice()),
        );
        set.samples = samples;
        ranges.extend(set_ranges.into_iter().map(|range| (index, range)));
    }
    ordered.check(robot)?;
    let columns = BaseColumns::of_study(robot, &ordered, priority)?;
    let system = columns.system_of_study(robot, &ordered)?;
    let width = columns.layout.columns();
    let candidates_rows = columns.slice(
        &system,
        ranges.iter().map(|(set, range)| {
            let set = &ordered.sets[*set];
            set.method.row_count(set.samples.slice(range.clone()))
        }),
    )?;
    let within_limits = |sample: SampleRef<'_>| {
        robot
            .joint_positions(sample.motor_positions())
            .is_ok_and(|q| robot.within_limits(q.as_slice()))
    };
    let admissible: Vec<bool> = ranges
        .iter()
        .map(|(set, range)| {
            ordered.sets[*set]
                .samples
                .slice(range.clone())
                .iter()
                .all(within_limits)
        })
        .collect();
    let total: usize = ordered.sets.iter().map(|set| set.samples.len()).sum();
    let unit_size = total.max(1) as f64 / ranges.len().max(1) as f64;
    let wanted = (count as f64 / unit_size).round() as usize;
    let admissible_count = admissible.iter().filter(|a| **a).count();
    if wanted > admissible_count || wanted == 0 {
        return Err(Error::InvalidOption {
            setting: Setting::Count,
            message: format!(
                "{count} configurations asked; the pools hold {admissible_count} units within \
                 the joint limits (at least one is needed)"
            ),
        });
    }
    let ridge = candidates_rows.ridge();
    let base = DMatrix::<f64>::identity(width, width) * ridge;
    let mut spacing = Spacing::new(vec![Vec::new(); ranges.len()], 0.0);
    let mut steps = 0;
    let total_steps = 3 * wanted;
    let mut step = || {
        steps += 1;
        report(
            observer,
            Progress::Step {
                done: steps.min(total_steps),
                total: total_steps,
            },
        )
    };
    let (chosen, exchanges) = detmax::detmax(
        &candidates_rows,
        base,
        ridge,
        wanted,
        &admissible,
        &mut spacing,
        &mut step,
    )?
    .swap_remove(0);
    report(
        observer,
        Progress::Step {
            done: total_steps,
            total: total_steps,
        },
    )?;
    let mut sets: Vec<Vec<Sample>> = vec![Vec::new(); ordered.sets.len()];
    let mut equations = 0;
    for (unit, (set, range)) in ranges.iter().enumerate() {
        if chosen[unit] {
            sets[*set].extend(ordered.sets[*set].samples.slice(range.clone()).iter().map(
                |sample| Sample {
                    position: None,
                    orientation: None,
                    distance: None,
                    line: None,
                    ..sample.to_sample()
                },
            ));
        }
    }
    for (set, samples) in ordered.sets.iter().zip(&sets) {
        let samples = Samples::from(samples.as_slice());
        let samples = samples.as_slice();
        equations += set.method.row_count(samples) - set.method.dependent_rows(samples);
    }
    if equations < width {
        return Err(Error::TooFewEquations {
            equations,
            unknowns: width,
        });
    }
    let zero = DMatrix::zeros(width, width);
    let chosen_units = (0..ranges.len()).filter(|u| chosen[*u]);
    let information = candidates_rows.information(&zero, chosen_units);
    let mut sampler = Sampler::new(seed);
    let random_units = sampler.subset(ranges.len(), wanted);
    let random_information = candidates_rows.information(&zero, random_units.into_iter());
    let configurations = sets.iter().map(Vec::len).sum();
    Ok(StudyPlan {
        sets,
        quality: quality(&information, &Objective::D, configurations),
        random: quality(&random_information, &Objective::D, configurations),
        exchanges,
        columns: columns.names.clone(),
    })
}

/// [`CandidatePool::assess`] on a pool built for this one assessment.
///
/// # Errors
/// As [`CandidatePool::new`] and [`CandidatePool::assess`].
pub fn assess_design(
    robot: &Robot,
    method: &dyn CalibrationMethod,
    pool: SampleSlice<'_>,
    design: SampleSlice<'_>,
    criterion: &Criterion,
    priority: &PriorityMatrix,
) -> Result<DesignQuality, Error> {
    CandidatePool::new(robot, method, pool, priority)?.assess(design, criterion)
}
