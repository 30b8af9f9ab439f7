//! Result documents stay bounded whatever the data: a million measurements
//! have thousands beyond 3 σ̂ by chance, and the JSON lists the worst.

use gecaro_app::limits::MAX_LISTED_OUTLIERS;
use gecaro_app::{DataSource, GenerateRequest, IdentifyRequest, LocalFiles};
use gecaro_calib::Quiet;

#[test]
fn a_document_lists_the_worst_outliers_and_counts_them_all() {
    let generate: GenerateRequest = serde_json::from_str(
        r#"{"robot": "stanford", "method": {"name": "position"}, "count": 4000,
            "error_level": 0.5, "noise": 1e-5, "seed": 3}"#,
    )
    .expect("request");
    let mut samples = generate
        .run(&LocalFiles, &mut Quiet)
        .expect("data")
        .samples
        .to_rows();
    // 1500 readings off by 1–3 cm (a reflector knocked, a wrong target):
    // beyond the bound on listed outliers, well within what a robust loss
    // sets aside.
    let corrupted = 1500;
    for (index, sample) in samples.iter_mut().enumerate().take(corrupted) {
        if let Some(position) = sample.position.as_mut() {
            position.x += 0.01 + 0.02 * index as f64 / corrupted as f64;
        }
    }
    let mut identify: IdentifyRequest = serde_json::from_str(
        r#"{"robot": "stanford", "method": {"name": "position"}, "loss": "tukey"}"#,
    )
    .expect("request");
    identify.measurements.data = Some(DataSource::Samples {
        samples: samples.into(),
        label: "corrupted".into(),
    });
    let identified = identify.run(&LocalFiles, &mut Quiet).expect("identified");
    let document = identified.document();
    assert_eq!(document.outlier_count, corrupted, "every gross error found");
    assert_eq!(document.outliers.len(), MAX_LISTED_OUTLIERS);
    assert!(
        document
            .outliers
            .windows(2)
            .all(|pair| pair[0].residual_sigmas >= pair[1].residual_sigmas),
        "worst first"
    );
    // The largest errors are the last rows corrupted (3 cm).
    assert!(
        document.outliers[0].error > 0.025,
        "{}",
        document.outliers[0].error
    );
    assert!(document.rejected.is_empty() && document.rejected_count == 0);
}

#[test]
fn an_evaluation_says_which_robot_is_better_and_by_how_much() {
    use gecaro_app::documents::ComparisonJson;
    use gecaro_calib::identification::ErrorSummary;
    let rms = |rms: f64| ErrorSummary {
        count: 10,
        rms,
        mean: rms,
        max: rms,
        rms_rotation: None,
        max_rotation: None,
    };
    let better = ComparisonJson::of(&rms(2.5e-3), &rms(1.7e-5));
    assert_eq!(better.outcome, "better");
    assert!(
        better.summary.starts_with("147× smaller errors"),
        "{}",
        better.summary
    );
    assert!(better.summary.contains("RMS 0.0170 mm against 2.5000 mm"));
    let worse = ComparisonJson::of(&rms(9.6e-3), &rms(98.8e-3));
    assert_eq!(worse.outcome, "worse");
    assert!(
        worse.summary.starts_with("WORSE: 10.3× larger"),
        "{}",
        worse.summary
    );
    assert_eq!(
        ComparisonJson::of(&rms(1e-3), &rms(1.04e-3)).outcome,
        "same"
    );
}
