//! The check report for a person: the job, the plan with its sources, the
//! figures of the family's model, warnings and errors, the program with its
//! path check.

use std::fmt::Write as _;

use gearcam_proto::{JobError, Source};

use super::{CheckReport, ModelReport, PlanSummary, ProgramSummary, SpiralReport};
use gearcam_proto::{Geometry, Kinematics};

fn src(s: Source) -> &'static str {
    match s {
        Source::Job => "job",
        Source::Case => "case",
        Source::Machine => "machine",
        Source::Default => "default",
        Source::Library => "library",
        Source::Grade => "grade",
    }
}

/// Formats errors for a person, one block each.
pub fn format_errors(errors: &[JobError]) -> String {
    let mut out = String::new();
    for e in errors {
        let _ = writeln!(
            out,
            "  ✗ [{}] {} — {}\n      field {}: expected {}, got {}",
            e.stage.as_str(),
            e.code,
            e.message,
            e.field,
            e.expected,
            e.got
        );
    }
    out
}

/// The wire model's lines for a person.
fn format_die(out: &mut String, d: &gearcam_proto::DieFigures) {
    let _ = writeln!(
        out,
        "{} m {} z {} α {}° x {}  radii base {:.4} tip {:.4} root {:.4} form {:.4} mm{}{}",
        d.part.as_str(),
        d.module_mm,
        d.teeth,
        d.pressure_angle_deg,
        d.profile_shift,
        d.base_radius_mm,
        d.tip_radius_mm,
        d.root_radius_mm,
        d.form_radius_mm,
        if d.undercut { "  UNDERCUT" } else { "" },
        d.centre_distance_mm
            .map_or(String::new(), |a| format!("  centre distance {a:.4} mm"))
    );
    let _ = writeln!(
        out,
        "  arcs per flank {} (tolerance {} µm)  per fillet {} ({} µm)  outline {} arcs  tip thickness {:.3} mm",
        d.arcs_per_flank,
        d.flank_tolerance_um,
        d.arcs_per_fillet,
        d.fillet_tolerance_um,
        d.outline_arcs,
        d.tip_thickness_mm
    );
    let _ = writeln!(
        out,
        "  wire offset {:.4} mm  path {:.1} mm  {:.1} min  teeth written {} of {}",
        d.offset_mm, d.path_length_mm, d.cutting_time_min, d.teeth_written, d.teeth
    );
    let _ = writeln!(
        out,
        "certificate (the program replayed): max deviation {:.3} µm (flank {:.3}, fillet {:.3})  closure {:.3} µm  {} blocks  {} bytes",
        d.max_deviation_um,
        d.flank_deviation_um,
        d.fillet_deviation_um,
        d.closure_um,
        d.blocks,
        d.bytes
    );
}

/// The report for a person.
pub fn format_human(r: &CheckReport) -> String {
    let mut out = String::new();
    if let Some(j) = &r.job {
        let _ = writeln!(
            out,
            "job {}  part {}  machine {}  quantity {}",
            j.id, j.part_number, j.machine, j.quantity
        );
    }
    if let Some(p) = &r.plan {
        plan(&mut out, p);
    }
    if let Some(g) = &r.geometry {
        geometry(&mut out, g);
    }
    match &r.model {
        Some(ModelReport::Spiral(m)) => spiral(&mut out, m),
        Some(ModelReport::Wire(w)) => format_die(&mut out, &w.die),
        _ => {}
    }
    let groove = matches!(&r.model, Some(ModelReport::Spiral(m)) if m.groove.is_some());
    if let Some(c) = &r.coverage {
        let _ = writeln!(
            out,
            "{} {}  {} {:.4} mm  max deviation from the spiral {:.5} mm  ({})",
            if groove { "pitch check" } else { "coverage" },
            if c.ok { "ok" } else { "FAILED" },
            if groove {
                "worst pitch error"
            } else {
                "max gap"
            },
            c.max_gap_mm,
            c.max_deviation_mm,
            match (groove, c.samples) {
                (true, n) => format!("{n} rays"),
                (false, 0) => "proved in closed form from the step-over and the tool".into(),
                (false, n) => format!("{n} points of the face"),
            }
        );
    }
    if let Some(p) = &r.picture {
        let _ = writeln!(out, "picture: {p}");
    }
    if let Some(p) = &r.drawing {
        let _ = writeln!(out, "outline (DXF): {p}");
    }
    if let Some(ModelReport::Hobbing(m)) = &r.model {
        hobbing(&mut out, m);
    }
    if let Some(s) = &r.simulation {
        simulation(&mut out, s);
    }
    if let Some(p) = &r.simulation_picture {
        let _ = writeln!(out, "simulation charts: {p}");
    }
    if let Some(why) = &r.not_simulated {
        let _ = writeln!(out, "virtual hobbing: not simulated ({why})");
    }
    for w in &r.warnings {
        let _ = writeln!(out, "  ! {} {}: {}", w.code, w.field, w.message);
    }
    if !r.errors.is_empty() {
        let _ = writeln!(out, "{} error(s):", r.errors.len());
        out.push_str(&format_errors(&r.errors));
    }
    if let Some(p) = &r.program {
        program(&mut out, p);
    }
    out
}

/// The plan: machine, class, tool and confidence, the cases, the drawing
/// data's origin, the hob choice and every value with its source.
fn plan(out: &mut String, p: &PlanSummary) {
    let _ = writeln!(
        out,
        "machine {} ({}, {})",
        p.machine.id, p.machine.name, p.machine.dialect
    );
    match &p.tool {
        Some(t) => {
            let _ = writeln!(
                out,
                "class {}  tool {} ({} Ø{} mm, corner R{} mm, {} flutes, from {})  confidence {:.2}",
                p.class,
                t.id,
                t.kind.as_str(),
                2.0 * t.radius_mm,
                t.corner_radius_mm,
                t.flutes,
                src(t.source),
                p.confidence
            );
        }
        None => {
            // A wire job's "tool" is its wire.
            let tool = if p.class.starts_with("wire-") {
                "wire"
            } else {
                "hob"
            };
            let _ = writeln!(
                out,
                "class {}  {tool} {}  confidence {:.2}",
                p.class, p.hob_id, p.confidence
            );
        }
    }
    for c in &p.cases {
        let _ = writeln!(
            out,
            "  case {} (similarity {:.2}): {}",
            c.id, c.similarity, c.provenance
        );
    }
    if let Some(w) = &p.workpiece {
        if w.supplied_gear {
            let _ = writeln!(
                out,
                "  drawing data: workpiece {} from the library ({})",
                w.part_number, w.provenance
            );
        } else {
            let _ = writeln!(
                out,
                "  drawing data: the job's [gear], over workpiece {} of the library{}",
                w.part_number,
                if w.differs.is_empty() {
                    " (the same values)".to_string()
                } else {
                    format!(" (differs in {})", w.differs.join(", "))
                }
            );
        }
    }
    if let Some(h) = &p.hob_choice {
        let _ = writeln!(out, "  hob choice: {}", h.reason);
        if !h.alternatives.is_empty() {
            let _ = writeln!(out, "    also fit: {}", h.alternatives.join(", "));
        }
        for r in &h.rejected {
            let _ = writeln!(out, "    rejected {}: {}", r.id, r.reasons.join("; "));
        }
    }
    values(out, p);
}

/// The plan's values, each with its source, and the proposal a job's value
/// overrode.
fn values(out: &mut String, p: &PlanSummary) {
    for (k, v) in &p.values {
        let proposed = match p.proposed.get(k) {
            Some(pv) if p.overridden.contains(k) => {
                format!("  (proposed {:.4} from {})", pv.value, src(pv.source))
            }
            _ => String::new(),
        };
        let _ = writeln!(
            out,
            "  {k:<22} {:>10.4}  from {}{proposed}",
            v.value,
            src(v.source)
        );
    }
}

/// The gear's figures.
fn geometry(out: &mut String, g: &Geometry) {
    let _ = writeln!(
        out,
        "geometry  d {:.4}  db {:.4}  da {:.4}  df {:.4} mm",
        g.d_mm, g.db_mm, g.da_mm, g.df_mm
    );
    let _ = writeln!(
        out,
        "  sn {:.4}  span over k = {} teeth Wk {:.4}  over {} mm balls MdK {:.4} mm",
        g.sn_mm, g.span_teeth, g.span_mm, g.ball_mm, g.over_balls_mm
    );
}

/// A spiral model: the region and the spiral, the path, the cut.
fn spiral(out: &mut String, m: &SpiralReport) {
    let s = &m.spiral;
    let _ = writeln!(
        out,
        "spiral  region Ro {} Ri {} mm  tool radius {} mm  centre R1 {:.4} → R2 {:.4} mm  {} turns  step-over {:.4} mm  {}",
        s.outer_radius_mm,
        s.inner_radius_mm,
        s.tool_radius_mm,
        s.start_radius_mm,
        s.end_radius_mm,
        s.turns,
        s.step_over_mm,
        if s.sense > 0 { "counter-clockwise" } else { "clockwise" }
    );
    let _ = writeln!(
        out,
        "  path {:.1} mm per pass  {} blocks ({} arcs or {} chords at {} mm, angle step {:.4}°)",
        s.path_length_mm, s.blocks, s.arcs, s.chords, m.cut.tolerance_mm, s.angle_step_deg
    );
    let _ = writeln!(
        out,
        "  {} pass(es) to {} mm  {:.0} rpm  feed {:.1} mm/min (plunge {:.1})  {:.2} min per part",
        m.cut.passes,
        m.cut.depth_mm,
        m.cut.spindle_rpm,
        m.cut.feed_mm_min,
        m.cut.plunge_feed_mm_min,
        m.part_time_min
    );
    if let Some(g) = &m.groove {
        let _ = writeln!(
            out,
            "  groove width {} mm  pitch {} mm  land {} mm",
            g.width_mm, g.pitch_mm, g.land_mm
        );
    }
}

/// A hobbing model: swivel, clearance, positions A–E, speeds and feeds, the
/// cuts and every computed value explained.
fn hobbing(out: &mut String, m: &Kinematics) {
    let _ = writeln!(
        out,
        "model  swivel {:.4}°  ΔH′ {:.3} mm (+{:.3} safety)  L {:.3} mm  depth {:.3} mm",
        m.swivel_deg, m.clearance_mm, m.safety_mm, m.centre_distance_mm, m.depth_mm
    );
    let p = &m.positions;
    for (name, pos) in [("A", p.A), ("B", p.B), ("C", p.C), ("D", p.D), ("E", p.E)] {
        let _ = writeln!(out, "  {name}  X {:>9.3}  Z {:>9.3}", pos.x_mm, pos.z_mm);
    }
    let _ = writeln!(
        out,
        "  hob {:.3} rpm  table {:.4} rpm  feed {:.3} mm/min  differential {:.6}°/mm  ratio {}/{}  {:.2} min/cut",
        m.hob_rpm,
        m.table_rpm,
        m.axial_feed_mm_min,
        m.differential_deg_per_mm,
        m.coupling.num,
        m.coupling.den,
        m.cut_time_min
    );
    let _ = writeln!(
        out,
        "  class {}  {} cut(s)  {:.2} min per part",
        m.class,
        m.cuts.len(),
        m.part_time_min
    );
    for e in &m.explain {
        let _ = writeln!(
            out,
            "    {:<34} {:>12.4} {:<6} from {:?}: {}",
            e.name, e.value, e.unit, e.origin, e.note
        );
    }
}

/// The virtual run: for each gear of the part the predicted class per item
/// and overall and the size; the safety findings.
fn simulation(out: &mut String, s: &gearcam_proto::SimulationReport) {
    let class = |c: Option<u8>| c.map_or("worse than 11".to_string(), |c| c.to_string());
    let _ = writeln!(
        out,
        "virtual hobbing ({}, {} sections × {} samples, {} gash passes, {:.0} ms){}: predicted ISO 1328-1 class {} (drawing {})",
        s.mode,
        s.sections,
        s.samples_per_section,
        s.passes,
        s.ms,
        s.unit.as_ref().map_or(String::new(), |u| format!(", gear \"{u}\"")),
        class(s.grade),
        s.required_grade
    );
    gear_simulation(out, s);
    for g in &s.units {
        let _ = writeln!(
            out,
            "  gear \"{}\" ({} gash passes): predicted ISO 1328-1 class {} (drawing {})",
            g.unit.as_deref().unwrap_or("?"),
            g.passes,
            class(g.grade),
            g.required_grade
        );
        gear_simulation(out, g);
    }
    if s.safety.is_empty() {
        let _ = writeln!(out, "  safety: no finding");
    }
    for f in &s.safety {
        let _ = writeln!(
            out,
            "  safety: line {} [{}] {}; {}",
            f.line, f.kind, f.what, f.why
        );
    }
}

/// One gear's measurement: what-if errors, why it cannot be measured, the
/// items and the size.
fn gear_simulation(out: &mut String, s: &gearcam_proto::SimulationReport) {
    let class = |c: Option<u8>| c.map_or("worse than 11".to_string(), |c| c.to_string());
    if let Some(note) = &s.note {
        let _ = writeln!(out, "  note: {note}");
    }
    if !s.what_if.is_empty() {
        let _ = writeln!(out, "  what if: {}", s.what_if.join(", "));
    }
    if let Some(why) = &s.not_measured {
        let _ = writeln!(out, "  the cut gear cannot be measured: {why}");
    }
    for d in &s.deviations {
        let _ = writeln!(
            out,
            "  {:<4} {:>8.2} µm  class {:<13} (tolerance {:.1} µm)",
            d.item,
            d.value_um,
            class(d.class),
            d.tolerance_um
        );
    }
    let pairs = [
        ("tooth thickness", s.thickness_mm),
        ("span", s.span_mm),
        ("over balls", s.over_balls_mm),
    ];
    for (name, v) in pairs {
        if let Some((got, design)) = v {
            let _ = writeln!(
                out,
                "  {name} {got:.4} mm (drawing {design:.4} mm, {:+.1} µm)",
                (got - design) * 1e3
            );
        }
    }
}

/// The program: its name, form, template and hash, the path check, the text.
fn program(out: &mut String, p: &ProgramSummary) {
    let _ = writeln!(
        out,
        "program {} ({}, template {} v{}, sha256 {})",
        p.name, p.dialect, p.template.id, p.template.version, p.sha256
    );
    if p.path_check.ok {
        let _ = writeln!(out, "path check: ok\n");
    } else {
        let _ = writeln!(
            out,
            "path check: {} finding(s); the program would not be sent",
            p.path_check.findings.len()
        );
        for f in &p.path_check.findings {
            let _ = writeln!(out, "  line {} [{}] {}", f.line, f.rule, f.message);
        }
        out.push('\n');
    }
    out.push_str(&p.text);
}
