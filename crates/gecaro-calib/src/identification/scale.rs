//! The scale that link and plane methods do not observe (Table 2 loses it).
//!
//! A point link constraint (eq. 11) holds for the robot scaled about the
//! world origin by any factor c: every length — d and r of every frame, the
//! gains and offsets of prismatic joints — times c moves every terminal
//! point P to cP, and the points of a set still coincide. So do frame link
//! (orientations do not change), plane link 2 (eq. 17) and an unknown plane
//! (its coefficients become a/c, b/c, c/c). A known plane keeps the scale
//! about one of its points, a scaling and a translation along its normal.
//! The paper's base set pins the free scale through a length it leaves out,
//! held at nominal: often a short one (the Stanford's `K3 − 37.4·r6 − 10·r7`),
//! so noise and the errors of that length alone set the size of the robot
//! (0.45× to 1.5× its size in simulation), and its residuals, in metres,
//! shrink with it.
//!
//! The scale kept instead is the most likely one: with ℓ_i the lengths and
//! prismatic gains of the base set at the solution, ℓ⁰_i their nominal
//! values and σ_i their prior σ (the prior's, regrouping included, or 1 cm
//! and 1 % per parameter without one), the factor
//! `c = Σ ℓ_i ℓ⁰_i/σ_i² / Σ ℓ_i²/σ_i²` brings them closest to nominal, and
//! the relative σ of the scale is `1/√(Σ ℓ_i²/σ_i²)`, over every length
//! and prismatic gain with an effect (scaling multiplies each). After each
//! pass on a base set, the robot scaled by c about the mean terminal point
//! of the data (a known plane passes through it) is fitted again on the
//! same base set: one iteration where the symmetry is exact, the lengths
//! left out of the base set staying at their scaled values (listed as
//! moved). So every pass is compared with the others at its most likely
//! scale: residuals in metres shrink with the robot, and an F test would
//! otherwise prefer a pass that shrank it.
//!
//! A base set leaves out a length that pins the scale; the steps over
//! every parameter (the score tests, the damped descent) hold it with a
//! gauge row instead ([`super::gauge`]): the residuals, in metres, shrink with the robot,
//! and such a step would otherwise take the direction that shrinks it,
//! whose column is the residuals themselves, for structure.
//!
//! The result is the robot's shape with the nominal robot's size; the
//! verdict calls it incomplete, never trusted, and says how well the size is
//! known ([`super::coverage::UnobservedScale`]).

use gecaro_core::{FrameType, ParameterId, ParameterKind, Robot};

use nalgebra::Vector3;

use super::coverage::UnobservedScale;
use super::gauge::scales;
use super::solver::{Iterate, Problem};
use super::weighting::second_pass_prior;
use crate::Error;
use crate::identifiability::{ParameterStatus, RankReport};
use crate::observation::ObservationSystem;
use crate::prior::Prior;
use crate::rows::{ColumnLayout, RowKind};
use crate::study::{Study, StudyStates};

/// The volume of the unit directions of r0, d1 and r1 below which they
/// cannot translate the robot (axis 1 within about 3° of the world z axis).
const TRANSLATION_CONDITION: f64 = 0.05;

/// Gauss–Newton steps that put the scaled robot's points back on a known
/// plane through the translations of its base.
const TRANSLATION_STEPS: usize = 4;

/// The relative excess of the data's sum of squares over the scaled one's
/// that a scaling may leave (a robust loss's residuals do not average to
/// zero, so the mean terminal point lies a little off a known plane).
const INVARIANCE: f64 = 1e-3;

/// A scale this close to 1 is kept as it is.
const NEGLIGIBLE: f64 = 1e-9;

/// `robot` scaled about the world origin by `factor`: d and r of every
/// frame, and the gains and offsets of prismatic joints, times `factor`.
///
/// # Errors
/// A factor that makes the robot invalid (not finite, zero).
fn scaled(robot: &Robot, factor: f64) -> Result<Robot, Error> {
    let mut spec = robot.to_spec();
    for frame in &mut spec.frames {
        frame.d *= factor;
        frame.r *= factor;
    }
    let prismatic: Vec<bool> = spec.frames[1..=spec.joints.len()]
        .iter()
        .map(|frame| frame.frame_type == FrameType::Prismatic)
        .collect();
    for (joint, prismatic) in spec.joints.iter_mut().zip(prismatic) {
        if prismatic {
            joint.gain *= factor;
            joint.offset *= factor;
        }
    }
    let mut scaled = Robot::new(spec)?;
    // Gravity's tilts are angles: a scale leaves them (not in a spec).
    for (axis, tilt) in robot.gravity_tilt().into_iter().enumerate() {
        let id = ParameterId::new(ParameterKind::GravityTilt, axis + 1);
        if scaled.parameters().contains(id) {
            scaled.set_parameter(id, tilt)?;
        }
    }
    Ok(scaled)
}

/// The most likely scale of `calibrated` (a robot like `nominal`) and its
/// relative σ (module docs): over every length and prismatic gain with an
/// effect on the data in the structural analysis `rank` (base set and
/// regrouped alike: scaling multiplies each), with the prior's σ of each;
/// `None` when none has a value.
///
/// Robustly: a length far from its nominal value in units of its σ — one
/// of a nearly singular pair (r2 = −1.5 m, r3 = +1.5 m on parallel axes),
/// or a base parameter carrying a combination of others — says nothing of
/// the robot's size. The factor starts at the weighted median of the
/// ratios `ℓ⁰_i/ℓ_i` (weights `ℓ⁰_i²/σ_i²`) and is refined by iteratively
/// reweighted least squares with Cauchy weights `1/(1 + (u_i/3)²)` of the
/// standardised deviations `u_i = (c ℓ_i − ℓ⁰_i)/σ_i`.
fn most_likely_scale(
    nominal: &Robot,
    calibrated: &Robot,
    rank: &RankReport,
    prior: &Prior,
) -> Option<(f64, f64)> {
    const CAUCHY: f64 = 3.0;
    const ROUNDS: usize = 20;
    // (value ℓ_i, nominal ℓ⁰_i, σ_i) of every length with an effect.
    let lengths: Vec<(f64, f64, f64)> = rank
        .parameters
        .iter()
        .filter(|classified| {
            matches!(
                classified.status,
                ParameterStatus::Identifiable | ParameterStatus::Regrouped
            )
        })
        .filter_map(|classified| classified.parameter)
        .filter(|id| scales(nominal, *id))
        .map(|id| {
            let reference = nominal.parameter(id);
            (
                calibrated.parameter(id),
                reference,
                prior.sigma(id, reference),
            )
        })
        .filter(|(value, reference, sigma)| {
            value.is_finite() && *sigma > 0.0 && (*value != 0.0 || *reference != 0.0)
        })
        .collect();
    // The weighted median of the ratios, over lengths of a nominal size.
    let mut ratios: Vec<(f64, f64)> = lengths
        .iter()
        .filter(|(value, reference, _)| *value != 0.0 && *reference != 0.0)
        .map(|(value, reference, sigma)| (reference / value, (reference / sigma).powi(2)))
        .filter(|(ratio, _)| *ratio > 0.0)
        .collect();
    if ratios.is_empty() {
        return None;
    }
    ratios.sort_by(|a, b| a.0.total_cmp(&b.0));
    let half = ratios.iter().map(|(_, weight)| weight).sum::<f64>() / 2.0;
    let mut cumulative = 0.0;
    let mut factor = ratios[ratios.len() - 1].0;
    for (ratio, weight) in &ratios {
        cumulative += weight;
        if cumulative >= half {
            factor = *ratio;
            break;
        }
    }
    let mut information = 0.0;
    for _ in 0..ROUNDS {
        let (mut cross, mut square) = (0.0, 0.0);
        for (value, reference, sigma) in &lengths {
            let standardised = (factor * value - reference) / sigma;
            let weight = 1.0 / (1.0 + (standardised / CAUCHY).powi(2));
            cross += weight * value * reference / (sigma * sigma);
            square += weight * value * value / (sigma * sigma);
        }
        if square <= 0.0 || cross <= 0.0 {
            return None;
        }
        let next = cross / square;
        information = square;
        let settled = (next - factor).abs() <= 1e-12 * factor;
        factor = next;
        if settled {
            break;
        }
    }
    Some((factor, 1.0 / (factor * information.sqrt())))
}

/// The mean terminal point of the data at `robot`: the centre the robot is
/// scaled about (a known plane passes through it, so its points stay on
/// it; the other methods are indifferent to the centre).
fn centre(robot: &Robot, study: &Study) -> Vector3<f64> {
    const POINTS: usize = 500;
    let samples: Vec<&[f64]> = study
        .sets
        .iter()
        .flat_map(|set| set.samples.iter())
        .map(|sample| sample.motor_positions())
        .collect();
    let points: Vec<Vector3<f64>> = crate::sampler::spread_indices(samples.len(), POINTS)
        .into_iter()
        .map(|index| samples[index])
        .filter_map(|motors| gecaro_core::terminal_pose(robot, motors).ok())
        .map(|pose| pose.translation.vector)
        .collect();
    if points.is_empty() {
        return Vector3::zeros();
    }
    points.iter().sum::<Vector3<f64>>() / points.len() as f64
}

/// `robot` translated by `shift` (world frame) through r0 (along the world
/// z axis), d1 (along x0, turned by β1) and r1 (along axis 1), which span
/// every direction unless axis 1 is parallel to the world z axis: its
/// frames 0 and 1 keep their angles, so nothing but these three lengths
/// changes. `None` when the three directions do not span the shift.
fn translated(robot: &Robot, shift: &Vector3<f64>) -> Result<Option<Robot>, Error> {
    use nalgebra::{Matrix3, Rotation3};
    let (zero, one) = (&robot.frames()[0], &robot.frames()[1]);
    let about_z = Rotation3::from_axis_angle(&Vector3::z_axis(), zero.theta);
    let about_y = about_z * Rotation3::from_axis_angle(&Vector3::y_axis(), one.beta);
    let x0 = about_y * Vector3::x();
    let z1 = about_y * Rotation3::from_axis_angle(&Vector3::x_axis(), one.alpha) * Vector3::z();
    let directions = Matrix3::from_columns(&[Vector3::z(), x0, z1]);
    // Nearly parallel, r0 and r1 would take metres of opposite signs.
    if directions.determinant().abs() < TRANSLATION_CONDITION {
        return Ok(None);
    }
    let Some(amounts) = directions.lu().solve(shift) else {
        return Ok(None);
    };
    let mut moved = robot.clone();
    let frame = |index: usize, kind: ParameterKind| ParameterId { frame: index, kind };
    for (id, amount) in [
        (frame(0, ParameterKind::R), amounts.x),
        (frame(1, ParameterKind::D), amounts.y),
        (frame(1, ParameterKind::R), amounts.z),
    ] {
        moved.set_parameter(id, robot.parameter(id) + amount)?;
    }
    Ok(Some(moved))
}

/// `robot` scaled by `factor` about `centre` (world frame): scaled about
/// the world origin, then translated by `(1 − factor)·centre`; about the
/// world origin when that translation cannot be made ([`translated`]).
fn scaled_about(robot: &Robot, factor: f64, centre: &Vector3<f64>) -> Result<Robot, Error> {
    let about_origin = scaled(robot, factor)?;
    Ok(translated(&about_origin, &((1.0 - factor) * centre))?.unwrap_or(about_origin))
}

/// The data rows' sums of squares of a system: of its length rows, and of
/// its angle rows.
fn data_costs(system: &ObservationSystem) -> (f64, f64) {
    let weighted = system.weighted_residuals();
    let (mut lengths, mut angles) = (0.0, 0.0);
    for (residual, kind) in weighted.iter().zip(system.kinds()) {
        match kind {
            RowKind::Length => lengths += residual * residual,
            RowKind::Angle => angles += residual * residual,
        }
    }
    (lengths, angles)
}

/// The solution of a pass moved to the most likely scale (module docs), for
/// a study that observes no length: the robot scaled by a factor c about
/// the mean terminal point of the data, where its length residuals are the
/// same times c (a known plane passes through that point, so its points
/// stay on it; an unknown plane through it is its own image; orientations
/// do not change), written with `problem`'s weighting. `reference` is the nominal robot (the
/// lengths' prior means), `rank` the structural analysis (which lengths
/// have an effect). A solution whose scale cannot be chosen (no length with
/// a nominal value) is left as it is, its scale's σ unknown (NaN). The
/// moved solution is `None` when it stays where it is.
///
/// # Errors
/// Only if the data cannot be evaluated at the scaled robot.
pub(super) fn rescaled(
    problem: &Problem<'_>,
    reference: &Robot,
    rank: &RankReport,
    best: &Iterate,
    states: &mut StudyStates,
) -> Result<(Option<Iterate>, UnobservedScale), Error> {
    let prior = problem
        .options
        .prior
        .clone()
        .unwrap_or_else(second_pass_prior);
    let Some((factor, std)) = most_likely_scale(reference, &best.robot, rank, &prior) else {
        return Ok((
            None,
            UnobservedScale {
                std: f64::NAN,
                base_set_scale: 1.0,
            },
        ));
    };
    let kept = UnobservedScale {
        std,
        base_set_scale: 1.0 / factor,
    };
    if (factor - 1.0).abs() <= NEGLIGIBLE {
        return Ok((None, kept));
    }
    let about = centre(&best.robot, problem.study);
    let robot = scaled_about(&best.robot, factor, &about)?;
    let mut moved = problem.assemble(&robot, &best.auxiliary, &problem.layout, states)?;
    // The scaling must leave the fit as good as it was, the length
    // residuals times the factor. About the world origin (when the robot
    // cannot be translated through r0, d1 and r1) it may not, for a known
    // plane that misses the origin: the translation of the base along r0 or
    // d1 that puts the points back on the plane is then fitted.
    // (The solution written again with `problem`'s weighting: a robust
    // loss's last weights may postdate its system.)
    let again = problem.assemble(&best.robot, &best.auxiliary, &problem.layout, states)?;
    let (lengths, angles) = data_costs(&again.system);
    let expected = factor * factor * lengths + angles;
    let invariant = |system: &ObservationSystem| {
        let (lengths, angles) = data_costs(system);
        lengths + angles <= expected * (1.0 + INVARIANCE) + 1e-24
    };
    if !invariant(&moved.system) {
        let back = translated_back(problem, &moved, states)?;
        let total = |system: &ObservationSystem| {
            let (lengths, angles) = data_costs(system);
            lengths + angles
        };
        if total(&back.system) < total(&moved.system) {
            moved = back;
        }
    }
    if !invariant(&moved.system) {
        return Ok((
            None,
            UnobservedScale {
                std,
                base_set_scale: 1.0,
            },
        ));
    }
    Ok((Some(moved), kept))
}

/// `moved` with the base translated along r0 or d1 (world z, x0) to
/// minimise its data rows' residuals, by a few Gauss–Newton steps on the one
/// of the two with the larger effect (a known plane's points move alike
/// along its normal: one translation takes them back), and written again in
/// `problem`'s layout.
///
/// # Errors
/// Only if the data cannot be evaluated on the way.
fn translated_back(
    problem: &Problem<'_>,
    moved: &Iterate,
    states: &mut StudyStates,
) -> Result<Iterate, Error> {
    let robot = &moved.robot;
    let translations: Vec<usize> = [(0, ParameterKind::R), (1, ParameterKind::D)]
        .into_iter()
        .filter_map(|(frame, kind)| robot.parameters().index_of(ParameterId { frame, kind }))
        .collect();
    let layout = ColumnLayout::with_auxiliary(
        robot.parameters().len(),
        &translations,
        moved.auxiliary.len(),
        &[],
    );
    // The data rows alone (a prior's rows are written for other columns).
    let plain = problem.with_weighting(super::weighting::Weighting::default());
    let (mut robot, auxiliary) = (moved.robot.clone(), moved.auxiliary.clone());
    for _ in 0..TRANSLATION_STEPS {
        // Written whole (two columns): the columns are read one by one.
        let mut system = ObservationSystem::default();
        plain
            .study
            .linearise(&robot, &auxiliary, &layout, states, &mut system)?;
        let rows = system.measured_rows();
        let right = system.weighted_residuals();
        let columns: Vec<Vec<f64>> = (0..layout.columns()).map(|c| system.column(c)).collect();
        let norm = |column: &[f64]| column[..rows].iter().map(|v| v * v).sum::<f64>();
        let Some((position, column)) = columns
            .iter()
            .enumerate()
            .max_by(|a, b| norm(a.1).total_cmp(&norm(b.1)))
        else {
            break;
        };
        let square = norm(column);
        if square <= 0.0 {
            break;
        }
        let step = (0..rows).map(|row| column[row] * right[row]).sum::<f64>() / square;
        let mut deltas = vec![0.0; robot.parameters().len()];
        deltas[translations[position]] = step;
        robot.apply_deltas(&deltas)?;
    }
    problem.assemble(&robot, &auxiliary, &problem.layout, states)
}
