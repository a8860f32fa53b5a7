//! The job: what a planning office asks for, typed by its part family. The
//! same structure is the TOML job file (`examples/*.toml`) and the body of the
//! [`JobRequest`] message.
//!
//! A job file names its family in `[job] family`; each family has its own
//! sections, and only those:
//!
//! | family | sections | module |
//! |---|---|---|
//! | `hobbing` (the default) | `[gear]`, `[hob]`, `[process]`, `[options]`, `[[units]]` | [`crate::hobbing`] |
//! | `spiral-face` | `[face]` or `[groove]`, `[mill]`, `[milling]` | [`crate::milling`] |
//! | `wire-edm` | `[die]`, `[wire]` | [`crate::die`] |
//!
//! [`JobSpec`] holds the header and one [`FamilySpec`] variant, so code that
//! plans a family reads that family's sections and nothing else. A section of
//! another family is refused when the job is decoded (a job file, a request on
//! the bus): [`ForeignSections`] names every such section. On the wire and in
//! a job file the job keeps its flat shape ([`JobFile`]: the header and the
//! sections side by side), so readers in other languages see one table per
//! section as before.

use serde::{Deserialize, Serialize};

use crate::codec::Message;
use crate::die::{DieSpec, WireOverrides};
use crate::hobbing::one;
pub use crate::hobbing::*;
use crate::ids::{JobId, MachineId};
use crate::milling::{FaceSpec, GrooveSpec, MillSpec, MillingOverrides};

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
    /// Every family, in the order documents list them.
    pub const ALL: [Family; 3] = [Family::Hobbing, Family::SpiralFace, Family::WireEdm];

    /// The name as written in job files.
    pub fn as_str(self) -> &'static str {
        match self {
            Family::Hobbing => "hobbing",
            Family::SpiralFace => "spiral-face",
            Family::WireEdm => "wire-edm",
        }
    }

    /// The sections a job of this family may have, as a job file writes them.
    pub fn sections(self) -> &'static [&'static str] {
        match self {
            Family::Hobbing => &["[gear]", "[hob]", "[process]", "[options]", "[[units]]"],
            Family::SpiralFace => &["[face] or [groove]", "[mill]", "[milling]"],
            Family::WireEdm => &["[die]", "[wire]"],
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

/// A hobbing job's sections.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct HobbingSpec {
    /// `[gear]`: the drawing data. A job file may leave the section out when
    /// its `part_number` names a workpiece in the knowledge base's library.
    /// The request keeps what was asked; the plan carries the resolved gear
    /// beside it ([`crate::ProcessPlan::gear`]), and every stage after the
    /// knowledge service reads that one.
    pub gear: Option<GearSpec>,
    /// `[hob]`
    pub hob: HobSpec,
    /// `[process]`
    pub process: ProcessOverrides,
    /// `[options]`
    pub options: Options,
    /// `[[units]]`: further gear units of a multi-gear part (empty for one gear).
    pub units: Vec<UnitSpec>,
}

/// A spiral face milling job's sections.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SpiralSpec {
    /// `[face]`: a circular or annular face.
    pub face: Option<FaceSpec>,
    /// `[groove]`: a planar spiral groove.
    pub groove: Option<GrooveSpec>,
    /// `[mill]`: the tool.
    pub mill: MillSpec,
    /// `[milling]`: the process values fixed by the planner.
    pub milling: MillingOverrides,
}

/// A wire EDM job's sections.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct WireSpec {
    /// `[die]`: the gear whose punch or die is cut.
    pub die: Option<DieSpec>,
    /// `[wire]`: the wire and program fixed by the planner.
    pub wire: WireOverrides,
}

/// The sections of a job, by its family.
// A job is made once per request and moved whole; the hobbing sections are
// the largest, and boxing them would buy nothing but indirection.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone, PartialEq)]
pub enum FamilySpec {
    /// Gear hobbing.
    Hobbing(HobbingSpec),
    /// Spiral face milling.
    SpiralFace(SpiralSpec),
    /// Wire EDM.
    WireEdm(WireSpec),
}

impl FamilySpec {
    /// The family of these sections.
    pub fn family(&self) -> Family {
        match self {
            FamilySpec::Hobbing(_) => Family::Hobbing,
            FamilySpec::SpiralFace(_) => Family::SpiralFace,
            FamilySpec::WireEdm(_) => Family::WireEdm,
        }
    }
}

/// A whole job: the `[job]` header and the sections of its family.
///
/// `job.family` names the variant of `part`; [`JobSpec::new`] keeps them
/// together, and decoding refuses a job whose sections belong to another
/// family.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "JobFile", into = "JobFile")]
pub struct JobSpec {
    /// `[job]`
    pub job: JobHeader,
    /// The family's sections.
    pub part: FamilySpec,
}

impl JobSpec {
    /// A job of `part`'s family (`job.family` set to it).
    pub fn new(mut job: JobHeader, part: FamilySpec) -> JobSpec {
        job.family = part.family();
        JobSpec { job, part }
    }

    /// The job's family.
    pub fn family(&self) -> Family {
        self.part.family()
    }

    /// The hobbing sections, if this is a hobbing job.
    pub fn hobbing(&self) -> Option<&HobbingSpec> {
        match &self.part {
            FamilySpec::Hobbing(h) => Some(h),
            _ => None,
        }
    }

    /// The hobbing sections to change, if this is a hobbing job.
    pub fn hobbing_mut(&mut self) -> Option<&mut HobbingSpec> {
        match &mut self.part {
            FamilySpec::Hobbing(h) => Some(h),
            _ => None,
        }
    }

    /// The spiral face milling sections, if this is a spiral job.
    pub fn spiral(&self) -> Option<&SpiralSpec> {
        match &self.part {
            FamilySpec::SpiralFace(s) => Some(s),
            _ => None,
        }
    }

    /// The spiral sections to change, if this is a spiral job.
    pub fn spiral_mut(&mut self) -> Option<&mut SpiralSpec> {
        match &mut self.part {
            FamilySpec::SpiralFace(s) => Some(s),
            _ => None,
        }
    }

    /// The wire EDM sections, if this is a wire job.
    pub fn wire(&self) -> Option<&WireSpec> {
        match &self.part {
            FamilySpec::WireEdm(w) => Some(w),
            _ => None,
        }
    }

    /// The wire sections to change, if this is a wire job.
    pub fn wire_mut(&mut self) -> Option<&mut WireSpec> {
        match &mut self.part {
            FamilySpec::WireEdm(w) => Some(w),
            _ => None,
        }
    }

    /// True when a hobbing job gives its drawing data in a `[gear]` section;
    /// false when it names the part only (`[job] part_number`), for the
    /// knowledge service to fill the gear from the workpiece library.
    pub fn has_gear(&self) -> bool {
        self.hobbing().is_some_and(|h| h.gear.is_some())
    }
}

/// A job in the shape of its file: the header and every family's sections
/// side by side. [`JobSpec`] is written in this shape and read from it;
/// [`JobSpec::try_from`] keeps the sections of the job's family and refuses
/// the others.
///
/// A section that has defaults counts as given when it differs from them
/// (a job written out carries `[hob]`, `[process]` and `[options]` at their
/// defaults whatever its family, as it always has).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JobFile {
    /// `[job]`
    pub job: JobHeader,
    /// `[gear]` (hobbing)
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gear: Option<GearSpec>,
    /// `[hob]` (hobbing)
    #[serde(default)]
    pub hob: HobSpec,
    /// `[process]` (hobbing)
    #[serde(default)]
    pub process: ProcessOverrides,
    /// `[options]` (hobbing)
    #[serde(default)]
    pub options: Options,
    /// `[[units]]` (hobbing)
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub units: Vec<UnitSpec>,
    /// `[face]` (spiral face milling)
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub face: Option<FaceSpec>,
    /// `[groove]` (spiral face milling)
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub groove: Option<GrooveSpec>,
    /// `[mill]` (spiral face milling)
    #[serde(default, skip_serializing_if = "is_default")]
    pub mill: MillSpec,
    /// `[milling]` (spiral face milling)
    #[serde(default, skip_serializing_if = "is_default")]
    pub milling: MillingOverrides,
    /// `[die]` (wire EDM)
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub die: Option<DieSpec>,
    /// `[wire]` (wire EDM)
    #[serde(default, skip_serializing_if = "is_default")]
    pub wire: WireOverrides,
}

fn is_default<T: Default + PartialEq>(v: &T) -> bool {
    *v == T::default()
}

/// The sections of a job file that belong to another family than its
/// `[job] family`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ForeignSections {
    /// The job's family.
    pub family: Family,
    /// Each section given that belongs to another family, with that family,
    /// in file order (`gear`, `face`, …).
    pub sections: Vec<(&'static str, Family)>,
}

impl std::fmt::Display for ForeignSections {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let named: Vec<String> = self
            .sections
            .iter()
            .map(|(s, fam)| format!("[{s}] belongs to the {} family", fam.as_str()))
            .collect();
        let lists: Vec<String> = Family::ALL
            .iter()
            .map(|fam| format!("{}: {}", fam.as_str(), fam.sections().join(", ")))
            .collect();
        write!(
            f,
            "{}; this job's [job] family is \"{}\" ({})",
            named.join(", "),
            self.family.as_str(),
            lists.join("; ")
        )
    }
}

impl std::error::Error for ForeignSections {}

impl JobFile {
    /// Every section given, with its family.
    fn given(&self) -> Vec<(&'static str, Family)> {
        [
            ("gear", Family::Hobbing, self.gear.is_some()),
            ("hob", Family::Hobbing, !is_default(&self.hob)),
            ("process", Family::Hobbing, !is_default(&self.process)),
            ("options", Family::Hobbing, !is_default(&self.options)),
            ("units", Family::Hobbing, !self.units.is_empty()),
            ("face", Family::SpiralFace, self.face.is_some()),
            ("groove", Family::SpiralFace, self.groove.is_some()),
            ("mill", Family::SpiralFace, !is_default(&self.mill)),
            ("milling", Family::SpiralFace, !is_default(&self.milling)),
            ("die", Family::WireEdm, self.die.is_some()),
            ("wire", Family::WireEdm, !is_default(&self.wire)),
        ]
        .into_iter()
        .filter(|(_, _, given)| *given)
        .map(|(s, f, _)| (s, f))
        .collect()
    }
}

impl TryFrom<JobFile> for JobSpec {
    type Error = ForeignSections;

    fn try_from(file: JobFile) -> Result<JobSpec, ForeignSections> {
        let family = file.job.family;
        let foreign: Vec<(&'static str, Family)> = file
            .given()
            .into_iter()
            .filter(|(_, f)| *f != family)
            .collect();
        if !foreign.is_empty() {
            return Err(ForeignSections {
                family,
                sections: foreign,
            });
        }
        let part = match family {
            Family::Hobbing => FamilySpec::Hobbing(HobbingSpec {
                gear: file.gear,
                hob: file.hob,
                process: file.process,
                options: file.options,
                units: file.units,
            }),
            Family::SpiralFace => FamilySpec::SpiralFace(SpiralSpec {
                face: file.face,
                groove: file.groove,
                mill: file.mill,
                milling: file.milling,
            }),
            Family::WireEdm => FamilySpec::WireEdm(WireSpec {
                die: file.die,
                wire: file.wire,
            }),
        };
        Ok(JobSpec {
            job: file.job,
            part,
        })
    }
}

impl From<JobSpec> for JobFile {
    fn from(spec: JobSpec) -> JobFile {
        let mut file = JobFile {
            job: spec.job,
            gear: None,
            hob: HobSpec::default(),
            process: ProcessOverrides::default(),
            options: Options::default(),
            units: Vec::new(),
            face: None,
            groove: None,
            mill: MillSpec::default(),
            milling: MillingOverrides::default(),
            die: None,
            wire: WireOverrides::default(),
        };
        file.job.family = spec.part.family();
        match spec.part {
            FamilySpec::Hobbing(h) => {
                (file.gear, file.hob, file.process) = (h.gear, h.hob, h.process);
                (file.options, file.units) = (h.options, h.units);
            }
            FamilySpec::SpiralFace(s) => {
                (file.face, file.groove) = (s.face, s.groove);
                (file.mill, file.milling) = (s.mill, s.milling);
            }
            FamilySpec::WireEdm(w) => (file.die, file.wire) = (w.die, w.wire),
        }
        file
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
        assert!(req.spec.hobbing().unwrap().gear.is_none());
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
        req.spec.hobbing_mut().unwrap().gear = Some(
            serde_json::from_value(serde_json::json!({
                "module_mm": 3.0, "teeth": 25, "face_width_mm": 30.0, "fixture_height_mm": 100.0,
            }))
            .unwrap(),
        );
        assert!(req.spec.has_gear());
        let back: JobRequest = decode(&encode(&req).unwrap()).unwrap();
        assert_eq!(
            back.spec.hobbing().unwrap().gear.as_ref().map(|g| g.teeth),
            Some(25)
        );
        assert!(back.spec.has_gear());
    }

    fn file(toml_text: &str) -> Result<JobSpec, String> {
        toml::from_str::<JobSpec>(toml_text).map_err(|e| e.to_string())
    }

    #[test]
    fn each_family_keeps_its_own_sections() {
        let hob = file("[job]\nmachine = \"H01\"\npart_number = \"P\"\n[gear]\nmodule_mm = 3\nteeth = 20\nface_width_mm = 20\nfixture_height_mm = 100\n").unwrap();
        assert_eq!(hob.family(), Family::Hobbing);
        assert_eq!(hob.hobbing().unwrap().gear.as_ref().unwrap().teeth, 20);
        assert!(hob.spiral().is_none() && hob.wire().is_none());
        let die = file("[job]\nfamily = \"wire-edm\"\nmachine = \"W01\"\npart_number = \"D\"\n[wire]\nprogram = \"3b\"\n").unwrap();
        assert_eq!(die.family(), Family::WireEdm);
        assert!(die.wire().unwrap().die.is_none());
        assert!(!die.has_gear());
    }

    #[test]
    fn a_section_of_another_family_is_a_decode_error_naming_it() {
        let err = file("[job]\nfamily = \"spiral-face\"\nmachine = \"M01\"\npart_number = \"F\"\n[gear]\nmodule_mm = 3\nteeth = 20\nface_width_mm = 20\nfixture_height_mm = 100\n[wire]\nprogram = \"3b\"\n").unwrap_err();
        assert!(
            err.contains("[gear] belongs to the hobbing family"),
            "{err}"
        );
        assert!(
            err.contains("[wire] belongs to the wire-edm family"),
            "{err}"
        );
        assert!(err.contains("family is \"spiral-face\""), "{err}");
        let direct: JobFile = toml::from_str("[job]\nmachine = \"H01\"\npart_number = \"P\"\n[die]\nteeth = 30\nmodule_mm = 2\npart = \"die\"\nthickness_mm = 10\nmaterial = \"Cr12MoV\"\n").unwrap();
        let foreign = JobSpec::try_from(direct).unwrap_err();
        assert_eq!(foreign.sections, [("die", Family::WireEdm)]);
        assert_eq!(foreign.family, Family::Hobbing);
    }

    #[test]
    fn a_request_on_the_bus_with_a_foreign_section_does_not_decode() {
        // A client's request in the flat shape with a [die] in a hobbing job:
        // the envelope is a job_request, and its body does not decode.
        #[derive(Serialize)]
        struct Loose<'a> {
            job_id: &'a str,
            submitted_at_ms: u64,
            submitted_by: &'a str,
            spec: JobFile,
        }
        #[derive(Serialize)]
        struct Envelope<'a> {
            schema: u16,
            kind: &'a str,
            body: Loose<'a>,
        }
        let mut spec = JobFile::from(by_part().spec);
        spec.die = Some(
            toml::from_str(
                "part = \"die\"\nmodule_mm = 2\nteeth = 20\nthickness_mm = 10\nmaterial = \"Cr12MoV\"",
            )
            .unwrap(),
        );
        let bytes = rmp_serde::to_vec_named(&Envelope {
            schema: crate::SCHEMA_VERSION,
            kind: JobRequest::KIND,
            body: Loose {
                job_id: "J1",
                submitted_at_ms: 0,
                submitted_by: "client",
                spec,
            },
        })
        .unwrap();
        let err = crate::decode::<JobRequest>(&bytes).unwrap_err();
        assert_eq!(err.code(), crate::Code::MALFORMED_MESSAGE);
        assert!(
            err.to_string()
                .contains("[die] belongs to the wire-edm family"),
            "{err}"
        );
    }

    #[test]
    fn a_job_is_written_in_its_file_shape_and_read_back() {
        let spec = file("[job]\nfamily = \"spiral-face\"\nmachine = \"M01\"\npart_number = \"F\"\n[face]\nouter_radius_mm = 100\ndepth_mm = 1\nmaterial = \"C45\"\n[milling]\npasses = 2\n").unwrap();
        let bytes = rmp_serde::to_vec_named(&spec).unwrap();
        let back: JobSpec = rmp_serde::from_slice(&bytes).unwrap();
        assert_eq!(back, spec);
        // The file shape: hobbing's defaulted sections are written for every
        // family, as before the job was typed, and read back as absent.
        let json = serde_json::to_value(&spec).unwrap();
        assert!(
            json.get("hob").is_some() && json.get("face").is_some(),
            "{json}"
        );
        assert_eq!(json["job"]["family"], "spiral-face");
        // new() keeps the header's family with the sections.
        let mut header = spec.job.clone();
        header.family = Family::Hobbing;
        let typed = JobSpec::new(header, FamilySpec::WireEdm(WireSpec::default()));
        assert_eq!(typed.job.family, Family::WireEdm);
    }
}
