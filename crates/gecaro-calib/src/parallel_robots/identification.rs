//! Identification of a parallel robot's parameters: Gauss–Newton on the base set
//! (module docs of [`super`]), with the precision of every parameter and a
//! serial robot's verdict.

use gecaro_core::parallel_model::{ParallelModel, ParameterUnit};
use gecaro_data::sample::Sample;
use nalgebra::Isometry3;

use super::auxiliary::Auxiliary;
use super::changed::changed_block;
use super::descent::{Descent, Fit, PriorRows, base_system, descend, descend_reweighted};
use super::identifiability::{PlatformRankReport, rank_of};
use super::leg::{LEG_UNKNOWNS, MeasuringLeg};
use super::measure::{PlatformMeasure, PlatformNoise};
use super::observation::{
    NormalSystem, PlatformRows, actuator_values, normal_system, platform_rows,
};
use super::plausible::{PLAUSIBLE_ANGLE, PLAUSIBLE_GAIN, PLAUSIBLE_LENGTH};
use super::region::{PlatformRegion, where_it_holds};
use super::registration::{in_base_frame, measurement_frame};
use super::reweighting::{Reweighted, reweighted};
use super::stations::{STATION_UNKNOWNS, StationFrames};
use crate::Error;
use crate::identifiability::ParameterStatus;
use crate::identification::{
    CellChange, DEFAULT_OUTLIER_THRESHOLD, Loss, LossKind, NoiseTest, Outcome, noise_test,
};
use gecaro_core::JointRegion;
use gecaro_data::prior::Prior;
use nalgebra::DMatrix;

/// Observations named as standing out, at most.
const MAX_OUTLIERS_NAMED: usize = 10;

/// How an identification of a platform runs.
#[derive(Clone, Debug, PartialEq)]
pub struct PlatformIdentificationOptions {
    /// Gauss–Newton iterations at most.
    pub max_iterations: usize,
    /// The relative decrease of the cost below which the fit has converged.
    pub tolerance: f64,
    /// The region the platform will be used in (a range of each actuator's
    /// values), over which the verdict predicts its error; `None`: the
    /// actuators' ranges.
    pub work_region: Option<JointRegion>,
    /// The loss: plain least squares by default; a robust one reweights
    /// each observation by its residual after the least-squares fit
    /// ([`identify_platform`]).
    pub loss: Loss,
    /// Drop the observations that stand out of a solved fit and identify
    /// the rest again, once.
    pub reject: bool,
    /// A Gaussian prior on the identifiable parameters about their nominal
    /// values: σ of lengths (m), of angles (rad), and of gains as a part
    /// of their nominal value (its per-parameter overrides name a serial
    /// robot's parameters: refused here). None by default.
    pub prior: Option<Prior>,
    /// The measuring leg's mount for the `leg` measure, as stated (its
    /// length at reading 0 is found from the data on the nominal robot;
    /// its mount and length are then identified with the parameters).
    pub leg: Option<MeasuringLeg>,
}

/// A prior's rows on the base columns `base` of `nominal`, weighted by
/// `unit/σ_p` of their unit (a gain's σ relative to its nominal value).
fn prior_rows<M: ParallelModel>(
    nominal: &M,
    prior: &Prior,
    base: &[usize],
    unit: f64,
) -> PriorRows {
    let values = nominal.parameters();
    PriorRows {
        rows: base
            .iter()
            .map(|column| {
                let sigma = match nominal.parameter_unit(*column) {
                    ParameterUnit::Length => prior.length,
                    ParameterUnit::Angle => prior.angle,
                    ParameterUnit::Gain => prior.gain * values[*column].abs().max(f64::EPSILON),
                };
                (*column, values[*column], sigma)
            })
            .collect(),
        unit,
    }
}

impl Default for PlatformIdentificationOptions {
    fn default() -> Self {
        Self {
            max_iterations: crate::identification::DEFAULT_MAX_ITERATIONS,
            tolerance: 1e-10,
            work_region: None,
            loss: Loss::default(),
            reject: false,
            prior: None,
            leg: None,
        }
    }
}

/// One parameter of an identified platform.
#[derive(Clone, Debug, PartialEq)]
pub struct PlatformParameter {
    /// Its name (`a1x`, `l3`, `K6`, `tz`).
    pub name: String,
    /// The nominal value (m; a gain dimensionless).
    pub nominal: f64,
    /// The identified value (the nominal one unless identifiable).
    pub identified: f64,
    /// `σ̂·√diag((WᵀW)⁻¹)` when identified.
    pub sigma: Option<f64>,
    /// Identifiable, regrouped, of no effect or excluded.
    pub status: ParameterStatus,
}

/// An identified parallel robot.
#[derive(Clone, Debug)]
pub struct PlatformIdentification<M> {
    /// The robot with the identified parameters.
    pub calibrated: M,
    /// Every parameter, in vocabulary order.
    pub parameters: Vec<PlatformParameter>,
    /// The identifiable parameters and the regrouping at the nominal ones.
    pub rank: PlatformRankReport,
    /// What the measurements say of the fit.
    pub outcome: Outcome,
    /// The χ² test of the residuals against the stated noise.
    pub noise_test: Option<NoiseTest>,
    /// RMS of the equations' residuals before and after (m: legs for poses,
    /// coordinates for points).
    pub rms_before: f64,
    /// See [`rms_before`](Self::rms_before).
    pub rms_after: f64,
    /// Gauss–Newton iterations made.
    pub iterations: usize,
    /// The parameters whose value no platform has (names).
    pub implausible: Vec<String>,
    /// Where the result holds: the predicted error at the measured poses
    /// and over the work region; `None` for a fit that is no solution.
    pub region: Option<PlatformRegion>,
    /// The observations whose residual stands out from the fit: their
    /// first line (a distance's pair by its first row) and the RMS of their
    /// rows in units of the stated σ (of σ̂ without one), above
    /// [`DEFAULT_OUTLIER_THRESHOLD`], the largest first (at most ten).
    pub outliers: Vec<PlatformOutlier>,
    /// Every observation's residual, in order: the RMS of its rows in the
    /// units the outliers' `ratio` is in (the stated σ, of σ̂ without one;
    /// with a robust loss, its robust σ̂); a [`dropped`](Self::dropped)
    /// one's in the fit with it.
    pub residual_ratios: Vec<f64>,
    /// The observations dropped before this fit (indices over every set's
    /// observations, in order; [`rejected`](Self::rejected) names them):
    /// [`weights`](Self::weights) and the fit's sums count the others only.
    pub dropped: Vec<usize>,
    /// The base frame in the instrument's frame, when the data were in
    /// another frame and were registered ([`super::measurement_frame`]).
    pub registered: Option<Isometry3<f64>>,
    /// Each set's station after the first ([`identify_platform_sets`]), in
    /// order: empty for one set.
    pub stations: Vec<PlatformStation>,
    /// The measuring leg of the `leg` measure: as stated and as identified.
    pub leg: Option<IdentifiedLeg>,
    /// The loss the fit minimised (least squares where a robust one was
    /// asked for but the least-squares fit it starts from did not converge).
    pub loss: Loss,
    /// Reweightings of a robust loss (0 for least squares).
    pub reweightings: usize,
    /// Each observation's robust weight at the solution, in order (empty
    /// for least squares).
    pub weights: Vec<f64>,
    /// The robust σ̂ of a row the weights were formed with (in units of the
    /// stated σ; m without one): the RMS of the observations within the
    /// outlier threshold of it, from the rows' median absolute deviation;
    /// `None` for least squares.
    pub robust_sigma: Option<f64>,
    /// The prior the fit was held by, if any (none where the least-squares
    /// fit it weighs against did not converge).
    pub prior: Option<Prior>,
    /// The observations dropped before this fit
    /// ([`reject`](PlatformIdentificationOptions::reject)): their first
    /// line and residual ratio in the fit with them, the largest first.
    pub rejected: Vec<PlatformOutlier>,
    /// The observations that disagree with the rest as one block in the
    /// data's row order, at the first fit (before a robust loss or a
    /// rejection weighs them down): the cell changed during the
    /// measurement (the test of [`CellChange`]); the outcome is then
    /// [`Outcome::Changed`]. Its label is empty.
    pub change: Option<CellChange>,
}

/// A measuring leg, identified with the platform.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IdentifiedLeg {
    /// As stated, with its length at reading 0 found from the data on the
    /// nominal platform (the start of the fit).
    pub stated: MeasuringLeg,
    /// As identified.
    pub identified: MeasuringLeg,
    /// σ of its unknowns `[a, b, l]` (m).
    pub sigma: [f64; LEG_UNKNOWNS],
}

/// An observation a fit names: where it is, and how far it stands out.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlatformOutlier {
    /// Its set ([`identify_platform_sets`]; 0 for one set).
    pub set: usize,
    /// Its first line in its set's file (a distance's pair by its first
    /// row).
    pub line: Option<usize>,
    /// The RMS of its rows in units of the stated σ (of σ̂ without one).
    pub ratio: f64,
}

/// A later set's station, identified: where the base frame is seen from it.
#[derive(Clone, Debug, PartialEq)]
pub struct PlatformStation {
    /// The base frame in the station's frame: its closed-form registration
    /// with the identified correction (what the set's data are read in).
    pub frame: Isometry3<f64>,
    /// σ of the correction's translation (m, along the base frame's axes)
    /// and rotation (rad, about them).
    pub sigma: [f64; 6],
}

/// Identifies `nominal`'s parameters from `samples` measured by `measure`,
/// their noise `noise` when stated (each row weighted by its σ, the
/// residuals tested against it). With [`reject`](PlatformIdentificationOptions::reject),
/// the observations that stand out of a solved fit — of a Huber fit for
/// least squares, which gross errors do not bend — are dropped and the
/// rest identified again, once ([`PlatformIdentification::rejected`]).
///
/// # Errors
/// The samples' own errors (missing columns, actuator values with no pose),
/// too few equations, a numerical failure.
pub fn identify_platform<M: ParallelModel>(
    nominal: &M,
    samples: &[Sample],
    measure: PlatformMeasure,
    noise: Option<PlatformNoise>,
    options: &PlatformIdentificationOptions,
) -> Result<PlatformIdentification<M>, Error> {
    identify_platform_sets(nominal, &[samples], measure, noise, options)
}

/// [`identify_platform`] from several sets, each measured from its own
/// station (a tracker moved between them): each registered in closed
/// form, the first's frame the base frame, and every later one's small
/// rigid correction `δ_s` (six unknowns after the robot's parameters, its
/// measurements read as `δ_s·m`) identified with the parameters
/// ([`PlatformIdentification::stations`]; the module docs of [`super`]).
/// Distances have no frame: their sets are one set. The samples' lines
/// are their own file's; their observations are counted over the sets in
/// order.
///
/// # Errors
/// As [`identify_platform`]; no set at all.
pub fn identify_platform_sets<M: ParallelModel>(
    nominal: &M,
    sets: &[&[Sample]],
    measure: PlatformMeasure,
    noise: Option<PlatformNoise>,
    options: &PlatformIdentificationOptions,
) -> Result<PlatformIdentification<M>, Error> {
    if options
        .prior
        .as_ref()
        .is_some_and(|prior| !prior.overrides.is_empty())
    {
        return Err(Error::InvalidOption {
            setting: crate::Setting::Prior,
            message: "a parallel robot's prior is one σ per unit (lengths, angles, gains): \
                      its parameters are not a serial robot's, which overrides name"
                .into(),
        });
    }
    // One set's samples as they are (10⁵ measured poses are not copied).
    let samples: std::borrow::Cow<'_, [Sample]> = match sets {
        [one] => std::borrow::Cow::Borrowed(*one),
        _ => sets.iter().flat_map(|set| set.iter().cloned()).collect(),
    };
    let taken = measure.samples_per_observation();
    if let Some(set) = sets.iter().find(|set| !set.len().is_multiple_of(taken)) {
        return Err(Error::InvalidData {
            line: set.last().and_then(|sample| sample.line),
            message: "a distance is measured between two rows: the set ends with half a pair"
                .into(),
        });
    }
    let set_of: Vec<usize> = sets
        .iter()
        .enumerate()
        .flat_map(|(set, samples)| std::iter::repeat_n(set, samples.len()))
        .collect();
    let stations = if sets.len() > 1 && measure.has_frame() {
        StationFrames::new(set_of.clone())
    } else {
        StationFrames::single()
    };
    let leg = match (measure, options.leg) {
        (PlatformMeasure::Leg, None) => {
            return Err(Error::InvalidOption {
                setting: crate::Setting::Method,
                message: "the leg measure needs the measuring leg's mount: its base and \
                          platform sockets"
                    .into(),
            });
        }
        (PlatformMeasure::Leg, Some(leg)) => {
            Some(MeasuringLeg::new(leg.base, leg.platform, leg.gain)?)
        }
        _ => None,
    };
    let auxiliary = Auxiliary { stations, leg };
    let (result, standing_out) = fit_platform(
        nominal,
        &samples,
        (&auxiliary, &set_of),
        measure,
        noise,
        options,
    )?;
    let change = changed_set(sets, measure, &standing_out);
    if !options.reject || standing_out.is_empty() || !result.outcome.solved() {
        return Ok(with_change(result, change));
    }
    // What stands out of a fit the gross errors do not bend: least squares
    // spreads them over their neighbours (four Delta points 0.5 mm off
    // made six good ones stand out), a robust loss does not.
    let standing_out = if options.loss.is_l2() {
        let judge = PlatformIdentificationOptions {
            loss: Loss::new(LossKind::Huber),
            ..options.clone()
        };
        match fit_platform(
            nominal,
            &samples,
            (&auxiliary, &set_of),
            measure,
            noise,
            &judge,
        )? {
            (judged, standing_out) if judged.outcome.solved() => standing_out,
            _ => standing_out,
        }
    } else {
        standing_out
    };
    if standing_out.is_empty() {
        return Ok(with_change(result, change));
    }
    let dropped: Vec<usize> = standing_out.iter().map(|(index, _)| *index).collect();
    let keep = |index: usize| !dropped.contains(&(index / taken));
    let kept: Vec<Sample> = (0..samples.len())
        .filter(|index| keep(*index))
        .map(|index| samples[index].clone())
        .collect();
    let kept_sets: Vec<usize> = (0..samples.len())
        .filter(|index| keep(*index))
        .map(|index| set_of[index])
        .collect();
    let (mut again, _) = fit_platform(
        nominal,
        &kept,
        (&auxiliary.kept(keep), &kept_sets),
        measure,
        noise,
        options,
    )?;
    // Every observation's residual: the kept ones' in this fit, the
    // dropped ones' in the fit with them.
    let mut dropped_sorted = dropped.clone();
    dropped_sorted.sort_unstable();
    let mut kept_ratios = again.residual_ratios.iter();
    again.residual_ratios = (0..samples.len() / taken)
        .map(
            |index| match standing_out.iter().find(|(at, _)| *at == index) {
                Some((_, ratio)) => *ratio,
                None => kept_ratios.next().copied().unwrap_or(f64::NAN),
            },
        )
        .collect();
    again.dropped = dropped_sorted;
    again.rejected = standing_out
        .into_iter()
        .map(|(index, ratio)| PlatformOutlier {
            set: set_of[index * taken],
            line: samples[index * taken].line,
            ratio,
        })
        .collect();
    Ok(with_change(again, change))
}

/// The change of [`changed_block`] within one of the `sets` (a block of
/// consecutive observations of one file: the cell changed while it was
/// measured), the observations `standing_out` counted over the sets in
/// order; the first set with one.
fn changed_set(
    sets: &[&[Sample]],
    measure: PlatformMeasure,
    standing_out: &StandingOut,
) -> Option<CellChange> {
    let taken = measure.samples_per_observation();
    let mut first = 0;
    for (set, samples) in sets.iter().enumerate() {
        let observations = samples.len() / taken;
        let own: Vec<usize> = standing_out
            .iter()
            .map(|(index, _)| *index)
            .filter(|index| (first..first + observations).contains(index))
            .map(|index| index - first)
            .collect();
        if let Some(mut change) = changed_block(samples, measure, &own) {
            change.set = set;
            return Some(change);
        }
        first += observations;
    }
    None
}

/// `result` with the change found at the first fit: a solved fit whose
/// data changed during the run is [`Outcome::Changed`], whatever its
/// residuals say (they are those of the cell before or after it).
fn with_change<M>(
    mut result: PlatformIdentification<M>,
    change: Option<CellChange>,
) -> PlatformIdentification<M> {
    if change.is_some() && result.outcome.solved() {
        result.outcome = Outcome::Changed;
    }
    result.change = change;
    result
}

/// Every observation that stands out of a fit: its index and residual
/// ratio, the largest first.
type StandingOut = Vec<(usize, f64)>;

/// One fit of [`identify_platform`], and every observation that stands out
/// of it.
fn fit_platform<M: ParallelModel>(
    nominal: &M,
    samples: &[Sample],
    (auxiliary, set_of): (&Auxiliary, &[usize]),
    measure: PlatformMeasure,
    noise: Option<PlatformNoise>,
    options: &PlatformIdentificationOptions,
) -> Result<(PlatformIdentification<M>, StandingOut), Error> {
    // Data an instrument took in its own frame, brought into the base
    // frame, a station at a time.
    let (registrations, moved) = register_stations(nominal, samples, &auxiliary.stations, measure);
    let registered = registrations.first().copied().flatten();
    let samples = moved.as_deref().unwrap_or(samples);
    // A measuring leg's zero, from its readings on the nominal platform.
    let auxiliary = &Auxiliary {
        stations: auxiliary.stations.clone(),
        leg: auxiliary
            .leg
            .map(|leg| zeroed_leg(nominal, &leg, samples))
            .transpose()?,
    };
    let mut rank = structural_rank(nominal, samples, auxiliary, measure, noise)?;
    let parameter_count = nominal.parameter_count();
    // The identified columns: the base set, then the auxiliary unknowns.
    let base: Vec<usize> = rank
        .base
        .iter()
        .copied()
        .chain(parameter_count..parameter_count + auxiliary.count())
        .collect();
    let mut poses: Vec<Isometry3<f64>> = Vec::new();
    let system = normal_system(
        nominal, samples, measure, noise, None, auxiliary, &mut poses,
    )?;
    let count = system.rows;
    if count < base.len() {
        return Err(Error::TooFewEquations {
            equations: count,
            unknowns: base.len(),
        });
    }
    let rms = |system: &NormalSystem| {
        let sigma = noise.map_or(1.0, |noise| noise.length);
        (system.cost / count as f64).sqrt() * sigma
    };
    let rms_before = rms(&system);
    let mut values = nominal.parameters();
    values.extend(auxiliary.start());
    let start = Descent {
        values,
        current: nominal.clone(),
        system,
        poses,
        iterations: 0,
        converged: false,
        diverged: false,
    };
    let fit = Fit {
        measure,
        noise,
        auxiliary,
    };
    let limits = (options.max_iterations, options.tolerance);
    let none = PriorRows::default();
    let mut descent = descend(nominal, samples, fit, (None, &none), &base, start, limits)?;
    let mut iterations = descent.iterations;
    // A prior: its rows weighted by the least-squares fit's σ̂ of unit
    // weight (as a serial robot's, maximum a posteriori with the noise the
    // data show), and the descent continued with them — on a converged fit
    // only (its σ̂ is no noise otherwise), and reported only where applied.
    let applied_prior = options.prior.as_ref().filter(|_| descent.converged);
    let prior = match applied_prior {
        Some(prior) => {
            let unit =
                (descent.system.cost / count.saturating_sub(base.len()).max(1) as f64).sqrt();
            let rows = prior_rows(nominal, prior, &rank.base, unit);
            descent =
                descend_reweighted(nominal, samples, fit, (None, &rows), &base, descent, limits)?;
            iterations += descent.iterations;
            rows
        }
        None => none,
    };
    let Reweighted {
        descent,
        weights,
        robust_sigma,
        reweightings,
        iterations: reweighted_iterations,
    } = reweighted(
        nominal,
        samples,
        fit,
        (&base, &prior),
        &options.loss,
        descent,
        limits,
    )?;
    iterations += reweighted_iterations;
    let Descent {
        values,
        current,
        system,
        poses,
        converged,
        diverged,
        ..
    } = descent;
    let (inverse, _) = base_system(&system, &base)?;
    rank.rows = count;
    rank.condition_number = condition(&system, &base);
    let found = auxiliary.at(&values[parameter_count..]);
    // What the test and σ̂ read: in least squares the fit's cost; with a
    // robust loss the residuals as measured of the observations within the
    // outlier threshold of σ̂ (as a serial robot's, `identification::tested`:
    // the loss weights the fit, not what the data say).
    // An observation stands out beyond the threshold of the robust σ̂ and,
    // when σ is stated, of the stated σ too: an RMS of a pose's correlated
    // closure rows is spread wider than χ² of its rows says, and a clean
    // pose at 2.7 σ stood out of a σ̂ of 0.88 σ.
    let scale = robust_sigma.map(|sigma| {
        if noise.is_some() {
            sigma.max(1.0)
        } else {
            sigma
        }
    });
    let rows_each = measure.rows_per_observation(nominal);
    let (tested_cost, tested_rows) = match scale {
        None => (system.cost - system.prior_cost, count),
        Some(scale) => system
            .errors
            .iter()
            .filter(|error| **error / scale <= DEFAULT_OUTLIER_THRESHOLD)
            .fold((0.0, 0), |(cost, rows), error| {
                (cost + error * error * rows_each as f64, rows + rows_each)
            }),
    };
    let freedom = tested_rows.saturating_sub(base.len());
    let test = noise.map(|_| noise_test(tested_cost, freedom));
    // σ̂ of a unit weight: √(χ²/ν) with σ stated, the residuals' own otherwise.
    let unit_sigma = (tested_cost / freedom.max(1) as f64).sqrt();
    let nominal_values = nominal.parameters();
    let parameters: Vec<PlatformParameter> = nominal
        .parameter_names()
        .into_iter()
        .enumerate()
        .map(|(index, name)| PlatformParameter {
            name,
            nominal: nominal_values[index],
            identified: values[index],
            sigma: base
                .iter()
                .position(|c| *c == index)
                .map(|k| unit_sigma * inverse[(k, k)].sqrt()),
            status: rank.statuses[index],
        })
        .collect();
    let implausible: Vec<String> = parameters
        .iter()
        .enumerate()
        .filter(|(index, parameter)| {
            let moved = (parameter.identified - parameter.nominal).abs();
            match nominal.parameter_unit(*index) {
                ParameterUnit::Gain => moved > PLAUSIBLE_GAIN * parameter.nominal.abs(),
                ParameterUnit::Angle => moved > PLAUSIBLE_ANGLE,
                ParameterUnit::Length => moved > PLAUSIBLE_LENGTH,
            }
        })
        .map(|(_, parameter)| parameter.name.clone())
        .collect();
    let solved = converged && !diverged;
    // The observations that stand out, in units of the stated σ (of σ̂
    // without one: the rows are then in metres).
    let scale = match scale {
        // With a robust loss, those left out of the test.
        Some(scale) => scale,
        None if noise.is_some() => 1.0,
        None => unit_sigma.max(f64::MIN_POSITIVE),
    };
    let residual_ratios: Vec<f64> = system.errors.iter().map(|error| error / scale).collect();
    let mut standing_out: StandingOut = residual_ratios
        .iter()
        .copied()
        .enumerate()
        .filter(|(_, ratio)| *ratio > DEFAULT_OUTLIER_THRESHOLD)
        .collect();
    standing_out.sort_by(|a, b| b.1.total_cmp(&a.1));
    let outliers: Vec<PlatformOutlier> = standing_out
        .iter()
        .take(MAX_OUTLIERS_NAMED)
        .map(|(index, ratio)| {
            let first = index * measure.samples_per_observation();
            PlatformOutlier {
                set: set_of.get(first).copied().unwrap_or(0),
                line: samples[first].line,
                ratio: *ratio,
            }
        })
        .collect();
    // The floor a held-out position measurement of a perfect platform
    // shows, √3 σ̂ of a coordinate; the posterior covariance σ̂²·(W_bᵀW_b)⁻¹
    // (rows weighted by 1/σ: σ̂ is the unit weight's).
    let region = solved
        .then(|| {
            // A held-out distance's noise is one coordinate's, a point's three.
            let coordinates: f64 =
                if matches!(measure, PlatformMeasure::Distance | PlatformMeasure::Leg) {
                    1.0
                } else {
                    3.0
                };
            let floor = coordinates.sqrt() * unit_sigma * noise.map_or(1.0, |noise| noise.length);
            where_it_holds(
                &current,
                measure,
                samples,
                |index| match measure {
                    PlatformMeasure::Pose => measure
                        .measured(&samples[index])
                        .ok()
                        .map(|pose| found.stations.corrected_measurement(index, &pose)),
                    PlatformMeasure::Point | PlatformMeasure::Distance | PlatformMeasure::Leg => {
                        poses.get(index).copied()
                    }
                },
                // The robot's covariance: the stations' corrections marginalised.
                (
                    &rank.base,
                    &(inverse.view((0, 0), (rank.base.len(), rank.base.len()))
                        * unit_sigma.powi(2)),
                ),
                floor,
                options.work_region.as_ref(),
            )
        })
        .flatten();
    let outcome = if diverged {
        Outcome::Diverged
    } else if !converged {
        Outcome::NotConverged
    } else if !implausible.is_empty() {
        Outcome::Implausible
    } else {
        match test {
            Some(test) if test.exceeded() => Outcome::ExceedsNoise,
            Some(test) if test.below() => Outcome::BelowNoise,
            _ if region
                .as_ref()
                .is_some_and(|region| !region.holds_everywhere) =>
            {
                Outcome::Regional
            }
            Some(_) => Outcome::FitsNoise,
            None => Outcome::Untested,
        }
    };
    let later_stations = station_frames(
        &registrations,
        &found.stations,
        &inverse,
        rank.base.len(),
        unit_sigma,
    );
    let leg = auxiliary.leg.zip(found.leg).map(|(stated, identified)| {
        let first = auxiliary.leg_column(rank.base.len());
        IdentifiedLeg {
            stated,
            identified,
            sigma: std::array::from_fn(|k| {
                unit_sigma * inverse[(first + k, first + k)].max(0.0).sqrt()
            }),
        }
    });
    let result = PlatformIdentification {
        calibrated: current,
        parameters,
        rank,
        outcome,
        noise_test: test,
        rms_before,
        // The residuals as measured, whatever weights a robust loss gave.
        rms_after: if robust_sigma.is_some() {
            let squares: f64 = system.errors.iter().map(|error| error * error).sum();
            (squares / system.errors.len().max(1) as f64).sqrt()
                * noise.map_or(1.0, |noise| noise.length)
        } else {
            rms(&system)
        },
        iterations,
        implausible,
        region,
        outliers,
        residual_ratios,
        dropped: Vec::new(),
        registered,
        stations: later_stations,
        leg,
        // What the fit did: a robust loss reweights a converged fit only.
        loss: if robust_sigma.is_some() {
            options.loss
        } else {
            Loss::default()
        },
        reweightings,
        weights,
        robust_sigma,
        rejected: Vec::new(),
        prior: applied_prior.cloned(),
        change: None,
    };
    Ok((result, standing_out))
}

/// `leg` with its length at reading 0 found from `samples` (their
/// readings) on the nominal platform's poses (the direct model from home),
/// checked: the leg's lengths there must follow its readings to within
/// what a platform's errors make ([`PLAUSIBLE_LENGTH`] RMS).
///
/// # Errors
/// [`Error::WrongUnit`] for readings in millimetres read as metres (they
/// fit once divided by 1,000); [`Error::InvalidData`] for readings no leg
/// mounted where stated gives (the sockets or the gain mistaken).
fn zeroed_leg<M: ParallelModel>(
    nominal: &M,
    leg: &MeasuringLeg,
    samples: &[Sample],
) -> Result<MeasuringLeg, Error> {
    let home = nominal.home();
    let (poses, readings): (Vec<Isometry3<f64>>, Vec<f64>) = samples
        .iter()
        .filter_map(|sample| {
            let actuators = actuator_values(nominal, sample).ok()?;
            Some((nominal.direct(actuators, &home).ok()?, sample.distance?))
        })
        .unzip();
    // The RMS of the leg's length against `l + K·s` with the readings
    // scaled by `scale`, its zero found for them.
    let misfit = |scale: f64| {
        let scaled: Vec<f64> = readings.iter().map(|reading| reading * scale).collect();
        let zeroed = leg.zeroed(&poses, &scaled);
        let squares: f64 = poses
            .iter()
            .zip(&scaled)
            .map(|(pose, reading)| {
                (zeroed.length_at(pose) - zeroed.length - zeroed.gain * reading).powi(2)
            })
            .sum();
        (zeroed, (squares / poses.len().max(1) as f64).sqrt())
    };
    let (zeroed, off) = misfit(1.0);
    if off <= PLAUSIBLE_LENGTH {
        return Ok(zeroed);
    }
    if misfit(1e-3).1 <= PLAUSIBLE_LENGTH {
        return Err(Error::WrongUnit {
            quantity: "length",
            unit: "mm",
            message: format!(
                "the measuring leg's readings depart from its lengths on the nominal platform \
                 by {off:.3} m RMS, as no platform's errors do; read as millimetres they \
                 follow them: the data are in millimetres"
            ),
        });
    }
    Err(Error::InvalidData {
        line: None,
        message: format!(
            "the measuring leg's readings depart from its lengths on the nominal platform by \
             {off:.3} m RMS, as no platform's errors do: its sockets (leg base, leg platform) \
             or its gain are not as stated"
        ),
    })
}

/// Each set's samples brought into the base frame, a station at a time
/// ([`measurement_frame`]): each station's registration (`None` where its
/// data were in the base frame already, or give no frame) and the moved
/// samples (`None` when none moved).
fn register_stations<M: ParallelModel>(
    nominal: &M,
    samples: &[Sample],
    stations: &StationFrames,
    measure: PlatformMeasure,
) -> (Vec<Option<Isometry3<f64>>>, Option<Vec<Sample>>) {
    let ranges = stations.ranges(samples.len());
    let registrations: Vec<Option<Isometry3<f64>>> = ranges
        .iter()
        .map(|range| measurement_frame(nominal, &samples[range.clone()], measure))
        .collect();
    if registrations.iter().all(Option::is_none) {
        return (registrations, None);
    }
    let mut moved = samples.to_vec();
    for (range, frame) in ranges.into_iter().zip(&registrations) {
        if let Some(frame) = frame {
            let registered = in_base_frame(&samples[range.clone()], frame);
            moved[range].clone_from_slice(&registered);
        }
    }
    (registrations, Some(moved))
}

/// The later stations' frames and precision: each the base frame in the
/// station's frame, `T_s·δ_s⁻¹` (its registration `T_s`, the identity
/// without one; `δ_s` the identified correction), and its correction's σ
/// from the covariance `inverse·σ̂²` (the corrections' columns after the
/// `parameters` identified).
fn station_frames(
    registrations: &[Option<Isometry3<f64>>],
    corrections: &StationFrames,
    inverse: &DMatrix<f64>,
    parameters: usize,
    unit_sigma: f64,
) -> Vec<PlatformStation> {
    (1..=corrections.corrected())
        .map(|station| {
            let registration = registrations
                .get(station)
                .copied()
                .flatten()
                .unwrap_or_else(Isometry3::identity);
            let first = parameters + STATION_UNKNOWNS * (station - 1);
            PlatformStation {
                frame: registration * corrections.correction(station).inverse(),
                sigma: std::array::from_fn(|k| {
                    unit_sigma * inverse[(first + k, first + k)].max(0.0).sqrt()
                }),
            }
        })
        .collect()
}

/// Configurations the rank analysis takes at most: the structure's rank
/// shows in a few thousand equations; more add precision, not rank.
const RANK_SAMPLES: usize = 2000;

/// The identifiable parameters from at most [`RANK_SAMPLES`] configurations
/// spread evenly over the data (all of them below that), measured from
/// the `auxiliary` unknowns: their columns projected out of W first, so
/// that a parameter whose effect a station's frame or the measuring leg's
/// mount takes is not counted identifiable.
pub(super) fn structural_rank<M: ParallelModel>(
    nominal: &M,
    samples: &[Sample],
    auxiliary: &Auxiliary,
    measure: PlatformMeasure,
    noise: Option<PlatformNoise>,
) -> Result<PlatformRankReport, Error> {
    // Whole observations (a distance's pairs), spread.
    let size = measure.samples_per_observation();
    let observations = samples.len() / size;
    let picked = RANK_SAMPLES / size;
    let indices: Vec<usize> = if samples.len() <= RANK_SAMPLES {
        (0..samples.len()).collect()
    } else {
        (0..picked)
            .flat_map(|k| {
                let first = k * observations / picked * size;
                first..first + size
            })
            .collect()
    };
    let taken: Vec<Sample> = indices
        .iter()
        .map(|index| samples[*index].clone())
        .collect();
    let mut chosen = vec![false; samples.len()];
    for index in &indices {
        chosen[*index] = true;
    }
    let auxiliary = auxiliary.kept(|index| chosen[index]);
    let mut rows = platform_rows(nominal, &taken, measure, noise, &auxiliary, &mut Vec::new())?;
    if auxiliary.count() > 0 {
        rows = without_corrections(rows, nominal.parameter_count());
    }
    rank_of(nominal, &rows, measure)
}

/// W's first `parameters` columns with what the columns after them (the
/// stations' corrections) can take projected out: `(I − Q·Qᵀ)·W_ξ`, `Q` an
/// orthonormal basis of the corrections' columns.
fn without_corrections(rows: PlatformRows, parameters: usize) -> PlatformRows {
    let matrix = &rows.matrix;
    let (count, columns) = (matrix.nrows(), matrix.ncols());
    let corrections = DMatrix::from_fn(count, columns - parameters, |i, j| {
        matrix[(i, parameters + j)]
    });
    let basis = corrections.qr().q();
    let own = DMatrix::from_fn(count, parameters, |i, j| matrix[(i, j)]);
    let projected = &own - &basis * (basis.transpose() * &own);
    PlatformRows {
        matrix: faer::Mat::from_fn(count, parameters, |i, j| projected[(i, j)]),
    }
}

/// The condition number of the base columns of W: `√(λmax/λmin)` of their
/// normal equations.
fn condition(system: &NormalSystem, base: &[usize]) -> f64 {
    let gram = DMatrix::from_fn(base.len(), base.len(), |i, j| {
        system.gram[(base[i], base[j])]
    });
    let values = gram.symmetric_eigenvalues();
    let (smallest, largest) = (values.min(), values.max());
    if smallest > 0.0 {
        (largest / smallest).sqrt()
    } else {
        f64::INFINITY
    }
}
