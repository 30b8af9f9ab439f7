//! `gecaro iso9283 plan` and `gecaro iso9283 evaluate`: ISO 9283's
//! acceptance test planned and evaluated (the jobs are gecaro-app's).

use gecaro_report::four_decimals;

use gecaro_app::{
    Iso9283EvaluateRequest, Iso9283PlanRequest, LocalFiles, MeasuredTestJson, ProgramSource,
    RobotSource, TestConditions,
};

use super::options::{cell_spec, data_format, name, written};
use crate::cli::{Iso9283Command, Iso9283EvaluateArgs, Iso9283PlanArgs};
use crate::failure::Failure;

pub(crate) fn run(command: &Iso9283Command) -> Result<(), Failure> {
    match command {
        Iso9283Command::Plan(args) => plan(args),
        Iso9283Command::Evaluate(args) => evaluate(args),
    }
}

/// Millimetres with four decimals.
fn mm(value: f64) -> String {
    four_decimals(value * 1e3)
}

fn plan(args: &Iso9283PlanArgs) -> Result<(), Failure> {
    let mut request = Iso9283PlanRequest::new(RobotSource::Named(args.robot.clone()));
    request.cube = args.cube.clone();
    request.cycles = Some(args.cycles);
    request.directions = Some(args.directions);
    request.cell = cell_spec(&args.cell)?;
    request.format = data_format(&args.format);
    request.output = written(&args.output, args.force);
    let planned = request.run(&LocalFiles)?;
    let document = planned.document();
    if args.json {
        return super::output::print_json(&document);
    }
    let [x, y, z] = document.centre;
    println!(
        "test cube for {}: centre x {} y {} z {} mm, side {} mm ({})",
        document.robot,
        mm(x),
        mm(y),
        mm(z),
        mm(document.side),
        if document.searched {
            "the largest found inside the working space"
        } else {
            "as stated"
        }
    );
    for pose in &document.poses {
        let [x, y, z] = pose.position;
        println!("  P{}: x {} y {} z {} mm", pose.pose, mm(x), mm(y), mm(z));
    }
    if !document.orientation_held {
        println!(
            "  the robot has fewer than 6 joints: positions are commanded, the orientation is \
             the model's"
        );
    }
    println!(
        "{} cycles, {} direction(s): {} rows, {} measured → {}",
        document.cycles,
        document.directions,
        document.rows,
        document.measured_rows,
        args.output.display()
    );
    Ok(())
}

/// The text of one measured file's results.
fn print_measured(before: &MeasuredTestJson, after: Option<&MeasuredTestJson>) {
    let value = |map: &serde_json::Map<String, serde_json::Value>, key: &str| {
        map.get(key).and_then(serde_json::Value::as_f64)
    };
    let both = |get: &dyn Fn(&MeasuredTestJson, usize) -> Option<f64>, index: usize| match after {
        Some(after) => format!(
            "{} → {}",
            get(before, index).map_or("–".into(), mm),
            get(after, index).map_or("–".into(), mm)
        ),
        None => get(before, index).map_or("–".into(), mm),
    };
    println!(
        "pose  AP_P (mm){}  RP_l (mm){}",
        if after.is_some() {
            " before → after"
        } else {
            ""
        },
        if after.is_some() {
            " before → after"
        } else {
            ""
        }
    );
    for (index, pose) in before.poses.iter().enumerate() {
        let ap = both(
            &|m, i| m.poses.get(i).and_then(|p| value(&p.ap, "p")),
            index,
        );
        let rp = both(
            &|m, i| m.poses.get(i).and_then(|p| value(&p.rp, "l")),
            index,
        );
        let mut line = format!("P{}    {ap}    {rp}", pose.pose);
        if before.oriented {
            let degrees = |key: &str, map: &serde_json::Map<String, serde_json::Value>| {
                value(map, key).map_or("–".into(), |v| four_decimals(v.to_degrees()))
            };
            line.push_str(&format!(
                "    AP_a,b,c {} {} {}°  RP_a,b,c ±{} ±{} ±{}°",
                degrees("a", &pose.ap),
                degrees("b", &pose.ap),
                degrees("c", &pose.ap),
                degrees("a", &pose.rp),
                degrees("b", &pose.rp),
                degrees("c", &pose.rp)
            ));
        }
        if let Some(vap) = &pose.vap {
            line.push_str(&format!(
                "    vAP_P {} mm",
                value(vap, "p").map_or("–".into(), mm)
            ));
        }
        println!("{line}  ({} cycles)", pose.cycles);
    }
    if let Some(distance) = &before.distance {
        let get = |key: &str| value(distance, key).map_or("–".into(), mm);
        println!(
            "distance P2–P4: commanded {} mm, AD {} mm, RD ±{} mm",
            get("commanded"),
            get("ad"),
            get("rd")
        );
    }
}

fn evaluate(args: &Iso9283EvaluateArgs) -> Result<(), Failure> {
    let mut request = Iso9283EvaluateRequest::new(
        ProgramSource::File(name(&args.program)),
        ProgramSource::File(name(&args.data)),
    );
    request.robot = args.robot.clone().map(RobotSource::Named);
    request.after = args
        .after
        .as_deref()
        .map(|path| ProgramSource::File(name(path)));
    request.format = data_format(&args.format);
    request.frame = args.frame.clone();
    request.conditions = TestConditions {
        load: args.load.clone(),
        speed: args.speed.clone(),
        warm_up: args.warm_up.clone(),
        instrument: args.instrument.clone(),
        uncertainty: args.uncertainty.clone(),
    };
    if let Some(path) = &args.output {
        request.output = written(path, args.force);
    }
    let evaluated = request.run(&LocalFiles)?;
    let document = evaluated.document();
    for warning in &document.warnings {
        eprintln!("warning: {warning}");
    }
    if args.json {
        return super::output::print_json(&document);
    }
    let before = &document.before;
    println!(
        "ISO 9283 test of {}{}: {}{}; measurement frame: {}",
        document.program,
        document
            .robot
            .as_ref()
            .map_or(String::new(), |robot| format!(" ({robot})")),
        before.data,
        document
            .after
            .as_ref()
            .map_or(String::new(), |after| format!(
                " before, {} after",
                after.data
            )),
        match before.registration {
            "base" => "the robot's base frame",
            "stated" => "stated",
            _ => "registered by a best fit of the barycentres",
        }
    );
    print_measured(before, document.after.as_ref());
    let conditions = &document.conditions;
    let stated = |value: &Option<String>| value.clone().unwrap_or_else(|| "not stated".into());
    println!(
        "conditions: load {}, speed {}, warm-up {}, instrument {} (uncertainty {})",
        stated(&conditions.load),
        stated(&conditions.speed),
        stated(&conditions.warm_up),
        stated(&conditions.instrument),
        stated(&conditions.uncertainty)
    );
    if let Some(path) = &evaluated.saved_report {
        println!("report → {}", path.display());
    }
    Ok(())
}
