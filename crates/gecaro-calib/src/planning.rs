//! Choosing the configurations to measure before measuring: a D-optimal
//! subset of a candidate pool.
//!
//! The pool is cut into *units*, what a measurement session takes whole: a
//! configuration (position, frame and plane methods), a set (point and frame
//! link) or a pair (distance). Unit u contributes the rows X_u of the base
//! columns W_b at the nominal robot (Appendix III), its columns scaled by the
//! error units as for the observability indices ([`crate::Observability`]),
//! and so the information X_uᵀX_u. A design S is judged by
//! D(S) = log det Σ_{u∈S} X_uᵀX_u, the D-criterion (maximising it shrinks the
//! volume of the parameters' confidence ellipsoid; O1 is exp(D/2L)/√m).
//!
//! Units with a configuration outside the joint limits are never chosen.
//! The design is built by a deterministic greedy pass (each step adds the unit
//! with the largest det(I + X_u M⁻¹ X_uᵀ), M the current information plus a
//! ridge of 1e-9 of its mean diagonal), then improved by Mitchell's DETMAX
//! exchange: add the best unit, remove the one whose removal costs least,
//! until the unit removed is the one just added. M⁻¹ and every candidate's
//! G_u = X_u M⁻¹ X_uᵀ are kept up to date by rank-r updates (Woodbury), so a
//! step costs O(K·r²·L) for K candidates — no refactorisation per trial; they
//! are recomputed from scratch every [`REFRESH`] steps against drift.

use std::ops::{ControlFlow, Range};

use gecaro_core::{PriorityMatrix, Robot};
use nalgebra::DMatrix;

use crate::Error;
use crate::identifiability::structural_parameters;
use crate::methods::{CalibrationMethod, groups};
use crate::observability::{AUXILIARY_UNIT, Observability, column_unit};
use crate::observation::{ColumnLayout, ObservationSystem};
use crate::sample::{DataColumn, Sample};
use crate::study::{Study, StudyStates};

/// Steps between two recomputations of M⁻¹ and the G_u from scratch.
const REFRESH: usize = 32;

/// A chosen design.
#[derive(Clone, Debug)]
pub struct Plan {
    /// The chosen configurations, kept ones first, then the chosen units
    /// (whole sets and pairs) in the order of [`units`] of the pool.
    pub samples: Vec<Sample>,
    /// The chosen units: indices into [`units`] of the pool, ascending.
    pub chosen: Vec<usize>,
    /// D(S) = log det of the information of the design (scaled W_b).
    pub log_det: f64,
    /// The observability indices of the design's scaled W_b.
    pub observability: Observability,
    /// Exchanges made by DETMAX after the greedy pass.
    pub exchanges: usize,
    /// Names of the base parameters (columns), auxiliary unknowns first.
    pub columns: Vec<String>,
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

/// `samples` reordered unit by unit, and each unit's range in the result:
/// the rows of W then come unit by unit too.
fn contiguous(samples: &[Sample], units: &[Vec<usize>]) -> (Vec<Sample>, Vec<Range<usize>>) {
    let mut ordered = Vec::with_capacity(samples.len());
    let ranges = units
        .iter()
        .map(|unit| {
            let start = ordered.len();
            ordered.extend(unit.iter().map(|index| samples[*index].clone()));
            start..ordered.len()
        })
        .collect();
    (ordered, ranges)
}

/// The scaled rows of W_b of every unit, one matrix per unit.
struct Blocks {
    units: Vec<DMatrix<f64>>,
    width: usize,
}

impl Blocks {
    fn of(&self, unit: usize) -> &DMatrix<f64> {
        &self.units[unit]
    }
}

/// The base columns of a set of configurations: the structural base set
/// (Appendix III, on random data like them), its layout, and each column's
/// name and error unit (auxiliary unknowns first).
pub(crate) struct BaseColumns {
    pub(crate) layout: ColumnLayout,
    /// Vocabulary indices of the base robot parameters, in column order.
    pub(crate) parameters: Vec<usize>,
    /// Number of base auxiliary unknowns (the first columns).
    pub(crate) auxiliary: usize,
    pub(crate) names: Vec<String>,
    scale: Vec<f64>,
}

impl BaseColumns {
    pub(crate) fn of(
        robot: &Robot,
        method: &dyn CalibrationMethod,
        samples: &[Sample],
        priority: &PriorityMatrix,
    ) -> Result<Self, Error> {
        let study = Study::single(method.clone_method(), samples.to_vec(), "candidates");
        let report = structural_parameters(robot, &study, priority, 1)?;
        let layout = ColumnLayout::with_auxiliary(
            robot.parameters().len(),
            &report.base_parameters,
            method.auxiliary_names().len(),
            &report.base_auxiliary,
        );
        let scale = report
            .base_auxiliary
            .iter()
            .map(|_| AUXILIARY_UNIT)
            .chain(report.base_parameters.iter().map(|index| {
                let id = robot.parameters().id(*index);
                column_unit(id.kind, robot.parameter(id))
            }))
            .collect();
        let names = report
            .base_auxiliary
            .iter()
            .map(|index| report.auxiliary[*index].name.clone())
            .chain(
                report
                    .base_parameters
                    .iter()
                    .map(|index| report.parameters[*index].name.clone()),
            )
            .collect();
        Ok(BaseColumns {
            layout,
            auxiliary: report.base_auxiliary.len(),
            parameters: report.base_parameters,
            names,
            scale,
        })
    }

    /// W_b of `samples` at the nominal robot (parameter units, rows as eq. 10).
    pub(crate) fn system(
        &self,
        robot: &Robot,
        method: &dyn CalibrationMethod,
        samples: &[Sample],
    ) -> Result<ObservationSystem, Error> {
        let study = Study::single(method.clone_method(), samples.to_vec(), "candidates");
        let mut states = StudyStates::default();
        study.evaluate_poses(robot, &mut states)?;
        let auxiliary = study.initial_auxiliary(&states)?;
        let mut system = ObservationSystem::default();
        study.linearise(robot, &auxiliary, &self.layout, &mut states, &mut system)?;
        Ok(system)
    }

    /// The scaled W_b of `samples`, whose units are the contiguous `ranges`,
    /// one block per unit.
    fn blocks(
        &self,
        robot: &Robot,
        method: &dyn CalibrationMethod,
        samples: &[Sample],
        ranges: &[Range<usize>],
    ) -> Result<Blocks, Error> {
        let system = self.system(robot, method, samples)?;
        let width = self.layout.columns();
        let mut blocks = Vec::with_capacity(ranges.len());
        let mut start = 0;
        for range in ranges {
            let count = method.row_count(&samples[range.clone()]);
            if start + count > system.rows() {
                break;
            }
            let rows = &system.matrix()[start * width..(start + count) * width];
            blocks.push(DMatrix::from_fn(count, width, |row, column| {
                rows[row * width + column] * self.scale[column]
            }));
            start += count;
        }
        if start != system.rows() || blocks.len() != ranges.len() {
            return Err(Error::Numerical {
                message: format!(
                    "planning: the units give {start} rows, W has {}",
                    system.rows()
                ),
            });
        }
        Ok(Blocks {
            units: blocks,
            width,
        })
    }
}

/// The exchange state: M⁻¹, and G_u = X_u M⁻¹ X_uᵀ of every candidate.
struct Exchange<'a> {
    candidates: &'a Blocks,
    inverse: DMatrix<f64>,
    gram: Vec<DMatrix<f64>>,
    chosen: Vec<bool>,
    /// Information of the kept units plus the ridge, the base of every refresh.
    base: DMatrix<f64>,
}

impl Exchange<'_> {
    /// Recomputes M⁻¹ and every G_u from the chosen units.
    fn refresh(&mut self) -> Result<(), Error> {
        let mut information = self.base.clone();
        for (unit, chosen) in self.chosen.iter().enumerate() {
            if *chosen {
                let block = self.candidates.of(unit);
                information += block.transpose() * block;
            }
        }
        self.inverse = information
            .cholesky()
            .ok_or_else(|| Error::Numerical {
                message: "planning: the information matrix is not positive definite".into(),
            })?
            .inverse();
        for (unit, gram) in self.gram.iter_mut().enumerate() {
            let block = self.candidates.of(unit);
            *gram = block * &self.inverse * block.transpose();
        }
        Ok(())
    }

    /// det(I ± G_u): the factor by which adding (+) or removing (−) unit u
    /// multiplies det M.
    fn factor(&self, unit: usize, sign: f64) -> f64 {
        let gram = &self.gram[unit];
        (DMatrix::identity(gram.nrows(), gram.ncols()) + gram * sign).determinant()
    }

    /// Adds (sign +1) or removes (−1) unit `s`: a rank-r update of M⁻¹ and
    /// of every G_u.
    fn update(&mut self, s: usize, sign: f64) -> Result<(), Error> {
        let block = self.candidates.of(s);
        let u = &self.inverse * block.transpose();
        let core = DMatrix::identity(block.nrows(), block.nrows()) + (block * &u) * sign;
        let core_inverse = core.try_inverse().ok_or_else(|| Error::Numerical {
            message: "planning: a singular exchange step".into(),
        })?;
        self.inverse -= &u * &core_inverse * u.transpose() * sign;
        for (unit, gram) in self.gram.iter_mut().enumerate() {
            let v = self.candidates.of(unit) * &u;
            *gram -= &v * &core_inverse * v.transpose() * sign;
        }
        self.chosen[s] = sign > 0.0;
        Ok(())
    }

    /// The unit whose addition raises det M most (among the admissible ones
    /// not chosen), with that factor.
    fn best_addition(&self, admissible: &[bool]) -> Option<(usize, f64)> {
        self.best(|u| admissible[u] && !self.chosen[u], 1.0)
    }

    /// The chosen unit whose removal lowers det M least, with that factor.
    fn best_removal(&self) -> Option<(usize, f64)> {
        self.best(|u| self.chosen[u], -1.0)
    }

    /// The eligible unit with the largest det(I ± G_u), and that value.
    fn best(&self, eligible: impl Fn(usize) -> bool, sign: f64) -> Option<(usize, f64)> {
        let mut best: Option<(usize, f64)> = None;
        for unit in (0..self.gram.len()).filter(|u| eligible(*u)) {
            let value = self.factor(unit, sign);
            if value.is_finite() && best.is_none_or(|(_, b)| value > b) {
                best = Some((unit, value));
            }
        }
        best
    }
}

/// Chooses about `count` configurations from `pool` for `method` on `robot`
/// (whole units; `kept` are measured already and always part of the design),
/// maximising the D-criterion (see the module docs). `progress(done, total)`
/// reports the greedy and exchange steps and stops the work with
/// [`Error::Interrupted`] on [`ControlFlow::Break`].
///
/// # Errors
/// Invalid samples, a pool with fewer configurations than asked, too few
/// equations for the base set, or [`Error::Interrupted`].
pub fn plan_d_optimal(
    robot: &Robot,
    method: &dyn CalibrationMethod,
    pool: &[Sample],
    count: usize,
    kept: &[Sample],
    priority: &PriorityMatrix,
    mut progress: impl FnMut(usize, usize) -> ControlFlow<()>,
) -> Result<Plan, Error> {
    let (pool, pool_units) = contiguous(pool, &units(method, pool));
    let (kept_ordered, kept_units) = contiguous(kept, &units(method, kept));
    // Only units whose every configuration is within the joint limits.
    let admissible: Vec<bool> = pool_units
        .iter()
        .map(|unit| {
            pool[unit.clone()].iter().all(|sample| {
                robot
                    .joint_positions(&sample.motor_positions)
                    .is_ok_and(|q| robot.within_limits(q.as_slice()))
            })
        })
        .collect();
    let admissible_count = admissible.iter().filter(|a| **a).count();
    let unit_size = pool.len().max(1) as f64 / pool_units.len().max(1) as f64;
    let wanted = ((count.saturating_sub(kept.len())) as f64 / unit_size).round() as usize;
    if wanted > admissible_count {
        return Err(Error::InvalidOption {
            option: "--count",
            message: format!(
                "{count} configurations asked; the pool has {} ({admissible_count} of its {} units within the joint limits)",
                pool.len(),
                pool_units.len()
            ),
        });
    }
    let base_columns = BaseColumns::of(robot, method, &pool, priority)?;
    let width = base_columns.layout.columns();
    let candidates = base_columns.blocks(robot, method, &pool, &pool_units)?;
    let mut base = DMatrix::<f64>::zeros(width, width);
    if !kept.is_empty() {
        let kept_blocks = base_columns.blocks(robot, method, &kept_ordered, &kept_units)?;
        for unit in 0..kept_units.len() {
            let block = kept_blocks.of(unit);
            base += block.transpose() * block;
        }
    }
    // The ridge: 1e-9 of the mean diagonal of a unit's information.
    let mut diagonal = 0.0;
    for unit in 0..pool_units.len() {
        let block = candidates.of(unit);
        diagonal += block.iter().map(|v| v * v).sum::<f64>();
    }
    let ridge = 1e-9 * diagonal / (pool_units.len().max(1) * width.max(1)) as f64;
    base += DMatrix::<f64>::identity(width, width) * ridge.max(f64::MIN_POSITIVE);
    let mut exchange = Exchange {
        candidates: &candidates,
        inverse: DMatrix::zeros(width, width),
        gram: vec![DMatrix::zeros(0, 0); pool_units.len()],
        chosen: vec![false; pool_units.len()],
        base,
    };
    exchange.refresh()?;
    let total = 3 * wanted.max(1);
    let mut steps = 0;
    let mut step = |exchange: &mut Exchange<'_>| -> Result<(), Error> {
        steps += 1;
        if steps % REFRESH == 0 {
            exchange.refresh()?;
        }
        match progress(steps.min(total), total) {
            ControlFlow::Continue(()) => Ok(()),
            ControlFlow::Break(()) => Err(Error::Interrupted),
        }
    };
    // Greedy pass.
    for _ in 0..wanted {
        let Some((unit, _)) = exchange.best_addition(&admissible) else {
            break;
        };
        exchange.update(unit, 1.0)?;
        step(&mut exchange)?;
    }
    // DETMAX exchange, from exact M⁻¹ and G_u (the greedy pass starts from
    // the ridge alone, where the updates lose the most digits).
    exchange.refresh()?;
    let mut exchanges = 0;
    for _ in 0..20 * wanted.max(1) {
        let Some((added, gain)) = exchange.best_addition(&admissible) else {
            break;
        };
        exchange.update(added, 1.0)?;
        let (removed, loss) = exchange.best_removal().unwrap_or((added, 1.0 / gain));
        exchange.update(removed, -1.0)?;
        step(&mut exchange)?;
        if removed == added || gain * loss <= 1.0 + 1e-10 {
            if removed != added {
                // No real improvement: undo the swap.
                exchange.update(added, -1.0)?;
                exchange.update(removed, 1.0)?;
            }
            break;
        }
        exchanges += 1;
    }
    let chosen: Vec<usize> = (0..pool_units.len())
        .filter(|u| exchange.chosen[*u])
        .collect();
    let mut samples = kept.to_vec();
    for unit in &chosen {
        samples.extend_from_slice(&pool[pool_units[*unit].clone()]);
    }
    let (log_det, observability) = design_quality(
        &candidates,
        &chosen,
        exchange.base.clone(),
        ridge,
        samples.len(),
    )?;
    Ok(Plan {
        samples,
        chosen,
        log_det,
        observability,
        exchanges,
        columns: base_columns.names,
    })
}

/// D(S) and the observability indices of the design (the ridge removed).
fn design_quality(
    candidates: &Blocks,
    chosen: &[usize],
    base: DMatrix<f64>,
    ridge: f64,
    configurations: usize,
) -> Result<(f64, Observability), Error> {
    let width = candidates.width;
    let mut information = base - DMatrix::<f64>::identity(width, width) * ridge;
    for unit in chosen {
        let block = candidates.of(*unit);
        information += block.transpose() * block;
    }
    let eigenvalues = information.symmetric_eigenvalues();
    let values: Vec<f64> = eigenvalues.iter().map(|v| v.max(0.0).sqrt()).collect();
    let log_det = eigenvalues.iter().map(|v| v.max(0.0).ln()).sum();
    Ok((
        log_det,
        Observability::from_singular_values(&values, configurations),
    ))
}

/// D = log det Σ X_uᵀX_u of any set of samples (whole units), in the scaled
/// base columns that [`plan_d_optimal`] uses for the same pool: for comparing
/// designs (random subsets, a plan, measured data).
///
/// # Errors
/// As [`plan_d_optimal`].
pub fn design_log_det(
    robot: &Robot,
    method: &dyn CalibrationMethod,
    pool: &[Sample],
    design: &[Sample],
    priority: &PriorityMatrix,
) -> Result<f64, Error> {
    let base_columns = BaseColumns::of(robot, method, pool, priority)?;
    let (design, design_units) = contiguous(design, &units(method, design));
    let blocks = base_columns.blocks(robot, method, &design, &design_units)?;
    let all: Vec<usize> = (0..design_units.len()).collect();
    let width = base_columns.layout.columns();
    design_quality(
        &blocks,
        &all,
        DMatrix::zeros(width, width),
        0.0,
        design.len(),
    )
    .map(|(log_det, _)| log_det)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Sampler;

    /// The rank-r updates of M⁻¹ and of every G_u equal a recomputation.
    #[test]
    fn woodbury_updates_equal_a_refresh() {
        let mut sampler = Sampler::new(5);
        let candidates = Blocks {
            units: (0..12)
                .map(|_| DMatrix::from_fn(3, 5, |_, _| sampler.uniform(-1.0, 1.0)))
                .collect(),
            width: 5,
        };
        let mut exchange = Exchange {
            candidates: &candidates,
            inverse: DMatrix::zeros(5, 5),
            gram: vec![DMatrix::zeros(0, 0); 12],
            chosen: vec![false; 12],
            base: DMatrix::identity(5, 5) * 0.1,
        };
        exchange.refresh().expect("positive definite");
        for (unit, sign) in [
            (0, 1.0),
            (3, 1.0),
            (7, 1.0),
            (3, -1.0),
            (11, 1.0),
            (0, -1.0),
        ] {
            exchange.update(unit, sign).expect("update");
        }
        let (inverse, gram) = (exchange.inverse.clone(), exchange.gram.clone());
        exchange.refresh().expect("positive definite");
        assert!((&inverse - &exchange.inverse).abs().max() < 1e-12 * exchange.inverse.abs().max());
        for (updated, fresh) in gram.iter().zip(&exchange.gram) {
            assert!((updated - fresh).abs().max() < 1e-12 * fresh.abs().max().max(1.0));
        }
        assert_eq!(
            exchange.chosen,
            [
                false, false, false, false, false, false, false, true, false, false, false, true
            ]
        );
    }
}
