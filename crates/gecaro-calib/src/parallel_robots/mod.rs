//! Calibration of parallel robots — a Gough–Stewart platform
//! ([`gecaro_core::gough_stewart`]) or a Delta robot ([`gecaro_core::delta`]),
//! any [`ParallelModel`](gecaro_core::parallel_model::ParallelModel) — identified
//! from what a tracker measures of its platform, as the serial robots are
//! (the paper's closing words).
//!
//! # The calibration equations
//!
//! - **Pose measured** (`frame`: the platform frame's pose (p, R) in the
//!   base frame, with the actuator values qm): Khalil and Besnard's way,
//!   through the inverse model, so no direct model is solved to form the
//!   equations. Each pose gives six equations, one a leg,
//!   `∂Fᵢ/∂ξ·Δξ = −Fᵢ` with `Fᵢ = ‖p + R·bᵢ − aᵢ‖ − lᵢ − Kᵢ·qmᵢ`
//!   ([`ParallelModel::parameter_jacobian`](gecaro_core::parallel_model::ParallelModel::parameter_jacobian)). A measured pose's noise reaches
//!   leg i's equation with variance `σ_p² + σ_r²·‖R·bᵢ × uᵢ‖²` (σ_p of a
//!   position coordinate, σ_r of a rotation angle); each row is weighted by
//!   it, so the residuals are tested against the stated noise like a serial
//!   robot's.
//! - **Point measured** (`position`: one point of the platform, the tool
//!   point t, whose position is identified): the platform's orientation is
//!   not measured, so the equations are in the measured point's
//!   coordinates, through the direct model x(qm, ξ) solved by Newton's
//!   method and its derivative by the implicit function theorem:
//!   `∂x/∂ξ = −J_x⁻¹·∂F/∂ξ`, then `∂y/∂ξ = [I, −[R·t]×]·∂x/∂ξ + R·∂t/∂ξ`.
//!
//! The identifiable parameters are found by QR of the observation matrix
//! at the nominal parameters (Appendix III, the same numerical zero as a
//! serial robot's); the others keep their nominal values and the regrouping
//! relations say what they stand in for. With the pose measured every one of
//! the 48 leg parameters is identifiable (the measured frames define the
//! base and platform frames); with one point measured the platform frame is
//! not observed, and six parameters are regrouped into the others.
//!
//! The fit is Gauss–Newton on the base parameters with the analytic
//! Jacobians, each step halved while it does not lower the cost; the
//! precision of each parameter is `σ̂·√diag((WᵀW)⁻¹)`, and the verdict is a
//! serial robot's [`Outcome`](crate::identification::Outcome) with its χ²
//! test of the residuals against the stated noise. A robust
//! [`Loss`](crate::identification::Loss) reweights each observation by its
//! residual after the least-squares fit (iteratively reweighted least
//! squares, its rows multiplied by `√w`), as for a serial robot.
//!
//! # Several stations
//! Sets measured from several tracker stations
//! ([`identify_platform_sets`]): each set is registered in closed form on
//! the nominal robot; the first set's frame is the base frame, and every
//! later station `s` keeps a rigid correction `δ_s = (t_s, r_s)`,
//! identified with the parameters (its measurements read as `δ_s·m`). Its
//! columns: for a measured pose, from the closure row `∂Fᵢ/∂x = [g_p; g_r]`
//! (`δp`, then `ω` with `R ← exp(ω)·R`), `[g_p, g_r + p × g_p]`; for a
//! measured point `m`, `[−I, [m]×]`. The rank analysis projects them out
//! of W first, so a parameter a station's frame takes is not counted
//! identifiable.
//!
//! # References
//! W. Khalil, S. Besnard, "Self calibration of Stewart–Gough parallel
//! robots without extra sensors", IEEE Trans. Robotics and Automation,
//! 1999; D. Daney, "Kinematic calibration of the Gough platform",
//! Robotica, 2003.

mod auxiliary;
mod changed;
mod descent;
mod evaluation;
mod identifiability;
mod identification;
mod leg;
mod measure;
mod observation;
mod planning;
mod plausible;
mod prediction;
mod region;
mod registration;
mod reweighting;
mod simulation;
mod stations;

pub use evaluation::{PlatformErrors, check_platform_samples, leg_errors, platform_errors};
pub use identifiability::{PlatformRankReport, platform_identifiability};
pub use identification::{
    IdentifiedLeg, PlatformIdentification, PlatformIdentificationOptions, PlatformOutlier,
    PlatformParameter, PlatformStation, identify_platform, identify_platform_sets,
};
pub use leg::{LEG_UNKNOWNS, MeasuringLeg};
pub use measure::{PlatformMeasure, PlatformNoise};
pub use planning::{PlannedPoses, plan_platform};
pub use prediction::{
    PlatformPrediction, SimulatedCalibrations, predict_platform, simulate_calibrations,
};
pub use region::{PlatformRegion, work_region_centre};
pub use registration::{in_base_frame, measurement_frame};
pub use simulation::{
    PlatformWorkspace, perturbed_platform, random_platform_poses, simulate_leg, simulate_platform,
};
