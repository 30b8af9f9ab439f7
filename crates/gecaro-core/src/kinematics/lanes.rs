//! Four configurations at once: the direct model (eq. 1–3) and the
//! parameter Jacobian (Appendix II) of a [`KinematicModel`] in SIMD lanes.
//!
//! A data set's configurations are independent, and each costs the same
//! products: the poses of the n + 2 frames, then the Jacobian's columns.
//! Here those products are taken for four configurations at once, one per
//! lane of nalgebra's SIMD scalar (`simba`'s `WideF64x4`), by the very code
//! the model runs for one configuration (its poses and Jacobian are written
//! once, generic over the scalar). No operation mixes lanes, the turns come
//! from [`turn::sin_cos_lanes`], whose lanes are
//! computed on their own, and a derived column skips a term only where its
//! weight is zero in every lane (which adds +0 elsewhere, changing no bit):
//! each lane's pose and Jacobian are those of its configuration alone, bit
//! for bit (tested for every kind of chain, loads and selections).
//!
//! The inputs of eq. 4 (couplings, gains, offsets, deflections under load)
//! are checked and computed for each configuration alone
//! ([`LaneBuffer::push`]) and the errors are those of
//! [`KinematicModel::forward_tilted`]. A group of fewer than four fills its
//! free lanes with its first configuration, whose values are not read.
//!
//! The lanes' products run in the widest instruction set the processor has
//! (AVX2 or AVX-512 on x86-64, chosen at run time by `pulp`, the baseline
//! elsewhere), with the same bits in each: the same IEEE operations in the
//! same order, no fused multiply-add (tested in every set the processor has).
//!
//! ```
//! use gecaro_core::{ChainBuffer, JacobianRows, KinematicModel, LaneBuffer, Robot};
//!
//! let robot = Robot::template("arm", "RRPRRR")?;
//! let model = KinematicModel::new(&robot);
//! let configurations = [[0.1, 0.2, 0.3, 0.4, 0.5, 0.6], [0.3, -1.0, 0.2, 0.0, 2.0, -0.5]];
//! let mut lanes = LaneBuffer::default();
//! for qm in &configurations {
//!     lanes.push(&model, qm, None, None)?;
//! }
//! model.forward_lanes(&mut lanes);
//! let mut rows = [Vec::new(), Vec::new()];
//! model.jacobian_rows_lanes(&mut lanes, rows.iter_mut(), JacobianRows::Full);
//!
//! // Each lane is its configuration alone, to the bit.
//! let (mut chain, mut alone) = (ChainBuffer::default(), Vec::new());
//! for (lane, qm) in configurations.iter().enumerate() {
//!     model.forward(qm, &mut chain)?;
//!     model.jacobian_rows(&chain, &mut alone, JacobianRows::Full);
//!     assert_eq!(lanes.world_from_tool(lane), *chain.world_from_tool());
//!     assert_eq!(rows[lane], alone);
//! }
//! # Ok::<(), gecaro_core::Error>(())
//! ```

use std::sync::OnceLock;

use nalgebra::{IsometryMatrix3, Rotation3, SimdValue, Translation3};
use simba::simd::WideF64x4;
use wide::f64x4;

use super::model::{ChainBuffer, ChainView, JacobianRows, KinematicModel, RowMajor};
use super::turn;
use crate::Error;

/// Configurations evaluated at once by [`KinematicModel::forward_lanes`].
pub const CONFIGURATION_LANES: usize = 4;

/// Four configurations' values, one per lane.
type Lanes = WideF64x4;

/// Up to [`CONFIGURATION_LANES`] configurations, and their poses once
/// [`KinematicModel::forward_lanes`] has evaluated them.
#[derive(Clone, Debug, Default)]
pub struct LaneBuffer {
    /// Each configuration's inputs of the poses (joint variables, coupled
    /// motor variables, loads), as [`KinematicModel::forward_tilted`]
    /// computes them.
    loaded: [ChainBuffer; CONFIGURATION_LANES],
    /// Configurations pushed since the last [`clear`](Self::clear).
    filled: usize,
    joint_positions: Vec<Lanes>,
    coupled_motor_positions: Vec<Lanes>,
    torques: Vec<Lanes>,
    tilt_torques: Vec<Lanes>,
    turns: Vec<(Lanes, Lanes)>,
    poses: Vec<IsometryMatrix3<Lanes>>,
    angles: Vec<f64>,
    /// The Jacobians in lanes, row-major as [`KinematicModel::jacobian_rows`]
    /// writes one.
    jacobian: Vec<Lanes>,
}

impl LaneBuffer {
    /// Empties the buffer (its storage is kept).
    pub fn clear(&mut self) {
        self.filled = 0;
    }

    /// Number of configurations pushed.
    pub fn len(&self) -> usize {
        self.filled
    }

    /// Whether no configuration was pushed.
    pub fn is_empty(&self) -> bool {
        self.filled == 0
    }

    /// Whether [`CONFIGURATION_LANES`] configurations were pushed.
    pub fn is_full(&self) -> bool {
        self.filled == CONFIGURATION_LANES
    }

    /// Adds a configuration of `model` (motor variables and loads, as
    /// [`KinematicModel::forward_tilted`] takes them) in the next lane.
    ///
    /// # Errors
    /// As [`KinematicModel::forward_tilted`].
    ///
    /// # Panics
    /// When the buffer [`is_full`](Self::is_full).
    pub fn push(
        &mut self,
        model: &KinematicModel,
        motor_positions: &[f64],
        torques: Option<&[f64]>,
        tilt_torques: Option<&[f64]>,
    ) -> Result<(), Error> {
        assert!(!self.is_full(), "a lane buffer holds four configurations");
        model.load(
            motor_positions,
            torques,
            tilt_torques,
            &mut self.loaded[self.filled],
        )?;
        self.filled += 1;
        Ok(())
    }

    /// The end-effector pose `(−1)T(n+1)` of configuration `lane` (in the
    /// order pushed), once evaluated.
    ///
    /// # Panics
    /// When `lane` was not pushed, or the poses were not evaluated.
    pub fn world_from_tool(&self, lane: usize) -> IsometryMatrix3<f64> {
        assert!(lane < self.filled, "lane {lane} holds no configuration");
        let pose = self
            .poses
            .last()
            .expect("filled by KinematicModel::forward_lanes");
        IsometryMatrix3::from_parts(
            Translation3::from(
                pose.translation
                    .vector
                    .map(|value| value.0.as_array()[lane]),
            ),
            Rotation3::from_matrix_unchecked(
                pose.rotation.matrix().map(|value| value.0.as_array()[lane]),
            ),
        )
    }
}

/// Each lane's configuration of the `filled` first of `loaded`: a free
/// lane repeats the first.
#[inline(always)]
fn sources(
    loaded: &[ChainBuffer; CONFIGURATION_LANES],
    filled: usize,
) -> [&ChainBuffer; CONFIGURATION_LANES] {
    std::array::from_fn(|lane| &loaded[if lane < filled { lane } else { 0 }])
}

/// Each lane's `values(configuration)[i]`, for i below the longest's
/// length, into `out`; 0 where a configuration has fewer values (loads
/// given with some configurations only: a term weighted 0 adds +0, which
/// leaves every bit as the configuration alone, without the load, has it).
#[inline(always)]
fn gather(
    sources: &[&ChainBuffer; CONFIGURATION_LANES],
    values: impl Fn(&ChainBuffer) -> &[f64],
    out: &mut Vec<Lanes>,
) {
    let values: [&[f64]; CONFIGURATION_LANES] = std::array::from_fn(|lane| values(sources[lane]));
    let count = values.iter().map(|values| values.len()).max().unwrap_or(0);
    out.clear();
    out.extend((0..count).map(|i| {
        WideF64x4(f64x4::new(std::array::from_fn(|lane| {
            values[lane].get(i).copied().unwrap_or(0.0)
        })))
    }));
}

/// The widest instruction set of this processor, found once: the lanes'
/// products are compiled also for the wider sets of x86-64 (AVX2, AVX-512)
/// and run in this one, chosen at run time by `pulp` (faer's SIMD layer).
/// They then take one instruction where SSE2 takes two, and spill less.
/// The same IEEE operations in the same order, and no fused multiply-add
/// (Rust never contracts `a * b + c`, and `wide` chose its SSE2 code when
/// this crate was compiled): each lane's bits are the same in every
/// instruction set, those of its configuration alone (tested in each one
/// the processor has). What the work runs is compiled so where it is
/// inlined into it (`#[inline(always)]`).
fn widest() -> pulp::Arch {
    static WIDEST: OnceLock<pulp::Arch> = OnceLock::new();
    *WIDEST.get_or_init(pulp::Arch::new)
}

/// [`KinematicModel::forward_lanes`], as work for [`widest`].
struct Forward<'a>(&'a KinematicModel, &'a mut LaneBuffer);

impl pulp::WithSimd for Forward<'_> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _: S) {
        self.0.forward_lanes_inlined(self.1);
    }
}

/// [`KinematicModel::jacobian_rows_lanes`], as work for [`widest`].
struct Jacobian<'a, R>(&'a KinematicModel, &'a mut LaneBuffer, R, JacobianRows);

impl<'r, R: IntoIterator<Item = &'r mut Vec<f64>>> pulp::WithSimd for Jacobian<'_, R> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _: S) {
        let Jacobian(model, lanes, rows, which) = self;
        model.jacobian_rows_lanes_inlined(lanes, rows, which);
    }
}

impl KinematicModel {
    /// The direct model (eq. 1) of the configurations in `lanes`, at once
    /// (see the module docs): each one's poses are, bit for bit, those
    /// [`forward_tilted`](Self::forward_tilted) gives it.
    ///
    /// # Panics
    /// When `lanes` is empty.
    pub fn forward_lanes(&self, lanes: &mut LaneBuffer) {
        self.forward_lanes_in(widest(), lanes);
    }

    /// [`forward_lanes`](Self::forward_lanes) in the instruction set `arch`.
    pub(crate) fn forward_lanes_in(&self, arch: pulp::Arch, lanes: &mut LaneBuffer) {
        assert!(!lanes.is_empty(), "no configuration to evaluate");
        arch.dispatch(Forward(self, lanes));
    }

    /// [`forward_lanes`](Self::forward_lanes)' products, inlined into
    /// [`widest`]'s instruction set.
    #[inline(always)]
    fn forward_lanes_inlined(&self, lanes: &mut LaneBuffer) {
        let LaneBuffer {
            loaded,
            filled,
            joint_positions,
            coupled_motor_positions,
            torques,
            tilt_torques,
            turns,
            poses,
            angles,
            ..
        } = lanes;
        let sources = sources(loaded, *filled);
        gather(&sources, ChainBuffer::joint_positions, joint_positions);
        gather(&sources, |chain| chain.loads().0, coupled_motor_positions);
        gather(&sources, |chain| chain.loads().1, torques);
        gather(&sources, |chain| chain.loads().2, tilt_torques);
        // Each joint's turn in its four lanes, as one configuration's
        // turns take theirs (turn::sin_cos_lanes computes lanes alone).
        angles.clear();
        for source in sources {
            angles.extend(self.turn_angles(source.joint_positions()));
        }
        let revolute = angles.len() / CONFIGURATION_LANES;
        turns.clear();
        turns.extend((0..revolute).map(|joint| {
            let (sines, cosines) =
                turn::sin_cos_lanes(std::array::from_fn(|lane| angles[lane * revolute + joint]));
            (WideF64x4(f64x4::new(sines)), WideF64x4(f64x4::new(cosines)))
        }));
        self.poses(joint_positions, turns, poses);
    }

    /// The parameter Jacobian (Appendix II) of each configuration in
    /// `lanes` (evaluated by [`forward_lanes`](Self::forward_lanes)), row-
    /// major into the next of `rows` in the order pushed, as
    /// [`jacobian_rows`](Self::jacobian_rows) writes it, bit for bit.
    ///
    /// # Panics
    /// When `rows` yields fewer buffers than `lanes` holds configurations.
    pub fn jacobian_rows_lanes<'r>(
        &self,
        lanes: &mut LaneBuffer,
        rows: impl IntoIterator<Item = &'r mut Vec<f64>>,
        which: JacobianRows,
    ) {
        self.jacobian_rows_lanes_in(widest(), lanes, rows, which);
    }

    /// [`jacobian_rows_lanes`](Self::jacobian_rows_lanes) in the
    /// instruction set `arch`.
    pub(crate) fn jacobian_rows_lanes_in<'r>(
        &self,
        arch: pulp::Arch,
        lanes: &mut LaneBuffer,
        rows: impl IntoIterator<Item = &'r mut Vec<f64>>,
        which: JacobianRows,
    ) {
        arch.dispatch(Jacobian(self, lanes, rows, which));
    }

    /// [`jacobian_rows_lanes`](Self::jacobian_rows_lanes)' products,
    /// inlined into [`widest`]'s instruction set.
    #[inline(always)]
    fn jacobian_rows_lanes_inlined<'r>(
        &self,
        lanes: &mut LaneBuffer,
        rows: impl IntoIterator<Item = &'r mut Vec<f64>>,
        which: JacobianRows,
    ) {
        let LaneBuffer {
            filled,
            poses,
            coupled_motor_positions,
            torques,
            tilt_torques,
            jacobian,
            ..
        } = lanes;
        let size = which.count() * self.parameter_count();
        if jacobian.len() != size || !self.writes_every_column() {
            jacobian.clear();
            jacobian.resize(size, Lanes::splat(0.0));
        }
        let view = ChainView {
            poses,
            coupled_motor_positions,
            torques,
            tilt_torques,
        };
        self.fill_jacobian(
            &view,
            &mut RowMajor {
                rows: jacobian,
                parameters: self.parameter_count(),
                rotation: which == JacobianRows::Full,
            },
        );
        let mut rows = rows.into_iter();
        for lane in 0..*filled {
            let row = rows.next().expect("a buffer for each configuration");
            row.clear();
            row.extend(jacobian.iter().map(|values| values.0.as_array()[lane]));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_robots::{elastic_stanford, random_configuration, random_robot, stanford};
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// Every lane's pose and Jacobian rows are its configuration's alone,
    /// bit for bit: rigid, coupled, β-tilted and elastic chains under loads
    /// and gravity's tilts (given with some configurations of a group
    /// only), whole and selecting models, both sets of rows,
    /// groups of one to four (free lanes), buffers reused across robots, a
    /// zero weight in some lanes of a gain column (a joint whose coupled
    /// motor variable is 0 in one configuration only), and angles beyond
    /// the lanes' range (their own fallback); in every instruction set
    /// this processor has.
    #[test]
    fn each_lane_is_its_configuration_alone() {
        let mut rng = ChaCha8Rng::seed_from_u64(43);
        let mut robots = vec![stanford(), elastic_stanford(2, -0.03)];
        robots.extend((0..8).map(|i| random_robot(&mut rng, 2 + i % 6)));
        let mut lanes = LaneBuffer::default();
        let mut chain = ChainBuffer::default();
        let (mut alone, mut rows) = (Vec::new(), vec![Vec::new(); CONFIGURATION_LANES]);
        let mut compared = 0;
        let sets = instruction_sets();
        for robot in &robots {
            let whole = KinematicModel::new(robot);
            let np = whole.parameter_count();
            let kept: Vec<usize> = (0..np).filter(|_| rng.random_bool(0.6)).collect();
            let n = robot.joint_count();
            for model in [whole.clone(), whole.selecting(&kept)] {
                for group in 1..=CONFIGURATION_LANES {
                    let configurations: Vec<(Vec<f64>, Vec<f64>, Vec<f64>)> = (0..group)
                        .map(|lane| {
                            let mut qm = random_configuration(robot, &mut rng);
                            if lane == 1 {
                                qm[0] = 0.0;
                            }
                            if lane == 2 {
                                qm[n - 1] += 3e4;
                            }
                            // Loads given with some configurations only.
                            let torques = (0..n).map(|_| rng.random_range(-20.0..20.0)).collect();
                            let tilts = (0..2 * n).map(|_| rng.random_range(-5.0..5.0)).collect();
                            match lane {
                                1 => (qm, Vec::new(), Vec::new()),
                                3 => (qm, torques, Vec::new()),
                                _ => (qm, torques, tilts),
                            }
                        })
                        .collect();
                    lanes.clear();
                    for (qm, torques, tilts) in &configurations {
                        lanes
                            .push(&model, qm, given_loads(torques), given_loads(tilts))
                            .expect("valid");
                    }
                    for &arch in &sets {
                        model.forward_lanes_in(arch, &mut lanes);
                        for which in [JacobianRows::Full, JacobianRows::Position] {
                            for row in &mut rows {
                                row.iter_mut().for_each(|value| *value = f64::NAN);
                            }
                            model.jacobian_rows_lanes_in(arch, &mut lanes, rows.iter_mut(), which);
                            for (lane, (qm, torques, tilts)) in configurations.iter().enumerate() {
                                model
                                    .forward_tilted(
                                        qm,
                                        given_loads(torques),
                                        given_loads(tilts),
                                        &mut chain,
                                    )
                                    .expect("valid");
                                model.jacobian_rows(&chain, &mut alone, which);
                                let pose = lanes.world_from_tool(lane);
                                assert_eq!(
                                    pose,
                                    *chain.world_from_tool(),
                                    "{} {arch:?}",
                                    robot.name()
                                );
                                assert_eq!(rows[lane].len(), alone.len());
                                for (k, (a, b)) in rows[lane].iter().zip(&alone).enumerate() {
                                    assert_eq!(
                                        a.to_bits(),
                                        b.to_bits(),
                                        "{} lane {lane} of {group}, entry {k}, {arch:?}",
                                        robot.name()
                                    );
                                }
                                compared += 1;
                            }
                        }
                    }
                }
            }
        }
        assert_eq!(compared, robots.len() * 2 * 2 * 10 * sets.len());
    }

    /// The instruction sets the lanes run in on this processor: the
    /// baseline, and AVX2 and AVX-512 where it has them.
    fn instruction_sets() -> Vec<pulp::Arch> {
        #[allow(unused_mut)]
        let mut sets = vec![pulp::Arch::Scalar];
        #[cfg(target_arch = "x86_64")]
        {
            sets.extend(pulp::x86::V3::try_new().map(pulp::Arch::V3));
            sets.extend(pulp::x86::V4::try_new().map(pulp::Arch::V4));
        }
        sets
    }

    /// Loads as `push` takes them: none when empty.
    fn given_loads(values: &[f64]) -> Option<&[f64]> {
        (!values.is_empty()).then_some(values)
    }

    /// A configuration that does not fit the model is refused as
    /// [`KinematicModel::forward_tilted`] refuses it, and takes no lane.
    #[test]
    fn a_configuration_that_does_not_fit_is_refused_alone() {
        let model = KinematicModel::new(&stanford());
        let mut lanes = LaneBuffer::default();
        lanes.push(&model, &[0.1; 6], None, None).expect("valid");
        let mut chain = ChainBuffer::default();
        for qm in [vec![0.1; 5], vec![0.1, f64::NAN, 0.0, 0.0, 0.0, 0.0]] {
            let expected = model.forward(&qm, &mut chain).expect_err("invalid");
            let found = lanes.push(&model, &qm, None, None).expect_err("invalid");
            assert_eq!(found.to_string(), expected.to_string());
        }
        assert_eq!(lanes.len(), 1);
    }
}
