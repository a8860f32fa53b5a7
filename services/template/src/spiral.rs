//! The spiral face milling family's programs (docs/spiral.md): the model's
//! spiral and cut written in the form the job or machine chose
//! (`fanuc-macro`, `fanuc-arcs`, `fanuc-chords`, `linuxcnc`) by
//! [`gearcam_spiral`]'s generators, with a header naming the job, the part,
//! the order, the tool, the spiral and its checks; then replayed and compared
//! with the model ([`gearcam_spiral::verify`]) before it may leave.

use gearcam_proto::naming;
use gearcam_proto::Code;
use gearcam_proto::{
    utc_text, CutMode, JobError, NcProgram, SpiralModel, SpiralPart, SpiralProgram, Stage,
    TemplateRef,
};
use gearcam_spiral::linuxcnc::Cut;
use gearcam_spiral::verify::{spiral_of, verify};
use sha2::{Digest, Sha256};

use crate::render::GENERATOR;

pub use crate::forms::SPIRAL_FORMS_VERSION;

/// The header lines of a spiral program.
fn header(model: &SpiralModel) -> Vec<String> {
    let plan = &model.plan;
    let job = &plan.request.spec.job;
    let s = &model.spiral;
    let t = &plan.tool;
    let part = match &plan.part {
        SpiralPart::Face(f) => format!(
            "FACE RO {} RI {} DEPTH {} MM",
            f.outer_radius_mm, f.inner_radius_mm, f.depth_mm
        ),
        SpiralPart::Groove(g) => format!(
            "PLANAR SPIRAL GROOVE R {} PITCH {} TURNS {} WIDTH {} DEPTH {} MM",
            g.outer_radius_mm, g.pitch_mm, g.turns, g.width_mm, g.depth_mm
        ),
    };
    let cases = if plan.cases.is_empty() {
        "NONE".to_string()
    } else {
        plan.cases
            .iter()
            .map(|c| c.id.as_str())
            .collect::<Vec<_>>()
            .join(" ")
    };
    vec![
        format!("JOB {} PART {}", plan.job_id, job.part_number),
        format!(
            "ORDER QTY={} MATERIAL {}",
            job.quantity,
            plan.part.material()
        ),
        format!(
            "SUBMITTED {} BY {}",
            utc_text(plan.request.submitted_at_ms),
            plan.request.submitted_by
        ),
        format!("MACHINE {} {}", plan.machine.id, plan.machine.controller),
        part,
        format!(
            "TOOL {} {} D{} CORNER R{} Z{}",
            t.id,
            t.kind.as_str(),
            2.0 * t.radius_mm,
            t.corner_radius_mm,
            t.flutes
        ),
        format!(
            "SPIRAL R1 {:.4} R2 {:.4} TURNS {} STEP {:.4} SENSE {} {}",
            s.start_radius_mm,
            s.end_radius_mm,
            s.turns,
            s.step_over_mm,
            if s.sense > 0 { "CCW" } else { "CW" },
            match plan.process.cut_mode {
                CutMode::Climb => "CLIMB",
                CutMode::Conventional => "CONVENTIONAL",
            }
        ),
        format!(
            "COVERAGE {} MAX GAP {:.4} MM MAX DEVIATION {:.4} MM TOLERANCE {} MM",
            if model.coverage.ok { "OK" } else { "FAILED" },
            model.coverage.max_gap_mm,
            model.coverage.max_deviation_mm,
            model.cut.tolerance_mm
        ),
        format!(
            "ORIGIN FACE CENTRE {} Z0 ON THE FACE",
            plan.machine.work_offset
        ),
        format!("CASES {cases} CONFIDENCE {:.2}", plan.confidence),
        format!("{} {}", model.model_version, GENERATOR),
    ]
}

/// Writes the program of a spiral model and replays it against the model
/// (the path check is attached whatever it found).
pub fn instantiate(model: &SpiralModel) -> Result<NcProgram, Vec<JobError>> {
    let plan = &model.plan;
    let form = plan.process.program;
    let dialect = form.dialect();
    if dialect != plan.machine.dialect {
        return Err(vec![Stage::Template.error(
            Code::PROGRAM_FORM,
            "milling.program",
            format!("a {} form", plan.machine.dialect.as_str()),
            form.as_str().to_string(),
            format!(
                "{} runs {} programs",
                plan.machine.id,
                plan.machine.dialect.as_str()
            ),
        )]);
    }
    let (name, _file) = naming::program_name(dialect, &model.plan.request.spec.job, false)
        .map_err(|p| vec![p.error(Stage::Template, dialect)])?;
    let spiral = spiral_of(model);
    let cut = Cut {
        depth_mm: model.cut.depth_mm,
        passes: model.cut.passes,
        feed_mm_min: round(model.cut.feed_mm_min),
        plunge_feed_mm_min: round(model.cut.plunge_feed_mm_min),
        spindle_rpm: model.cut.spindle_rpm.round(),
        safe_z_mm: model.cut.safe_z_mm,
        tolerance_mm: model.cut.tolerance_mm,
    };
    let lines = header(model);
    let number = || {
        name.trim_start_matches('O')
            .parse::<u32>()
            .expect("a FANUC name is O and four digits (checked)")
    };
    let text = match form {
        SpiralProgram::FanucMacro => {
            gearcam_spiral::fanuc::macro_program(&spiral, &cut, number(), &lines)
        }
        SpiralProgram::FanucArcs => {
            gearcam_spiral::fanuc::arc_program(&spiral, &cut, number(), &lines)
        }
        SpiralProgram::FanucChords => {
            gearcam_spiral::fanuc::chord_program(&spiral, &cut, number(), &lines)
        }
        SpiralProgram::Linuxcnc => gearcam_spiral::linuxcnc::program(&spiral, &cut, &lines),
    };
    let (path_check, _) = verify(&text, form, model);
    let sha256 = hex::encode(Sha256::digest(text.as_bytes()));
    Ok(NcProgram {
        job_id: model.job_id.clone(),
        machine: plan.machine.id.clone(),
        name,
        revision: 1,
        dialect,
        text,
        sha256,
        template: TemplateRef {
            id: crate::forms::spiral_id(form),
            version: SPIRAL_FORMS_VERSION,
        },
        part_number: plan.request.spec.job.part_number.clone(),
        cases: plan.cases.iter().map(|c| c.id.clone()).collect(),
        model_version: model.model_version.clone(),
        generator: GENERATOR.to_string(),
        path_check,
        form: Some(form),
        simulation: None,
    })
}

/// Feeds to 0.1 mm/min as printed.
fn round(v: f64) -> f64 {
    (v * 10.0).round() / 10.0
}

/// [`instantiate`], returning the program only when its replay matches the
/// model (one `PATH_CHECK_FAILED` per finding otherwise).
pub fn render(model: &SpiralModel) -> Result<NcProgram, Vec<JobError>> {
    let program = instantiate(model)?;
    if program.path_check.ok {
        return Ok(program);
    }
    Err(crate::render::path_check_errors(&program))
}

#[cfg(test)]
mod tests {
    use super::*;
    use gearcam_proto::{JobId, JobRequest, JobSpec};
    use serde_json::{json, Value};

    fn model(machine: &str, part: Value, milling: Value) -> SpiralModel {
        let mut v = json!({
            "job": {"family": "spiral-face", "machine": machine, "part_number": "FL-3010"},
            "milling": milling,
        });
        v.as_object_mut()
            .unwrap()
            .extend(part.as_object().unwrap().clone());
        let spec: JobSpec = serde_json::from_value(v).unwrap();
        let req = JobRequest {
            job_id: JobId::new("J-T1").unwrap(),
            submitted_at_ms: 1_700_000_000_000,
            submitted_by: "test".into(),
            spec,
        };
        let conn = gearcam_knowledge::db::open_in_memory().unwrap();
        let plan = gearcam_knowledge::spiral::plan_spiral(&conn, &req).unwrap();
        gearcam_model::spiral::compute_spiral(&plan).unwrap()
    }

    fn annulus() -> Value {
        json!({"face": {"outer_radius_mm": 80.0, "inner_radius_mm": 15.0, "depth_mm": 2.0,
                        "material": "C45"},
               "mill": {"id": "EM-16"}})
    }

    /// Every form of a face and a groove replays onto its model, under the
    /// controller's naming; the header names the job, the order and the
    /// checks.
    #[test]
    fn every_form_replays_onto_its_model() {
        let groove = json!({"groove": {"outer_radius_mm": 60.0, "pitch_mm": 16.0, "turns": 3,
                                        "depth_mm": 4.0, "width_mm": 10.0, "material": "C45"}});
        for (machine, part, form, name) in [
            ("M01", annulus(), "fanuc-macro", "O3010"),
            ("M01", annulus(), "fanuc-arcs", "O3010"),
            ("M01", annulus(), "fanuc-chords", "O3010"),
            ("M02", annulus(), "linuxcnc", "FL-3010"),
            ("M01", groove.clone(), "fanuc-macro", "O3010"),
            ("M02", groove.clone(), "linuxcnc", "FL-3010"),
        ] {
            let m = model(machine, part, json!({"program": form, "passes": 2}));
            let p = render(&m).unwrap_or_else(|e| panic!("{form}: {e:?}"));
            assert_eq!((p.name.as_str(), p.form.unwrap().as_str()), (name, form));
            assert!(p.text.contains("ORDER QTY=1 MATERIAL C45"), "{form}");
            assert!(p.text.contains("COVERAGE OK"), "{form}");
            let (_, replayed) = verify(&p.text, m.plan.process.program, &m);
            let r = replayed.unwrap();
            assert_eq!(
                (r.passes, r.blocks),
                (2, m.spiral.blocks as usize),
                "{form}"
            );
            assert!(
                r.max_deviation_mm <= m.cut.tolerance_mm * 1.01 + 2e-4,
                "{form}: {r:?}"
            );
        }
    }

    /// The verification catches what it is for: a flipped sense, a start
    /// radius off by a millimetre, a wrong arc centre and a dropped depth
    /// pass are each refused before delivery.
    #[test]
    fn the_replay_refuses_a_program_that_is_not_its_model() {
        let m = model(
            "M01",
            annulus(),
            json!({"program": "fanuc-macro", "passes": 2}),
        );
        let good = instantiate(&m).unwrap().text;
        let check = |text: &str, form: SpiralProgram, m: &SpiralModel| verify(text, form, m).0;
        assert!(check(&good, SpiralProgram::FanucMacro, &m).ok);
        for (from, to, rule) in [
            // Whole turns end where they would have: only the path shows it.
            ("#6=-1.0", "#6=1.0", "SPIRAL_DEVIATION"),
            ("#8=2.0", "#8=1.0", "PASS_DEPTHS"),
        ] {
            assert!(good.contains(from), "{from}");
            let bad = good.replace(from, to);
            let c = check(&bad, SpiralProgram::FanucMacro, &m);
            assert!(
                c.findings.iter().any(|f| f.rule == rule),
                "{from}: {:?}",
                c.findings
            );
        }
        // R1 one millimetre further out.
        let bad = good.replacen("\n#1=", "\n#1=1+", 1);
        assert_ne!(bad, good);
        assert!(!check(&bad, SpiralProgram::FanucMacro, &m).ok);

        let m = model(
            "M01",
            annulus(),
            json!({"program": "fanuc-arcs", "passes": 1}),
        );
        let good = instantiate(&m).unwrap().text;
        assert!(check(&good, SpiralProgram::FanucArcs, &m).ok);
        // The 20th arc's J moved by 0.05 mm: its centre, so its path, is wrong.
        let lines: Vec<String> = good.lines().map(str::to_string).collect();
        let k = lines
            .iter()
            .enumerate()
            .filter(|(_, l)| l.starts_with("G02") || l.starts_with("G03"))
            .nth(20)
            .unwrap()
            .0;
        let mut bad_lines = lines.clone();
        let j_at = bad_lines[k].find(" J").unwrap();
        let (head, tail) = bad_lines[k].split_at(j_at + 2);
        let end = tail.find(' ').unwrap_or(tail.len());
        let j: f64 = tail[..end].parse().unwrap();
        bad_lines[k] = format!("{head}{:.4}{}", j + 0.05, &tail[end..]);
        let c = check(&(bad_lines.join("\n") + "\n"), SpiralProgram::FanucArcs, &m);
        assert!(
            c.findings.iter().any(|f| f.rule == "SPIRAL_DEVIATION"),
            "{:?}",
            c.findings
        );

        let m = model("M02", annulus(), json!({"passes": 1}));
        let good = instantiate(&m).unwrap().text;
        assert!(check(&good, SpiralProgram::Linuxcnc, &m).ok);
        let bad = good.replace("#<r2> - #<r1>", "#<r2> - #<r1> * 1.001");
        assert!(!check(&bad, SpiralProgram::Linuxcnc, &m).ok);
        // The retract after the pass dropped: the program ends in the cut.
        let bad = good.replace("  G0 Z[#<safe>]\n  #<pass>", "  #<pass>");
        assert_ne!(bad, good);
        let c = check(&bad, SpiralProgram::Linuxcnc, &m);
        assert!(
            c.findings.iter().any(|f| f.rule == "NO_RETRACT"),
            "{:?}",
            c.findings
        );
    }

    /// Every block counts, not only the passes: the retract between two
    /// passes dropped (the next pass's rapid then crosses the face at
    /// depth), the first retract dropped (the tool moves in X/Y before it is
    /// known to be up), and the plunge moved into the face's material are
    /// each refused; the final retract is `NO_RETRACT` above.
    #[test]
    fn every_block_is_checked_approach_plunges_and_retracts_between_passes() {
        let m = model(
            "M01",
            annulus(),
            json!({"program": "fanuc-macro", "passes": 2}),
        );
        let good = instantiate(&m).unwrap().text;
        let check = |text: &str| verify(text, SpiralProgram::FanucMacro, &m).0;
        assert!(check(&good).ok);
        let rules = |text: &str| -> Vec<Code> {
            check(text).findings.into_iter().map(|f| f.rule).collect()
        };
        // The retract inside the pass loop, before the pass counter.
        let between = "G15\nG00 Z#17\n#30=#30+1";
        assert!(good.contains(between));
        let bad = good.replace(between, "G15\n#30=#30+1");
        assert!(
            rules(&bad).contains(&Code::RAPID_IN_MATERIAL),
            "{:?}",
            rules(&bad)
        );
        // The retract made a rapid that also moves sideways out of the cut:
        // it ends above the face, but drags the tool through the material.
        let diagonal = good.replace(between, "G15\nG00 X0 Y0 Z#17\n#30=#30+1");
        assert!(
            rules(&diagonal).contains(&Code::RAPID_IN_MATERIAL),
            "{:?}",
            rules(&diagonal)
        );
        // The first retract, before the first move in X/Y.
        let first = "S#11 M03\nG00 Z#17\n";
        assert!(good.contains(first));
        let bad = good.replacen(first, "S#11 M03\n", 1);
        assert!(
            rules(&bad).contains(&Code::UNSAFE_APPROACH),
            "{:?}",
            rules(&bad)
        );
        // The plunge at the outer edge of the face, not clear of it: R1
        // replaced by the face's outer radius.
        let bad = good.replacen("\n#1=", "\n#1=-8.0+", 1);
        assert!(
            rules(&bad).contains(&Code::PLUNGE_IN_MATERIAL),
            "{:?}",
            rules(&bad)
        );
    }
}
