//! The HTML report: one file with everything inline (SVG plots, CSS), to
//! archive with a calibration and to read without a network.

use gecaro_calib::{
    identifiability::ParameterStatus,
    identification::{Identification, Route, StopReason},
    study::Study,
};
use gecaro_core::{FrameType, ParameterId, ParameterKind};
use std::fmt::Write as _;

use crate::Error;
use crate::plots::{
    convergence_svg, error_histograms_svg, errors_per_configuration_svg, robot_projections_svg,
};

/// What a report is made of.
#[derive(Debug)]
pub struct ReportInput<'a> {
    /// The nominal robot.
    pub robot: &'a gecaro_core::Robot,
    /// The measurements.
    pub study: &'a Study,
    /// The identification of the robot from them.
    pub identification: &'a Identification,
    /// The command line that produced the report.
    pub command: &'a str,
}

const STYLE: &str = "body{font-family:system-ui,-apple-system,'Segoe UI',sans-serif;max-width:980px;margin:2rem auto;\
padding:0 1rem;color:#1d2630;line-height:1.45}h1{margin-bottom:.2rem}h2{margin-top:2rem;border-bottom:1px solid #d8dee6;\
padding-bottom:.2rem}table{border-collapse:collapse;margin:.6rem 0;font-size:.92rem}td,th{border:1px solid #d8dee6;\
padding:.25rem .6rem;text-align:right}th{background:#f2f5f8}td:first-child,th:first-child{text-align:left}\
.muted{color:#5b6775}.ok{color:#1a7f37}.bad{color:#b42318}code{background:#f2f5f8;padding:.1rem .3rem;border-radius:3px}\
.warn{background:#fff6e5;border:1px solid #f0c36d;padding:.5rem .8rem;border-radius:4px}.id{background:#e8f3ec}\
.n{background:#fbeeee}.z{background:#f2f2f2}svg{max-width:100%;height:auto}";

/// Escapes text for HTML.
fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

fn number(value: f64) -> String {
    if value == 0.0 {
        "0".into()
    } else if value.abs() >= 1e-3 && value.abs() < 1e4 {
        let text = format!("{value:.6}");
        text.trim_end_matches('0').trim_end_matches('.').to_owned()
    } else {
        format!("{value:.3e}")
    }
}

/// The report of an identification (see the module docs).
///
/// # Errors
/// [`Error::Plot`] if a plot cannot be drawn.
pub fn html_report(input: &ReportInput<'_>) -> Result<String, Error> {
    let robot = input.robot;
    let result = input.identification;
    let mut html = String::new();
    let methods = input.study.method_names();
    let _ = write!(
        html,
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\
         <title>gecaro report — {name}, {methods}</title><style>{STYLE}</style></head><body>\n\
         <h1>Calibration report</h1><p class=\"muted\">{name} ({joints} joints, {letters}) — {methods} — made by \
         <code>{command}</code></p>\n",
        name = escape(robot.name()),
        joints = robot.joint_count(),
        letters = robot.joint_letters(),
        methods = escape(&methods),
        command = escape(input.command),
    );

    // Summary.
    let converged = result.stop_reason == StopReason::Converged;
    let route = match result.route {
        Route::GaussNewton => "plain Gauss–Newton (the paper's scheme)",
        Route::MinimumNorm => "minimum-norm steps, then continuation to the base set",
        Route::LevenbergMarquardt => "Levenberg–Marquardt",
    };
    let _ = write!(
        html,
        "<h2>Summary</h2><table>\
         <tr><td>result</td><td class=\"{class}\">{status} after {iterations} iterations ({route})</td></tr>\
         <tr><td>data</td><td>{data}</td></tr>\
         <tr><td>identified parameters</td><td>{count}{aux}</td></tr>\
         <tr><td>error RMS (observations)</td><td>{before} → {after} mm</td></tr>\
         <tr><td>largest error</td><td>{before_max} → {after_max} mm</td></tr>{rotation}\
         <tr><td>condition number of W<sub>b</sub></td><td>{condition}</td></tr>\
         <tr><td>observability O1 · O2 · O3 · O4 · O5 (W<sub>b</sub> of the data scaled to 1 cm, 1°, 1 %)</td><td>{observability}</td></tr>\
         <tr><td>residual standard deviation σ</td><td>{sigma}</td></tr></table>",
        class = if converged { "ok" } else { "bad" },
        status = if converged {
            "converged"
        } else {
            "NOT converged"
        },
        iterations = result.iterations(),
        data = input
            .study
            .sets
            .iter()
            .map(|set| format!(
                "{} ({}, {} configurations, σ {})",
                escape(&set.label),
                set.method.title(),
                set.samples.len(),
                set.sigma
            ))
            .collect::<Vec<_>>()
            .join("<br>"),
        count = result.parameters.len(),
        aux = if result.auxiliary.is_empty() {
            String::new()
        } else {
            format!(" + {} auxiliary", result.auxiliary.len())
        },
        before = number(result.before.rms * 1e3),
        after = number(result.after.rms * 1e3),
        before_max = number(result.before.max * 1e3),
        after_max = number(result.after.max * 1e3),
        rotation = match (result.before.rms_rotation, result.after.rms_rotation) {
            (Some(before), Some(after)) => format!(
                "<tr><td>orientation error RMS</td><td>{} → {}°</td></tr>",
                number(before.to_degrees()),
                number(after.to_degrees())
            ),
            _ => String::new(),
        },
        condition = number(result.condition_number),
        observability = {
            let o = result.observability();
            [o.o1, o.o2, o.o3, o.o4, o.o5].map(number).join(" · ")
        },
        sigma = number(result.residual_sigma),
    );
    if !result.warnings.is_empty() {
        html.push_str("<div class=\"warn\"><strong>Warnings</strong><ul>");
        for warning in &result.warnings {
            let _ = write!(html, "<li>{}</li>", escape(warning));
        }
        html.push_str("</ul></div>\n");
    }

    robustness(&mut html, result);

    // Plots.
    let lengths = |errors: &[(f64, f64)]| errors.iter().map(|e| e.0 * 1e3).collect::<Vec<f64>>();
    let (before, after) = (
        lengths(&result.errors_before),
        lengths(&result.errors_after),
    );
    let _ = write!(
        html,
        "<h2>Convergence</h2>{}\n<h2>Errors before and after</h2><p class=\"muted\">Per configuration: distance to the \
         measured point, to the mean point of its set, to the plane, or distance error of a pair (mm).</p>{}\n{}\n",
        convergence_svg(&result.history)?,
        error_histograms_svg(&before, &after, "mm")?,
        errors_per_configuration_svg(&before, &after, &result.outlier_observations(), "mm")?,
    );

    // Identified parameters.
    html.push_str(
        "<h2>Identified parameters</h2><table><tr><th>parameter</th><th>nominal</th><th>identified</th>\
         <th>deviation</th><th>σ</th>",
    );
    if result.prior.is_some() {
        html.push_str("<th>prior σ</th>");
    }
    html.push_str("</tr>");
    for parameter in result.parameters.iter().chain(&result.auxiliary) {
        let _ = write!(
            html,
            "<tr><td>{}</td><td>{}</td><td>{}</td><td>{:+.3e}</td><td>{:.2e}</td>",
            escape(&parameter.name),
            number(parameter.nominal),
            number(parameter.identified),
            parameter.identified - parameter.nominal,
            parameter.std
        );
        if result.prior.is_some() {
            let prior = parameter
                .prior_std
                .map_or("–".into(), |s| format!("{s:.2e}"));
            let _ = write!(html, "<td>{prior}</td>");
        }
        html.push_str("</tr>");
    }
    html.push_str("</table><p class=\"muted\">Metres and radians; gains without unit.</p>\n");
    if !result.moved.is_empty() {
        html.push_str("<p>Parameters outside the base set that had to move: ");
        let moved: Vec<String> = result
            .moved
            .iter()
            .map(|p| format!("{} {:+.3e}", escape(&p.name), p.identified - p.nominal))
            .collect();
        let _ = writeln!(html, "{}</p>", moved.join(", "));
    }

    // Identifiable parameters.
    let rank = &result.rank;
    html.push_str(
        "<h2>Identifiable parameters</h2><p class=\"muted\">id = identified, n = regrouped on others, 0 = no effect, \
         – = excluded (priority 0); structural analysis on random configurations like the data (Appendix III).</p>\
         <table><tr><th>j</th><th>α</th><th>d</th><th>θ</th><th>r</th><th>β</th><th>K</th></tr>",
    );
    for frame in 0..robot.frames().len() {
        let _ = write!(html, "<tr><td>{frame}</td>");
        for kind in ParameterKind::ALL {
            let id = ParameterId::new(kind, frame);
            let cell = rank
                .parameters
                .iter()
                .find(|p| p.parameter == Some(id))
                .map(|p| p.status);
            let (class, text) = match cell {
                Some(ParameterStatus::Identifiable) => ("id", "id"),
                Some(ParameterStatus::Regrouped) => ("n", "n"),
                Some(ParameterStatus::NoEffect) => ("z", "0"),
                Some(ParameterStatus::Excluded) => ("z", "–"),
                None => ("", ""),
            };
            let _ = write!(html, "<td class=\"{class}\">{text}</td>");
        }
        html.push_str("</tr>");
    }
    let _ = write!(
        html,
        "</table><p>{} identifiable parameters; condition number of W<sub>b</sub> on random configurations {}.</p>",
        rank.count(),
        number(rank.condition_number())
    );
    if !rank.relations().is_empty() {
        html.push_str("<details><summary>Regrouping relations (eq. 32)</summary><ul>");
        for relation in rank.relations() {
            let terms: Vec<String> = relation
                .absorbed
                .iter()
                .map(|(name, coefficient)| format!("{coefficient:+.4}·{}", escape(name)))
                .collect();
            let _ = write!(
                html,
                "<li><code>{0}_b = {0} {1}</code></li>",
                escape(&relation.base),
                terms.join(" ")
            );
        }
        html.push_str("</ul></details>\n");
    }

    // The robot.
    html.push_str(
        "<h2>Robot (nominal)</h2><table><tr><th>j</th><th>σ</th><th>α</th><th>d</th><th>θ</th><th>r</th><th>β</th>\
         <th>K</th><th>qmin</th><th>qmax</th></tr>",
    );
    for (j, frame) in robot.frames().iter().enumerate() {
        let joint = (j >= 1 && j <= robot.joint_count()).then(|| robot.joints()[j - 1]);
        let _ = write!(
            html,
            "<tr><td>{j}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
            frame.frame_type.sigma(),
            number(frame.alpha),
            number(frame.d),
            number(frame.theta),
            number(frame.r),
            number(frame.beta),
            joint.map_or_else(|| "–".into(), |joint| number(joint.gain)),
            joint.map_or_else(|| "–".into(), |joint| number(joint.qmin)),
            joint.map_or_else(|| "–".into(), |joint| number(joint.qmax)),
        );
    }
    html.push_str("</table>");
    let middle: Vec<f64> = robot
        .joints()
        .iter()
        .map(|joint| 0.5 * (joint.qmin + joint.qmax))
        .collect();
    if let Ok(motor) = robot.motor_positions(&middle) {
        let frames = robot
            .frames()
            .iter()
            .filter(|f| f.frame_type != FrameType::Fixed)
            .count();
        let _ = write!(
            html,
            "<p class=\"muted\">Calibrated robot at the middle of its {frames} joint ranges (origins of frames 0..n+1, m):</p>{}",
            robot_projections_svg(&result.calibrated, motor.as_slice())?
        );
    }
    html.push_str("\n<p class=\"muted\">gecaro — geometric calibration of serial robots (GECARO, Khalil et al.).</p></body></html>\n");
    Ok(html)
}

/// The loss, the prior and the outlier report of `result`.
fn robustness(html: &mut String, result: &Identification) {
    html.push_str("<h2>Measurements as they are</h2><p>");
    let _ = write!(
        html,
        "Loss <strong>{}</strong>{}; robust σ̂ of the residuals {:.3e} (units of the sensor σ).",
        escape(&result.loss.to_string()),
        if result.reweightings > 0 {
            format!(" after {} reweightings", result.reweightings)
        } else {
            String::new()
        },
        result.robust_sigma
    );
    if let Some(prior) = &result.prior {
        let _ = write!(
            html,
            " Prior around the nominal values: {} (maximum a posteriori; σ is posterior).",
            escape(&prior.to_string())
        );
    }
    html.push_str("</p>\n");
    for (title, outliers) in [
        ("Rejected before this fit", &result.rejected),
        ("Outliers", &result.outliers),
    ] {
        if outliers.is_empty() {
            continue;
        }
        let _ = write!(
            html,
            "<p><strong>{title}</strong> (beyond {} robust σ̂; ringed on the per-configuration plot):</p>\
             <table><tr><th>observation</th><th>error (mm)</th><th>residual (σ̂)</th><th>weight</th></tr>",
            result.outlier_threshold
        );
        for outlier in outliers {
            let _ = write!(
                html,
                "<tr><td>{}</td><td>{:.3}</td><td>{:.1}</td><td>{:.3}</td></tr>",
                escape(&outlier.location()),
                outlier.error * 1e3,
                outlier.standardized,
                outlier.weight
            );
        }
        html.push_str("</table>\n");
    }
    if result.outliers.is_empty() {
        let _ = writeln!(
            html,
            "<p class=\"muted\">No outliers: every observation is within {} robust σ̂.</p>",
            result.outlier_threshold
        );
    }
}
