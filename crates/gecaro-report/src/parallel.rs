//! The HTML report of a parallel robot's identification (a Gough–Stewart
//! platform's, a Delta's): the verdict and where it holds, the errors at
//! the measured configurations before and after as plots, every parameter
//! with its σ and status, and the regrouping — one file, as the serial
//! report ([`crate::html_report`]), to archive with the calibrated robot.
//!
//! Lengths are shown in millimetres, angles in degrees, gains without
//! unit; the verdict's words are the application's, passed in as they are
//! printed and returned, so that the report says what the terminal said.

use gecaro_calib::identifiability::ParameterStatus;
use gecaro_calib::identification::DEFAULT_OUTLIER_THRESHOLD;
use gecaro_calib::parallel_robots::{
    PlatformErrors, PlatformIdentification, PlatformMeasure, PlatformOutlier,
};
use gecaro_core::parallel_model::{ParallelModel, ParameterUnit};
use gecaro_core::parallel_robot::ParallelRobot;
use maud::{Markup, PreEscaped, html};

use crate::Error;
use crate::page::{number, page};
use crate::plots::{error_histograms_svg, errors_per_configuration_svg};

/// What a parallel robot's report is made of.
#[derive(Debug)]
pub struct PlatformReportInput<'a> {
    /// The nominal robot.
    pub nominal: &'a ParallelRobot,
    /// Its identification.
    pub result: &'a PlatformIdentification<ParallelRobot>,
    /// What was measured.
    pub measure: PlatformMeasure,
    /// The data's label (its file, or its files).
    pub data: &'a str,
    /// Each set's label (its file), in order: one for one file.
    pub sets: &'a [String],
    /// Each observation's set and first line in its file, in order (a
    /// distance's pair by its first row; no line for data not read from a
    /// file's lines): the plots name them.
    pub observation_lines: &'a [(usize, Option<usize>)],
    /// The direct model's errors at the measured configurations, nominal.
    pub errors_before: &'a PlatformErrors,
    /// The same, calibrated.
    pub errors_after: &'a PlatformErrors,
    /// The verdict in words.
    pub summary: &'a str,
    /// What the verdict adds, in words.
    pub warnings: &'a [String],
    /// The prior the fit was held by, in words (`1 mm, 0.05°, 0.1 %`).
    pub prior: Option<&'a str>,
    /// The command line that produced the report.
    pub command: &'a str,
}

/// The two plots of a parallel robot's identification, as SVG.
#[derive(Clone, Debug)]
pub struct PlatformPlots {
    /// The histograms of the observations' errors before and after (mm).
    pub errors_histogram: String,
    /// Every observation's error before and after (mm), those standing out
    /// of the fit ringed, each titled by its file and line.
    pub errors_per_observation: String,
}

/// The plots the report shows ([`PlatformPlots`]), for `gecaro identify
/// --plot` too.
///
/// # Errors
/// [`Error::Plot`] if a plot cannot be drawn.
pub fn platform_plots(input: &PlatformReportInput<'_>) -> Result<PlatformPlots, Error> {
    let millimetres = |errors: &PlatformErrors| -> Vec<f64> {
        errors
            .observations
            .iter()
            .map(|error| error * 1e3)
            .collect()
    };
    let (before, after) = (
        millimetres(input.errors_before),
        millimetres(input.errors_after),
    );
    let errors_histogram = error_histograms_svg(&before, &after, "mm")?;
    let names: Vec<String> = input
        .observation_lines
        .iter()
        .enumerate()
        .map(|(index, (set, line))| {
            let file = input.sets.get(*set).map_or(input.data, String::as_str);
            match line {
                Some(line) => format!("{file}: observation {} (line {line})", index + 1),
                None => format!("{file}: observation {}", index + 1),
            }
        })
        .collect();
    let ringed: Vec<usize> = input
        .result
        .residual_ratios
        .iter()
        .enumerate()
        .filter(|(_, ratio)| **ratio > DEFAULT_OUTLIER_THRESHOLD)
        .map(|(index, _)| index)
        .collect();
    let errors_per_observation =
        errors_per_configuration_svg(&before, &after, &ringed, &names, "mm")?;
    Ok(PlatformPlots {
        errors_histogram,
        errors_per_observation,
    })
}

/// The report of a parallel robot's identification (see the module docs).
///
/// # Errors
/// [`Error::Plot`] if a plot cannot be drawn.
pub fn platform_report(input: &PlatformReportInput<'_>) -> Result<String, Error> {
    let (robot, result) = (input.nominal, input.result);
    let method = input.measure.name();
    let PlatformPlots {
        errors_histogram: histograms,
        errors_per_observation: per_observation,
    } = platform_plots(input)?;
    let body = html! {
        h1 { "Calibration report" }
        p.muted {
            (robot.name()) " (" (structure_words(robot)) ") — " (method) " method on "
            (input.data) " — made by " code { (input.command) }
        }
        (summary(input))
        (region(robot, result))
        (measurements(input))
        h2 { "Errors before and after" }
        p.muted {
            (match input.measure {
                PlatformMeasure::Pose => "Per measured pose: the distance of the platform \
                    frame's origin the direct model predicts from the measured one (mm).",
                PlatformMeasure::Point => "Per measured configuration: the distance of the \
                    tool point the direct model predicts from the measured one (mm).",
                PlatformMeasure::Distance => "Per measured pair: the predicted distance \
                    between the pair's tool points against the measured one (mm).",
                PlatformMeasure::Leg => "Per configuration: the measuring leg's length the \
                    direct model predicts against the one it read (mm).",
            })
            " These are the data the fit saw: judge the calibration on held-out \
             measurements (gecaro evaluate)."
        }
        (PreEscaped(histograms))
        (PreEscaped(per_observation))
        (parameters(robot, result))
        (regrouping(result))
        (actuators(robot))
        p.muted {
            "gecaro — geometric calibration of serial and parallel robots (GECARO, Khalil \
             et al.; Khalil and Besnard for the Gough–Stewart platform)."
        }
    };
    Ok(page(
        &format!("gecaro report — {}, {}", robot.name(), method),
        body,
    ))
}

/// `a Gough–Stewart platform, 6 legs` or `a Delta robot, 3 arms`.
fn structure_words(robot: &ParallelRobot) -> String {
    let kind = match robot {
        ParallelRobot::GoughStewart(_) => "a Gough–Stewart platform",
        ParallelRobot::Delta(_) => "a Delta robot",
    };
    format!(
        "{kind}, {} {}s",
        robot.actuator_count(),
        robot.actuator_word()
    )
}

/// The verdict, the summary table and the warnings.
fn summary(input: &PlatformReportInput<'_>) -> Markup {
    let result = input.result;
    let outcome = result.outcome;
    let (before, after) = (input.errors_before, input.errors_after);
    html! {
        p class=(if outcome.trusted() { "verdict ok" } else { "verdict bad" }) {
            strong { "Verdict: " } (input.summary) "."
        }
        h2 { "Summary" }
        table {
            tr {
                td { "result" }
                td class=(if outcome.solved() { "ok" } else { "bad" }) {
                    (outcome.as_str().replace('_', " ")) " after " (result.iterations)
                    (if result.iterations == 1 { " iteration" } else { " iterations" })
                }
            }
            tr {
                td { "data" }
                td {
                    (input.data) " (" (input.observation_lines.len()) " "
                    (if input.measure == PlatformMeasure::Distance { "pairs" } else { "configurations" })
                    ", " (input.measure.name()) " method)"
                }
            }
            tr {
                td { "identifiable parameters" }
                td { (result.rank.rank()) " of " (result.parameters.len()) }
            }
            tr {
                td { "condition number of W" sub { "b" } }
                td { (number(result.rank.condition_number)) }
            }
            tr {
                td { "equations' residual RMS" }
                td { (number(result.rms_before * 1e3)) " → " (number(result.rms_after * 1e3)) " mm" }
            }
            tr {
                td { "error RMS at the measured configurations" }
                td { (number(before.position_rms * 1e3)) " → " (number(after.position_rms * 1e3)) " mm" }
            }
            tr {
                td { "largest error" }
                td { (number(before.position_max * 1e3)) " → " (number(after.position_max * 1e3)) " mm" }
            }
            @if let (Some(before), Some(after)) = (before.angle_rms, after.angle_rms) {
                tr {
                    td { "orientation error RMS" }
                    td { (number(before.to_degrees())) " → " (number(after.to_degrees())) "°" }
                }
            }
            @if let Some(test) = result.noise_test {
                tr {
                    td { "residuals against the stated σ" }
                    td class=(if test.passed { "ok" } else { "bad" }) {
                        "σ̂/σ " (format!("{:.3}", test.sigma_ratio)) " (χ² " (format!("{:.1}", test.chi_square))
                        ", " (test.degrees_of_freedom) " degrees of freedom)"
                    }
                }
            }
            @if let Some(frame) = &result.registered {
                tr {
                    td { "instrument's frame (registered)" }
                    td {
                        "the base frame at ("
                        (frame.translation.vector.iter().map(|value| number(value * 1e3)).collect::<Vec<_>>().join(", "))
                        ") mm, turned " (number(frame.rotation.angle().to_degrees())) "°"
                    }
                }
            }
            @if let Some(leg) = &result.leg {
                tr {
                    td { "measuring leg (identified)" }
                    td {
                        "base socket ("
                        (leg.identified.base.iter().map(|value| number(value * 1e3)).collect::<Vec<_>>().join(", "))
                        ") mm, platform socket ("
                        (leg.identified.platform.iter().map(|value| number(value * 1e3)).collect::<Vec<_>>().join(", "))
                        ") mm, length at reading 0 " (number(leg.identified.length * 1e3)) " mm (σ "
                        (number(leg.sigma[6] * 1e3)) " mm); the frames those of joints 1–3 as drawn"
                    }
                }
            }
            @for (station, data) in result.stations.iter().zip(input.sets.iter().skip(1)) {
                tr {
                    td { "station of " (data) " (identified)" }
                    td {
                        "the base frame at ("
                        (station.frame.translation.vector.iter().map(|value| number(value * 1e3)).collect::<Vec<_>>().join(", "))
                        ") mm, turned " (number(station.frame.rotation.angle().to_degrees())) "° (σ "
                        (number(station.sigma[..3].iter().map(|s| s * s).sum::<f64>().sqrt() * 1e3)) " mm, "
                        (number(station.sigma[3..].iter().map(|s| s * s).sum::<f64>().sqrt().to_degrees())) "°)"
                    }
                }
            }
        }
        @if !input.warnings.is_empty() {
            div.warn {
                strong { "Warnings" }
                ul { @for warning in input.warnings { li { (warning) } } }
            }
        }
    }
}

/// Where the result holds: the predicted tool-point error at the measured
/// configurations and over the work region, against the noise floor.
fn region(robot: &ParallelRobot, result: &PlatformIdentification<ParallelRobot>) -> Markup {
    let Some(region) = &result.region else {
        return html! {
            h2 { "Where it holds" }
            p.bad { "No prediction: the fit is no solution." }
        };
    };
    let what = if region.distances {
        "distance error from the home pose's tool point"
    } else {
        "tool-point error"
    };
    let work = if region.work_is_ranges {
        "the workspace (the actuators' ranges)"
    } else {
        "the stated work region"
    };
    let range = |range: (f64, f64)| actuator_range(robot, range);
    html! {
        h2 { "Where it holds" }
        p class=(if region.holds_everywhere { "ok" } else { "bad" }) {
            @if region.holds_everywhere {
                "The result holds over " (work) "."
            } @else {
                "The result holds only where the data were taken: measure configurations spread \
                 over " (work) "."
            }
        }
        table {
            tr { th { "predicted " (what) } th { "mm RMS" } }
            tr { td { "at the measured configurations" } td { (number(region.inside * 1e3)) } }
            tr { td { "over " (work) } td { (number(region.work_rms * 1e3)) } }
            tr { td { "largest over " (work) } td { (number(region.work_max * 1e3)) } }
            tr { td { "noise floor (a held-out measurement of a perfect robot)" } td { (number(region.floor * 1e3)) } }
        }
        table {
            tr { th { (robot.actuator_word()) } th { "measured" } th { "work region" } }
            @for actuator in 0..region.measured.joints() {
                tr {
                    td { (actuator + 1) }
                    td { (range(region.measured.range(actuator))) }
                    td { (range(region.work.range(actuator))) }
                }
            }
        }
    }
}

/// An actuator's range in its unit: mm for a leg, degrees for an arm.
fn actuator_range(robot: &ParallelRobot, (low, high): (f64, f64)) -> String {
    match robot.actuator_unit() {
        ParameterUnit::Angle => format!(
            "{} … {}°",
            number(low.to_degrees()),
            number(high.to_degrees())
        ),
        _ => format!("{} … {} mm", number(low * 1e3), number(high * 1e3)),
    }
}

/// The loss, the prior, and the measurements that stand out or were
/// dropped.
fn measurements(input: &PlatformReportInput<'_>) -> Markup {
    let result = input.result;
    let several = input.sets.len() > 1;
    let listed = |title: &str, observations: &[PlatformOutlier]| {
        html! {
            @if !observations.is_empty() {
                p { strong { (title) } " (" (observations.len()) "):" }
                table {
                    tr { @if several { th { "file" } } th { "line" } th { "residual (σ)" } }
                    @for outlier in observations {
                        tr {
                            @if several {
                                td { (input.sets.get(outlier.set).map_or("–", String::as_str)) }
                            }
                            td { (outlier.line.map_or_else(|| "–".to_owned(), |line| line.to_string())) }
                            td { (format!("{:.1}", outlier.ratio)) }
                        }
                    }
                }
            }
        }
    };
    html! {
        h2 { "Measurements as they are" }
        p {
            "Loss " strong { (result.loss) }
            @if result.reweightings > 0 { " after " (result.reweightings) " reweightings" }
            "."
            @if let Some(prior) = input.prior {
                " Prior around the nominal values: σ " (prior) " (maximum a posteriori; σ is posterior)."
            }
        }
        (listed("Dropped before this fit", &result.rejected))
        (listed("Standing out of the fit (ringed on the per-observation plot)", &result.outliers))
        @if result.outliers.is_empty() {
            p.muted { "No measurement stands out of the fit." }
        }
    }
}

/// A parameter's value in its shown unit: mm, degrees, or a gain as it is.
fn shown(robot: &ParallelRobot, index: usize, value: f64) -> String {
    match robot.parameter_unit(index) {
        ParameterUnit::Length => number(value * 1e3),
        ParameterUnit::Angle => number(value.to_degrees()),
        ParameterUnit::Gain => number(value),
    }
}

/// The unit [`shown`] gives a parameter.
fn shown_unit(robot: &ParallelRobot, index: usize) -> &'static str {
    match robot.parameter_unit(index) {
        ParameterUnit::Length => "mm",
        ParameterUnit::Angle => "°",
        ParameterUnit::Gain => "",
    }
}

/// Every parameter: nominal, identified, the change and its σ, its status.
fn parameters(robot: &ParallelRobot, result: &PlatformIdentification<ParallelRobot>) -> Markup {
    html! {
        h2 { "Parameters" }
        table {
            tr {
                th { "parameter" } th { "unit" } th { "nominal" } th { "identified" }
                th { "change" } th { "σ" } th { "status" }
            }
            @for (index, parameter) in result.parameters.iter().enumerate() {
                tr class=[status_class(parameter.status)] {
                    td { (parameter.name) }
                    td { (shown_unit(robot, index)) }
                    td { (shown(robot, index, parameter.nominal)) }
                    td { (shown(robot, index, parameter.identified)) }
                    td { (shown(robot, index, parameter.identified - parameter.nominal)) }
                    td { (parameter.sigma.map_or_else(|| "–".to_owned(), |sigma| shown(robot, index, sigma))) }
                    td { (parameter.status.as_str().replace('_', " ")) }
                }
            }
        }
        p.muted {
            "Green: identified; grey: regrouped onto the identified ones (their effect is \
             carried by the combination below, their value stays nominal), of no effect on \
             these measurements, or excluded (the tool point when poses are measured)."
        }
    }
}

/// The class of a parameter's row.
fn status_class(status: ParameterStatus) -> Option<&'static str> {
    match status {
        ParameterStatus::Identifiable => Some("id"),
        _ => Some("z"),
    }
}

/// The regrouped parameters and what carries each.
fn regrouping(result: &PlatformIdentification<ParallelRobot>) -> Markup {
    let names = &result.rank.names;
    html! {
        @if !result.rank.relations.is_empty() {
            h2 { "Regrouping" }
            p.muted {
                "A regrouped parameter's effect on these measurements is that of the \
                 combination of identified ones: each of those identifies its own value plus \
                 the coefficient times the regrouped parameter's error (QR, Appendix III)."
            }
            table {
                tr { th { "regrouped" } th { "carried by" } }
                @for relation in &result.rank.relations {
                    tr {
                        td { (names[relation.parameter]) }
                        td {
                            (relation.terms.iter()
                                .map(|(base, coefficient)| format!("{} {}", number(*coefficient), names[*base]))
                                .collect::<Vec<_>>()
                                .join(" + "))
                        }
                    }
                }
            }
        }
    }
}

/// The actuators' ranges of the nominal robot.
fn actuators(robot: &ParallelRobot) -> Markup {
    html! {
        h2 { "Actuators (nominal)" }
        table {
            tr { th { (robot.actuator_word()) } th { "range" } }
            @for actuator in 0..robot.actuator_count() {
                tr {
                    td { (actuator + 1) }
                    td { (actuator_range(robot, robot.actuator_range(actuator))) }
                }
            }
        }
    }
}
