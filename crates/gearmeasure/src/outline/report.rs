//! What [`super::measure`] returns, serialisable, with a plain-text
//! report ([`Measurement`]'s `Display`).

use super::Geometry;
use crate::helix::HelixDeviations;
use crate::iso1328::{Grade, Item};
use crate::pitch::FlankPair;
use crate::profile::ProfileDeviations;
use serde::{Deserialize, Serialize};
use std::fmt;

/// One trace per tooth and flank, tooth 0 first (tooth 0: the first tooth
/// counter-clockwise from θ = 0 at the measuring circle of the middle
/// section).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TeethTraces<T> {
    /// Left flanks (facing −θ).
    pub left: Vec<T>,
    /// Right flanks (facing +θ).
    pub right: Vec<T>,
}

impl<T> Default for TeethTraces<T> {
    fn default() -> Self {
        TeethTraces {
            left: Vec::new(),
            right: Vec::new(),
        }
    }
}

impl<T> TeethTraces<T> {
    /// The value of `f` with the largest magnitude over both flanks of
    /// every tooth, its sign kept (0 when empty).
    pub fn worst_signed(&self, f: impl Fn(&T) -> f64) -> f64 {
        self.left
            .iter()
            .chain(&self.right)
            .map(f)
            .fold(0.0, |w, v| if v.abs() > w.abs() { v } else { w })
    }
}

/// A value per flank.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct FlankValues {
    /// Left flanks.
    pub left: f64,
    /// Right flanks.
    pub right: f64,
}

impl FlankValues {
    /// The mean of `f` over the teeth, per flank.
    pub(super) fn mean_of<T>(t: &TeethTraces<T>, f: impl Fn(&T) -> f64) -> FlankValues {
        let mean = |v: &[T]| v.iter().map(&f).sum::<f64>() / v.len().max(1) as f64;
        FlankValues {
            left: mean(&t.left),
            right: mean(&t.right),
        }
    }
}

/// The profile deviations of one section, worst over its teeth and flanks
/// (not graded: the graded profile items are the middle section's).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SectionProfile {
    /// The section's height, mm.
    pub z_mm: f64,
    /// fHα with the largest magnitude, µm, signed.
    pub slope_um: f64,
    /// The largest ffα, µm.
    pub form_um: f64,
    /// The largest Fα, µm.
    pub total_um: f64,
    /// Mean fHα per flank, µm.
    pub slope_mean_um: FlankValues,
}

/// One graded item.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ItemResult {
    /// The item.
    pub item: Item,
    /// Its value, µm (the worst over teeth and flanks; slopes signed).
    pub value_um: f64,
    /// The finest class it meets.
    pub grade: Grade,
    /// The tolerance of that class (of class 11 when worse), µm.
    pub tolerance_um: f64,
}

/// Runout: the ball and its radial positions.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Runout {
    /// The ball diameter DM, mm.
    pub ball_diameter_mm: f64,
    /// The ball centre's distance from the axis in each space (space j
    /// follows tooth j), µm.
    pub radial_um: Vec<f64>,
    /// Fr = the range of `radial_um`, µm.
    pub runout_um: f64,
}

/// Size: thickness, span and dimension over balls, measured and designed.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SizeResult {
    /// Design normal tooth thickness sn, mm.
    pub design_thickness_mm: f64,
    /// Measured normal arc thickness at the reference circle, mean over
    /// teeth, mm (transverse arc r·Δθ times cos β).
    pub thickness_mm: f64,
    /// Its spread over the teeth (max − min), µm.
    pub thickness_spread_um: f64,
    /// Teeth spanned, k.
    pub span_teeth: u32,
    /// Design span Wk, mm.
    pub span_design_mm: f64,
    /// Measured span, mean over the z groups of k teeth, mm.
    pub span_mm: f64,
    /// Its spread, µm.
    pub span_spread_um: f64,
    /// The thickness the measured span implies, mm.
    pub span_thickness_mm: f64,
    /// Ball diameter DM, mm.
    pub ball_diameter_mm: f64,
    /// Design dimension over balls, mm.
    pub over_balls_design_mm: f64,
    /// Measured dimension over balls, mean over the pairs of spaces, mm.
    pub over_balls_mm: f64,
    /// Its spread, µm.
    pub over_balls_spread_um: f64,
    /// The thickness the measured dimension implies, mm.
    pub over_balls_thickness_mm: f64,
}

/// Everything measured on the gear.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Measurement {
    /// The design geometry of the middle section (the one profile, pitch,
    /// runout and size are measured in; a conical gear's own there).
    pub geometry: Geometry,
    /// The height of the section profile, pitch, runout and size were
    /// measured in, mm.
    pub middle_section_mm: f64,
    /// Profile deviations per tooth and flank.
    pub profile: TeethTraces<ProfileDeviations>,
    /// Mean profile slope deviation fHαm per flank, µm.
    pub profile_slope_mean_um: FlankValues,
    /// Helix deviations per tooth traced and flank (`None` with fewer than
    /// three sections in the helix evaluation range).
    pub helix: Option<TeethTraces<HelixDeviations>>,
    /// The teeth the helix, and the profile outside the middle section,
    /// were traced on, in the order of [`Measurement::helix`]: every tooth
    /// unless fewer were asked for.
    pub helix_teeth: Vec<usize>,
    /// Mean helix slope deviation fHβm per flank, µm.
    pub helix_slope_mean_um: Option<FlankValues>,
    /// The profile in every section of the face, worst over the teeth
    /// traced (empty when the helix is not measured).
    pub profile_by_section: Vec<SectionProfile>,
    /// Pitch deviations of both flanks.
    pub pitch: FlankPair,
    /// Runout.
    pub runout: Runout,
    /// Size.
    pub size: SizeResult,
    /// Every graded item: value, class, tolerance.
    pub items: Vec<ItemResult>,
    /// The gear's class: the worst item's.
    pub overall: Grade,
}

impl Measurement {
    /// The graded result of `item`, if it was measured.
    pub fn item(&self, item: Item) -> Option<&ItemResult> {
        self.items.iter().find(|i| i.item == item)
    }
}

/// The symbol of an item as a gear-measuring machine prints it (fp, Fp,
/// fHα, ...).
pub fn symbol(item: Item) -> &'static str {
    match item {
        Item::SinglePitch => "fp",
        Item::CumulativePitch => "Fp",
        Item::ProfileSlope => "fHα",
        Item::ProfileForm => "ffα",
        Item::ProfileTotal => "Fα",
        Item::HelixSlope => "fHβ",
        Item::HelixForm => "ffβ",
        Item::HelixTotal => "Fβ",
        Item::Runout => "Fr",
    }
}

fn grade_text(g: Grade) -> String {
    match g {
        Grade::Class(c) => format!("class {}", c.number()),
        Grade::WorseThan11 => "worse than class 11".to_string(),
    }
}

impl fmt::Display for Measurement {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "ISO 1328-1:2013 flank tolerance classes")?;
        for i in &self.items {
            writeln!(
                f,
                "  {:<4} {:>9.2} µm  {} (tolerance {} µm)",
                symbol(i.item),
                i.value_um,
                grade_text(i.grade),
                i.tolerance_um
            )?;
        }
        writeln!(f, "  overall: {}", grade_text(self.overall))?;
        let s = &self.size;
        writeln!(
            f,
            "size: sn {:.4} mm (design {:.4}); W{} {:.4} mm (design {:.4}, sn {:.4}); \
             over balls DM {:.3}: {:.4} mm (design {:.4}, sn {:.4})",
            s.thickness_mm,
            s.design_thickness_mm,
            s.span_teeth,
            s.span_mm,
            s.span_design_mm,
            s.span_thickness_mm,
            s.ball_diameter_mm,
            s.over_balls_mm,
            s.over_balls_design_mm,
            s.over_balls_thickness_mm
        )
    }
}
