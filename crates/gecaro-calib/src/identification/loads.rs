//! An elastic robot's loads follow each pass
//! ([`IdentificationOptions::masses`](super::IdentificationOptions::masses)).
//!
//! The samples' torques come evaluated at the nominal robot, whose geometry
//! is off by centimetres and a degree: that moves them by a few per cent,
//! tens of micrometres of deflection at the flange. After a pass's descent
//! (and its reweighted phase), the loads are evaluated at its solution; when
//! they move the modelled tool point by more than a tenth of the noise
//! ([`crate::elastic::reweighed`]), the descent continues from the solution
//! with them, on the same columns, weights and prior rows: a few
//! Gauss–Newton iterations. The Jacobian leaves out `c_j·∂τ_j/∂η`, a
//! thousandth of the joint's own column: the loads are a fixed point the
//! identification reaches, not part of its linearised model.
//!
//! A pass is compared with the one before it (the F tests of the second
//! pass and the damped descent) with the loads both were given, before
//! this pass followed them.

use super::reweighting::Reweighted;
use super::solver::{Damping, Problem};
use super::statistics::ResidualStatistics;
use super::verdict::StopReason;
use crate::Error;
use crate::progress::Quiet;
use crate::study::{Study, StudyStates};

/// Most rounds of loads followed in a pass: each moves the torques by about
/// c·∂τ/∂q ≈ 1e-3 of the round before, so one suffices in practice.
const LOAD_ROUNDS: usize = 3;

/// Iterations allowed to each round's descent.
const ROUND_ITERATIONS: usize = 10;

/// The pass's `reweighted` solution with an elastic robot's loads followed
/// (see the module docs), and the study with the loads it ended with when
/// they moved (`None`: the pass's own, or a rigid robot, or no masses).
///
/// # Errors
/// A configuration that does not fit the solution's robot, an invalid
/// payload, numerical failures of the descent.
pub(super) fn follow_the_loads(
    problem: &Problem<'_>,
    mut reweighted: Reweighted,
    states: &mut StudyStates,
) -> Result<(Reweighted, Option<Study>), Error> {
    let masses = match &problem.options.masses {
        Some(masses) if problem.nominal.is_elastic() => masses,
        _ => return Ok((reweighted, None)),
    };
    if reweighted.run.stop != StopReason::Converged {
        return Ok((reweighted, None));
    }
    // The pass's final weights and prior rows.
    let weighted = problem.with_weighting(reweighted.weighting.clone());
    let mut loaded: Option<Study> = None;
    for _ in 0..LOAD_ROUNDS {
        let best = &reweighted.run.best;
        let study = loaded.as_ref().unwrap_or(problem.study);
        let Some(next) = crate::elastic::reweighed(study, &best.robot, masses)? else {
            break;
        };
        let round = weighted.with_study(&next);
        let start = round.assemble(&best.robot, &best.auxiliary, &round.layout, states)?;
        let run = round.descend(
            start,
            Damping::WhenNeeded,
            ROUND_ITERATIONS,
            states,
            &mut Quiet,
        )?;
        if run.stop != StopReason::Converged {
            break;
        }
        reweighted.statistics = ResidualStatistics::of(
            &run.best.system,
            &problem.options.loss,
            next.equation_count(),
            round.layout.columns(),
        );
        reweighted.run.history.extend(run.history);
        reweighted.run.best = run.best;
        loaded = Some(next);
    }
    Ok((reweighted, loaded))
}
