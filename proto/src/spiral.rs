//! The spiral face milling family (docs/spiral.md): the knowledge service's
//! [`SpiralPlan`] and the model service's [`SpiralModel`] (the job file's
//! sections are in [`crate::milling`]).
//!
//! A job names its family in `[job] family`; a spiral job gives `[face]`
//! (a circle or an annulus) or `[groove]` (a planar spiral groove), and may
//! give `[mill]` and `[milling]`. Its plan and model travel on the same keys
//! as hobbing's (`gearcam/v1/jobs/{job}/plan`, `…/model`) with their own
//! envelope kinds (`spiral_plan`, `spiral_model`); every stage dispatches on
//! the kind ([`crate::AnyPlan`], [`crate::AnyModel`]).

use serde::{Deserialize, Serialize};

use crate::cutting::CutMode;
use crate::ids::{JobId, MachineId};
use crate::job::JobRequest;
use crate::milling::{FaceSpec, GrooveSpec, MillKind, SpiralDirection, SpiralProgram};
use crate::model::Warning;
use crate::plan::{CaseRef, Dialect, Source, Sourced};
use crate::Message;

impl SpiralProgram {
    /// The controller dialect the form is written in.
    pub fn dialect(self) -> Dialect {
        match self {
            SpiralProgram::Linuxcnc => Dialect::Linuxcnc,
            _ => Dialect::Fanuc,
        }
    }
}

/// The part of a spiral job, resolved.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum SpiralPart {
    /// A circular or annular face.
    Face(FaceSpec),
    /// A planar spiral groove.
    Groove(GrooveSpec),
}

impl SpiralPart {
    /// The workpiece material.
    pub fn material(&self) -> &str {
        match self {
            SpiralPart::Face(f) => &f.material,
            SpiralPart::Groove(g) => &g.material,
        }
    }

    /// Depth to cut, mm.
    pub fn depth_mm(&self) -> f64 {
        match self {
            SpiralPart::Face(f) => f.depth_mm,
            SpiralPart::Groove(g) => g.depth_mm,
        }
    }

    /// The outermost radius of material touched, mm.
    pub fn outer_radius_mm(&self) -> f64 {
        match self {
            SpiralPart::Face(f) => f.outer_radius_mm,
            SpiralPart::Groove(g) => g.outer_radius_mm + g.width_mm / 2.0,
        }
    }

    /// `face` or `groove`.
    pub fn kind(&self) -> &'static str {
        match self {
            SpiralPart::Face(_) => "face",
            SpiralPart::Groove(_) => "groove",
        }
    }
}

/// A milling machine's profile (knowledge base, `mill_machines`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MillProfile {
    /// Machine id, e.g. `M01`.
    pub id: MachineId,
    /// Name, e.g. `Vertical mill, FANUC 0i-MF`.
    pub name: String,
    /// Controller, e.g. `FANUC 0i-MF`.
    pub controller: String,
    /// NC dialect: `fanuc` or `linuxcnc`.
    pub dialect: Dialect,
    /// The program form used when the job does not choose one.
    pub default_program: SpiralProgram,
    /// Forms the controller runs.
    pub programs: Vec<SpiralProgram>,
    /// Highest spindle speed, rpm.
    pub max_rpm: f64,
    /// Highest cutting feed, mm/min.
    pub max_feed_mm_min: f64,
    /// Largest tool-centre radius the X/Y travel reaches about the face's
    /// centre (the work offset is the face's centre), mm.
    pub max_radius_mm: f64,
    /// Safe height above the face, mm.
    pub safe_z_mm: f64,
    /// Work offset, e.g. `G54`.
    pub work_offset: String,
}

/// A milling tool from the library or the job file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MillData {
    /// Library id (`job` when given inline).
    pub id: String,
    /// Face mill or end mill.
    pub kind: MillKind,
    /// Cutting radius, mm.
    pub radius_mm: f64,
    /// Corner radius, mm.
    pub corner_radius_mm: f64,
    /// Flutes.
    pub flutes: u32,
    /// Cutting material, e.g. `carbide`.
    pub material: String,
    /// Where the data come from.
    pub source: Source,
}

/// The process of a spiral job, each number with its provenance.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MillingProcess {
    /// Largest step-over, mm.
    pub step_over_mm: Sourced,
    /// Depth passes.
    pub passes: u32,
    /// Cutting speed, m/min.
    pub cutting_speed_m_min: Sourced,
    /// Feed per tooth, mm.
    pub feed_per_tooth_mm: Sourced,
    /// Outside-in or inside-out.
    pub direction: SpiralDirection,
    /// Climb or conventional.
    pub cut_mode: CutMode,
    /// Outer overtravel, mm.
    pub outer_overtravel_mm: Sourced,
    /// Inner overtravel, mm.
    pub inner_overtravel_mm: Sourced,
    /// Start angle, degrees.
    pub start_angle_deg: Sourced,
    /// Chord/arc tolerance, mm.
    pub tolerance_mm: Sourced,
    /// Program form.
    pub program: SpiralProgram,
}

/// Message: the knowledge service's plan of a spiral job.
///
/// Key `gearcam/v1/jobs/{job}/plan` (kind `spiral_plan`); published by the
/// knowledge service, subscribed by the model service.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SpiralPlan {
    /// The job's id.
    pub job_id: JobId,
    /// The request as asked.
    pub request: JobRequest,
    /// The face or groove.
    pub part: SpiralPart,
    /// The machine.
    pub machine: MillProfile,
    /// The tool.
    pub tool: MillData,
    /// The process.
    pub process: MillingProcess,
    /// Cases the proposal used, most similar first.
    pub cases: Vec<CaseRef>,
    /// Confidence of the proposal, 0–1.
    pub confidence: f64,
}

impl Message for SpiralPlan {
    const KIND: &'static str = "spiral_plan";
}

/// The spiral's figures (`model.spiral` in `gearcam check --json`); the
/// face's centre is the origin.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SpiralFigures {
    /// Region's outer radius, mm.
    pub outer_radius_mm: f64,
    /// Region's inner radius, mm (0: a full circle).
    pub inner_radius_mm: f64,
    /// Tool radius, mm.
    pub tool_radius_mm: f64,
    /// Turns.
    pub turns: u32,
    /// Step-over used, mm.
    pub step_over_mm: f64,
    /// Tool-centre start radius R1, mm.
    pub start_radius_mm: f64,
    /// Tool-centre end radius R2, mm.
    pub end_radius_mm: f64,
    /// Start angle θ0, degrees.
    pub start_angle_deg: f64,
    /// +1 counter-clockwise, −1 clockwise, seen from +Z.
    pub sense: i8,
    /// Chord angle step, degrees.
    pub angle_step_deg: f64,
    /// Path length along the spiral per depth pass, mm.
    pub path_length_mm: f64,
    /// Motion blocks of the program along the spiral, per pass.
    pub blocks: u32,
    /// Tangent arcs within the tolerance, per pass.
    pub arcs: u32,
    /// Chords within the tolerance, per pass.
    pub chords: u32,
}

/// The cutting data of the program.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SpiralCut {
    /// Total depth below the face, mm.
    pub depth_mm: f64,
    /// Depth passes.
    pub passes: u32,
    /// Feed along the spiral, mm/min.
    pub feed_mm_min: f64,
    /// Plunge feed, mm/min.
    pub plunge_feed_mm_min: f64,
    /// Spindle speed, rpm.
    pub spindle_rpm: f64,
    /// Safe height, mm.
    pub safe_z_mm: f64,
    /// Chord/arc tolerance, mm.
    pub tolerance_mm: f64,
}

/// The coverage check (`coverage` in `gearcam check --json`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CoverageCheck {
    /// Every point of the region lies inside the tool's disc somewhere.
    pub ok: bool,
    /// The largest distance from a region point to the nearest tool disc
    /// (0 when covered), mm.
    pub max_gap_mm: f64,
    /// Where that point is, mm.
    pub worst_point_mm: (f64, f64),
    /// The largest deviation of the program's chords or arcs from the spiral, mm.
    pub max_deviation_mm: f64,
    /// Points checked (rays for a groove); 0 for a face whose coverage is
    /// proved in closed form, with no points sampled.
    pub samples: u64,
}

/// A groove's figures.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct GrooveFigures {
    /// Width (the tool's diameter), mm.
    pub width_mm: f64,
    /// Pitch, mm.
    pub pitch_mm: f64,
    /// Land between turns, mm.
    pub land_mm: f64,
}

/// Message: the machining model of a spiral job.
///
/// Key `gearcam/v1/jobs/{job}/model` (kind `spiral_model`); published by the
/// model service, subscribed by the template service and the agents.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SpiralModel {
    /// The job's id.
    pub job_id: JobId,
    /// The plan it was computed from.
    pub plan: SpiralPlan,
    /// The spiral.
    pub spiral: SpiralFigures,
    /// The groove (groove jobs only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub groove: Option<GrooveFigures>,
    /// Cutting data.
    pub cut: SpiralCut,
    /// Coverage (faces) and deviation.
    pub coverage: CoverageCheck,
    /// Cutting time of one part, min.
    pub part_time_min: f64,
    /// Warnings.
    pub warnings: Vec<Warning>,
    /// Version of the model code.
    pub model_version: String,
}

impl Message for SpiralModel {
    const KIND: &'static str = "spiral_model";
}
