//! A plane of the world frame (paper §3.3): the plane of the plane methods,
//! by its unit normal and a point (metres), with its coefficients in the form
//! of eq. 13 and the least-squares fit of §3.3.1.

use nalgebra::{Matrix3, Vector3};

use crate::error::{Error, Setting};

/// A plane through `point` with unit `normal`, in the world frame (metres).
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Plane {
    normal: Vector3<f64>,
    point: Vector3<f64>,
}

impl Plane {
    /// The plane through `point` normal to `normal` (normalised here).
    ///
    /// # Errors
    /// [`Error::InvalidOption`] for a zero or non-finite normal or point.
    pub fn new(normal: Vector3<f64>, point: Vector3<f64>) -> Result<Self, Error> {
        if !normal.iter().chain(point.iter()).all(|v| v.is_finite()) {
            return Err(Error::InvalidOption {
                setting: Setting::Plane,
                message: "the plane has a value that is not a finite number".into(),
            });
        }
        let norm = normal.norm();
        if norm < 1e-12 {
            return Err(Error::InvalidOption {
                setting: Setting::PlaneNormal,
                message: "the plane normal is zero; give a direction such as (0.3, 0.5, 0.81)"
                    .into(),
            });
        }
        Ok(Plane {
            normal: normal / norm,
            point,
        })
    }

    /// The unit normal.
    pub fn normal(&self) -> Vector3<f64> {
        self.normal
    }

    /// The point the plane was given through.
    pub fn point(&self) -> Vector3<f64> {
        self.point
    }

    /// Signed distance of `point` from the plane, along the normal.
    pub fn distance(&self, point: &Vector3<f64>) -> f64 {
        self.normal.dot(&(point - self.point))
    }

    /// The plane coefficients (a, b, c) of eq. 13, `a x + b y + c z + 1 = 0`.
    ///
    /// # Errors
    /// [`Error::InvalidOption`] when the plane passes through the world origin,
    /// which that form cannot represent.
    pub fn coefficients(&self) -> Result<Vector3<f64>, Error> {
        let offset = self.normal.dot(&self.point);
        if offset.abs() < 1e-9 {
            return Err(Error::InvalidOption {
                setting: Setting::PlanePoint,
                message: "the plane passes through the world origin, which the plane equation \
                          a·x + b·y + c·z + 1 = 0 (eq. 13) cannot represent; move the world frame \
                          or use plane2"
                    .into(),
            });
        }
        Ok(-self.normal / offset)
    }

    /// The least-squares plane through `points` (at least three, not collinear).
    ///
    /// # Errors
    /// [`Error::InvalidData`] when the points do not define a plane.
    pub fn fit(points: impl Iterator<Item = Vector3<f64>> + Clone) -> Result<Self, Error> {
        let count = points.clone().count();
        if count < 3 {
            return Err(Error::InvalidData {
                line: None,
                message: format!("a plane needs at least 3 points, got {count}"),
            });
        }
        let centroid = points.clone().sum::<Vector3<f64>>() / count as f64;
        let scatter: Matrix3<f64> = points
            .map(|p| (p - centroid) * (p - centroid).transpose())
            .sum();
        let eigen = scatter.symmetric_eigen();
        let mut order = [0, 1, 2];
        order.sort_by(|a, b| eigen.eigenvalues[*a].total_cmp(&eigen.eigenvalues[*b]));
        let [smallest, middle, largest] = order;
        // Collinear points: the two smallest spreads vanish together.
        if eigen.eigenvalues[middle] <= 1e-12 * eigen.eigenvalues[largest].max(f64::MIN_POSITIVE) {
            return Err(Error::InvalidData {
                line: None,
                message:
                    "the terminal points are (nearly) on a line, so they do not define a plane"
                        .into(),
            });
        }
        Plane::new(eigen.eigenvectors.column(smallest).into_owned(), centroid)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plane_fit_and_coefficients() {
        let plane =
            Plane::new(Vector3::new(0.3, 0.5, 0.81), Vector3::new(0.3, 0.2, 0.6)).expect("valid");
        let (u, v) = (
            Vector3::new(0.5, -0.3, 0.0),
            plane.normal().cross(&Vector3::new(0.5, -0.3, 0.0)),
        );
        let points: Vec<_> = (0..10)
            .map(|i| plane.point() + u * (i as f64 * 0.1) + v * ((i * i) as f64 * 0.01))
            .collect();
        let fitted = Plane::fit(points.iter().copied()).expect("a plane");
        assert!(fitted.normal().cross(&plane.normal()).norm() < 1e-12);
        let abc = plane.coefficients().expect("not through the origin");
        for p in points {
            assert!((abc.dot(&p) + 1.0).abs() < 1e-12);
        }
        assert!(Plane::new(Vector3::zeros(), Vector3::zeros()).is_err());
        assert!(
            Plane::new(Vector3::z(), Vector3::x())
                .expect("valid")
                .coefficients()
                .is_err()
        );
    }
}
