//! What the verdict finds beyond the fit, as data: where the result holds
//! ([`super::region`]), every set's fit and the set that disagrees
//! ([`super::disagreement`]), a join off by a few rows ([`super::join`]).
//!
//! The modules that find them read a whole [`Identification`](super::Identification),
//! which holds the verdict that holds these: their types sit here, beneath
//! both, and each renders itself in words for the verdict's sentence.

use gecaro_core::JointRegion;

use super::words;

/// A joint whose measured range is below this part of its work range is
/// named as one to measure over more of.
pub const NARROW_FRACTION: f64 = 0.5;

/// Where the result holds; see the module docs.
#[derive(Clone, Debug, PartialEq)]
pub struct RegionPrediction {
    /// The smallest box of joint ranges holding every measured
    /// configuration (joint variables of eq. 4: radians, metres).
    pub measured: JointRegion,
    /// The region the robot is used in: its joint limits, or the one stated.
    pub work: JointRegion,
    /// Whether [`work`](Self::work) is the joint limits (not a stated region).
    pub work_is_limits: bool,
    /// Whether each joint is revolute (its range in degrees in words).
    pub revolute: Vec<bool>,
    /// RMS of the predicted position error at the measured configurations (m).
    pub inside: f64,
    /// RMS of the predicted position error over the work region (m).
    pub work_rms: f64,
    /// The largest predicted position error at a configuration of the work
    /// region (m, the RMS of its distribution).
    pub work_max: f64,
    /// What a held-out position measurement of a perfect robot shows: √3
    /// times the residual σ of the length rows (m).
    pub floor: f64,
    /// Joints (1-based) that never moved in the data.
    pub still_joints: Vec<usize>,
    /// Whether the result holds over the work region (module docs).
    pub holds_everywhere: bool,
}

impl RegionPrediction {
    /// Joints (1-based) whose measured range covers less than
    /// [`NARROW_FRACTION`] of their work range.
    pub fn narrow_joints(&self) -> Vec<usize> {
        (0..self.measured.joints())
            .filter(|j| self.measured.fraction_of(&self.work, *j) < NARROW_FRACTION)
            .map(|j| j + 1)
            .collect()
    }

    /// The work region in words: `the joint limits` or `the stated work region`.
    pub fn work_words(&self) -> &'static str {
        if self.work_is_limits {
            "the joint limits"
        } else {
            "the stated work region"
        }
    }

    /// The measured range of joint `joint` (1-based) in words: `q2 −15.0…30.0°`.
    pub fn range_words(&self, joint: usize) -> String {
        let (min, max) = self.measured.range(joint - 1);
        if self.revolute[joint - 1] {
            format!(
                "q{joint} {}…{}°",
                signed(min.to_degrees(), 1),
                signed(max.to_degrees(), 1)
            )
        } else {
            format!(
                "q{joint} {}…{} mm",
                signed(min * 1e3, 1),
                signed(max * 1e3, 1)
            )
        }
    }

    /// A warning when the result holds everywhere but its predicted error
    /// over the work region is above the noise floor: both figures.
    pub fn warning(&self) -> Option<String> {
        (self.holds_everywhere && self.work_rms > self.floor).then(|| {
            format!(
                "the calibrated robot is predicted to {} over {} ({:.1}× the noise floor of {}), \
                 {} at the measured configurations: measure poses over more of the work region \
                 to bring it down",
                words::millimetres(self.work_rms),
                self.work_words(),
                self.work_rms / self.floor,
                words::millimetres(self.floor),
                words::millimetres(self.inside),
            )
        })
    }

    /// The verdict's clause when the result does not hold everywhere.
    pub fn words(&self) -> String {
        let narrow = self.narrow_joints();
        let shown: Vec<usize> = if narrow.is_empty() {
            (1..=self.measured.joints()).collect()
        } else {
            narrow.clone()
        };
        let ranges = shown
            .iter()
            .map(|joint| self.range_words(*joint))
            .collect::<Vec<_>>()
            .join(", ");
        let covered = if narrow.is_empty() {
            format!("the data's configurations ({ranges}) leave much of the joint space unvisited")
        } else {
            format!("the data cover only part of the joint space ({ranges})")
        };
        let still = if self.still_joints.is_empty() {
            String::new()
        } else {
            format!(
                " (and more: joint{} {} never moved, whose parameters no prediction sees)",
                if self.still_joints.len() == 1 {
                    ""
                } else {
                    "s"
                },
                list(&self.still_joints)
            )
        };
        let extend: Vec<usize> = narrow
            .iter()
            .chain(&self.still_joints)
            .copied()
            .collect::<std::collections::BTreeSet<_>>()
            .into_iter()
            .collect();
        let advice = if extend.is_empty() {
            "measure poses spread over the whole work region".to_owned()
        } else {
            format!(
                "measure poses over more of joint{} {}",
                if extend.len() == 1 { "" } else { "s" },
                list(&extend)
            )
        };
        format!(
            "{covered}: the calibrated robot is predicted to {} there but {} over {}{still} \
             ({:.0}× the noise floor of {}); use it within the measured ranges (the calibrated \
             robot file keeps them, and compensate and evaluate flag poses outside), or {advice}",
            words::millimetres(self.inside),
            words::millimetres(self.work_rms),
            self.work_words(),
            self.work_rms / self.floor,
            words::millimetres(self.floor),
        )
    }
}

/// `1, 2 and 3`.
fn list(joints: &[usize]) -> String {
    let names: Vec<String> = joints.iter().map(ToString::to_string).collect();
    match names.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} and {last}", rest.join(", ")),
        _ => names.join(""),
    }
}

/// `value` with `decimals` decimals and a true minus sign.
fn signed(value: f64, decimals: usize) -> String {
    let text = format!("{value:.decimals$}");
    match text.strip_prefix('-') {
        Some(rest) if rest.chars().any(|c| c.is_ascii_digit() && c != '0') => format!("−{rest}"),
        Some(rest) => rest.to_owned(),
        None => text,
    }
}

/// One set's fit at the solution, or the fit of the sets of one named
/// tool or station pooled.
#[derive(Clone, Debug, PartialEq)]
pub struct SetFit {
    /// The set's label (usually its data file), or `tool smr_a`,
    /// `station tracker_2`.
    pub label: String,
    /// Its residuals' σ̂ over its stated σ (over 1 for an unweighted set:
    /// metres and radians), `√(χ²_k/ν_k)`.
    pub sigma_ratio: f64,
}

/// The set that disagrees with the rest: see the module docs.
#[derive(Clone, Debug, PartialEq)]
pub struct Disagreement {
    /// The set (its index in the study).
    pub set: usize,
    /// Its label.
    pub label: String,
    /// σ̂/σ of the other sets identified without it.
    pub rest_ratio: f64,
    /// The set's RMS error at the robot the others give (metres).
    pub error: f64,
    /// σ̂/σ of the study as a whole.
    pub whole_ratio: f64,
}

impl Disagreement {
    /// The verdict's words.
    pub fn words(&self) -> String {
        format!(
            "{} disagrees with the other sets: identified without it they fit the noise (σ̂/σ = \
             {:.2} against {:.1} with it), and it is {:.4} mm off the robot they give — a set \
             labelled with the wrong tool or station, another robot's data, or a cell changed \
             between the sets?",
            self.label,
            self.rest_ratio,
            self.whole_ratio,
            self.error * 1e3
        )
    }
}

/// A set whose measurements belong to other rows' configurations.
#[derive(Clone, Debug, PartialEq)]
pub struct ShiftedJoin {
    /// The set (its index in the study).
    pub set: usize,
    /// Its label.
    pub label: String,
    /// The shift: the measurement of row i belongs to the configuration of
    /// row i − `shift` (1: each measurement sits one row below its
    /// configuration).
    pub shift: isize,
    /// The residual RMS of the identification as read (weighted rows).
    pub rms_as_read: f64,
    /// The same with the measurements shifted.
    pub rms_shifted: f64,
}

impl ShiftedJoin {
    /// The diagnosis in words.
    pub fn words(&self) -> String {
        let rows = self.shift.unsigned_abs();
        format!(
            "{}: the measurements seem to belong to the configurations {} row{} {} them (a joint \
             log and a measurement file joined {} row{} off?): moved so, the identification \
             converges to a residual RMS {:.2e} against {:.2e} as read; join the files again",
            self.label,
            rows,
            if rows == 1 { "" } else { "s" },
            if self.shift > 0 { "above" } else { "below" },
            rows,
            if rows == 1 { "" } else { "s" },
            self.rms_shifted,
            self.rms_as_read,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn joints_and_signs_in_words() {
        assert_eq!(list(&[3]), "3");
        assert_eq!(list(&[1, 2]), "1 and 2");
        assert_eq!(list(&[1, 4, 6]), "1, 4 and 6");
        assert_eq!(signed(-15.04, 1), "−15.0");
        assert_eq!(signed(-0.04, 1), "0.0");
        assert_eq!(signed(30.0, 1), "30.0");
    }
}
