//! The knowledge base's libraries as records: list, read, add, change, remove,
//! each write validated field by field.
//!
//! A record is a JSON object (field name → value). Every flat library is
//! described by a table of [`Field`]s (name, type, required or default,
//! allowed range); the same description drives the SQL, the validation, the
//! CSV columns and the CLI's value parsing, so a new field is added in one
//! place. Machines are nested profiles ([`gearcam_proto::MachineProfile`])
//! stored as JSON and validated by deserialising them.
//!
//! These generic records serve the libraries' own machinery (validation on
//! add and edit, CSV, the `kb` queryable and CLI). Planning, retrieval, hob
//! matching and the learning loop read the typed records of
//! [`crate::records`] instead.
//!
//! Every error is a [`JobError`](gearcam_proto::JobError) (stage
//! `knowledge`) naming the field, what was expected and what was given.
//!
//! # Layout
//!
//! - `fields`: the machinery: [`Record`], [`Field`] and its [`Kind`],
//!   [`Check`], [`Need`] and [`Def`], [`Library`], text values
//!   ([`parse_value`], [`cell`]).
//! - `defs`: the library definitions ([`LIBRARIES`]) and [`library`] by name;
//!   `milling`: those of the spiral face milling family.
//! - `validate`: [`validate`], field by field and across fields, and whole
//!   machine profiles.
//! - `onwire`: records as the bus carries them and back
//!   ([`record_from_wire`], [`record_to_wire`]).
//! - `store`: the SQL reads and writes ([`list`], [`get`], [`keys`], [`add`],
//!   [`edit`], [`remove`]).

mod all;
mod defs;
mod fields;
mod milling;
mod onwire;
mod store;
mod validate;
mod wire;

pub use all::{library, LIBRARIES};
pub use defs::{CASES, CLASSES_LIB, HOBS, JOBS, MACHINES, MATERIALS, WEIGHTS, WORKPIECES};
pub use fields::{cell, parse_value, Check, Def, Field, Kind, Library, Need, Outcome, Record};
pub use milling::{MILLING_CASES, MILLING_DATA, MILLS, MILL_MACHINES};
pub use onwire::{record_from_wire, record_to_wire};
pub use store::{add, edit, get, keys, list, machine_error, remove};
pub use validate::validate;
pub use wire::{WIRES, WIRE_DATA, WIRE_MACHINES};
