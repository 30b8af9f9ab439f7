//! Every configuration that puts an arm with a spherical wrist at a pose
//! (Pieper's reduction), for a global inverse model where the local solver
//! ([`inverse`](super::inverse)) would search from random starts.
//!
//! An arm of six joints R R (R|P) R R R has a *spherical wrist* when the
//! axes z4, z5, z6 meet in one point, the wrist centre: in the
//! Khalil–Kleinfinger frames (eq. 3) `d5 = r5 = d6 = 0`, with α5 and α6
//! neither 0 nor π, and no Hayati β on frames 1, 2, 4, 5 and 6 (β3, often
//! found between the parallel axes z2 and z3, is allowed). The wrist centre
//! is then the origin of frames 4 and 5; it depends on q1, q2, q3 only, and
//! a pose sets it: `c = p6 − r6 · z6`, frame 6's origin moved back along its
//! axis.
//!
//! **The arm (q1, q2, q3).** With `u = Rot(x, α1)ᵀ c − (d1, 0, 0)` (the
//! centre in frame 0, seen from joint 1) and `g(q3)` the centre in frame 2,
//! shifted by r2 along z2, the centre in frame 1 is
//! `f = Rot(x, α2) · ((d2, 0, 0) + Rot(z, θ2 + q2) · g)`. Joint 1 turns f
//! about z1, so the centre's height along z1 and its distance from z1 are
//! the target's whatever q1 is (Pieper):
//!
//! - `‖f‖² = d2² + 2 d2 P + ‖g‖² = u_x² + u_y² + (u_z − r1)²`
//! - `f_z = sin α2 · Q + cos α2 · g_z = u_z − r1`
//!
//! where `(P, Q) = Rot(θ2 + q2) · (g_x, g_y)`, so `P² + Q² = g_x² + g_y²`.
//! When d2 ≠ 0 and sin α2 ≠ 0 each equation gives one of P, Q and
//! `h(q3) = P² + Q² − g_x² − g_y²` vanishes at the solutions (a quartic in
//! tan(q3/2) for a revolute joint 3); when d2 = 0 (a shoulder such as the
//! PUMA's or the Stanford arm's) the first equation alone is `h(q3)` and P
//! takes both signs; when sin α2 = 0 (parallel z1, z2) the second is, and Q
//! takes both. The roots of `h` are found by sampling it (96 points over a
//! turn of a revolute joint 3; for a prismatic one, from −L to L with L its
//! largest value's size plus its range: the arm reversed reaches the centre
//! too) and bisecting every change of sign: a double
//! root (the centre on the boundary of the arm's reach) may be missed. Then
//! `θ2 + q2 = atan2(Q, P) − atan2(g_y, g_x)` and
//! `θ1 + q1 = atan2(u_y, u_x) − atan2(f_y, f_x)`.
//!
//! **The wrist (q4, q5, q6).** `M = (R03 · Rot(x, α4))ᵀ · R06 =
//! Rot(z, a) · Rot(x, α5) · Rot(z, b) · Rot(x, α6) · Rot(z, c)` with
//! `a = θ4 + q4`, `b = θ5 + q5`, `c = θ6 + q6`: M's third column m gives
//! `cos b = (cos α5 cos α6 − m_z)/(sin α5 sin α6)` (the two wrists, ±b),
//! then `a` from m's x and y, and `c` from what is left. At the wrist's
//! singularity (sin b = 0) a is set to 0 and c takes the whole turn.
//!
//! So a pose has up to eight configurations (four arms, two wrists), each
//! returned with its revolute joints anywhere in a turn: the caller chooses
//! the turns ([`SphericalWrist::branches_near`] takes those closest to a
//! reference). They are the robot's own, exact to rounding; for a robot
//! close to this one (a calibrated model) they are starting points a few
//! Newton steps away from its solutions (near a singularity or the edge of
//! the reach, where Newton steps fail, a damped solver's start).

use std::f64::consts::{PI, TAU};

use nalgebra::{IsometryMatrix3, Matrix3, Rotation3, Vector3};

use super::direct::frame_transform;
use super::turn::wrapped as wrap;
use crate::frame::{Frame, FrameType, Joint};
use crate::robot::Robot;

/// Samples of `h(q3)` over the searched range of q3 (a turn: 3.75° apart).
const SAMPLES: usize = 96;
/// Bisections of a change of sign of `h(q3)` (from 3.75°: to 1e-13 rad).
const BISECTIONS: usize = 40;
/// Below this, d2 (metres) and sin α2 count as zero: the reductions with
/// one equation in q3 alone.
const DEGENERATE: f64 = 1e-9;
/// A wrist whose sin α5 or sin α6 is below this reaches too few
/// orientations to be solved so (and is not a wrist).
const WRIST_TWIST: f64 = 1e-6;

/// Which of the two equations holds q3 alone (see the module docs).
#[derive(Copy, Clone, Debug, PartialEq)]
enum Reduction {
    /// d2 ≠ 0 and sin α2 ≠ 0: `h = P² + Q² − g_x² − g_y²`.
    Both,
    /// d2 = 0: the distance from z1 and the height along it set ‖g‖.
    Distance,
    /// sin α2 = 0: the height along z1 sets g_z.
    Height,
}

/// An arm with a spherical wrist, ready to give every configuration that
/// reaches a pose ([`SphericalWrist::of`] says whether a robot is one).
#[derive(Clone, Debug)]
pub struct SphericalWrist {
    /// `(−1)T(0)⁻¹`: the world in frame 0.
    base_inverse: IsometryMatrix3<f64>,
    /// `(6)T(7)⁻¹`: frame 6 from the end frame.
    tool_inverse: IsometryMatrix3<f64>,
    /// Frames 1..=6.
    frames: [Frame; 6],
    /// The wrist centre (frame 4's origin) in frame 3.
    centre_in_3: Vector3<f64>,
    reduction: Reduction,
    /// The range of q3 searched: a turn, or ±(a prismatic joint's largest
    /// value's size plus its range).
    q3_range: (f64, f64),
}

impl SphericalWrist {
    /// The arm of `robot` when it has a spherical wrist (see the module
    /// docs) and no compliance; `None` otherwise.
    pub fn of(robot: &Robot) -> Option<SphericalWrist> {
        if robot.is_elastic() {
            return None;
        }
        SphericalWrist::of_frames(robot.frames(), robot.joints())
    }

    /// The arm of frames 0..=7 and joints 1..=6 (see [`of`](Self::of)).
    fn of_frames(frames: &[Frame], joints: &[Joint]) -> Option<SphericalWrist> {
        if joints.len() != 6 || frames.len() != 8 {
            return None;
        }
        let types: Vec<FrameType> = frames[1..7].iter().map(|f| f.frame_type).collect();
        let revolute = |j: usize| types[j - 1] == FrameType::Revolute;
        if !(revolute(1) && revolute(2) && revolute(4) && revolute(5) && revolute(6))
            || types[2] == FrameType::Fixed
        {
            return None;
        }
        if [1, 2, 4, 5, 6].iter().any(|&j| frames[j].beta != 0.0)
            || frames[5].d != 0.0
            || frames[5].r != 0.0
            || frames[6].d != 0.0
            || frames[5].alpha.sin().abs() < WRIST_TWIST
            || frames[6].alpha.sin().abs() < WRIST_TWIST
        {
            return None;
        }
        let reduction = match (
            frames[2].d.abs() < DEGENERATE,
            frames[2].alpha.sin().abs() < DEGENERATE,
        ) {
            (false, false) => Reduction::Both,
            (true, false) => Reduction::Distance,
            (false, true) => Reduction::Height,
            (true, true) => return None,
        };
        let q3_range = match types[2] {
            // The arm reversed (q3 < 0 where the range is positive) reaches
            // the centre too: searched as far on the other side.
            FrameType::Prismatic => {
                let joint = joints[2];
                let span = (joint.qmax - joint.qmin).max(0.1);
                let reach = joint.qmax.abs().max(joint.qmin.abs()) + span;
                (-reach, reach)
            }
            _ => (-PI, PI),
        };
        Some(SphericalWrist {
            base_inverse: frame_transform(&frames[0], 0.0).inverse(),
            tool_inverse: frame_transform(&frames[7], 0.0).inverse(),
            frames: std::array::from_fn(|j| frames[j + 1]),
            centre_in_3: frame_transform(&frames[4], 0.0).translation.vector,
            reduction,
            q3_range,
        })
    }

    /// The joint positions q1..q6 of every configuration found that puts
    /// the end frame at `pose` (world frame), each revolute joint within
    /// (−2π, 2π): up to eight, none when the wrist centre is out of the
    /// arm's reach.
    pub fn branches(&self, pose: &IsometryMatrix3<f64>) -> Vec<[f64; 6]> {
        let [f1, f2, f3, f4, f5, f6] = &self.frames;
        let wrist = self.base_inverse * pose * self.tool_inverse;
        let z6 = wrist.rotation.matrix().column(2).into_owned();
        let centre = wrist.translation.vector - f6.r * z6;
        let u = rot_x(f1.alpha).transpose() * centre - Vector3::new(f1.d, 0.0, 0.0);
        let height = u.z - f1.r;
        let squared = u.x * u.x + u.y * u.y + height * height;
        let (sin2, cos2) = f2.alpha.sin_cos();
        // g(q3): the centre in frame 2, moved by r2 along z2.
        let g = |q3: f64| {
            frame_transform(f3, q3)
                .transform_point(&self.centre_in_3.into())
                .coords
                + Vector3::new(0.0, 0.0, f2.r)
        };
        let p_of = |g: &Vector3<f64>| (squared - f2.d * f2.d - g.norm_squared()) / (2.0 * f2.d);
        let q_of = |g: &Vector3<f64>| (height - cos2 * g.z) / sin2;
        let h = |q3: f64| {
            let g = g(q3);
            match self.reduction {
                Reduction::Both => p_of(&g).powi(2) + q_of(&g).powi(2) - g.x * g.x - g.y * g.y,
                Reduction::Distance => g.norm_squared() - squared,
                Reduction::Height => cos2 * g.z - height,
            }
        };
        let mut found = Vec::new();
        for q3 in roots(&h, self.q3_range, f3.frame_type == FrameType::Revolute) {
            let g = g(q3);
            let planar = g.x * g.x + g.y * g.y;
            // Each root's (P, Q): one, or a pair of opposite signs.
            let mut pairs = [None, None];
            match self.reduction {
                Reduction::Both => pairs[0] = Some((p_of(&g), q_of(&g))),
                Reduction::Distance => {
                    let q = q_of(&g);
                    for (pair, p) in pairs.iter_mut().zip(both_roots(planar - q * q)) {
                        *pair = p.map(|p| (p, q));
                    }
                }
                Reduction::Height => {
                    let p = p_of(&g);
                    for (pair, q) in pairs.iter_mut().zip(both_roots(planar - p * p)) {
                        *pair = q.map(|q| (p, q));
                    }
                }
            }
            for (p, q) in pairs.into_iter().flatten() {
                let phi2 = q.atan2(p) - g.y.atan2(g.x);
                let f = Vector3::new(f2.d + p, cos2 * q - sin2 * g.z, sin2 * q + cos2 * g.z);
                let phi1 = u.y.atan2(u.x) - f.y.atan2(f.x);
                let arm = [wrap(phi1 - f1.theta), wrap(phi2 - f2.theta), q3];
                let to_3 = frame_transform(f1, arm[0])
                    * frame_transform(f2, arm[1])
                    * frame_transform(f3, arm[2]);
                let m = (to_3.rotation.matrix() * rot_x(f4.alpha)).transpose()
                    * wrist.rotation.matrix();
                for [a, b, c] in wrist_turns(&m, f5.alpha, f6.alpha) {
                    found.push([
                        arm[0],
                        arm[1],
                        arm[2],
                        wrap(a - f4.theta),
                        wrap(b - f5.theta),
                        wrap(c - f6.theta),
                    ]);
                }
            }
        }
        found
    }

    /// [`branches`](Self::branches) with every revolute joint turned by
    /// whole turns to the value closest to `reference` (joint positions).
    pub fn branches_near(&self, pose: &IsometryMatrix3<f64>, reference: &[f64]) -> Vec<[f64; 6]> {
        let mut found = self.branches(pose);
        for branch in &mut found {
            for (j, (q, reference)) in branch.iter_mut().zip(reference).enumerate() {
                if self.frames[j].frame_type == FrameType::Revolute {
                    *q += TAU * ((*reference - *q) / TAU).round();
                }
            }
        }
        found
    }
}

/// `Rot(x, α)`.
fn rot_x(alpha: f64) -> Matrix3<f64> {
    *Rotation3::from_axis_angle(&Vector3::x_axis(), alpha).matrix()
}

/// `Rot(z, γ)`.
fn rot_z(gamma: f64) -> Matrix3<f64> {
    *Rotation3::from_axis_angle(&Vector3::z_axis(), gamma).matrix()
}

/// `+√x` and `−√x` (one of them when x is rounding's worth from zero, none
/// when x is below it).
fn both_roots(x: f64) -> [Option<f64>; 2] {
    if x < -1e-12 {
        [None, None]
    } else if x < 1e-24 {
        [Some(0.0), None]
    } else {
        let root = x.sqrt();
        [Some(root), Some(-root)]
    }
}

/// The zeros of `h` over `range` where it changes sign between samples
/// (`periodic`: the range is a turn and its ends meet), each bisected.
fn roots(h: &impl Fn(f64) -> f64, (low, high): (f64, f64), periodic: bool) -> Vec<f64> {
    let step = (high - low) / SAMPLES as f64;
    let at = |i: usize| low + step * i as f64;
    let values: Vec<f64> = (0..SAMPLES).map(|i| h(at(i))).collect();
    let intervals = if periodic { SAMPLES } else { SAMPLES - 1 };
    let mut found = Vec::new();
    for i in 0..intervals {
        let (h0, h1) = (values[i], values[(i + 1) % SAMPLES]);
        if !(h0.is_finite() && h1.is_finite()) || (h0 > 0.0) == (h1 > 0.0) {
            continue;
        }
        if h0 == 0.0 {
            found.push(at(i));
            continue;
        }
        let (mut a, mut b) = (at(i), at(i) + step);
        for _ in 0..BISECTIONS {
            let middle = 0.5 * (a + b);
            if (h(middle) > 0.0) == (h0 > 0.0) {
                a = middle;
            } else {
                b = middle;
            }
        }
        found.push(0.5 * (a + b));
    }
    found
}

/// The turns (a, b, c) with `Rot(z, a) Rot(x, α5) Rot(z, b) Rot(x, α6)
/// Rot(z, c) = m`: two wrists, one at the singularity, none when m's axis
/// is beyond what the twists reach.
fn wrist_turns(m: &Matrix3<f64>, alpha5: f64, alpha6: f64) -> Vec<[f64; 3]> {
    let (s5, c5) = alpha5.sin_cos();
    let (s6, c6) = alpha6.sin_cos();
    let axis = m.column(2);
    let cos_b = (c5 * c6 - axis.z) / (s5 * s6);
    if cos_b.abs() > 1.0 + 1e-9 {
        return Vec::new();
    }
    let b = cos_b.clamp(-1.0, 1.0).acos();
    let wrists: &[f64] = if b.sin().abs() < 1e-12 {
        &[b]
    } else {
        &[b, -b]
    };
    wrists
        .iter()
        .map(|&b| {
            let (sb, cb) = b.sin_cos();
            let (vx, vy) = (s6 * sb, -c5 * s6 * cb - s5 * c6);
            let a = if vx.hypot(vy) < 1e-12 {
                0.0
            } else {
                axis.y.atan2(axis.x) - vy.atan2(vx)
            };
            let rest = (rot_z(a) * rot_x(alpha5) * rot_z(b) * rot_x(alpha6)).transpose() * m;
            [a, b, rest[(1, 0)].atan2(rest[(0, 0)])]
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::RobotSpec;
    use crate::kinematics::terminal_pose;
    use crate::test_robots::{random_configuration, stanford};
    use rand::{Rng, RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;
    use std::f64::consts::FRAC_PI_2;

    /// A six-axis arm with a spherical wrist and random geometry (lengths
    /// 0.1–0.5 m, twists anywhere): `shoulder` chooses d2 = 0, sin α2 = 0
    /// or neither, `prismatic` joint 3's kind.
    fn random_wrist_arm(rng: &mut impl Rng, shoulder: usize, prismatic: bool) -> Robot {
        let mut length = || rng.random_range(0.1..0.5);
        let lengths: Vec<f64> = (0..12).map(|_| length()).collect();
        let angles: Vec<f64> = (0..14).map(|_| rng.random_range(-PI..PI)).collect();
        let frame = |frame_type, alpha, d, theta, r| Frame {
            alpha,
            d,
            theta,
            r,
            ..Frame::new(frame_type)
        };
        let (alpha2, d2) = match shoulder {
            0 => (angles[1], lengths[1]),
            1 => (angles[1], 0.0),
            _ => (PI, lengths[1]),
        };
        let third = if prismatic {
            FrameType::Prismatic
        } else {
            FrameType::Revolute
        };
        let frames = vec![
            frame(FrameType::Fixed, 0.0, 0.0, angles[8], lengths[8]),
            frame(
                FrameType::Revolute,
                angles[2],
                lengths[2],
                angles[9],
                lengths[9],
            ),
            frame(FrameType::Revolute, alpha2, d2, angles[10], lengths[10]),
            frame(third, angles[3], lengths[3], angles[11], lengths[11]),
            frame(
                FrameType::Revolute,
                angles[4],
                lengths[4],
                angles[12],
                lengths[5],
            ),
            frame(
                FrameType::Revolute,
                FRAC_PI_2 + 0.3 * angles[5] / PI,
                0.0,
                angles[13],
                0.0,
            ),
            frame(FrameType::Revolute, -FRAC_PI_2, 0.0, angles[6], lengths[6]),
            frame(FrameType::Fixed, angles[7], lengths[7], 0.4, lengths[0]),
        ];
        let mut joints: Vec<Joint> = (0..6)
            .map(|_| Joint::default_for(FrameType::Revolute))
            .collect();
        if prismatic {
            joints[2] = Joint {
                qmin: -0.5,
                qmax: 0.5,
                ..Joint::default_for(FrameType::Prismatic)
            };
        }
        Robot::new(RobotSpec::rigid("wrist arm", frames, joints)).expect("valid")
    }

    /// Whether two configurations are the same, revolute joints modulo a turn.
    fn same(robot: &Robot, a: &[f64], b: &[f64], tolerance: f64) -> bool {
        a.iter()
            .zip(b)
            .zip(robot.frames()[1..7].iter())
            .all(|((a, b), frame)| {
                let difference = a - b;
                match frame.frame_type {
                    FrameType::Revolute => wrap(difference).abs() < tolerance,
                    _ => difference.abs() < tolerance,
                }
            })
    }

    /// Every configuration of random arms (each reduction, joint 3 revolute
    /// or prismatic) and of the Stanford arm is among the branches of its
    /// own pose, and every branch reaches that pose: checked by the direct
    /// model (eq. 1–3), an independent route.
    #[test]
    fn every_branch_reaches_the_pose_and_the_configuration_is_among_them() {
        let mut rng = ChaCha8Rng::seed_from_u64(12);
        let (mut trials, mut found, mut branches) = (0, 0, 0);
        for trial in 0..240 {
            let robot = if trial % 8 == 7 {
                stanford()
            } else {
                random_wrist_arm(&mut rng, trial % 3, trial % 2 == 1)
            };
            let wrist = SphericalWrist::of(&robot).expect("a spherical wrist");
            let q = random_configuration(&robot, &mut rng);
            let pose = terminal_pose(&robot, &q).expect("valid");
            let all = wrist.branches_near(&pose, &q);
            trials += 1;
            branches += all.len();
            for branch in &all {
                let reached = terminal_pose(&robot, branch).expect("valid");
                let apart = (reached.translation.vector - pose.translation.vector).norm();
                let turned = (reached.rotation.matrix() - pose.rotation.matrix()).amax();
                assert!(
                    apart < 1e-9 && turned < 1e-9,
                    "trial {trial}: {apart} m, {turned} rad"
                );
            }
            found += usize::from(all.iter().any(|branch| same(&robot, branch, &q, 1e-7)));
            // The turns chosen are the reference's.
            if let Some(branch) = all
                .iter()
                .find(|branch| same(&robot, &branch[..], &q, 1e-7))
            {
                assert!(branch.iter().zip(&q).all(|(a, b)| (a - b).abs() < 1e-7));
            }
        }
        assert!(found * 100 >= trials * 98, "found {found} of {trials}");
        assert!(
            branches >= 4 * trials,
            "{branches} branches in {trials} trials"
        );
    }

    /// The PUMA 560 (d2 = 0, joint 3 revolute) has its eight configurations
    /// (two shoulders, two elbows, two wrists) at a pose well inside its
    /// reach; the Stanford arm four within its joint 3's range and eight
    /// with the prismatic joint reversed.
    #[test]
    fn a_pose_inside_the_reach_has_eight_configurations() {
        let frame = |frame_type, alpha: f64, d, r| Frame {
            alpha,
            d,
            r,
            ..Frame::new(frame_type)
        };
        use FrameType::{Fixed, Revolute};
        let puma = Robot::new(RobotSpec::rigid(
            "PUMA 560",
            vec![
                frame(Fixed, 0.0, 0.0, 0.6604),
                frame(Revolute, 0.0, 0.0, 0.0),
                frame(Revolute, -FRAC_PI_2, 0.0, 0.0),
                frame(Revolute, 0.0, 0.4318, 0.15005),
                frame(Revolute, -FRAC_PI_2, 0.0203, 0.4318),
                frame(Revolute, FRAC_PI_2, 0.0, 0.0),
                frame(Revolute, -FRAC_PI_2, 0.0, 0.0),
                frame(Fixed, 0.0, 0.0, 0.05625),
            ],
            vec![Joint::default_for(Revolute); 6],
        ))
        .expect("valid");
        let q = [0.3, -0.7, 0.9, 0.4, 0.8, -0.2];
        let pose = terminal_pose(&puma, &q).expect("valid");
        let wrist = SphericalWrist::of(&puma).expect("a spherical wrist");
        let all = wrist.branches_near(&pose, &q);
        assert_eq!(all.len(), 8, "{all:?}");
        for (i, a) in all.iter().enumerate() {
            for b in &all[i + 1..] {
                assert!(!same(&puma, a, b, 1e-3), "{a:?} twice");
            }
        }
        let robot = stanford();
        let q = [0.4, 1.1, 0.45, 0.3, -0.8, 0.2];
        let pose = terminal_pose(&robot, &q).expect("valid");
        let all = SphericalWrist::of(&robot).expect("wrist").branches(&pose);
        assert_eq!(all.len(), 8, "{all:?}");
        let within = all.iter().filter(|branch| branch[2] > 0.0).count();
        assert_eq!(within, 4);
    }

    /// What is not an arm with a spherical wrist is said so.
    #[test]
    fn other_arms_have_no_closed_form() {
        let mut spec = stanford().to_spec();
        spec.frames[5].d = 0.01;
        assert!(SphericalWrist::of(&Robot::new(spec).expect("valid")).is_none());
        let mut spec = stanford().to_spec();
        spec.frames[4].beta = 0.01;
        assert!(SphericalWrist::of(&Robot::new(spec).expect("valid")).is_none());
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let seven = crate::test_robots::random_robot(&mut rng, 7);
        assert!(SphericalWrist::of(&seven).is_none());
    }
}
