//! Human output of what the identification did about measurements as they
//! are: the loss and its reweightings, the prior, and the outlier report.
use gecaro_calib::identification::{Identification, Outlier};

use crate::format::{number, table};

/// Outliers listed in the text output; `--json` lists the worst 1000.
const LISTED: usize = 20;

/// The loss, the prior and the outliers of `result`, after its errors.
pub(super) fn print_robustness(result: &Identification) {
    if !result.loss.is_l2() {
        println!(
            "Loss {} after {} reweightings; robust σ̂ of the residuals {}",
            result.loss,
            result.reweightings,
            result.robust_sigma_words()
        );
    }
    if let Some(prior) = &result.prior {
        println!(
            "Prior around the nominal values: {prior} (maximum a posteriori; σ below is posterior)"
        );
    }
    if !result.rejected.is_empty() {
        println!(
            "Rejected before this fit ({} observations):\n{}",
            result.rejected.len(),
            outlier_table(&result.rejected)
        );
    }
    if result.outliers.is_empty() {
        println!(
            "No outliers: every observation is within {} robust σ̂ ({:.3e}).",
            number(result.outlier_threshold, 2),
            result.robust_sigma
        );
    } else {
        println!(
            "Outliers beyond {} robust σ̂ ({} of {} observations, worst first{}):\n{}",
            number(result.outlier_threshold, 2),
            result.outliers.len(),
            result.standardized.len(),
            if result.outliers.len() > LISTED {
                format!(
                    "; the first {LISTED}, --json lists the worst {}",
                    gecaro_app::limits::MAX_LISTED_OUTLIERS
                )
            } else {
                String::new()
            },
            outlier_table(&result.outliers[..result.outliers.len().min(LISTED)])
        );
        if result.rejected.is_empty() && result.loss.is_l2() {
            println!(
                "(--reject drops them and identifies again; --loss tukey discounts them in one fit)"
            );
        }
    }
}

fn outlier_table(outliers: &[Outlier]) -> comfy_table::Table {
    let rotation = outliers.iter().any(|o| o.rotation_error.is_some());
    let mut header = vec!["observation", "error (mm)"];
    if rotation {
        header.push("error (°)");
    }
    header.extend(["residual (σ̂)", "weight"]);
    let mut rows = table(&header, 1);
    for outlier in outliers {
        let mut row = vec![
            outlier.location.describe(),
            format!("{:.3}", outlier.error * 1e3),
        ];
        if rotation {
            row.push(
                outlier
                    .rotation_error
                    .map_or("–".into(), |r| format!("{:.3}", r.to_degrees())),
            );
        }
        row.extend([
            format!("{:.1}", outlier.standardized),
            format!("{:.3}", outlier.weight),
        ]);
        rows.add_row(row);
    }
    rows
}
