//! Pose accuracy and repeatability (7.2), multi-directional pose accuracy
//! variation and distance accuracy and repeatability (7.3) of attained
//! poses: the formulas of the [module docs](super).

use nalgebra::{IsometryMatrix3, Vector3};

use crate::Error;

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
