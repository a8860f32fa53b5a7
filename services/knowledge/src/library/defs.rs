//! The library definitions: every library's table, key and fields.

use super::fields::{Check, Def, Field, Kind, Library, Need};

pub(super) const fn f(
    name: &'static str,
    kind: Kind,
    need: Need,
    check: Check,
    doc: &'static str,
) -> Field {
    Field {
        name,
        kind,
        need,
        check,
        doc,
    }
}

use Check::{Any, Id, OneOf, Positive, Range};
use Kind::{Bool, Int, Real, Text};
use Need::{Optional, Required};

const HANDS: &[&str] = &["right", "left"];
const CLASSES: &[&str] = &[
    "cylindrical",
    "conical",
    "worm_wheel",
    "crowned",
    "curved_tooth",
    "multi_gear",
];
/// A planned job's class: a hobbing class, or the spiral family's part kind.
const JOB_CLASSES: &[&str] = &[
    "cylindrical",
    "conical",
    "worm_wheel",
    "crowned",
    "curved_tooth",
    "multi_gear",
    "spiral-face",
    "spiral-groove",
    "wire-punch",
    "wire-die",
];
const ACCURACY: &[&str] = &["AA", "A", "B", "C"];
const OPERATIONS: &[&str] = &["rough", "finish"];
pub(super) const OUTCOMES: &[&str] = &["ok", "rework", "scrap", "unknown"];
const CUT_MODES: &[&str] = &["conventional", "climb"];
const JOB_STATES: &[&str] = &["planned", "delivered", "confirmed", "refused"];

/// The group-technology class tree (docs/knowledge.md#group-technology-classes).
pub const CLASSES_LIB: Library = Library {
    name: "classes",
    table: "gt_classes",
    key: "id",
    doc: "group-technology class tree (docs/knowledge.md#group-technology-classes)",
    csv: false,
    fields: &[
        f("id", Text, Required, Id, "class id, e.g. cylindrical"),
        f(
            "parent",
            Text,
            Optional,
            Id,
            "parent class id (absent for the root)",
        ),
        f("name", Text, Required, Any, "human name"),
        f(
            "tooth_trace",
            Text,
            Required,
            Any,
            "tooth trace / generating line",
        ),
        f(
            "deformation",
            Text,
            Required,
            Any,
            "deformation along the face width",
        ),
        f("hobbing_method", Text, Required, Any, "how it is hobbed"),
        f(
            "programmable",
            Bool,
            Need::Default(Def::Bool(false)),
            Any,
            "whether gearcam programs it in this release",
        ),
        f(
            "source",
            Text,
            Need::Default(Def::Text("user")),
            Any,
            "where the entry comes from",
        ),
    ],
};

/// Workpieces: drawing data by part number.
pub const WORKPIECES: Library = Library {
    name: "workpieces",
    table: "workpieces",
    key: "part_number",
    doc: "workpieces: drawing data by part number",
    csv: true,
    fields: &[
        f("part_number", Text, Required, Id, "drawing number"),
        f(
            "description",
            Text,
            Need::Default(Def::Text("")),
            Any,
            "what the part is",
        ),
        f(
            "class",
            Text,
            Need::Default(Def::Text("cylindrical")),
            OneOf(CLASSES),
            "group-technology class",
        ),
        f(
            "module_mm",
            Real,
            Required,
            Positive,
            "normal module mn, mm",
        ),
        f(
            "teeth",
            Int,
            Required,
            Range(1.0, 10000.0),
            "number of teeth z",
        ),
        f(
            "pressure_angle_deg",
            Real,
            Need::Default(Def::Real(20.0)),
            Range(5.0, 45.0),
            "normal pressure angle αn, degrees",
        ),
        f(
            "helix_angle_deg",
            Real,
            Need::Default(Def::Real(0.0)),
            Range(0.0, 89.0),
            "helix angle β magnitude, degrees",
        ),
        f(
            "helix_hand",
            Text,
            Optional,
            OneOf(HANDS),
            "hand of the helix (required when β ≠ 0)",
        ),
        f(
            "face_width_mm",
            Real,
            Required,
            Positive,
            "face width b, mm",
        ),
        f(
            "profile_shift",
            Real,
            Need::Default(Def::Real(0.0)),
            Range(-3.0, 3.0),
            "profile shift coefficient x",
        ),
        f(
            "addendum_coef",
            Real,
            Need::Default(Def::Real(1.0)),
            Range(0.0, 3.0),
            "addendum coefficient ha*",
        ),
        f(
            "clearance_coef",
            Real,
            Need::Default(Def::Real(0.25)),
            Range(0.0, 1.0),
            "tip clearance coefficient c*",
        ),
        f(
            "blank_od_mm",
            Real,
            Optional,
            Positive,
            "blank outside diameter Da1, mm",
        ),
        f(
            "od_correction_mm",
            Real,
            Need::Default(Def::Real(0.0)),
            Range(-50.0, 50.0),
            "X correction Δx, mm",
        ),
        f(
            "material",
            Text,
            Need::Default(Def::Text("unspecified")),
            Any,
            "material, e.g. 20CrMnTi",
        ),
        f(
            "hardness_hb",
            Real,
            Optional,
            Range(50.0, 700.0),
            "hardness when hobbed, HB",
        ),
        f(
            "quality_grade",
            Int,
            Need::Default(Def::Int(8)),
            Range(1.0, 12.0),
            "accuracy grade (ISO 1328)",
        ),
        f(
            "fixture_height_mm",
            Real,
            Required,
            Range(0.0, 2000.0),
            "H: lower tooth face above the table, mm",
        ),
        f(
            "cone_angle_deg",
            Real,
            Optional,
            Range(0.0, 45.0),
            "cone angle δ of a conical gear, degrees",
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

/// Hobs: the tool library.
pub const HOBS: Library = Library {
    name: "hobs",
    table: "hobs",
    key: "id",
    doc: "hobs: geometry, accuracy class, material, coating, shift position, remaining life",
    csv: true,
    fields: &[
        f("id", Text, Required, Id, "hob id"),
        f(
            "module_mm",
            Real,
            Required,
            Positive,
            "normal module mn0, mm",
        ),
        f(
            "pressure_angle_deg",
            Real,
            Need::Default(Def::Real(20.0)),
            Range(5.0, 45.0),
            "normal pressure angle α0, degrees",
        ),
        f(
            "starts",
            Int,
            Required,
            Range(1.0, 12.0),
            "number of starts z0",
        ),
        f("hand", Text, Required, OneOf(HANDS), "hand of the thread"),
        f(
            "lead_angle_deg",
            Real,
            Required,
            Range(0.0, 45.0),
            "lead angle γ0, degrees",
        ),
        f(
            "od_mm",
            Real,
            Required,
            Positive,
            "outside diameter da0, mm",
        ),
        f("length_mm", Real, Required, Positive, "overall length, mm"),
        f(
            "usable_length_mm",
            Real,
            Required,
            Positive,
            "usable (cutting) length, mm",
        ),
        f(
            "accuracy_class",
            Text,
            Need::Default(Def::Text("A")),
            OneOf(ACCURACY),
            "accuracy class (DIN 3968)",
        ),
        f(
            "material",
            Text,
            Need::Default(Def::Text("HSS")),
            Any,
            "cutting material, e.g. HSS, PM-HSS, carbide",
        ),
        f(
            "coating",
            Text,
            Need::Default(Def::Text("none")),
            Any,
            "coating, e.g. none, TiN, TiAlN, AlCrN",
        ),
        f(
            "shift_position_mm",
            Real,
            Need::Default(Def::Real(0.0)),
            Range(0.0, 1000.0),
            "current shift position from the start of the usable length, mm",
        ),
        f(
            "shift_step_mm",
            Real,
            Need::Default(Def::Real(0.5)),
            Positive,
            "shift per step, mm",
        ),
        f(
            "parts_per_shift",
            Int,
            Need::Default(Def::Int(1)),
            Range(1.0, 10000.0),
            "parts cut per shift step",
        ),
        f(
            "remaining_life_parts",
            Int,
            Need::Default(Def::Int(0)),
            Range(0.0, 1e9),
            "parts the hob can still cut before regrinding",
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

/// Machines: whole profiles (see [`gearcam_proto::MachineProfile`]) plus `source`.
pub const MACHINES: Library = Library {
    name: "machines",
    table: "machines",
    key: "id",
    doc: "machines: dialect, axis names and sign conventions, M-codes, travels and limits",
    csv: false,
    fields: &[],
};

/// Machining history: cases (problem features → solution → outcome).
pub const CASES: Library = Library {
    name: "cases",
    table: "cases",
    key: "id",
    doc: "machining history: cases (features → solution → outcome) with provenance and confidence",
    csv: true,
    fields: &[
        f("id", Text, Required, Id, "case id"),
        // Problem features.
        f(
            "class",
            Text,
            Need::Default(Def::Text("cylindrical")),
            OneOf(CLASSES),
            "group-technology class",
        ),
        f("machine", Text, Optional, Id, "machine the case was cut on"),
        f("material", Text, Required, Any, "workpiece material"),
        f(
            "material_group",
            Text,
            Required,
            Any,
            "material group (hard constraint)",
        ),
        f(
            "hardness_hb",
            Real,
            Optional,
            Range(50.0, 700.0),
            "hardness when hobbed, HB",
        ),
        f("module_mm", Real, Required, Positive, "normal module, mm"),
        f("teeth", Int, Required, Range(1.0, 10000.0), "teeth"),
        f(
            "helix_angle_deg",
            Real,
            Need::Default(Def::Real(0.0)),
            Range(0.0, 89.0),
            "helix angle magnitude, degrees",
        ),
        f("face_width_mm", Real, Optional, Positive, "face width, mm"),
        f(
            "quality_grade",
            Int,
            Need::Default(Def::Int(8)),
            Range(1.0, 12.0),
            "accuracy grade",
        ),
        f(
            "hob_material",
            Text,
            Need::Default(Def::Text("HSS")),
            Any,
            "hob cutting material",
        ),
        f(
            "hob_coating",
            Text,
            Need::Default(Def::Text("none")),
            Any,
            "hob coating",
        ),
        f(
            "hob_starts",
            Int,
            Need::Default(Def::Int(1)),
            Range(1.0, 12.0),
            "hob starts",
        ),
        f(
            "hob_od_mm",
            Real,
            Optional,
            Positive,
            "hob outside diameter used, mm",
        ),
        f(
            "operation",
            Text,
            Need::Default(Def::Text("finish")),
            OneOf(OPERATIONS),
            "rough or finish hobbing",
        ),
        // Solution.
        f(
            "cutting_speed_m_min",
            Real,
            Required,
            Positive,
            "cutting speed vc, m/min",
        ),
        f(
            "feed_mm_per_rev",
            Real,
            Required,
            Positive,
            "axial feed per workpiece revolution, mm/rev",
        ),
        f("hob_rpm", Real, Optional, Positive, "hob speed used, rpm"),
        f(
            "axial_feed_mm_min",
            Real,
            Optional,
            Positive,
            "axial feed rate used, mm/min",
        ),
        f(
            "radial_feed_mm_min",
            Real,
            Optional,
            Positive,
            "radial (infeed) feed rate, mm/min",
        ),
        f(
            "cuts",
            Int,
            Need::Default(Def::Int(1)),
            Range(1.0, 10.0),
            "number of cuts",
        ),
        f(
            "allowance_mm",
            Real,
            Optional,
            Range(0.0, 20.0),
            "stock / finish allowance, mm",
        ),
        f(
            "shifting",
            Bool,
            Need::Default(Def::Bool(false)),
            Any,
            "hob shifted during the job",
        ),
        f(
            "cut_mode",
            Text,
            Optional,
            OneOf(CUT_MODES),
            "conventional or climb",
        ),
        // Outcome and trust.
        f(
            "outcome",
            Text,
            Need::Default(Def::Text("unknown")),
            OneOf(OUTCOMES),
            "ok, rework, scrap or unknown",
        ),
        f(
            "quality_achieved",
            Int,
            Optional,
            Range(1.0, 12.0),
            "grade measured",
        ),
        f("notes", Text, Need::Default(Def::Text("")), Any, "remarks"),
        f(
            "confidence",
            Real,
            Required,
            Range(0.0, 1.0),
            "how far to trust the case, 0–1",
        ),
        f(
            "provenance",
            Text,
            Required,
            Any,
            "where the values come from",
        ),
        f(
            "job_id",
            Text,
            Optional,
            Id,
            "the confirmed job it came from",
        ),
        f(
            "created_at_ms",
            Int,
            Need::Default(Def::Int(0)),
            Range(0.0, 1e15),
            "when recorded, ms since the epoch",
        ),
    ],
};

/// Jobs the knowledge service planned, and their state.
pub const JOBS: Library = Library {
    name: "jobs",
    table: "jobs",
    key: "job_id",
    doc: "jobs planned by the knowledge service, delivered and confirmed",
    csv: false,
    fields: &[
        f("job_id", Text, Required, Id, "job id"),
        f("part_number", Text, Required, Any, "part number"),
        f("machine", Text, Required, Id, "machine"),
        f(
            "class",
            Text,
            Required,
            OneOf(JOB_CLASSES),
            "class (spiral-face, spiral-groove for the spiral family; wire-punch, wire-die for wire EDM)",
        ),
        f(
            "quantity",
            Int,
            Need::Default(Def::Int(1)),
            Range(0.0, 1e9),
            "parts ordered",
        ),
        f(
            "tool_id",
            Text,
            Required,
            Any,
            "the tool used: the hob, the mill (spiral face milling) or the wire (wire EDM)",
        ),
        f(
            "state",
            Text,
            Need::Default(Def::Text("planned")),
            OneOf(JOB_STATES),
            "planned, delivered, confirmed or refused (a later stage refused it)",
        ),
        f(
            "confidence",
            Real,
            Need::Default(Def::Real(0.0)),
            Range(0.0, 1.0),
            "confidence of the proposal",
        ),
        f("plan_json", Text, Required, Any, "the process plan (JSON)"),
        f("program_name", Text, Optional, Any, "delivered program"),
        f(
            "planned_at_ms",
            Int,
            Need::Default(Def::Int(0)),
            Range(0.0, 1e15),
            "when planned",
        ),
        f(
            "delivered_at_ms",
            Int,
            Optional,
            Range(0.0, 1e15),
            "when delivered",
        ),
        f(
            "confirmed_at_ms",
            Int,
            Optional,
            Range(0.0, 1e15),
            "when confirmed",
        ),
        f(
            "delivered_quantity",
            Int,
            Optional,
            Range(0.0, 1e9),
            "parts actually cut (confirm)",
        ),
        f(
            "case_id",
            Text,
            Optional,
            Id,
            "the case the confirmation made",
        ),
    ],
};

/// Materials and their groups (the case retrieval's hard constraint).
pub const MATERIALS: Library = Library {
    name: "materials",
    table: "materials",
    key: "name",
    doc: "materials: group (hard constraint of retrieval) and typical hardness",
    csv: true,
    fields: &[
        f("name", Text, Required, Any, "material name, e.g. 20CrMnTi"),
        f(
            "material_group",
            Text,
            Required,
            Any,
            "group, e.g. case_hardening_steel",
        ),
        f(
            "hardness_hb",
            Real,
            Optional,
            Range(50.0, 700.0),
            "typical hardness when hobbed, HB",
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

/// Similarity weights of case retrieval, by feature.
pub const WEIGHTS: Library = Library {
    name: "weights",
    table: "cbr_weights",
    key: "feature",
    doc: "similarity weights of case retrieval, by feature",
    csv: false,
    fields: &[
        f(
            "feature",
            Text,
            Required,
            OneOf(crate::cbr::FEATURES),
            "feature",
        ),
        f(
            "weight",
            Real,
            Required,
            Range(0.0, 100.0),
            "weight (0 ignores the feature)",
        ),
        f(
            "source",
            Text,
            Need::Default(Def::Text("user")),
            Any,
            "who set it and why",
        ),
    ],
};
