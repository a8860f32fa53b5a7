//! The raw trace points behind a [`super::Measurement`], for charts: a
//! gear-measuring machine prints each trace it evaluates, and the
//! measurement keeps only the evaluated values. [`chart_data`] finds the
//! teeth and follows them exactly as [`super::measure`] does and returns
//! the points the profile and helix evaluations are given, so
//! `evaluate_profile` / `evaluate_helix` of a trace's points give that
//! trace's deviations in the measurement.

use super::flank::{self, Section};
use super::report::TeethTraces;
use super::{traces, GearSpec, PolarSections};
use crate::Error;
use serde::{Deserialize, Serialize};

/// One trace: abscissae and the deviation at each, +material, µm, offset
/// so the first point is 0 (an offset changes no deviation).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TracePoints {
    /// Roll length (profile) or height from the reference face (helix), mm.
    pub x_mm: Vec<f64>,
    /// Deviation at each abscissa, µm.
    pub deviation_um: Vec<f64>,
}

/// The trace points of every tooth and flank, tooth 0 first (the numbering
/// of [`super::Measurement`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ChartData {
    /// The index of the section profile, pitch, runout and size are
    /// measured in.
    pub middle_section: usize,
    /// Each tooth's centre angle at the measuring circle of that section,
    /// rad (the middle of its flanks' angles there).
    pub tooth_centre_rad: Vec<f64>,
    /// Profile traces in the middle section: roll length, deviation, from
    /// the form circle to the tip form circle at the spacing of the
    /// measurement's points (those in the evaluation range are the ones
    /// it evaluated).
    pub profile: TeethTraces<TracePoints>,
    /// Helix traces at the measuring diameter: height from the reference
    /// face, deviation (`None` when the helix is not measured).
    pub helix: Option<TeethTraces<TracePoints>>,
    /// The teeth of the helix traces, in their order.
    pub helix_teeth: Vec<usize>,
}

/// The trace points [`super::measure_traced`] evaluates for `sections`
/// against `spec` with the helix traced on `traced` (every tooth when
/// `None`); the same errors.
pub fn chart_data(
    sections: &PolarSections,
    spec: &GearSpec,
    traced: Option<&[usize]>,
) -> Result<ChartData, Error> {
    let n = sections.check()?;
    let geo = spec.geometry()?;
    let middle = geo.middle_section(&sections.z_mm, spec.face_start_mm);
    let mid_spec = spec.at(sections.z_mm[middle])?;
    let mid_geo = mid_spec.geometry()?;
    let mid = Section::new(&sections.r_mm[middle], n);
    let teeth = flank::find_teeth(&mid, spec.teeth, mid_geo.measuring_diameter_mm / 2.0)?;
    let steps = profile_steps(&mid_geo)?;
    let z = spec.teeth as usize;
    let helix_teeth = super::traced_teeth(traced, z)?;
    let chosen: Vec<flank::Tooth> = helix_teeth.iter().map(|&t| teeth[t]).collect();
    let mut profile = TeethTraces::default();
    for tooth in &teeth {
        for right in [false, true] {
            let (x_mm, deviation_um) =
                traces::profile_points(&mid, tooth, right, z, steps, &mid_geo, &mid_spec);
            let side = if right {
                &mut profile.right
            } else {
                &mut profile.left
            };
            side.push(TracePoints { x_mm, deviation_um });
        }
    }
    let helix = traces::follow_teeth(sections, middle, &chosen, &geo, spec)?.map(|f| {
        let mut out = TeethTraces::default();
        for flanks in &f.teeth {
            for right in [false, true] {
                let (x_mm, deviation_um) = traces::helix_points(&f, flanks, right, &geo, spec);
                let side = if right { &mut out.right } else { &mut out.left };
                side.push(TracePoints { x_mm, deviation_um });
            }
        }
        out
    });
    Ok(ChartData {
        middle_section: middle,
        tooth_centre_rad: teeth.iter().map(|t| t.centre()).collect(),
        profile,
        helix,
        helix_teeth,
    })
}

/// The steps k of [`traces::profile_points`] from the form circle to the
/// tip form circle: the evaluation range is k = 0..=P − 1 (P =
/// [`traces::PROFILE_POINTS`]), a step its length / (P − 1), and the
/// trace goes on by whole steps as far as both circles.
fn profile_steps(geo: &super::Geometry) -> Result<(i64, i64), Error> {
    let range = geo.profile_range;
    let last = traces::PROFILE_POINTS as i64 - 1;
    let step = (range.end_mm - range.start_mm) / last as f64;
    let roll = |d: f64| crate::profile::roll_length_from_diameter(d, geo.base_diameter_mm);
    let (form, tip) = (roll(geo.form_diameter_mm)?, roll(geo.tip_form_diameter_mm)?);
    if step.abs() < 1e-12 {
        return Ok((0, last));
    }
    let below = ((range.start_mm - form) / step).floor().max(0.0) as i64;
    let above = ((tip - range.end_mm) / step).floor().max(0.0) as i64;
    Ok((-below, last + above))
}
