//! The performance characteristics of ISO 9283 ("Manipulating industrial
//! robots — Performance criteria and related test methods"), clause 7: the
//! test cube and its five poses, pose accuracy and repeatability (7.2),
//! multi-directional pose accuracy variation, and distance accuracy and
//! repeatability (7.3), computed from attained poses as the standard states
//! them.
//!
//! ## The test cube and its poses
//!
//! A cube of side `s` centred at `c`, its edges along the base frame's
//! axes ([`TestCube`]). The measuring plane C1–C2–C7–C8 is the diagonal
//! plane through the cube's vertical edges at (−x, −y) and (+x, +y); its
//! corners, in gecaro's numbering, are C1 = c + s/2·(−1, −1, −1),
//! C2 = c + s/2·(+1, +1, −1), C7 = c + s/2·(+1, +1, +1) and
//! C8 = c + s/2·(−1, −1, +1). Its diagonals are two of the cube's space
//! diagonals (C1–C7 and C2–C8, length √3·s). P1 is the cube's centre; P2 to
//! P5 lie on those diagonals at 10 % of the diagonal's length from C1, C2,
//! C7 and C8 ([`TestCube::poses`]).
//!
//! The program ([`plan_test`]: the cube stated or searched for, the poses
//! solved on the robot's model, the cycles) and the evaluation of what was
//! measured ([`evaluate_test`]: the frame registered, the characteristics
//! per pose) have their own conventions in their modules' docs.
//!
//! ## Pose accuracy and repeatability (7.2)
//!
//! For the `n` attained positions `x_j` of one commanded pose `x_c`
//! (metres) and their orientations, [`pose_characteristics`]:
//!
//! - the barycentre `x̄ = (1/n) Σ x_j`;
//! - **AP_P** `= ‖x̄ − x_c‖`, with its components `AP_x, AP_y, AP_z`;
//! - **AP_a, AP_b, AP_c** `= ā − a_c, …`: the mean orientation error about
//!   x, y and z. gecaro takes each attained orientation's error as the
//!   roll, pitch, yaw (about the fixed x, y, z) of `R_cᵀ R_j`, the attained
//!   orientation seen from the commanded one — the standard's difference of
//!   angles to first order, without a turn's wrap where an angle passes ±π;
//! - **RP_l** `= l̄ + 3 S_l`, with `l_j = ‖x_j − x̄‖`, `l̄` their mean and
//!   `S_l = √(Σ (l_j − l̄)² / (n − 1))`;
//! - **RP_a, RP_b, RP_c** `= ±3 S_a, …`, `S_a = √(Σ (a_j − ā)² / (n − 1))`.
//!
//! ## Multi-directional pose accuracy variation
//!
//! A pose approached from several directions: for each approach its
//! barycentre and mean orientation error; **vAP_P** is the largest distance
//! between two approaches' barycentres, **vAP_a, vAP_b, vAP_c** the largest
//! difference of their mean errors ([`multi_directional`]).
//!
//! ## Distance accuracy and repeatability (7.3)
//!
//! Between two commanded positions `P_c1`, `P_c2` (P2 and P4 of the cube),
//! attained `n` times each: `D_c = ‖P_c1 − P_c2‖`, `D_j = ‖P_1j − P_2j‖`;
//! **AD_P** `= D̄ − D_c` and **RD** `= ±3 S_D`,
//! `S_D = √(Σ (D_j − D̄)² / (n − 1))` ([`distance_characteristics`]).
//!
//! ```
//! use gecaro_calib::iso9283::{TestCube, pose_characteristics};
//! use nalgebra::{IsometryMatrix3, Vector3};
//!
//! let cube = TestCube::new(Vector3::new(0.8, 0.0, 0.6), 0.4)?;
//! let [p1, ..] = cube.poses();
//! assert_eq!(p1, Vector3::new(0.8, 0.0, 0.6));
//! // Three cycles 0.1 mm off along x, 0.05 mm apart along y.
//! let commanded = IsometryMatrix3::translation(p1.x, p1.y, p1.z);
//! let attained: Vec<IsometryMatrix3<f64>> = [-5e-5, 0.0, 5e-5]
//!     .iter()
//!     .map(|dy| IsometryMatrix3::translation(p1.x + 1e-4, p1.y + dy, p1.z))
//!     .collect();
//! let pose = pose_characteristics(&commanded, &attained)?;
//! assert!((pose.accuracy - 1e-4).abs() < 1e-12);
//! # Ok::<(), gecaro_calib::Error>(())
//! ```

mod characteristics;
mod cube;
mod evaluation;
mod noise;
mod plan;

pub use characteristics::{
    DirectionalVariation, DistanceCharacteristics, PoseCharacteristics, distance_characteristics,
    multi_directional, pose_characteristics,
};
pub use cube::{CORNER_SHARE, TestCube};
pub use evaluation::{PoseResult, Registration, TestEvaluation, Visit, evaluate_test};
pub use noise::{PooledNoise, pooled_noise};
pub use plan::{
    APPROACH_SHARE, Approaches, CubeChoice, DEFAULT_CYCLES, JOINT_MARGIN, PlannedPoint,
    SPACE_MARGIN, TestOptions, TestPlan, TestRow, plan_test,
};
