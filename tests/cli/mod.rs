//! End-to-end tests of the `gecaro` binary: each runs the real executable.
//!
//! Its tests in files by job (the models, robot files, calibration,
//! planning); the helpers and imports they share are here.

mod calibration;
mod kinematics;
mod planning;
mod robots;

pub(crate) use gecaro_calib::study::Samples;
pub(crate) use std::path::Path;

pub(crate) use crate::util::{command, gecaro, json_output};
pub(crate) use predicates::prelude::*;
pub(crate) use serde_json::Value;

pub(crate) fn as_f64s(value: &Value) -> Vec<f64> {
    value
        .as_array()
        .expect("array")
        .iter()
        .map(|v| v.as_f64().expect("number"))
        .collect()
}

/// Text of every `<text>` element of an SVG, for checking what a plot says.
pub(crate) fn svg_texts(svg: &str) -> Vec<String> {
    svg.split("<text")
        .skip(1)
        .filter_map(|rest| {
            let start = rest.find('>')? + 1;
            let end = rest.find("</text>")?;
            Some(rest[start..end].trim().to_owned())
        })
        .collect()
}
