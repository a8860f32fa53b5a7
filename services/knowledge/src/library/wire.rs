//! The library definitions of the wire EDM family: wire EDM machines,
//! wires and starting technology (docs/wire.md#knowledge-base).

use super::defs::f;
use super::fields::{Check, Def, Kind, Library, Need};

use Check::{Any, Id, OneOf, Positive, Range};
use Kind::{Bool, Real, Text};
use Need::Required;

const WIRE_DIALECTS: &[&str] = &["wire3b", "wireiso"];
const WIRE_FORMS: &[&str] = &["3b", "4b", "iso-wire"];

const SOURCE: super::fields::Field = f(
    "source",
    Text,
    Need::Default(Def::Text("user")),
    Any,
    "where the data comes from",
);

/// Wire EDM machines.
pub const WIRE_MACHINES: Library = Library {
    name: "wire-machines",
    table: "wire_machines",
    key: "id",
    doc: "wire EDM machines: control, program forms, default wire, thickness and reach",
    csv: true,
    fields: &[
        f("id", Text, Required, Id, "machine id, e.g. W01"),
        f("name", Text, Required, Any, "human name"),
        f("controller", Text, Required, Any, "control, e.g. HF 3B/4B"),
        f(
            "dialect",
            Text,
            Required,
            OneOf(WIRE_DIALECTS),
            "the dialect its agent stores: wire3b or wireiso",
        ),
        f(
            "programs",
            Text,
            Required,
            Any,
            "program forms the control runs, space-separated: 3b 4b iso-wire",
        ),
        f(
            "default_program",
            Text,
            Required,
            OneOf(WIRE_FORMS),
            "the form used when the job names none",
        ),
        f(
            "wire",
            Text,
            Required,
            Id,
            "the wire threaded when the job names none (library wires)",
        ),
        f(
            "max_thickness_mm",
            Real,
            Required,
            Positive,
            "thickest plate, mm",
        ),
        f(
            "max_radius_mm",
            Real,
            Required,
            Positive,
            "largest contour radius about the start hole the X/Y travel reaches, mm",
        ),
        f(
            "rotates",
            Bool,
            Need::Default(Def::Bool(true)),
            Any,
            "whether the control repeats a section of blocks turned (3B/4B rotate, ISO G68); without it every program is written whole",
        ),
        SOURCE,
    ],
};

/// Wires.
pub const WIRES: Library = Library {
    name: "wires",
    table: "wires",
    key: "id",
    doc: "wires: material, diameter and the spark gap it cuts with",
    csv: true,
    fields: &[
        f("id", Text, Required, Id, "wire id, e.g. MO-018"),
        f(
            "material",
            Text,
            Required,
            Any,
            "wire material, e.g. molybdenum, brass",
        ),
        f(
            "diameter_mm",
            Real,
            Required,
            Range(0.02, 0.5),
            "diameter, mm",
        ),
        f(
            "spark_gap_mm",
            Real,
            Required,
            Range(0.0, 0.1),
            "spark gap per side, mm",
        ),
        SOURCE,
    ],
};

/// Starting technology of wire EDM, by wire material and plate material group.
pub const WIRE_DATA: Library = Library {
    name: "wire-data",
    table: "wire_data",
    key: "id",
    doc: "starting wire EDM technology by wire material and plate material group, with provenance",
    csv: true,
    fields: &[
        f("id", Text, Required, Id, "row id"),
        f("wire_material", Text, Required, Any, "wire material"),
        f(
            "material_group",
            Text,
            Required,
            Any,
            "plate material group, e.g. tool_steel, or any",
        ),
        f("pulse_on_us", Real, Required, Positive, "pulse on time, µs"),
        f(
            "pulse_off_us",
            Real,
            Required,
            Positive,
            "pulse off time, µs",
        ),
        f("current_a", Real, Required, Positive, "peak current, A"),
        f(
            "cutting_rate_mm2_min",
            Real,
            Required,
            Positive,
            "cutting rate, mm²/min (feed times thickness)",
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
