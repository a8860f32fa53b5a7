//! The typed records, one per library, each read field by field from its
//! table's row (the fields as [`crate::library`] defines them).

use gearcam_proto::{CutMode, GearClass, Hand, HobData, Operation, Source};

use super::row::{RecordRow, TableRecord};
use crate::library::{self, Library};
use crate::KnowledgeError;

/// A hand as the libraries write it: `right` or `left`.
pub fn hand_name(hand: Hand) -> &'static str {
    match hand {
        Hand::Right => "right",
        Hand::Left => "left",
    }
}

fn hand(text: &str) -> Option<Hand> {
    match text {
        "right" => Some(Hand::Right),
        "left" => Some(Hand::Left),
        _ => None,
    }
}

fn operation(text: &str) -> Option<Operation> {
    match text {
        "rough" => Some(Operation::Rough),
        "finish" => Some(Operation::Finish),
        _ => None,
    }
}

fn cut_mode(text: &str) -> Option<CutMode> {
    match text {
        "conventional" => Some(CutMode::Conventional),
        "climb" => Some(CutMode::Climb),
        _ => None,
    }
}

/// How a case's job came out.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CaseOutcome {
    /// The parts were good.
    Ok,
    /// The parts needed rework.
    Rework,
    /// The parts were scrapped.
    Scrap,
    /// Not recorded.
    Unknown,
}

impl CaseOutcome {
    /// As the library writes it.
    pub fn as_str(self) -> &'static str {
        match self {
            CaseOutcome::Ok => "ok",
            CaseOutcome::Rework => "rework",
            CaseOutcome::Scrap => "scrap",
            CaseOutcome::Unknown => "unknown",
        }
    }

    /// From the library's text.
    pub fn parse(text: &str) -> Option<CaseOutcome> {
        [
            CaseOutcome::Ok,
            CaseOutcome::Rework,
            CaseOutcome::Scrap,
            CaseOutcome::Unknown,
        ]
        .into_iter()
        .find(|o| o.as_str() == text)
    }
}

/// Where a planned job stands.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JobState {
    /// Planned by the knowledge service.
    Planned,
    /// Its program was delivered to the machine.
    Delivered,
    /// Confirmed by the planner; it became a case.
    Confirmed,
    /// A later stage (model, template, agent) refused it: never cut from
    /// gearcam's program, never a case.
    Refused,
}

impl JobState {
    /// As the library writes it.
    pub fn as_str(self) -> &'static str {
        match self {
            JobState::Planned => "planned",
            JobState::Delivered => "delivered",
            JobState::Confirmed => "confirmed",
            JobState::Refused => "refused",
        }
    }

    /// From the library's text.
    pub fn parse(text: &str) -> Option<JobState> {
        [
            JobState::Planned,
            JobState::Delivered,
            JobState::Confirmed,
            JobState::Refused,
        ]
        .into_iter()
        .find(|s| s.as_str() == text)
    }
}

/// A case of the machining history (library `cases`): the problem's
/// features, the solution (cutting data) and the outcome, with trust.
#[derive(Debug, Clone, PartialEq)]
pub struct CaseRecord {
    /// Case id.
    pub id: String,
    /// Group-technology class.
    pub class: GearClass,
    /// Machine the case was cut on, when recorded.
    pub machine: Option<String>,
    /// Workpiece material.
    pub material: String,
    /// Material group (hard constraint of retrieval).
    pub material_group: String,
    /// Hardness when hobbed, HB, when recorded.
    pub hardness_hb: Option<f64>,
    /// Normal module, mm.
    pub module_mm: f64,
    /// Teeth.
    pub teeth: u32,
    /// Helix angle magnitude, degrees.
    pub helix_angle_deg: f64,
    /// Face width, mm, when recorded.
    pub face_width_mm: Option<f64>,
    /// Accuracy grade.
    pub quality_grade: u8,
    /// Hob cutting material.
    pub hob_material: String,
    /// Hob coating.
    pub hob_coating: String,
    /// Hob starts.
    pub hob_starts: u32,
    /// Hob outside diameter used, mm, when recorded.
    pub hob_od_mm: Option<f64>,
    /// Rough or finish hobbing.
    pub operation: Operation,
    /// Cutting speed vc, m/min.
    pub cutting_speed_m_min: f64,
    /// Axial feed per workpiece revolution, mm/rev.
    pub feed_mm_per_rev: f64,
    /// Hob speed used, rpm, when recorded.
    pub hob_rpm: Option<f64>,
    /// Axial feed rate used, mm/min, when recorded.
    pub axial_feed_mm_min: Option<f64>,
    /// Radial (infeed) feed rate, mm/min, when recorded.
    pub radial_feed_mm_min: Option<f64>,
    /// Number of cuts.
    pub cuts: u32,
    /// Stock / finish allowance, mm, when recorded.
    pub allowance_mm: Option<f64>,
    /// Whether the hob was shifted during the job.
    pub shifting: bool,
    /// Cutting mode, when recorded.
    pub cut_mode: Option<CutMode>,
    /// How the job came out.
    pub outcome: CaseOutcome,
    /// Grade measured, when recorded.
    pub quality_achieved: Option<u8>,
    /// Remarks.
    pub notes: String,
    /// How far to trust the case, 0–1.
    pub confidence: f64,
    /// Where the values come from.
    pub provenance: String,
    /// The confirmed job it came from, if any.
    pub job_id: Option<String>,
    /// When recorded, ms since the epoch.
    pub created_at_ms: u64,
}

impl TableRecord for CaseRecord {
    const LIBRARY: &'static Library = &library::CASES;

    fn from_row(r: &RecordRow<'_, '_>) -> Result<Self, KnowledgeError> {
        Ok(CaseRecord {
            id: r.get("id")?,
            class: r.choice("class", GearClass::parse)?,
            machine: r.get("machine")?,
            material: r.get("material")?,
            material_group: r.get("material_group")?,
            hardness_hb: r.get("hardness_hb")?,
            module_mm: r.get("module_mm")?,
            teeth: r.get("teeth")?,
            helix_angle_deg: r.get("helix_angle_deg")?,
            face_width_mm: r.get("face_width_mm")?,
            quality_grade: r.get("quality_grade")?,
            hob_material: r.get("hob_material")?,
            hob_coating: r.get("hob_coating")?,
            hob_starts: r.get("hob_starts")?,
            hob_od_mm: r.get("hob_od_mm")?,
            operation: r.choice("operation", operation)?,
            cutting_speed_m_min: r.get("cutting_speed_m_min")?,
            feed_mm_per_rev: r.get("feed_mm_per_rev")?,
            hob_rpm: r.get("hob_rpm")?,
            axial_feed_mm_min: r.get("axial_feed_mm_min")?,
            radial_feed_mm_min: r.get("radial_feed_mm_min")?,
            cuts: r.get("cuts")?,
            allowance_mm: r.get("allowance_mm")?,
            shifting: r.get("shifting")?,
            cut_mode: r.choice_or_null("cut_mode", cut_mode)?,
            outcome: r.choice("outcome", CaseOutcome::parse)?,
            quality_achieved: r.get("quality_achieved")?,
            notes: r.get("notes")?,
            confidence: r.get("confidence")?,
            provenance: r.get("provenance")?,
            job_id: r.get("job_id")?,
            created_at_ms: r.get("created_at_ms")?,
        })
    }
}

/// A hob of the tool library (library `hobs`): what hob matching reads,
/// what the plan's [`HobData`] is made of, and what the seed writes.
#[derive(Debug, Clone, PartialEq)]
pub struct HobRecord {
    /// Hob id.
    pub id: String,
    /// Normal module mn0, mm.
    pub module_mm: f64,
    /// Normal pressure angle α0, degrees.
    pub pressure_angle_deg: f64,
    /// Starts z0.
    pub starts: u32,
    /// Hand of the thread.
    pub hand: Hand,
    /// Lead angle γ0, degrees.
    pub lead_angle_deg: f64,
    /// Outside diameter da0, mm.
    pub od_mm: f64,
    /// Overall length, mm.
    pub length_mm: f64,
    /// Usable (cutting) length, mm.
    pub usable_length_mm: f64,
    /// Accuracy class AA/A/B/C (DIN 3968); hob matching explains any other.
    pub accuracy_class: String,
    /// Cutting material, e.g. HSS.
    pub material: String,
    /// Coating, e.g. TiN.
    pub coating: String,
    /// Current shift position from the start of the usable length, mm.
    pub shift_position_mm: f64,
    /// Shift per step, mm.
    pub shift_step_mm: f64,
    /// Parts cut per shift step.
    pub parts_per_shift: u32,
    /// Parts the hob can still cut before regrinding.
    pub remaining_life_parts: u64,
    /// Where the data comes from.
    pub source: String,
}

impl HobRecord {
    /// The hob's data as the plan carries it, with source `library`: its
    /// geometry comes from the tool library, not from a case or the machine.
    pub fn data(&self) -> HobData {
        HobData {
            id: self.id.clone(),
            starts: self.starts,
            od_mm: self.od_mm,
            module_mm: self.module_mm,
            pressure_angle_deg: self.pressure_angle_deg,
            lead_angle_deg: self.lead_angle_deg,
            hand: self.hand,
            length_mm: self.length_mm,
            usable_length_mm: Some(self.usable_length_mm),
            source: Source::Library,
        }
    }
}

impl TableRecord for HobRecord {
    const LIBRARY: &'static Library = &library::HOBS;

    fn from_row(r: &RecordRow<'_, '_>) -> Result<Self, KnowledgeError> {
        Ok(HobRecord {
            id: r.get("id")?,
            module_mm: r.get("module_mm")?,
            pressure_angle_deg: r.get("pressure_angle_deg")?,
            starts: r.get("starts")?,
            hand: r.choice("hand", hand)?,
            lead_angle_deg: r.get("lead_angle_deg")?,
            od_mm: r.get("od_mm")?,
            length_mm: r.get("length_mm")?,
            usable_length_mm: r.get("usable_length_mm")?,
            accuracy_class: r.get("accuracy_class")?,
            material: r.get("material")?,
            coating: r.get("coating")?,
            shift_position_mm: r.get("shift_position_mm")?,
            shift_step_mm: r.get("shift_step_mm")?,
            parts_per_shift: r.get("parts_per_shift")?,
            remaining_life_parts: r.get("remaining_life_parts")?,
            source: r.get("source")?,
        })
    }
}

/// A workpiece (library `workpieces`): drawing data by part number.
#[derive(Debug, Clone, PartialEq)]
pub struct WorkpieceRecord {
    /// Drawing number.
    pub part_number: String,
    /// What the part is.
    pub description: String,
    /// Group-technology class.
    pub class: GearClass,
    /// Normal module mn, mm.
    pub module_mm: f64,
    /// Number of teeth z.
    pub teeth: u32,
    /// Normal pressure angle αn, degrees.
    pub pressure_angle_deg: f64,
    /// Helix angle β magnitude, degrees.
    pub helix_angle_deg: f64,
    /// Hand of the helix (absent for a spur gear).
    pub helix_hand: Option<Hand>,
    /// Face width b, mm.
    pub face_width_mm: f64,
    /// Profile shift coefficient x.
    pub profile_shift: f64,
    /// Addendum coefficient ha*.
    pub addendum_coef: f64,
    /// Tip clearance coefficient c*.
    pub clearance_coef: f64,
    /// Blank outside diameter Da1, mm, when known.
    pub blank_od_mm: Option<f64>,
    /// X correction Δx, mm.
    pub od_correction_mm: f64,
    /// Material.
    pub material: String,
    /// Hardness when hobbed, HB, when known.
    pub hardness_hb: Option<f64>,
    /// Accuracy grade (ISO 1328).
    pub quality_grade: u8,
    /// H: lower tooth face above the table, mm.
    pub fixture_height_mm: f64,
    /// Cone angle δ of a conical gear, degrees, when known.
    pub cone_angle_deg: Option<f64>,
    /// Where the data comes from.
    pub source: String,
}

impl TableRecord for WorkpieceRecord {
    const LIBRARY: &'static Library = &library::WORKPIECES;

    fn from_row(r: &RecordRow<'_, '_>) -> Result<Self, KnowledgeError> {
        Ok(WorkpieceRecord {
            part_number: r.get("part_number")?,
            description: r.get("description")?,
            class: r.choice("class", GearClass::parse)?,
            module_mm: r.get("module_mm")?,
            teeth: r.get("teeth")?,
            pressure_angle_deg: r.get("pressure_angle_deg")?,
            helix_angle_deg: r.get("helix_angle_deg")?,
            helix_hand: r.choice_or_null("helix_hand", hand)?,
            face_width_mm: r.get("face_width_mm")?,
            profile_shift: r.get("profile_shift")?,
            addendum_coef: r.get("addendum_coef")?,
            clearance_coef: r.get("clearance_coef")?,
            blank_od_mm: r.get("blank_od_mm")?,
            od_correction_mm: r.get("od_correction_mm")?,
            material: r.get("material")?,
            hardness_hb: r.get("hardness_hb")?,
            quality_grade: r.get("quality_grade")?,
            fixture_height_mm: r.get("fixture_height_mm")?,
            cone_angle_deg: r.get("cone_angle_deg")?,
            source: r.get("source")?,
        })
    }
}

/// A material (library `materials`): its group, the hard constraint of
/// retrieval, and its typical hardness.
#[derive(Debug, Clone, PartialEq)]
pub struct MaterialRecord {
    /// Material name, e.g. 20CrMnTi.
    pub name: String,
    /// Group, e.g. case_hardening_steel.
    pub material_group: String,
    /// Typical hardness when hobbed, HB, when known.
    pub hardness_hb: Option<f64>,
    /// Where the data comes from.
    pub source: String,
}

impl TableRecord for MaterialRecord {
    const LIBRARY: &'static Library = &library::MATERIALS;

    fn from_row(r: &RecordRow<'_, '_>) -> Result<Self, KnowledgeError> {
        Ok(MaterialRecord {
            name: r.get("name")?,
            material_group: r.get("material_group")?,
            hardness_hb: r.get("hardness_hb")?,
            source: r.get("source")?,
        })
    }
}

/// A similarity weight of case retrieval (library `weights`).
#[derive(Debug, Clone, PartialEq)]
pub struct WeightRecord {
    /// The feature, one of [`crate::cbr::FEATURES`].
    pub feature: String,
    /// Its weight (0 ignores the feature).
    pub weight: f64,
    /// Who set it and why.
    pub source: String,
}

impl TableRecord for WeightRecord {
    const LIBRARY: &'static Library = &library::WEIGHTS;

    fn from_row(r: &RecordRow<'_, '_>) -> Result<Self, KnowledgeError> {
        Ok(WeightRecord {
            feature: r.get("feature")?,
            weight: r.get("weight")?,
            source: r.get("source")?,
        })
    }
}

/// A job the knowledge service planned (library `jobs`), and its state.
#[derive(Debug, Clone, PartialEq)]
pub struct JobRecord {
    /// Job id.
    pub job_id: String,
    /// Part number.
    pub part_number: String,
    /// Machine.
    pub machine: String,
    /// Group-technology class (hobbing), or the spiral family's part kind.
    pub class: JobClass,
    /// Parts ordered.
    pub quantity: u32,
    /// The tool used: the hob, the mill (spiral face milling) or the wire
    /// (wire EDM).
    pub tool_id: String,
    /// Planned, delivered or confirmed.
    pub state: JobState,
    /// Confidence of the proposal.
    pub confidence: f64,
    /// The process plan (JSON).
    pub plan_json: String,
    /// The delivered program, once delivered.
    pub program_name: Option<String>,
    /// When planned, ms since the epoch.
    pub planned_at_ms: u64,
    /// When delivered.
    pub delivered_at_ms: Option<u64>,
    /// When confirmed.
    pub confirmed_at_ms: Option<u64>,
    /// Parts actually cut (confirm).
    pub delivered_quantity: Option<u32>,
    /// The case the confirmation made.
    pub case_id: Option<String>,
}

impl TableRecord for JobRecord {
    const LIBRARY: &'static Library = &library::JOBS;

    fn from_row(r: &RecordRow<'_, '_>) -> Result<Self, KnowledgeError> {
        Ok(JobRecord {
            job_id: r.get("job_id")?,
            part_number: r.get("part_number")?,
            machine: r.get("machine")?,
            class: r.choice("class", JobClass::parse)?,
            quantity: r.get("quantity")?,
            tool_id: r.get("tool_id")?,
            state: r.choice("state", JobState::parse)?,
            confidence: r.get("confidence")?,
            plan_json: r.get("plan_json")?,
            program_name: r.get("program_name")?,
            planned_at_ms: r.get("planned_at_ms")?,
            delivered_at_ms: r.get("delivered_at_ms")?,
            confirmed_at_ms: r.get("confirmed_at_ms")?,
            delivered_quantity: r.get("delivered_quantity")?,
            case_id: r.get("case_id")?,
        })
    }
}

/// What a planned job is: a hobbed gear of a group-technology class, or a
/// spiral face milling job (`spiral-face`, `spiral-groove`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JobClass {
    /// Hobbing, with the gear's class.
    Gear(GearClass),
    /// Spiral face milling of a face.
    SpiralFace,
    /// Spiral face milling of a planar spiral groove.
    SpiralGroove,
    /// A punch or die cut by wire EDM.
    Wire,
}

impl JobClass {
    /// The class from its stored name.
    pub fn parse(s: &str) -> Option<JobClass> {
        match s {
            "spiral-face" => Some(JobClass::SpiralFace),
            "spiral-groove" => Some(JobClass::SpiralGroove),
            "wire-punch" | "wire-die" => Some(JobClass::Wire),
            _ => GearClass::parse(s).map(JobClass::Gear),
        }
    }
}

/// A class of the group-technology tree (library `classes`).
#[derive(Debug, Clone, PartialEq)]
pub struct ClassRecord {
    /// Class id, e.g. cylindrical.
    pub id: String,
    /// Parent class id (absent for the root).
    pub parent: Option<String>,
    /// Human name.
    pub name: String,
    /// Tooth trace / generating line.
    pub tooth_trace: String,
    /// Deformation along the face width.
    pub deformation: String,
    /// How it is hobbed.
    pub hobbing_method: String,
    /// Whether gearcam programs it in this release.
    pub programmable: bool,
    /// Where the entry comes from.
    pub source: String,
}

impl TableRecord for ClassRecord {
    const LIBRARY: &'static Library = &library::CLASSES_LIB;

    fn from_row(r: &RecordRow<'_, '_>) -> Result<Self, KnowledgeError> {
        Ok(ClassRecord {
            id: r.get("id")?,
            parent: r.get("parent")?,
            name: r.get("name")?,
            tooth_trace: r.get("tooth_trace")?,
            deformation: r.get("deformation")?,
            hobbing_method: r.get("hobbing_method")?,
            programmable: r.get("programmable")?,
            source: r.get("source")?,
        })
    }
}
