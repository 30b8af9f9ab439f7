//! The parameter vocabulary: which geometric and joint parameters a robot has,
//! in which order, and under which names.
//!
//! For a robot with n joints the parameter vector η (paper §2.1–2.2) is, in this
//! order (NOTES.md):
//!
//! ```text
//! theta0 r0 | alpha1 d1 theta1 r1 beta1 | ... | alpha(n+1) d(n+1) theta(n+1) r(n+1) beta(n+1) | K1 ... Kn
//! ```
//!
//! that is Np = 2 + 5(n+1) + n parameters: 43 for the six-joint Stanford arm.
//! An elastic robot (issue 38, `docs/elastic.md`) appends the compliance of
//! every joint, `c1 ... cn` (rad/(N·m) for a revolute joint, m/N for a
//! prismatic one): Np + n parameters, the geometric ones first and unmoved,
//! then the two angles `tilt1 tilt2` by which gravity leans from the
//! direction the mass model states (a measurement frame that is not
//! levelled; [`crate::MassModel::tilted`]): Np + n + 2 in all.
//! Frame 0 carries only θ0 and r0 (α0 = d0 = β0 = 0 by definition of the
//! base frame, eq. 1–2). These names are used in every file, table and JSON
//! output of gecaro. Lengths are in metres, angles in radians, gains have no
//! unit.

use std::fmt;
use std::str::FromStr;

use crate::Error;

/// The kind of a parameter: one column of the priority matrix (paper §2.2).
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum ParameterKind {
    /// α_j: rotation about x_{j-1} (radians).
    Alpha,
    /// d_j: translation along x_{j-1} (metres).
    D,
    /// θ_j: rotation about z_j (radians); the offset of a revolute joint.
    Theta,
    /// r_j: translation along z_j (metres); the offset of a prismatic joint.
    R,
    /// β_j: Hayati rotation about y_{j-1} for parallel axes (radians, eq. 3).
    Beta,
    /// K_j: transmission gain of joint j (eq. 4).
    Gain,
    /// c_j: compliance of joint j, `q_j = K_j·qm_j + offset_j + c_j·τ_j`
    /// (rad/(N·m) or m/N; issue 38). Only elastic robots have it.
    Compliance,
    /// tilt_k (k = 1, 2): the angle (radians) by which gravity leans from
    /// the direction the robot's mass model states, about the first and the
    /// second axis perpendicular to it (the world's x and y for gravity
    /// along −z; [`crate::MassModel::tilt_axes`]). Only elastic robots have
    /// it, and only their loads see it.
    GravityTilt,
}

impl ParameterKind {
    /// The six kinds in the column order of the priority matrix: α, d, θ, r, β, K.
    pub const ALL: [ParameterKind; 6] = [
        ParameterKind::Alpha,
        ParameterKind::D,
        ParameterKind::Theta,
        ParameterKind::R,
        ParameterKind::Beta,
        ParameterKind::Gain,
    ];

    /// Column of this kind in the (n+2)×6 priority matrix; the compliance's
    /// priorities are a seventh column beside it (see [`crate::PriorityMatrix`]).
    pub fn column(self) -> usize {
        self as usize
    }

    /// The name stem used in parameter names: `alpha`, `d`, `theta`, `r`,
    /// `beta`, `K`, `c`.
    pub fn symbol(self) -> &'static str {
        match self {
            ParameterKind::Alpha => "alpha",
            ParameterKind::D => "d",
            ParameterKind::Theta => "theta",
            ParameterKind::R => "r",
            ParameterKind::Beta => "beta",
            ParameterKind::Gain => "K",
            ParameterKind::Compliance => "c",
            ParameterKind::GravityTilt => "tilt",
        }
    }

    /// Whether the parameter is an angle (radians), as opposed to a length or a gain.
    pub fn is_angle(self) -> bool {
        matches!(
            self,
            ParameterKind::Alpha
                | ParameterKind::Theta
                | ParameterKind::Beta
                | ParameterKind::GravityTilt
        )
    }

    /// Whether the parameter is a length (metres).
    pub fn is_length(self) -> bool {
        matches!(self, ParameterKind::D | ParameterKind::R)
    }
}

/// One parameter of a robot: a kind and the frame (or joint) it belongs to.
///
/// Displayed and parsed as its name: `theta0`, `alpha3`, `K2`.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct ParameterId {
    /// Frame j (0..=n+1) for geometric parameters, joint j (1..=n) for
    /// gains and compliances, the axis k (1, 2) of a gravity tilt.
    pub frame: usize,
    /// Which parameter of the frame.
    pub kind: ParameterKind,
}

impl ParameterId {
    /// The parameter `kind` of frame `frame`.
    pub fn new(kind: ParameterKind, frame: usize) -> Self {
        ParameterId { frame, kind }
    }
}

impl fmt::Display for ParameterId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}{}", self.kind.symbol(), self.frame)
    }
}

impl FromStr for ParameterId {
    type Err = Error;

    /// Parses a name such as `alpha3` or `K1` (the frame number is not checked
    /// against any robot; see [`ParameterSpace::index_of`]).
    fn from_str(name: &str) -> Result<Self, Error> {
        let digits = name.find(|c: char| c.is_ascii_digit());
        let parsed = digits.and_then(|at| {
            let (stem, number) = name.split_at(at);
            let kind = ParameterKind::ALL
                .into_iter()
                .chain([ParameterKind::Compliance, ParameterKind::GravityTilt])
                .find(|kind| kind.symbol() == stem)?;
            let frame = number.parse::<usize>().ok()?;
            Some(ParameterId { frame, kind })
        });
        parsed.ok_or_else(|| Error::UnknownParameter {
            name: name.to_owned(),
            suggestion: None,
        })
    }
}

/// The ordered parameter vector η of a robot with n joints (see the module docs).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ParameterSpace {
    joint_count: usize,
    /// Whether the compliances c1..cn follow the gains.
    elastic: bool,
    ids: Vec<ParameterId>,
}

impl ParameterSpace {
    /// The vocabulary of a robot with `joint_count` joints (frames 0..=n+1).
    pub fn new(joint_count: usize) -> Self {
        let n = joint_count;
        let mut ids = Vec::with_capacity(Self::len_for(n));
        ids.push(ParameterId::new(ParameterKind::Theta, 0));
        ids.push(ParameterId::new(ParameterKind::R, 0));
        for frame in 1..=n + 1 {
            for kind in &ParameterKind::ALL[..5] {
                ids.push(ParameterId::new(*kind, frame));
            }
        }
        for joint in 1..=n {
            ids.push(ParameterId::new(ParameterKind::Gain, joint));
        }
        ParameterSpace {
            joint_count: n,
            elastic: false,
            ids,
        }
    }

    /// The vocabulary of an elastic robot: [`ParameterSpace::new`]'s, then
    /// the compliances `c1 … cn`, then the gravity tilts `tilt1 tilt2`.
    pub fn elastic(joint_count: usize) -> Self {
        let mut space = Self::new(joint_count);
        space.elastic = true;
        space.ids.extend(
            (1..=joint_count).map(|joint| ParameterId::new(ParameterKind::Compliance, joint)),
        );
        space
            .ids
            .extend((1..=2).map(|axis| ParameterId::new(ParameterKind::GravityTilt, axis)));
        space
    }

    fn len_for(joint_count: usize) -> usize {
        2 + 5 * (joint_count + 1) + joint_count
    }

    /// Whether the vocabulary holds the compliances (an elastic robot).
    pub fn is_elastic(&self) -> bool {
        self.elastic
    }

    /// Number of parameters Np = 2 + 5(n+1) + n (+ n compliances and two
    /// gravity tilts when elastic).
    pub fn len(&self) -> usize {
        self.ids.len()
    }

    /// Always false: every robot has at least θ0 and r0.
    pub fn is_empty(&self) -> bool {
        self.ids.is_empty()
    }

    /// Number of joints n.
    pub fn joint_count(&self) -> usize {
        self.joint_count
    }

    /// The parameters in vector order.
    pub fn ids(&self) -> &[ParameterId] {
        &self.ids
    }

    /// The parameter at position `index` of η.
    pub fn id(&self, index: usize) -> ParameterId {
        self.ids[index]
    }

    /// Position of a parameter in η, or `None` if the robot has no such parameter
    /// (α0, d0, β0, K of a fixed frame, a frame beyond n+1).
    pub fn index_of(&self, id: ParameterId) -> Option<usize> {
        let n = self.joint_count;
        match (id.kind, id.frame) {
            (ParameterKind::Theta, 0) => Some(0),
            (ParameterKind::R, 0) => Some(1),
            (_, 0) => None,
            (ParameterKind::Gain, joint) if joint <= n => Some(2 + 5 * (n + 1) + joint - 1),
            (ParameterKind::Gain, _) => None,
            (ParameterKind::Compliance, joint) if self.elastic && joint <= n => {
                Some(Self::len_for(n) + joint - 1)
            }
            (ParameterKind::Compliance, _) => None,
            (ParameterKind::GravityTilt, axis @ 1..=2) if self.elastic => {
                Some(Self::len_for(n) + n + axis - 1)
            }
            (ParameterKind::GravityTilt, _) => None,
            (kind, frame) if frame <= n + 1 => Some(2 + 5 * (frame - 1) + kind.column()),
            _ => None,
        }
    }

    /// Position of the parameter called `name`, with a suggestion when the name
    /// is not one of this robot's.
    pub fn index_of_name(&self, name: &str) -> Result<usize, Error> {
        name.parse::<ParameterId>()
            .ok()
            .and_then(|id| self.index_of(id))
            .ok_or_else(|| Error::UnknownParameter {
                name: name.to_owned(),
                suggestion: self.closest_name(name),
            })
    }

    /// Whether (kind, frame) is a parameter of this robot (a non-zero cell of
    /// the priority matrix is allowed only there).
    pub fn contains(&self, id: ParameterId) -> bool {
        self.index_of(id).is_some()
    }

    /// The names of all parameters, in vector order.
    pub fn names(&self) -> Vec<String> {
        self.ids.iter().map(ToString::to_string).collect()
    }

    fn closest_name(&self, name: &str) -> Option<String> {
        self.ids
            .iter()
            .map(ToString::to_string)
            .map(|candidate| (strsim::levenshtein(name, &candidate), candidate))
            .filter(|(distance, _)| *distance <= 2)
            .min_by_key(|(distance, _)| *distance)
            .map(|(_, candidate)| candidate)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stanford_has_43_parameters_in_paper_order() {
        let space = ParameterSpace::new(6);
        assert_eq!(space.len(), 43);
        let names = space.names();
        assert_eq!(
            &names[..7],
            ["theta0", "r0", "alpha1", "d1", "theta1", "r1", "beta1"]
        );
        assert_eq!(names[36], "beta7");
        assert_eq!(&names[37..], ["K1", "K2", "K3", "K4", "K5", "K6"]);
    }

    #[test]
    fn index_of_inverts_id() {
        for n in 1..9 {
            let space = ParameterSpace::new(n);
            for (index, id) in space.ids().iter().enumerate() {
                assert_eq!(space.index_of(*id), Some(index));
                assert_eq!(space.index_of_name(&id.to_string()), Ok(index));
            }
        }
    }

    #[test]
    fn an_elastic_space_appends_the_compliances() {
        let space = ParameterSpace::elastic(6);
        assert_eq!(space.len(), 51);
        assert!(space.is_elastic() && !ParameterSpace::new(6).is_elastic());
        assert_eq!(&space.names()[..43], &ParameterSpace::new(6).names()[..]);
        assert_eq!(
            &space.names()[43..],
            ["c1", "c2", "c3", "c4", "c5", "c6", "tilt1", "tilt2"]
        );
        for (index, id) in space.ids().iter().enumerate() {
            assert_eq!(space.index_of_name(&id.to_string()), Ok(index));
        }
        for name in ["c0", "c7", "tilt0", "tilt3"] {
            assert!(space.index_of_name(name).is_err(), "{name}");
        }
        assert!(ParameterSpace::new(6).index_of_name("c1").is_err());
        assert!(ParameterSpace::new(6).index_of_name("tilt1").is_err());
    }

    #[test]
    fn non_parameters_are_rejected() {
        let space = ParameterSpace::new(6);
        for name in [
            "alpha0", "d0", "beta0", "K0", "K7", "theta8", "gamma1", "theta",
        ] {
            assert!(space.index_of_name(name).is_err(), "{name}");
        }
        match space.index_of_name("alpah1") {
            Err(Error::UnknownParameter { suggestion, .. }) => {
                assert_eq!(suggestion.as_deref(), Some("alpha1"))
            }
            other => panic!("unexpected {other:?}"),
        }
    }
}
