//! SYMORO `.par` files (W. Khalil's symbolic modelling package): the
//! Khalil–Kleinfinger description of a robot, read for serial robots.
//!
//! A `.par` file is a list of `NAME = value` statements and `(* comments *)`;
//! the geometric parameters are lists over frames 1..NF: `ant` (the frame
//! each frame is placed on), `sigma`, `gamma`, `b`, `alpha`, `d`, `theta`,
//! `r`, `mu` (eq. 3 with the tree's extra `Rot(z,γ)·Trans(z,b)` in front).
//! Entries are numbers or expressions (`-pi/2`, `2*pi/3`); a symbol in θ of
//! a revolute joint or r of a prismatic one is the joint variable (its zero
//! stands there: `th2 + pi/2` is the offset π/2); any other symbol needs a
//! value, given by a line `RL2 = 0.2` in the file. `Z` (16 numbers, row by
//! row) places frame 0 in the world.
//!
//! gecaro reads serial robots: `ant_j = j − 1`, joints 1..NJ, and at most one
//! more fixed frame (σ = 2) carried by the last joint, which becomes frame
//! n+1. γ1 and b1 become frame 0 (θ0, r0); a γ_j, b_j of a later frame is
//! folded into frame j−1's θ and r. Trees, closed loops and floating bases
//! are errors; `.par` files carry no joint limits (defaults, with a note).
//!
//! [`export`] writes them back.

pub(crate) mod export;

use std::collections::HashMap;
use std::path::Path;

use exmex::Express;
use gecaro_core::{Frame, FrameType, Joint, MassModel, Robot, RobotSpec};
use nalgebra::{IsometryMatrix3, Matrix3, Rotation3, Translation3};

use crate::Error;
use crate::conversion::Imported;
use crate::robot_file::{AngleUnit, RobotFile};

/// Keys of SYMORO that are not symbol definitions.
const KEYWORDS: &[&str] = &[
    "NL",
    "NJ",
    "NF",
    "Type",
    "is_floating",
    "is_mobile",
    "ant",
    "sigma",
    "b",
    "d",
    "r",
    "gamma",
    "alpha",
    "mu",
    "theta",
    "XX",
    "XY",
    "XZ",
    "YY",
    "YZ",
    "ZZ",
    "MX",
    "MY",
    "MZ",
    "M",
    "IA",
    "FV",
    "FS",
    "FX",
    "FY",
    "FZ",
    "CX",
    "CY",
    "CZ",
    "eta",
    "k",
    "QP",
    "QDP",
    "GAM",
    "W0",
    "WP0",
    "V0",
    "VP0",
    "Z",
    "G",
];

/// A statement's value as written, with its line.
struct Statement {
    line: usize,
    items: Vec<String>,
    is_list: bool,
}

/// The text without `(* … *)` comments (newlines kept, so lines count), and
/// the robot name of a `Robotname = '…'` comment.
fn strip_comments(text: &str) -> (String, Option<String>) {
    let mut kept = String::with_capacity(text.len());
    let mut name = None;
    let mut rest = text;
    while let Some(start) = rest.find("(*") {
        kept.push_str(&rest[..start]);
        let after = &rest[start + 2..];
        let end = after.find("*)").map_or(after.len(), |e| e);
        let comment = &after[..end];
        if let Some(position) = comment.find("Robotname") {
            name = comment[position..]
                .split('\'')
                .nth(1)
                .map(str::to_owned)
                .or(name);
        }
        kept.extend(comment.chars().filter(|c| *c == '\n'));
        rest = after.get(end + 2..).unwrap_or("");
    }
    kept.push_str(rest);
    (kept, name)
}

fn parse_statements(text: &str, path: &Path) -> Result<HashMap<String, Statement>, Error> {
    let mut statements = HashMap::new();
    let mut line = 1;
    let mut rest = text;
    loop {
        let skipped = rest.len() - rest.trim_start().len();
        line += rest[..skipped].matches('\n').count();
        rest = &rest[skipped..];
        if rest.is_empty() {
            break;
        }
        let Some(equals) = rest.find('=') else {
            return Err(Error::parse(
                path,
                line,
                None,
                format!("`{}`: expected NAME = value", short(first_line(rest))),
            ));
        };
        let name = rest[..equals].trim().to_owned();
        if name.is_empty() || name.contains(char::is_whitespace) {
            return Err(Error::parse(
                path,
                line,
                None,
                format!("`{}`: expected NAME = value", short(first_line(rest))),
            ));
        }
        let value_start = &rest[equals + 1..];
        let trimmed = value_start.trim_start();
        let (value, consumed, is_list) = if let Some(list) = trimmed.strip_prefix('{') {
            let close = list.find('}').ok_or_else(|| {
                Error::parse(path, line, Some(name.clone()), "a list `{` without its `}`")
            })?;
            let offset = value_start.len() - trimmed.len() + 1 + close + 1;
            (&list[..close], offset, true)
        } else {
            let end = value_start.find('\n').unwrap_or(value_start.len());
            (&value_start[..end], end, false)
        };
        let statement_line = line;
        line += rest[..equals + 1 + consumed].matches('\n').count();
        rest = &value_start[consumed..];
        rest = rest.trim_start_matches([' ', '\t', ';']);
        let items = if is_list {
            value
                .split(',')
                .map(|item| item.trim().to_owned())
                .collect()
        } else {
            vec![value.trim().trim_end_matches(';').trim().to_owned()]
        };
        statements.insert(
            name,
            Statement {
                line: statement_line,
                items,
                is_list,
            },
        );
    }
    Ok(statements)
}

/// `text` as a message quotes it: at most 60 characters, the rest cut with `…`.
fn short(text: &str) -> std::borrow::Cow<'_, str> {
    const MOST: usize = 60;
    match text.char_indices().nth(MOST) {
        Some((end, _)) => format!("{}…", &text[..end]).into(),
        None => text.into(),
    }
}

fn first_line(text: &str) -> &str {
    text.lines().next().unwrap_or_default().trim()
}

/// Evaluates SYMORO expressions with the file's symbols.
struct Evaluator<'a> {
    symbols: HashMap<String, f64>,
    path: &'a Path,
}

impl Evaluator<'_> {
    /// The value of `text`; `variable` symbols (a joint's own variable) count 0.
    fn value(
        &self,
        text: &str,
        line: usize,
        field: &str,
        allow_variable: bool,
    ) -> Result<f64, Error> {
        let fail = |message: String| {
            Error::parse(self.path, line, Some(short(field).into_owned()), message)
        };
        let expression = parse_expression(text).map_err(fail)?;
        let expression = match expression {
            Parsed::Number(value) => return Ok(value),
            Parsed::Expression(expression) => expression,
        };
        let mut unknown = Vec::new();
        let values: Vec<f64> = expression
            .var_names()
            .iter()
            .map(|name| match name.as_str() {
                "pi" | "Pi" => std::f64::consts::PI,
                other => self.symbols.get(other).copied().unwrap_or_else(|| {
                    unknown.push(other.to_owned());
                    0.0
                }),
            })
            .collect();
        match unknown.as_slice() {
            [] => {}
            [_] if allow_variable => {}
            _ => {
                return Err(fail(format!(
                    "`{}`: {} without a value; add a line `{} = <value>` to the file (metres, radians)",
                    short(text),
                    short(&unknown.join(", ")),
                    short(&unknown[0])
                )));
            }
        }
        let value = expression
            .eval(&values)
            .map_err(|error| fail(format!("`{}`: {}", short(text), short(&error.to_string()))))?;
        if value.is_finite() {
            Ok(value)
        } else {
            Err(fail(format!("`{}` is not a finite number", short(text))))
        }
    }
}

/// The longest expression a value may be: SYMORO values are short formulas
/// (`-pi/2`, `RL2 + 0.1`); the parser's time grows faster than the length.
const MAX_EXPRESSION_BYTES: usize = 4096;

/// A value as written: a plain number, or an expression to evaluate.
enum Parsed {
    Number(f64),
    Expression(Box<exmex::FlatEx<f64>>),
}

/// `text` read as a number, else parsed as an expression (at most
/// [`MAX_EXPRESSION_BYTES`]); the error in a sentence.
fn parse_expression(text: &str) -> Result<Parsed, String> {
    if let Ok(value) = text.parse::<f64>() {
        return if value.is_finite() {
            Ok(Parsed::Number(value))
        } else {
            Err(format!("`{}` is not a finite number", short(text)))
        };
    }
    if text.len() > MAX_EXPRESSION_BYTES {
        return Err(format!(
            "an expression of {} characters: a SYMORO value is a short formula (at most \
             {MAX_EXPRESSION_BYTES} characters)",
            text.len()
        ));
    }
    exmex::parse::<f64>(text)
        .map(|expression| Parsed::Expression(Box::new(expression)))
        .map_err(|error| {
            format!(
                "`{}` is not an expression: {}",
                short(text),
                short(&error.to_string())
            )
        })
}

/// The symbol definitions in an order where each comes after the symbols it
/// uses (a depth-first walk with an explicit stack: a chain of 50,000
/// definitions is fine); a definition that uses itself, through others or
/// not, is an error at its line.
fn definition_order<'a>(
    definitions: &HashMap<&'a str, &'a Statement>,
    path: &Path,
) -> Result<Vec<&'a str>, Error> {
    let mut uses: HashMap<&str, Vec<&'a str>> = HashMap::with_capacity(definitions.len());
    for (name, statement) in definitions {
        let used = match parse_expression(&statement.items[0]) {
            Ok(Parsed::Expression(expression)) => expression
                .var_names()
                .iter()
                .filter_map(|used| {
                    definitions
                        .get_key_value(used.as_str())
                        .map(|(key, _)| *key)
                })
                .collect(),
            Ok(Parsed::Number(_)) => Vec::new(),
            Err(message) => {
                return Err(Error::parse(
                    path,
                    statement.line,
                    Some(short(name).into_owned()),
                    message,
                ));
            }
        };
        uses.insert(name, used);
    }
    #[derive(Clone, Copy, PartialEq)]
    enum Mark {
        Active,
        Done,
    }
    let mut marks: HashMap<&str, Mark> = HashMap::with_capacity(definitions.len());
    let mut order = Vec::with_capacity(definitions.len());
    let mut names: Vec<&'a str> = definitions.keys().copied().collect();
    names.sort_by_key(|name| definitions[name].line);
    for root in names {
        if marks.contains_key(root) {
            continue;
        }
        let mut stack: Vec<(&'a str, usize)> = vec![(root, 0)];
        marks.insert(root, Mark::Active);
        while let Some((name, next)) = stack.last_mut() {
            let used = &uses[*name];
            if let Some(dependency) = used.get(*next).copied() {
                *next += 1;
                match marks.get(dependency) {
                    Some(Mark::Done) => {}
                    Some(Mark::Active) => {
                        let statement = definitions[name];
                        return Err(Error::parse(
                            path,
                            statement.line,
                            Some(short(name).into_owned()),
                            format!(
                                "`{}` is defined through itself (via `{}`): give one of them a \
                                 value",
                                short(name),
                                short(dependency)
                            ),
                        ));
                    }
                    None => {
                        marks.insert(dependency, Mark::Active);
                        stack.push((dependency, 0));
                    }
                }
            } else {
                marks.insert(name, Mark::Done);
                order.push(*name);
                stack.pop();
            }
        }
    }
    Ok(order)
}

/// Imports a serial robot from the text of a `.par` file.
pub(crate) fn import_symoro(text: &str, path: &Path) -> Result<Imported, Error> {
    let (text, robot_name) = strip_comments(text);
    let statements = parse_statements(&text, path)?;
    let statement = |name: &str| {
        statements.get(name).ok_or_else(|| {
            Error::parse(
                path,
                1,
                Some(name.to_owned()),
                format!("missing `{name} = …`"),
            )
        })
    };
    let mut evaluator = Evaluator {
        symbols: HashMap::new(),
        path,
    };
    // Symbol definitions: scalar statements that are not SYMORO keys, each
    // evaluated after the symbols it uses.
    let definitions: HashMap<&str, &Statement> = statements
        .iter()
        .filter(|(name, definition)| !KEYWORDS.contains(&name.as_str()) && !definition.is_list)
        .map(|(name, definition)| (name.as_str(), definition))
        .collect();
    for name in definition_order(&definitions, path)? {
        let definition = definitions[name];
        let value = evaluator.value(&definition.items[0], definition.line, name, false)?;
        evaluator.symbols.insert(name.to_owned(), value);
    }
    let integer = |name: &str| -> Result<i64, Error> {
        let found = statement(name)?;
        found.items[0].parse().map_err(|_| {
            Error::parse(
                path,
                found.line,
                Some(name.to_owned()),
                format!("`{}` is not a whole number", short(&found.items[0])),
            )
        })
    };
    let joint_count = usize::try_from(integer("NJ")?).unwrap_or(0);
    let frame_count = usize::try_from(integer("NF")?).unwrap_or(0);
    for key in ["is_floating", "is_mobile"] {
        if statements.contains_key(key) && integer(key)? != 0 {
            return Err(Error::parse(
                path,
                statement(key)?.line,
                Some(key.to_owned()),
                "a floating or mobile base: gecaro calibrates fixed-base serial robots",
            ));
        }
    }
    if statements.contains_key("Type") && integer("Type")? != 0 {
        let line = statement("Type")?.line;
        return Err(Error::parse(
            path,
            line,
            Some("Type".into()),
            "Type ≠ 0: a tree or closed-loop robot; gecaro calibrates serial robots (Type = 0)",
        ));
    }
    if joint_count == 0 || frame_count < joint_count || frame_count > joint_count + 1 {
        let line = statement("NF")?.line;
        return Err(Error::parse(
            path,
            line,
            Some("NF".into()),
            format!(
                "NJ = {joint_count}, NF = {frame_count}: a serial robot has NF = NJ (no tool frame) or NJ + 1 (a tool frame)"
            ),
        ));
    }
    let list = |name: &str, required: bool| -> Result<Option<&Statement>, Error> {
        let Some(found) = statements.get(name) else {
            return if required {
                Err(Error::parse(
                    path,
                    1,
                    Some(name.to_owned()),
                    format!("missing `{name} = {{…}}`"),
                ))
            } else {
                Ok(None)
            };
        };
        if !found.is_list || found.items.len() != frame_count {
            return Err(Error::parse(
                path,
                found.line,
                Some(name.to_owned()),
                format!(
                    "needs a list of NF = {frame_count} entries, got {}",
                    if found.is_list { found.items.len() } else { 1 }
                ),
            ));
        }
        Ok(Some(found))
    };
    let ant = list("ant", true)?.ok_or_else(|| Error::parse(path, 1, None, "missing ant"))?;
    let sigma = list("sigma", true)?.ok_or_else(|| Error::parse(path, 1, None, "missing sigma"))?;
    let mut frames = vec![Frame::new(FrameType::Fixed)];
    for j in 1..=frame_count {
        let at = |name: &str, message: String| {
            let line = statements.get(name).map_or(1, |s| s.line);
            Error::parse(path, line, Some(format!("{name}, frame {j}")), message)
        };
        let parent: i64 = ant.items[j - 1].parse().map_err(|_| {
            at(
                "ant",
                format!("`{}` is not a frame number", short(&ant.items[j - 1])),
            )
        })?;
        if parent != j as i64 - 1 {
            return Err(at(
                "ant",
                format!(
                    "frame {j} is carried by frame {parent}: a tree; gecaro reads serial robots (ant = j − 1)"
                ),
            ));
        }
        let frame_type = match (sigma.items[j - 1].as_str(), j <= joint_count) {
            ("0", true) => FrameType::Revolute,
            ("1", true) => FrameType::Prismatic,
            ("2", false) => FrameType::Fixed,
            (other, true) => {
                return Err(at(
                    "sigma",
                    format!(
                        "joint {j} has sigma = {other}; joints are 0 (revolute) or 1 (prismatic)"
                    ),
                ));
            }
            (other, false) => {
                return Err(at(
                    "sigma",
                    format!("the tool frame has sigma = {other}, not 2 (fixed)"),
                ));
            }
        };
        let entry = |name: &str| -> Result<f64, Error> {
            let Some(found) = list(name, false)? else {
                return Ok(0.0);
            };
            let variable = matches!(
                (name, frame_type),
                ("theta", FrameType::Revolute) | ("r", FrameType::Prismatic)
            );
            evaluator.value(
                &found.items[j - 1],
                found.line,
                &format!("{name}, frame {j}"),
                variable,
            )
        };
        let (gamma, b) = (entry("gamma")?, entry("b")?);
        // Rot(z,γ)·Trans(z,b) in front of frame j: the end of frame j−1.
        frames[j - 1].theta += gamma;
        frames[j - 1].r += b;
        frames.push(Frame {
            alpha: entry("alpha")?,
            d: entry("d")?,
            theta: entry("theta")?,
            r: entry("r")?,
            ..Frame::new(frame_type)
        });
    }
    if frame_count == joint_count {
        frames.push(Frame::new(FrameType::Fixed));
    }
    let joints: Vec<Joint> = frames[1..=joint_count]
        .iter()
        .map(|frame| Joint::default_for(frame.frame_type))
        .collect();
    let robot = Robot::new(RobotSpec::rigid(
        robot_name.unwrap_or_else(|| crate::robot_file::fallback_name(path)),
        frames,
        joints,
    ))
    .map_err(|error| Error::Format {
        path: path.to_owned(),
        message: error.to_string(),
    })?;
    let mut robot = match statements.get("Z") {
        None => robot,
        Some(z) => {
            let values = z
                .items
                .iter()
                .map(|item| evaluator.value(item, z.line, "Z", false))
                .collect::<Result<Vec<f64>, Error>>()?;
            let world = base_transform(&values)
                .map_err(|message| Error::parse(path, z.line, Some("Z".into()), message))?;
            robot
                .reframed(&world, &IsometryMatrix3::identity())
                .map_err(|error| Error::Format {
                    path: path.to_owned(),
                    message: error.to_string(),
                })?
        }
    };
    // Angles within a turn, as a robot file states them (θ = 8 rad is the
    // geometry of 8 − 2π).
    robot.wrap_angles();
    Ok(Imported {
        file: RobotFile {
            masses: MassModel::new(robot.frames().len()),
            measured_region: None,
            tools: Vec::new(),
            tool_frame_observed: true,
            robot,
            description: Some(format!(
                "imported from {} (SYMORO, {joint_count} joints)",
                path.file_name()
                    .map_or_else(String::new, |f| f.to_string_lossy().into_owned())
            )),
            angle_unit: AngleUnit::Radians,
            urdf: None,
        },
        notes: vec![
            "a .par file has no joint limits: ±π (revolute) and 0..1 m (prismatic) set".to_owned(),
        ],
    })
}

/// The base transform of `Z` (4×4, row by row).
fn base_transform(values: &[f64]) -> Result<IsometryMatrix3<f64>, String> {
    if values.len() != 16 {
        return Err(format!(
            "needs 16 numbers (a 4×4 matrix row by row), got {}",
            values.len()
        ));
    }
    if values[12..] != [0.0, 0.0, 0.0, 1.0] {
        return Err(
            "its last row is not 0, 0, 0, 1: not a homogeneous transform written row by row".into(),
        );
    }
    let rotation = Matrix3::new(
        values[0], values[1], values[2], values[4], values[5], values[6], values[8], values[9],
        values[10],
    );
    if (rotation.transpose() * rotation - Matrix3::identity())
        .abs()
        .max()
        > 1e-6
        || rotation.determinant() < 0.0
    {
        return Err("its rotation part is not a rotation".into());
    }
    Ok(IsometryMatrix3::from_parts(
        Translation3::new(values[3], values[7], values[11]),
        Rotation3::from_matrix(&rotation),
    ))
}
