//! The "Plan" function of a method menu: the configurations to measure,
//! chosen from a generated pool, and how many are enough (docs/planning.md).

use axum::extract::State;
use gecaro_calib::{
    curve::accuracy_curve,
    planning::{CandidatePool, Criterion, PlanRequest as Request},
    prediction::random_test_poses,
    simulation::Sampler,
};
use gecaro_io::{RobotDocument, format_samples};
use gecaro_report::json::{CurvePointJson, PlanJson};
use serde::{Deserialize, Serialize};

use super::{Json, MethodRequest, data_file_name, robot_file, save_csv};
use crate::error::ApiError;
use crate::limits::{MAX_CURVE_POINTS, MAX_GENERATE};
use crate::state::AppState;

/// Random test poses for the test criterion and the curve.
const TEST_POSES: usize = 200;

/// A design criterion, as `gecaro plan --criterion` names it.
#[derive(Copy, Clone, Debug, Default, Deserialize)]
#[serde(rename_all = "lowercase")]
pub(crate) enum CriterionChoice {
    #[default]
    D,
    A,
    E,
    O4,
    O5,
    Test,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct PlanRequest {
    robot: RobotDocument,
    method: MethodRequest,
    /// Configurations to choose (rows of the data file).
    count: usize,
    #[serde(default)]
    criterion: CriterionChoice,
    /// Candidates generated (default 20 × count).
    #[serde(default)]
    pool: Option<usize>,
    /// Smallest joint-space distance between chosen configurations.
    #[serde(default)]
    min_distance: f64,
    #[serde(default = "default_seed")]
    seed: u64,
    /// Counts of the accuracy curve (none: no curve).
    #[serde(default)]
    curve: Vec<usize>,
    /// The sensor's σ for the curve (metres).
    #[serde(default = "default_noise")]
    noise: f64,
    /// Also save the plan to this file of the folder.
    #[serde(default)]
    save_as: Option<String>,
    #[serde(default)]
    overwrite: bool,
}

fn default_seed() -> u64 {
    1
}

fn default_noise() -> f64 {
    1e-4
}

#[derive(Serialize)]
pub(crate) struct CurveJson {
    noise: f64,
    points: Vec<CurvePointJson>,
    /// The curve as an SVG plot.
    svg: String,
}

#[derive(Serialize)]
pub(crate) struct Planned {
    #[serde(flatten)]
    plan: PlanJson,
    /// The planned data file (configurations, set or pair ids).
    csv: String,
    file_name: String,
    #[serde(skip_serializing_if = "Option::is_none")]
    saved: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    curve: Option<CurveJson>,
}

/// Plans the configurations of a method, and optionally the accuracy curve.
pub(crate) async fn plan(
    State(state): State<AppState>,
    Json(request): Json<PlanRequest>,
) -> Result<Json<Planned>, ApiError> {
    let file = robot_file(&request.robot)?;
    let method = request.method.build()?;
    let largest = request
        .curve
        .iter()
        .copied()
        .chain([request.count])
        .max()
        .unwrap_or(0);
    let pool_size = request.pool.unwrap_or(20 * largest);
    if !(1..=MAX_GENERATE).contains(&pool_size) || request.count == 0 {
        return Err(ApiError::BadRequest(format!(
            "count {} and pool {pool_size}: at least one configuration, a pool of up to \
             {MAX_GENERATE}",
            request.count
        )));
    }
    if request.curve.len() > MAX_CURVE_POINTS || request.curve.contains(&0) {
        return Err(ApiError::BadRequest(format!(
            "curve: up to {MAX_CURVE_POINTS} positive counts"
        )));
    }
    if !(request.noise > 0.0 && request.noise.is_finite()) {
        return Err(ApiError::BadRequest(format!(
            "noise {}: a standard deviation > 0 (metres)",
            request.noise
        )));
    }
    state
        .compute(move |state| {
            let robot = &file.robot;
            let pool =
                method
                    .sensor()
                    .generate(robot, pool_size, 0.0, &mut Sampler::new(request.seed))?;
            let poses = random_test_poses(robot, TEST_POSES, request.seed);
            let criterion = match request.criterion {
                CriterionChoice::D => Criterion::D,
                CriterionChoice::A => Criterion::A,
                CriterionChoice::E => Criterion::E,
                CriterionChoice::O4 => Criterion::O4,
                CriterionChoice::O5 => Criterion::O5,
                CriterionChoice::Test => Criterion::TestPoses(poses.clone()),
            };
            let plan_request = Request {
                criterion,
                min_distance: request.min_distance,
                ..Request::new(request.count)
            };
            let pool = CandidatePool::new(robot, method.as_ref(), &pool, &robot.priority())?;
            let planned = pool.plan(&plan_request, &mut gecaro_calib::Quiet)?;
            let random =
                pool.random_design(&[], planned.chosen.len(), &mut Sampler::new(request.seed));
            let random_quality = pool.assess(&random, &plan_request.criterion)?;
            let curve = if request.curve.is_empty() {
                None
            } else {
                let points = accuracy_curve(
                    &pool,
                    &request.curve,
                    &plan_request,
                    request.noise,
                    &poses,
                    request.seed,
                    &mut gecaro_calib::Quiet,
                )?;
                Some(CurveJson {
                    noise: request.noise,
                    svg: gecaro_report::accuracy_curve_svg(&points)?,
                    points: points.iter().map(CurvePointJson::from).collect(),
                })
            };
            let columns = gecaro_calib::study::DataColumn::grouping(method.data_columns());
            let csv = format_samples(robot.joint_count(), &columns, &planned.samples);
            // Saved last: a failed request leaves no file.
            let saved = save_csv(state, request.save_as.as_deref(), &csv, request.overwrite)?;
            Ok(Json(Planned {
                plan: PlanJson::new(
                    method.name(),
                    &plan_request.criterion,
                    &planned,
                    &random_quality,
                    pool.len(),
                    0,
                ),
                file_name: data_file_name(
                    robot,
                    &format!("{}-planned", request.method.name),
                    planned.samples.len(),
                ),
                csv,
                saved,
                curve,
            }))
        })
        .await
}
