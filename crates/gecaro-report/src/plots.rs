//! The plots of a calibration, as SVG text (plotters' SVG backend with the
//! bundled DejaVu Sans, so no system font is needed and the SVG shows the same
//! everywhere).

use gecaro_calib::{
    curve::CurvePoint,
    identification::{
        Identification, IterationRecord, ObservationErrors, ObservationLocation,
        locate_observations,
    },
    study::Study,
};
use gecaro_core::{Robot, forward_kinematics};
use plotters::prelude::*;
use std::sync::Once;

use crate::Error;

const WIDTH: u32 = 720;
const HEIGHT: u32 = 340;
pub(crate) const BEFORE: RGBColor = RGBColor(214, 39, 40);
pub(crate) const AFTER: RGBColor = RGBColor(31, 119, 180);
pub(crate) const FONT: &str = "sans-serif";

/// Registers the bundled font once per process.
fn fonts() {
    static REGISTER: Once = Once::new();
    REGISTER.call_once(|| {
        // DejaVu Sans is a valid font; registration only fails for invalid bytes.
        let _ = plotters::style::register_font(FONT, FontStyle::Normal, dejavu::sans::regular());
        let _ = plotters::style::register_font(FONT, FontStyle::Bold, dejavu::sans::bold());
    });
}

pub(crate) fn plot_error(error: impl std::fmt::Display) -> Error {
    Error::Plot(error.to_string())
}

/// Renders into an SVG string with `draw`.
pub(crate) fn svg(
    width: u32,
    height: u32,
    draw: impl FnOnce(DrawingArea<SVGBackend<'_>, plotters::coord::Shift>) -> Result<(), Error>,
) -> Result<String, Error> {
    fonts();
    let mut text = String::new();
    {
        let root = SVGBackend::with_string(&mut text, (width, height)).into_drawing_area();
        root.fill(&WHITE).map_err(plot_error)?;
        draw(root.clone())?;
        root.present().map_err(plot_error)?;
    }
    Ok(text)
}

/// The residual RMS of every iteration (log scale): how identification converged.
///
/// # Errors
/// [`Error::Plot`] if drawing fails.
pub fn convergence_svg(history: &[IterationRecord]) -> Result<String, Error> {
    convergence_in(history, 1.0, "residual RMS")
}

/// [`convergence_svg`] with the RMS multiplied by `scale` and the y axis
/// labelled `label`.
fn convergence_in(history: &[IterationRecord], scale: f64, label: &str) -> Result<String, Error> {
    let values: Vec<f64> = history.iter().map(|h| (h.rms * scale).max(1e-18)).collect();
    let largest = values.iter().copied().fold(f64::MIN_POSITIVE, f64::max) * 2.0;
    let smallest = values
        .iter()
        .copied()
        .fold(f64::INFINITY, f64::min)
        .min(largest / 10.0)
        / 2.0;
    let last = values.len().saturating_sub(1).max(1);
    svg(WIDTH, HEIGHT, |root| {
        let mut chart = ChartBuilder::on(&root)
            .caption("Convergence: residual RMS per iteration", (FONT, 18))
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(70)
            .build_cartesian_2d(0..last, (smallest..largest).log_scale())
            .map_err(plot_error)?;
        chart
            .configure_mesh()
            .x_desc("iteration")
            .y_desc(label)
            .x_labels(last.min(12) + 1)
            .y_label_formatter(&|v| format!("{v:.0e}"))
            .label_style((FONT, 13))
            .draw()
            .map_err(plot_error)?;
        chart
            .draw_series(LineSeries::new(
                values.iter().enumerate().map(|(i, v)| (i, *v)),
                AFTER.stroke_width(2),
            ))
            .map_err(plot_error)?;
        chart
            .draw_series(
                values
                    .iter()
                    .enumerate()
                    .map(|(i, v)| Circle::new((i, *v), 4, AFTER.filled())),
            )
            .map_err(plot_error)?;
        Ok(())
    })
}

/// One histogram panel of errors (millimetres or degrees).
fn histogram_panel(
    area: &DrawingArea<SVGBackend<'_>, plotters::coord::Shift>,
    title: &str,
    values: &[f64],
    color: RGBColor,
    unit: &str,
) -> Result<(), Error> {
    const BINS: usize = 20;
    let top = values.iter().copied().fold(0.0, f64::max).max(1e-12);
    let width = top / BINS as f64 * 1.0001;
    let mut counts = [0_u32; BINS];
    for value in values {
        counts[((value / width) as usize).min(BINS - 1)] += 1;
    }
    let highest = counts.iter().copied().max().unwrap_or(1).max(1);
    let mut chart = ChartBuilder::on(area)
        .caption(title, (FONT, 16))
        .margin(10)
        .x_label_area_size(38)
        .y_label_area_size(45)
        .build_cartesian_2d(0.0..width * BINS as f64, 0..highest + highest / 10 + 1)
        .map_err(plot_error)?;
    chart
        .configure_mesh()
        .disable_x_mesh()
        .x_desc(unit)
        .y_desc("configurations")
        .x_labels(6)
        .x_label_formatter(&|v| short(*v))
        .label_style((FONT, 12))
        .draw()
        .map_err(plot_error)?;
    chart
        .draw_series(counts.iter().enumerate().map(|(bin, count)| {
            let left = bin as f64 * width;
            Rectangle::new(
                [(left, 0), (left + width * 0.92, *count)],
                color.mix(0.8).filled(),
            )
        }))
        .map_err(plot_error)?;
    Ok(())
}

/// A compact axis label: three significant digits, no trailing zeros.
pub(crate) fn short(value: f64) -> String {
    let magnitude = value.abs();
    if magnitude == 0.0 {
        return "0".into();
    }
    if !(1e-3..1e5).contains(&magnitude) {
        return format!("{value:.0e}");
    }
    let decimals = (2 - magnitude.log10().floor() as i32).max(0) as usize;
    let text = format!("{value:.decimals$}");
    if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.').to_owned()
    } else {
        text
    }
}

/// The plots of an identification, as SVG.
#[derive(Clone, Debug)]
pub struct IdentificationSvgs {
    /// Residual RMS per iteration, in the units the rows are in: multiples
    /// of the stated σ when every set states one (1 = the noise), else
    /// millimetres (angle rows in mrad).
    pub convergence: String,
    /// Errors before and after (mm); with outliers, "after" holds the
    /// inliers only, so that a few gross errors do not swamp it.
    pub errors_histogram: String,
    /// Every observation's error before and after (mm), outliers ringed.
    pub errors_per_configuration: String,
}

/// The plots of `result`, identified from `study` (the command's report,
/// the web page and Python show the same).
///
/// # Errors
/// [`Error::Plot`] if drawing fails.
pub fn identification_svgs(
    study: &Study,
    result: &Identification,
) -> Result<IdentificationSvgs, Error> {
    let millimetres = |errors: &ObservationErrors| {
        errors
            .lengths
            .iter()
            .map(|length| length * 1e3)
            .collect::<Vec<f64>>()
    };
    let (before, after) = (
        millimetres(&result.errors_before),
        millimetres(&result.errors_after),
    );
    let outliers = result.outlier_observations();
    let mut is_outlier = vec![false; after.len()];
    for index in &outliers {
        if let Some(flag) = is_outlier.get_mut(*index) {
            *flag = true;
        }
    }
    let inliers: Vec<f64> = after
        .iter()
        .zip(&is_outlier)
        .filter(|(_, outlier)| !**outlier)
        .map(|(error, _)| *error)
        .collect();
    let stated = study.sets.iter().all(|set| set.sigma.is_some());
    let convergence = if stated {
        convergence_in(
            &result.history,
            1.0,
            "residual RMS / stated σ (1 = the noise)",
        )?
    } else {
        convergence_in(
            &result.history,
            1e3,
            "residual RMS (mm; angle rows in mrad)",
        )?
    };
    Ok(IdentificationSvgs {
        convergence,
        errors_histogram: error_histograms_svg(&before, &inliers, "mm")?,
        errors_per_configuration: errors_per_configuration_svg(
            &before,
            &after,
            &outliers,
            &observation_names(study),
            "mm",
        )?,
    })
}

/// Where each observation of `study` comes from, as the per-configuration
/// plot's titles name it (`data.csv: configuration 17 (line 19)`).
pub fn observation_names(study: &Study) -> Vec<String> {
    locate_observations(study)
        .iter()
        .map(ObservationLocation::describe)
        .collect()
}

/// Histograms of the per-configuration errors before and after (side by
/// side, each on its own scale: they usually differ by orders of magnitude).
/// `before` and `after` are in the unit of `unit` (e.g. mm).
///
/// # Errors
/// [`Error::Plot`] if drawing fails.
pub fn error_histograms_svg(before: &[f64], after: &[f64], unit: &str) -> Result<String, Error> {
    labelled_error_histograms_svg(
        (before, "before (nominal)"),
        Some((after, "after (calibrated)")),
        unit,
    )
}

/// Histograms of the per-configuration errors of one robot, or of two side
/// by side, each with its caption: an evaluation names the robots it
/// compares (the table's robot need not be the nominal one), and draws one
/// panel when there is nothing to compare with.
///
/// # Errors
/// [`Error::Plot`] if drawing fails.
pub fn labelled_error_histograms_svg(
    first: (&[f64], &str),
    second: Option<(&[f64], &str)>,
    unit: &str,
) -> Result<String, Error> {
    svg(WIDTH, HEIGHT, |root| {
        let Some((after, label)) = second else {
            return histogram_panel(&root, first.1, first.0, BEFORE, unit);
        };
        let (left, right) = root.split_horizontally(WIDTH / 2);
        histogram_panel(&left, first.1, first.0, BEFORE, unit)?;
        histogram_panel(&right, label, after, AFTER, unit)?;
        Ok(())
    })
}

/// The series labels of `chart` in gecaro's style, at `position`.
fn legend<'a, DB, CT>(
    chart: &mut ChartContext<'a, DB, CT>,
    position: SeriesLabelPosition,
) -> Result<(), Error>
where
    DB: DrawingBackend + 'a,
    DB::ErrorType: 'static,
    CT: CoordTranslate,
{
    chart
        .configure_series_labels()
        .position(position)
        .background_style(WHITE.mix(0.9))
        .border_style(BLACK.mix(0.3))
        .label_font((FONT, 13))
        .draw()
        .map_err(plot_error)
}

/// The most points a per-configuration plot draws per series: beyond, the
/// configurations are taken in consecutive groups and each group's largest
/// error is drawn (200,000 dots are unreadable, and made a 37 MB SVG).
pub(crate) const MAX_PLOTTED_POINTS: usize = 2000;

/// The error of every configuration before and after (log scale); the
/// observations listed in `outliers` (indices into `after`) are ringed.
/// Every dot carries an SVG `<title>` (a browser shows it on hover): where
/// the configuration comes from, `names[k]` (e.g. `data.csv: configuration
/// 17 (line 19)`; "configuration k" where `names` has none), and its error.
/// Past `MAX_PLOTTED_POINTS` configurations, each dot is the largest error
/// of a group of consecutive configurations (the caption says how many), and
/// a group holding an outlier is ringed.
///
/// # Errors
/// [`Error::Plot`] if drawing fails.
pub fn errors_per_configuration_svg(
    before: &[f64],
    after: &[f64],
    outliers: &[usize],
    names: &[String],
    unit: &str,
) -> Result<String, Error> {
    let all = before.iter().chain(after).copied().filter(|v| *v > 0.0);
    let largest = all.clone().fold(f64::MIN_POSITIVE, f64::max) * 2.0;
    let smallest = all.fold(f64::INFINITY, f64::min).min(largest / 10.0) / 2.0;
    let count = before.len().max(after.len()).max(1);
    let group = count.div_ceil(MAX_PLOTTED_POINTS);
    // (first configuration of the group, its largest positive error).
    let grouped = |values: &[f64]| -> Vec<(usize, f64)> {
        values
            .chunks(group)
            .enumerate()
            .filter_map(|(k, chunk)| {
                let most = chunk
                    .iter()
                    .copied()
                    .filter(|v| *v > 0.0)
                    .fold(0.0, f64::max);
                (most > 0.0).then_some((k * group, most))
            })
            .collect()
    };
    let mut ringed: Vec<usize> = outliers.iter().map(|i| i / group).collect();
    ringed.sort_unstable();
    ringed.dedup();
    let ringed: Vec<(usize, f64)> = ringed
        .into_iter()
        .filter_map(|k| {
            let chunk = after.get(k * group..((k + 1) * group).min(after.len()))?;
            let most = chunk.iter().copied().fold(0.0, f64::max);
            (most > 0.0).then_some((k * group, most))
        })
        .collect();
    // The dots' titles, in the order they are drawn: before, then after.
    let name = |k: usize| {
        names
            .get(k)
            .cloned()
            .unwrap_or_else(|| format!("configuration {}", k + 1))
    };
    let titles: Vec<String> = [(before, "before"), (after, "after")]
        .iter()
        .flat_map(|(values, when)| {
            grouped(values).into_iter().map(move |(first, most)| {
                if group == 1 {
                    format!("{}: {when} {} {unit}", name(first), short_value(most))
                } else {
                    let last = (first + group).min(count);
                    format!(
                        "configurations {}–{last}: largest {when} {} {unit} (from {})",
                        first + 1,
                        short_value(most),
                        name(first)
                    )
                }
            })
        })
        .collect();
    let caption = if group == 1 {
        "Error of every configuration".to_owned()
    } else {
        format!("Largest error of every {group} configurations ({count} in all)")
    };
    svg(WIDTH, HEIGHT, |root| {
        let mut chart = ChartBuilder::on(&root)
            .caption(caption, (FONT, 18))
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(70)
            // A band on the right with no configurations, where the legend
            // sits off the data.
            .build_cartesian_2d(0..count + count / 5 + 1, (smallest..largest).log_scale())
            .map_err(plot_error)?;
        chart
            .configure_mesh()
            .x_desc("configuration (or pair)")
            .y_desc(unit)
            .y_label_formatter(&|v| short(*v))
            .label_style((FONT, 13))
            .draw()
            .map_err(plot_error)?;
        for (values, color, label) in [(before, BEFORE, "before"), (after, AFTER, "after")] {
            chart
                .draw_series(
                    grouped(values)
                        .into_iter()
                        .map(|point| Circle::new(point, 3, color.filled())),
                )
                .map_err(plot_error)?
                .label(label)
                .legend(move |(x, y)| Circle::new((x, y), 4, color.filled()));
        }
        if !ringed.is_empty() {
            let ring = BLACK.stroke_width(2);
            chart
                .draw_series(ringed.iter().map(move |point| Circle::new(*point, 7, ring)))
                .map_err(plot_error)?
                .label("outlier")
                .legend(move |(x, y)| Circle::new((x, y), 6, ring));
        }
        legend(&mut chart, SeriesLabelPosition::MiddleRight)
    })
    .map(|text| titled_circles(&text, &titles))
}

/// A value to 4 significant digits, as a dot's title shows it.
fn short_value(value: f64) -> String {
    if value == 0.0 || !value.is_finite() {
        return format!("{value}");
    }
    let decimals = (3 - value.abs().log10().floor() as i32).max(0) as usize;
    format!("{value:.decimals$}")
}

/// `svg` with its first `titles.len()` `<circle …/>` elements given the
/// titles, in order (`<circle …><title>…</title></circle>`).
fn titled_circles(svg: &str, titles: &[String]) -> String {
    let mut out =
        String::with_capacity(svg.len() + titles.iter().map(|t| t.len() + 24).sum::<usize>());
    let mut rest = svg;
    for title in titles {
        let Some(start) = rest.find("<circle") else {
            break;
        };
        let Some(end) = rest[start..].find("/>").map(|end| start + end) else {
            break;
        };
        out.push_str(&rest[..end]);
        out.push_str("><title>");
        out.push_str(&escape_xml(title));
        out.push_str("</title></circle>");
        rest = &rest[end + 2..];
    }
    out.push_str(rest);
    out
}

/// `text` with XML's special characters escaped.
fn escape_xml(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// Three projections (top, front, side) of the robot's frames 0..n+1 at a
/// motor configuration: the chain of frame origins and the tool's z axis.
///
/// # Errors
/// [`Error::Plot`] if drawing fails, [`Error::Model`] for a bad configuration.
pub fn robot_projections_svg(robot: &Robot, motor_positions: &[f64]) -> Result<String, Error> {
    let chain =
        forward_kinematics(robot, motor_positions).map_err(|e| Error::Model(e.to_string()))?;
    let points: Vec<[f64; 3]> = std::iter::once([0.0; 3])
        .chain(chain.poses().iter().map(|pose| {
            let p = pose.translation.vector;
            [p.x, p.y, p.z]
        }))
        .collect();
    let reach = points
        .iter()
        .flat_map(|p| p.iter().map(|v| v.abs()))
        .fold(0.1_f64, f64::max)
        * 1.15;
    svg(WIDTH, 260, |root| {
        let panels = root.split_evenly((1, 3));
        for (panel, (title, a, b)) in panels.iter().zip([
            ("top (x, y)", 0, 1),
            ("front (x, z)", 0, 2),
            ("side (y, z)", 1, 2),
        ]) {
            let mut chart = ChartBuilder::on(panel)
                .caption(title, (FONT, 14))
                .margin(8)
                .x_label_area_size(24)
                .y_label_area_size(36)
                .build_cartesian_2d(-reach..reach, -reach..reach)
                .map_err(plot_error)?;
            chart
                .configure_mesh()
                .x_labels(5)
                .y_labels(5)
                .x_label_formatter(&|v| format!("{v:.1}"))
                .y_label_formatter(&|v| format!("{v:.1}"))
                .label_style((FONT, 10))
                .draw()
                .map_err(plot_error)?;
            chart
                .draw_series(LineSeries::new(
                    points.iter().map(|p| (p[a], p[b])),
                    BLACK.stroke_width(2),
                ))
                .map_err(plot_error)?;
            chart
                .draw_series(
                    points
                        .iter()
                        .skip(1)
                        .map(|p| Circle::new((p[a], p[b]), 3, AFTER.filled())),
                )
                .map_err(plot_error)?;
        }
        Ok(())
    })
}

/// How many configurations are enough: the predicted RMS position error of
/// the calibrated robot (millimetres, log scale) against the number of
/// configurations (log scale), planned and random ([`gecaro_calib::curve::accuracy_curve`]).
/// Counts without a value (designs that determine nothing) are left out.
///
/// # Errors
/// [`Error::Plot`] if drawing fails.
pub fn accuracy_curve_svg(curve: &[CurvePoint]) -> Result<String, Error> {
    let millimetres = |value: Option<f64>| value.map(|v| (v * 1e3).max(1e-12));
    let series = |pick: fn(&CurvePoint) -> Option<f64>| -> Vec<(f64, f64)> {
        curve
            .iter()
            .filter_map(|point| millimetres(pick(point)).map(|v| (point.count.max(1) as f64, v)))
            .collect()
    };
    let planned = series(|point| point.planned);
    let random = series(|point| point.random);
    let values = planned.iter().chain(&random).map(|(_, v)| *v);
    let top = values.clone().fold(f64::MIN_POSITIVE, f64::max) * 1.5;
    let bottom = values.fold(f64::INFINITY, f64::min).min(top / 10.0) / 1.5;
    let counts = curve.iter().map(|point| point.count.max(1) as f64);
    let left = counts.clone().fold(f64::INFINITY, f64::min).min(1e9) / 1.2;
    let right = counts.fold(1.0, f64::max).max(left * 2.0) * 1.2;
    svg(WIDTH, HEIGHT, |root| {
        let mut chart = ChartBuilder::on(&root)
            .caption(
                "Predicted position error of the calibrated robot",
                (FONT, 18),
            )
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(70)
            .build_cartesian_2d((left..right).log_scale(), (bottom..top).log_scale())
            .map_err(plot_error)?;
        chart
            .configure_mesh()
            .x_desc("configurations measured")
            .y_desc("RMS position error (mm)")
            .x_label_formatter(&|v| short(*v))
            .y_label_formatter(&|v| short(*v))
            .label_style((FONT, 13))
            .draw()
            .map_err(plot_error)?;
        for (points, color, label) in [(&planned, AFTER, "planned"), (&random, BEFORE, "random")] {
            chart
                .draw_series(LineSeries::new(
                    points.iter().copied(),
                    color.stroke_width(2),
                ))
                .map_err(plot_error)?
                .label(label)
                .legend(move |(x, y)| {
                    PathElement::new([(x, y), (x + 18, y)], color.stroke_width(2))
                });
            chart
                .draw_series(points.iter().map(|p| Circle::new(*p, 4, color.filled())))
                .map_err(plot_error)?;
        }
        legend(&mut chart, SeriesLabelPosition::UpperRight)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_per_configuration_plot_of_many_configurations_stays_small() {
        let before: Vec<f64> = (0..200_000).map(|i| 1.0 + f64::from(i % 97)).collect();
        let after: Vec<f64> = (0..200_000)
            .map(|i| 0.01 + f64::from(i % 89) * 1e-4)
            .collect();
        let outliers: Vec<usize> = (0..200_000).step_by(1000).collect();
        let svg = errors_per_configuration_svg(&before, &after, &outliers, &[], "mm").expect("svg");
        assert!(svg.len() < 1_500_000, "{} bytes", svg.len());
        assert!(svg.contains("Largest error of every 100 configurations (200000 in all)"));
        // Each series draws at most MAX_PLOTTED_POINTS dots.
        assert!(svg.matches("<circle").count() <= 3 * MAX_PLOTTED_POINTS + 10);
    }

    #[test]
    fn plots_are_svg_with_text() {
        let history: Vec<IterationRecord> = [1e-2, 1e-4, 1e-9, 1e-15]
            .iter()
            .map(|rms| IterationRecord {
                rms: *rms,
                step: 0.0,
                damping: 0.0,
            })
            .collect();
        let convergence = convergence_svg(&history).expect("svg");
        assert!(convergence.starts_with("<svg") && convergence.contains("residual RMS"));
        let histograms =
            error_histograms_svg(&[10.0, 20.0, 35.0], &[0.01, 0.02], "mm").expect("svg");
        assert!(histograms.contains("after (calibrated)"));
        let alone = labelled_error_histograms_svg((&[10.0, 20.0], "the table's robot"), None, "mm")
            .expect("svg");
        assert!(alone.contains("the table") && !alone.contains("before (nominal)"));
        let points = errors_per_configuration_svg(
            &[10.0, 20.0],
            &[0.01, 0.02],
            &[1],
            &["a.csv: configuration 1 (line 3)".into()],
            "mm",
        )
        .expect("svg");
        assert!(points.contains("<circle"));
        // Each dot says where it comes from and its error (a title shows on hover).
        assert!(
            points.contains(
                "<title>a.csv: configuration 1 (line 3): before 10.00 mm</title></circle>"
            ),
            "{points}"
        );
        assert!(points.contains("<title>configuration 2: after 0.02000 mm</title></circle>"));
        assert_eq!(points.matches("<title>").count(), 4);
    }

    #[test]
    fn axis_labels_are_short() {
        let labels: Vec<String> = [0.0, 50.0, 100.0, 0.1, 0.05, 0.125, 1.5, 2e-5, 123456.0]
            .iter()
            .map(|v| short(*v))
            .collect();
        assert_eq!(
            labels,
            [
                "0", "50", "100", "0.1", "0.05", "0.125", "1.5", "2e-5", "1e5"
            ]
        );
    }
}
