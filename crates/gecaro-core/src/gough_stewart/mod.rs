//! A Gough–Stewart platform (6-UPS / 6-SPS): the parallel robot of the
//! paper's closing words, modelled as Khalil and Besnard calibrate it —
//! through its inverse geometric model, which is explicit.
//!
//! # The model
//!
//! Leg i (1..6) joins the base at the centre `aᵢ` of its base joint (base
//! frame) to the platform at the centre `bᵢ` of its platform joint (platform
//! frame). With the platform at pose (p, R) — the platform frame in the base
//! frame — the leg's length is
//!
//! ```text
//! ℓᵢ = ‖p + R·bᵢ − aᵢ‖                        (the inverse model)
//! ℓᵢ = lᵢ + Kᵢ·qmᵢ                              (the actuator, as eq. 4)
//! ```
//!
//! with `lᵢ` the leg's length at actuator value zero, `Kᵢ` its gain and
//! `qmᵢ` the actuator value (metres for a gain of 1). A calibration equation
//! is the difference of the two (`Fᵢ = ‖p + R·bᵢ − aᵢ‖ − lᵢ − Kᵢ·qmᵢ = 0`),
//! differentiated with respect to the pose
//! ([`GoughStewart::inverse_kinematic_jacobian`])
//! and to the leg's parameters ([`GoughStewart::leg_parameter_rows`]).
//!
//! The direct model — the pose from the actuator values — has no closed
//! form (up to 40 assembly modes); [`ParallelModel::direct`] solves the six
//! leg equations by Newton's method from a start pose, which keeps the
//! assembly mode of the start (the platform's home pose, or the pose of the
//! previous target along a program).
//!
//! # Parameters and units
//!
//! 8 per leg, then the tool point's 3, 51 in all, in this order and with
//! these names ([`ParallelModel::parameter_names`]):
//! `a1x a1y a1z b1x b1y b1z l1 K1 … a6x … K6 tx ty tz`. Metres, except the
//! gains (dimensionless). A pose's small rotation ω is a rotation vector
//! in the base frame (`R ← exp(ω)·R`); 6-vectors are `[position; rotation]`.
//!
//! # Example
//!
//! ```
//! use gecaro_core::gough_stewart::{GoughStewart, Leg};
//! use gecaro_core::parallel_model::ParallelModel;
//! use nalgebra::{Isometry3, Vector3};
//!
//! // Base joints on a circle of 0.5 m, platform joints on one of 0.3 m.
//! let legs = (0..6)
//!     .map(|i| {
//!         let pair = (i / 2) as f64 * 120f64.to_radians();
//!         let side = if i % 2 == 0 { -0.2 } else { 0.2 };
//!         let on = |radius: f64, angle: f64| Vector3::new(radius * angle.cos(), radius * angle.sin(), 0.0);
//!         Leg::new(on(0.5, pair + side), on(0.3, pair + 3.0 * side), 0.6)
//!     })
//!     .collect();
//! let hexapod = GoughStewart::new("hexapod", legs, Vector3::zeros())?;
//! let pose = Isometry3::translation(0.01, -0.02, 0.55);
//! let actuators = hexapod.actuator_values(&pose)?;
//! let found = hexapod.direct(&actuators, &hexapod.home())?;
//! assert!((found.translation.vector - pose.translation.vector).norm() < 1e-12);
//! # Ok::<(), gecaro_core::Error>(())
//! ```

use nalgebra::{DMatrix, DVector, Isometry3, Matrix6, Point3, Vector3, Vector6};

use crate::error::{Error, Field};
use crate::parallel_model::{
    EquationVisitor, ParallelModel, ParameterUnit, check_actuator, check_tool,
};
use crate::stated::MAX_MAGNITUDE;

/// The number of legs of a Gough–Stewart platform.
pub const LEGS: usize = 6;

/// Parameters per leg: `a` (3), `b` (3), `l`, `K`.
pub const PARAMETERS_PER_LEG: usize = 8;

/// Parameters of a platform: 8 per leg and the tool point's 3.
pub const PARAMETER_COUNT: usize = LEGS * PARAMETERS_PER_LEG + 3;

/// One leg; see the module docs.
#[derive(Clone, Debug, PartialEq)]
pub struct Leg {
    /// `a`: the centre of the base joint, in the base frame (m).
    pub base: Vector3<f64>,
    /// `b`: the centre of the platform joint, in the platform frame (m).
    pub platform: Vector3<f64>,
    /// `l`: the leg's length at actuator value zero (m).
    pub length: f64,
    /// `K`: metres of leg per unit of actuator value.
    pub gain: f64,
    /// The smallest actuator value.
    pub min: f64,
    /// The largest actuator value.
    pub max: f64,
}

impl Leg {
    /// A leg of gain 1 with an actuator range of ±0.1 (m).
    pub fn new(base: Vector3<f64>, platform: Vector3<f64>, length: f64) -> Self {
        Self {
            base,
            platform,
            length,
            gain: 1.0,
            min: -0.1,
            max: 0.1,
        }
    }
}

/// A Gough–Stewart platform; see the module docs.
#[derive(Clone, Debug, PartialEq)]
pub struct GoughStewart {
    name: String,
    legs: Vec<Leg>,
    tool: Vector3<f64>,
    home: Isometry3<f64>,
}

impl GoughStewart {
    /// A platform of six legs and a tool point (platform frame, m), its home
    /// pose found with the platform level above the base and every leg near
    /// the middle of its range ([`home`](Self::home)).
    ///
    /// # Errors
    /// [`Error::Invalid`] naming the leg and key of a value no platform has:
    /// not six legs, a value not finite or beyond ±1 km, a gain of zero, a
    /// range with its ends reversed, a leg of length zero at home, or no
    /// home pose with the platform above the base.
    pub fn new(name: &str, legs: Vec<Leg>, tool: Vector3<f64>) -> Result<Self, Error> {
        if legs.len() != LEGS {
            return Err(Error::Invalid {
                field: Field::Frames,
                message: format!(
                    "a Gough–Stewart platform has {LEGS} legs, {} are given",
                    legs.len()
                ),
            });
        }
        for (index, leg) in legs.iter().enumerate() {
            check_leg(index + 1, leg)?;
        }
        check_tool(&tool)?;
        let mut platform = Self {
            name: name.to_owned(),
            legs,
            tool,
            home: Isometry3::identity(),
        };
        platform.home = platform.level_home()?;
        Ok(platform)
    }

    /// The six legs, leg 1 first.
    pub fn legs(&self) -> &[Leg] {
        &self.legs
    }

    /// `p + R·bᵢ − aᵢ` of every leg: from the base joint to the platform
    /// joint, in the base frame.
    pub fn leg_vectors(&self, pose: &Isometry3<f64>) -> [Vector3<f64>; LEGS] {
        std::array::from_fn(|i| {
            let leg = &self.legs[i];
            pose.transform_point(&Point3::from(leg.platform)).coords - leg.base
        })
    }

    /// The legs' lengths ℓᵢ at a pose: the inverse geometric model.
    pub fn leg_lengths(&self, pose: &Isometry3<f64>) -> [f64; LEGS] {
        self.leg_vectors(pose).map(|v| v.norm())
    }

    /// The legs' lengths the actuators give: `lᵢ + Kᵢ·qmᵢ`.
    pub fn commanded_lengths(&self, actuators: &[f64; LEGS]) -> [f64; LEGS] {
        std::array::from_fn(|i| self.legs[i].length + self.legs[i].gain * actuators[i])
    }

    /// ∂ℓ/∂x at a pose: row i is `[uᵢᵀ, (R·bᵢ × uᵢ)ᵀ]`, uᵢ the unit vector of
    /// leg i, for a pose change `[δp; ω]` with `R ← exp(ω)·R` (the
    /// platform's inverse kinematic Jacobian).
    pub fn inverse_kinematic_jacobian(&self, pose: &Isometry3<f64>) -> Matrix6<f64> {
        let vectors = self.leg_vectors(pose);
        let mut jacobian = Matrix6::zeros();
        for (i, vector) in vectors.iter().enumerate() {
            let unit = vector / vector.norm();
            let arm = pose.rotation * self.legs[i].platform;
            let turn = arm.cross(&unit);
            jacobian
                .fixed_view_mut::<1, 3>(i, 0)
                .copy_from(&unit.transpose());
            jacobian
                .fixed_view_mut::<1, 3>(i, 3)
                .copy_from(&turn.transpose());
        }
        jacobian
    }

    /// ∂Fᵢ/∂(aᵢ, bᵢ, lᵢ, Kᵢ) of each leg's equation
    /// `Fᵢ = ‖p + R·bᵢ − aᵢ‖ − lᵢ − Kᵢ·qmᵢ` at a pose and actuator values:
    /// `[−uᵢᵀ, uᵢᵀR, −1, −qmᵢ]`. Leg i's equation involves only leg i's
    /// parameters.
    pub fn leg_parameter_rows(
        &self,
        pose: &Isometry3<f64>,
        actuators: &[f64; LEGS],
    ) -> [[f64; PARAMETERS_PER_LEG]; LEGS] {
        let mut rows = [[0.0; PARAMETERS_PER_LEG]; LEGS];
        self.visit_equations(pose, actuators, &mut |leg, _, _, own| {
            rows[leg].copy_from_slice(own);
        });
        rows
    }

    /// The residuals `Fᵢ` of the leg equations at a pose.
    pub fn leg_residuals(&self, pose: &Isometry3<f64>, actuators: &[f64; LEGS]) -> Vector6<f64> {
        let lengths = self.leg_lengths(pose);
        let commanded = self.commanded_lengths(actuators);
        Vector6::from_fn(|i, _| lengths[i] - commanded[i])
    }

    /// The home pose of [`home`](Self::home), by bisection on the height.
    fn level_home(&self) -> Result<Isometry3<f64>, Error> {
        let centre = self.legs.iter().map(|leg| leg.base).sum::<Vector3<f64>>() / LEGS as f64
            - self
                .legs
                .iter()
                .map(|leg| leg.platform)
                .sum::<Vector3<f64>>()
                / LEGS as f64;
        let wanted = self
            .legs
            .iter()
            .map(|leg| leg.length + leg.gain * 0.5 * (leg.min + leg.max))
            .sum::<f64>()
            / LEGS as f64;
        let mean_at = |height: f64| {
            let pose = Isometry3::translation(centre.x, centre.y, centre.z + height);
            self.leg_lengths(&pose).iter().sum::<f64>() / LEGS as f64
        };
        // The mean length grows with the height above the joints' plane.
        let (mut low, mut high) = (0.0, wanted.abs() + MAX_MAGNITUDE.min(10.0 * wanted.abs()));
        if !(mean_at(low) <= wanted && mean_at(high) >= wanted) || wanted <= 0.0 {
            return Err(Error::Invalid {
                field: Field::Frames,
                message: format!(
                    "no pose with the platform level above the base has the legs' mean length \
                     at the middle of their ranges ({wanted} m): lengths or ranges mistaken"
                ),
            });
        }
        for _ in 0..200 {
            let middle = 0.5 * (low + high);
            if mean_at(middle) < wanted {
                low = middle;
            } else {
                high = middle;
            }
        }
        Ok(Isometry3::translation(
            centre.x,
            centre.y,
            centre.z + 0.5 * (low + high),
        ))
    }
}

/// Six legs' closure equations `Fᵢ = ‖p + R·bᵢ − aᵢ‖ − lᵢ − Kᵢ·qmᵢ`.
impl ParallelModel for GoughStewart {
    fn name(&self) -> &str {
        &self.name
    }

    fn renamed(&self, name: &str) -> Self {
        Self {
            name: name.to_owned(),
            ..self.clone()
        }
    }

    fn actuator_count(&self) -> usize {
        LEGS
    }

    fn pose_freedom(&self) -> usize {
        6
    }

    /// In the order of the module docs.
    fn parameters(&self) -> Vec<f64> {
        let mut values = Vec::with_capacity(PARAMETER_COUNT);
        for leg in &self.legs {
            values.extend(leg.base.iter());
            values.extend(leg.platform.iter());
            values.push(leg.length);
            values.push(leg.gain);
        }
        values.extend(self.tool.iter());
        values
    }

    fn parameter_count(&self) -> usize {
        PARAMETER_COUNT
    }

    fn parameter_names(&self) -> Vec<String> {
        let mut names = Vec::with_capacity(PARAMETER_COUNT);
        for leg in 1..=LEGS {
            for part in ["a", "b"] {
                for axis in ["x", "y", "z"] {
                    names.push(format!("{part}{leg}{axis}"));
                }
            }
            names.push(format!("l{leg}"));
            names.push(format!("K{leg}"));
        }
        names.extend(["tx", "ty", "tz"].map(String::from));
        names
    }

    fn parameter_unit(&self, index: usize) -> ParameterUnit {
        if index < LEGS * PARAMETERS_PER_LEG && index % PARAMETERS_PER_LEG == 7 {
            ParameterUnit::Gain
        } else {
            ParameterUnit::Length
        }
    }

    fn tool_parameters(&self) -> std::ops::Range<usize> {
        LEGS * PARAMETERS_PER_LEG..PARAMETER_COUNT
    }

    /// Ranges, name and home kept: the home of a calibrated platform is its
    /// nominal one's, so the direct model keeps the same assembly mode.
    fn with_parameters(&self, values: &[f64]) -> Result<Self, Error> {
        if values.len() != PARAMETER_COUNT {
            return Err(Error::Invalid {
                field: Field::Frames,
                message: format!(
                    "a Gough–Stewart platform has {PARAMETER_COUNT} parameters, {} are given",
                    values.len()
                ),
            });
        }
        let legs: Vec<Leg> = self
            .legs
            .iter()
            .zip(values.chunks_exact(PARAMETERS_PER_LEG))
            .map(|(leg, chunk)| Leg {
                base: Vector3::new(chunk[0], chunk[1], chunk[2]),
                platform: Vector3::new(chunk[3], chunk[4], chunk[5]),
                length: chunk[6],
                gain: chunk[7],
                ..leg.clone()
            })
            .collect();
        for (index, leg) in legs.iter().enumerate() {
            check_leg(index + 1, leg)?;
        }
        let tool = &values[LEGS * PARAMETERS_PER_LEG..];
        Ok(Self {
            name: self.name.clone(),
            legs,
            tool: Vector3::new(tool[0], tool[1], tool[2]),
            home: self.home,
        })
    }

    /// The platform level (R = I), centred over the base's joints, at the
    /// height where the legs' mean length is the mean of their ranges'
    /// middles: the platform above the base.
    fn home(&self) -> Isometry3<f64> {
        self.home
    }

    fn tool(&self) -> Vector3<f64> {
        self.tool
    }

    fn closure(&self, pose: &Isometry3<f64>, actuators: &[f64]) -> DVector<f64> {
        let lengths = self.leg_lengths(pose);
        DVector::from_fn(LEGS, |i, _| {
            lengths[i] - self.legs[i].length - self.legs[i].gain * actuators[i]
        })
    }

    fn pose_jacobian(&self, pose: &Isometry3<f64>, _actuators: &[f64]) -> DMatrix<f64> {
        let jacobian = self.inverse_kinematic_jacobian(pose);
        DMatrix::from_fn(LEGS, 6, |r, c| jacobian[(r, c)])
    }

    /// Leg by leg on the stack: a leg's row of `∂F/∂x` is `[uᵢ, R·bᵢ × uᵢ]`
    /// and its coefficients `[−uᵢ, Rᵀ·uᵢ, −1, −qmᵢ]`.
    fn visit_equations(
        &self,
        pose: &Isometry3<f64>,
        actuators: &[f64],
        visit: &mut EquationVisitor<'_>,
    ) {
        let inverse = pose.rotation.inverse();
        for (i, leg) in self.legs.iter().enumerate() {
            let arm = pose.rotation * leg.platform;
            let vector = pose.translation.vector + arm - leg.base;
            let length = vector.norm();
            let unit = vector / length;
            let turn = arm.cross(&unit);
            let turned = inverse * unit;
            let row = [unit.x, unit.y, unit.z, turn.x, turn.y, turn.z];
            let own = [
                -unit.x,
                -unit.y,
                -unit.z,
                turned.x,
                turned.y,
                turned.z,
                -1.0,
                -actuators[i],
            ];
            visit(i, length - leg.length - leg.gain * actuators[i], &row, &own);
        }
    }

    /// A 3-2-1 convention on the first three legs' joints, for each of
    /// the base (`a`) and the platform (`b`): joint 1's three coordinates
    /// (the frame's origin), joint 2's two across the line from joint 1 to
    /// it (its direction), and joint 3's one along the normal of the three
    /// joints' plane (the turn about that line) — the coordinates chosen
    /// from the stated joints, so that they hold the frame whatever its
    /// axes are drawn along.
    fn frame_parameters(&self) -> Vec<usize> {
        let largest = |vector: Vector3<f64>| vector.iamax();
        let mut held = Vec::with_capacity(12);
        let base: fn(&Leg) -> Vector3<f64> = |leg| leg.base;
        let platform: fn(&Leg) -> Vector3<f64> = |leg| leg.platform;
        for (offset, joint) in [(0, base), (3, platform)] {
            let (one, two, three) = (
                joint(&self.legs[0]),
                joint(&self.legs[1]),
                joint(&self.legs[2]),
            );
            let along = largest(two - one);
            let normal = largest((two - one).cross(&(three - one)));
            held.extend((0..3).map(|axis| offset + axis));
            held.extend(
                (0..3)
                    .filter(|axis| *axis != along)
                    .map(|axis| PARAMETERS_PER_LEG + offset + axis),
            );
            held.push(2 * PARAMETERS_PER_LEG + offset + normal);
        }
        held.sort_unstable();
        held
    }

    /// Leg i's equation involves leg i's eight parameters only.
    fn equation_parameters(&self, equation: usize) -> std::ops::Range<usize> {
        equation * PARAMETERS_PER_LEG..(equation + 1) * PARAMETERS_PER_LEG
    }

    /// `qmᵢ = (ℓᵢ − lᵢ)/Kᵢ`: every pose has its values (a leg's range is
    /// checked apart, [`out_of_range`](Self::out_of_range)).
    fn actuator_values(&self, pose: &Isometry3<f64>) -> Result<Vec<f64>, Error> {
        let lengths = self.leg_lengths(pose);
        Ok((0..LEGS)
            .map(|i| (lengths[i] - self.legs[i].length) / self.legs[i].gain)
            .collect())
    }

    fn actuator_range(&self, index: usize) -> (f64, f64) {
        (self.legs[index].min, self.legs[index].max)
    }

    fn actuator_unit(&self) -> ParameterUnit {
        ParameterUnit::Length
    }
}

/// The rules a stated leg meets ([`check_actuator`]).
fn check_leg(number: usize, leg: &Leg) -> Result<(), Error> {
    check_actuator(
        |key| Field::Leg { number, key },
        &[
            ("base", leg.base.as_slice()),
            ("platform", leg.platform.as_slice()),
            ("length", &[leg.length]),
            ("gain", &[leg.gain]),
            ("min", &[leg.min]),
            ("max", &[leg.max]),
        ],
        leg.gain,
        leg.min,
        leg.max,
    )
}

#[cfg(test)]
mod tests;
