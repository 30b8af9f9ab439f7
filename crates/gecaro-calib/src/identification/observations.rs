//! Where each observation of a study comes from: its measurement set, the
//! set's label (usually its data file), whether it is a configuration or a
//! pair, and the lines of the file its samples were read from.
//!
//! Observations are numbered across the sets in the study's order, as the
//! observation system numbers them: observation `k` of the whole study is
//! entry `k` of [`Identification::errors_before`](super::Identification),
//! `errors_after`, `standardized` and `observation_weights`.

use crate::study::Study;

/// One observation's place in its set and file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ObservationLocation {
    /// Index of its measurement set in the study.
    pub set: usize,
    /// The set's label (usually its data file).
    pub label: String,
    /// `configuration` or `pair`.
    pub kind: &'static str,
    /// Its index within the set (0-based, configurations or pairs).
    pub observation: usize,
    /// Indices of its samples in the set.
    pub samples: Vec<usize>,
    /// Lines of the data file its samples came from, when known.
    pub lines: Vec<usize>,
}

impl ObservationLocation {
    /// `file.csv: configuration 17 (line 19)` and the like.
    pub fn describe(&self) -> String {
        let lines = match self.lines.as_slice() {
            [] => String::new(),
            [line] => format!(" (line {line})"),
            lines => format!(
                " (lines {})",
                lines
                    .iter()
                    .map(usize::to_string)
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        };
        format!(
            "{}: {} {}{lines}",
            self.label,
            self.kind,
            self.observation + 1
        )
    }
}

/// Every observation of `study`, numbered across its sets.
pub fn locate_observations(study: &Study) -> Vec<ObservationLocation> {
    locate(study, |_| true)
        .into_iter()
        .map(|(_, located)| located)
        .collect()
}

/// The observations of `study` whose number (across its sets) `wanted`
/// accepts, in order, with their numbers: on large data, without a list
/// for every observation.
pub(crate) fn locate(
    study: &Study,
    wanted: impl Fn(usize) -> bool,
) -> Vec<(usize, ObservationLocation)> {
    let mut located = Vec::new();
    let mut first = 0;
    for (set_index, set) in study.sets.iter().enumerate() {
        let grouped = set.method.grouped_observations(set.samples.as_slice());
        let count = grouped.as_ref().map_or(set.samples.len(), Vec::len);
        let kind = if grouped
            .as_ref()
            .is_some_and(|groups| groups.iter().any(|members| members.len() > 1))
        {
            "pair"
        } else {
            "configuration"
        };
        for observation in (0..count).filter(|k| wanted(first + k)) {
            let samples = grouped
                .as_ref()
                .map_or_else(|| vec![observation], |groups| groups[observation].clone());
            located.push((
                first + observation,
                ObservationLocation {
                    set: set_index,
                    label: set.label.clone(),
                    kind,
                    observation,
                    lines: samples
                        .iter()
                        .filter_map(|index| set.samples.get(*index).line())
                        .collect(),
                    samples,
                },
            ));
        }
        first += count;
    }
    located
}
