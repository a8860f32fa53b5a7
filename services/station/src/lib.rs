//! The planning station: it journals submitted jobs durably (SQLite), drives
//! them through the pipeline, follows their events and re-drives every
//! unfinished job until the machine's agent has acknowledged its program.
//!
//! - [`journal`]: the durable job journal.
//! - [`service`]: the station on the bus: submit, status, drive, re-drive.
//!
//! The `gearcam station` command runs it as its own process; `gearcam up` and
//! `gearcam demo` run it beside the other services.
#![forbid(unsafe_code)]

pub mod journal;
pub mod service;

pub use service::{run, StationConfig, StationError};
