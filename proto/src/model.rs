//! The machining model: geometry and hobbing kinematics computed by the model service.

use serde::{Deserialize, Serialize};

use crate::class::GearClass;
use crate::codec::Message;
use crate::ids::JobId;
use crate::job::Infeed;
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
    /// Base helix angle βb = asin(sin β·cos αn), degrees (0 for spur gears).
    #[serde(default)]
    pub base_helix_deg: f64,
    /// Normal tooth thickness at the reference circle without backlash
    /// allowance, sn = mn·(π/2 + 2·x·tan αn), mm.
    #[serde(default)]
    pub sn_mm: f64,
    /// Number of teeth k spanned by the base tangent length measurement.
    #[serde(default)]
    pub span_teeth: u32,
    /// Base tangent length (span measurement) over `span_teeth` teeth,
    /// Wk = mn·cos αn·((k − 0.5)·π + z·inv αt) + 2·x·mn·sin αn, mm.
    #[serde(default)]
    pub span_mm: f64,
    /// Ball (or pin) diameter DM of the measurement over balls, mm.
    #[serde(default)]
    pub ball_mm: f64,
    /// Dimension over two balls MdK, mm.
    #[serde(default)]
    pub over_balls_mm: f64,
    /// Geometry of the pair with the mating gear, when the job names one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pair: Option<PairGeometry>,
}

/// A gear pair (ISO 21771): the job's gear with its mate.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PairGeometry {
    /// Teeth of the mating gear.
    pub mate_teeth: u32,
    /// Profile shift coefficient of the mating gear.
    pub mate_profile_shift: f64,
    /// Reference centre distance a = (d1 + d2)/2, mm.
    pub reference_centre_distance_mm: f64,
    /// Working transverse pressure angle αwt, degrees.
    pub working_pressure_angle_deg: f64,
    /// Working centre distance aw = a·cos αt / cos αwt, mm.
    pub centre_distance_mm: f64,
    /// Transverse contact ratio εα.
    pub contact_ratio: f64,
    /// Overlap ratio εβ = b·sin β / (π·mn).
    pub overlap_ratio: f64,
    /// Total contact ratio εγ = εα + εβ.
    pub total_contact_ratio: f64,
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

/// The exact coupling ratio of the electronic gearbox: table turns per hob
/// turn, signed (the sign is the direction of the table against the hob, see
/// `docs/hobbing.md`, "Signs").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct Ratio {
    /// Numerator: hob starts z0 (reduced), with the direction's sign.
    pub num: i32,
    /// Denominator: gear teeth z.
    pub den: u32,
}

/// Hobbing kinematics of one job (docs/hobbing.md#4-the-cycle-positions-speeds-feeds).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Kinematics {
    /// Signed setting angle of the hob axis against the gear end face in the
    /// machine-neutral frame, η = s_g·β − s_h·γ0, degrees (docs/hobbing.md).
    pub swivel_deg: f64,
    /// Value programmed on the swivel axis: swivel_sign·η + swivel_offset of
    /// the machine profile, degrees.
    pub swivel_axis_deg: f64,
    /// ΔH′: how far the finite hob (tip cylinder of its length, tilted by
    /// |η|) reaches below its centre over the blank at the approach end, mm,
    /// without safety distance.
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
    /// Differential in the machine-neutral frame: degrees of table per mm of
    /// axial travel, s_g·360·sin β/(π·mn·z); the gear's hand alone gives the sign.
    pub differential_deg_per_mm: f64,
    /// Indexing ratio table:hob in the machine-neutral frame, s_h·z0/z, kept
    /// exact; the hob's hand alone gives the sign.
    pub coupling: Ratio,
    /// Machining time of one cut, minutes: (b + 2·ΔH′)·z / (Nt·z0·fa).
    pub cut_time_min: f64,
    /// Cutting mode.
    pub cut_mode: crate::job::CutMode,
    /// The cuts in order, each with its depth, positions, feeds, shift, moves
    /// and time; the last one finishes. The top-level positions, centre
    /// distance, depth, speeds and feed above are those of the finishing cut.
    pub cuts: Vec<Cut>,
    /// Group-technology class the model was computed for.
    #[serde(default)]
    pub class: GearClass,
    /// Infeed mode.
    #[serde(default)]
    pub infeed: Infeed,
    /// Electronic-gearbox coupling factors.
    #[serde(default)]
    pub factors: CouplingFactors,
    /// Machining time of one part (every cut, plunges and dwells), minutes.
    #[serde(default)]
    pub part_time_min: f64,
    /// Machining time of the whole quantity, minutes.
    #[serde(default)]
    pub job_time_min: f64,
    /// Hob shifting, when the job asks for it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shift: Option<ShiftPlan>,
    /// Conical gear: the taper of the X–Z path.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cone: Option<ConeModel>,
    /// Crowned gear: the crowning curve.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub crowning: Option<CrowningModel>,
    /// Worm wheel: the infeed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub worm: Option<WormModel>,
    /// Multi-gear part: every unit in machining order (empty for one gear).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub units: Vec<UnitModel>,
    /// Every input and result with where it came from.
    #[serde(default)]
    pub explain: Vec<Explained>,
}

/// Kind of a path move.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum MoveKind {
    /// Rapid positioning (G0).
    Rapid,
    /// Straight move at feed (G1).
    Feed,
    /// Circular move at feed through an intermediate point (840D `CIP`).
    Arc,
    /// Dwell at the current position (G4).
    Dwell,
}

/// One move of a cut's path; X, Z and Y are end points, given only for the
/// axes the move changes.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Move {
    /// Kind.
    pub kind: MoveKind,
    /// X at the end, mm, when the move changes X.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub x_mm: Option<f64>,
    /// Z at the end, mm, when the move changes Z.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub z_mm: Option<f64>,
    /// Hob shift Y at the end, mm, when the move involves the shift axis.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub y_mm: Option<f64>,
    /// Feed rate, mm/min (0 for rapid moves and dwells).
    pub feed_mm_min: f64,
    /// Intermediate point of an arc.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub via: Option<Position>,
    /// Radius of an arc, mm.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radius_mm: Option<f64>,
    /// Dwell time, seconds.
    #[serde(default)]
    pub dwell_s: f64,
    /// What the move does, for the program's comments.
    pub note: String,
}

/// One cut of a hobbing cycle.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Cut {
    /// 1-based number.
    pub number: u32,
    /// True for the finishing (last) cut.
    pub finish: bool,
    /// Radial depth reached by this cut, mm.
    pub depth_mm: f64,
    /// Radial stock left for later cuts, mm.
    pub allowance_mm: f64,
    /// Centre distance of this cut, mm.
    pub centre_distance_mm: f64,
    /// Approach clearance ΔH′ of this cut, mm.
    pub clearance_mm: f64,
    /// Positions A–E of this cut.
    pub positions: Positions,
    /// Axial feed per workpiece revolution, mm/rev.
    pub feed_mm_per_rev: f64,
    /// Table speed, rpm.
    pub table_rpm: f64,
    /// Axial feed rate, mm/min.
    pub axial_feed_mm_min: f64,
    /// Radial feed rate of a plunge, mm/min (0 without one).
    pub radial_feed_mm_min: f64,
    /// Hob shift position of this cut for the first part, mm.
    pub shift_mm: f64,
    /// True when the gearbox re-synchronises into the existing gaps before this cut.
    pub resync: bool,
    /// The moves from B to E.
    pub moves: Vec<Move>,
    /// Machining time: feed moves and dwells, minutes.
    pub time_min: f64,
}

/// Electronic-gearbox coupling factors (docs/hobbing.md#4-the-cycle-positions-speeds-feeds).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CouplingFactors {
    /// C per B as programmed: table turns per hob turn in the machine's axis
    /// directions, ±z0/z as an exact integer ratio.
    pub c_per_b: Ratio,
    /// C per Z as programmed: differential, degrees of table per mm of axial
    /// travel in the machine's axis directions (signed).
    pub c_per_z_deg_per_mm: f64,
    /// C per Y as programmed: shift compensation, degrees of table per mm of
    /// hob shift in the machine's axis directions (signed).
    pub c_per_y_deg_per_mm: f64,
}

impl Default for CouplingFactors {
    fn default() -> Self {
        CouplingFactors {
            c_per_b: Ratio { num: 1, den: 1 },
            c_per_z_deg_per_mm: 0.0,
            c_per_y_deg_per_mm: 0.0,
        }
    }
}

/// Shift positions for a run of parts.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PartShift {
    /// First part (1-based).
    pub from_part: u32,
    /// Last part.
    pub to_part: u32,
    /// Shift position of the first cut, mm.
    pub shift_mm: f64,
}

/// Hob shifting inside the usable hob length.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ShiftPlan {
    /// Per part or per cut.
    pub mode: crate::job::ShiftMode,
    /// Usable range of shift positions relative to the hob centre, mm [from, to].
    pub usable_mm: [f64; 2],
    /// Active (generating) length of the hob, mm.
    pub active_length_mm: f64,
    /// First position, mm.
    pub start_mm: f64,
    /// Last position, mm.
    pub end_mm: f64,
    /// Shift per step, mm.
    pub step_mm: f64,
    /// Parts per step.
    pub parts_per_step: u32,
    /// Number of distinct positions in [start, end].
    pub positions: u32,
    /// Position of the first cut for each run of parts of the job's quantity.
    pub parts: Vec<PartShift>,
}

/// Conical gear: X follows Z along the cone angle.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ConeModel {
    /// Cone angle δ, degrees.
    pub angle_deg: f64,
    /// Face with the larger diameter.
    pub large_end: crate::job::LargeEnd,
    /// Change of X per mm of Z upwards (−tan δ when the large end is at the bottom).
    pub x_per_z: f64,
    /// Finishing X at the large end face, mm.
    pub x_large_mm: f64,
    /// Finishing X at the small end face, mm.
    pub x_small_mm: f64,
}

/// Crowned gear: the X–Z crowning curve.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CrowningModel {
    /// Shape.
    pub shape: crate::job::CrowningShape,
    /// Crowning amount Cb, mm.
    pub amount_mm: f64,
    /// Radius of a circular crowning Rc = (b²/4 + Cb²)/(2·Cb), mm.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radius_mm: Option<f64>,
    /// Chords of a parabolic crowning.
    pub chords: u32,
    /// Stated chord tolerance, mm.
    pub tolerance_mm: f64,
    /// Largest deviation of the programmed path from the curve, mm.
    pub max_deviation_mm: f64,
}

/// Worm wheel infeed.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct WormModel {
    /// Radial or tangential.
    pub infeed: crate::job::WormInfeed,
    /// Final centre distance a = (d2 + d0)/2 + x·mn, mm.
    pub centre_distance_mm: f64,
    /// Throat plane height (hob centre Z), mm.
    pub throat_z_mm: f64,
    /// X where the radial feed starts, mm.
    pub start_x_mm: f64,
    /// Radial feed rate, mm/min.
    pub radial_feed_mm_min: f64,
    /// Dwell at the final centre distance, seconds.
    pub dwell_s: f64,
    /// Tangential infeed: Y where the feed starts, mm.
    pub start_y_mm: f64,
    /// Tangential infeed: Y where it ends, mm.
    pub end_y_mm: f64,
    /// Tangential feed rate, mm/min.
    pub tangential_feed_mm_min: f64,
}

/// One unit of a multi-gear part.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct UnitModel {
    /// Name.
    pub name: String,
    /// Unit class.
    pub class: GearClass,
    /// Height of the unit's lower tooth face above the first unit's, mm.
    pub z_offset_mm: f64,
    /// Hob id.
    pub hob_id: String,
    /// True when the hob must be changed before this unit.
    pub hob_change: bool,
    /// The unit's hob.
    pub hob: crate::plan::HobData,
    /// The unit's gear data.
    pub gear: crate::job::GearSpec,
    /// The unit's geometry.
    pub geometry: Geometry,
    /// The unit's kinematics.
    pub model: Kinematics,
}

/// Where a value came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Origin {
    /// The job file.
    Job,
    /// A knowledge-base case or cutting-data record.
    Case,
    /// The machine profile.
    Machine,
    /// A knowledge-base library: the tool library (hob data) or the
    /// workpiece library (drawing data by part number).
    Library,
    /// A documented gearcam default.
    Default,
    /// Bounded by the drawing's accuracy class (a feed whose feed marks
    /// stay within the class).
    Grade,
    /// Computed by the model from other values.
    Computed,
}

/// A value with its unit, origin and how it was obtained.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Explained {
    /// Name, e.g. `hob_rpm`.
    pub name: String,
    /// Value.
    pub value: f64,
    /// Unit, e.g. `rpm`.
    pub unit: String,
    /// Origin.
    pub origin: Origin,
    /// Formula or reference.
    pub note: String,
}

/// A non-fatal finding (e.g. blank OD at the edge of its window).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Warning {
    /// Stable code.
    pub code: crate::Code,
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
