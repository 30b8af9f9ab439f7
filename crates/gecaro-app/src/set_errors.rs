//! An identification's errors set by set and station by station: what a
//! tracker cell's engineer checks after the overall RMS — does one
//! reflector, one station or one payload fit worse than the others?
//!
//! Per set: its observations (configurations or pairs), the RMS and
//! largest position-like error before (the robot and frames as stated) and
//! after (as calibrated), in metres. Per station: the same over the sets
//! measured from it (the measurement frame itself for the sets that name
//! none).

use gecaro_calib::identification::{ErrorSummary, Identification, locate_observations};
use gecaro_calib::study::Study;
use serde::Serialize;

/// One set's (or one station's) errors.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct GroupErrorsJson {
    /// The set's number (from 1) and label, or the station's name.
    pub name: String,
    /// The method of the set (none for a station).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub method: Option<&'static str>,
    /// The set's tool, when it names one.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tool: Option<String>,
    /// The set's station (or the station's own name), `None`: the
    /// measurement frame.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub station: Option<String>,
    /// Its observations.
    pub observations: usize,
    /// RMS of its position-like errors before and after (m).
    pub rms_before: f64,
    /// See [`rms_before`](Self::rms_before).
    pub rms_after: f64,
    /// Its largest error after (m).
    pub max_after: f64,
}

/// A group's document from the errors of its observations (`keep` says
/// which of the identification's).
fn group(
    result: &Identification,
    keep: impl Fn(usize) -> bool,
    (name, method, tool, station): (String, Option<&'static str>, Option<String>, Option<String>),
) -> GroupErrorsJson {
    let before = ErrorSummary::of_errors(&result.errors_before.retained(&keep));
    let after = ErrorSummary::of_errors(&result.errors_after.retained(&keep));
    GroupErrorsJson {
        name,
        method,
        tool,
        station,
        observations: after.count,
        rms_before: before.rms,
        rms_after: after.rms,
        max_after: after.max,
    }
}

/// `result`'s errors per set of `study`, then per station (only when the
/// study has more than one set, or more than one station; empty otherwise).
pub(crate) fn group_errors(
    study: &Study,
    result: &Identification,
) -> (Vec<GroupErrorsJson>, Vec<GroupErrorsJson>) {
    if study.sets.len() < 2 {
        return (Vec::new(), Vec::new());
    }
    let set_of: Vec<usize> = locate_observations(study).iter().map(|l| l.set).collect();
    let set_of = &set_of;
    let frame_name = |k: Option<usize>| k.and_then(|k| study.frames.get(k)).map(|f| f.name.clone());
    let per_set = study
        .sets
        .iter()
        .enumerate()
        .map(|(k, set)| {
            let labels = (
                format!("{}: {}", k + 1, set.label),
                Some(set.method.name()),
                frame_name(set.tool),
                frame_name(set.station),
            );
            group(result, |index| set_of.get(index) == Some(&k), labels)
        })
        .collect();
    // Stations in the order the sets first name them.
    let mut stations: Vec<Option<usize>> = Vec::new();
    for set in &study.sets {
        if !stations.contains(&set.station) {
            stations.push(set.station);
        }
    }
    let per_station = if stations.len() < 2 {
        Vec::new()
    } else {
        stations
            .into_iter()
            .map(|station| {
                let name = frame_name(station).unwrap_or_else(|| "the measurement frame".into());
                let from_station = |index: usize| {
                    set_of
                        .get(index)
                        .is_some_and(|&set| study.sets[set].station == station)
                };
                group(
                    result,
                    from_station,
                    (name, None, None, frame_name(station)),
                )
            })
            .collect()
    };
    (per_set, per_station)
}
