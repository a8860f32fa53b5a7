//! The library definitions of the spiral face milling family: milling
//! machines, mills, starting cutting data and cases (docs/spiral.md).

use super::defs::{f, OUTCOMES};
use super::fields::{Check, Def, Kind, Library, Need};

use Check::{Any, Id, OneOf, Positive, Range};
use Kind::{Int, Real, Text};
use Need::{Optional, Required};

const MILL_KINDS: &[&str] = &["face-mill", "end-mill"];
const MILL_DIALECTS: &[&str] = &["fanuc", "linuxcnc"];
const SPIRAL_FORMS: &[&str] = &["fanuc-macro", "fanuc-arcs", "fanuc-chords", "linuxcnc"];
const SPIRAL_KINDS: &[&str] = &["face", "groove"];

/// Milling machines of the spiral family (docs/spiral.md#machines).
pub const MILL_MACHINES: Library = Library {
    name: "mill-machines",
    table: "mill_machines",
    key: "id",
    doc: "milling machines: controller, program forms, spindle, feed and reach",
    csv: true,
    fields: &[
        f("id", Text, Required, Id, "machine id, e.g. M01"),
        f("name", Text, Required, Any, "human name"),
        f("controller", Text, Required, Any, "controller, e.g. FANUC 0i-MF"),
        f("dialect", Text, Required, OneOf(MILL_DIALECTS), "NC dialect"),
        f(
            "programs",
            Text,
            Required,
            Any,
            "program forms the control runs, space-separated: fanuc-macro fanuc-arcs fanuc-chords linuxcnc",
        ),
        f(
            "default_program",
            Text,
            Required,
            OneOf(SPIRAL_FORMS),
            "the form used when the job names none",
        ),
        f("max_rpm", Real, Required, Positive, "highest spindle speed, rpm"),
        f(
            "max_feed_mm_min",
            Real,
            Required,
            Positive,
            "highest cutting feed, mm/min",
        ),
        f(
            "max_radius_mm",
            Real,
            Required,
            Positive,
            "largest tool-centre radius about the face's centre the travels reach, mm",
        ),
        f(
            "safe_z_mm",
            Real,
            Need::Default(Def::Real(5.0)),
            Positive,
            "safe height above the face, mm",
        ),
        f(
            "work_offset",
            Text,
            Need::Default(Def::Text("G54")),
            Any,
            "work offset holding the face's centre",
        ),
        f(
            "source",
            Text,
            Need::Default(Def::Text("user")),
            Any,
            "where the data comes from",
        ),
    ],
};

/// Milling tools of the spiral family.
pub const MILLS: Library = Library {
    name: "mills",
    table: "mills",
    key: "id",
    doc: "face and end mills: diameter, corner radius, flutes, cutting material",
    csv: true,
    fields: &[
        f("id", Text, Required, Id, "tool id, e.g. FM-063"),
        f(
            "kind",
            Text,
            Required,
            OneOf(MILL_KINDS),
            "face-mill or end-mill",
        ),
        f(
            "diameter_mm",
            Real,
            Required,
            Positive,
            "cutting diameter, mm",
        ),
        f(
            "corner_radius_mm",
            Real,
            Need::Default(Def::Real(0.0)),
            Range(0.0, 50.0),
            "corner radius, mm",
        ),
        f(
            "flutes",
            Int,
            Required,
            Range(1.0, 100.0),
            "flutes or inserts",
        ),
        f(
            "material",
            Text,
            Need::Default(Def::Text("carbide")),
            Any,
            "cutting material",
        ),
        f(
            "source",
            Text,
            Need::Default(Def::Text("user")),
            Any,
            "where the data comes from",
        ),
    ],
};

/// Starting cutting data of the spiral family, by material group.
pub const MILLING_DATA: Library = Library {
    name: "milling-data",
    table: "milling_data",
    key: "id",
    doc: "starting cutting data of spiral face milling by material group, with provenance",
    csv: true,
    fields: &[
        f("id", Text, Required, Id, "row id"),
        f(
            "material_group",
            Text,
            Required,
            Any,
            "material group, e.g. steel",
        ),
        f(
            "tool_material",
            Text,
            Need::Default(Def::Text("carbide")),
            Any,
            "cutting material",
        ),
        f(
            "cutting_speed_m_min",
            Real,
            Required,
            Positive,
            "cutting speed, m/min",
        ),
        f(
            "feed_per_tooth_mm",
            Real,
            Required,
            Positive,
            "feed per tooth, mm",
        ),
        f(
            "step_over_ratio",
            Real,
            Required,
            Range(0.05, 0.95),
            "step-over as a share of the tool's diameter",
        ),
        f(
            "max_depth_per_pass_mm",
            Real,
            Required,
            Positive,
            "deepest pass, mm",
        ),
        f(
            "confidence",
            Real,
            Required,
            Range(0.0, 1.0),
            "how far to trust the row",
        ),
        f("source", Text, Required, Any, "where the values come from"),
    ],
};

/// Machining history of the spiral family: cases.
pub const MILLING_CASES: Library = Library {
    name: "milling-cases",
    table: "milling_cases",
    key: "id",
    doc: "spiral face milling history: cases (face or groove, material, sizes → tool, step-over, speed, feed → outcome)",
    csv: true,
    fields: &[
        f("id", Text, Required, Id, "case id"),
        f("kind", Text, Required, OneOf(SPIRAL_KINDS), "face or groove"),
        f("machine", Text, Optional, Id, "machine id"),
        f("material", Text, Required, Any, "workpiece material"),
        f("material_group", Text, Required, Any, "material group"),
        f(
            "outer_radius_mm",
            Real,
            Required,
            Positive,
            "outer radius of the face or groove, mm",
        ),
        f(
            "inner_radius_mm",
            Real,
            Need::Default(Def::Real(0.0)),
            Range(0.0, 1e4),
            "inner radius, mm (0: a full circle)",
        ),
        f("tool_id", Text, Optional, Id, "tool id"),
        f("tool_diameter_mm", Real, Required, Positive, "tool diameter, mm"),
        f("flutes", Int, Required, Range(1.0, 100.0), "flutes"),
        f("step_over_mm", Real, Required, Positive, "step-over, mm"),
        f("passes", Int, Required, Range(1.0, 1000.0), "depth passes"),
        f("depth_mm", Real, Required, Positive, "total depth, mm"),
        f(
            "cutting_speed_m_min",
            Real,
            Required,
            Positive,
            "cutting speed, m/min",
        ),
        f(
            "feed_per_tooth_mm",
            Real,
            Required,
            Positive,
            "feed per tooth, mm",
        ),
        f("outcome", Text, Required, OneOf(OUTCOMES), "what came of it"),
        f(
            "notes",
            Text,
            Need::Default(Def::Text("")),
            Any,
            "remarks",
        ),
        f(
            "confidence",
            Real,
            Required,
            Range(0.0, 1.0),
            "how far to trust the case",
        ),
        f("provenance", Text, Required, Any, "where the case comes from"),
        f("job_id", Text, Optional, Any, "the gearcam job it was confirmed from"),
        f(
            "created_at_ms",
            Int,
            Need::Default(Def::Int(0)),
            Range(0.0, 1e15),
            "when it was recorded, ms since the epoch",
        ),
    ],
};
