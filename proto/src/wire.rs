//! The wire EDM family (docs/wire.md): the punch or die of a spur gear cut
//! by wire. The job file gives `[die]` and may give `[wire]`
//! ([`crate::die`]); the knowledge service's [`WirePlan`] and the model
//! service's [`WireModel`] travel on the same keys as the other families'
//! under their own kinds (`wire_plan`, `wire_model`).

use serde::{Deserialize, Serialize};

use crate::die::{DiePart, DieSpec, WireProgram};
use crate::ids::{JobId, MachineId};
use crate::job::JobRequest;
use crate::model::Warning;
use crate::plan::{CaseRef, Dialect, Sourced};
use crate::Message;

impl WireProgram {
    /// The dialect of a control that runs the form.
    pub fn dialect(self) -> Dialect {
        match self {
            WireProgram::ThreeB | WireProgram::FourB => Dialect::Wire3b,
            WireProgram::IsoWire => Dialect::WireIso,
        }
    }
}

/// A wire EDM machine (knowledge base, `wire-machines`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct WireMachine {
    /// Machine id, e.g. `W01`.
    pub id: MachineId,
    /// Name.
    pub name: String,
    /// Controller, e.g. `HF 3B/4B`.
    pub controller: String,
    /// The dialect its agent stores (`wire3b` or `wireiso`).
    pub dialect: Dialect,
    /// Forms the control runs.
    pub programs: Vec<WireProgram>,
    /// The form used when the job does not choose one.
    pub default_program: WireProgram,
    /// Largest plate thickness, mm.
    pub max_thickness_mm: f64,
    /// Largest contour the X/Y travel reaches about the start hole, mm
    /// (a radius).
    pub max_radius_mm: f64,
    /// The control repeats a section of blocks turned (a 3B/4B rotate
    /// instruction, ISO `G68`); without it every program is written whole.
    /// Absent in a message of an older writer: true, as every wire machine
    /// then was.
    #[serde(default = "rotates_by_default")]
    pub rotates: bool,
}

fn rotates_by_default() -> bool {
    true
}

/// The wire and the starting technology, each with its provenance.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct WireProcess {
    /// Wire id (`job` when given inline).
    pub wire: String,
    /// Wire diameter, mm.
    pub wire_diameter_mm: Sourced,
    /// Spark gap per side, mm.
    pub spark_gap_mm: Sourced,
    /// Pulse on time, µs.
    pub pulse_on_us: Sourced,
    /// Pulse off time, µs.
    pub pulse_off_us: Sourced,
    /// Peak current, A.
    pub current_a: Sourced,
    /// Cutting speed, mm²/min (area: feed times thickness).
    pub cutting_rate_mm2_min: Sourced,
    /// Program form.
    pub program: WireProgram,
    /// Every tooth written (no rotation).
    pub whole: bool,
}

impl WireProcess {
    /// Wire radius plus spark gap: how far the wire's centre runs from the
    /// part's outline, mm.
    pub fn offset_mm(&self) -> f64 {
        self.wire_diameter_mm.value / 2.0 + self.spark_gap_mm.value
    }
}

/// Message: the knowledge service's plan of a wire job.
///
/// Key `gearcam/v1/jobs/{job}/plan` (kind `wire_plan`); published by the
/// knowledge service, subscribed by the model service.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct WirePlan {
    /// The job's id.
    pub job_id: JobId,
    /// The request as asked.
    pub request: JobRequest,
    /// The gear and the part.
    pub die: DieSpec,
    /// The machine.
    pub machine: WireMachine,
    /// The wire and the technology.
    pub process: WireProcess,
    /// Records the proposal used, most similar first.
    pub cases: Vec<CaseRef>,
    /// Confidence of the proposal, 0–1.
    pub confidence: f64,
}

impl Message for WirePlan {
    const KIND: &'static str = "wire_plan";
}

/// The die's figures and the fit's certificate (`model.die` in `gearcam
/// check --json`); the gear's centre is the origin.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DieFigures {
    /// `punch` or `die`.
    pub part: DiePart,
    /// Teeth.
    pub teeth: u32,
    /// Module, mm.
    pub module_mm: f64,
    /// Pressure angle, degrees.
    pub pressure_angle_deg: f64,
    /// Profile shift.
    pub profile_shift: f64,
    /// Pitch radius, mm.
    pub pitch_radius_mm: f64,
    /// Base radius, mm.
    pub base_radius_mm: f64,
    /// Tip radius, mm.
    pub tip_radius_mm: f64,
    /// Root radius, mm.
    pub root_radius_mm: f64,
    /// Where the fillet meets the flank, mm.
    pub form_radius_mm: f64,
    /// The pair's centre distance (with `mating_teeth`), mm.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub centre_distance_mm: Option<f64>,
    /// The flank is undercut.
    pub undercut: bool,
    /// Tooth thickness at the tip circle, mm.
    pub tip_thickness_mm: f64,
    /// Wire radius plus spark gap, mm.
    pub offset_mm: f64,
    /// Arcs per flank.
    pub arcs_per_flank: u32,
    /// Arcs per fillet.
    pub arcs_per_fillet: u32,
    /// Arcs of the whole outline.
    pub outline_arcs: u32,
    /// The flank's tolerance, µm.
    pub flank_tolerance_um: f64,
    /// The fillet's tolerance, µm.
    pub fillet_tolerance_um: f64,
    /// The largest deviation of the wire path from where it belongs (the
    /// outline set off by the offset), over the whole program as replayed,
    /// µm.
    pub max_deviation_um: f64,
    /// On the flanks and tips, µm.
    pub flank_deviation_um: f64,
    /// On the fillets and roots, µm.
    pub fillet_deviation_um: f64,
    /// The replayed path's end against its start, µm.
    pub closure_um: f64,
    /// Motion blocks of the program.
    pub blocks: u32,
    /// Program size, bytes.
    pub bytes: u32,
    /// Teeth written; the control's rotation repeats them.
    pub teeth_written: u32,
    /// Path length of the cut (the outline set off), mm.
    pub path_length_mm: f64,
    /// Cutting time, min.
    pub cutting_time_min: f64,
}

/// Message: the machining model of a wire job.
///
/// Key `gearcam/v1/jobs/{job}/model` (kind `wire_model`); published by the
/// model service, subscribed by the template service and the agents.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct WireModel {
    /// The job's id.
    pub job_id: JobId,
    /// The plan it was computed from.
    pub plan: WirePlan,
    /// Figures and certificate.
    pub die: DieFigures,
    /// Warnings.
    pub warnings: Vec<Warning>,
    /// Version of the model code.
    pub model_version: String,
}

impl Message for WireModel {
    const KIND: &'static str = "wire_model";
}
