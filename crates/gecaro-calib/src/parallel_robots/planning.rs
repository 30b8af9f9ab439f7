//! The poses to measure (as `gecaro plan` chooses a serial robot's
//! configurations): from a pool of reachable poses, the `count` whose
//! equations determine the identifiable parameters best. D-optimal,
//! `max log det(W_bᵀW_b)`, by default, chosen greedily one pose at a time
//! by the matrix determinant lemma `det(G + BᵀB) = det(G)·det(I +
//! B·G⁻¹·Bᵀ)`; any other criterion of [`Criterion`] (A, E, O4, O5) by the
//! exchanges a serial plan makes, and `test` — the calibrated platform's
//! predicted error over its workspace, `trace(M⁻¹·Σ D_tᵀD_t)` with `D_t`
//! the rows of the error the verdict judges ([`super::region`]: the tool
//! point's, or a distance's from home) at the verdict's random workspace
//! poses — likewise. The columns are scaled to unit norms over the pool,
//! the test rows with them, so the test criterion is the error in metres
//! per unit σ.

use gecaro_core::parallel_model::ParallelModel;
use gecaro_data::sample::Sample;
use nalgebra::{DMatrix, Isometry3};

use super::auxiliary::Auxiliary;
use super::identifiability::{PlatformRankReport, rank_of};
use super::measure::{PlatformMeasure, PlatformNoise};
use super::observation::{observation_rows, platform_rows};
use super::region::ErrorRows;
use super::simulation::{PlatformWorkspace, random_platform_poses, simulate_platform};
use crate::Error;
use crate::identification::WORK_POSES;
use crate::planning::{Criterion, choose_units};
use crate::simulation::Sampler;

/// A planned set of poses.
#[derive(Clone, Debug)]
pub struct PlannedPoses {
    /// The chosen poses, in the order chosen.
    pub poses: Vec<Isometry3<f64>>,
    /// Their configurations (actuator values), with what the sensor would
    /// read on the nominal robot.
    pub samples: Vec<Sample>,
    /// The identifiable parameters the design is for.
    pub rank: PlatformRankReport,
    /// The criterion the poses were chosen for (`d`, `a`, `e`, `o4`,
    /// `o5`, `test`).
    pub criterion_name: &'static str,
    /// Its value for the chosen poses: D's `log det(W_bᵀW_b)` per equation
    /// (comparable across counts); the others' as a serial plan reports
    /// them ([`Criterion::meaning`]; `test`: the predicted RMS error over
    /// the workspace per unit σ).
    pub criterion: f64,
    /// The same of as many random poses of the pool, for comparison.
    pub random_criterion: f64,
}

/// Chooses `count` poses of `model` measured by `measure` from `pool`
/// random reachable poses (seed `seed`) for `criterion` (the module docs;
/// the test criterion's own test poses are the workspace's, whatever it
/// holds).
///
/// # Errors
/// A measure the structure cannot take, a pool or count too small for the
/// identifiable parameters, a workspace with too few reachable poses.
pub fn plan_platform<M: ParallelModel>(
    model: &M,
    measure: PlatformMeasure,
    count: usize,
    pool: usize,
    seed: u64,
    criterion: &Criterion,
) -> Result<PlannedPoses, Error> {
    measure.check_for(model)?;
    let mut sampler = Sampler::new(seed);
    let poses = random_platform_poses(model, pool, PlatformWorkspace::of(model), &mut sampler)?;
    let exact = PlatformNoise {
        length: 0.0,
        angle: 0.0,
    };
    let candidates = simulate_platform(model, measure, &poses, exact, &mut sampler)?;
    let rank = rank_of(
        model,
        &platform_rows(
            model,
            &candidates,
            measure,
            None,
            &Auxiliary::none(),
            &mut Vec::new(),
        )?,
        measure,
    )?;
    // A distance's pairs are chosen whole: `count` poses are count/2 pairs.
    let taken = measure.samples_per_observation();
    if !count.is_multiple_of(taken) {
        return Err(Error::InvalidOption {
            setting: crate::Setting::Count,
            message: format!(
                "a distance is measured between two poses: {count} poses are not whole pairs"
            ),
        });
    }
    let per_observation = measure.rows_per_observation(model);
    let unknowns = rank.base.len();
    let observations = count / taken;
    if observations * per_observation < unknowns || count > pool {
        return Err(Error::TooFewEquations {
            equations: observations.min(pool / taken) * per_observation,
            unknowns,
        });
    }
    // Every candidate's rows on the base columns, scaled to unit column
    // norms over the pool (the criterion then weighs a millimetre of a
    // joint and a part per thousand of a gain alike).
    let mut blocks: Vec<DMatrix<f64>> = candidates
        .chunks_exact(taken)
        .map(|observation| {
            let mut starts = vec![model.home(); taken];
            observation_rows(
                model,
                observation,
                measure,
                None,
                (&Auxiliary::none(), 0),
                &mut starts,
            )
            .map(|(block, _)| block.select_columns(&rank.base))
        })
        .collect::<Result<_, _>>()?;
    let mut norms = vec![0.0f64; unknowns];
    for block in &blocks {
        for (j, norm) in norms.iter_mut().enumerate() {
            *norm += block.column(j).norm_squared();
        }
    }
    for block in &mut blocks {
        for (j, norm) in norms.iter().enumerate() {
            block
                .column_mut(j)
                .unscale_mut(norm.sqrt().max(f64::MIN_POSITIVE));
        }
    }
    let (chosen, criterion_value, random_criterion) = if *criterion == Criterion::D {
        let chosen = greedy_d_optimal(&blocks, observations)?;
        let criterion_of = |indices: &[usize]| {
            let mut gram = DMatrix::<f64>::zeros(unknowns, unknowns);
            for index in indices {
                gram += blocks[*index].transpose() * &blocks[*index];
            }
            gram.cholesky().map_or(f64::NEG_INFINITY, |factor| {
                2.0 * factor.l().diagonal().iter().map(|d| d.ln()).sum::<f64>()
            }) / (indices.len() * per_observation) as f64
        };
        let random: Vec<usize> = sampler.subset(blocks.len(), observations);
        (chosen.clone(), criterion_of(&chosen), criterion_of(&random))
    } else {
        let random: Vec<usize> = sampler.subset(blocks.len(), observations);
        let test_rows = if matches!(criterion, Criterion::TestPoses(_)) {
            test_rows(model, measure, &rank.base, &norms, &mut sampler)?
        } else {
            Vec::new()
        };
        let found = choose_units(blocks, observations, criterion, &test_rows, &random)?;
        (found.chosen, found.value, found.compared)
    };
    // Each chosen observation's poses and samples (a pair's two).
    let rows_of = |index: &usize| index * taken..(index + 1) * taken;
    Ok(PlannedPoses {
        poses: chosen
            .iter()
            .flat_map(|index| poses[rows_of(index)].to_vec())
            .collect(),
        samples: chosen
            .iter()
            .flat_map(|index| candidates[rows_of(index)].to_vec())
            .collect(),
        criterion_name: criterion.name(),
        criterion: criterion_value,
        random_criterion,
        rank,
    })
}

/// `observations` of `blocks` chosen greedily for D (module docs).
///
/// # Errors
/// A design whose normal equations lose positive definiteness, a pool
/// that runs out.
fn greedy_d_optimal(blocks: &[DMatrix<f64>], observations: usize) -> Result<Vec<usize>, Error> {
    let unknowns = blocks.first().map_or(0, DMatrix::ncols);
    // G starts as a small ridge, so that the first poses are compared by
    // what they add; it weighs nothing once the design determines G.
    let ridge = 1e-6 * blocks.len() as f64 / (observations as f64);
    let mut gram = DMatrix::<f64>::identity(unknowns, unknowns) * ridge;
    let mut chosen = Vec::with_capacity(observations);
    let mut used = vec![false; blocks.len()];
    for _ in 0..observations {
        let inverse = gram
            .clone()
            .cholesky()
            .ok_or_else(|| Error::Numerical {
                message: "the design's normal equations lost positive definiteness".into(),
            })?
            .inverse();
        let gain = |block: &DMatrix<f64>| {
            let inner = DMatrix::<f64>::identity(block.nrows(), block.nrows())
                + block * &inverse * block.transpose();
            inner.determinant().ln()
        };
        let best = (0..blocks.len())
            .filter(|index| !used[*index])
            .map(|index| (index, gain(&blocks[index])))
            .max_by(|a, b| a.1.total_cmp(&b.1))
            .map(|(index, _)| index)
            .ok_or_else(|| Error::Generation {
                message: "the pool ran out of poses".into(),
            })?;
        used[best] = true;
        gram += blocks[best].transpose() * &blocks[best];
        chosen.push(best);
    }
    Ok(chosen)
}

/// The rows of the error the verdict judges ([`ErrorRows`]) at
/// [`WORK_POSES`] random workspace poses, on the columns `base` scaled as
/// the pool's (each divided by the square root of its `norms` entry).
///
/// # Errors
/// A workspace with too few reachable poses, or a singular pose.
fn test_rows<M: ParallelModel>(
    model: &M,
    measure: PlatformMeasure,
    base: &[usize],
    norms: &[f64],
    sampler: &mut Sampler,
) -> Result<Vec<DMatrix<f64>>, Error> {
    let singular = || Error::Numerical {
        message: "the platform is singular at a test pose of the workspace".into(),
    };
    let errors = ErrorRows::new(model, measure).ok_or_else(singular)?;
    random_platform_poses(model, WORK_POSES, PlatformWorkspace::whole(model), sampler)?
        .iter()
        .map(|pose| {
            let actuators = model.actuator_values(pose)?;
            let mut rows = errors.at(pose, &actuators, base).ok_or_else(singular)?;
            for (j, norm) in norms.iter().enumerate() {
                rows.column_mut(j)
                    .unscale_mut(norm.sqrt().max(f64::MIN_POSITIVE));
            }
            Ok(rows)
        })
        .collect()
}
