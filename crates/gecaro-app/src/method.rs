//! The method of a request, as a user names it, and the names of the
//! libraries' choices (solvers, losses, criteria) parsed in one place.

use gecaro_calib::methods::{CalibrationMethod, MethodOptions, Plane};
use gecaro_core::OrientationDifference;
use nalgebra::Vector3;
use serde::Deserialize;

use crate::error::{AppError, ErrorKind, Hint, Part};

/// A method and its options (paper §3).
#[derive(Clone, Debug, Default, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct MethodSpec {
    /// `position`, `frame`, `point-link`, `frame-link`, `plane1`, `plane2`, `distance`.
    pub name: String,
    /// Normal of the plane of a plane method, world frame.
    pub plane_normal: Option<[f64; 3]>,
    /// A point of that plane, world frame, metres.
    pub plane_point: Option<[f64; 3]>,
    /// Whether the plane (plane1) or its normal (plane2) is identified too;
    /// by default known when given.
    pub plane_unknown: Option<bool>,
    /// Orientation difference of the frame methods (Appendix I):
    /// `axis-angle` (default) or `cross-products`.
    pub orientation: Option<String>,
    /// Configurations per set when generating link data.
    pub set_size: Option<usize>,
}

impl MethodSpec {
    /// The method `name` with default options.
    pub fn named(name: impl Into<String>) -> Self {
        MethodSpec {
            name: name.into(),
            ..MethodSpec::default()
        }
    }

    /// The library options these give.
    ///
    /// # Errors
    /// An impossible plane, orientation difference or set size, naming the setting.
    pub fn options(&self) -> Result<MethodOptions, AppError> {
        let plane = match (self.plane_normal, self.plane_point) {
            (None, None) => None,
            (Some(normal), Some(point)) => {
                Some(Plane::new(Vector3::from(normal), Vector3::from(point))?)
            }
            _ => {
                return Err(AppError::new(
                    ErrorKind::Usage,
                    vec![
                        Part::Text("a plane needs both ".into()),
                        Part::Setting("plane_normal".into()),
                        Part::Text(" and ".into()),
                        Part::Setting("plane_point".into()),
                    ],
                )
                .with_help(vec![Part::Hint(Hint::PlaneExample)]));
            }
        };
        let (plane, plane_unknown) = MethodOptions::plane_choice(plane, self.plane_unknown)?;
        Ok(MethodOptions {
            plane,
            plane_unknown,
            orientation: parse_name(
                "orientation",
                self.orientation.as_deref(),
                &OrientationDifference::NAMES,
                OrientationDifference::from_name,
            )?
            .unwrap_or_default(),
            set_size: MethodOptions::check_set_size(self.set_size)?,
        })
    }

    /// The method with its options.
    ///
    /// # Errors
    /// An unknown method (listing the methods) or impossible options.
    pub fn build(&self) -> Result<Box<dyn CalibrationMethod>, AppError> {
        Ok(gecaro_calib::methods::method(&self.name, &self.options()?)?)
    }
}

/// `name` parsed by `parse` for the setting `key`, whose values are `names`;
/// `None` when no name is given.
///
/// # Errors
/// A name that is none of `names`, listing them.
pub fn parse_name<T>(
    key: &str,
    name: Option<&str>,
    names: &[&str],
    parse: impl Fn(&str) -> Option<T>,
) -> Result<Option<T>, AppError> {
    let Some(name) = name.map(str::trim) else {
        return Ok(None);
    };
    parse(name).map(Some).ok_or_else(|| {
        AppError::setting(key, format!("`{name}` is not one of {}", names.join(", ")))
    })
}
