//! The gearcam template service: NC programs from human-readable template source
//! files by expression evaluation (SPEC §4.5, §6).
//!
//! The library is pure: [`Templates`] compiles the templates once and
//! [`Templates::render`] turns a [`MachiningModel`](gearcam_proto::MachiningModel)
//! into an [`NcProgram`](gearcam_proto::NcProgram) named under the controller's
//! rules, hashed, and carrying its provenance (template id and version,
//! knowledge-base cases, model and generator versions). The Zenoh wrapper in
//! [`service`] subscribes to models and publishes the programs.
//!
//! # Layout
//!
//! - [`render`]: the compiled template library, the NC number filters, 840D
//!   program names ([`program_name_840d`], [`check_name_840d`]).
//! - [`source`]: reading a template directory at start (the only file I/O).
//! - [`error`]: [`TemplateError`], a template that cannot be loaded or compiled.
//! - [`service`]: the Zenoh wrapper.
//! - `templates/`: the built-in template sources, e.g. `cylindrical_840d.mpf.j2`,
//!   compiled into the binary.
#![forbid(unsafe_code)]

pub mod builtin;
pub mod engine;
pub mod error;
pub mod expr;
pub mod library;
pub mod nc;
pub mod params;
pub mod render;
pub mod service;
pub mod similarity;
pub mod source;
pub mod stdcode;

pub use error::TemplateError;
pub use render::{
    check_name_840d, format_fixed, program_name_840d, TemplateSource, Templates, DEFAULT_FUEL,
    GENERATOR, MAX_NAME_840D, MAX_PROGRAM_BYTES,
};
