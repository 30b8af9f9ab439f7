//! One frame of the robot model (paper §2.1): its type σ_j, its
//! Khalil–Kleinfinger parameters (α, d, θ, r) with Hayati's β (eq. 2–3), and,
//! for frames 1..=n, its joint's limits, offset and gain (paper §2.2).
//!
//! Lengths in metres, angles in radians. A frame on its own is plain data; a
//! [`Robot`](crate::Robot) checks frames and joints together.

use crate::parameters::ParameterKind;

/// The type σ_j of frame j.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub enum FrameType {
    /// σ = 0: revolute joint, q_j is added to θ_j.
    Revolute,
    /// σ = 1: prismatic joint, q_j is added to r_j.
    Prismatic,
    /// σ = 2: a frame of constant parameters (frames 0 and n+1).
    Fixed,
}

impl FrameType {
    /// The paper's σ: 0, 1 or 2.
    pub fn sigma(self) -> u8 {
        match self {
            FrameType::Revolute => 0,
            FrameType::Prismatic => 1,
            FrameType::Fixed => 2,
        }
    }

    /// The type of σ, or `None` if σ is not 0, 1 or 2.
    pub fn from_sigma(sigma: i64) -> Option<Self> {
        match sigma {
            0 => Some(FrameType::Revolute),
            1 => Some(FrameType::Prismatic),
            2 => Some(FrameType::Fixed),
            _ => None,
        }
    }

    /// One letter as in a joint string like `RRPRRR`: `R`, `P` or `F`.
    pub fn letter(self) -> char {
        match self {
            FrameType::Revolute => 'R',
            FrameType::Prismatic => 'P',
            FrameType::Fixed => 'F',
        }
    }
}

/// The geometric parameters of one frame (eq. 3). Lengths in metres, angles in radians.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Frame {
    /// σ_j.
    pub frame_type: FrameType,
    /// α_j: angle between z_{j−1} and z_j about x_{j−1}.
    pub alpha: f64,
    /// d_j: distance between z_{j−1} and z_j along x_{j−1}.
    pub d: f64,
    /// θ_j: angle between x_{j−1} and x_j about z_j (constant part).
    pub theta: f64,
    /// r_j: distance between x_{j−1} and x_j along z_j (constant part).
    pub r: f64,
    /// β_j: Hayati angle about y_{j−1}; nominally 0, needed for parallel axes.
    pub beta: f64,
}

impl Frame {
    /// A frame of the given type with all parameters zero.
    pub fn new(frame_type: FrameType) -> Self {
        Frame {
            frame_type,
            alpha: 0.0,
            d: 0.0,
            theta: 0.0,
            r: 0.0,
            beta: 0.0,
        }
    }

    /// The value of a geometric parameter of this frame (`Gain` is not one).
    pub(crate) fn get(&self, kind: ParameterKind) -> f64 {
        match kind {
            ParameterKind::Alpha => self.alpha,
            ParameterKind::D => self.d,
            ParameterKind::Theta => self.theta,
            ParameterKind::R => self.r,
            ParameterKind::Beta => self.beta,
            ParameterKind::Gain | ParameterKind::Compliance | ParameterKind::GravityTilt => {
                f64::NAN
            }
        }
    }

    pub(crate) fn get_mut(&mut self, kind: ParameterKind) -> Option<&mut f64> {
        match kind {
            ParameterKind::Alpha => Some(&mut self.alpha),
            ParameterKind::D => Some(&mut self.d),
            ParameterKind::Theta => Some(&mut self.theta),
            ParameterKind::R => Some(&mut self.r),
            ParameterKind::Beta => Some(&mut self.beta),
            ParameterKind::Gain | ParameterKind::Compliance | ParameterKind::GravityTilt => None,
        }
    }
}

/// The joint parameters of one joint (paper §2.2).
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Joint {
    /// Lower limit of the joint variable q_j.
    pub qmin: f64,
    /// Upper limit of the joint variable q_j.
    pub qmax: f64,
    /// Offset_j of eq. 4 (added to the joint variable; not identified — the
    /// identifiable joint offset is θ_j or r_j).
    pub offset: f64,
    /// Transmission gain K_j of eq. 4.
    pub gain: f64,
}

impl Joint {
    /// Limits ±π for a revolute joint, 0..1 m for a prismatic one; offset 0, gain 1.
    pub fn default_for(frame_type: FrameType) -> Self {
        let (qmin, qmax) = match frame_type {
            FrameType::Prismatic => (0.0, 1.0),
            _ => (-std::f64::consts::PI, std::f64::consts::PI),
        };
        Joint {
            qmin,
            qmax,
            offset: 0.0,
            gain: 1.0,
        }
    }
}
