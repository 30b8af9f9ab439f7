//! `gecaro identifiable` and `gecaro table2` (Appendix III, Table 2).

use gecaro_app::{IdentifiableRequest, LocalFiles, PrioritySource};
use gecaro_calib::identifiability::{Excitation, ParameterStatus, RankReport};
use gecaro_calib::table2::{
    TABLE2_COLUMNS, TABLE2_PLANE_NORMAL, default_plane, table2 as table2_reports,
};
use gecaro_core::{ParameterId, ParameterKind, Robot};
use gecaro_io::load_robot;
use serde::Serialize;

use super::options::{measurements, plane, print_notes, vector3};
use super::progress::with_steps;
use crate::cli::{IdentifiableArgs, Table2Args};
use crate::failure::Failure;
use crate::format::{number, table};

pub(crate) fn identifiable(args: &IdentifiableArgs) -> Result<(), Failure> {
    let mut request = IdentifiableRequest::new(measurements(&args.source, args.data.as_deref())?);
    request.priority = args
        .priority
        .as_deref()
        .map(|path| PrioritySource::File(path.display().to_string()));
    request.count = args.count;
    request.seed = Some(args.seed);
    request.model = args.model.clone();
    let outcome = with_steps("drawing configurations", |observer| {
        request.run(&LocalFiles, observer)
    })?;
    print_notes(&outcome.loaded.notes);
    let (robot, analysis) = (&outcome.loaded.robot.robot, &outcome.analysis);
    if args.json {
        return super::output::print_json(&outcome.document());
    }
    print_report(robot, &analysis.report, &analysis.source);
    match &analysis.excitation {
        Some(excitation) => {
            print_excitation(excitation);
            println!(
                "{}",
                crate::format::observability(&excitation.report.observability(), "the data")
            );
        }
        None => println!(
            "{}",
            crate::format::observability(
                &analysis.report.observability(),
                "these random configurations"
            )
        ),
    }
    for warning in analysis.report.set_up_warnings(robot) {
        println!("warning: {warning}");
    }
    Ok(())
}

fn print_excitation(excitation: &Excitation) {
    let condition = number(excitation.report.condition_number(), 1);
    if excitation.not_excited.is_empty() {
        println!(
            "Excitation: the data excite every identifiable parameter; condition number of their W_b: {condition}."
        );
    } else {
        println!(
            "Excitation: the data do NOT excite {} (condition number of W_b on the data: {condition}); \
             they would stay at their nominal values.",
            excitation.not_excited.join(", "),
        );
    }
}

/// The status cell of one parameter in the frame × kind grid.
fn cell(report: &RankReport, id: ParameterId) -> String {
    report
        .parameters
        .iter()
        .find(|p| p.parameter == Some(id))
        .map_or_else(String::new, |p| match p.status {
            ParameterStatus::Identifiable => "id".to_owned(),
            other => other.symbol().to_owned(),
        })
}

fn print_report(robot: &Robot, report: &RankReport, source: &str) {
    println!(
        "Identifiable parameters — {}, {} method, {source}",
        robot.name(),
        report.method
    );
    let auxiliary_kept = report.base_auxiliary.len();
    println!(
        "{} identifiable of {} parameters{}; {} equations; condition number of W_b: {}",
        report.count(),
        report.parameters.len(),
        if report.auxiliary.is_empty() {
            String::new()
        } else {
            format!(
                " (+{auxiliary_kept} auxiliary of {})",
                report.auxiliary.len()
            )
        },
        report.equations,
        number(report.condition_number(), 2)
    );
    println!(
        "id = identifiable, n = regrouped on others, 0 = no effect, - = excluded (priority 0)"
    );
    // An elastic robot's compliances: a seventh column (joints 1..n).
    let elastic = robot.is_elastic();
    let headings: &[&str] = if elastic {
        &["j", "α", "d", "θ", "r", "β", "K", "c"]
    } else {
        &["j", "α", "d", "θ", "r", "β", "K"]
    };
    let compliance = ParameterKind::Compliance;
    let mut grid = table(headings, 1);
    for frame in 0..robot.frames().len() {
        let mut row = vec![frame.to_string()];
        row.extend(ParameterKind::ALL.map(|kind| cell(report, ParameterId::new(kind, frame))));
        if elastic {
            row.push(cell(report, ParameterId::new(compliance, frame)));
        }
        grid.add_row(row);
    }
    println!("{grid}");
    // Gravity's tilts (elastic-gravity): two parameters beside the grid.
    let tilts: Vec<String> = (1..=2)
        .map(|axis| ParameterId::new(ParameterKind::GravityTilt, axis))
        .filter_map(|id| {
            let p = report.parameters.iter().find(|p| p.parameter == Some(id))?;
            (p.status != ParameterStatus::Excluded).then(|| format!("{id} {}", p.status.as_str()))
        })
        .collect();
    if !tilts.is_empty() {
        println!("gravity's tilts: {}", tilts.join(", "));
    }
    for auxiliary in &report.auxiliary {
        println!(
            "auxiliary {}: {}",
            auxiliary.name,
            auxiliary.status.as_str()
        );
    }
    if !report.relations().is_empty() {
        println!("Regrouping relations (what each base parameter identifies, eq. 32):");
        for relation in report.relations() {
            let terms: Vec<String> = relation
                .absorbed
                .iter()
                .map(|(name, coefficient)| {
                    let sign = if *coefficient < 0.0 { "−" } else { "+" };
                    format!("{sign} {}·{name}", number(coefficient.abs(), 6))
                })
                .collect();
            println!("  {0}_b = {0} {1}", relation.base, terms.join(" "));
        }
    }
    println!(
        "Numerical zero τ = {:.1e}; smallest kept |R_ii| = {:.3e}, largest rejected = {:.1e}; \
         relations hold to {:.1e}",
        report.tolerance,
        report.smallest_kept,
        report.largest_rejected,
        report.relation_residual()
    );
    println!("New priority matrix (non-identifiable set to 0):");
    let mut priority = table(headings, 1);
    for (j, row) in report.priority.rows().iter().enumerate() {
        let mut cells = vec![j.to_string()];
        cells.extend(row.iter().map(ToString::to_string));
        if elastic {
            cells.push(
                report
                    .priority
                    .get(ParameterId::new(compliance, j))
                    .to_string(),
            );
        }
        priority.add_row(cells);
    }
    println!("{priority}");
}

#[derive(Serialize)]
struct Table2Json {
    robot: String,
    plane_normal: [f64; 3],
    plane_point: [f64; 3],
    columns: Vec<&'static str>,
    totals: Vec<usize>,
    parameters: Vec<Table2Row>,
}

#[derive(Serialize)]
struct Table2Row {
    name: String,
    statuses: Vec<&'static str>,
}

pub(crate) fn table2(args: &Table2Args) -> Result<(), Failure> {
    let robot = load_robot(&args.robot)?.robot;
    let normal = match &args.plane_normal {
        Some(values) => values.clone(),
        None => TABLE2_PLANE_NORMAL.to_vec(),
    };
    let plane = match &args.plane_point {
        Some(point) => plane(Some(&normal), Some(point))?.expect("both given"),
        None => {
            let middle = default_plane(&robot)?;
            gecaro_calib::methods::Plane::new(vector3(&normal, "--plane-normal")?, middle.point())?
        }
    };
    let reports = table2_reports(&robot, plane, &robot.priority(), args.seed)?;
    let totals: Vec<usize> = reports.iter().map(RankReport::count).collect();
    if args.json {
        return super::output::print_json(&Table2Json {
            robot: robot.name().to_owned(),
            plane_normal: plane.normal().into(),
            plane_point: plane.point().into(),
            columns: TABLE2_COLUMNS.iter().map(|c| c.heading).collect(),
            totals,
            parameters: robot
                .parameters()
                .ids()
                .iter()
                .enumerate()
                .map(|(index, id)| Table2Row {
                    name: id.to_string(),
                    statuses: reports
                        .iter()
                        .map(|r| r.parameters[index].status.as_str())
                        .collect(),
                })
                .collect(),
        });
    }
    println!(
        "Table 2 — identifiable parameters of {} ({} joints, {})",
        robot.name(),
        robot.joint_count(),
        robot.joint_letters()
    );
    println!(
        "blank = identifiable, n = regrouped, 0 = no effect; plane methods use the plane of normal ({}) through ({})",
        crate::format::list(plane.normal().as_slice()),
        crate::format::list(plane.point().as_slice())
    );
    let mut headers = vec!["parameter"];
    headers.extend(TABLE2_COLUMNS.iter().map(|c| c.heading));
    let mut grid = table(&headers, 1);
    for (index, id) in robot.parameters().ids().iter().enumerate() {
        let mut row = vec![id.to_string()];
        row.extend(
            reports
                .iter()
                .map(|r| r.parameters[index].status.symbol().to_owned()),
        );
        grid.add_row(row);
    }
    let mut total = vec!["Total".to_owned()];
    total.extend(totals.iter().map(ToString::to_string));
    grid.add_row(total);
    println!("{grid}");
    Ok(())
}
