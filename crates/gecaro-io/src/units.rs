//! Units of lengths and angles in files that are not gecaro's own (tables,
//! tracker exports). gecaro computes in metres and radians; readers convert.

use crate::robot_file::AngleUnit;

/// The unit of the lengths of a table or data file.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub enum LengthUnit {
    /// Metres (the default, and what gecaro writes).
    #[default]
    Metres,
    /// Millimetres.
    Millimetres,
}

impl LengthUnit {
    /// Metres per unit.
    pub fn to_metres(self) -> f64 {
        match self {
            LengthUnit::Metres => 1.0,
            LengthUnit::Millimetres => 1e-3,
        }
    }

    /// The unit of a name: `m`, `mm` (and their long forms).
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "m" | "metre" | "metres" | "meter" | "meters" => Some(LengthUnit::Metres),
            "mm" | "millimetre" | "millimetres" | "millimeter" | "millimeters" => {
                Some(LengthUnit::Millimetres)
            }
            _ => None,
        }
    }

    /// The unit of `name`, or what a length unit must be: one wording for
    /// every file, setting and front end.
    ///
    /// # Errors
    /// A name that is no length unit's.
    pub fn parse(name: &str) -> Result<Self, String> {
        Self::from_name(name).ok_or_else(|| format!("must be \"m\" or \"mm\", not {name:?}"))
    }

    /// Its short name.
    pub fn name(self) -> &'static str {
        match self {
            LengthUnit::Metres => "m",
            LengthUnit::Millimetres => "mm",
        }
    }
}

impl AngleUnit {
    /// Radians per unit.
    pub fn to_radians(self) -> f64 {
        match self {
            AngleUnit::Radians => 1.0,
            AngleUnit::Degrees => std::f64::consts::PI / 180.0,
        }
    }

    /// The unit of a name: `rad`, `deg` (and their long forms).
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "rad" | "radian" | "radians" => Some(AngleUnit::Radians),
            "deg" | "degree" | "degrees" => Some(AngleUnit::Degrees),
            _ => None,
        }
    }

    /// The unit of `name`, or what an angle unit must be (see
    /// [`LengthUnit::parse`]).
    ///
    /// # Errors
    /// A name that is no angle unit's.
    pub fn parse(name: &str) -> Result<Self, String> {
        Self::from_name(name).ok_or_else(|| format!("must be \"rad\" or \"deg\", not {name:?}"))
    }

    /// Its short name.
    pub fn name(self) -> &'static str {
        match self {
            AngleUnit::Radians => "rad",
            AngleUnit::Degrees => "deg",
        }
    }
}
