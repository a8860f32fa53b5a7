//! The job file's sections of the wire EDM family (docs/wire.md#the-job-file):
//! `[die]` and `[wire]`. The plan and model messages are in [`crate::wire`].

use serde::{Deserialize, Serialize};

/// Which part of the tool set is cut.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum DiePart {
    /// The punch: the gear itself; the wire runs outside its outline.
    Punch,
    /// The die: a plate with the gear's opening; the wire runs inside.
    Die,
}

impl DiePart {
    /// The name as written in files.
    pub fn as_str(self) -> &'static str {
        match self {
            DiePart::Punch => "punch",
            DiePart::Die => "die",
        }
    }
}

/// The tool that generates the gear's root fillet.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Cutter {
    /// A rack or hob (the default).
    #[default]
    Rack,
    /// A pinion-type (shaper) cutter: `cutter_teeth`, `cutter_shift`.
    Pinion,
}

/// The program form of a wire job.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum WireProgram {
    /// 3B: the wire's path, µm blocks `B X B Y B J G Z`.
    #[serde(rename = "3b")]
    ThreeB,
    /// 4B: the part's outline with each arc's radius and convexity; the
    /// control sets the wire off.
    #[serde(rename = "4b")]
    FourB,
    /// ISO wire G-code: the part's outline with G41/G42 compensation.
    #[serde(rename = "iso-wire")]
    IsoWire,
}

impl WireProgram {
    /// The name as written in files and JSON.
    pub fn as_str(self) -> &'static str {
        match self {
            WireProgram::ThreeB => "3b",
            WireProgram::FourB => "4b",
            WireProgram::IsoWire => "iso-wire",
        }
    }
}

/// `[die]`: the gear whose punch or die is cut, and how exactly.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DieSpec {
    /// `punch` or `die`.
    pub part: DiePart,
    /// Module m, mm.
    pub module_mm: f64,
    /// Teeth z (≥ 5).
    pub teeth: u32,
    /// Pressure angle α, degrees (default 20).
    #[serde(default = "twenty")]
    pub pressure_angle_deg: f64,
    /// Profile shift x (default 0).
    #[serde(default)]
    pub profile_shift: f64,
    /// Addendum coefficient ha* (default 1).
    #[serde(default = "one")]
    pub addendum_coef: f64,
    /// Tip clearance coefficient c* (default 0.25).
    #[serde(default = "quarter")]
    pub clearance_coef: f64,
    /// The generating tool (default `rack`).
    #[serde(default)]
    pub cutter: Cutter,
    /// The tool's tip radius as a share of m, ρ* (default 0.38).
    #[serde(default = "tip_radius")]
    pub cutter_tip_radius_coef: f64,
    /// A pinion cutter's teeth z0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cutter_teeth: Option<u32>,
    /// A pinion cutter's profile shift x0 (default 0).
    #[serde(default)]
    pub cutter_shift: f64,
    /// The mating gear's teeth z2, for the pair's centre distance.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mating_teeth: Option<u32>,
    /// The mating gear's profile shift x2 (default 0).
    #[serde(default)]
    pub mating_shift: f64,
    /// Tolerance of the arcs on the flank, µm (default 1).
    #[serde(default = "one")]
    pub flank_tolerance_um: f64,
    /// Tolerance of the arcs on the root fillet, µm (default 5).
    #[serde(default = "five")]
    pub fillet_tolerance_um: f64,
    /// Plate thickness, mm.
    pub thickness_mm: f64,
    /// Plate material, e.g. `Cr12MoV`.
    pub material: String,
}

impl DieSpec {
    /// A die or punch with the job file's defaults: α 20°, no shift, ha* 1,
    /// c* 0.25, a rack with ρ* 0.38, 1 µm on the flank, 5 µm on the fillet.
    pub fn new(
        part: DiePart,
        module_mm: f64,
        teeth: u32,
        thickness_mm: f64,
        material: &str,
    ) -> DieSpec {
        DieSpec {
            part,
            module_mm,
            teeth,
            pressure_angle_deg: twenty(),
            profile_shift: 0.0,
            addendum_coef: one(),
            clearance_coef: quarter(),
            cutter: Cutter::Rack,
            cutter_tip_radius_coef: tip_radius(),
            cutter_teeth: None,
            cutter_shift: 0.0,
            mating_teeth: None,
            mating_shift: 0.0,
            flank_tolerance_um: one(),
            fillet_tolerance_um: five(),
            thickness_mm,
            material: material.to_string(),
        }
    }
}

fn twenty() -> f64 {
    20.0
}
fn one() -> f64 {
    1.0
}
fn quarter() -> f64 {
    0.25
}
fn tip_radius() -> f64 {
    0.38
}
fn five() -> f64 {
    5.0
}

/// `[wire]`: what the job fixes of the wire and the program; the rest the
/// knowledge service proposes.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WireOverrides {
    /// Wire id in the knowledge base, e.g. `MO-018`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wire: Option<String>,
    /// Wire diameter, mm.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wire_diameter_mm: Option<f64>,
    /// Spark gap per side, mm.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub spark_gap_mm: Option<f64>,
    /// Program form (default: the machine's).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub program: Option<WireProgram>,
    /// Write every tooth even when a quarter or half program with the
    /// control's rotation would do. Default: false where the machine's
    /// control turns a section of blocks (its profile's `rotates`), true
    /// where it does not; false there is refused.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub whole: Option<bool>,
}
