//! Identification of a parallel robot from a data file: the calibrated
//! platform, every parameter with its precision, the verdict, and the
//! direct model's errors at the measured configurations before and after.

use gecaro_calib::identification::{Loss, LossKind, Prior};
use gecaro_calib::parallel_robots::{
    PlatformErrors, PlatformIdentification, PlatformIdentificationOptions, PlatformMeasure,
    PlatformNoise, PlatformOutlier, PlatformRegion, check_platform_samples, identify_platform_sets,
    in_base_frame, leg_errors, platform_errors,
};
use gecaro_calib::study::Sample;
use gecaro_core::parallel_model::ParallelModel;
use gecaro_core::parallel_robot::ParallelRobot;
use gecaro_io::{ParallelRobotFile, StandardDeviation};
use gecaro_report::{PlatformPlots, PlatformReportInput, platform_plots, platform_report};
use serde::Deserialize;

use super::documents::{
    PlatformIdentificationDocument, PlatformLegDocument, PlatformOutlierDocument,
    PlatformRankDocument, PlatformStationDocument, pose_document,
};
use super::leg::measuring_leg;
use super::region::stated_work_region;
use super::residuals::{ObservationPlaces, platform_residuals_csv};
use super::{actuator_types, load_parallel_robot, measure_for};
use crate::error::{AppError, ErrorKind};
use crate::files::Files;
use crate::output::Output;
use crate::sources::{DataFormatSpec, DataSource};

/// An identification of a parallel robot.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ParallelIdentifyRequest {
    /// The nominal platform (a file, or a ready parallel robot's name).
    pub robot: String,
    /// `frame`, `position` or `distance`.
    pub method: String,
    /// The measurements.
    pub data: DataSource,
    /// More sets of the same measure, each measured from another tracker
    /// station (the instrument moved between them), in order: each set's
    /// frame is registered and identified with the platform, the first
    /// set's frame the base frame. Distances have no frame: their sets are
    /// read as one. Units and columns as `format` says for every set.
    #[serde(default)]
    pub stations: Vec<DataSource>,
    /// The `leg` method's measuring leg: its base socket's centre (base
    /// frame), a point with its units (`250mm,-100mm,0`).
    #[serde(default)]
    pub leg_base: Option<String>,
    /// Its platform socket's centre (platform frame), likewise.
    #[serde(default)]
    pub leg_platform: Option<String>,
    /// Its gain: metres of length per unit of reading (default 1).
    #[serde(default)]
    pub leg_gain: Option<f64>,
    /// Units and columns of the data file.
    #[serde(default)]
    pub format: DataFormatSpec,
    /// The sensor's σ of a position coordinate: a number in the data's
    /// length unit, or a text with its unit (`"20um"`); also the
    /// orientations' unless `sigma_rotation` is given.
    pub sigma: Option<StandardDeviation>,
    /// The σ of a rotation angle: a number in the data's angle unit, or a
    /// text with its unit (`"0.001deg"`).
    pub sigma_rotation: Option<StandardDeviation>,
    /// Gauss–Newton iterations at most (default 30).
    pub max_iterations: Option<usize>,
    /// The region the platform will be used in, over which the verdict
    /// predicts its error: actuator ranges with their units
    /// (`qm1=-10..10mm,qm4=-5..5mm`; actuators not named: their ranges;
    /// default: the actuators' ranges).
    #[serde(default)]
    pub work_region: Option<String>,
    /// The loss: `l2` (default), `huber`, `cauchy` or `tukey` — a robust
    /// one weighs each observation down by its residual after the
    /// least-squares fit.
    #[serde(default)]
    pub loss: Option<String>,
    /// A robust loss's scale, in robust σ̂ (the loss's default when `None`).
    #[serde(default)]
    pub loss_scale: Option<f64>,
    /// Drop the measurements that stand out and identify the rest again,
    /// once.
    #[serde(default)]
    pub reject: Option<bool>,
    /// A Gaussian prior about the nominal values: σ of lengths, angles and
    /// gains with their units, `"1mm,0.05deg,0.1%"`.
    #[serde(default)]
    pub prior: Option<String>,
    /// The calibrated platform's file.
    #[serde(flatten)]
    pub output: Output,
}

/// An identified platform.
#[derive(Clone, Debug)]
pub struct ParallelIdentified {
    /// The calibrated platform as a file.
    pub calibrated: ParallelRobotFile,
    /// The identification.
    pub result: PlatformIdentification<ParallelRobot>,
    /// Its document.
    pub document: PlatformIdentificationDocument,
    /// What the report shows beside the document.
    shown: Shown,
}

/// What a report shows that the document summarises: the nominal robot,
/// each observation's first line and its errors before and after.
#[derive(Clone, Debug)]
struct Shown {
    nominal: ParallelRobot,
    measure: PlatformMeasure,
    sets: Vec<String>,
    observation_lines: Vec<(usize, Option<usize>)>,
    places: ObservationPlaces,
    errors_before: PlatformErrors,
    errors_after: PlatformErrors,
}

impl ParallelIdentified {
    /// Whether the fit converged (trusted or not).
    pub fn converged(&self) -> bool {
        self.result.outcome.solved()
    }

    /// The error a front end ends with: not converged
    /// ([`ErrorKind::NotConverged`]), or converged to a fit its data do not
    /// trust ([`ErrorKind::Untrusted`]); `None` for a trusted fit.
    pub fn failure(&self) -> Option<AppError> {
        let outcome = self.result.outcome;
        if !outcome.solved() {
            Some(AppError::plain(
                ErrorKind::NotConverged,
                format!("the identification {}", self.document.summary),
            ))
        } else if !outcome.trusted() {
            Some(AppError::plain(
                ErrorKind::Untrusted,
                format!("the identification {}", self.document.summary),
            ))
        } else {
            None
        }
    }

    /// Every observation's errors and residual as CSV text, one row per
    /// configuration (or distance's pair): the serial residuals' columns
    /// ([`crate::residuals_csv`]) — `set`, `file`, `kind`, `observation`,
    /// `lines`, `error_before_mm`, `error_after_mm`, the rotation errors of
    /// measured poses, `residual_sigmas`, `weight` (0 for a measurement
    /// `reject` dropped), `outlier`.
    ///
    /// # Errors
    /// As [`crate::residuals_csv`].
    pub fn residuals_csv(&self) -> Result<String, AppError> {
        let shown = &self.shown;
        platform_residuals_csv(
            &self.result,
            &shown.places,
            (&shown.errors_before, &shown.errors_after),
        )
    }

    /// The report's two plots as SVG: the errors' histograms before and
    /// after, and every observation's error (those standing out ringed).
    ///
    /// # Errors
    /// A plot that cannot be drawn.
    pub fn plots(&self) -> Result<PlatformPlots, AppError> {
        Ok(platform_plots(&self.report_input(""))?)
    }

    /// What the report and the plots are made from.
    fn report_input<'a>(&'a self, command: &'a str) -> PlatformReportInput<'a> {
        let shown = &self.shown;
        PlatformReportInput {
            nominal: &shown.nominal,
            result: &self.result,
            measure: shown.measure,
            data: &self.document.data,
            sets: &shown.sets,
            observation_lines: &shown.observation_lines,
            errors_before: &shown.errors_before,
            errors_after: &shown.errors_after,
            summary: &self.document.summary,
            warnings: &self.document.warnings,
            prior: self.document.prior.as_deref(),
            command,
        }
    }

    /// The self-contained HTML report of the identification
    /// ([`gecaro_report::platform_report`]), made by `command`.
    ///
    /// # Errors
    /// A plot that cannot be drawn.
    pub fn report(&self, command: &str) -> Result<String, AppError> {
        Ok(platform_report(&self.report_input(command))?)
    }
}

impl ParallelIdentifyRequest {
    /// Runs the identification.
    ///
    /// # Errors
    /// A robot or data file that cannot be read, a σ that is no sensor's,
    /// too few equations, actuator values with no pose, a file that cannot
    /// be written.
    pub fn run(&self, files: &dyn Files) -> Result<ParallelIdentified, AppError> {
        let nominal = load_parallel_robot(&self.robot, files)?;
        let measure = measure_for(&self.method, &nominal.robot)?;
        // Before any file is read: a leg the method needs, or does not take.
        let leg = measuring_leg(
            measure,
            self.leg_base.as_deref(),
            self.leg_platform.as_deref(),
            self.leg_gain,
        )?;
        self.output.check(files, "toml")?;
        let format = self.format.format()?;
        let reads = std::iter::once(&self.data)
            .chain(&self.stations)
            .map(|source| {
                source.read(
                    files,
                    &actuator_types(&nominal.robot),
                    measure.columns(),
                    &format,
                )
            })
            .collect::<Result<Vec<_>, _>>()?;
        let labels: Vec<String> = reads.iter().map(|read| read.label.clone()).collect();
        let label = labels.join(" + ");
        let sets: Vec<Vec<Sample>> = reads.iter().map(|read| read.samples.to_rows()).collect();
        // Every sample's set and line, in the fit's order (sets one after
        // the other).
        let lines: Vec<(usize, Option<usize>)> = sets
            .iter()
            .enumerate()
            .flat_map(|(set, samples)| samples.iter().map(move |sample| (set, sample.line)))
            .collect();
        let value = |setting: &str, sigma: &Option<StandardDeviation>, rotation: bool| {
            sigma
                .as_ref()
                .map(|sigma| sigma.value(rotation, format.units))
                .transpose()
                .map_err(|message| AppError::setting(setting, message))
        };
        let length = value("sigma", &self.sigma, false)?;
        let angle = value("sigma_rotation", &self.sigma_rotation, true)?;
        let noise = length.map(|length| PlatformNoise {
            length,
            angle: angle.unwrap_or(length),
        });
        let mut options = PlatformIdentificationOptions::default();
        if let Some(iterations) = self.max_iterations {
            if !(1..=crate::limits::MAX_ITERATIONS).contains(&iterations) {
                return Err(AppError::setting_value(
                    "max_iterations",
                    iterations,
                    format!("takes 1 to {}", crate::limits::MAX_ITERATIONS),
                ));
            }
            options.max_iterations = iterations;
        }
        if let Some(text) = &self.work_region {
            options.work_region = Some(stated_work_region(&nominal.robot, text)?);
        }
        let kind: LossKind = self.loss.as_deref().unwrap_or("l2").parse()?;
        options.loss = Loss::from_parts(kind, self.loss_scale)?;
        options.reject = self.reject.unwrap_or(false);
        options.prior = crate::settings::prior(self.prior.as_deref(), None)?;
        options.leg = leg;
        // With several files, a sample's problem (actuator values with no
        // pose, a missing column) is named by its file as well as its line:
        // each file's configurations are solved once first.
        if sets.len() > 1 {
            for (set, label) in sets.iter().zip(&labels) {
                check_platform_samples(&nominal.robot, set, measure)
                    .map_err(|error| in_file(label, error))?;
            }
        }
        let borrowed: Vec<&[Sample]> = sets.iter().map(Vec::as_slice).collect();
        let mut result =
            identify_platform_sets(&nominal.robot, &borrowed, measure, noise, &options)?;
        if let Some(change) = &mut result.change {
            change.label.clone_from(&labels[change.set]);
        }
        // The errors in the base frame: each set's samples brought there by
        // the frame its registration and correction found.
        let frames = std::iter::once(result.registered)
            .chain(result.stations.iter().map(|station| Some(station.frame)))
            .chain(std::iter::repeat(None));
        // One set in the base frame already is read as it is (10⁵ poses
        // are not copied).
        let in_base: std::borrow::Cow<'_, [Sample]> = match sets.as_slice() {
            [one] if result.registered.is_none() => std::borrow::Cow::Borrowed(one.as_slice()),
            _ => sets
                .iter()
                .zip(frames)
                .flat_map(|(set, frame)| match frame {
                    Some(frame) => in_base_frame(set, &frame),
                    None => set.clone(),
                })
                .collect(),
        };
        let (errors_before, errors_after) = match &result.leg {
            Some(leg) => (
                leg_errors(&nominal.robot, &leg.stated, &in_base)?,
                leg_errors(&result.calibrated, &leg.identified, &in_base)?,
            ),
            None => (
                platform_errors(&nominal.robot, &in_base, measure)?,
                platform_errors(&result.calibrated, &in_base, measure)?,
            ),
        };
        let name = format!("{} (calibrated)", nominal.robot.name());
        // A result that holds in the measured region only keeps that region:
        // compensation flags targets outside it.
        let regional = result
            .region
            .as_ref()
            .filter(|region| !region.holds_everywhere);
        let registered = result
            .registered
            .as_ref()
            .map_or_else(String::new, |frame| {
                format!(
                    "; measured in an instrument's frame registered at ({}) mm, turned {:.4}°",
                    frame
                        .translation
                        .vector
                        .iter()
                        .map(|value| format!("{:.3}", value * 1e3))
                        .collect::<Vec<_>>()
                        .join(", "),
                    frame.rotation.angle().to_degrees()
                )
            });
        let holds = regional.map_or_else(String::new, |region| {
            format!(
                "; holds within the measured actuator ranges (predicted {:.4} mm there, {:.4} mm \
                 over the workspace)",
                region.inside * 1e3,
                region.work_rms * 1e3
            )
        });
        let calibrated = ParallelRobotFile {
            robot: result.calibrated.clone().renamed(&name),
            description: Some(format!(
                "{} calibrated by gecaro: {} method on {}, {} parameters identified, verdict \
                 {}{registered}{holds}",
                nominal.robot.name(),
                measure.name(),
                label,
                result.rank.rank(),
                result.outcome.as_str()
            )),
            calibrated_from: Some(measure.name().to_owned()),
            measured_region: regional.map(|region| region.measured.clone()),
        };
        let written = self.output.write(
            files,
            "toml",
            gecaro_io::format_parallel_robot_file(&calibrated).as_bytes(),
        )?;
        let rank = PlatformRankDocument::new(&result.rank, label.clone());
        let outlier = |outlier: &PlatformOutlier| PlatformOutlierDocument {
            data: (labels.len() > 1).then(|| labels[outlier.set].clone()),
            line: outlier.line,
            ratio: outlier.ratio,
        };
        let document = PlatformIdentificationDocument {
            robot: nominal.robot.name().to_owned(),
            method: measure.name(),
            data: label,
            configurations: lines.len(),
            outcome: result.outcome.as_str(),
            summary: summary(&result, &labels),
            sigma_ratio: result.noise_test.map(|test| test.sigma_ratio),
            iterations: result.iterations,
            rms_before: result.rms_before,
            rms_after: result.rms_after,
            errors_before: (&errors_before).into(),
            errors_after: (&errors_after).into(),
            rank: result.rank.rank(),
            parameters: PlatformIdentificationDocument::parameters(&nominal.robot, &result),
            regrouped: rank.regrouped,
            region: result.region.as_ref().map(Into::into),
            registered: result.registered.as_ref().map(pose_document),
            outliers: result.outliers.iter().map(outlier).collect(),
            warnings: result
                .region
                .as_ref()
                .and_then(PlatformRegion::warning)
                .into_iter()
                .chain(
                    (self.work_region.is_some()
                        && result.outcome.solved()
                        && result.region.is_none())
                    .then(|| {
                        "no error is predicted over the stated work region: the direct model \
                         solves too few of its actuator values (state ranges the platform \
                         reaches together)"
                            .to_owned()
                    }),
                )
                .collect(),
            written: written.map(|path| path.display().to_string()),
            loss: result.loss.to_string(),
            reweightings: result.reweightings,
            robust_sigma: result.robust_sigma,
            weighed_down: weighed_down(&result.weights),
            ignored: ignored(&result.weights),
            prior: result.prior.as_ref().map(prior_words),
            change: result.change.as_ref().map(Into::into),
            rejected: result.rejected.iter().map(outlier).collect(),
            stations: labels
                .iter()
                .skip(1)
                .zip(&result.stations)
                .map(|(data, station)| PlatformStationDocument {
                    data: data.clone(),
                    frame: pose_document(&station.frame),
                    sigma_position: [station.sigma[0], station.sigma[1], station.sigma[2]],
                    sigma_rotation: [station.sigma[3], station.sigma[4], station.sigma[5]],
                })
                .collect(),
            leg: result.leg.as_ref().map(|leg| PlatformLegDocument {
                base: leg.identified.base.into(),
                platform: leg.identified.platform.into(),
                length: leg.identified.length,
                gain: leg.identified.gain,
                sigma: leg.sigma,
                stated_length: leg.stated.length,
            }),
        };
        let taken = measure.samples_per_observation();
        let observation_lines = lines.iter().step_by(taken).copied().collect();
        let places = ObservationPlaces {
            labels: labels.clone(),
            samples: lines,
            taken,
        };
        Ok(ParallelIdentified {
            calibrated,
            result,
            document,
            shown: Shown {
                nominal: nominal.robot,
                measure,
                sets: labels,
                observation_lines,
                places,
                errors_before,
                errors_after,
            },
        })
    }
}

/// `error` of a sample of the file `label`, named `file:line:` as a data
/// file's reading errors are (an error of no line as it is).
fn in_file(label: &str, error: gecaro_calib::Error) -> AppError {
    match error {
        gecaro_calib::Error::InvalidData {
            line: Some(line),
            message,
        } => AppError::plain(ErrorKind::Input, format!("{label}:{line}: {message}")),
        other => other.into(),
    }
}

/// A parallel robot's prior in words, in the units its parameters are
/// read in: `1 mm, 0.05°, 0.1 %`.
fn prior_words(prior: &Prior) -> String {
    let shown = |value: f64| (value * 1e4).round() / 1e4;
    format!(
        "{} mm, {}°, {} %",
        shown(prior.length * 1e3),
        shown(prior.angle.to_degrees()),
        shown(prior.gain * 1e2)
    )
}

/// Measurements a robust loss gave no weight at all (a redescending one).
fn ignored(weights: &[f64]) -> usize {
    weights.iter().filter(|weight| **weight == 0.0).count()
}

/// Measurements a robust loss weighed below one half.
fn weighed_down(weights: &[f64]) -> usize {
    weights.iter().filter(|weight| **weight < 0.5).count()
}

/// The verdict in words, after the registration of the instrument's frame
/// when there was one, and the measurements that stand out (and what a
/// robust loss made of them).
fn summary(result: &PlatformIdentification<ParallelRobot>, labels: &[String]) -> String {
    let mut verdict = verdict(result);
    // A line (`line 19`), with its file when there are several
    // (`station2.csv:19`).
    let line_of = |outlier: &PlatformOutlier| {
        let line = outlier
            .line
            .map_or_else(|| "?".into(), |line| line.to_string());
        match labels.get(outlier.set).filter(|_| labels.len() > 1) {
            Some(label) => format!("{label}:{line}"),
            None => format!("line {line}"),
        }
    };
    if let Some(prior) = &result.prior {
        verdict.push_str(&format!(
            ", held by a prior of σ {} about the nominal values",
            prior_words(prior)
        ));
    }
    if !result.rejected.is_empty() {
        let shown = &result.rejected[..result.rejected.len().min(5)];
        let listed = if labels.len() > 1 {
            shown.iter().map(line_of).collect::<Vec<_>>().join(", ")
        } else {
            let numbers: Vec<String> = shown
                .iter()
                .map(|outlier| {
                    outlier
                        .line
                        .map_or_else(|| "?".into(), |line| line.to_string())
                })
                .collect();
            format!(
                "line{} {}",
                if numbers.len() == 1 { "" } else { "s" },
                numbers.join(", ")
            )
        };
        verdict.push_str(&format!(
            " without the {} measurement{} that stood out ({listed}{}), rejected",
            result.rejected.len(),
            if result.rejected.len() == 1 { "" } else { "s" },
            if result.rejected.len() > 5 {
                ", …"
            } else {
                ""
            }
        ));
    }
    if result.reweightings > 0 {
        let ignored = ignored(&result.weights);
        verdict.push_str(&format!(
            "; the robust loss, {}, weighed {} of {} measurements below one half{}",
            result.loss,
            weighed_down(&result.weights),
            result.weights.len(),
            if ignored > 0 {
                format!(" ({ignored} not at all)")
            } else {
                String::new()
            }
        ));
    }
    if !result.outliers.is_empty() {
        let named: Vec<String> = result
            .outliers
            .iter()
            .take(3)
            .map(|outlier| format!("{} at {:.1}σ", line_of(outlier), outlier.ratio))
            .collect();
        verdict.push_str(&format!(
            "; {} measurement{} stand{} out ({}{}): check {}",
            result.outliers.len(),
            if result.outliers.len() == 1 { "" } else { "s" },
            if result.outliers.len() == 1 { "s" } else { "" },
            named.join(", "),
            if result.outliers.len() > 3 {
                ", …"
            } else {
                ""
            },
            if result.outliers.len() == 1 {
                "it"
            } else {
                "them"
            }
        ));
    }
    if let Some(leg) = &result.leg {
        verdict.push_str(&format!(
            "; the measuring leg found with its base socket at ({}) mm, its platform socket at \
             ({}) mm and its length at reading 0 {:.3} mm (σ {:.4} mm); nothing outside the \
             robot measured its frames: they are those of joints 1–3 at their stated \
             coordinates, and its tool point is as stated",
            millimetres(&leg.identified.base),
            millimetres(&leg.identified.platform),
            leg.identified.length * 1e3,
            leg.sigma[6] * 1e3,
        ));
    }
    for (label, station) in labels.iter().skip(1).zip(&result.stations) {
        verdict.push_str(&format!(
            "; {label} was measured from another station, identified with the platform: the \
             base at ({}) mm in it, turned {:.4}° (σ {:.3} mm, {:.4}°)",
            millimetres(&station.frame.translation.vector),
            station.frame.rotation.angle().to_degrees(),
            station.sigma[..3].iter().map(|s| s * s).sum::<f64>().sqrt() * 1e3,
            station.sigma[3..]
                .iter()
                .map(|s| s * s)
                .sum::<f64>()
                .sqrt()
                .to_degrees(),
        ));
    }
    match &result.registered {
        Some(frame) => format!(
            "the data were in another frame than the base (the nominal platform more than 50 mm \
             off them): the instrument's frame was registered — the base at ({}) mm in it, \
             turned {:.3}° — before the fit, which {verdict}",
            millimetres(&frame.translation.vector),
            frame.rotation.angle().to_degrees()
        ),
        None => verdict,
    }
}

/// A position in millimetres, two decimals: `12.34, -5.00, 0.25`.
fn millimetres(position: &nalgebra::Vector3<f64>) -> String {
    position
        .iter()
        .map(|value| format!("{:.2}", value * 1e3))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The verdict alone in words.
fn verdict(result: &PlatformIdentification<ParallelRobot>) -> String {
    use gecaro_calib::identification::Outcome;
    let ratio = result
        .noise_test
        .map(|test| format!("{:.2}", test.sigma_ratio))
        .unwrap_or_default();
    match result.outcome {
        Outcome::FitsNoise => format!(
            "converged in {} iterations: the residuals fit the stated noise (σ̂/σ {ratio})",
            result.iterations
        ),
        Outcome::ExceedsNoise => format!(
            "converged, but the residuals are {ratio}× the stated noise: a model error (a joint \
             not at its stated place, an elastic leg), data from another platform, or σ \
             understated"
        ),
        Outcome::BelowNoise => format!(
            "converged, but the residuals are {ratio}× the stated noise, far below it: σ \
             overstated, or the same measurements counted twice"
        ),
        Outcome::Regional => format!(
            "converged in {} iterations{}, but {}",
            result.iterations,
            if ratio.is_empty() {
                String::new()
            } else {
                format!(" and the residuals fit the stated noise (σ̂/σ {ratio})")
            },
            result
                .region
                .as_ref()
                .map_or_else(String::new, PlatformRegion::words)
        ),
        Outcome::Changed => format!(
            "converged, but the data changed during the run: {}",
            result.change.as_ref().map_or_else(String::new, |change| {
                change.words_with(
                    gecaro_calib::identification::DEFAULT_OUTLIER_THRESHOLD,
                    "leave those rows out (a file of their own is identified as another \
                     cell), or measure the platform again",
                )
            })
        ),
        Outcome::Untested => format!(
            "converged in {} iterations; no σ was stated, so the fit is not tested against the \
             noise",
            result.iterations
        ),
        Outcome::Implausible => {
            // Moved beyond any platform's error but within 3σ of nominal:
            // the data do not determine them (poses too close together),
            // which is no mistake in the file.
            let undetermined = result
                .parameters
                .iter()
                .filter(|parameter| result.implausible.contains(&parameter.name))
                .all(|parameter| {
                    parameter.sigma.is_some_and(|sigma| {
                        (parameter.identified - parameter.nominal).abs() < 3.0 * sigma
                    })
                });
            let cause = match &result.region {
                Some(region) if undetermined => format!(
                    "within 3σ of their nominal values: the data do not determine them — {}",
                    region.words()
                ),
                _ => "the robot file or the data are mistaken".to_owned(),
            };
            format!(
                "converged, but {} took values no platform has (more than 50 mm, or a gain 10 % \
                 off, from nominal), {cause}",
                result.implausible.join(", ")
            )
        }
        Outcome::NotConverged => format!(
            "not converged after {} iteration{}: more iterations, or a nominal platform nearer \
             the real one",
            result.iterations,
            if result.iterations == 1 { "" } else { "s" }
        ),
        Outcome::Diverged => "diverged: no step lowered the residuals from the nominal \
                              platform; check the robot file and the data's units"
            .to_owned(),
        // A serial robot's outcomes a parallel fit does not produce (a
        // degenerate or repeated design, an underdetermined or incomplete
        // model): named as they are, should one come.
        other => other.as_str().replace('_', " "),
    }
}
