//! ISO 9283's acceptance test as jobs (issue 78): the test planned on a
//! robot ([`Iso9283PlanRequest`]: `gecaro iso9283 plan`, Python
//! `gecaro.iso9283_plan`, the page's `/api/iso9283/plan`) and evaluated
//! from what an instrument measured ([`Iso9283EvaluateRequest`]: `gecaro
//! iso9283 evaluate`, `gecaro.iso9283_evaluate`, `/api/iso9283/evaluate`).
//! The characteristics and their conventions are
//! [`gecaro_calib::iso9283`]'s; the program is a program file as
//! `compensate` reads it, so that the test run after a calibration is the
//! same program compensated.
//!
//! The program's columns: `pose` (1–5), `cycle` (from 1), `direction`
//! (1; 1–3 in the multi-directional test), `measure` (1 where the pose is
//! measured, 0 at an approach point), the joints `qm1..qmn` and the
//! commanded pose of frame n+1 `x,y,z[,qw,qx,qy,qz]` (base frame).

mod evaluate;
mod plan;

pub use evaluate::{
    EvaluatedTest, Iso9283EvaluateRequest, MeasuredTestJson, PoseResultJson, TestConditions,
    TestEvaluationJson, TestWarning,
};
pub use plan::{Iso9283PlanRequest, MAX_CYCLES, PlannedTest, TestPlanJson};

/// The program's key columns, in order.
pub(crate) const KEYS: [&str; 4] = ["pose", "cycle", "direction", "measure"];
