//! The gearcam template service: NC programs from the standard-template method
//! of seed 000 (docs/programs.md#standard-templates), checked before they leave.
//!
//! Standard NC code per gear class and controller dialect (`standard/*.tpl`, one
//! six-tuple record ⟨ID, O, P, S, T, N⟩ per line) is split into the six control
//! modules, compared line by line with the literal similarity, and stored in a
//! SQLite library as similar components (shared by classes, stored once) and
//! non-similar ones, versioned. A class's template is assembled from its
//! components and compiled once; the expression-driven algorithm instantiates
//! it for a [`MachiningModel`](gearcam_proto::MachiningModel); the program is
//! parsed back and its axis motion simulated (the path check) before it becomes
//! an [`NcProgram`](gearcam_proto::NcProgram) with its provenance and hash.
//!
//! # Layout
//!
//! - [`stdcode`]: the template source format (records, modules, scopes).
//! - [`expr`]: the expression language (bounded, side-effect free, NC numbers).
//! - [`params`]: the parameter table a template reads, by scope.
//! - [`engine`]: compilation and the expression-driven algorithm.
//! - [`similarity`]: Sim = K/(M+N−K) and the similar / non-similar split.
//! - [`library`]: the SQLite template library (components, versions, decision
//!   tables, assembly).
//! - [`builtin`]: the shipped standard code, compiled into the binary.
//! - [`render`]: [`Templates`]: the compiled library, rendering a model into a
//!   checked program, program names.
//! - [`source`]: reading a directory of template files (the only file I/O
//!   besides the library).
//! - [`error`]: [`TemplateError`], a template that cannot be loaded or compiled.
//! - [`spiral`]: the spiral face milling family's programs.
//! - [`wire`]: the wire EDM family's programs (3B, 4B, ISO wire), certified by their replay.
//! - [`forms`]: the program forms written by code (spiral and wire), listed
//!   beside the library's templates.
//! - [`service`]: the Zenoh wrapper.
//!
//! Why our own expression language rather than a crate: `EXPRESSIONS.md`.
#![forbid(unsafe_code)]

pub mod builtin;
pub mod engine;
pub mod error;
pub mod expr;
pub mod forms;
pub mod library;
pub mod params;
pub mod render;
pub mod service;
pub mod similarity;
pub mod simulation;
pub mod source;
pub mod spiral;
pub mod stdcode;
pub mod wire;

pub use error::TemplateError;
pub use render::{
    check_name_840d, format_fixed, program_name_840d, TemplateSource, Templates, DEFAULT_FUEL,
    GENERATOR, MAX_NAME_840D, MAX_PROGRAM_BYTES,
};
