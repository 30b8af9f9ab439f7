//! # gecaro-report
//!
//! The pictures of a calibration and a self-contained HTML report: plots as
//! SVG made with plotters ([`convergence_svg`], [`error_histograms_svg`],
//! [`errors_per_configuration_svg`], [`robot_projections_svg`]),
//! and [`html_report`], one HTML file with the plots inline, readable without
//! a network; [`platform_report`], the same for a parallel robot;
//! [`acceptance_report`], the same for ISO 9283's acceptance test.

#![warn(missing_docs)]

mod acceptance;
mod html;
mod page;
mod parallel;
mod plots;

pub use acceptance::{AcceptanceInput, MeasuredInput, acceptance_report, four_decimals};
pub use html::{ReportInput, html_report};
pub use parallel::{PlatformPlots, PlatformReportInput, platform_plots, platform_report};
pub use plots::{
    IdentificationSvgs, accuracy_curve_svg, convergence_svg, error_histograms_svg,
    errors_per_configuration_svg, identification_svgs, labelled_error_histograms_svg,
    observation_names, robot_projections_svg,
};

/// Errors of report making.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// Drawing a plot failed.
    #[error("cannot draw a plot: {0}")]
    Plot(String),
    /// The robot or configuration does not fit.
    #[error("{0}")]
    Model(String),
}
