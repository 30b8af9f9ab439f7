//! The performance characteristics of ISO 9283 ("Manipulating industrial
//! robots — Performance criteria and related test methods"), clause 7: the
//! test cube and its five poses, pose accuracy and repeatability (7.2),
//! multi-directional pose accuracy variation, and distance accuracy and
//! repeatability (7.3), computed from attained poses as the standard states
//! them.
//!
//! ## The test cube and its poses
//!
//! A cube of side `s` centred at `c`, its edges along the base frame's
//! axes ([`TestCube`]). The measuring plane C1–C2–C7–C8 is the diagonal
//! plane through the cube's vertical edges at (−x, −y) and (+x, +y); its
//! corners, in gecaro's numbering, are C1 = c + s/2·(−1, −1, −1),
//! C2 = c + s/2·(+1, +1, −1), C7 = c + s/2·(+1, +1, +1) and
//! C8 = c + s/2·(−1, −1, +1). Its diagonals are two of the cube's space
//! diagonals (C1–C7 and C2–C8, length √3·s). P1 is the cube's centre; P2 to
//! P5 lie on those diagonals at 10 % of the diagonal's length from C1, C2,
//! C7 and C8 ([`TestCube::poses`]).
//!
//! ## Pose accuracy and repeatability (7.2)
//!
//! For the `n` attained positions `x_j` of one commanded pose `x_c`
//! (metres) and their orientations, [`pose_characteristics`]:
//!
//! - the barycentre `x̄ = (1/n) Σ x_j`;
//! - **AP_P** `= ‖x̄ − x_c‖`, with its components `AP_x, AP_y, AP_z`;
//! - **AP_a, AP_b, AP_c** `= ā − a_c, …`: the mean orientation error about
//!   x, y and z. gecaro takes each attained orientation's error as the
//!   roll, pitch, yaw (about the fixed x, y, z) of `R_cᵀ R_j`, the attained
//!   orientation seen from the commanded one — the standard's difference of
//!   angles to first order, without a turn's wrap where an angle passes ±π;
//! - **RP_l** `= l̄ + 3 S_l`, with `l_j = ‖x_j − x̄‖`, `l̄` their mean and
//!   `S_l = √(Σ (l_j − l̄)² / (n − 1))`;
//! - **RP_a, RP_b, RP_c** `= ±3 S_a, …`, `S_a = √(Σ (a_j − ā)² / (n − 1))`.
//!
//! ## Multi-directional pose accuracy variation
//!
//! A pose approached from several directions: for each approach its
//! barycentre and mean orientation error; **vAP_P** is the largest distance
//! between two approaches' barycentres, **vAP_a, vAP_b, vAP_c** the largest
//! difference of their mean errors ([`multi_directional`]).
//!
//! ## Distance accuracy and repeatability (7.3)
//!
//! Between two commanded positions `P_c1`, `P_c2` (P2 and P4 of the cube),
//! attained `n` times each: `D_c = ‖P_c1 − P_c2‖`, `D_j = ‖P_1j − P_2j‖`;
//! **AD_P** `= D̄ − D_c` and **RD** `= ±3 S_D`,
//! `S_D = √(Σ (D_j − D̄)² / (n − 1))` ([`distance_characteristics`]).
//!
//! ```
//! use gecaro_calib::iso9283::{TestCube, pose_characteristics};
//! use nalgebra::{IsometryMatrix3, Vector3};
//!
//! let cube = TestCube::new(Vector3::new(0.8, 0.0, 0.6), 0.4)?;
//! let [p1, ..] = cube.poses();
//! assert_eq!(p1, Vector3::new(0.8, 0.0, 0.6));
//! // Three cycles 0.1 mm off along x, 0.05 mm apart along y.
//! let commanded = IsometryMatrix3::translation(p1.x, p1.y, p1.z);
//! let attained: Vec<IsometryMatrix3<f64>> = [-5e-5, 0.0, 5e-5]
//!     .iter()
//!     .map(|dy| IsometryMatrix3::translation(p1.x + 1e-4, p1.y + dy, p1.z))
//!     .collect();
//! let pose = pose_characteristics(&commanded, &attained)?;
//! assert!((pose.accuracy - 1e-4).abs() < 1e-12);
//! # Ok::<(), gecaro_calib::Error>(())
//! ```

use nalgebra::{IsometryMatrix3, Vector3};

use crate::Error;

/// The distance of P2–P5 from their corners, as a share of the diagonal.
pub const CORNER_SHARE: f64 = 0.1;

/// The cube of the test (see the module docs): its centre in the base
/// frame and its side (metres).
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct TestCube {
    /// The cube's centre, base frame (m).
    pub centre: Vector3<f64>,
    /// Its side (m).
    pub side: f64,
}

impl TestCube {
    /// The cube of `side` (m) centred at `centre`.
    ///
    /// # Errors
    /// [`Error::InvalidData`] for a side that is not positive and finite, or
    /// a centre that is not finite.
    pub fn new(centre: Vector3<f64>, side: f64) -> Result<Self, Error> {
        if !(side.is_finite() && side > 0.0 && centre.iter().all(|x| x.is_finite())) {
            return Err(Error::InvalidData {
                line: None,
                message: format!(
                    "the test cube needs a finite centre and a side above 0 m, not side {side} m \
                     at ({}, {}, {})",
                    centre.x, centre.y, centre.z
                ),
            });
        }
        Ok(TestCube { centre, side })
    }

    /// The corners C1, C2, C7, C8 of the measuring plane (module docs).
    pub fn plane_corners(&self) -> [Vector3<f64>; 4] {
        let h = self.side / 2.0;
        [
            Vector3::new(-h, -h, -h),
            Vector3::new(h, h, -h),
            Vector3::new(h, h, h),
            Vector3::new(-h, -h, h),
        ]
        .map(|corner| self.centre + corner)
    }

    /// P1 (the centre), then P2–P5 at [`CORNER_SHARE`] of the diagonal from
    /// C1, C2, C7 and C8 along the plane's diagonals.
    pub fn poses(&self) -> [Vector3<f64>; 5] {
        let [c1, c2, c7, c8] = self.plane_corners();
        let towards = |from: Vector3<f64>, to: Vector3<f64>| from + CORNER_SHARE * (to - from);
        [
            self.centre,
            towards(c1, c7),
            towards(c2, c8),
            towards(c7, c1),
            towards(c8, c2),
        ]
    }
}

/// Pose accuracy and repeatability of one commanded pose (7.2; module
/// docs). Lengths in metres, angles in radians.
#[derive(Clone, Debug, PartialEq)]
pub struct PoseCharacteristics {
    /// Cycles measured (n).
    pub cycles: usize,
    /// The barycentre of the attained positions x̄ (base frame).
    pub barycentre: Vector3<f64>,
    /// AP_P = ‖x̄ − x_c‖.
    pub accuracy: f64,
    /// AP_x, AP_y, AP_z: x̄ − x_c.
    pub accuracy_components: Vector3<f64>,
    /// AP_a, AP_b, AP_c: the mean orientation error about x, y, z.
    pub orientation_accuracy: [f64; 3],
    /// RP_l = l̄ + 3 S_l.
    pub repeatability: f64,
    /// RP_a, RP_b, RP_c = 3 S_a, 3 S_b, 3 S_c (the standard writes ±).
    pub orientation_repeatability: [f64; 3],
}

/// The orientation error of `attained` against `commanded`: roll, pitch,
/// yaw of `R_cᵀ R_j` (module docs).
fn orientation_error(
    commanded: &IsometryMatrix3<f64>,
    attained: &IsometryMatrix3<f64>,
) -> [f64; 3] {
    let (a, b, c) = (commanded.rotation.inverse() * attained.rotation).euler_angles();
    [a, b, c]
}

/// The mean and the sample standard deviation (n − 1) of `values`.
fn mean_and_deviation(values: &[f64]) -> (f64, f64) {
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let squares: f64 = values.iter().map(|value| (value - mean).powi(2)).sum();
    (mean, (squares / (n - 1.0)).sqrt())
}

/// Checks that there are at least two cycles (a standard deviation needs
/// them) and that every pose is finite.
fn check_cycles(what: &str, poses: &[IsometryMatrix3<f64>]) -> Result<(), Error> {
    if poses.len() < 2 {
        return Err(Error::InvalidData {
            line: None,
            message: format!(
                "{what}: {} attained pose(s); repeatability needs at least 2 cycles (ISO 9283 \
                 asks for 30)",
                poses.len()
            ),
        });
    }
    if let Some(index) = poses.iter().position(|pose| {
        !(pose.translation.vector.iter().all(|x| x.is_finite())
            && pose.rotation.matrix().iter().all(|x| x.is_finite()))
    }) {
        return Err(Error::InvalidData {
            line: None,
            message: format!("{what}: attained pose {} is not finite", index + 1),
        });
    }
    Ok(())
}

/// Pose accuracy and repeatability of `attained` (one per cycle) against
/// `commanded` (module docs).
///
/// # Errors
/// [`Error::InvalidData`] for fewer than two cycles or a pose that is not
/// finite.
pub fn pose_characteristics(
    commanded: &IsometryMatrix3<f64>,
    attained: &[IsometryMatrix3<f64>],
) -> Result<PoseCharacteristics, Error> {
    check_cycles("pose characteristics", attained)?;
    let n = attained.len() as f64;
    let barycentre = attained
        .iter()
        .map(|pose| pose.translation.vector)
        .sum::<Vector3<f64>>()
        / n;
    let components = barycentre - commanded.translation.vector;
    let distances: Vec<f64> = attained
        .iter()
        .map(|pose| (pose.translation.vector - barycentre).norm())
        .collect();
    let (mean_distance, distance_deviation) = mean_and_deviation(&distances);
    let errors: Vec<[f64; 3]> = attained
        .iter()
        .map(|pose| orientation_error(commanded, pose))
        .collect();
    let mut orientation_accuracy = [0.0; 3];
    let mut orientation_repeatability = [0.0; 3];
    for axis in 0..3 {
        let about: Vec<f64> = errors.iter().map(|error| error[axis]).collect();
        let (mean, deviation) = mean_and_deviation(&about);
        orientation_accuracy[axis] = mean;
        orientation_repeatability[axis] = 3.0 * deviation;
    }
    Ok(PoseCharacteristics {
        cycles: attained.len(),
        barycentre,
        accuracy: components.norm(),
        accuracy_components: components,
        orientation_accuracy,
        repeatability: mean_distance + 3.0 * distance_deviation,
        orientation_repeatability,
    })
}

/// Multi-directional pose accuracy variation of one commanded pose.
#[derive(Clone, Debug, PartialEq)]
pub struct DirectionalVariation {
    /// vAP_P: the largest distance between two approaches' barycentres (m).
    pub position: f64,
    /// vAP_a, vAP_b, vAP_c: the largest difference of two approaches' mean
    /// orientation errors (rad).
    pub orientation: [f64; 3],
}

/// vAP of `commanded` approached from several directions, `approaches[h]`
/// the attained poses of approach h (module docs).
///
/// # Errors
/// [`Error::InvalidData`] for fewer than two approaches, or an approach
/// [`pose_characteristics`] refuses.
pub fn multi_directional(
    commanded: &IsometryMatrix3<f64>,
    approaches: &[Vec<IsometryMatrix3<f64>>],
) -> Result<DirectionalVariation, Error> {
    if approaches.len() < 2 {
        return Err(Error::InvalidData {
            line: None,
            message: format!(
                "multi-directional variation: {} approach direction(s); it compares at least 2 \
                 (ISO 9283 approaches each pose from 3)",
                approaches.len()
            ),
        });
    }
    let each: Vec<PoseCharacteristics> = approaches
        .iter()
        .map(|attained| pose_characteristics(commanded, attained))
        .collect::<Result<_, _>>()?;
    let mut variation = DirectionalVariation {
        position: 0.0,
        orientation: [0.0; 3],
    };
    for (h, first) in each.iter().enumerate() {
        for second in &each[h + 1..] {
            variation.position = variation
                .position
                .max((first.barycentre - second.barycentre).norm());
            for axis in 0..3 {
                variation.orientation[axis] = variation.orientation[axis].max(
                    (first.orientation_accuracy[axis] - second.orientation_accuracy[axis]).abs(),
                );
            }
        }
    }
    Ok(variation)
}

/// Distance accuracy and repeatability between two commanded positions
/// (7.3; module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct DistanceCharacteristics {
    /// D_c = ‖P_c1 − P_c2‖ (m).
    pub commanded: f64,
    /// D̄, the mean attained distance (m).
    pub mean: f64,
    /// AD_P = D̄ − D_c (m).
    pub accuracy: f64,
    /// RD = 3 S_D (the standard writes ±; m).
    pub repeatability: f64,
}

/// Distance accuracy and repeatability of the pairs `(first[j], second[j])`
/// attained for the commanded positions `commanded_first`, `commanded_second`.
///
/// # Errors
/// [`Error::InvalidData`] for fewer than two cycles, unequal counts, or a
/// position that is not finite.
pub fn distance_characteristics(
    (commanded_first, commanded_second): (Vector3<f64>, Vector3<f64>),
    first: &[Vector3<f64>],
    second: &[Vector3<f64>],
) -> Result<DistanceCharacteristics, Error> {
    let invalid = |message: String| Error::InvalidData {
        line: None,
        message,
    };
    if first.len() != second.len() {
        return Err(invalid(format!(
            "distance characteristics: {} attained positions of the first pose and {} of the \
             second; each cycle attains both",
            first.len(),
            second.len()
        )));
    }
    if first.len() < 2 {
        return Err(invalid(format!(
            "distance characteristics: {} cycle(s); repeatability needs at least 2",
            first.len()
        )));
    }
    if first
        .iter()
        .chain(second)
        .any(|position| !position.iter().all(|x| x.is_finite()))
    {
        return Err(invalid(
            "distance characteristics: an attained position is not finite".into(),
        ));
    }
    let commanded = (commanded_first - commanded_second).norm();
    let distances: Vec<f64> = first
        .iter()
        .zip(second)
        .map(|(a, b)| (a - b).norm())
        .collect();
    let (mean, deviation) = mean_and_deviation(&distances);
    Ok(DistanceCharacteristics {
        commanded,
        mean,
        accuracy: mean - commanded,
        repeatability: 3.0 * deviation,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampler::Sampler;
    use nalgebra::{Rotation3, Translation3};

    fn at(position: Vector3<f64>) -> IsometryMatrix3<f64> {
        IsometryMatrix3::from_parts(Translation3::from(position), Rotation3::identity())
    }

    /// The cube's poses: P1 the centre; P2–P5 on the plane's diagonals, a
    /// tenth of √3·s from their corners, in the plane through the edges at
    /// (−x, −y) and (+x, +y); a cube that is none is refused.
    #[test]
    fn the_cube_s_poses_lie_where_the_standard_puts_them() {
        let cube = TestCube::new(Vector3::new(1.0, -0.5, 0.3), 0.6).expect("cube");
        let poses = cube.poses();
        assert_eq!(poses[0], cube.centre);
        let diagonal = 3f64.sqrt() * 0.6;
        for (pose, corner) in poses[1..].iter().zip(cube.plane_corners()) {
            assert!(((pose - corner).norm() - 0.1 * diagonal).abs() < 1e-12);
            assert!(((pose - cube.centre).norm() - 0.4 * diagonal).abs() < 1e-12);
            // In the plane x − y = const through the centre.
            let offset = pose - cube.centre;
            assert!((offset.x - offset.y).abs() < 1e-12);
        }
        assert!(TestCube::new(Vector3::zeros(), 0.0).is_err());
        assert!(TestCube::new(Vector3::new(f64::NAN, 0.0, 0.0), 0.3).is_err());
    }

    /// Hand-computed: four cycles at known offsets.
    #[test]
    fn pose_characteristics_by_hand() {
        let commanded = at(Vector3::zeros());
        // Offsets (mm): (1,0,0), (3,0,0), (2,1,0), (2,-1,0): barycentre
        // (2,0,0), l = 1,1,1,1: l̄ = 1, S_l = 0, RP = 1 mm, AP = 2 mm.
        let attained: Vec<_> = [[1.0, 0.0], [3.0, 0.0], [2.0, 1.0], [2.0, -1.0]]
            .iter()
            .map(|[x, y]| at(Vector3::new(x * 1e-3, y * 1e-3, 0.0)))
            .collect();
        let pose = pose_characteristics(&commanded, &attained).expect("pose");
        assert!((pose.accuracy - 2e-3).abs() < 1e-15);
        assert!((pose.repeatability - 1e-3).abs() < 1e-15);
        assert_eq!(pose.orientation_accuracy, [0.0; 3]);
        // One more cycle at the barycentre: l = 1,1,1,1,0, l̄ = 0.8,
        // S_l = √(4·0.04 + 0.64)/2 = √0.8/2 (mm).
        let mut more = attained.clone();
        more.push(at(Vector3::new(2e-3, 0.0, 0.0)));
        let pose = pose_characteristics(&commanded, &more).expect("pose");
        let expected = 0.8e-3 + 3.0 * (0.8f64).sqrt() / 2.0 * 1e-3;
        assert!((pose.repeatability - expected).abs() < 1e-15);
        assert!(pose_characteristics(&commanded, &attained[..1]).is_err());
    }

    /// Known simulated truth: a bias and Gaussian noise σ per axis. AP is
    /// the bias; RP_l is the χ(3) distribution's mean + 3 standard
    /// deviations times σ (2√(2/π) + 3√(3 − 8/π) = 3.615); RP_a is 3σ of
    /// the orientation noise, AP_a its bias.
    #[test]
    fn pose_characteristics_find_a_simulated_bias_and_noise() {
        let mut sampler = Sampler::new(9283);
        let commanded = IsometryMatrix3::from_parts(
            Translation3::new(0.8, 0.1, 0.5),
            Rotation3::from_euler_angles(0.3, -0.2, 1.0),
        );
        let (sigma, angle_sigma) = (2e-5, 1e-4);
        let bias = Vector3::new(3e-4, -1e-4, 2e-4);
        let turn = [2e-3, -1e-3, 5e-4];
        let attained: Vec<_> = (0..40_000)
            .map(|_| {
                let error = Rotation3::from_euler_angles(
                    turn[0] + sampler.gaussian(angle_sigma),
                    turn[1] + sampler.gaussian(angle_sigma),
                    turn[2] + sampler.gaussian(angle_sigma),
                );
                IsometryMatrix3::from_parts(
                    Translation3::from(
                        commanded.translation.vector + bias + sampler.gaussian_vector(sigma),
                    ),
                    commanded.rotation * error,
                )
            })
            .collect();
        let pose = pose_characteristics(&commanded, &attained).expect("pose");
        assert!((pose.accuracy_components - bias).norm() < 1e-6);
        let chi3 = 2.0 * (2.0 / std::f64::consts::PI).sqrt()
            + 3.0 * (3.0 - 8.0 / std::f64::consts::PI).sqrt();
        assert!(
            (pose.repeatability / (chi3 * sigma) - 1.0).abs() < 0.02,
            "{} against {}",
            pose.repeatability,
            chi3 * sigma
        );
        for ((accuracy, repeatability), turn) in pose
            .orientation_accuracy
            .iter()
            .zip(pose.orientation_repeatability)
            .zip(turn)
        {
            assert!((accuracy - turn).abs() < 5e-6);
            assert!((repeatability / (3.0 * angle_sigma) - 1.0).abs() < 0.03);
        }
    }

    /// vAP: three approaches whose barycentres are 0.1, 0.2 and 0.25 mm
    /// along x: the largest gap is 0.15 mm; fewer than two approaches are
    /// refused.
    #[test]
    fn the_multi_directional_variation_is_the_largest_gap() {
        let commanded = at(Vector3::zeros());
        let approach = |x: f64| {
            vec![
                at(Vector3::new(x, 1e-5, 0.0)),
                at(Vector3::new(x, -1e-5, 0.0)),
            ]
        };
        let approaches = vec![approach(1e-4), approach(2e-4), approach(2.5e-4)];
        let variation = multi_directional(&commanded, &approaches).expect("vAP");
        assert!((variation.position - 1.5e-4).abs() < 1e-15);
        assert_eq!(variation.orientation, [0.0; 3]);
        assert!(multi_directional(&commanded, &approaches[..1]).is_err());
    }

    /// AD and RD by hand: a 1 m commanded distance attained as 1.001,
    /// 0.999, 1.002 and 0.998 m (D̄ = 1, S_D = √(10/3) mm).
    #[test]
    fn distance_characteristics_by_hand() {
        let first = vec![Vector3::zeros(); 4];
        let second: Vec<_> = [1.001, 0.999, 1.002, 0.998]
            .iter()
            .map(|x| Vector3::new(*x, 0.0, 0.0))
            .collect();
        let distance = distance_characteristics(
            (Vector3::zeros(), Vector3::new(1.0, 0.0, 0.0)),
            &first,
            &second,
        )
        .expect("distance");
        assert!((distance.commanded - 1.0).abs() < 1e-15);
        assert!(distance.accuracy.abs() < 1e-12);
        let expected = 3.0 * (10.0f64 / 3.0).sqrt() * 1e-3;
        assert!((distance.repeatability - expected).abs() < 1e-12);
        assert!(
            distance_characteristics((Vector3::zeros(), Vector3::x()), &first, &second[..3])
                .is_err()
        );
    }
}
