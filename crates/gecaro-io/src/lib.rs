//! # gecaro-io
//!
//! The files of gecaro: robot files (TOML, [`read_robot_file`]), the library
//! of ready robots ([`ready_robots`], [`load_robot`]), measurement data (CSV,
//! [`read_samples`]), robots from and to other formats (URDF, DH tables,
//! SYMORO: [`import_robot`], [`export_robot`]), and safe
//! output ([`write_atomically`]). Every error names the file, and for content errors
//! the line and key ([`Error::Parse`]).

#![warn(missing_docs)]

mod columns;
mod conversion;
mod data_file;
mod data_rows;
mod dh;
mod document;
mod error;
mod input;
mod interchange;
mod join;
mod joint_calibration;
mod line_chunks;
mod named_points;
mod output;
mod parallel_file;
mod payload;
mod plain_body;
mod pose;
mod prior;
mod problem;
mod program;
mod ready;
mod robot_file;
mod robot_toml;
pub mod roles;
mod rotation;
mod stated_units;
mod symoro;
mod table_text;
mod test_cube;
mod toml_source;
mod units;
mod urdf;
mod whole;
mod work_region;
mod written_lengths;

pub use columns::{ColumnMap, DataUnits, Delimiter, header_names, joint_types};
pub use conversion::{ChainEnds, Exported, Imported};
pub use data_file::{
    DataFile, DataFormat, data_headers, format_configurations, format_samples, parse_samples,
    parse_samples_from, read_samples, write_samples,
};
pub use data_rows::MAX_CONFIGURATIONS;
pub use dh::{DhConvention, TableUnits};
pub use document::{
    CouplingDocument, FrameDocument, PriorityDocument, RobotDocument, ToolDocument,
};
pub use error::{Error, line_at, toml_message};
pub use input::{is_hidden_character, open_input, read_description};
pub use interchange::{ImportOptions, RobotFormat, export_robot, import_robot, import_robot_text};
pub use join::{JoinSpec, Joined, join_tables};
pub use joint_calibration::apply_joint_calibration;
pub use named_points::{
    BasePoint, FramePoint, MAX_BASE_POINT_DISTANCE, parse_base_points, parse_frame_points,
};
pub use output::{
    OutputPolicy, remove_temporary_files, write_all_atomically, write_atomically, write_in_folder,
    write_with,
};
pub use parallel_file::{
    PARALLEL_KIND, ParallelRobotFile, format_parallel_robot_file, is_parallel_robot_text,
    parse_parallel_robot_file, read_parallel_robot_file,
};
pub use payload::{
    MAX_PAYLOAD_CENTRE, MAX_PAYLOAD_KG, PayloadSpec, Quantity, check_payload, parse_payload,
};
pub use pose::{
    parse_point, parse_pose, parse_tool_pose, pose_from_matrix, pose_from_seven, unit_quaternion,
};
pub use prior::{StandardDeviation, parse_angle, parse_override, parse_prior, parse_signed_angle};
pub use problem::{DocumentError, Location};
pub use program::{
    CorrectedProgram, ProgramBlock, ProgramFile, ProgramKind, ProgramLayout, ProgramReader,
    WrittenRow, format_program, parse_program, read_program,
};
pub use ready::{
    ReadyRobot, load_parallel_robot, load_robot, ready_parallel_robot, ready_parallel_robots,
    ready_robot, ready_robots,
};
pub use robot_file::{AngleUnit, IdentifiedTool, RobotFile, fallback_name};
pub use robot_toml::{
    format_robot_file, parse_priority_file, parse_robot_document, parse_robot_file,
    read_priority_file, read_robot_file, robot_file_text,
};
pub use rotation::RotationFormat;
pub use test_cube::parse_test_cube;
pub use units::LengthUnit;
pub use urdf::names::{
    UrdfDocument, UrdfFixedDocument, UrdfFixedLink, UrdfJointDocument, UrdfJointNames, UrdfNames,
};
pub use whole::{Content, MAPPED_MAX_BYTES, WholeFile, map_small};
pub use work_region::{parse_actuator_region, parse_work_region};
