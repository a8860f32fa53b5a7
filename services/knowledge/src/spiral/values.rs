//! The process values of a spiral plan: the milling cases ranked by their
//! similarity to the job, each cutting value from the job, the best case
//! or the cutting data (each with its source), a proposal lowered to what
//! the machine can run, the cases the plan cites, and the milling process
//! with the job's choices or their documented defaults.

use gearcam_proto::{
    CaseRef, CutMode, MillData, MillProfile, MillingOverrides, MillingProcess, Source, Sourced,
    SpiralDirection, SpiralPart, SpiralProgram,
};
use rusqlite::Connection;

use super::{
    num, text, DEFAULT_INNER_OVERTRAVEL_MM, DEFAULT_OUTER_OVERTRAVEL_MM, DEFAULT_TOLERANCE_MM,
    MIN_SIMILARITY,
};
use crate::library::{self, Record};
use crate::KnowledgeError;

/// A case's similarity to the job, 0–1: the material group (weight 3), the
/// outer radius (1) and the inner radius as a share of it (0.5) by relative
/// difference, the tool's diameter (1), the machine (0.5). Cases of the
/// other kind (face or groove) are not compared.
fn similarity(case: &Record, part: &SpiralPart, group: &str, tool_d: f64, machine: &str) -> f64 {
    let close = |a: f64, b: f64| {
        if a.max(b) <= 0.0 {
            1.0
        } else {
            1.0 - (a - b).abs() / a.max(b)
        }
    };
    let (ro, ri) = match part {
        SpiralPart::Face(f) => (f.outer_radius_mm, f.inner_radius_mm),
        SpiralPart::Groove(g) => (g.outer_radius_mm, 0.0),
    };
    let terms = [
        (
            3.0,
            f64::from(u8::from(text(case, "material_group") == group)),
        ),
        (1.0, close(ro, num(case, "outer_radius_mm"))),
        (
            0.5,
            1.0 - (ri / ro - num(case, "inner_radius_mm") / num(case, "outer_radius_mm")).abs(),
        ),
        (1.0, close(tool_d, num(case, "tool_diameter_mm"))),
        (0.5, f64::from(u8::from(text(case, "machine") == machine))),
    ];
    let total: f64 = terms.iter().map(|t| t.0).sum();
    terms
        .iter()
        .map(|(w, s)| w * s.clamp(0.0, 1.0))
        .sum::<f64>()
        / total
}

/// The cases of the part's kind (not the scrapped ones), each with its
/// similarity to the job, most similar first.
pub(super) fn ranked_cases(
    conn: &Connection,
    part: &SpiralPart,
    group: &str,
    tool_d: f64,
    machine: &str,
) -> Result<Vec<(f64, Record)>, KnowledgeError> {
    let mut scored: Vec<(f64, Record)> = library::list(conn, &library::MILLING_CASES)?
        .into_iter()
        .filter(|c| text(c, "kind") == part.kind() && text(c, "outcome") != "scrap")
        .map(|c| (similarity(&c, part, group, tool_d, machine), c))
        .collect();
    scored.sort_by(|a, b| b.0.total_cmp(&a.0));
    Ok(scored)
}

/// A value the job gives.
fn given(value: f64) -> Sourced {
    Sourced {
        value,
        source: Source::Job,
    }
}

/// A value a case, or the cutting data, proposes.
fn from_case(value: f64) -> Sourced {
    Sourced {
        value,
        source: Source::Case,
    }
}

/// A documented default.
fn by_default(value: f64) -> Sourced {
    Sourced {
        value,
        source: Source::Default,
    }
}

/// A value: the job's, else the best case's (adapted), else the cutting data's.
fn pick(given_value: Option<f64>, case: Option<f64>, data: Option<f64>) -> Option<Sourced> {
    given_value
        .map(given)
        .or_else(|| case.map(from_case))
        .or_else(|| data.map(from_case))
}

/// The cutting values of a job, each with its source.
pub(super) struct Proposed {
    /// Cutting speed, m/min.
    cutting_speed_m_min: Sourced,
    /// Feed per tooth, mm.
    feed_per_tooth_mm: Sourced,
    /// Largest step-over, mm.
    step_over_mm: Sourced,
    /// Depth passes.
    passes: u32,
}

/// The cutting values proposed for the part with a tool of diameter `d`:
/// the job's, else the best case's (`case`, adapted to the tool), else the
/// cutting data's (`data`). The caller has checked that one of them gives
/// every value.
pub(super) fn proposed(
    o: &MillingOverrides,
    part: &SpiralPart,
    case: Option<&Record>,
    data: Option<&Record>,
    d: f64,
) -> Proposed {
    let cutting_speed_m_min = pick(
        o.cutting_speed_m_min,
        case.map(|c| num(c, "cutting_speed_m_min")),
        data.map(|r| num(r, "cutting_speed_m_min")),
    );
    let feed_per_tooth_mm = pick(
        o.feed_per_tooth_mm,
        case.map(|c| num(c, "feed_per_tooth_mm")),
        data.map(|r| num(r, "feed_per_tooth_mm")),
    );
    // A groove's step-over is its pitch; a face's is the case's share of its
    // tool's diameter, or the data's.
    let step_over_mm = match part {
        SpiralPart::Groove(g) => Some(given(g.pitch_mm)),
        SpiralPart::Face(_) => pick(
            o.step_over_mm,
            case.map(|c| num(c, "step_over_mm") / num(c, "tool_diameter_mm") * d),
            data.map(|r| num(r, "step_over_ratio") * d),
        ),
    };
    let depth = part.depth_mm();
    let passes = o.passes.unwrap_or_else(|| {
        let per_pass = case
            .map(|c| num(c, "depth_mm") / num(c, "passes"))
            .or_else(|| data.map(|r| num(r, "max_depth_per_pass_mm")))
            .unwrap_or(depth);
        ((depth / per_pass).ceil().max(1.0)) as u32
    });
    let (Some(cutting_speed_m_min), Some(feed_per_tooth_mm), Some(step_over_mm)) =
        (cutting_speed_m_min, feed_per_tooth_mm, step_over_mm)
    else {
        unreachable!("checked above: the job, a case or the data gives every value")
    };
    Proposed {
        cutting_speed_m_min,
        feed_per_tooth_mm,
        step_over_mm,
        passes,
    }
}

/// A proposal the machine cannot run is lowered to its limit (source
/// `machine`): the cutting speed to its spindle speed with a tool of
/// diameter `d`, then the feed per tooth to its feed at that speed. A value
/// the job gives is the planner's and is checked, never changed, by the
/// model service.
pub(super) fn within_machine(
    mut v: Proposed,
    machine: &MillProfile,
    tool: &MillData,
    d: f64,
) -> Proposed {
    let vc_max = machine.max_rpm * std::f64::consts::PI * d / 1000.0;
    if v.cutting_speed_m_min.source != Source::Job && v.cutting_speed_m_min.value > vc_max {
        v.cutting_speed_m_min = Sourced {
            value: (vc_max * 10.0).floor() / 10.0,
            source: Source::Machine,
        };
    }
    let rpm = 1000.0 * v.cutting_speed_m_min.value / (std::f64::consts::PI * d);
    let fz_max = machine.max_feed_mm_min / (f64::from(tool.flutes) * rpm);
    if v.feed_per_tooth_mm.source != Source::Job && v.feed_per_tooth_mm.value > fz_max {
        v.feed_per_tooth_mm = Sourced {
            value: (fz_max * 10_000.0).floor() / 10_000.0,
            source: Source::Machine,
        };
    }
    v
}

/// The cases the plan cites: the three most similar, those similar enough
/// for their values to be proposed.
pub(super) fn case_refs(scored: &[(f64, Record)]) -> Vec<CaseRef> {
    scored
        .iter()
        .take(3)
        .filter(|(s, _)| *s >= MIN_SIMILARITY)
        .map(|(s, c)| CaseRef {
            id: text(c, "id").to_string(),
            similarity: *s,
            provenance: text(c, "provenance").to_string(),
        })
        .collect()
}

/// The milling process of the plan: the cutting values, and the job's
/// direction, cut mode, overtravels, start angle and tolerance or their
/// documented defaults.
pub(super) fn milling_process(
    o: &MillingOverrides,
    v: Proposed,
    program: SpiralProgram,
) -> MillingProcess {
    MillingProcess {
        step_over_mm: v.step_over_mm,
        passes: v.passes,
        cutting_speed_m_min: v.cutting_speed_m_min,
        feed_per_tooth_mm: v.feed_per_tooth_mm,
        direction: o.direction.unwrap_or(SpiralDirection::OutsideIn),
        cut_mode: o.cut_mode.unwrap_or(CutMode::Climb),
        outer_overtravel_mm: o
            .outer_overtravel_mm
            .map_or(by_default(DEFAULT_OUTER_OVERTRAVEL_MM), given),
        inner_overtravel_mm: o
            .inner_overtravel_mm
            .map_or(by_default(DEFAULT_INNER_OVERTRAVEL_MM), given),
        start_angle_deg: o.start_angle_deg.map_or(by_default(0.0), given),
        tolerance_mm: o
            .tolerance_mm
            .map_or(by_default(DEFAULT_TOLERANCE_MM), given),
        program,
    }
}
