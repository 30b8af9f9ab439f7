//! What the data determine of the robot, beside how well they are fitted:
//! the joints they move, the base parameters they excite, the equations
//! they give per unknown, and what their methods observe at all — the
//! robot's scale, its tool (frame n+1) and its base (frames 0 and 1).
//!
//! A fit can explain every measurement to the noise and still leave these
//! undetermined. A joint that never moved leaves its parameters at nominal
//! and lets others absorb their effect at that one joint value (held out,
//! such a robot can be worse than the nominal one); twelve poses for 34
//! unknowns fit their own data below the noise and miss held-out poses by
//! five times it; link and plane methods measure no length (Table 2 loses
//! the scale), and frame link never sees the tool (paper §3.2: r_n, θ_n,
//! β_n and frame n+1 have no effect). The verdict calls such results
//! *underdetermined* or *incomplete*, never trusted ([`super::Verdict`]).

use gecaro_core::Robot;

use crate::identifiability::{ParameterStatus, RankReport};
use crate::parallel::{run_parts, scan_parts};
use crate::samples::SampleSlice;
use crate::study::Study;

/// Equations per unknown below which the data are too few to trust: with
/// `p` unknowns and `n` equations the fit's residuals shrink by
/// `(n − p)/n` and its predictions grow by `p/n` of the noise variance, so
/// at twice as many equations as unknowns the held-out error is 1.2× the
/// noise on poses like the measured ones, and more away from them.
pub const MIN_REDUNDANCY: f64 = 2.0;

/// A joint whose motor values in the data span less than this (radians, or
/// metres for a prismatic joint) never moved.
pub const STILL_RANGE: f64 = 1e-6;

/// The robot's scale when no measurement set observes it (link and plane
/// methods only): how it was chosen and how well it is known.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UnobservedScale {
    /// The relative standard deviation of the scale: that of the lengths
    /// closest to the nominal ones (the prior's σ of every length and
    /// prismatic gain, 1 cm and 1 % without a prior), e.g. 0.009 for ±0.9 %.
    pub std: f64,
    /// The size of the paper's base-set solution relative to the robot
    /// kept: where the length that the base set holds at nominal had put
    /// the scale (0.45: the base set alone calibrated the robot at 0.45 of
    /// the size kept).
    pub base_set_scale: f64,
}

/// What the data determine; see the module docs.
#[derive(Clone, Debug, PartialEq)]
pub struct Coverage {
    /// Joints (1-based) whose motor values never changed in the data.
    pub still_joints: Vec<usize>,
    /// Structural base parameters the data do not excite (left at nominal).
    pub not_excited: Vec<String>,
    /// Independent equations of the data.
    pub equations: usize,
    /// Identified unknowns.
    pub unknowns: usize,
    /// The scale, when no measurement set observes it.
    pub scale: Option<UnobservedScale>,
    /// Whether the methods observe the tool: some parameter of frame n+1
    /// that the priority matrix lets be identified has an effect (a named
    /// tool of the study is observed by its own unknowns).
    pub tool_observed: bool,
    /// Whether the methods observe where the robot stands in the
    /// measurement frame: some parameter of frame 0 has an effect.
    pub base_observed: bool,
}

impl Coverage {
    /// What `study` determines of `robot` (its structural analysis `rank`,
    /// the base parameters the data do not excite, the identified unknowns,
    /// and the scale chosen when no set observes it, [`super::scale`]).
    pub(super) fn of(
        robot: &Robot,
        study: &Study,
        rank: &RankReport,
        not_excited: &[String],
        unknowns: usize,
        scale: Option<UnobservedScale>,
    ) -> Coverage {
        let last = robot.frames().len() - 1;
        let observes_frame = |frame: usize| {
            let candidates: Vec<ParameterStatus> = rank
                .parameters
                .iter()
                .filter(|p| p.parameter.is_some_and(|id| id.frame == frame))
                .map(|p| p.status)
                .filter(|status| *status != ParameterStatus::Excluded)
                .collect();
            candidates.is_empty() || candidates.iter().any(|s| *s != ParameterStatus::NoEffect)
        };
        let named_tool = study.sets.iter().any(|set| set.tool.is_some());
        Coverage {
            still_joints: still_joints(robot, study),
            not_excited: not_excited.to_vec(),
            equations: study.equation_count(),
            unknowns,
            scale: (!study.observes_scale()).then(|| {
                scale.unwrap_or(UnobservedScale {
                    std: f64::NAN,
                    base_set_scale: 1.0,
                })
            }),
            tool_observed: named_tool || observes_frame(last),
            base_observed: observes_frame(0),
        }
    }

    /// Whether the equations are fewer than [`MIN_REDUNDANCY`] per unknown.
    pub fn low_redundancy(&self) -> bool {
        (self.equations as f64) < MIN_REDUNDANCY * self.unknowns as f64
    }

    /// Whether the data leave part of what they should identify
    /// undetermined: a joint that never moved, a base parameter not
    /// excited, or too few equations.
    pub fn underdetermined(&self) -> bool {
        !self.still_joints.is_empty() || !self.not_excited.is_empty() || self.low_redundancy()
    }

    /// Whether the methods leave the scale or the tool unobserved.
    pub fn incomplete(&self) -> bool {
        self.scale.is_some() || !self.tool_observed
    }

    /// What the data leave undetermined, in words (empty when nothing).
    pub fn underdetermined_words(&self) -> String {
        let mut parts = Vec::new();
        if !self.still_joints.is_empty() {
            let joints: Vec<String> = self.still_joints.iter().map(|j| format!("{j}")).collect();
            parts.push(format!(
                "joint{} {} never moved",
                if joints.len() == 1 { "" } else { "s" },
                joints.join(", ")
            ));
        }
        if !self.not_excited.is_empty() {
            parts.push(format!(
                "{} not excited (left at nominal)",
                self.not_excited.join(", ")
            ));
        }
        if self.low_redundancy() {
            parts.push(format!(
                "{} equations for {} unknowns (at least {} needed, {MIN_REDUNDANCY} per unknown)",
                self.equations,
                self.unknowns,
                (MIN_REDUNDANCY * self.unknowns as f64).ceil()
            ));
        }
        if parts.is_empty() {
            return String::new();
        }
        format!(
            "the data do not determine the robot: {}; the result holds only near the measured \
             poses — measure more configurations that move every joint",
            parts.join("; ")
        )
    }

    /// What the methods do not observe, in words (empty when nothing).
    pub fn incomplete_words(&self) -> String {
        let mut parts = Vec::new();
        if let Some(scale) = &self.scale {
            let known = if scale.std.is_finite() {
                format!(
                    ", its lengths kept closest to the nominal ones (scale known to ±{:.2} %)",
                    100.0 * scale.std
                )
            } else {
                String::new()
            };
            parts.push(format!(
                "the data measure no length, so the robot's scale is not measured: its shape is \
                 calibrated{known} — add a distance set (10 pairs fix it)"
            ));
        }
        if !self.tool_observed {
            parts.push(
                "the methods do not observe the tool (frame n+1 has no effect on them): it is \
                 left at nominal — add a position or distance set, or measure the tool"
                    .to_owned(),
            );
        }
        parts.join("; ")
    }
}

/// Joints (1-based) whose motor values span less than [`STILL_RANGE`].
fn still_joints(robot: &Robot, study: &Study) -> Vec<usize> {
    let joints = robot.joint_count();
    // Each part's range of every joint, on all cores for long data (the
    // least and greatest values do not depend on the cut).
    let parts: Vec<SampleSlice<'_>> = study
        .sets
        .iter()
        .flat_map(|set| {
            let samples = set.samples.as_slice();
            scan_parts(samples.len())
                .into_iter()
                .map(move |part| samples.slice(part))
        })
        .collect();
    let ranges = run_parts(parts, |part| {
        let mut low = vec![f64::INFINITY; joints];
        let mut high = vec![f64::NEG_INFINITY; joints];
        for sample in part.iter() {
            for (joint, value) in sample.motor_positions().iter().enumerate().take(joints) {
                low[joint] = low[joint].min(*value);
                high[joint] = high[joint].max(*value);
            }
        }
        (low, high)
    });
    (0..joints)
        .filter(|joint| {
            let low = ranges
                .iter()
                .map(|(low, _)| low[*joint])
                .fold(f64::INFINITY, f64::min);
            let high = ranges
                .iter()
                .map(|(_, high)| high[*joint])
                .fold(f64::NEG_INFINITY, f64::max);
            high - low < STILL_RANGE
        })
        .map(|joint| joint + 1)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::methods::{MethodOptions, method};
    use crate::sample::Sample;

    /// A joint held still is found in short data and in long data read in
    /// parts, and one that moved once, in the last sample, is not.
    #[test]
    fn a_joint_that_never_moved_is_found_in_long_data() {
        let robot = Robot::template("arm", "RRR").expect("robot");
        for count in [100, 3 * crate::parallel::PARALLEL_SCAN + 7] {
            let mut samples: Vec<Sample> = (0..count)
                .map(|i| {
                    let turn = (i as f64 * 1e-3).sin();
                    Sample::new(vec![turn, 0.3, -turn])
                })
                .collect();
            let study = |samples: &[Sample]| {
                let position = method("position", &MethodOptions::default()).expect("method");
                Study::single(position, samples, "still")
            };
            assert_eq!(still_joints(&robot, &study(&samples)), vec![2], "{count}");
            let last = samples.last_mut().expect("samples");
            last.motor_positions[1] += 2.0 * STILL_RANGE;
            assert!(still_joints(&robot, &study(&samples)).is_empty(), "{count}");
        }
    }
}
