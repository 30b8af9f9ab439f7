//! The test cube of ISO 9283 (clause 6.2) and its five poses: see the
//! [module docs](super) for the conventions.

use nalgebra::Vector3;

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

#[cfg(test)]
mod tests {
    use super::*;

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
}
