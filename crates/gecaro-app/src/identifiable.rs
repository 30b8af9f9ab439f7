//! The "Identifiable parameters" function (paper §4, Appendix III) as a job:
//! on random configurations of a method, or on measured data with the
//! excitation check.

use gecaro_calib::Observer;
use gecaro_calib::identifiability::{Identifiability, identifiability};
use gecaro_calib::validation::Model;
use serde::Deserialize;

use crate::documents::IdentifiableJson;
use crate::error::AppError;
use crate::files::Files;
use crate::limits::MAX_RANDOM;
use crate::loads::TYPICAL_COMPLIANCE;
use crate::measurements::{Data, Loaded, Measurements, Unknown};
use crate::settings::PrioritySource;

/// Which parameters a method can identify.
#[derive(Clone, Debug, Default, Deserialize)]
pub struct IdentifiableRequest {
    /// The robot and method, with or without data.
    #[serde(flatten)]
    pub measurements: Measurements,
    /// The priority matrix; default the study file's, else the robot's.
    pub priority: Option<PrioritySource>,
    /// Random configurations when there are no data (default: about 2.5
    /// equations per unknown, at most [`MAX_RANDOM`]).
    pub count: Option<usize>,
    /// Seed of the random configurations (default 1).
    pub seed: Option<u64>,
    /// Which parameters are candidates: a model as `identify --model` takes
    /// it, restricting the priority matrix; `"elastic"` adds every joint's
    /// compliance after the geometry, on the data's loads (docs/elastic.md).
    /// None: the priority matrix as it is.
    pub model: Option<String>,
    #[serde(flatten)]
    unknown: Unknown,
}

/// The identifiable parameters of a study.
#[derive(Clone, Debug)]
pub struct IdentifiabilityAnalysis {
    /// The robot, study and notes.
    pub loaded: Loaded,
    /// The library's analysis.
    pub analysis: Identifiability,
}

impl IdentifiableRequest {
    /// A request on `measurements`.
    pub fn new(measurements: Measurements) -> Self {
        IdentifiableRequest {
            measurements,
            ..IdentifiableRequest::default()
        }
    }

    /// Runs the analysis; `observer` hears of the random configurations
    /// drawn and may stop the work.
    ///
    /// # Errors
    /// Bad input or settings, configurations that cannot be generated, too
    /// few equations, an interruption.
    pub fn run(
        &self,
        files: &dyn Files,
        observer: &mut dyn Observer,
    ) -> Result<IdentifiabilityAnalysis, AppError> {
        self.unknown.check()?;
        if let Some(count) = self.count
            && !(1..=MAX_RANDOM).contains(&count)
        {
            return Err(AppError::setting_value(
                "count",
                count,
                format!("between 1 and {MAX_RANDOM} random configurations"),
            ));
        }
        let mut loaded = self.measurements.load(files, Data::Optional)?;
        let model = loaded
            .model(self.model.as_deref())
            .map(|name| crate::settings::model(name, &loaded.robot.robot, files))
            .transpose()?;
        if model.as_ref().is_some_and(Model::is_elastic) {
            // Random configurations carry no loads: the data's are what
            // tells a compliance from the geometry.
            if loaded.study.sets.iter().any(|set| set.samples.is_empty()) {
                return Err(AppError::setting(
                    "model",
                    "the elastic model's identifiable parameters are analysed on measured (or \
                     planned) configurations and their loads: give the data (plan with \
                     payloads first)",
                ));
            }
            loaded.make_elastic()?;
            if *model.as_ref().expect("elastic") == Model::ElasticGravity {
                lean_on_typical_compliances(&mut loaded)?;
            }
        }
        let robot = &loaded.robot.robot;
        let priority = match &self.priority {
            Some(source) => source.load(robot, files)?,
            None => loaded.priority.clone().unwrap_or_else(|| robot.priority()),
        };
        let priority = match &model {
            Some(model) => model.priority(robot, Some(&priority)),
            None => priority,
        };
        let analysis = identifiability(
            robot,
            &loaded.study,
            &priority,
            self.count,
            self.seed.unwrap_or(gecaro_calib::simulation::DEFAULT_SEED),
            observer,
        )?;
        Ok(IdentifiabilityAnalysis { loaded, analysis })
    }
}

impl IdentifiabilityAnalysis {
    /// The JSON document (`gecaro identifiable --json`, the web page's answer).
    pub fn document(&self) -> IdentifiableJson {
        IdentifiableJson::new(&self.loaded.robot.robot, &self.analysis)
    }
}

/// Gravity's tilts act through the joints' compliances (their columns are
/// `c_j ∂τ_j/∂tilt`): where the robot states none, they are analysed on
/// compliances of [`TYPICAL_COMPLIANCE`] (the structure does not depend
/// on their size; an identification finds them first), and a note says so.
///
/// # Errors
/// Never for a valid elastic robot.
fn lean_on_typical_compliances(loaded: &mut crate::measurements::Loaded) -> Result<(), AppError> {
    let robot = &mut loaded.robot.robot;
    if robot
        .compliances()
        .is_some_and(|compliances| compliances.iter().any(|c| *c != 0.0))
    {
        return Ok(());
    }
    let typical = vec![TYPICAL_COMPLIANCE; robot.joint_count()];
    robot
        .set_compliances(Some(typical))
        .map_err(|error| AppError::setting("model", error.to_string()))?;
    loaded.notes.push(crate::measurements::Note::plain(format!(
        "gravity's tilts act through the joints' compliances, which the robot file does not \
         state: analysed with {TYPICAL_COMPLIANCE:e} rad/(N·m) on every joint (an \
         identification finds the compliances first, then the tilts in a second pass)"
    )));
    Ok(())
}
