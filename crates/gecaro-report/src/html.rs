//! The HTML report: one file with everything inline (SVG plots, CSS), to
//! archive with a calibration and to read without a network. Written with
//! maud's templates, which escape every text they are given; the plots,
//! SVG made here, go in as markup.

use gecaro_calib::identifiability::{ParameterStatus, RankReport};
use gecaro_calib::identification::{Identification, Outlier, Route, StopReason};
use gecaro_calib::study::Study;
use gecaro_core::{FrameType, ParameterId, ParameterKind, Robot};
use maud::{Markup, PreEscaped, html};

use crate::Error;
use crate::page::{number, page};
use crate::plots::{IdentificationSvgs, identification_svgs, robot_projections_svg};

/// What a report is made of.
#[derive(Debug)]
pub struct ReportInput<'a> {
    /// The nominal robot.
    pub robot: &'a Robot,
    /// The measurements.
    pub study: &'a Study,
    /// The identification of the robot from them.
    pub identification: &'a Identification,
    /// The command line that produced the report.
    pub command: &'a str,
}

/// The report of an identification (see the module docs).
///
/// # Errors
/// [`Error::Plot`] if a plot cannot be drawn.
pub fn html_report(input: &ReportInput<'_>) -> Result<String, Error> {
    let (robot, result) = (input.robot, input.identification);
    let methods = input.study.method_names();
    let IdentificationSvgs {
        convergence,
        errors_histogram: histograms,
        errors_per_configuration: per_configuration,
    } = identification_svgs(input.study, result)?;
    let middle: Vec<f64> = robot
        .joints()
        .iter()
        .map(|joint| 0.5 * (joint.qmin + joint.qmax))
        .collect();
    let view = match robot.motor_positions(&middle) {
        Ok(motor) => Some(robot_projections_svg(&result.calibrated, motor.as_slice())?),
        Err(_) => None,
    };
    let body = html! {
        h1 { "Calibration report" }
        p.muted {
            (robot.name()) " (" (robot.joint_count()) " joints, " (robot.joint_letters())
            ") — " (methods) " — made by " code { (input.command) }
        }
        (summary(input))
        (robustness(result))
        h2 { "Convergence" }
        (PreEscaped(convergence))
        h2 { "Errors before and after" }
        p.muted {
            "Per configuration: distance to the measured point, to the mean point of its set, \
             to the plane, or distance error of a pair (mm). With outliers, the \
             histogram after holds the inliers only."
        }
        (PreEscaped(histograms))
        (PreEscaped(per_configuration))
        (parameters(result))
        (identifiable(robot, &result.rank))
        h2 { "Robot (nominal)" }
        (robot_table(robot))
        @if let Some(view) = view {
            p.muted {
                "Calibrated robot at the middle of its "
                (robot.frames().iter().filter(|f| f.frame_type != FrameType::Fixed).count())
                " joint ranges (origins of frames 0..n+1, m):"
            }
            (PreEscaped(view))
        }
        p.muted { "gecaro — geometric calibration of serial robots (GECARO, Khalil et al.)." }
    };
    Ok(page(
        &format!("gecaro report — {}, {}", robot.name(), methods),
        body,
    ))
}

/// The summary table and the warnings.
fn summary(input: &ReportInput<'_>) -> Markup {
    let result = input.identification;
    let converged = result.stop_reason == StopReason::Converged;
    let route = match result.route {
        Route::GaussNewton => "plain Gauss–Newton (the paper's scheme)",
        Route::MinimumNorm => "minimum-norm steps, then continuation to the base set",
        Route::LevenbergMarquardt => "Levenberg–Marquardt",
    };
    let observability = {
        let o = result.observability();
        [o.o1, o.o2, o.o3, o.o4, o.o5].map(number).join(" · ")
    };
    let verdict = &result.verdict;
    html! {
        p class=(if verdict.outcome.trusted() { "verdict ok" } else { "verdict bad" }) {
            strong { "Verdict: " } (verdict.summary) "."
        }
        h2 { "Summary" }
        table {
            tr {
                td { "result" }
                td class=(if converged { "ok" } else { "bad" }) {
                    (if converged { "converged" } else { "NOT converged" })
                    " after " (result.iterations()) " iterations (" (route) ")"
                }
            }
            tr {
                td { "data" }
                td {
                    @for (index, set) in input.study.sets.iter().enumerate() {
                        @if index > 0 { br; }
                        (set.label) " (" (set.method.title()) ", " (set.samples.len())
                        " configurations, "
                        @match set.sigma {
                            Some(sigma) => { "σ " (number(sigma * 1e3)) " mm" }
                            None => { "no σ stated" }
                        }
                        ")"
                    }
                }
            }
            tr {
                td { "identified parameters" }
                td {
                    (result.parameters.len())
                    @if !result.auxiliary.is_empty() { " + " (result.auxiliary.len()) " auxiliary" }
                }
            }
            tr {
                td { "error RMS (observations)" }
                td { (number(result.before.rms * 1e3)) " → " (number(result.after.rms * 1e3)) " mm" }
            }
            @if let Some(inliers) = result.after_inliers() {
                tr {
                    td { "error RMS without the " (result.outliers.len()) " outliers" }
                    td { (number(inliers.rms * 1e3)) " mm (largest " (number(inliers.max * 1e3)) " mm)" }
                }
            }
            tr {
                td { "largest error" }
                td { (number(result.before.max * 1e3)) " → " (number(result.after.max * 1e3)) " mm" }
            }
            @if let (Some(before), Some(after)) = (result.before.rms_rotation, result.after.rms_rotation) {
                tr {
                    td { "orientation error RMS" }
                    td { (number(before.to_degrees())) " → " (number(after.to_degrees())) "°" }
                }
            }
            tr { td { "condition number of W" sub { "b" } } td { (number(result.condition_number)) } }
            tr {
                td { "observability O1 · O2 · O3 · O4 · O5 (W" sub { "b" } " of the data scaled to 1 cm, 1°, 1 %)" }
                td { (observability) }
            }
            tr {
                td { "residual standard deviation" }
                td {
                    @if let Some(length) = verdict.residual_length { (number(length * 1e3)) " mm" }
                    @if verdict.residual_length.is_some() && verdict.residual_angle.is_some() { ", " }
                    @if let Some(angle) = verdict.residual_angle { (number(angle.to_degrees())) "°" }
                    @if let Some(test) = verdict.noise_test {
                        " (" (number(test.sigma_ratio)) "× the stated σ)"
                    }
                }
            }
        }
        @if !result.warnings.is_empty() {
            div.warn {
                strong { "Warnings" }
                ul { @for warning in &result.warnings { li { (warning) } } }
            }
        }
    }
}

/// The loss, the prior and the outlier report of `result`.
fn robustness(result: &Identification) -> Markup {
    html! {
        h2 { "Measurements as they are" }
        p {
            "Loss " strong { (result.loss) }
            @if result.reweightings > 0 { " after " (result.reweightings) " reweightings" }
            "; robust σ̂ of the residuals " (result.robust_sigma_words()) "."
            @if let Some(prior) = &result.prior {
                " Prior around the nominal values: " (prior) " (maximum a posteriori; σ is posterior)."
            }
        }
        (outlier_table("Rejected before this fit", &result.rejected, result.outlier_threshold))
        (outlier_table("Outliers", &result.outliers, result.outlier_threshold))
        @if result.outliers.is_empty() {
            p.muted {
                "No outliers: every observation is within " (result.outlier_threshold) " robust σ̂."
            }
        }
    }
}

/// Outliers a report lists (worst first); it counts them all.
const LISTED_OUTLIERS: usize = 100;

fn outlier_table(title: &str, outliers: &[Outlier], threshold: f64) -> Markup {
    let listed = &outliers[..outliers.len().min(LISTED_OUTLIERS)];
    html! {
        @if !outliers.is_empty() {
            p {
                strong { (title) }
                " (" (outliers.len()) " beyond " (threshold) " robust σ̂; ringed on the per-configuration plot"
                @if listed.len() < outliers.len() { "; the worst " (listed.len()) " listed" }
                "):"
            }
            table {
                tr { th { "observation" } th { "error (mm)" } th { "residual (σ̂)" } th { "weight" } }
                @for outlier in listed {
                    tr {
                        td { (outlier.location.describe()) }
                        td { (format!("{:.3}", outlier.error * 1e3)) }
                        td { (format!("{:.1}", outlier.standardized)) }
                        td { (format!("{:.3}", outlier.weight)) }
                    }
                }
            }
        }
    }
}

/// The identified parameters, and those outside the base set that moved.
fn parameters(result: &Identification) -> Markup {
    let with_prior = result.prior.is_some();
    html! {
        h2 { "Identified parameters" }
        table {
            tr {
                th { "parameter" } th { "nominal" } th { "identified" } th { "deviation" } th { "σ" }
                @if with_prior { th { "noise σ" } th { "prior σ" } }
                th { "the deviation stands for" }
            }
            @for parameter in result.parameters.iter().chain(&result.auxiliary) {
                tr class=[parameter.is_regrouped().then_some("z")] {
                    td { (parameter.name) }
                    td { (number(parameter.nominal)) }
                    td { (number(parameter.identified)) }
                    td { (format!("{:+.3e}", parameter.identified - parameter.nominal)) }
                    td { (format!("{:.2e}", parameter.std)) }
                    @if with_prior {
                        td { (format!("{:.2e}", parameter.noise_std)) }
                        td { (parameter.prior_std.map_or("–".into(), |s| format!("{s:.2e}"))) }
                    }
                    td {
                        @match parameter.combination() {
                            Some(combination) => { "regrouped: " (combination) }
                            None => { "itself" }
                        }
                    }
                }
            }
        }
        p.muted {
            "Metres and radians; gains without unit. A regrouped parameter (grey) absorbs others \
             (Appendix III): its deviation is the combination shown, not a physical value."
        }
        @if !result.moved.is_empty() {
            p {
                "Parameters outside the base set that had to move: "
                (result.moved.iter().map(|p| format!("{} {:+.3e}", p.name, p.identified - p.nominal)).collect::<Vec<_>>().join(", "))
            }
        }
    }
}

/// The status of every parameter in the frame × kind grid, and the
/// regrouping relations.
fn identifiable(robot: &Robot, rank: &RankReport) -> Markup {
    let cell = |frame: usize, kind: ParameterKind| {
        let id = ParameterId::new(kind, frame);
        match rank
            .parameters
            .iter()
            .find(|p| p.parameter == Some(id))
            .map(|p| p.status)
        {
            Some(ParameterStatus::Identifiable) => ("id", "id"),
            Some(ParameterStatus::Regrouped) => ("n", "n"),
            Some(ParameterStatus::NoEffect) => ("z", "0"),
            Some(ParameterStatus::Excluded) => ("z", "–"),
            None => ("", ""),
        }
    };
    html! {
        h2 { "Identifiable parameters" }
        p.muted {
            "id = identified, n = regrouped on others, 0 = no effect, – = excluded (priority 0); \
             structural analysis on random configurations like the data (Appendix III)."
        }
        table {
            tr {
                th { "j" } th { "α" } th { "d" } th { "θ" } th { "r" } th { "β" } th { "K" }
                // An elastic robot's compliances (joints 1..n).
                @if robot.is_elastic() { th { "c" } }
            }
            @for frame in 0..robot.frames().len() {
                tr {
                    td { (frame) }
                    @for kind in ParameterKind::ALL {
                        @let (class, text) = cell(frame, kind);
                        td class=(class) { (text) }
                    }
                    @if robot.is_elastic() {
                        @let (class, text) = cell(frame, ParameterKind::Compliance);
                        td class=(class) { (text) }
                    }
                }
            }
        }
        p {
            (rank.count()) " identifiable parameters; condition number of W" sub { "b" }
            " on random configurations " (number(rank.condition_number())) "."
        }
        @if !rank.relations().is_empty() {
            details {
                summary { "Regrouping relations (eq. 32)" }
                ul {
                    @for relation in rank.relations() {
                        li {
                            code {
                                (relation.base) "_b = " (relation.base) " "
                                (relation.absorbed.iter().map(|(name, coefficient)| format!("{coefficient:+.4}·{name}")).collect::<Vec<_>>().join(" "))
                            }
                        }
                    }
                }
            }
        }
    }
}

/// The robot's table.
fn robot_table(robot: &Robot) -> Markup {
    html! {
        table {
            tr {
                th { "j" } th { "σ" } th { "α" } th { "d" } th { "θ" } th { "r" } th { "β" }
                th { "K" } th { "qmin" } th { "qmax" }
            }
            @for (j, frame) in robot.frames().iter().enumerate() {
                @let joint = (j >= 1 && j <= robot.joint_count()).then(|| robot.joints()[j - 1]);
                tr {
                    td { (j) }
                    td { (frame.frame_type.sigma()) }
                    td { (number(frame.alpha)) }
                    td { (number(frame.d)) }
                    td { (number(frame.theta)) }
                    td { (number(frame.r)) }
                    td { (number(frame.beta)) }
                    td { (joint.map_or_else(|| "–".into(), |joint| number(joint.gain))) }
                    td { (joint.map_or_else(|| "–".into(), |joint| number(joint.qmin))) }
                    td { (joint.map_or_else(|| "–".into(), |joint| number(joint.qmax))) }
                }
            }
        }
    }
}
