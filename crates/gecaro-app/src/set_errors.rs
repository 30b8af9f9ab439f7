//! An identification's errors set by set and station by station: what a
//! tracker cell's engineer checks after the overall RMS — does one
//! reflector, one station or one payload fit worse than the others?
//!
//! Per set: its observations (configurations or pairs), the RMS and
//! largest position-like error before (the robot and frames as stated) and
//! after (as calibrated), in metres. Per station: the same over the sets
//! measured from it (the measurement frame itself for the sets that name
//! none).

use gecaro_calib::identification::{Identification, locate_observations};
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

/// Sums of one group's errors.
#[derive(Default)]
struct Sums {
    count: usize,
    before: f64,
    after: f64,
    max_after: f64,
}

impl Sums {
    fn add(&mut self, before: f64, after: f64) {
        self.count += 1;
        self.before += before * before;
        self.after += after * after;
        self.max_after = self.max_after.max(after);
    }

    fn rms(sum: f64, count: usize) -> f64 {
        if count == 0 {
            0.0
        } else {
            (sum / count as f64).sqrt()
        }
    }
}

/// `result`'s errors per set of `study`, then per station (only when the
/// study has more than one set; empty otherwise).
pub(crate) fn group_errors(
    study: &Study,
    result: &Identification,
) -> (Vec<GroupErrorsJson>, Vec<GroupErrorsJson>) {
    if study.sets.len() < 2 {
        return (Vec::new(), Vec::new());
    }
    let mut sets: Vec<Sums> = study.sets.iter().map(|_| Sums::default()).collect();
    for (index, located) in locate_observations(study).iter().enumerate() {
        if let (Some(before), Some(after)) = (
            result.errors_before.get(index),
            result.errors_after.get(index),
        ) {
            sets[located.set].add(before.0, after.0);
        }
    }
    let frame_name = |k: Option<usize>| k.and_then(|k| study.frames.get(k)).map(|f| f.name.clone());
    let per_set = study
        .sets
        .iter()
        .zip(&sets)
        .enumerate()
        .map(|(k, (set, sums))| GroupErrorsJson {
            name: format!("{}: {}", k + 1, set.label),
            method: Some(set.method.name()),
            tool: frame_name(set.tool),
            station: frame_name(set.station),
            observations: sums.count,
            rms_before: Sums::rms(sums.before, sums.count),
            rms_after: Sums::rms(sums.after, sums.count),
            max_after: sums.max_after,
        })
        .collect();
    // Stations in the order the sets first name them.
    let mut stations: Vec<(Option<usize>, Sums)> = Vec::new();
    for (set, sums) in study.sets.iter().zip(&sets) {
        let slot = match stations
            .iter()
            .position(|(station, _)| *station == set.station)
        {
            Some(slot) => slot,
            None => {
                stations.push((set.station, Sums::default()));
                stations.len() - 1
            }
        };
        let total = &mut stations[slot].1;
        total.count += sums.count;
        total.before += sums.before;
        total.after += sums.after;
        total.max_after = total.max_after.max(sums.max_after);
    }
    let per_station = if stations.len() < 2 {
        Vec::new()
    } else {
        stations
            .into_iter()
            .map(|(station, sums)| GroupErrorsJson {
                name: frame_name(station).unwrap_or_else(|| "the measurement frame".into()),
                method: None,
                tool: None,
                station: frame_name(station),
                observations: sums.count,
                rms_before: Sums::rms(sums.before, sums.count),
                rms_after: Sums::rms(sums.after, sums.count),
                max_after: sums.max_after,
            })
            .collect()
    };
    (per_set, per_station)
}
