//! The gearcam wire protocol: every message, id and key expression the services
//! exchange over Zenoh, and the codec that puts them on the wire.
//!
//! # Layout
//!
//! - [`ids`]: validating id newtypes ([`JobId`], [`MachineId`], [`HobId`]).
//! - [`keys`]: key-expression builders; the only place key strings are spelled.
//! - [`codec`]: MessagePack with field names in a versioned envelope.
//! - [`job`]: the job file / [`JobRequest`].
//! - [`plan`]: machine profiles, hobs, the [`ProcessPlan`].
//! - [`model`]: geometry and the [`MachiningModel`].
//! - [`program`]: [`NcProgram`], [`DeliveryReceipt`], [`JobEvent`] and typed [`JobError`]s.
//! - [`naming`]: controllers' program naming rules.
//! - [`error`]: id and codec errors.
//!
//! `proto/README.md` documents the same for readers in other languages.
#![forbid(unsafe_code)]

pub mod codec;
pub mod error;
pub mod ids;
pub mod job;
pub mod keys;
pub mod model;
pub mod naming;
pub mod plan;
pub mod program;

pub use codec::{decode, encode, Message, MAX_MESSAGE_BYTES, SCHEMA_VERSION};
pub use error::{CodecError, IdError};
pub use ids::{HobId, JobId, MachineId};
pub use job::{
    CutMode, GearSpec, Hand, HobSpec, JobHeader, JobRequest, JobSpec, Options, ProcessOverrides,
};
pub use model::{Geometry, Kinematics, MachiningModel, Position, Positions, Ratio, Warning};
pub use plan::{
    AxisNames, CaseRef, Dialect, HobData, MCodes, MachineLimits, MachineProfile, MachineSettings,
    ProcessData, ProcessPlan, Source, Sourced,
};
pub use program::{
    now_ms, DeliveryReceipt, EventKind, JobError, JobEvent, NcProgram, Stage, TemplateRef,
};
