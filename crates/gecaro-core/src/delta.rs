//! A Delta robot (Clavel's 3-RUU / 3-RSS with parallelograms): three
//! motors on the base turn three upper arms; each arm's forearm (a
//! parallelogram) keeps the travelling plate level, so the plate only
//! translates.
//!
//! # The model
//!
//! Arm i (1..3): its motor axis passes through the base joint centre `Bᵢ`
//! (base frame), horizontal and perpendicular to the arm's plane, whose
//! azimuth is `φᵢ` (`hᵢ = (cos φᵢ, sin φᵢ, 0)`). The motor turns the upper
//! arm of length `Laᵢ` to `θᵢ = θ0ᵢ + Kᵢ·qmᵢ` (0 horizontal and outward,
//! positive downward), putting the elbow at
//!
//! ```text
//! Eᵢ = Bᵢ + Laᵢ·(cos θᵢ·hᵢ − sin θᵢ·ẑ)
//! ```
//!
//! The forearm of length `Lbᵢ` joins the elbow to the plate's joint centre
//! `cᵢ` (plate frame): with the plate at p, the closure equation is
//!
//! ```text
//! Fᵢ = ‖p + cᵢ − Eᵢ‖ − Lbᵢ = 0
//! ```
//!
//! The inverse model is explicit (`A cos θ + B sin θ = C` per arm, the
//! elbow-out solution); the direct model is Newton's method on the three
//! closure equations from the home pose (the plate below the base).
//!
//! # Parameters and units
//!
//! 11 per arm, then the tool point's 3, 36 in all, with these names:
//! `B1x B1y B1z phi1 theta1 K1 La1 Lb1 c1x c1y c1z … tx ty tz`. Metres and
//! radians; gains dimensionless. Because the plate only translates, `cᵢ`
//! and `Bᵢ` meet the measurements only through their difference — QR
//! regroups three coordinates an arm, as it finds them.

use nalgebra::{DMatrix, DVector, Isometry3, Point3, Translation3, Vector3};

use crate::error::{Error, Field};
use crate::parallel_model::{
    EquationVisitor, ParallelModel, ParameterUnit, check_actuator, check_tool,
};

/// A Delta robot's arms.
pub const ARMS: usize = 3;

/// Parameters per arm: `B` (3), `φ`, `θ0`, `K`, `La`, `Lb`, `c` (3).
pub const PARAMETERS_PER_ARM: usize = 11;

/// Parameters of a Delta robot: 11 per arm and the tool point's 3.
pub const PARAMETER_COUNT: usize = ARMS * PARAMETERS_PER_ARM + 3;

/// One arm; see the module docs.
#[derive(Clone, Debug, PartialEq)]
pub struct Arm {
    /// `B`: the motor axis's point in the arm's plane, base frame (m).
    pub base: Vector3<f64>,
    /// `φ`: the azimuth of the arm's plane (rad).
    pub azimuth: f64,
    /// `θ0`: the arm's angle at actuator value zero (rad, positive down).
    pub offset: f64,
    /// `K`: radians of arm per unit of actuator value.
    pub gain: f64,
    /// `La`: the upper arm's length (m).
    pub upper_arm: f64,
    /// `Lb`: the forearm's length (m).
    pub forearm: f64,
    /// `c`: the plate's joint centre, plate frame (m).
    pub platform: Vector3<f64>,
    /// The smallest actuator value.
    pub min: f64,
    /// The largest actuator value.
    pub max: f64,
}

/// A Delta robot; see the module docs.
#[derive(Clone, Debug, PartialEq)]
pub struct Delta {
    name: String,
    arms: Vec<Arm>,
    /// Each arm's hᵢ, from its azimuth (computed once: every closure
    /// equation reads it).
    directions: Vec<Vector3<f64>>,
    tool: Vector3<f64>,
    home: Isometry3<f64>,
}

/// `(cos φ, sin φ, 0)` of each arm.
fn directions(arms: &[Arm]) -> Vec<Vector3<f64>> {
    arms.iter()
        .map(|arm| Vector3::new(arm.azimuth.cos(), arm.azimuth.sin(), 0.0))
        .collect()
}

impl Delta {
    /// A Delta robot of three arms and a tool point (plate frame, m), its
    /// home pose found with every arm at the middle of its range and the
    /// plate below the base.
    ///
    /// # Errors
    /// [`Error::Invalid`] naming the arm and key of a value no Delta robot
    /// has, or when no plate pose closes the arms at the middle of their
    /// ranges.
    pub fn new(name: &str, arms: Vec<Arm>, tool: Vector3<f64>) -> Result<Self, Error> {
        if arms.len() != ARMS {
            return Err(Error::Invalid {
                field: Field::Frames,
                message: format!("a Delta robot has {ARMS} arms, {} are given", arms.len()),
            });
        }
        for (index, arm) in arms.iter().enumerate() {
            check_arm(index + 1, arm)?;
        }
        check_tool(&tool)?;
        let mut delta = Self {
            name: name.to_owned(),
            directions: directions(&arms),
            arms,
            tool,
            home: Isometry3::identity(),
        };
        delta.home = delta.middle_pose()?;
        Ok(delta)
    }

    /// The three arms, arm 1 first.
    pub fn arms(&self) -> &[Arm] {
        &self.arms
    }

    /// The arm's angle θᵢ at an actuator value.
    fn angle(&self, arm: usize, actuator: f64) -> f64 {
        self.arms[arm].offset + self.arms[arm].gain * actuator
    }

    /// The arm's horizontal direction hᵢ.
    fn direction(&self, arm: usize) -> Vector3<f64> {
        self.directions[arm]
    }

    /// The elbow Eᵢ at angle θ.
    pub fn elbow(&self, arm: usize, angle: f64) -> Vector3<f64> {
        let a = &self.arms[arm];
        a.base + a.upper_arm * (angle.cos() * self.direction(arm) - angle.sin() * Vector3::z())
    }

    /// `p + cᵢ − Eᵢ`: the forearm, base frame.
    fn forearm(&self, pose: &Isometry3<f64>, arm: usize, actuator: f64) -> Vector3<f64> {
        pose.transform_point(&Point3::from(self.arms[arm].platform))
            .coords
            - self.elbow(arm, self.angle(arm, actuator))
    }

    /// The plate's pose with every arm at the middle of its range: Newton
    /// from the plate below the base, where the first arm's forearm hangs
    /// straight down from its elbow.
    fn middle_pose(&self) -> Result<Isometry3<f64>, Error> {
        let middle: Vec<f64> = self.arms.iter().map(|a| 0.5 * (a.min + a.max)).collect();
        let elbow = self.elbow(0, self.angle(0, middle[0]));
        let centre = self.arms.iter().map(|a| a.base).sum::<Vector3<f64>>() / ARMS as f64
            - self.arms.iter().map(|a| a.platform).sum::<Vector3<f64>>() / ARMS as f64;
        let reach = (elbow - self.arms[0].platform - centre).xy().norm();
        let depth = (self.arms[0].forearm.powi(2) - reach.powi(2))
            .max(0.0)
            .sqrt();
        let start = Isometry3::from_parts(
            Translation3::new(centre.x, centre.y, elbow.z - depth),
            nalgebra::UnitQuaternion::identity(),
        );
        self.direct(&middle, &start).map_err(|_| Error::Invalid {
            field: Field::Frames,
            message: "no plate pose closes the three arms at the middle of their ranges: the \
                      arms, forearms or ranges are mistaken"
                .into(),
        })
    }
}

impl ParallelModel for Delta {
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
        ARMS
    }

    fn pose_freedom(&self) -> usize {
        3
    }

    fn parameters(&self) -> Vec<f64> {
        let mut values = Vec::with_capacity(PARAMETER_COUNT);
        for arm in &self.arms {
            values.extend(arm.base.iter());
            values.extend([
                arm.azimuth,
                arm.offset,
                arm.gain,
                arm.upper_arm,
                arm.forearm,
            ]);
            values.extend(arm.platform.iter());
        }
        values.extend(self.tool.iter());
        values
    }

    fn parameter_count(&self) -> usize {
        PARAMETER_COUNT
    }

    fn parameter_names(&self) -> Vec<String> {
        let mut names = Vec::with_capacity(PARAMETER_COUNT);
        for arm in 1..=ARMS {
            for axis in ["x", "y", "z"] {
                names.push(format!("B{arm}{axis}"));
            }
            for part in ["phi", "theta", "K", "La", "Lb"] {
                names.push(format!("{part}{arm}"));
            }
            for axis in ["x", "y", "z"] {
                names.push(format!("c{arm}{axis}"));
            }
        }
        names.extend(["tx", "ty", "tz"].map(String::from));
        names
    }

    fn parameter_unit(&self, index: usize) -> ParameterUnit {
        match (index < ARMS * PARAMETERS_PER_ARM).then_some(index % PARAMETERS_PER_ARM) {
            Some(3 | 4) => ParameterUnit::Angle,
            Some(5) => ParameterUnit::Gain,
            _ => ParameterUnit::Length,
        }
    }

    fn tool_parameters(&self) -> std::ops::Range<usize> {
        ARMS * PARAMETERS_PER_ARM..PARAMETER_COUNT
    }

    fn with_parameters(&self, values: &[f64]) -> Result<Self, Error> {
        if values.len() != PARAMETER_COUNT {
            return Err(Error::Invalid {
                field: Field::Frames,
                message: format!(
                    "a Delta robot has {PARAMETER_COUNT} parameters, {} are given",
                    values.len()
                ),
            });
        }
        let arms: Vec<Arm> = self
            .arms
            .iter()
            .zip(values.chunks_exact(PARAMETERS_PER_ARM))
            .map(|(arm, v)| Arm {
                base: Vector3::new(v[0], v[1], v[2]),
                azimuth: v[3],
                offset: v[4],
                gain: v[5],
                upper_arm: v[6],
                forearm: v[7],
                platform: Vector3::new(v[8], v[9], v[10]),
                ..arm.clone()
            })
            .collect();
        for (index, arm) in arms.iter().enumerate() {
            check_arm(index + 1, arm)?;
        }
        let tool = &values[ARMS * PARAMETERS_PER_ARM..];
        Ok(Self {
            name: self.name.clone(),
            directions: directions(&arms),
            arms,
            tool: Vector3::new(tool[0], tool[1], tool[2]),
            home: self.home,
        })
    }

    /// Every arm at the middle of its range, the plate below the base.
    fn home(&self) -> Isometry3<f64> {
        self.home
    }

    fn tool(&self) -> Vector3<f64> {
        self.tool
    }

    fn closure(&self, pose: &Isometry3<f64>, actuators: &[f64]) -> DVector<f64> {
        DVector::from_fn(ARMS, |i, _| {
            self.forearm(pose, i, actuators[i]).norm() - self.arms[i].forearm
        })
    }

    /// Row i: `uᵢᵀ`, the forearm's unit vector (the plate translates only).
    fn pose_jacobian(&self, pose: &Isometry3<f64>, actuators: &[f64]) -> DMatrix<f64> {
        let mut jacobian = DMatrix::zeros(ARMS, 3);
        for (i, actuator) in actuators.iter().enumerate().take(ARMS) {
            let unit = self.forearm(pose, i, *actuator).normalize();
            jacobian.row_mut(i).copy_from(&unit.transpose());
        }
        jacobian
    }

    /// Arm by arm on the stack, each arm's angle's sine and cosine once:
    /// the rows of [`closure`](ParallelModel::closure) and
    /// [`pose_jacobian`](ParallelModel::pose_jacobian), and the coefficients
    /// `∂Fᵢ/∂B = −uᵀ`, `∂Fᵢ/∂φ = −uᵀ·∂E/∂φ`, `∂Fᵢ/∂θ0 = −uᵀ·∂E/∂θ`,
    /// `∂Fᵢ/∂K = −uᵀ·∂E/∂θ·qmᵢ`, `∂Fᵢ/∂La = −uᵀ·e`, `∂Fᵢ/∂Lb = −1`,
    /// `∂Fᵢ/∂c = uᵀ·R` (the tool point is in no closure equation).
    fn visit_equations(
        &self,
        pose: &Isometry3<f64>,
        actuators: &[f64],
        visit: &mut EquationVisitor<'_>,
    ) {
        let inverse = pose.rotation.inverse();
        for (i, arm) in self.arms.iter().enumerate() {
            let angle = self.angle(i, actuators[i]);
            let (sin, cos) = angle.sin_cos();
            let h = self.direction(i);
            let along = cos * h - sin * Vector3::z();
            let elbow = arm.base + arm.upper_arm * along;
            let forearm = pose.transform_point(&Point3::from(arm.platform)).coords - elbow;
            let length = forearm.norm();
            let unit = forearm / length;
            let turned = arm.upper_arm * (-sin * h - cos * Vector3::z());
            // ∂h/∂φ = (−sin φ, cos φ, 0), from h = (cos φ, sin φ, 0).
            let sideways = arm.upper_arm * cos * Vector3::new(-h.y, h.x, 0.0);
            let plate = inverse * unit;
            let own = [
                -unit.x,
                -unit.y,
                -unit.z,
                -unit.dot(&sideways),
                -unit.dot(&turned),
                -unit.dot(&turned) * actuators[i],
                -unit.dot(&along),
                -1.0,
                plate.x,
                plate.y,
                plate.z,
            ];
            visit(i, length - arm.forearm, &[unit.x, unit.y, unit.z], &own);
        }
    }

    /// Arm i's equation involves arm i's eleven parameters only.
    fn equation_parameters(&self, equation: usize) -> std::ops::Range<usize> {
        equation * PARAMETERS_PER_ARM..(equation + 1) * PARAMETERS_PER_ARM
    }

    /// Per arm, `A cos θ + B sin θ = C` with `v = p + R·c − B`, `A = v·h`,
    /// `B = −v_z`, `C = (‖v‖² + La² − Lb²)/(2 La)`; of its two solutions the
    /// one whose elbow is further out (the Delta's working mode).
    fn actuator_values(&self, pose: &Isometry3<f64>) -> Result<Vec<f64>, Error> {
        (0..ARMS)
            .map(|i| {
                let arm = &self.arms[i];
                let v = pose.transform_point(&Point3::from(arm.platform)).coords - arm.base;
                let (a, b) = (v.dot(&self.direction(i)), -v.z);
                let c = (v.norm_squared() + arm.upper_arm.powi(2) - arm.forearm.powi(2))
                    / (2.0 * arm.upper_arm);
                let radius = a.hypot(b);
                if radius == 0.0 || (c / radius).abs() > 1.0 {
                    return Err(Error::Unreachable {
                        iterations: 0,
                        residual: (c.abs() - radius).max(0.0),
                        tolerance: 0.0,
                        met_limit: false,
                    });
                }
                let (middle, spread) = (b.atan2(a), (c / radius).acos());
                let angle = [middle + spread, middle - spread]
                    .into_iter()
                    .max_by(|x, y| x.cos().total_cmp(&y.cos()))
                    .unwrap_or(middle);
                Ok((angle - arm.offset) / arm.gain)
            })
            .collect()
    }

    fn actuator_range(&self, index: usize) -> (f64, f64) {
        (self.arms[index].min, self.arms[index].max)
    }

    fn actuator_unit(&self) -> ParameterUnit {
        ParameterUnit::Angle
    }
}

/// The rules a stated arm meets ([`check_actuator`], and arms of a length).
fn check_arm(number: usize, arm: &Arm) -> Result<(), Error> {
    let field = |key| Field::Arm { number, key };
    check_actuator(
        field,
        &[
            ("base", arm.base.as_slice()),
            ("azimuth", &[arm.azimuth]),
            ("offset", &[arm.offset]),
            ("gain", &[arm.gain]),
            ("upper_arm", &[arm.upper_arm]),
            ("forearm", &[arm.forearm]),
            ("platform", arm.platform.as_slice()),
            ("min", &[arm.min]),
            ("max", &[arm.max]),
        ],
        arm.gain,
        arm.min,
        arm.max,
    )?;
    for (key, value) in [("upper_arm", arm.upper_arm), ("forearm", arm.forearm)] {
        if value <= 0.0 {
            return Err(Error::Invalid {
                field: field(key),
                message: format!("{value} is not the length of an arm"),
            });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests;
