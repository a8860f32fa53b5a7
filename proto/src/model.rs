//! The machining model: geometry and hobbing kinematics computed by the model service.

use serde::{Deserialize, Serialize};

use crate::codec::Message;
use crate::ids::JobId;
use crate::plan::ProcessPlan;

/// Gear geometry (ISO 21771), all diameters in mm.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Geometry {
    /// Reference diameter d = z·mn / cos β.
    pub d_mm: f64,
    /// Base diameter db = d·cos αt.
    pub db_mm: f64,
    /// Tip diameter da = d + 2·mn·(ha* + x).
    pub da_mm: f64,
    /// Root diameter df = d − 2·mn·(ha* + c* − x).
    pub df_mm: f64,
    /// Transverse module mt = mn / cos β.
    pub mt_mm: f64,
    /// Transverse pressure angle αt, degrees.
    pub alpha_t_deg: f64,
    /// Whole depth h = (2·ha* + c*)·mn.
    pub whole_depth_mm: f64,
    /// Lead of the helix Pz = π·mn·z / sin β (absent for spur gears).
    pub lead_mm: Option<f64>,
}

/// One machine position: X radial centre distance, Z axial hob-centre height, mm.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Position {
    /// X, mm.
    pub x_mm: f64,
    /// Z, mm.
    pub z_mm: f64,
}

/// The five positions of the hobbing cycle (patent step 3②).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[allow(non_snake_case)]
pub struct Positions {
    /// Start and end of the cycle.
    pub A: Position,
    /// Rapid approach point.
    pub B: Position,
    /// Infeed to depth; gearbox coupled.
    pub C: Position,
    /// End of the axial feed.
    pub D: Position,
    /// Retract point.
    pub E: Position,
}

/// The exact coupling ratio of the electronic gearbox: table turns per hob turn.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct Ratio {
    /// Numerator: hob starts z0.
    pub num: u32,
    /// Denominator: gear teeth z.
    pub den: u32,
}

/// Hobbing kinematics of one job (SPEC §4.3).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Kinematics {
    /// Hob head swivel γ, degrees (SPEC §4.3 sign: −(|β| ∓ |γ0|)).
    pub swivel_deg: f64,
    /// Value programmed on the swivel axis: machine sign · γ, degrees.
    pub swivel_axis_deg: f64,
    /// ΔH′ = max ΔH(x), mm, without safety distance.
    pub clearance_mm: f64,
    /// Safety distance added to ΔH′ in the Z positions, mm.
    pub safety_mm: f64,
    /// Final centre distance L = R + r − h, mm.
    pub centre_distance_mm: f64,
    /// Radial depth h, mm.
    pub depth_mm: f64,
    /// Blank outside diameter used, mm.
    pub blank_od_mm: f64,
    /// Positions A–E.
    pub positions: Positions,
    /// Hob speed Nt = 1000·vc / (π·da0), rpm.
    pub hob_rpm: f64,
    /// Indexing speed Ni = z0·Nt / z, rpm.
    pub index_rpm: f64,
    /// Actual table speed Nw = Ni / (1 ∓ fa/Pz), rpm.
    pub table_rpm: f64,
    /// Axial feed Vf = fa·Nw, mm/min.
    pub axial_feed_mm_min: f64,
    /// Differential: degrees of table per mm of axial travel, signed.
    pub differential_deg_per_mm: f64,
    /// Gearbox ratio table:hob = z0/z, kept exact.
    pub coupling: Ratio,
    /// Machining time of one cut, minutes: (b + 2·ΔH′)·z / (Nt·z0·fa).
    pub cut_time_min: f64,
    /// Cutting mode.
    pub cut_mode: crate::job::CutMode,
    /// Number of cuts.
    pub cuts: u32,
}

/// A non-fatal finding (e.g. blank OD at the edge of its window).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Warning {
    /// Stable code.
    pub code: String,
    /// Field concerned.
    pub field: String,
    /// A sentence.
    pub message: String,
}

/// Message: the machining model of a job.
///
/// Key `gearcam/v1/jobs/{job}/model`; published by the model service,
/// subscribed by the template service.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MachiningModel {
    /// The job's id.
    pub job_id: JobId,
    /// The plan it was computed from.
    pub plan: ProcessPlan,
    /// Gear geometry.
    pub geometry: Geometry,
    /// Kinematics.
    pub model: Kinematics,
    /// Warnings.
    pub warnings: Vec<Warning>,
    /// Version of the model code, e.g. `gearcam-model 0.1.0`.
    pub model_version: String,
}

impl Message for MachiningModel {
    const KIND: &'static str = "machining_model";
}
