//! The report of ISO 9283's acceptance test: one self-contained HTML file
//! (as the calibration report) with the conditions, the characteristics
//! per pose before and after calibration, a view of the cube with the
//! attained positions, and a bullseye per pose. Lengths in millimetres and
//! angles in degrees, for people; the JSON of `gecaro iso9283 evaluate`
//! keeps metres and radians.

use gecaro_calib::iso9283::{PoseResult, Registration, TestCube, TestEvaluation};
use maud::{Markup, PreEscaped, html};
use plotters::prelude::*;

use crate::Error;
use crate::page::page;
use crate::plots::{AFTER, BEFORE, FONT, plot_error, svg};

/// One measured file of the test.
#[derive(Debug)]
pub struct MeasuredInput<'a> {
    /// Its name.
    pub label: &'a str,
    /// Its characteristics.
    pub evaluation: &'a TestEvaluation,
}

/// What the acceptance report is made of.
#[derive(Debug)]
pub struct AcceptanceInput<'a> {
    /// The robot, when known.
    pub robot: Option<&'a str>,
    /// The test's program.
    pub program: &'a str,
    /// Before calibration (or the only measurement).
    pub before: MeasuredInput<'a>,
    /// After calibration.
    pub after: Option<MeasuredInput<'a>>,
    /// The conditions: name and the value stated.
    pub conditions: &'a [(&'a str, Option<&'a str>)],
    /// What a reader should know.
    pub warnings: &'a [String],
    /// The command that made the report.
    pub command: &'a str,
}

/// `value` with four decimals, without the sign of a value that rounds to 0
/// (`-0.0000` says nothing a reader can use): the report's millimetres and
/// degrees, and the command line's.
pub fn four_decimals(value: f64) -> String {
    let text = format!("{value:.4}");
    if text
        .trim_start_matches('-')
        .bytes()
        .all(|b| b == b'0' || b == b'.')
    {
        text.trim_start_matches('-').to_owned()
    } else {
        text
    }
}

fn mm(value: f64) -> String {
    four_decimals(value * 1e3)
}

fn degrees(value: f64) -> String {
    four_decimals(value.to_degrees())
}

/// A bullseye of one pose: the attained positions (x–y of the base frame)
/// about their barycentre (µm), the circle of RP_l.
fn bullseye_svg(pose: &PoseResult, colour: RGBColor) -> Result<String, Error> {
    let centre = pose.characteristics.barycentre;
    let radius = pose.characteristics.repeatability * 1e6;
    let points: Vec<(f64, f64)> = pose
        .attained
        .iter()
        .map(|x| ((x.x - centre.x) * 1e6, (x.y - centre.y) * 1e6))
        .collect();
    let reach = points
        .iter()
        .map(|(x, y)| x.abs().max(y.abs()))
        .fold(radius, f64::max)
        .max(1e-3)
        * 1.15;
    svg(230, 230, |root| {
        let mut chart = ChartBuilder::on(&root)
            .caption(format!("P{} (µm)", pose.pose), (FONT, 13))
            .margin(6)
            .x_label_area_size(20)
            .y_label_area_size(34)
            .build_cartesian_2d(-reach..reach, -reach..reach)
            .map_err(plot_error)?;
        chart
            .configure_mesh()
            .x_labels(4)
            .y_labels(4)
            .x_label_formatter(&|v| format!("{v:.1}"))
            .y_label_formatter(&|v| format!("{v:.1}"))
            .label_style((FONT, 9))
            .draw()
            .map_err(plot_error)?;
        let circle: Vec<(f64, f64)> = (0..=72)
            .map(|k| {
                let angle = f64::from(k) * std::f64::consts::TAU / 72.0;
                (radius * angle.cos(), radius * angle.sin())
            })
            .collect();
        chart
            .draw_series(LineSeries::new(circle, BLACK.stroke_width(1)))
            .map_err(plot_error)?;
        chart
            .draw_series(
                points
                    .iter()
                    .map(|point| Circle::new(*point, 2, colour.filled())),
            )
            .map_err(plot_error)?;
        Ok(())
    })
}

/// The cube seen along its (−1, −1, −1) diagonal's side (an oblique
/// projection): its edges, the commanded poses, and each barycentre's
/// error drawn `scale` times larger.
fn cube_svg(evaluation: &TestEvaluation, side: f64) -> Result<(String, f64), Error> {
    let commanded: Vec<nalgebra::Vector3<f64>> = evaluation
        .poses
        .iter()
        .map(|pose| pose.commanded.translation.vector)
        .collect();
    let centre = commanded
        .first()
        .copied()
        .unwrap_or_else(nalgebra::Vector3::zeros);
    let project = |p: nalgebra::Vector3<f64>| {
        let d = p - centre;
        (d.x - 0.5 * d.y, d.z - 0.35 * d.y)
    };
    let h = side / 2.0;
    let corner = |bits: usize| {
        centre
            + nalgebra::Vector3::new(
                if bits & 1 == 1 { h } else { -h },
                if bits & 2 == 2 { h } else { -h },
                if bits & 4 == 4 { h } else { -h },
            )
    };
    let largest = evaluation
        .poses
        .iter()
        .map(|pose| pose.characteristics.accuracy)
        .fold(0.0, f64::max);
    // The largest error drawn at 12–30 % of the side, by a round factor
    // (1, 2 or 5 times a power of ten).
    let scale = if largest > 0.0 {
        let raw = 0.3 * side / largest;
        let decade = 10f64.powf(raw.log10().floor());
        [5.0, 2.0, 1.0]
            .into_iter()
            .map(|step| step * decade)
            .find(|scale| *scale <= raw)
            .unwrap_or(decade)
    } else {
        1.0
    };
    // The side is read from P2–P4; a program whose poses are not that
    // cube's (edited, or another test) is drawn without the cube's edges.
    let is_cube = evaluation.poses.len() == 5
        && TestCube::new(centre, side).is_ok_and(|cube| {
            cube.poses()
                .iter()
                .zip(&commanded)
                .all(|(expected, at)| (expected - at).norm() < 1e-6)
        });
    let caption = if is_cube {
        format!("The cube (side {} mm), errors × {scale}", mm(side))
    } else {
        format!("The commanded poses (not a test cube's), errors × {scale}")
    };
    let reach = side * 1.1;
    let text = svg(420, 380, |root| {
        let mut chart = ChartBuilder::on(&root)
            .caption(caption, (FONT, 13))
            .margin(8)
            .build_cartesian_2d(-reach..reach, -reach..reach)
            .map_err(plot_error)?;
        for a in (0..8usize).filter(|_| is_cube) {
            for bit in [1, 2, 4] {
                if a & bit == 0 {
                    let (from, to) = (project(corner(a)), project(corner(a | bit)));
                    chart
                        .draw_series(LineSeries::new([from, to], RGBColor(160, 170, 180)))
                        .map_err(plot_error)?;
                }
            }
        }
        for pose in &evaluation.poses {
            let at = pose.commanded.translation.vector;
            let error = pose.characteristics.barycentre - at;
            chart
                .draw_series(std::iter::once(Circle::new(project(at), 4, BLACK.filled())))
                .map_err(plot_error)?;
            chart
                .draw_series(LineSeries::new(
                    [project(at), project(at + scale * error)],
                    BEFORE.stroke_width(2),
                ))
                .map_err(plot_error)?;
            // The repeatability sphere about the barycentre, at the same scale
            // (its outline in the drawing's plane).
            let (cx, cy) = project(at + scale * error);
            let radius = scale * pose.characteristics.repeatability;
            let outline: Vec<(f64, f64)> = (0..=48)
                .map(|k| {
                    let angle = f64::from(k) * std::f64::consts::TAU / 48.0;
                    (cx + radius * angle.cos(), cy + radius * angle.sin())
                })
                .collect();
            chart
                .draw_series(LineSeries::new(outline, AFTER.stroke_width(1)))
                .map_err(plot_error)?;
            let (x, y) = project(at);
            chart
                .draw_series(std::iter::once(Text::new(
                    format!("P{}", pose.pose),
                    (x + 0.03 * side, y + 0.03 * side),
                    (FONT, 12),
                )))
                .map_err(plot_error)?;
        }
        Ok(())
    })?;
    Ok((text, scale))
}

/// The table of one measured file's characteristics.
fn characteristics(measured: &MeasuredInput<'_>) -> Markup {
    let evaluation = measured.evaluation;
    let oriented = evaluation.oriented;
    html! {
        table {
            tr {
                th { "pose" } th { "cycles" } th { "AP_P (mm)" } th { "AP_x, AP_y, AP_z (mm)" }
                @if oriented { th { "AP_a, AP_b, AP_c (°)" } }
                th { "RP_l (mm)" }
                @if oriented { th { "RP_a, RP_b, RP_c (± °)" } }
                @if evaluation.directions > 1 { th { "vAP_P (mm)" } }
            }
            @for pose in &evaluation.poses {
                @let c = &pose.characteristics;
                tr {
                    td { "P" (pose.pose) }
                    td { (c.cycles) }
                    td { (mm(c.accuracy)) }
                    td { (mm(c.accuracy_components.x)) ", " (mm(c.accuracy_components.y)) ", " (mm(c.accuracy_components.z)) }
                    @if oriented {
                        td { (c.orientation_accuracy.map(degrees).join(", ")) }
                    }
                    td { (mm(c.repeatability)) }
                    @if oriented {
                        td { (c.orientation_repeatability.map(degrees).join(", ")) }
                    }
                    @if evaluation.directions > 1 {
                        td { (pose.variation.as_ref().map_or("–".into(), |v| mm(v.position))) }
                    }
                }
            }
        }
        @if let Some(distance) = &evaluation.distance {
            p {
                "Distance P2–P4 (7.3): commanded " (mm(distance.commanded)) " mm, mean attained "
                (mm(distance.mean)) " mm; AD " (mm(distance.accuracy)) " mm, RD ±"
                (mm(distance.repeatability)) " mm."
            }
        }
    }
}

/// How a file's measurement frame was registered, in words.
fn registration(evaluation: &TestEvaluation) -> String {
    let p = evaluation.frame.translation.vector;
    let at = format!("at ({}, {}, {}) mm", mm(p.x), mm(p.y), mm(p.z));
    match evaluation.registration {
        Registration::Base => "the measurements are in the robot's base frame".into(),
        Registration::Stated(_) => format!("the instrument's stated pose, {at}"),
        Registration::BestFit => format!(
            "a best fit of the poses' barycentres onto the commanded positions, {at} (AP \
             excludes the rigid part of the robot's error)"
        ),
    }
}

/// The acceptance report (see the module docs).
///
/// # Errors
/// [`Error::Plot`] if a plot cannot be drawn.
pub fn acceptance_report(input: &AcceptanceInput<'_>) -> Result<String, Error> {
    let shown = input.after.as_ref().unwrap_or(&input.before);
    let side = {
        let poses = &shown.evaluation.poses;
        match (
            poses.iter().find(|p| p.pose == 2),
            poses.iter().find(|p| p.pose == 4),
        ) {
            // P2–P4 is 0.8 of a space diagonal, √3·0.8·s.
            (Some(p2), Some(p4)) => {
                (p2.commanded.translation.vector - p4.commanded.translation.vector).norm()
                    / (0.8 * 3f64.sqrt())
            }
            _ => 0.1,
        }
    };
    let (cube, scale) = cube_svg(shown.evaluation, side)?;
    let mut bullseyes = String::new();
    for pose in &shown.evaluation.poses {
        let colour = if input.after.is_some() { AFTER } else { BEFORE };
        bullseyes.push_str(&bullseye_svg(pose, colour)?);
    }
    let worst = |measured: &MeasuredInput<'_>| {
        (
            measured.evaluation.worst_accuracy(),
            measured.evaluation.worst_repeatability(),
        )
    };
    let body = html! {
        h1 { "Acceptance test (ISO 9283)" }
        p.muted {
            @if let Some(robot) = input.robot { (robot) " — " }
            "program " code { (input.program) } " — made by " code { (input.command) }
        }
        @for warning in input.warnings { p.warn { (warning) } }
        h2 { "Summary" }
        table {
            tr { th { "" } th { "measured" } th { "largest AP_P (mm)" } th { "largest RP_l (mm)" } th { "measurement frame" } }
            @for (name, measured) in std::iter::once(("before", &input.before)).chain(input.after.as_ref().map(|after| ("after", after))) {
                @let (ap, rp) = worst(measured);
                tr {
                    td { (if input.after.is_some() { name } else { "test" }) }
                    td { (measured.label) }
                    td { (mm(ap)) }
                    td { (mm(rp)) }
                    td { (registration(measured.evaluation)) }
                }
            }
        }
        h2 { "Conditions" }
        table {
            @for (name, value) in input.conditions {
                tr { td { (name) } td { (value.unwrap_or("not stated")) } }
            }
        }
        @for (name, measured) in std::iter::once(("Before calibration", &input.before)).chain(input.after.as_ref().map(|after| ("After calibration", after))) {
            h2 { (if input.after.is_some() { name } else { "Characteristics" }) " — " (measured.label) }
            (characteristics(measured))
        }
        h2 { "The cube and the errors" }
        p.muted {
            "Commanded poses (black), each barycentre's error drawn " (scale) " times larger (red), \
             and the sphere of RP_l about it at the same scale (blue)"
            @if input.after.is_some() { ", after calibration" } "."
        }
        (PreEscaped(cube))
        h2 { "Repeatability: the attained positions about their barycentre" }
        p.muted { "x–y of the base frame, µm; the circle is RP_l." }
        div { (PreEscaped(bullseyes)) }
        p.muted {
            "ISO 9283 clause 7 as gecaro implements it: docs/iso9283.md. Lengths in mm, \
             angles in degrees."
        }
    };
    Ok(page("gecaro — ISO 9283 acceptance test", body))
}
