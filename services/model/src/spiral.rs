//! The spiral face milling family's model (docs/spiral.md): from a
//! [`SpiralPlan`] the tool-centre spiral ([`gearcam_spiral::plan`] or
//! [`gearcam_spiral::groove::plan_groove`]), its sense from climb or
//! conventional milling, speeds and feeds against the machine, chords and
//! tangent arcs within the tolerance with their deviation measured
//! independently, and the coverage check of a face or the pitch check of a
//! groove. Every failure is a typed error on the job file's field.

use gearcam_proto::{
    CoverageCheck, CutMode, GrooveFigures, JobError, SpiralCut, SpiralDirection, SpiralFigures,
    SpiralModel, SpiralPart, SpiralPlan, SpiralProgram, Stage, Warning,
};
use gearcam_spiral::{arcs, Direction, Region, Spiral, SpiralSpec};

use crate::MODEL_VERSION;

/// The plunge feed as a share of the feed along the spiral (a documented
/// default: the tool enters the cut axially, with the centre cutting).
pub const PLUNGE_SHARE: f64 = 0.25;

/// Points sampled along the spiral for the arcs' deviation.
const ARC_SAMPLES: usize = 20_000;

/// The sense of rotation (seen from +Z) that gives climb or conventional
/// milling with the spindle turning clockwise (`M03`).
///
/// With a clockwise spindle the cutting edge on the tool's right-hand side
/// (looking along the feed) moves against the feed, so the tooth enters the
/// material at full chip thickness: climb milling has the uncut material on
/// the right. Outside-in, the uncut material is towards the centre, which is
/// on the right when the spiral runs clockwise (sense −1); inside-out it is
/// outwards, on the right when it runs counter-clockwise (+1).
pub fn sense(direction: SpiralDirection, cut_mode: CutMode) -> i8 {
    match (direction, cut_mode) {
        (SpiralDirection::OutsideIn, CutMode::Climb) => -1,
        (SpiralDirection::OutsideIn, CutMode::Conventional) => 1,
        (SpiralDirection::InsideOut, CutMode::Climb) => 1,
        (SpiralDirection::InsideOut, CutMode::Conventional) => -1,
    }
}

fn machine_error(field: &str, expected: String, got: String, message: String) -> JobError {
    Stage::Model.error("MACHINE_RANGE", field, expected, got, message)
}

/// The spiral of the plan's face or groove (sense set), and the groove's figures.
fn spiral_of(plan: &SpiralPlan) -> Result<(Spiral, Option<GrooveFigures>), Vec<JobError>> {
    let p = &plan.process;
    let rt = plan.tool.radius_mm;
    let (mut spiral, groove) = match &plan.part {
        SpiralPart::Face(f) => {
            let spec = SpiralSpec {
                region: Region {
                    outer_radius_mm: f.outer_radius_mm,
                    inner_radius_mm: f.inner_radius_mm,
                },
                tool_radius_mm: rt,
                step_over_mm: p.step_over_mm.value,
                outer_overtravel_mm: p.outer_overtravel_mm.value,
                inner_overtravel_mm: p.inner_overtravel_mm.value,
                start_angle_deg: p.start_angle_deg.value,
                direction: match p.direction {
                    SpiralDirection::OutsideIn => Direction::OutsideIn,
                    SpiralDirection::InsideOut => Direction::InsideOut,
                },
            };
            (gearcam_spiral::plan(&spec)?, None)
        }
        SpiralPart::Groove(g) => {
            if (g.width_mm - 2.0 * rt).abs() > 1e-3 {
                return Err(vec![Stage::Model.error(
                    "GROOVE_RANGE",
                    "groove.width_mm",
                    format!("the tool's diameter, {} mm (tool {})", 2.0 * rt, plan.tool.id),
                    format!("{}", g.width_mm),
                    "the groove is cut in one pass of the tool's full width: choose a tool whose diameter is the groove's width",
                )]);
            }
            let planned = gearcam_spiral::groove::plan_groove(&gearcam_spiral::groove::GrooveSpec {
                outer_radius_mm: g.outer_radius_mm,
                pitch_mm: g.pitch_mm,
                turns: g.turns,
                tool_radius_mm: rt,
                start_angle_deg: p.start_angle_deg.value,
            })?;
            let mut s = planned.spiral;
            if p.direction == SpiralDirection::InsideOut {
                std::mem::swap(&mut s.start_radius_mm, &mut s.end_radius_mm);
            }
            (
                s,
                Some(GrooveFigures {
                    width_mm: planned.width_mm,
                    pitch_mm: g.pitch_mm,
                    land_mm: planned.land_mm,
                }),
            )
        }
    };
    spiral.sense = sense(p.direction, p.cut_mode);
    Ok((spiral, groove))
}

/// The measured pitch error of a groove's chord path, mm: along 72 rays the
/// radial distance between neighbouring turns, against the pitch (the path
/// is seen only through its points).
fn pitch_error(points: &[(f64, f64)], pitch_mm: f64) -> f64 {
    let mut worst: f64 = 0.0;
    for k in 0..72 {
        let a = std::f64::consts::TAU * f64::from(k) / 72.0;
        let (c, s) = (a.cos(), a.sin());
        // Where the polyline crosses the ray at angle a (x·s − y·c = 0, ahead).
        let mut radii: Vec<f64> = points
            .windows(2)
            .filter_map(|w| {
                let f0 = w[0].0 * s - w[0].1 * c;
                let f1 = w[1].0 * s - w[1].1 * c;
                if (f0 > 0.0) == (f1 > 0.0) || f0 == f1 {
                    return None;
                }
                let t = f0 / (f0 - f1);
                let (x, y) = (
                    w[0].0 + t * (w[1].0 - w[0].0),
                    w[0].1 + t * (w[1].1 - w[0].1),
                );
                (x * c + y * s > 0.0).then(|| (x * x + y * y).sqrt())
            })
            .collect();
        radii.sort_by(f64::total_cmp);
        for w in radii.windows(2) {
            worst = worst.max(((w[1] - w[0]) - pitch_mm).abs());
        }
    }
    worst
}

/// Validates a spiral plan and computes its model.
pub fn compute_spiral(plan: &SpiralPlan) -> Result<SpiralModel, Vec<JobError>> {
    let p = &plan.process;
    let m = &plan.machine;
    let rt = plan.tool.radius_mm;
    let mut errors = Vec::new();
    if !m.programs.contains(&p.program) {
        errors.push(Stage::Model.error(
            "PROGRAM_FORM",
            "milling.program",
            format!(
                "a form {} runs: {}",
                m.id,
                m.programs
                    .iter()
                    .map(|f| f.as_str())
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
            p.program.as_str(),
            format!("{} is a {} control", m.id, m.controller),
        ));
    }
    if p.passes == 0 {
        errors.push(Stage::Model.error(
            "SPIRAL_RANGE",
            "milling.passes",
            "1 or more depth passes",
            "0",
            "the depth is cut in equal passes",
        ));
    }
    let depth = plan.part.depth_mm();
    if !(depth.is_finite() && depth > 0.0) {
        errors.push(Stage::Model.error(
            "SPIRAL_RANGE",
            &format!("{}.depth_mm", plan.part.kind()),
            "a depth > 0 mm",
            format!("{depth}"),
            "the depth to cut below the face",
        ));
    }
    let tol = p.tolerance_mm.value;
    if !(tol.is_finite() && tol > 0.0 && tol <= 0.1) {
        errors.push(Stage::Model.error(
            "SPIRAL_RANGE",
            "milling.tolerance_mm",
            "a tolerance in (0, 0.1] mm",
            format!("{tol}"),
            "the chords and arcs stay this close to the spiral",
        ));
    }
    let (spiral, groove) = match spiral_of(plan) {
        Ok(s) => s,
        Err(mut e) => {
            errors.append(&mut e);
            return Err(errors);
        }
    };
    if !errors.is_empty() {
        return Err(errors);
    }
    let reach = spiral.start_radius_mm.max(spiral.end_radius_mm);
    if reach > m.max_radius_mm {
        errors.push(machine_error(
            &format!("{}.outer_radius_mm", plan.part.kind()),
            format!(
                "a tool-centre radius within {} mm of the face's centre on {}",
                m.max_radius_mm, m.id
            ),
            format!("{reach:.3} mm"),
            format!(
                "the spiral starts outside the part (outer overtravel) and {} cannot reach it",
                m.id
            ),
        ));
    }
    let rpm = 1000.0 * p.cutting_speed_m_min.value / (std::f64::consts::PI * 2.0 * rt);
    if rpm > m.max_rpm {
        errors.push(machine_error(
            "milling.cutting_speed_m_min",
            format!(
                "at most {:.1} m/min with this {} mm tool ({} rpm on {})",
                m.max_rpm * std::f64::consts::PI * 2.0 * rt / 1000.0,
                2.0 * rt,
                m.max_rpm,
                m.id
            ),
            format!("{} m/min ({rpm:.0} rpm)", p.cutting_speed_m_min.value),
            "the spindle speed would exceed the machine's".into(),
        ));
    }
    let feed = p.feed_per_tooth_mm.value * f64::from(plan.tool.flutes) * rpm;
    if feed > m.max_feed_mm_min {
        errors.push(machine_error(
            "milling.feed_per_tooth_mm",
            format!(
                "at most {:.4} mm per tooth ({} mm/min on {})",
                m.max_feed_mm_min / (f64::from(plan.tool.flutes) * rpm),
                m.max_feed_mm_min,
                m.id
            ),
            format!("{} mm ({feed:.0} mm/min)", p.feed_per_tooth_mm.value),
            "the feed would exceed the machine's".into(),
        ));
    }
    if !errors.is_empty() {
        return Err(errors);
    }

    let (angle_step_deg, points) = spiral.chords(tol);
    let fitted = arcs::fit(&spiral, tol);
    let chord_dev = gearcam_spiral::chord_deviation(&spiral, &points);
    let arc_dev = arcs::max_deviation(&spiral, &fitted, ARC_SAMPLES);
    let (blocks, max_deviation_mm) = match p.program {
        SpiralProgram::FanucArcs => (fitted.len(), arc_dev),
        _ => (points.len() - 1, chord_dev),
    };
    let mut warnings = Vec::new();
    let coverage = match (&plan.part, &groove) {
        (SpiralPart::Face(f), _) => {
            // The program's path strays up to the deviation from the
            // spiral: the tool covers at least rt − deviation around it.
            let c = gearcam_spiral::coverage(
                &Region {
                    outer_radius_mm: f.outer_radius_mm,
                    inner_radius_mm: f.inner_radius_mm,
                },
                rt - max_deviation_mm,
                &points,
                (rt / 4.0).min(0.5),
            );
            CoverageCheck {
                ok: c.ok,
                max_gap_mm: c.max_gap_mm,
                worst_point_mm: c.worst_point,
                max_deviation_mm,
                samples: c.samples as u64,
            }
        }
        (SpiralPart::Groove(g), Some(fig)) => {
            let err = pitch_error(&points, g.pitch_mm);
            let ok = err <= 2.0 * tol + 1e-9 && fig.land_mm > 0.0;
            CoverageCheck {
                ok,
                max_gap_mm: err,
                worst_point_mm: (0.0, 0.0),
                max_deviation_mm,
                samples: 72,
            }
        }
        (SpiralPart::Groove(_), None) => unreachable!("a groove plans its figures"),
    };
    if !coverage.ok {
        let (x, y) = coverage.worst_point_mm;
        return Err(vec![Stage::Model.error(
            "COVERAGE_FAILED",
            "milling.step_over_mm",
            match plan.part {
                SpiralPart::Face(_) => "a path whose tool disc covers every point of the face".to_string(),
                SpiralPart::Groove(_) => format!("turns {} mm apart within {} mm", spiral.step_over_mm(), 2.0 * tol),
            },
            match plan.part {
                SpiralPart::Face(_) => format!("a point {:.4} mm outside the tool at X{x:.3} Y{y:.3}", coverage.max_gap_mm),
                SpiralPart::Groove(_) => format!("a pitch error of {:.4} mm", coverage.max_gap_mm),
            },
            "the coverage check found material the path leaves uncut; lower the step-over or the inner overtravel",
        )]);
    }
    if rt - max_deviation_mm < spiral.step_over_mm() {
        warnings.push(Warning {
            code: "STEP_OVER_LARGE".into(),
            field: "milling.step_over_mm".into(),
            message: format!(
                "the step-over {:.3} mm is more than the tool's radius {rt} mm: neighbouring turns overlap little",
                spiral.step_over_mm()
            ),
        });
    }
    let passes = p.passes;
    let plunge = PLUNGE_SHARE * feed;
    let length = spiral.length();
    // Along the spiral, and each pass's plunge from the safe height.
    let part_time_min =
        f64::from(passes) * (length / feed) + (depth + f64::from(passes) * m.safe_z_mm) / plunge;
    let step_over = spiral.step_over_mm();
    let (ro, ri) = match &plan.part {
        SpiralPart::Face(f) => (f.outer_radius_mm, f.inner_radius_mm),
        SpiralPart::Groove(g) => (
            g.outer_radius_mm + rt,
            (g.outer_radius_mm - g.pitch_mm * f64::from(g.turns) - rt).max(0.0),
        ),
    };
    Ok(SpiralModel {
        job_id: plan.job_id.clone(),
        plan: plan.clone(),
        spiral: SpiralFigures {
            outer_radius_mm: ro,
            inner_radius_mm: ri,
            tool_radius_mm: rt,
            turns: spiral.turns,
            step_over_mm: step_over,
            start_radius_mm: spiral.start_radius_mm,
            end_radius_mm: spiral.end_radius_mm,
            start_angle_deg: spiral.start_angle_deg,
            sense: spiral.sense,
            angle_step_deg,
            path_length_mm: length,
            blocks: blocks as u32,
            arcs: fitted.len() as u32,
            chords: (points.len() - 1) as u32,
        },
        groove,
        cut: SpiralCut {
            depth_mm: depth,
            passes,
            feed_mm_min: feed,
            plunge_feed_mm_min: plunge,
            spindle_rpm: rpm,
            safe_z_mm: m.safe_z_mm,
            tolerance_mm: tol,
        },
        coverage,
        part_time_min,
        warnings,
        model_version: MODEL_VERSION.to_string(),
    })
}

/// The crate's spiral of a model (for programs and checks).
pub fn spiral_of_model(model: &SpiralModel) -> Spiral {
    Spiral {
        start_radius_mm: model.spiral.start_radius_mm,
        end_radius_mm: model.spiral.end_radius_mm,
        start_angle_deg: model.spiral.start_angle_deg,
        turns: model.spiral.turns,
        sense: model.spiral.sense,
    }
}
