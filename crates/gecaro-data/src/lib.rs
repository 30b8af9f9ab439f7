//! gecaro's measured data, shared by the file formats (`gecaro-io`) and the
//! calibration (`gecaro-calib`) without either knowing the other: the
//! configurations of a data set and what was measured at each, as columns
//! ([`samples::Samples`]) or rows ([`sample::Sample`]); a robot program's
//! points and their compensation ([`program`]); a prior's values
//! ([`prior`]); and the work split over the cores that reading and
//! calibrating share ([`parallel`]).
//!
//! Units are SI throughout: metres, radians, unit quaternions `(w, x, y, z)`;
//! a file's own units are read and written by `gecaro-io`.
//!
//! ```
//! use gecaro_data::sample::Sample;
//! use gecaro_data::samples::Samples;
//! use nalgebra::Vector3;
//!
//! let mut row = Sample::new(vec![0.1, 0.2]);
//! row.position = Some(Vector3::new(1.0, 2.0, 3.0));
//! let samples = Samples::from(vec![row]);
//! assert_eq!(samples.get(0).position(), Some(Vector3::new(1.0, 2.0, 3.0)));
//! ```

pub mod parallel;
pub mod prior;
pub mod program;
pub mod sample;
pub mod samples;
