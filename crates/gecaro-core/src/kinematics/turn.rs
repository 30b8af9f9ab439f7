//! The sine and cosine of a frame's turn about z (eq. 3): θ_j + q_j for a
//! revolute joint, θ_j for a prismatic or fixed frame.
//!
//! One function for every route of the direct model: the reference
//! [`frame_transform`](super::frame_transform) and the compiled
//! [`KinematicModel`](super::KinematicModel) both take their turns from here,
//! so the poses they give agree bit for bit where no frame has a Hayati β
//! (the Python package's `fk` and `gecaro fk` are the two routes, and are
//! compared so).
//!
//! The values are computed four at a time in SIMD lanes (`wide`'s `f64x4`:
//! about 7 ns a value here, against 19–21 ns for libm's `sincos`), within
//! 2 units in the last place of the standard library's `sin_cos` for
//! |angle| ≤ 100 rad (tested). Each lane is computed on its own, so one value
//! taken alone in [`sin_cos`] has the bits it has among four in
//! [`sin_cos_lanes`].
//!
//! ```
//! use gecaro_core::turn;
//!
//! let (sin, cos) = turn::sin_cos(0.5);
//! assert!((sin - 0.5_f64.sin()).abs() < 1e-15 && (cos - 0.5_f64.cos()).abs() < 1e-15);
//! let (sines, cosines) = turn::sin_cos_lanes([0.5, 1.0, -2.0, 3.0]);
//! assert_eq!((sines[0], cosines[0]), (sin, cos));
//! ```

use wide::f64x4;

/// `angle` (radians) turned by whole turns into (−π, π].
pub(crate) fn wrapped(angle: f64) -> f64 {
    use std::f64::consts::{PI, TAU};
    let wrapped = angle - TAU * ((angle + PI) / TAU).ceil() + TAU;
    if wrapped <= -PI {
        wrapped + TAU
    } else {
        wrapped
    }
}

/// Lanes taken at once by [`sin_cos_lanes`].
pub const LANES: usize = 4;

/// Beyond this magnitude (radians, some 1,600 turns), and for NaN, a lane
/// takes the standard library's value instead. The lanes' range reduction
/// holds to 1 unit in the last place up to 1e8 rad and fails beyond
/// (measured: 2.7e8 units at 1e8–1e9 rad); no joint turns even this far,
/// a misread file might.
const LANE_RANGE: f64 = 1e4;

/// The sine and cosine of four angles (radians) at once.
#[must_use]
#[inline(always)]
pub fn sin_cos_lanes(angles: [f64; LANES]) -> ([f64; LANES], [f64; LANES]) {
    let (sines, cosines) = f64x4::from(angles).sin_cos();
    let (mut sines, mut cosines) = (sines.to_array(), cosines.to_array());
    for (lane, angle) in angles.iter().enumerate() {
        if angle.is_nan() || angle.abs() > LANE_RANGE {
            (sines[lane], cosines[lane]) = angle.sin_cos();
        }
    }
    (sines, cosines)
}

/// The sine and cosine of one angle (radians), bit for bit as
/// [`sin_cos_lanes`] gives it.
#[must_use]
pub fn sin_cos(angle: f64) -> (f64, f64) {
    let (sines, cosines) = sin_cos_lanes([angle; LANES]);
    (sines[0], cosines[0])
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    /// Within a few units in the last place of the standard library's, for
    /// turns of many revolutions (continuous joints, ±100 rad), and the same
    /// bits whichever lane a value takes and whatever its neighbours are.
    #[test]
    fn lanes_agree_with_the_standard_library_and_with_each_other() {
        let mut rng = ChaCha8Rng::seed_from_u64(29);
        for _ in 0..20_000 {
            let angles: [f64; LANES] =
                std::array::from_fn(|_| rand::RngExt::random_range(&mut rng, -100.0..100.0));
            let (sines, cosines) = sin_cos_lanes(angles);
            for lane in 0..LANES {
                let (sin, cos) = angles[lane].sin_cos();
                assert!(
                    (sines[lane] - sin).abs() <= 2.0 * f64::EPSILON,
                    "{}",
                    angles[lane]
                );
                assert!(
                    (cosines[lane] - cos).abs() <= 2.0 * f64::EPSILON,
                    "{}",
                    angles[lane]
                );
                assert_eq!(
                    (sines[lane].to_bits(), cosines[lane].to_bits()),
                    {
                        let (s, c) = super::sin_cos(angles[lane]);
                        (s.to_bits(), c.to_bits())
                    },
                    "{}",
                    angles[lane]
                );
            }
        }
        // Far turns and NaN take the standard library's route, alone or not.
        for far in [1e4 + 1.0, -3e7, 1e300, f64::NAN, f64::INFINITY] {
            let (sines, cosines) = sin_cos_lanes([0.5, far, 1.0, 2.0]);
            let (sin, cos) = far.sin_cos();
            assert_eq!(sines[1].to_bits(), sin.to_bits(), "{far}");
            assert_eq!(cosines[1].to_bits(), cos.to_bits(), "{far}");
            // Its neighbours keep the lanes' values.
            assert_eq!(sines[0].to_bits(), super::sin_cos(0.5).0.to_bits());
            assert_eq!(cosines[3].to_bits(), super::sin_cos(2.0).1.to_bits());
        }
        for exact in [0.0, -0.0] {
            let (sin, cos) = super::sin_cos(exact);
            assert_eq!((sin.to_bits(), cos), (exact.to_bits(), 1.0));
        }
    }
}
