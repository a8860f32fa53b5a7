//! The job: what a planning office asks for. The same structure is the TOML job
//! file (`examples/*.toml`) and the body of the [`JobRequest`] message.
//!
//! Drawing data is required: in the `[gear]` section, or by a `[job]
//! part_number` that names a workpiece in the knowledge base's library (the
//! knowledge service resolves the gear and the plan carries it, see
//! [`crate::ProcessPlan::gear`]).
//! Everything else has a decided default that the knowledge service fills in
//! and records as such. Unknown keys are rejected so a misspelt key never
//! silently falls back to a default.

use serde::{Deserialize, Serialize};

use crate::codec::Message;
pub use crate::cutting::CutMode;
use crate::ids::{HobId, JobId, MachineId};

/// Hand of a helix (gear tooth trace or hob thread).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Hand {
    /// Right hand.
    #[serde(alias = "rh", alias = "RH", alias = "R")]
    Right,
    /// Left hand.
    #[serde(alias = "lh", alias = "LH", alias = "L")]
    Left,
}

/// The part family of a job: which process, which stages' models.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Family {
    /// Gear hobbing (`[gear]`, `[hob]`, `[process]`; the default, so every
    /// hobbing job file written before families stays valid).
    #[default]
    Hobbing,
    /// Spiral face milling of a circular or annular face or a planar
    /// spiral groove (`[face]` or `[groove]`, `[mill]`, `[milling]`).
    SpiralFace,
    /// Wire EDM of a spur gear's punch or die (`[die]`, `[wire]`).
    WireEdm,
}

impl Family {
    /// The name as written in job files.
    pub fn as_str(self) -> &'static str {
        match self {
            Family::Hobbing => "hobbing",
            Family::SpiralFace => "spiral-face",
            Family::WireEdm => "wire-edm",
        }
    }
}

/// `[job]`: which machine, how many parts, which part.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JobHeader {
    /// The part family (default `hobbing`).
    #[serde(default, skip_serializing_if = "is_hobbing")]
    pub family: Family,
    /// Optional fixed job id (letters, digits, `_`, `-`); the station generates one if absent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub id: Option<JobId>,
    /// Machine that will cut the part, e.g. `H01`.
    pub machine: MachineId,
    /// Number of parts.
    #[serde(default = "one")]
    pub quantity: u32,
    /// Part (drawing) number, e.g. `SP-1001`: 1 to [`MAX_PART_NUMBER`]
    /// characters on one line ([`part_number_problem`]).
    pub part_number: String,
    /// Program name at the machine; by default made from the part number by
    /// the controller's rule (docs/programs.md#program-names-and-files).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub program_name: Option<String>,
}

fn is_hobbing(f: &Family) -> bool {
    *f == Family::Hobbing
}

/// Longest part number accepted, characters: it goes into program headers,
/// names and the store's index.
pub const MAX_PART_NUMBER: usize = 64;

/// What makes a part number unusable (empty, over [`MAX_PART_NUMBER`]
/// characters, a control character such as a line break), or `None`.
pub fn part_number_problem(part: &str) -> Option<String> {
    let n = part.chars().count();
    if part.trim().is_empty() {
        Some("it is empty".to_string())
    } else if n > MAX_PART_NUMBER {
        Some(format!("it has {n} characters"))
    } else if part.chars().any(char::is_control) {
        Some("it contains a control character (a line break?)".to_string())
    } else {
        None
    }
}

/// The first number of a job that is not finite (`inf` or `NaN`), as its
/// field (`gear.module_mm`, `die.cutters[0].x`) and value, or `None`.
///
/// A job file's TOML allows `inf` and `nan`, and a client's MessagePack
/// carries them too; no stage can plan with one, and the first to meet it
/// would blame something else (no hob of module `inf`), so the station and
/// the CLI refuse it on its field before any stage sees it.
pub fn non_finite(spec: &JobSpec) -> Option<(String, f64)> {
    fn walk(v: &toml::Value, path: &str) -> Option<(String, f64)> {
        match v {
            toml::Value::Float(f) if !f.is_finite() => Some((path.to_string(), *f)),
            toml::Value::Table(t) => t.iter().find_map(|(k, v)| {
                let field = if path.is_empty() {
                    k.clone()
                } else {
                    format!("{path}.{k}")
                };
                walk(v, &field)
            }),
            toml::Value::Array(a) => a
                .iter()
                .enumerate()
                .find_map(|(i, v)| walk(v, &format!("{path}[{i}]"))),
            _ => None,
        }
    }
    // Every number of a spec is a TOML number (TOML has `inf` and `nan`),
    // so the spec's TOML value holds them all under their field names.
    walk(&toml::Value::try_from(spec).ok()?, "")
}

/// `[gear]`: drawing data of the gear (patent step 1, workpiece parameters).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GearSpec {
    /// Normal module mn, mm.
    pub module_mm: f64,
    /// Number of teeth z.
    pub teeth: u32,
    /// Normal pressure angle αn, degrees (default 20).
    #[serde(default = "twenty")]
    pub pressure_angle_deg: f64,
    /// Helix angle β at the reference circle, degrees, magnitude (default 0 = spur).
    #[serde(default)]
    pub helix_angle_deg: f64,
    /// Hand of the helix; required when the helix angle is not zero.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub helix_hand: Option<Hand>,
    /// Face width b, mm.
    pub face_width_mm: f64,
    /// Profile shift coefficient x (default 0).
    #[serde(default)]
    pub profile_shift: f64,
    /// Addendum coefficient ha* (default 1).
    #[serde(default = "one_f")]
    pub addendum_coef: f64,
    /// Tip clearance coefficient c* (default 0.25).
    #[serde(default = "quarter")]
    pub clearance_coef: f64,
    /// Blank outside diameter Da1, mm (default: the theoretical tip diameter).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub blank_od_mm: Option<f64>,
    /// OD correction Δx added to every X position, mm (patent "X 方向修正量"; default 0).
    #[serde(default)]
    pub od_correction_mm: f64,
    /// Material, e.g. `20CrMnTi`, `16MnCr5`, `42CrMo4`, `C45`, `GG25`.
    #[serde(default = "unspecified")]
    pub material: String,
    /// Accuracy grade (ISO 1328 / GB 10095), 1–12 (default 8).
    #[serde(default = "eight")]
    pub quality_grade: u8,
    /// Distance H from the lower tooth face to the table (fixture height), mm.
    pub fixture_height_mm: f64,
    /// Diameter of the fixture (riser, support ring) between the table and
    /// the gear's lower face, mm (default: the machine profile's).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fixture_diameter_mm: Option<f64>,
    /// Ball (pin) diameter DM for the measurement over balls, mm (default 1.7·mn).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ball_diameter_mm: Option<f64>,
    /// The mating gear, for the pair geometry (working pressure angle, centre
    /// distance, contact ratio).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mate: Option<MateSpec>,
    /// `[gear.cone]`: a conical involute gear (beveloid); tip and root on a cone.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cone: Option<ConeSpec>,
    /// `[gear.crowning]`: a crowned (barrel) gear.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub crowning: Option<CrowningSpec>,
    /// `[gear.worm_wheel]`: a worm wheel (throated), hobbed radially or tangentially.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub worm_wheel: Option<WormWheelSpec>,
    /// `[gear.curved_tooth]`: a gear with a curved tooth trace.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub curved_tooth: Option<CurvedToothSpec>,
}

/// `[gear.mate]`: the gear this one meshes with.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MateSpec {
    /// Teeth of the mate z2.
    pub teeth: u32,
    /// Profile shift coefficient x2 (default 0).
    #[serde(default)]
    pub profile_shift: f64,
    /// Tip diameter da2, mm (default d2 + 2·mn·(ha* + x2)).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tip_diameter_mm: Option<f64>,
    /// Working centre distance, mm; when given the working pressure angle is
    /// taken from it, otherwise from the sum of the profile shifts.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub centre_distance_mm: Option<f64>,
}

/// Which face of a conical gear has the larger diameter.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum LargeEnd {
    /// The lower face (nearer the table).
    #[default]
    Bottom,
    /// The upper face.
    Top,
}

/// `[gear.cone]`: the cone of a conical involute gear.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ConeSpec {
    /// Cone angle δ between the tip line and the gear axis, degrees (seed 000: 6.5°).
    pub angle_deg: f64,
    /// The face with the larger diameter (default bottom); `blank_od_mm` is taken there.
    #[serde(default)]
    pub large_end: LargeEnd,
}

/// Shape of a crowning.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum CrowningShape {
    /// Circular arc (exact G2/G3 / CIP arc in X–Z).
    #[default]
    Circular,
    /// Parabola, approximated by chords.
    Parabolic,
}

/// `[gear.crowning]`: crowning along the face width.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CrowningSpec {
    /// Crowning amount Cb: how much deeper the hob cuts (radially, X) at each face than in the middle, so the teeth are thickest in the middle, mm.
    pub amount_mm: f64,
    /// Shape (default circular).
    #[serde(default)]
    pub shape: CrowningShape,
    /// Chord tolerance of a parabolic crowning, mm (default 0.001).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub chord_tolerance_mm: Option<f64>,
}

/// How a worm wheel is hobbed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum WormInfeed {
    /// Radial infeed to the final centre distance.
    #[default]
    Radial,
    /// Tangential infeed along the hob axis at the final centre distance.
    Tangential,
}

/// `[gear.worm_wheel]`: hobbing data of a worm wheel.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WormWheelSpec {
    /// Infeed method (default radial).
    #[serde(default)]
    pub infeed: WormInfeed,
    /// Radial feed per wheel revolution, mm/rev (default: a third of the axial feed).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radial_feed_mm_per_rev: Option<f64>,
    /// Tangential feed per wheel revolution, mm/rev (default: the axial feed).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tangential_feed_mm_per_rev: Option<f64>,
    /// Dwell at the final centre distance, wheel revolutions (default 2).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dwell_rev: Option<f64>,
}

/// `[gear.curved_tooth]`: a curved tooth trace (classified, not yet programmable).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CurvedToothSpec {
    /// Radius of the tooth trace (cutter radius), mm.
    pub trace_radius_mm: f64,
}

/// `[[units]]`: a further gear unit of a multi-gear (cluster) part. The job's
/// `[gear]` and `[hob]` are the first unit, at Z offset 0.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct UnitSpec {
    /// Name of the unit, e.g. `upper gear` (default `unit N`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// Height of the unit's lower tooth face above the first unit's, mm.
    pub z_offset_mm: f64,
    /// Drawing data of the unit (its own class: cylindrical, conical, crowned).
    pub gear: GearSpec,
    /// The unit's hob, inline; empty means the job's hob.
    #[serde(default)]
    pub hob: HobSpec,
}

/// `[hob]`: either a library `id` or the hob's data inline, or nothing (the
/// knowledge service then picks a matching hob from the library).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HobSpec {
    /// Hob id in the tool library.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub id: Option<HobId>,
    /// Number of starts z0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub starts: Option<u32>,
    /// Outside diameter da0, mm.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub od_mm: Option<f64>,
    /// Normal module mn0, mm.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub module_mm: Option<f64>,
    /// Normal pressure angle α0, degrees.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pressure_angle_deg: Option<f64>,
    /// Lead angle γ0 at the reference diameter, degrees.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lead_angle_deg: Option<f64>,
    /// Hand of the hob thread.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hand: Option<Hand>,
    /// Overall length, mm.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub length_mm: Option<f64>,
}

impl HobSpec {
    /// True when any inline data field is given.
    pub fn has_inline_data(&self) -> bool {
        self.starts.is_some()
            || self.od_mm.is_some()
            || self.module_mm.is_some()
            || self.pressure_angle_deg.is_some()
            || self.lead_angle_deg.is_some()
            || self.hand.is_some()
            || self.length_mm.is_some()
    }
}

/// Rough or finish hobbing.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Operation {
    /// Roughing: the cut leaves stock for a later operation (finish hobbing,
    /// shaving, grinding), as in seed 000's bevel-gear example.
    Rough,
    /// Finishing: the cut gives the final flanks (the default).
    #[default]
    Finish,
}

impl Operation {
    /// As written in job files and the knowledge base: `rough` or `finish`.
    pub fn as_str(self) -> &'static str {
        match self {
            Operation::Rough => "rough",
            Operation::Finish => "finish",
        }
    }
}

/// `[process]`: optional overrides of the proposed process data.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ProcessOverrides {
    /// Rough or finish hobbing (default finish). Case retrieval proposes the
    /// cutting data from cases of the same operation first (docs/knowledge.md#case-based-reasoning).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub operation: Option<Operation>,
    /// Cutting mode (default conventional, as in the patent).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cut_mode: Option<CutMode>,
    /// Number of cuts: rough cuts leave `finish_allowance_mm`, the last cut finishes.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cuts: Option<u32>,
    /// Cutting speed vc, m/min.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cutting_speed_m_min: Option<f64>,
    /// Axial feed per workpiece revolution fa, mm/rev.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub feed_mm_per_rev: Option<f64>,
    /// Radial cut depth h, mm (default: so that the final centre distance is the theoretical one).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub depth_mm: Option<f64>,
    /// Safety distance added to the clearance ΔH′ in the Z positions, mm (default from the machine).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub safety_mm: Option<f64>,
    /// Infeed mode of a cylindrical gear (default axial).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub infeed: Option<Infeed>,
    /// Radial stock the rough cuts leave for the finishing cut, mm (default 0.1·mn).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub finish_allowance_mm: Option<f64>,
    /// Axial feed of the finishing cut, mm/rev (default the rough feed).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub finish_feed_mm_per_rev: Option<f64>,
    /// Radial feed of a radial plunge, mm per workpiece revolution (default a third of the axial feed).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radial_feed_mm_per_rev: Option<f64>,
    /// Hob shifting (patent: shift start, end, per step, parts per step).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shift: Option<ShiftSpec>,
}

/// Infeed mode of hobbing.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Infeed {
    /// Axial feed over the face width from outside the blank.
    #[default]
    Axial,
    /// A radial plunge at the entry face, then axial feed.
    RadialAxial,
}

/// When the hob shifts.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ShiftMode {
    /// After every `parts_per_step` parts.
    #[default]
    Part,
    /// Before every cut after the first, and per part as well.
    Cut,
}

/// `[process.shift]`: hob shifting along its axis (Y).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ShiftSpec {
    /// Per part or per cut (default part).
    #[serde(default)]
    pub mode: ShiftMode,
    /// First shift position relative to the hob centre, mm (default: the start of the usable range).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub start_mm: Option<f64>,
    /// Last shift position, mm (default: the end of the usable range).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub end_mm: Option<f64>,
    /// Shift per step, mm (default: one axial pitch of the hob, π·mn0/cos γ0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub step_mm: Option<f64>,
    /// Parts cut before each step (default 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub parts_per_step: Option<u32>,
}

/// `[options]`: machine functions switched on or off (patent "other parameters").
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Options {
    /// Coolant on during cutting (default true).
    #[serde(default = "yes")]
    pub coolant: bool,
    /// Outer hob support engaged (default false).
    #[serde(default)]
    pub outer_support: bool,
    /// Fixture clamped (default true).
    #[serde(default = "yes")]
    pub fixture_clamp: bool,
    /// Cancel the gearbox coupling at the end (default true).
    #[serde(default = "yes")]
    pub sync_cancel: bool,
    /// Chip conveyor on (default true).
    #[serde(default = "yes")]
    pub chip_conveyor: bool,
    /// Oil-mist separator on (default false).
    #[serde(default)]
    pub mist_separator: bool,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            coolant: true,
            outer_support: false,
            fixture_clamp: true,
            sync_cancel: true,
            chip_conveyor: true,
            mist_separator: false,
        }
    }
}

/// A whole job file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JobSpec {
    /// `[job]`
    pub job: JobHeader,
    /// `[gear]`: the drawing data. A job file may leave the section out when
    /// its `part_number` names a workpiece in the knowledge base's library.
    /// The request keeps what was asked; the plan carries the resolved gear
    /// beside it ([`crate::ProcessPlan::gear`]), and every stage after the
    /// knowledge service reads that one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gear: Option<GearSpec>,
    /// `[hob]`
    #[serde(default)]
    pub hob: HobSpec,
    /// `[process]`
    #[serde(default)]
    pub process: ProcessOverrides,
    /// `[options]`
    #[serde(default)]
    pub options: Options,
    /// `[[units]]`: further gear units of a multi-gear part (empty for one gear).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub units: Vec<UnitSpec>,
    /// `[face]` (spiral family): a circular or annular face.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub face: Option<crate::milling::FaceSpec>,
    /// `[groove]` (spiral family): a planar spiral groove.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub groove: Option<crate::milling::GrooveSpec>,
    /// `[mill]` (spiral family): the tool.
    #[serde(default, skip_serializing_if = "is_default_mill")]
    pub mill: crate::milling::MillSpec,
    /// `[milling]` (spiral family): the process values fixed by the planner.
    #[serde(default, skip_serializing_if = "is_default_milling")]
    pub milling: crate::milling::MillingOverrides,
    /// `[die]` (wire family): the gear whose punch or die is cut.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub die: Option<crate::die::DieSpec>,
    /// `[wire]` (wire family): the wire and program fixed by the planner.
    #[serde(default, skip_serializing_if = "is_default_wire")]
    pub wire: crate::die::WireOverrides,
}

fn is_default_wire(w: &crate::die::WireOverrides) -> bool {
    *w == crate::die::WireOverrides::default()
}

fn is_default_mill(m: &crate::milling::MillSpec) -> bool {
    *m == crate::milling::MillSpec::default()
}

fn is_default_milling(m: &crate::milling::MillingOverrides) -> bool {
    *m == crate::milling::MillingOverrides::default()
}

impl JobSpec {
    /// True when the job gives its drawing data in a `[gear]` section; false
    /// when it names the part only (`[job] part_number`), for the knowledge
    /// service to fill the gear from the workpiece library.
    pub fn has_gear(&self) -> bool {
        self.gear.is_some()
    }
}

/// Message: a planning station asks for a job to be programmed and delivered.
///
/// Key `gearcam/v1/jobs/{job}/request`; published by the planning station,
/// subscribed by the knowledge service.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct JobRequest {
    /// The job's id (also in the key).
    pub job_id: JobId,
    /// When the station accepted the job, milliseconds since the Unix epoch.
    pub submitted_at_ms: u64,
    /// Who submitted it (station or user name).
    pub submitted_by: String,
    /// The job file's content.
    pub spec: JobSpec,
}

impl Message for JobRequest {
    const KIND: &'static str = "job_request";
}

/// The typed errors of the ids inside an encoded [`JobRequest`] that does not
/// decode: `BAD_JOB_ID` (`job_id` or `spec.job.id`) or `BAD_MACHINE_ID`
/// (`spec.job.machine`), each with the id as given. Empty when the ids are
/// valid or cannot be read (then the request is malformed for another reason).
pub fn request_id_errors(bytes: &[u8], stage: crate::Stage) -> Vec<crate::JobError> {
    #[derive(Deserialize)]
    struct Envelope {
        body: Loose,
    }
    #[derive(Deserialize)]
    struct Loose {
        job_id: Option<String>,
        spec: Option<LooseSpec>,
    }
    #[derive(Deserialize)]
    struct LooseSpec {
        job: Option<LooseHeader>,
    }
    #[derive(Deserialize)]
    struct LooseHeader {
        id: Option<String>,
        machine: Option<String>,
    }
    let Ok(Envelope { body }) = rmp_serde::from_slice::<Envelope>(bytes) else {
        return Vec::new();
    };
    let header = body.spec.and_then(|s| s.job);
    let (id, machine) = header.map_or((None, None), |h| (h.id, h.machine));
    let mut errors = Vec::new();
    if let Some(Err(e)) = body.job_id.map(JobId::new) {
        errors.push(crate::JobError::bad_id(stage, "job_id", &e));
    }
    if let Some(Err(e)) = id.map(JobId::new) {
        errors.push(crate::JobError::bad_id(stage, "spec.job.id", &e));
    }
    if let Some(Err(e)) = machine.map(MachineId::new) {
        errors.push(crate::JobError::bad_id(stage, "spec.job.machine", &e));
    }
    errors
}

fn one() -> u32 {
    1
}
fn one_f() -> f64 {
    1.0
}
fn twenty() -> f64 {
    20.0
}
fn quarter() -> f64 {
    0.25
}
fn eight() -> u8 {
    8
}
fn yes() -> bool {
    true
}
fn unspecified() -> String {
    "unspecified".into()
}

/// The machines of every family, as the station and the knowledge service
/// both name them when a job names a machine that is not there:
/// `H01, H02 (hobbing); M01, M02 (spiral face milling); W01, W02 (wire
/// EDM)` — a family without machines is left out.
pub fn machines_by_family(hobbing: &[String], mills: &[String], wires: &[String]) -> String {
    [
        (hobbing, "hobbing"),
        (mills, "spiral face milling"),
        (wires, "wire EDM"),
    ]
    .into_iter()
    .filter(|(ids, _)| !ids.is_empty())
    .map(|(ids, family)| format!("{} ({family})", ids.join(", ")))
    .collect::<Vec<_>>()
    .join("; ")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{decode, encode};

    fn by_part() -> JobRequest {
        let spec: JobSpec = serde_json::from_value(serde_json::json!({
            "job": {"machine": "H01", "part_number": "SP-1001"},
        }))
        .unwrap();
        JobRequest {
            job_id: JobId::new("J1").unwrap(),
            submitted_at_ms: 0,
            submitted_by: "test".into(),
            spec,
        }
    }

    #[test]
    fn a_job_may_name_its_part_instead_of_giving_a_gear_section() {
        let req = by_part();
        assert!(!req.spec.has_gear());
        assert!(req.spec.gear.is_none());
        // The absent gear is not written out, on the wire or as JSON.
        let json = serde_json::to_value(&req.spec).unwrap();
        assert!(json.get("gear").is_none(), "{json}");
        let back: JobRequest = decode(&encode(&req).unwrap()).unwrap();
        assert_eq!(back, req);
        assert!(!back.spec.has_gear());
    }

    #[test]
    fn a_gear_section_is_kept_and_written_out() {
        let mut req = by_part();
        req.spec.gear = Some(
            serde_json::from_value(serde_json::json!({
                "module_mm": 3.0, "teeth": 25, "face_width_mm": 30.0, "fixture_height_mm": 100.0,
            }))
            .unwrap(),
        );
        assert!(req.spec.has_gear());
        let back: JobRequest = decode(&encode(&req).unwrap()).unwrap();
        assert_eq!(back.spec.gear.as_ref().map(|g| g.teeth), Some(25));
        assert!(back.spec.has_gear());
    }
}
