//! The job file's sections of the spiral face milling family
//! (docs/spiral.md#the-job-file): `[face]` or `[groove]`, `[mill]` and
//! `[milling]`. The plan and model messages are in [`crate::spiral`].

use serde::{Deserialize, Serialize};

use crate::cutting::CutMode;

/// `[face]`: a circular (inner radius 0) or annular face, centred on the
/// program's origin.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FaceSpec {
    /// Outer radius Ro, mm.
    pub outer_radius_mm: f64,
    /// Inner radius Ri, mm (0: a full circle).
    #[serde(default)]
    pub inner_radius_mm: f64,
    /// Stock to take off the face, mm.
    pub depth_mm: f64,
    /// Workpiece material, e.g. `C45`.
    pub material: String,
}

/// `[groove]`: a planar spiral groove ("planar thread"): the groove's
/// centre line is an Archimedean spiral of `pitch_mm` per turn, starting at
/// `outer_radius_mm` and running inwards `turns` turns.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GrooveSpec {
    /// Radius of the groove's centre line at its start, mm.
    pub outer_radius_mm: f64,
    /// Pitch: radial distance between neighbouring turns, mm.
    pub pitch_mm: f64,
    /// Turns (≥ 1).
    pub turns: u32,
    /// Groove depth, mm.
    pub depth_mm: f64,
    /// Groove width, mm: the tool's diameter must equal it (checked).
    pub width_mm: f64,
    /// Workpiece material.
    pub material: String,
}

/// Kind of milling tool.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum MillKind {
    /// A face mill (inserts on a body).
    FaceMill,
    /// An end mill (solid).
    EndMill,
}

impl MillKind {
    /// The name as written in files.
    pub fn as_str(self) -> &'static str {
        match self {
            MillKind::FaceMill => "face-mill",
            MillKind::EndMill => "end-mill",
        }
    }
}

/// `[mill]`: the tool, by library id or given inline (every field is
/// optional; what is missing comes from the tool library).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MillSpec {
    /// Tool library id, e.g. `FM-063`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub id: Option<String>,
    /// Face mill or end mill.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kind: Option<MillKind>,
    /// Cutting radius, mm.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radius_mm: Option<f64>,
    /// Corner radius, mm.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub corner_radius_mm: Option<f64>,
    /// Flutes (teeth or inserts).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub flutes: Option<u32>,
}

/// Which way the spiral runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum SpiralDirection {
    /// From outside the face inwards (the seed's way).
    OutsideIn,
    /// From the inner edge outwards.
    InsideOut,
}

/// The program form of a spiral job (`program.dialect` in `gearcam check --json`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum SpiralProgram {
    /// FANUC 0i parametric macro: `#` variable table, `G16` polar chords in a `WHILE` loop.
    FanucMacro,
    /// FANUC expanded program of tangent-continuous `G02`/`G03` arcs.
    FanucArcs,
    /// FANUC expanded program of `G01` chords (controls without arcs or macros).
    FanucChords,
    /// LinuxCNC: named parameters, `o`-word loop, polar `@`/`^` words.
    Linuxcnc,
}

impl SpiralProgram {
    /// The name as written in files and JSON.
    pub fn as_str(self) -> &'static str {
        match self {
            SpiralProgram::FanucMacro => "fanuc-macro",
            SpiralProgram::FanucArcs => "fanuc-arcs",
            SpiralProgram::FanucChords => "fanuc-chords",
            SpiralProgram::Linuxcnc => "linuxcnc",
        }
    }

    /// Every form.
    pub const ALL: [SpiralProgram; 4] = [
        SpiralProgram::FanucMacro,
        SpiralProgram::FanucArcs,
        SpiralProgram::FanucChords,
        SpiralProgram::Linuxcnc,
    ];
}

/// `[milling]`: process values the planner fixes; every one left out is
/// proposed by the knowledge service (cases, cutting data, defaults).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MillingOverrides {
    /// Largest radial step-over between turns, mm (< the tool's diameter).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub step_over_mm: Option<f64>,
    /// Depth passes.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub passes: Option<u32>,
    /// Cutting speed, m/min.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cutting_speed_m_min: Option<f64>,
    /// Feed per tooth, mm.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub feed_per_tooth_mm: Option<f64>,
    /// Outside-in (default) or inside-out.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub direction: Option<SpiralDirection>,
    /// Climb (default) or conventional milling: sets the spiral's sense
    /// with the spindle turning clockwise (`M03`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cut_mode: Option<CutMode>,
    /// Outer overtravel beyond Ro + tool radius, mm.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub outer_overtravel_mm: Option<f64>,
    /// Inner overtravel past the inner edge, mm.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub inner_overtravel_mm: Option<f64>,
    /// Start angle θ0, degrees.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub start_angle_deg: Option<f64>,
    /// Chord/arc tolerance to the spiral, mm.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tolerance_mm: Option<f64>,
    /// Program form; by default the machine's.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub program: Option<SpiralProgram>,
}
