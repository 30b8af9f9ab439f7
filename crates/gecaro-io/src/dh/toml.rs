//! Denavit–Hartenberg tables in TOML (the module docs of [`super`] show the
//! keys).

use std::path::Path;

use serde::Deserialize;
use toml::Spanned;

use super::table::{
    DhConvention, Row, RowDocument, Table, TableUnits, TransformDocument, Units, joint_type,
};
use crate::Error;
use crate::robot_file::AngleUnit;
use crate::units::LengthUnit;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct TableDocument {
    name: Option<String>,
    description: Option<String>,
    convention: Option<Spanned<String>>,
    angle_unit: Option<Spanned<String>>,
    length_unit: Option<Spanned<String>>,
    base: Option<Spanned<TransformDocument>>,
    tool: Option<Spanned<TransformDocument>>,
    #[serde(default)]
    joint: Vec<Spanned<RowDocument>>,
}

pub(super) fn parse_toml(text: &str, path: &Path, defaults: TableUnits) -> Result<Table, Error> {
    let line_of = |offset: usize| crate::error::line_at(text, offset);
    // The line of `field` in the table whose header is at `span` (its keys
    // run to the next header), else the header's line.
    let fail = |span: std::ops::Range<usize>, field: &str, message: String| {
        let table = &text[span.start.min(text.len())..];
        let offset = table
            .lines()
            .scan(0, |at, line| {
                let start = *at;
                *at += line.len() + 1;
                Some((start, line))
            })
            .take_while(|(start, line)| *start == 0 || !line.trim_start().starts_with('['))
            .find(|(_, line)| {
                line.split('=')
                    .next()
                    .is_some_and(|key| key.trim() == field)
            })
            .map_or(0, |(start, _)| start);
        Error::parse(
            path,
            line_of(span.start + offset),
            Some(field.to_owned()),
            message,
        )
    };
    let document: TableDocument = toml::from_str(text).map_err(|error| {
        let line = error.span().map_or(1, |span| line_of(span.start));
        Error::parse(path, line, None, crate::error::toml_message(&error, text))
    })?;
    let angle = match &document.angle_unit {
        None => defaults.angle.unwrap_or_default(),
        Some(unit) => AngleUnit::parse(unit.get_ref())
            .map_err(|message| fail(unit.span(), "angle_unit", message))?,
    };
    let length = match &document.length_unit {
        None => defaults.length.unwrap_or_default(),
        Some(unit) => LengthUnit::parse(unit.get_ref())
            .map_err(|message| fail(unit.span(), "length_unit", message))?,
    };
    let units = Units {
        angle: angle.to_radians(),
        length: length.to_metres(),
    };
    let convention = match &document.convention {
        None => None,
        Some(name) => Some(DhConvention::from_name(name.get_ref()).ok_or_else(|| {
            fail(
                name.span(),
                "convention",
                format!("must be \"dh\" or \"mdh\", not {:?}", name.get_ref()),
            )
        })?),
    };
    let transform = |document: &Option<Spanned<TransformDocument>>, key: &str| {
        document
            .as_ref()
            .map(|spanned| {
                let values = spanned.get_ref();
                if values.xyz.iter().chain(&values.rpy).all(|v| v.is_finite()) {
                    Ok(units.transform(values))
                } else {
                    Err(fail(
                        spanned.span(),
                        key,
                        "holds a value that is not a finite number".into(),
                    ))
                }
            })
            .transpose()
    };
    let mut rows = Vec::with_capacity(document.joint.len());
    for spanned in &document.joint {
        let row = spanned.get_ref();
        let at = |field: &str, message: String| fail(spanned.span(), field, message);
        let frame_type = joint_type(&row.joint_type).ok_or_else(|| {
            at(
                "type",
                format!(
                    "must be \"R\" (revolute) or \"P\" (prismatic), not {:?}",
                    row.joint_type
                ),
            )
        })?;
        for (key, value) in [
            ("a", Some(row.a)),
            ("alpha", Some(row.alpha)),
            ("d", Some(row.d)),
            ("theta", Some(row.theta)),
            ("qmin", row.qmin),
            ("qmax", row.qmax),
        ] {
            if value.is_some_and(|v| !v.is_finite()) {
                return Err(at(
                    key,
                    format!("{} is not a finite number", value.unwrap_or_default()),
                ));
            }
        }
        let scale = units.joint(frame_type);
        rows.push(Row {
            frame_type,
            step: units.step(row.a, row.alpha, row.d, row.theta),
            limits: (row.qmin.map(|v| v * scale), row.qmax.map(|v| v * scale)),
        });
    }
    if rows.is_empty() {
        return Err(Error::parse(
            path,
            1,
            None,
            "no [[joint]] rows: a table needs one row per joint",
        ));
    }
    Ok(Table {
        name: document.name,
        description: document.description,
        convention,
        world_from_base: transform(&document.base, "base")?,
        last_from_tool: transform(&document.tool, "tool")?,
        rows,
    })
}
