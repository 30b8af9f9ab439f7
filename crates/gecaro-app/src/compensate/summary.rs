//! What a corrected program comes to, gathered block by block as it is
//! compensated: the targets, the lines of those flagged, the largest
//! residual and the largest correction. It is all the command line prints,
//! and all a streamed compensation keeps of its targets.

use gecaro_calib::compensation::{
    CompensatedPoint, CompensationStatus, ProgramPoint, ProgramTarget,
};
use gecaro_io::ProgramLayout;

use crate::documents::{CompensatedJson, CompensationJson, LargestCorrection};
use crate::error::{AppError, ErrorKind, Part};

/// See the module docs.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CompensationSummary {
    /// Targets compensated.
    pub targets: usize,
    /// Lines (file) or rows (arrays) of the targets reached only in
    /// another configuration.
    pub reconfigured: Vec<usize>,
    /// Lines of the targets reached outside the region the calibration's
    /// data covered.
    pub outside_region: Vec<usize>,
    /// Lines of the targets reached only beyond a joint limit.
    pub outside_limits: Vec<usize>,
    /// Lines of the targets not reached.
    pub not_reached: Vec<usize>,
    /// The largest residual of a reached target (m).
    pub largest_position_error: f64,
    /// The largest joint change of a target reached (program files only).
    pub largest_correction: Option<LargestCorrection>,
    /// The turn of the tool beyond which a position match's target is
    /// flagged (rad); none checked when `None`.
    pub max_tool_turn: Option<f64>,
    /// The largest turn of the tool a position match left (rad), and its
    /// target's line.
    pub largest_tool_turn: Option<(f64, usize)>,
    /// Lines of the targets a position match reached with the tool turned
    /// beyond [`max_tool_turn`](Self::max_tool_turn).
    pub turned: Vec<usize>,
}

impl CompensationSummary {
    /// An empty summary that flags targets a position match reaches with
    /// the tool turned by more than `max_tool_turn` (rad).
    pub fn limiting_tool_turn(max_tool_turn: f64) -> Self {
        CompensationSummary {
            max_tool_turn: Some(max_tool_turn),
            ..Self::default()
        }
    }

    /// Adds a block of targets and their results; `line` gives a target's
    /// line from its index in the block; `layout` is the program file's
    /// (the correction is given in its units), if the targets came from one.
    pub fn add(
        &mut self,
        points: &[ProgramPoint],
        results: &[CompensatedPoint],
        line: impl Fn(usize) -> usize,
        layout: Option<&ProgramLayout>,
    ) {
        self.targets += results.len();
        for (index, (point, result)) in points.iter().zip(results).enumerate() {
            match result.status {
                CompensationStatus::Reached => {}
                CompensationStatus::Reconfigured => self.reconfigured.push(line(index)),
                CompensationStatus::OutsideRegion => self.outside_region.push(line(index)),
                CompensationStatus::OutsideLimits => self.outside_limits.push(line(index)),
                CompensationStatus::NotReached => {
                    self.not_reached.push(line(index));
                    continue;
                }
            }
            self.largest_position_error = self.largest_position_error.max(result.position_error);
            if let Some(turn) = result.tool_turn {
                if self
                    .largest_tool_turn
                    .is_none_or(|(largest, _)| turn > largest)
                {
                    self.largest_tool_turn = Some((turn, line(index)));
                }
                if self.max_tool_turn.is_some_and(|limit| turn > limit) {
                    self.turned.push(line(index));
                }
            }
            let Some(layout) = layout.filter(|_| result.status == CompensationStatus::Reached)
            else {
                continue;
            };
            let original = match &point.target {
                ProgramTarget::Joints(qm) => Some(qm),
                _ => point.joints.as_ref(),
            };
            for (j, (before, after)) in original
                .into_iter()
                .flatten()
                .zip(&result.motor_positions)
                .enumerate()
            {
                let (value, unit) = layout.joint_in_file_unit(j, (after - before).abs());
                if self
                    .largest_correction
                    .is_none_or(|largest| value > largest.value)
                {
                    self.largest_correction = Some(LargestCorrection {
                        value,
                        unit,
                        joint: j + 1,
                        line: line(index),
                    });
                }
            }
        }
    }

    /// The lines of the targets with `status` (none for those reached).
    pub fn lines_with(&self, status: CompensationStatus) -> &[usize] {
        match status {
            CompensationStatus::Reached => &[],
            CompensationStatus::Reconfigured => &self.reconfigured,
            CompensationStatus::OutsideRegion => &self.outside_region,
            CompensationStatus::OutsideLimits => &self.outside_limits,
            CompensationStatus::NotReached => &self.not_reached,
        }
    }

    /// Targets flagged: reconfigured, outside the measured region, beyond a
    /// limit or not reached.
    pub fn flagged(&self) -> usize {
        self.reconfigured.len()
            + self.outside_region.len()
            + self.outside_limits.len()
            + self.not_reached.len()
    }

    /// Targets reached within the limits in the program's configuration.
    pub fn reached(&self) -> usize {
        self.targets - self.flagged()
    }

    /// The JSON document (`gecaro compensate --json`) of these targets,
    /// written to `output`, listing `points` (none for a program corrected
    /// as it was read).
    pub fn document(
        &self,
        output: Option<String>,
        points: Vec<CompensatedJson>,
    ) -> CompensationJson {
        CompensationJson {
            targets: self.targets,
            reached: self.reached(),
            reconfigured: self.reconfigured.clone(),
            outside_region: self.outside_region.clone(),
            outside_limits: self.outside_limits.clone(),
            not_reached: self.not_reached.clone(),
            largest_position_error: self.largest_position_error,
            largest_correction: self.largest_correction.map_or(0.0, |largest| largest.value),
            largest_correction_at: self.largest_correction,
            largest_tool_turn: self.largest_tool_turn.map(|(turn, _)| turn),
            turned: self.turned.clone(),
            output,
            points,
            registration: None,
        }
    }

    /// Why the corrected program (written to `saved`) is not to be run as
    /// it is: targets reconfigured, outside the measured region, beyond a
    /// limit or not reached.
    pub fn failure(&self, saved: Option<&std::path::Path>) -> Option<AppError> {
        let flagged = self.flagged();
        let place = saved.map_or_else(String::new, |path| format!(" in {}", path.display()));
        if flagged > 0 {
            return Some(AppError::plain(
                ErrorKind::NotConverged,
                format!(
                    "{flagged} of {} targets are flagged{place}; check them before running the \
                     program",
                    self.targets
                ),
            ));
        }
        let (Some((largest, line)), Some(limit)) = (self.largest_tool_turn, self.max_tool_turn)
        else {
            return None;
        };
        (!self.turned.is_empty()).then(|| {
            AppError::new(
                ErrorKind::NotConverged,
                vec![
                    Part::Text(format!(
                        "the position match turns the tool by more than {:.2}° at {} of {} \
                         targets{place} (up to {:.2}° at line {line}): it moves the point only, \
                         and leaves the orientation to the joints; match the pose (a calibration \
                         that measured orientations) or accept the turn with a larger ",
                        limit.to_degrees(),
                        self.turned.len(),
                        self.targets,
                        largest.to_degrees()
                    )),
                    Part::Setting("max_tool_turn".into()),
                ],
            )
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn result(status: CompensationStatus, position_error: f64, q: f64) -> CompensatedPoint {
        CompensatedPoint {
            motor_positions: vec![q, 0.0],
            position_error,
            rotation_error: None,
            tool_turn: None,
            status,
        }
    }

    #[test]
    fn blocks_add_up_to_the_summary_of_the_whole() {
        let point = ProgramPoint {
            target: ProgramTarget::Joints(vec![0.0, 0.0]),
            joints: None,
        };
        let points = vec![point; 6];
        let results = [
            result(CompensationStatus::Reached, 1e-9, 0.01),
            result(CompensationStatus::NotReached, 5.0, 3.0),
            result(CompensationStatus::Reached, 2e-9, -0.03),
            result(CompensationStatus::OutsideLimits, 3e-9, 0.5),
            result(CompensationStatus::Reconfigured, 1e-10, 1.5),
            result(CompensationStatus::OutsideRegion, 4e-10, 0.2),
        ];
        // Lines as a file numbers them: the header, then a row each.
        let mut whole = CompensationSummary::default();
        whole.add(&points, &results, |index| index + 2, None);
        let mut blocks = CompensationSummary::default();
        blocks.add(&points[..2], &results[..2], |index| index + 2, None);
        blocks.add(&points[2..], &results[2..], |index| index + 4, None);
        assert_eq!(whole, blocks);
        assert_eq!((whole.targets, whole.reached(), whole.flagged()), (6, 2, 4));
        assert_eq!(whole.lines_with(CompensationStatus::NotReached), [3]);
        assert_eq!(whole.lines_with(CompensationStatus::OutsideLimits), [5]);
        assert_eq!(whole.lines_with(CompensationStatus::Reconfigured), [6]);
        assert_eq!(whole.lines_with(CompensationStatus::OutsideRegion), [7]);
        // The target not reached does not count as a residual.
        assert_eq!(whole.largest_position_error, 3e-9);
        assert!(whole.failure(None).is_some());
    }
}
