//! `gecaro tcp`, `gecaro frame` and `gecaro join`: the owner's tool point
//! and user frames, and the instrument's files joined with the
//! controller's.

use gecaro_app::{
    DataFormatSpec, DataSource, FramePointsSource, JoinRequest, LocalFiles, RobotSource,
    ToolPointRequest, UserFrameRequest,
};

use super::options::{data_format, name, written};
use crate::cli::{FrameArgs, JoinArgs, TcpArgs};
use crate::failure::Failure;

/// Millimetres with four decimals.
fn mm(value: f64) -> String {
    format!("{:.4}", value * 1e3)
}

pub(crate) fn tcp(args: &TcpArgs) -> Result<(), Failure> {
    let mut request = ToolPointRequest::new(
        RobotSource::Named(args.robot.clone()),
        DataSource::File(name(&args.data)),
    );
    request.format = data_format(&args.format);
    let taught = request.run(&LocalFiles)?;
    let document = taught.document();
    for warning in &document.warnings {
        eprintln!("warning: {warning}");
    }
    if args.json {
        return super::output::print_json(&document);
    }
    let [x, y, z] = document.tool;
    let [px, py, pz] = document.fixed_point;
    println!(
        "tool point in frame n+1 of {}: x {} y {} z {} mm (σ {} mm per axis)",
        taught.robot,
        mm(x),
        mm(y),
        mm(z),
        mm(document.tool_sigma)
    );
    println!(
        "fixed point in the world frame: x {} y {} z {} mm (σ {} mm per axis)",
        mm(px),
        mm(py),
        mm(pz),
        mm(document.fixed_sigma)
    );
    println!(
        "{} orientations (spread {:.1}°): residual RMS {} mm, max {} mm",
        document.orientations,
        document.spread.to_degrees(),
        mm(document.rms),
        mm(document.max)
    );
    Ok(())
}

pub(crate) fn frame(args: &FrameArgs) -> Result<(), Failure> {
    let mut request = UserFrameRequest::new(FramePointsSource::File(name(&args.points)));
    request.format = data_format(&args.format);
    let frame = request.run(&LocalFiles)?;
    let document = frame.document();
    if args.json {
        return super::output::print_json(&document);
    }
    let [x, y, z] = document.position;
    let [w, i, j, k] = document.quaternion;
    let [roll, pitch, yaw] = document.rpy.map(f64::to_degrees);
    println!(
        "user frame ({}): origin x {} y {} z {} mm; quaternion (w, x, y, z) {w:.8}, {i:.8}, \
         {j:.8}, {k:.8}; rpy {roll:.4} {pitch:.4} {yaw:.4}°",
        document.way,
        mm(x),
        mm(y),
        mm(z)
    );
    if let (Some(sigma), Some(origin), Some(rotation)) = (
        document.sigma,
        document.origin_sigma,
        document.rotation_sigma,
    ) {
        println!(
            "{} points: residual σ {} mm; origin to {} mm, rotation to {:.4} mrad (1σ per axis)",
            document.residuals.len(),
            mm(sigma),
            mm(origin),
            rotation * 1e3
        );
        for (name, residual) in &document.residuals {
            println!("  {name:<12} residual {} mm", mm(*residual));
        }
    } else {
        println!(
            "three points define it exactly: no σ (give more points with frame_x, frame_y, frame_z for one)"
        );
    }
    Ok(())
}

pub(crate) fn join(args: &JoinArgs) -> Result<(), Failure> {
    let mut request = JoinRequest::new(
        RobotSource::Named(args.robot.clone()),
        DataSource::File(name(&args.tracker)),
        DataSource::File(name(&args.log)),
    );
    request.key = args.key.clone();
    request.log_key = args.log_key.clone();
    request.tracker_format = DataFormatSpec {
        length_unit: args.length_unit.clone(),
        angle_unit: args.rotation_unit.clone(),
        columns: args.tracker_columns.clone(),
        rotation: args.rotation.clone(),
        ..DataFormatSpec::default()
    };
    request.log_format = DataFormatSpec {
        angle_unit: args.angle_unit.clone(),
        length_unit: args.log_length_unit.clone(),
        columns: args.log_columns.clone(),
        ..DataFormatSpec::default()
    };
    request.output = written(&args.output, args.force);
    let joined = request.run(&LocalFiles)?;
    if let Some(note) = joined.unmeasured_note() {
        eprintln!("note: {note}");
    }
    let check = match joined.distance_rms {
        Some(rms) => format!(
            "; the distances between consecutive points match the robot's to {} mm RMS, and \
             no shift of up to {} rows matches them better",
            mm(rms),
            gecaro_app::MAX_SHIFT
        ),
        None => String::new(),
    };
    println!(
        "wrote {}: {} configurations with their measured {}{check}",
        args.output.display(),
        joined.joined.points.len(),
        if joined.joined.orientations {
            "poses"
        } else {
            "points"
        }
    );
    Ok(())
}
