//! The gearcam wire protocol: every message, id and key expression the services
//! exchange over Zenoh, and the codec that puts them on the wire.
//!
//! # Layout
//!
//! - [`class`]: the group-technology gear classes and [`classify`].
//! - [`ids`]: validating id newtypes ([`JobId`], [`MachineId`], [`HobId`]).
//! - [`keys`]: key-expression builders; the only place key strings are spelled.
//! - [`codec`]: MessagePack with field names in a versioned envelope.
//! - [`job`]: the job typed by its part family ([`JobSpec`]), the job file's
//!   shape ([`JobFile`]) and the [`JobRequest`].
//! - [`family`]: the plan and model of any family ([`AnyPlan`], [`AnyModel`]).
//! - [`hobbing`]: the hobbing family's job sections (`[gear]`, `[hob]`, …).
//! - [`plan`]: machine profiles, hobs, the [`ProcessPlan`].
//! - [`model`]: geometry and the [`MachiningModel`].
//! - [`program`]: [`NcProgram`], [`DeliveryReceipt`], [`JobEvent`].
//! - [`cutting`]: what the families share ([`CutMode`]).
//! - [`milling`]: the spiral face milling family's job sections.
//! - [`spiral`]: its [`SpiralPlan`] and [`SpiralModel`].
//! - [`die`]: the wire EDM family's job sections (`[die]`, `[wire]`).
//! - [`wire`]: its [`WirePlan`] and [`WireModel`].
//! - [`naming`]: controllers' program naming rules.
//! - [`delivery`]: station journal states and queries, agent replies and program history.
//! - [`error`]: typed [`JobError`]s and the [`Stage`] that found them, id and codec errors.
//!
//! `proto/README.md` documents the same for readers in other languages.
#![forbid(unsafe_code)]

pub mod class;
pub mod codec;
pub mod codes;
pub mod cutting;
pub mod delivery;
pub mod die;
pub mod error;
pub mod family;
pub mod hobbing;
pub mod ids;
pub mod job;
pub mod keys;
pub mod milling;
pub mod model;
pub mod naming;
pub mod plan;
pub mod program;
pub mod simulation;
pub mod spiral;
pub mod wire;

pub use class::{classify, GearClass};
pub use codec::{decode, encode, Incoming, Message, MAX_MESSAGE_BYTES, SCHEMA_VERSION};
pub use codes::Code;
pub use delivery::{
    CancelRequest, DeliveryReply, JobIds, JobState, JobStatus, ProgramHistory, ProgramRef,
    ProgramText, ProgramVersion, StationReply, StoreReply, StoreRequest,
};
pub use die::{Cutter, DiePart, DieSpec, WireOverrides, WireProgram};
pub use error::{CodecError, IdError, JobError, Problem, Stage};
pub use family::{AnyModel, AnyPlan};
pub use ids::{HobId, JobId, MachineId};
pub use job::{
    part_number_problem, ConeSpec, CrowningShape, CrowningSpec, CurvedToothSpec, CutMode, Family,
    FamilySpec, ForeignSections, GearSpec, Hand, HobSpec, HobbingSpec, Infeed, JobFile, JobHeader,
    JobRequest, JobSpec, LargeEnd, MateSpec, Operation, Options, ProcessOverrides, ShiftMode,
    ShiftSpec, SpiralSpec, UnitSpec, WireSpec, WormInfeed, WormWheelSpec, MAX_PART_NUMBER,
};
pub use milling::{
    FaceSpec, GrooveSpec, MillKind, MillSpec, MillingOverrides, SpiralDirection, SpiralProgram,
};
pub use model::{
    ConeModel, CouplingFactors, CrowningModel, Cut, Explained, Geometry, Kinematics,
    MachiningModel, Move, MoveKind, Origin, PairGeometry, PartShift, Position, Positions, Ratio,
    ShiftPlan, UnitModel, Warning, WormModel,
};
pub use plan::{
    AxisNames, CaseRef, Dialect, Envelope, GCodeSystem, HobData, MCodes, MachineLimits,
    MachineProfile, MachineSettings, ParameterBlock, ProcessData, ProcessPlan, Source, Sourced,
    WorkpieceRef,
};
pub use program::{
    now_ms, utc_text, DeliveryReceipt, EventKind, JobEvent, NcProgram, PathCheck, PathFinding,
    TemplateRef,
};
pub use simulation::SimulationReport;
pub use spiral::{
    CoverageCheck, GrooveFigures, MillData, MillProfile, MillingProcess, SpiralCut, SpiralFigures,
    SpiralModel, SpiralPart, SpiralPlan,
};
pub use wire::{DieFigures, WireMachine, WireModel, WirePlan, WireProcess};
