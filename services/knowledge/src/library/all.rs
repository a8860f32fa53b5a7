//! Every library of the knowledge base in one list, and the lookup by name:
//! the hobbing family's libraries (`defs`), the spiral face milling
//! family's (`milling`) and the wire EDM family's (`wire`). A module of its
//! own, so that the families' definitions depend on the shared helpers and
//! not on one another.

use gearcam_proto::Code;
use gearcam_proto::{JobError, Stage};

use super::defs::{CASES, CLASSES_LIB, HOBS, JOBS, MACHINES, MATERIALS, WEIGHTS, WORKPIECES};
use super::fields::Library;
use super::{milling, wire};

/// Every library, in the order `gearcam kb` lists them.
pub const LIBRARIES: &[Library] = &[
    CLASSES_LIB,
    WORKPIECES,
    HOBS,
    MACHINES,
    CASES,
    JOBS,
    MATERIALS,
    WEIGHTS,
    milling::MILL_MACHINES,
    milling::MILLS,
    milling::MILLING_DATA,
    milling::MILLING_CASES,
    wire::WIRE_MACHINES,
    wire::WIRES,
    wire::WIRE_DATA,
];

/// A library by name.
pub fn library(name: &str) -> Result<Library, JobError> {
    LIBRARIES
        .iter()
        .find(|l| l.name == name)
        .copied()
        .ok_or_else(|| {
            Stage::Knowledge.error(
                Code::UNKNOWN_LIBRARY,
                "library",
                format!("one of {}", names().join(", ")),
                name,
                "there is no such library in the knowledge base",
            )
        })
}

fn names() -> Vec<&'static str> {
    LIBRARIES.iter().map(|l| l.name).collect()
}
