//! The spiral face milling family's model (docs/spiral.md): from a
//! [`SpiralPlan`] the tool-centre spiral ([`gearcam_spiral::plan`] or
//! [`gearcam_spiral::groove::plan_groove`]), its sense from climb or
//! conventional milling, speeds and feeds against the machine, chords and
//! tangent arcs within the tolerance with their deviation measured
//! independently, and the coverage check of a face or the pitch check of a
//! groove. Every failure is a typed error on the job file's field.

use gearcam_proto::{Code, Problem};
use gearcam_proto::{
    CoverageCheck, CutMode, GrooveFigures, JobError, SpiralCut, SpiralDirection, SpiralFigures,
    SpiralModel, SpiralPart, SpiralPlan, SpiralProgram, Stage, Warning,
};
use gearcam_spiral::{arcs, Direction, Region, Spiral, SpiralSpec};

use crate::MODEL_VERSION;

/// The spiral crate's problems as the model stage's errors.
fn model_errors(problems: Vec<Problem>) -> Vec<JobError> {
    problems
        .into_iter()
        .map(|p| p.raise(Stage::Model))
        .collect()
}

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
    Stage::Model.error(Code::MACHINE_RANGE, field, expected, got, message)
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
            (gearcam_spiral::plan(&spec).map_err(model_errors)?, None)
        }
        SpiralPart::Groove(g) => {
            if (g.width_mm - 2.0 * rt).abs() > 1e-3 {
                return Err(vec![Stage::Model.error(
                    Code::GROOVE_RANGE,
                    "groove.width_mm",
                    format!("the tool's diameter, {} mm (tool {})", 2.0 * rt, plan.tool.id),
                    format!("{}", g.width_mm),
                    "the groove is cut in one pass of the tool's full width: choose a tool whose diameter is the groove's width",
                )]);
            }
            let planned =
                gearcam_spiral::groove::plan_groove(&gearcam_spiral::groove::GrooveSpec {
                    outer_radius_mm: g.outer_radius_mm,
                    pitch_mm: g.pitch_mm,
                    turns: g.turns,
                    tool_radius_mm: rt,
                    start_angle_deg: p.start_angle_deg.value,
                })
                .map_err(model_errors)?;
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
    let checked = validate(plan)?;
    model_of(plan, checked)
}

/// A plan whose inputs passed every check: its spiral (sense set), a
/// groove's figures, and the spindle speed and feed the machine can run.
struct Checked {
    /// The tool-centre spiral, its sense set.
    spiral: Spiral,
    /// A groove's figures; `None` for a face.
    groove: Option<GrooveFigures>,
    /// Spindle speed, rpm.
    rpm: f64,
    /// Feed along the spiral, mm/min.
    feed: f64,
}

/// The validation: every typed input problem (field, expected, got), in
/// two rounds. First the plan's own values and its spiral; then, on a
/// spiral that exists, the overlap of its turns and the machine's limits.
fn validate(plan: &SpiralPlan) -> Result<Checked, Vec<JobError>> {
    let mut errors = input_errors(plan);
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
    if groove.is_none() {
        errors.extend(ring_error(plan, &spiral));
    }
    let (rpm, feed) = spindle_and_feed(plan);
    errors.extend(machine_errors(plan, &spiral, rpm, feed));
    if !errors.is_empty() {
        return Err(errors);
    }
    Ok(Checked {
        spiral,
        groove,
        rpm,
        feed,
    })
}

/// The plan's own values checked: a program form the machine runs, one
/// depth pass or more, a depth above zero, a tolerance in (0, 0.1] mm.
fn input_errors(plan: &SpiralPlan) -> Vec<JobError> {
    let p = &plan.process;
    let m = &plan.machine;
    let mut errors = Vec::new();
    if !m.programs.contains(&p.program) {
        let forms: Vec<&str> = m.programs.iter().map(|f| f.as_str()).collect();
        errors.push(crate::program_form_error(
            "milling.program",
            &m.id,
            &m.controller,
            &forms,
            p.program.as_str(),
        ));
    }
    if p.passes == 0 {
        errors.push(Stage::Model.error(
            Code::SPIRAL_RANGE,
            "milling.passes",
            "1 or more depth passes",
            "0",
            "the depth is cut in equal passes",
        ));
    }
    let depth = plan.part.depth_mm();
    if !(depth.is_finite() && depth > 0.0) {
        errors.push(Stage::Model.error(
            Code::SPIRAL_RANGE,
            &format!("{}.depth_mm", plan.part.kind()),
            "a depth > 0 mm",
            format!("{depth}"),
            "the depth to cut below the face",
        ));
    }
    let tol = p.tolerance_mm.value;
    if !(tol.is_finite() && tol > 0.0 && tol <= 0.1) {
        errors.push(Stage::Model.error(
            Code::SPIRAL_RANGE,
            "milling.tolerance_mm",
            "a tolerance in (0, 0.1] mm",
            format!("{tol}"),
            "the chords and arcs stay this close to the spiral",
        ));
    }
    errors
}

/// A face's neighbouring turns must overlap by more than the path strays
/// from the spiral (chords and arcs up to the tolerance, on either side
/// for arcs): refused on the step-over before the coverage proof, which
/// then takes the path's own stray.
fn ring_error(plan: &SpiralPlan, spiral: &Spiral) -> Option<JobError> {
    let rt = plan.tool.radius_mm;
    let tol = plan.process.tolerance_mm.value;
    (spiral.step_over_mm() > 2.0 * rt - 2.0 * tol).then(|| {
        Stage::Model.error(
            Code::SPIRAL_RANGE,
            "milling.step_over_mm",
            format!(
                "at most {:.4} mm: the tool's diameter less twice the tolerance {tol} mm",
                2.0 * rt - 2.0 * tol
            ),
            format!("{:.4}", spiral.step_over_mm()),
            "the path strays up to the tolerance from the spiral, so turns a tool's diameter apart would leave a ring",
        )
    })
}

/// The spindle speed, rpm, of the plan's cutting speed with its tool, and
/// the feed along the spiral, mm/min, of its feed per tooth at that speed.
fn spindle_and_feed(plan: &SpiralPlan) -> (f64, f64) {
    let p = &plan.process;
    let rt = plan.tool.radius_mm;
    let rpm = 1000.0 * p.cutting_speed_m_min.value / (std::f64::consts::PI * 2.0 * rt);
    let feed = p.feed_per_tooth_mm.value * f64::from(plan.tool.flutes) * rpm;
    (rpm, feed)
}

/// The machine's limits checked: the spiral's largest tool-centre radius
/// within its reach, the spindle speed and the feed within its own.
fn machine_errors(plan: &SpiralPlan, spiral: &Spiral, rpm: f64, feed: f64) -> Vec<JobError> {
    let p = &plan.process;
    let m = &plan.machine;
    let rt = plan.tool.radius_mm;
    let mut errors = Vec::new();
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
    errors
}

/// The computation on a checked plan: the chords and arcs within the
/// tolerance and their deviation measured independently, the coverage (or
/// pitch) check of the path the program cuts, the warnings, the cut and the
/// part's time.
fn model_of(plan: &SpiralPlan, checked: Checked) -> Result<SpiralModel, Vec<JobError>> {
    let Checked {
        spiral,
        groove,
        rpm,
        feed,
    } = checked;
    let p = &plan.process;
    let m = &plan.machine;
    let rt = plan.tool.radius_mm;
    let tol = p.tolerance_mm.value;
    let depth = plan.part.depth_mm();
    let (angle_step_deg, points) = spiral.chords(tol);
    let fitted = arcs::fit(&spiral, tol);
    // The deviation of the path the program cuts, measured.
    let (blocks, max_deviation_mm) = match p.program {
        SpiralProgram::FanucArcs => (
            fitted.len(),
            arcs::max_deviation(&spiral, &fitted, ARC_SAMPLES),
        ),
        _ => (
            points.len() - 1,
            gearcam_spiral::chord_deviation(&spiral, &points),
        ),
    };
    let coverage = coverage_of(plan, groove.as_ref(), &spiral, &points, max_deviation_mm);
    if !coverage.ok {
        return Err(vec![coverage_error(plan, &spiral, &coverage)]);
    }
    let mut warnings = Vec::new();
    if groove.is_none() {
        warnings.extend(step_over_warning(rt, &spiral));
    }
    let passes = p.passes;
    let plunge = PLUNGE_SHARE * feed;
    let length = spiral.length();
    // Along the spiral, and each pass's plunge from the safe height.
    let part_time_min =
        f64::from(passes) * (length / feed) + (depth + f64::from(passes) * m.safe_z_mm) / plunge;
    let step_over = spiral.step_over_mm();
    let (ro, ri) = part_radii(plan);
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

/// The coverage of a face, proved from the spiral
/// ([`gearcam_spiral::prove_coverage`]: neighbouring turns overlap and the
/// innermost and outermost turns reach past the edges, the tool's reach
/// taken less δ, how far the spiral may lie from the path the program
/// cuts: for chords the proven bound [`Spiral::chord_stray_mm`] and the
/// measured deviation, for arcs the measured deviation and at least the
/// tolerance the fit holds); over a groove, the pitch measured on the
/// chords within twice the tolerance, with a land left between the turns.
fn coverage_of(
    plan: &SpiralPlan,
    groove: Option<&GrooveFigures>,
    spiral: &Spiral,
    points: &[(f64, f64)],
    max_deviation_mm: f64,
) -> CoverageCheck {
    let p = &plan.process;
    let rt = plan.tool.radius_mm;
    let tol = p.tolerance_mm.value;
    match (&plan.part, groove) {
        (SpiralPart::Face(f), _) => {
            let stray = match p.program {
                SpiralProgram::FanucArcs => max_deviation_mm.max(tol),
                _ => spiral.chord_stray_mm(tol).max(max_deviation_mm),
            };
            let proof = gearcam_spiral::prove_coverage(
                &Region {
                    outer_radius_mm: f.outer_radius_mm,
                    inner_radius_mm: f.inner_radius_mm,
                },
                spiral,
                rt,
                stray,
            );
            CoverageCheck {
                ok: proof.ok,
                max_gap_mm: proof.max_gap_mm,
                worst_point_mm: proof.worst_point,
                max_deviation_mm,
                samples: 0,
            }
        }
        (SpiralPart::Groove(g), Some(fig)) => {
            let err = pitch_error(points, g.pitch_mm);
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
    }
}

/// The refusal of a path whose coverage check failed: where a face is left
/// uncut, or how far a groove's pitch is off.
fn coverage_error(plan: &SpiralPlan, spiral: &Spiral, coverage: &CoverageCheck) -> JobError {
    let tol = plan.process.tolerance_mm.value;
    let (x, y) = coverage.worst_point_mm;
    Stage::Model.error(
        Code::COVERAGE_FAILED,
        "milling.step_over_mm",
        match plan.part {
            SpiralPart::Face(_) => "a path whose tool disc covers every point of the face".to_string(),
            SpiralPart::Groove(_) => format!("turns {} mm apart within {} mm", spiral.step_over_mm(), 2.0 * tol),
        },
        match plan.part {
            SpiralPart::Face(_) => format!("up to {:.4} mm of the face outside the tool, near X{x:.3} Y{y:.3}", coverage.max_gap_mm),
            SpiralPart::Groove(_) => format!("a pitch error of {:.4} mm", coverage.max_gap_mm),
        },
        "the coverage proof finds material the path may leave uncut; lower the step-over or raise the overtravels",
    )
}

/// Coverage holds; but with a face's turns nearly a tool's diameter apart
/// (over 90 %) a tool a little smaller than its nominal size leaves a ring.
fn step_over_warning(rt: f64, spiral: &Spiral) -> Option<Warning> {
    (spiral.step_over_mm() > 0.9 * 2.0 * rt).then(|| Warning {
        code: Code::STEP_OVER_LARGE,
        field: "milling.step_over_mm".into(),
        message: format!(
            "the step-over {:.3} mm is over 90 % of the tool's diameter {} mm: neighbouring turns overlap by {:.3} mm only",
            spiral.step_over_mm(),
            2.0 * rt,
            2.0 * rt - spiral.step_over_mm()
        ),
    })
}

/// The radii of the part the model reports: a face's own; for a groove,
/// the band the tool sweeps, from its outer edge to the last turn's inner
/// edge (not below the centre).
fn part_radii(plan: &SpiralPlan) -> (f64, f64) {
    let rt = plan.tool.radius_mm;
    match &plan.part {
        SpiralPart::Face(f) => (f.outer_radius_mm, f.inner_radius_mm),
        SpiralPart::Groove(g) => (
            g.outer_radius_mm + rt,
            (g.outer_radius_mm - g.pitch_mm * f64::from(g.turns) - rt).max(0.0),
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use gearcam_proto::{JobId, JobRequest, JobSpec};
    use serde_json::{json, Value};

    fn plan(v: Value) -> SpiralPlan {
        let spec: JobSpec = serde_json::from_value(v).unwrap();
        let req = JobRequest {
            job_id: JobId::new("J-M1").unwrap(),
            submitted_at_ms: 0,
            submitted_by: "test".into(),
            spec,
        };
        let conn = gearcam_knowledge::db::open_in_memory().unwrap();
        gearcam_knowledge::spiral::plan_spiral(&conn, &req).unwrap()
    }

    fn face(milling: Value) -> SpiralPlan {
        plan(json!({
            "job": {"family": "spiral-face", "machine": "M01", "part_number": "FL-1"},
            "face": {"outer_radius_mm": 60.0, "inner_radius_mm": 10.0, "depth_mm": 1.0,
                     "material": "C45"},
            "mill": {"id": "EM-16"},
            "milling": milling,
        }))
    }

    /// Climb milling with a clockwise spindle keeps the uncut material on
    /// the right of the feed, for both directions; conventional on the
    /// left. Checked on the model's own path: the side of the face's
    /// centre (outside-in: the uncut side) or of the outside (inside-out).
    #[test]
    fn climb_keeps_the_uncut_material_on_the_right_of_the_feed() {
        for direction in ["outside-in", "inside-out"] {
            for mode in ["climb", "conventional"] {
                let model =
                    compute_spiral(&face(json!({"direction": direction, "cut_mode": mode})))
                        .unwrap();
                let spiral = gearcam_spiral::verify::spiral_of(&model);
                let (_, pts) = spiral.chords(0.005);
                let k = pts.len() / 2;
                let (p, q) = (pts[k], pts[k + 1]);
                let feed = (q.0 - p.0, q.1 - p.1);
                // Towards the uncut material.
                let uncut = if direction == "outside-in" {
                    (-p.0, -p.1)
                } else {
                    (p.0, p.1)
                };
                let cross = feed.0 * uncut.1 - feed.1 * uncut.0;
                let on_right = cross < 0.0;
                assert_eq!(on_right, mode == "climb", "{direction} {mode}");
            }
        }
    }

    /// The analytic guard: turns closer to a tool's diameter apart than
    /// twice the tolerance are refused before the coverage check.
    #[test]
    fn a_step_over_within_twice_the_tolerance_of_the_diameter_is_refused() {
        // Numbers exact in binary, so the turns come out whole: 45 mm of face
        // plus 2 + 0.9765625 mm of overtravel is 3 steps of 15.9921875 mm
        // (16 less 1/128), over the 15.99 mm a 5 um tolerance allows.
        let tight = |tol: f64| {
            plan(json!({
                "job": {"family": "spiral-face", "machine": "M01", "part_number": "FL-1"},
                "face": {"outer_radius_mm": 60.0, "inner_radius_mm": 15.0, "depth_mm": 1.0,
                         "material": "C45"},
                "mill": {"id": "EM-16"},
                "milling": {"step_over_mm": 15.9921875, "tolerance_mm": tol,
                            "outer_overtravel_mm": 2.0, "inner_overtravel_mm": 0.9765625},
            }))
        };
        let ok = compute_spiral(&tight(0.001)).unwrap();
        assert_eq!((ok.spiral.turns, ok.spiral.step_over_mm), (4, 15.9921875));
        assert!(ok.coverage.ok, "{:?}", ok.coverage);
        let e = compute_spiral(&tight(0.005)).unwrap_err();
        assert_eq!(
            (e[0].code.as_str(), e[0].field.as_str()),
            ("SPIRAL_RANGE", "milling.step_over_mm")
        );
        assert!(e[0].expected.contains("15.99"), "{}", e[0].expected);
    }

    /// A face's coverage is the proof's, with the form's stray: the
    /// plan's own spiral is proved; the same face in turns 2.5 tool radii
    /// apart or more is refused, by at least L/2 − (R − δ) (between the
    /// turns; the inner edge falls short too, the end radius kept), the
    /// shortfall the proof gives for the chords' stray.
    #[test]
    fn a_faces_coverage_is_proved_with_the_paths_stray() {
        let p = face(json!({"tolerance_mm": 0.002}));
        let rt = p.tool.radius_mm;
        let (spiral, _) = spiral_of(&p).unwrap();
        let (_, points) = spiral.chords(0.002);
        let dev = gearcam_spiral::chord_deviation(&spiral, &points);
        let ok = coverage_of(&p, None, &spiral, &points, dev);
        assert!(ok.ok && ok.max_gap_mm == 0.0 && ok.samples == 0, "{ok:?}");
        let span = (spiral.start_radius_mm - spiral.end_radius_mm).abs();
        let wide = Spiral {
            turns: ((span / (2.5 * rt)).floor() as u32).max(1),
            ..spiral
        };
        let (_, points) = wide.chords(0.002);
        let dev = gearcam_spiral::chord_deviation(&wide, &points);
        let gap = coverage_of(&p, None, &wide, &points, dev);
        let stray = wide.chord_stray_mm(0.002).max(dev);
        let between = wide.step_over_mm() / 2.0 - (rt - stray);
        assert!(
            between > 0.0 && !gap.ok && gap.max_gap_mm >= between,
            "{gap:?}"
        );
        let region = Region {
            outer_radius_mm: 60.0,
            inner_radius_mm: 10.0,
        };
        let proof = gearcam_spiral::prove_coverage(&region, &wide, rt, stray);
        assert_eq!(
            (gap.max_gap_mm, gap.worst_point_mm),
            (proof.max_gap_mm, proof.worst_point)
        );
    }

    /// The groove's pitch is measured on the path's points: a path of
    /// 16 mm pitch checked against 15 mm is off by 1 mm.
    #[test]
    fn the_pitch_check_measures_the_path() {
        let spiral = Spiral {
            start_radius_mm: 60.0,
            end_radius_mm: 12.0,
            start_angle_deg: 10.0,
            turns: 3,
            sense: -1,
        };
        let (_, pts) = spiral.chords(0.005);
        assert!(
            pitch_error(&pts, 16.0) < 0.01,
            "{}",
            pitch_error(&pts, 16.0)
        );
        assert!((pitch_error(&pts, 15.0) - 1.0).abs() < 0.01);
    }

    /// Every form's model is covered, with the deviation of its own path.
    #[test]
    fn faces_are_covered_in_every_form_and_the_machine_limits_hold() {
        for form in ["fanuc-macro", "fanuc-arcs", "fanuc-chords"] {
            let m = compute_spiral(&face(json!({"program": form, "tolerance_mm": 0.002}))).unwrap();
            assert!(
                m.coverage.ok && m.coverage.max_gap_mm == 0.0,
                "{form}: {:?}",
                m.coverage
            );
            assert!(
                m.coverage.max_deviation_mm <= 0.002 * 1.01,
                "{form}: {:?}",
                m.coverage
            );
            let expected = if form == "fanuc-arcs" {
                m.spiral.arcs
            } else {
                m.spiral.chords
            };
            assert_eq!(m.spiral.blocks, expected, "{form}");
            assert!(
                m.spiral.arcs * 10 < m.spiral.chords,
                "{form}: {:?}",
                m.spiral
            );
        }
        let e = compute_spiral(&face(json!({"program": "linuxcnc"}))).unwrap_err();
        assert_eq!(
            (e[0].code.as_str(), e[0].field.as_str()),
            ("PROGRAM_FORM", "milling.program")
        );
        let e = compute_spiral(&face(json!({"cutting_speed_m_min": 600.0}))).unwrap_err();
        assert_eq!(
            (e[0].code.as_str(), e[0].field.as_str()),
            ("MACHINE_RANGE", "milling.cutting_speed_m_min")
        );
    }
}
