//! The program forms written by code rather than by a template of the
//! library: every form of the spiral face milling and wire EDM families.
//! Their programs name them in the header as templates do (`template
//! spiral-fanuc-macro v1`), so `gearcam templates list` and `show` list them
//! beside the library's templates, with what they write and what checks
//! them. Their version moves with gearcam's (a change of what a form
//! writes bumps [`SPIRAL_FORMS_VERSION`] or [`WIRE_FORMS_VERSION`]).

use gearcam_proto::{Dialect, SpiralProgram, WireProgram};
use serde::Serialize;

/// The generator's version of the spiral forms, written into the program's
/// template reference (`spiral-{form}` v1).
pub const SPIRAL_FORMS_VERSION: u32 = 1;

/// The generator's version of the wire forms, written into the program's
/// template reference (`wire-{form}` v1).
pub const WIRE_FORMS_VERSION: u32 = 1;

/// A program form written by code.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GeneratedForm {
    /// The id programs name, e.g. `spiral-fanuc-macro`.
    pub id: String,
    /// The part family.
    pub family: &'static str,
    /// The controller dialect it writes.
    pub dialect: Dialect,
    /// Its version.
    pub version: u32,
    /// What it writes.
    pub writes: &'static str,
    /// What checks each of its programs before it leaves.
    pub checked_by: &'static str,
    /// Always true: not a template of the library (no decision table, not
    /// imported or edited with `gearcam templates import`).
    pub generated: bool,
}

/// The id a spiral program names its form by, e.g. `spiral-fanuc-macro`.
pub fn spiral_id(form: SpiralProgram) -> String {
    format!("spiral-{}", form.as_str())
}

/// The id a wire program names its form by, e.g. `wire-iso-wire`.
pub fn wire_id(form: WireProgram) -> String {
    format!("wire-{}", form.as_str())
}

/// Every form written by code, spiral forms first.
pub fn generated() -> Vec<GeneratedForm> {
    let spiral = SpiralProgram::ALL.into_iter().map(|form| {
        let (dialect, writes) = match form {
            SpiralProgram::FanucMacro => (
                Dialect::Fanuc,
                "a FANUC Macro B program: the variable table, G16 polar chords in a WHILE loop per depth pass",
            ),
            SpiralProgram::FanucArcs => (
                Dialect::Fanuc,
                "a FANUC program of tangent-continuous G02/G03 arcs fitted to the spiral",
            ),
            SpiralProgram::FanucChords => (
                Dialect::Fanuc,
                "a FANUC program of G01 chords, every chord in the file",
            ),
            SpiralProgram::Linuxcnc => (
                Dialect::Linuxcnc,
                "a LinuxCNC program: named parameters, an o-word loop, polar @/^ words",
            ),
        };
        GeneratedForm {
            id: spiral_id(form),
            family: "spiral-face",
            dialect,
            version: SPIRAL_FORMS_VERSION,
            writes,
            checked_by: "its replay against the model: every move from the first block to M30 (docs/spiral.md)",
            generated: true,
        }
    });
    let wire = [
        (
            WireProgram::ThreeB,
            Dialect::Wire3b,
            "a 3B program of the wire's path in µm blocks, a quarter or half with the control's rotation",
        ),
        (
            WireProgram::FourB,
            Dialect::Wire3b,
            "a 4B program of the part's outline with each arc's radius and convexity",
        ),
        (
            WireProgram::IsoWire,
            Dialect::WireIso,
            "an ISO wire program of the outline with G41/G42, a turned section as a subprogram under G68",
        ),
    ]
    .into_iter()
    .map(|(form, dialect, writes)| GeneratedForm {
        id: wire_id(form),
        family: "wire-edm",
        dialect,
        version: WIRE_FORMS_VERSION,
        writes,
        checked_by: "its certificate: every block replayed as the control runs it, measured against the outline (docs/wire.md)",
        generated: true,
    });
    spiral.chain(wire).collect()
}

/// The form of `id`, if code writes one of that id.
pub fn find(id: &str) -> Option<GeneratedForm> {
    generated().into_iter().find(|f| f.id == id)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The ids are the ones the families' programs put in their headers.
    #[test]
    fn every_form_is_listed_under_the_id_its_programs_name() {
        let ids: Vec<String> = generated().into_iter().map(|f| f.id).collect();
        assert_eq!(
            ids,
            [
                "spiral-fanuc-macro",
                "spiral-fanuc-arcs",
                "spiral-fanuc-chords",
                "spiral-linuxcnc",
                "wire-3b",
                "wire-4b",
                "wire-iso-wire"
            ]
        );
        assert!(find("wire-iso-wire").is_some_and(|f| f.dialect == Dialect::WireIso));
        assert!(find("cylindrical_840d").is_none());
    }
}
