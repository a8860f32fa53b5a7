//! The process plan: the knowledge service's decision for a job — machine
//! profile, hob, cutting data — each value with where it came from.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use crate::class::GearClass;
use crate::codec::Message;
use crate::ids::{HobId, JobId, MachineId};
use crate::job::{CutMode, GearSpec, Hand, JobRequest};

/// NC dialect of a controller.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Dialect {
    /// Siemens SINUMERIK 840D (main programs `_N_NAME_MPF`).
    Sinumerik840d,
    /// FANUC (programs `O0001`–`O7999`).
    Fanuc,
    /// LinuxCNC rs274ngc.
    Linuxcnc,
    /// Wire-EDM 3B/4B (programs `NAME.3b`, `NAME.4b`).
    Wire3b,
    /// Wire-EDM ISO G-code (programs `O0001`–`O7999`, as FANUC).
    WireIso,
}

impl Dialect {
    /// The dialect's name as written in messages and files.
    pub fn as_str(self) -> &'static str {
        match self {
            Dialect::Sinumerik840d => "sinumerik840d",
            Dialect::Fanuc => "fanuc",
            Dialect::Linuxcnc => "linuxcnc",
            Dialect::Wire3b => "wire3b",
            Dialect::WireIso => "wireiso",
        }
    }
}

/// Where a value in a plan or model came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Source {
    /// Given in the job file.
    Job,
    /// Proposed from the knowledge base's cutting data / cases.
    Case,
    /// Taken from the machine profile.
    Machine,
    /// A documented default of gearcam.
    Default,
    /// Taken from a knowledge-base library: the tool library (a hob's data)
    /// or the workpiece library (drawing data by part number).
    Library,
    /// Bounded by the drawing's accuracy class: the finishing feed whose
    /// feed marks stay within the class's helix form and runout tolerances.
    Grade,
}

/// A number with its provenance.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Sourced {
    /// The value.
    pub value: f64,
    /// Where it came from.
    pub source: Source,
}

/// Axis names of a hobbing machine as its controller knows them.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AxisNames {
    /// Radial axis (centre distance), usually `X`.
    pub radial: String,
    /// Axial axis (hob slide along the gear axis), usually `Z`.
    pub axial: String,
    /// Hob head swivel axis, usually `A`.
    pub swivel: String,
    /// Hob spindle as an axis (gearbox leading axis), usually `B`.
    pub hob: String,
    /// Work table (gearbox following axis), usually `C`.
    pub table: String,
    /// Hob shift axis, usually `Y`.
    pub shift: String,
}

/// M-codes of a machine's functions.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MCodes {
    /// Hob spindle on (clockwise).
    pub spindle_on: u16,
    /// Hob spindle stop.
    pub spindle_off: u16,
    /// Coolant on.
    pub coolant_on: u16,
    /// Coolant off.
    pub coolant_off: u16,
    /// Outer hob support engage.
    pub outer_support_on: u16,
    /// Outer hob support release.
    pub outer_support_off: u16,
    /// Fixture clamp.
    pub fixture_clamp: u16,
    /// Fixture unclamp.
    pub fixture_unclamp: u16,
    /// Chip conveyor on.
    pub chip_conveyor_on: u16,
    /// Chip conveyor off.
    pub chip_conveyor_off: u16,
    /// Oil-mist separator on.
    pub mist_on: u16,
    /// Oil-mist separator off.
    pub mist_off: u16,
    /// End of program.
    pub program_end: u16,
}

/// Travel, speed and size limits of a machine.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MachineLimits {
    /// Smallest and largest module the machine cuts, mm.
    pub module_mm: [f64; 2],
    /// Largest workpiece outside diameter, mm.
    pub max_workpiece_od_mm: f64,
    /// Largest hob outside diameter, mm.
    pub max_hob_od_mm: f64,
    /// X (radial) travel, mm.
    pub x_mm: [f64; 2],
    /// Z (axial) travel, mm.
    pub z_mm: [f64; 2],
    /// Largest hob spindle speed, rpm.
    pub max_hob_rpm: f64,
    /// Largest table speed, rpm.
    pub max_table_rpm: f64,
    /// Largest axial feed rate, mm/min.
    pub max_axial_feed_mm_min: f64,
    /// Largest swivel angle magnitude, degrees.
    pub max_swivel_deg: f64,
}

/// Tolerances, windows and distances the model uses for this machine.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MachineSettings {
    /// Blank OD may lie this far under the theoretical tip diameter, mm (patent: 1–2 mm).
    pub blank_od_below_mm: f64,
    /// Blank OD may lie this far over the theoretical tip diameter, mm.
    pub blank_od_above_mm: f64,
    /// Requested depth may exceed the whole depth by this much, mm.
    pub depth_allowance_mm: f64,
    /// Safety distance added to ΔH′ in the Z positions, mm.
    pub safety_mm: f64,
    /// X retract of B over C (patent: 100 mm).
    pub retract_mm: f64,
    /// X lift of E over D (patent: 5 mm).
    pub exit_mm: f64,
    /// Sign of the swivel axis: the A value is `swivel_sign·η + swivel_offset_deg`
    /// (+1 or −1), η the signed setting angle of the machine-neutral frame
    /// (`docs/hobbing.md`, "Signs").
    pub swivel_sign: f64,
    /// Swivel axis reading with the hob axis parallel to the gear end face
    /// (η = 0), degrees; e.g. 90 on a machine whose A reads 90° there.
    pub swivel_offset_deg: f64,
    /// +1 when the table axis turns the neutral frame's positive way
    /// (clockwise seen from above the table), −1 when the other way.
    pub table_sign: f64,
    /// +1 when the hob axis turns the neutral frame's positive way
    /// (right-handed about the hob axis direction u), −1 when the other way.
    pub hob_sign: f64,
    /// +1 when the shift axis moves the hob along the neutral frame's hob axis
    /// direction u, −1 when against it.
    pub shift_sign: f64,
}

/// The G-code system of a FANUC control, which decides what G90, G94 and G98
/// mean (FANUC T series: systems A, B, C; the M series has one).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum GCodeSystem {
    /// SINUMERIK 840D (ISO dialect: G90/G91 absolute/incremental, G94 feed per minute).
    Sinumerik,
    /// FANUC M series: G90/G91 absolute/incremental, G94/G95 feed per minute/revolution,
    /// G98/G99 canned-cycle return levels; the EGB is `G81 T L Q P` ... `G80`.
    FanucM,
    /// FANUC T series, G-code system A: X/Z absolute, U/W incremental,
    /// G98/G99 feed per minute/revolution, G90 a turning cycle.
    FanucTA,
    /// FANUC T series, G-code system B: G90/G91, G94/G95, G98/G99 return levels.
    FanucTB,
    /// FANUC T series, G-code system C: as B with other group numbers.
    FanucTC,
}

impl GCodeSystem {
    /// The name written in profiles and messages.
    pub fn as_str(self) -> &'static str {
        match self {
            GCodeSystem::Sinumerik => "sinumerik",
            GCodeSystem::FanucM => "fanuc_m",
            GCodeSystem::FanucTA => "fanuc_t_a",
            GCodeSystem::FanucTB => "fanuc_t_b",
            GCodeSystem::FanucTC => "fanuc_t_c",
        }
    }
}

/// The block of parameters a machine leaves free for gearcam's programs: a
/// program's parameter slot n (1–29) is the 840D R parameter `r_first + n − 1`
/// or the FANUC common variable `#(macro_first + n − 1)`. Slot 25 is the part
/// counter of hob shifting, which the control keeps between runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct ParameterBlock {
    /// First 840D R parameter gearcam may use (R0–R999).
    pub r_first: u16,
    /// First FANUC common variable gearcam may use (retained: #500–#999).
    pub macro_first: u16,
}

impl ParameterBlock {
    /// Parameter slots a program may use (1 to this).
    pub const SLOTS: u16 = 29;
}

/// What the hob must never touch besides the blank: the table, the work
/// fixture (riser and arbor support) under the gear and the tailstock above
/// it. Heights are measured from the table plane (Z = 0 of the program), radii
/// from the table axis.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Envelope {
    /// Table radius: everything at or below Z = 0 within it is the table, mm.
    pub table_radius_mm: f64,
    /// Radius of the fixture standing on the table up to the gear's lower face
    /// (height H), mm, unless the job gives its own (`gear.fixture_diameter_mm`).
    pub fixture_radius_mm: f64,
    /// Tailstock (counter column centre) radius, mm; 0 when the machine has none.
    pub tailstock_radius_mm: f64,
    /// Gap between the gear's upper face and the tailstock's lowest point, mm.
    pub tailstock_gap_mm: f64,
}

/// A machine's profile from the knowledge base.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MachineProfile {
    /// Machine id, e.g. `H01`.
    pub id: MachineId,
    /// Human name, e.g. `YK3126 CNC hobbing machine`.
    pub name: String,
    /// Controller dialect.
    pub dialect: Dialect,
    /// Axis names.
    pub axes: AxisNames,
    /// M-codes.
    pub mcodes: MCodes,
    /// Limits.
    pub limits: MachineLimits,
    /// Model settings.
    pub settings: MachineSettings,
    /// The G-code system the programs are written in.
    pub gcode_system: GCodeSystem,
    /// Table, fixture and tailstock the hob must stay clear of.
    pub envelope: Envelope,
    /// Work offset that puts Z = 0 on the table plane and X = 0 on the table
    /// axis, e.g. `G54`.
    pub work_offset: String,
    /// The parameters the machine leaves free for gearcam's programs.
    pub parameters: ParameterBlock,
    /// Start/end position A: X0, mm.
    pub home_x_mm: f64,
    /// Start/end position A: Z0, mm.
    pub home_z_mm: f64,
}

/// A hob resolved from the library or given inline.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct HobData {
    /// Library id, or `inline` when given in the job.
    pub id: String,
    /// Number of starts z0.
    pub starts: u32,
    /// Outside diameter da0, mm.
    pub od_mm: f64,
    /// Normal module mn0, mm.
    pub module_mm: f64,
    /// Normal pressure angle α0, degrees.
    pub pressure_angle_deg: f64,
    /// Lead angle γ0, degrees.
    pub lead_angle_deg: f64,
    /// Thread hand.
    pub hand: Hand,
    /// Overall length, mm.
    pub length_mm: f64,
    /// Length of the hob whose teeth may cut, mm, centred on the hob: the
    /// shift travels inside it (the tool library's usable length). Absent for
    /// a hob the job gave inline: its overall length.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub usable_length_mm: Option<f64>,
    /// Where the data came from.
    pub source: Source,
}

impl HobData {
    /// The length the shift may travel in: the usable length, or the overall
    /// length when the usable one is not known.
    pub fn usable_mm(&self) -> f64 {
        self.usable_length_mm.unwrap_or(self.length_mm)
    }
}

/// The process data decided for the job.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ProcessData {
    /// Cutting mode.
    pub cut_mode: CutMode,
    /// Number of cuts.
    pub cuts: u32,
    /// Cutting speed vc, m/min.
    pub cutting_speed_m_min: f64,
    /// Axial feed per workpiece revolution fa, mm/rev.
    pub feed_mm_per_rev: f64,
    /// Radial depth h, mm, when given; else computed by the model.
    pub depth_mm: Option<f64>,
    /// Safety distance added to ΔH′, mm.
    pub safety_mm: f64,
}

/// A knowledge-base record that contributed to the plan.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CaseRef {
    /// Record id, e.g. `CD-STEEL-HSS-1`.
    pub id: String,
    /// Similarity to the job, 0–1 (1 for an exact rule match).
    pub similarity: f64,
    /// Where the record's values come from.
    pub provenance: String,
}

/// Message: the knowledge service's process plan for a job.
///
/// Key `gearcam/v1/jobs/{job}/plan`; published by the knowledge service,
/// subscribed by the model service.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ProcessPlan {
    /// The job's id.
    pub job_id: JobId,
    /// The request as submitted (its `spec.gear` absent when the job named
    /// a part of the workpiece library instead).
    pub request: JobRequest,
    /// The gear to cut, resolved: the job's `[gear]`, or the workpiece
    /// library's record of its part number. Every later stage reads this.
    pub gear: GearSpec,
    /// Group-technology class of the job, decided once here (from the resolved
    /// gear and the job's units).
    pub class: GearClass,
    /// The machine's profile.
    pub machine: MachineProfile,
    /// The hob.
    pub hob: HobData,
    /// The process data.
    pub process: ProcessData,
    /// Every decided value with its source, by name (e.g. `cutting_speed_m_min`).
    pub values: BTreeMap<String, Sourced>,
    /// Knowledge-base records used.
    pub cases: Vec<CaseRef>,
    /// Confidence of the proposal, 0–1.
    pub confidence: f64,
    /// What the knowledge base proposed before the job's overrides, which
    /// values the job overrode, and why the hob was chosen. Absent in plans
    /// from older knowledge services.
    #[serde(default)]
    pub proposal: Proposal,
}

/// The knowledge base's proposal for a job, kept beside the final values so a
/// reader sees what was proposed and what the job overrode.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Proposal {
    /// Every value the knowledge base proposed, with its source (`case`,
    /// `machine` or `default`), whether or not the job overrode it.
    #[serde(default)]
    pub values: BTreeMap<String, Sourced>,
    /// Names of the values the job overrode (their final value in
    /// [`ProcessPlan::values`] has source `job`).
    #[serde(default)]
    pub overridden: Vec<String>,
    /// How the hob was chosen: the choice explained and every rejected
    /// library hob with its reasons. Absent when the job named or gave its hob.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hob: Option<HobChoice>,
    /// The similarity weights used for case retrieval, by feature.
    #[serde(default)]
    pub weights: BTreeMap<String, f64>,
    /// The workpiece library's record of the job's part number, when it has
    /// one: whether it supplied the drawing data or the job's `[gear]`
    /// section replaced it. Absent when the part is not in the library.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub workpiece: Option<WorkpieceRef>,
}

/// The workpiece library's record of a job's part, as the plan used it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct WorkpieceRef {
    /// The part number, e.g. `SP-1001`.
    pub part_number: String,
    /// Where the record's data comes from (its `source`).
    pub provenance: String,
    /// True when the job had no `[gear]` section and the record supplied
    /// the drawing data (values `gear.*` with source `library`); false when
    /// the job's `[gear]` section replaced the record as a whole.
    pub supplied_gear: bool,
    /// The drawing-data fields in which the job's `[gear]` differs from the
    /// record (empty when the record supplied the gear).
    #[serde(default)]
    pub differs: Vec<String>,
}

/// The explained result of hob matching.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct HobChoice {
    /// The chosen hob's id.
    pub chosen: String,
    /// Why it was chosen, as a sentence.
    pub reason: String,
    /// Library hobs that fit but ranked lower, best first.
    #[serde(default)]
    pub alternatives: Vec<String>,
    /// Library hobs that were rejected, each with every reason.
    #[serde(default)]
    pub rejected: Vec<HobRejection>,
}

/// A library hob that cannot cut the job, and why.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct HobRejection {
    /// The hob's id.
    pub id: String,
    /// Every reason, e.g. `normal base pitch 2.3492 mm ≠ gear 2.8191 mm`.
    pub reasons: Vec<String>,
}

/// A value in a knowledge-base record on the wire (a MessagePack nil, bool,
/// integer, float, string, array or map).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum KbValue {
    /// Nil: no value.
    Null,
    /// A boolean.
    Bool(bool),
    /// An integer.
    Int(i64),
    /// A floating-point number.
    Float(f64),
    /// A string.
    Text(String),
    /// An array.
    List(Vec<KbValue>),
    /// A map with string keys (nested records such as a machine's `limits`).
    Map(BTreeMap<String, KbValue>),
}

/// A knowledge-base record: field name → value.
pub type KbRecord = BTreeMap<String, KbValue>;

/// What a knowledge-base query asks for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum KbOp {
    /// Every record of the library (key `gearcam/v1/kb/{library}`).
    List,
    /// One record (key `gearcam/v1/kb/{library}/{id}`).
    Get,
    /// Add a new record (`record` holds every field; its id must be new).
    Add,
    /// Change fields of an existing record (`set`: field path → new value).
    Edit,
    /// Remove a record.
    Remove,
}

/// Message: a query on a knowledge-base library. Reads (`list`, `get`) are
/// asked on `gearcam/v1/kb/{library}[/{id}]` (a query without payload is a
/// `list` without id, a `get` with one); changes (`add`, `edit`, `remove`)
/// on `gearcam/v1/kb-changes/{user}/{library}[/{id}]`, recorded as `user`'s.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct KbRequest {
    /// The operation.
    pub op: KbOp,
    /// The record to add.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub record: Option<KbRecord>,
    /// Fields to change (`edit`), by name or dotted path (`limits.max_hob_rpm`).
    #[serde(default)]
    pub set: KbRecord,
    /// The client's own name for who makes a change; not recorded: the
    /// change is the key's user's ([`crate::keys::kb_change`]).
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub by: String,
}

impl Message for KbRequest {
    const KIND: &'static str = "kb_request";
}

/// Message: the knowledge service's reply to a [`KbRequest`]: the records
/// read or written, or every error (stage `knowledge`) found.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct KbReply {
    /// The library queried, e.g. `hobs`.
    pub library: String,
    /// The records listed, read, added or changed (after the change); for
    /// `remove`, the removed record.
    #[serde(default)]
    pub records: Vec<KbRecord>,
    /// Errors; empty on success.
    #[serde(default)]
    pub errors: Vec<crate::error::JobError>,
}

impl Message for KbReply {
    const KIND: &'static str = "kb_reply";
}

/// Message: a query of the knowledge base's change log, on
/// `gearcam/v1/kb-log[/{library}[/{id}]]` ([`crate::keys::kb_log`]); a
/// query without payload asks for the newest [`KbLogRequest::DEFAULT_LIMIT`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct KbLogRequest {
    /// At most this many changes, newest first (1 to
    /// [`KbLogRequest::MAX_LIMIT`]).
    pub limit: u32,
}

impl KbLogRequest {
    /// The changes a query without payload gets.
    pub const DEFAULT_LIMIT: u32 = 50;
    /// The most changes one query gets.
    pub const MAX_LIMIT: u32 = 1000;
}

impl Default for KbLogRequest {
    fn default() -> Self {
        KbLogRequest {
            limit: KbLogRequest::DEFAULT_LIMIT,
        }
    }
}

impl Message for KbLogRequest {
    const KIND: &'static str = "kb_log_request";
}

/// One recorded change of the knowledge base: who, when, which record, the
/// old and the new values. Every change is recorded, whatever made it (the
/// CLI, a CSV import, a confirmed job, a change over the bus).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct KbChange {
    /// Order of the change (larger is later).
    pub seq: i64,
    /// When, ms since the epoch (UTC).
    pub at_ms: i64,
    /// Who: the user of the change key, the CLI's login, `seed`, or
    /// `{user} (confirm {job})` for what a confirmation changed.
    pub by: String,
    /// The library, e.g. `hobs` (as on the bus and the CLI).
    pub library: String,
    /// The record's key.
    pub record_id: String,
    /// `add`, `edit` or `remove`.
    pub op: String,
    /// The record before (edit, remove); absent for an add.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub old: Option<KbRecord>,
    /// The record after (add, edit); absent for a remove.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub new: Option<KbRecord>,
}

/// Message: the knowledge service's reply to a [`KbLogRequest`]: the
/// changes newest first, or every error (stage `knowledge`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct KbLogReply {
    /// The changes, newest first.
    #[serde(default)]
    pub changes: Vec<KbChange>,
    /// Errors; empty on success.
    #[serde(default)]
    pub errors: Vec<crate::error::JobError>,
}

impl Message for KbLogReply {
    const KIND: &'static str = "kb_log_reply";
}

/// Message: the confirmation of a delivered job, on
/// `gearcam/v1/kb-confirm/{user}/{job}` ([`crate::keys::kb_confirm`]): the
/// values actually used (each absent: the plan's) and the outcome. The
/// job becomes a case, recorded as `user`'s (what `gearcam confirm` does).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ConfirmRequest {
    /// Parts actually cut (absent: the job's quantity).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub quantity: Option<u32>,
    /// Cutting speed actually used, m/min (absent: the plan's).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cutting_speed_m_min: Option<f64>,
    /// Feed actually used (absent: the plan's): mm/rev for hobbing, mm per
    /// tooth for spiral face milling.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub feed_mm_per_rev: Option<f64>,
    /// Cuts actually made (absent: the plan's); depth passes for spiral
    /// face milling.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cuts: Option<u32>,
    /// Outcome of the cut: `ok`, `rework`, `scrap` or `unknown`.
    pub outcome: String,
    /// Accuracy grade measured.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub quality_achieved: Option<u8>,
    /// Remarks.
    #[serde(default)]
    pub notes: String,
    /// How far to trust the new case, 0–1.
    pub confidence: f64,
    /// Accept a job whose delivery the knowledge service did not hear (the
    /// cutting speed and feed that ran must then be given).
    #[serde(default)]
    pub undelivered: bool,
}

impl Message for ConfirmRequest {
    const KIND: &'static str = "confirm_request";
}

/// Message: the knowledge service's reply to a [`ConfirmRequest`]: the
/// case the job became, the hob after its wear, the job after; or every
/// error (stage `knowledge`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ConfirmReply {
    /// The job, as the key named it.
    pub job_id: String,
    /// The library of the case: `cases` (hobbing) or `milling-cases`
    /// (spiral face milling); empty on a refusal.
    #[serde(default)]
    pub case_library: String,
    /// The new case.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub case: Option<KbRecord>,
    /// The library hob after the update of its shift position and life.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hob: Option<KbRecord>,
    /// The job's record after (state `confirmed`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub job: Option<KbRecord>,
    /// Errors; empty on success.
    #[serde(default)]
    pub errors: Vec<crate::error::JobError>,
}

impl Message for ConfirmReply {
    const KIND: &'static str = "confirm_reply";
}

impl Message for ProcessPlan {
    const KIND: &'static str = "process_plan";
}

impl ProcessPlan {
    /// The hob's id as a library id, if it came from the library.
    pub fn hob_library_id(&self) -> Option<HobId> {
        HobId::new(self.hob.id.clone()).ok()
    }

    /// The hobbing sections of the job the plan was made for.
    ///
    /// Only the hobbing planner makes a process plan, from a hobbing job, and
    /// a process plan that carries another family's job does not decode
    /// ([`crate::AnyPlan`], [`crate::AnyModel`]); a plan built in memory from
    /// another family's job is a bug, and this panics on it.
    pub fn sections(&self) -> &crate::HobbingSpec {
        self.request
            .spec
            .hobbing()
            .expect("a process plan is made for a hobbing job")
    }

    /// The hobbing sections to change ([`ProcessPlan::sections`]).
    pub fn sections_mut(&mut self) -> &mut crate::HobbingSpec {
        self.request
            .spec
            .hobbing_mut()
            .expect("a process plan is made for a hobbing job")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{decode, encode};

    #[test]
    fn kb_messages_round_trip_every_value_kind() {
        let mut limits = KbRecord::new();
        limits.insert("max_hob_rpm".into(), KbValue::Float(1200.5));
        let mut set = KbRecord::new();
        set.insert("limits".into(), KbValue::Map(limits));
        set.insert("starts".into(), KbValue::Int(-2));
        set.insert("coating".into(), KbValue::Text("TiAlN".into()));
        set.insert("active".into(), KbValue::Bool(true));
        set.insert("note".into(), KbValue::Null);
        set.insert(
            "list".into(),
            KbValue::List(vec![KbValue::Int(1), KbValue::Float(0.5)]),
        );
        let req = KbRequest {
            op: KbOp::Edit,
            record: None,
            set,
            by: "admin".into(),
        };
        let back: KbRequest = decode(&encode(&req).unwrap()).unwrap();
        assert_eq!(back, req);
        let reply = KbReply {
            library: "hobs".into(),
            records: vec![req.set.clone()],
            errors: vec![],
        };
        let back: KbReply = decode(&encode(&reply).unwrap()).unwrap();
        assert_eq!(back, reply);
    }

    #[test]
    fn log_and_confirm_messages_round_trip() {
        let mut rec = KbRecord::new();
        rec.insert("coating".into(), KbValue::Text("TiN".into()));
        let log = KbLogReply {
            changes: vec![KbChange {
                seq: 7,
                at_ms: 1_700_000_000_000,
                by: "admin".into(),
                library: "hobs".into(),
                record_id: "HOB-M3-80".into(),
                op: "edit".into(),
                old: Some(rec.clone()),
                new: None,
            }],
            errors: vec![],
        };
        assert_eq!(decode::<KbLogReply>(&encode(&log).unwrap()).unwrap(), log);
        let req = KbLogRequest::default();
        assert_eq!(req.limit, KbLogRequest::DEFAULT_LIMIT);
        assert_eq!(decode::<KbLogRequest>(&encode(&req).unwrap()).unwrap(), req);
        let confirm = ConfirmRequest {
            quantity: Some(20),
            cutting_speed_m_min: Some(95.0),
            feed_mm_per_rev: None,
            cuts: None,
            outcome: "ok".into(),
            quality_achieved: Some(7),
            notes: "good flanks".into(),
            confidence: 0.8,
            undelivered: false,
        };
        let back: ConfirmRequest = decode(&encode(&confirm).unwrap()).unwrap();
        assert_eq!(back, confirm);
        let reply = ConfirmReply {
            job_id: "J1".into(),
            case_library: "cases".into(),
            case: Some(rec),
            hob: None,
            job: None,
            errors: vec![],
        };
        assert_eq!(
            decode::<ConfirmReply>(&encode(&reply).unwrap()).unwrap(),
            reply
        );
    }
}
