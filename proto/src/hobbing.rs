//! The hobbing family's job sections: `[gear]` (with its mate, cone,
//! crowning, worm wheel and curved tooth), `[hob]`, `[process]` (with
//! `[process.shift]`), `[options]` and `[[units]]`.
//!
//! Drawing data is required: in the `[gear]` section, or by a `[job]
//! part_number` that names a workpiece in the knowledge base's library (the
//! knowledge service resolves the gear and the plan carries it, see
//! [`crate::ProcessPlan::gear`]). Everything else has a decided default that
//! the knowledge service fills in and records as such. Unknown keys are
//! rejected so a misspelt key never silently falls back to a default.

use serde::{Deserialize, Serialize};

pub use crate::cutting::CutMode;
use crate::ids::HobId;

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

pub(crate) fn one() -> u32 {
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
