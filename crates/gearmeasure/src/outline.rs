//! Measuring a gear given as its transverse outlines, the way a
//! gear-measuring machine (GMM) measures a real one, and grading it by
//! ISO 1328-1:2013 (docs/measurement.md, section 6).
//!
//! The input is what a simulated cut leaves ([`PolarSections`]): sections
//! at heights z (mm, up the gear axis), each an outline r(θᵢ) with
//! θᵢ = 2π·i/n counter-clockwise seen from +z. The coordinates are those of
//! [`crate::helix`]: a right-hand gear's flanks turn +θ as z grows,
//! dθ/dz = +tan β / r (left hand: −); the right flank of a tooth faces +θ.
//!
//! From the outlines [`measure`] takes, like a GMM:
//!
//! - a **profile** trace on both flanks of every tooth in the middle
//!   section (graded), and in every other section of the face (reported
//!   per section, worst over its teeth): where the outline crosses each radius of the evaluation range,
//!   the flank's angle θ(r) interpolated between samples, and its
//!   deviation from the design involute along the base tangent,
//!   e = rb·(n·θ + inv α(r)) + const (n = +1 right flank, −1 left; the
//!   derivation in docs/measurement.md, section 6) → Fα, fHα, ffα;
//! - a **helix** trace on both flanks of every tooth at the measuring
//!   diameter, one point per section in the face: e(z) = n·(rb·θ(z) −
//!   h·z·tan βb) + const (h = +1 right hand, −1 left, 0 spur) → Fβ, fHβ, ffβ;
//! - **pitch**: both flanks of every tooth at the measuring diameter in the
//!   middle section → fp, Fp;
//! - **runout**: a ball touching both flanks of every space, its centre
//!   found on the polygonal outline → Fr;
//! - **size**: the mean arc tooth thickness at the reference circle, the
//!   span Wk (two parallel jaws rocked to their smallest opening) and the
//!   dimension over two balls, against the design values of
//!   [`crate::size`];
//! - the ISO 1328-1:2013 **class** of every graded item and the overall
//!   class.
//!
//! Every tooth is measured (it costs little here), and each graded item is
//! the worst over teeth and flanks: ISO 1328-1:2013 applies its tolerances
//! to every measured flank, so one flank out of tolerance is enough to fail
//! a class. The mean slope deviation per flank (fHαm, fHβm, which
//! ISO/TR 10064-1 discusses for lead and profile corrections) is reported
//! beside it, not graded.

mod chart_data;
mod flank;
mod gauge;
mod report;
mod spec;
mod traces;

pub use chart_data::{chart_data, ChartData, TracePoints};
pub use report::{
    symbol, FlankValues, ItemResult, Measurement, Runout, SectionProfile, SizeResult, TeethTraces,
};
pub use spec::{Direction, GearSpec, Geometry};

use crate::helix::{Hand, HelixDeviations};
use crate::iso1328::{self, GearData, Grade, Item};
use crate::profile::ProfileDeviations;
use crate::size::inv;
use crate::Error;
use serde::{Deserialize, Serialize};

/// A gear as transverse sections: at height `z_mm[j]` the outline radius
/// `r_mm[j][i]` (mm) at the angle θᵢ = 2π·i/n, counter-clockwise seen from
/// +z, the same n for every section. The heights must increase.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PolarSections {
    /// Heights of the sections along the gear axis, mm, increasing.
    pub z_mm: Vec<f64>,
    /// One outline per section, n radii each, mm.
    pub r_mm: Vec<Vec<f64>>,
}

impl PolarSections {
    /// The number of angles n per section, after checking the shape: as
    /// many outlines as heights, increasing heights, n ≥ 64 equal in every
    /// section, positive finite radii.
    fn check(&self) -> Result<usize, Error> {
        if self.z_mm.is_empty() || self.r_mm.len() != self.z_mm.len() {
            return Err(Error::TooFewSamples {
                what: "outlines, one per section height",
                needed: self.z_mm.len().max(1),
                got: self.r_mm.len(),
            });
        }
        if let Some(w) = self
            .z_mm
            .windows(2)
            .find(|w| w[1].partial_cmp(&w[0]) != Some(std::cmp::Ordering::Greater))
        {
            return Err(Error::OutOfRange {
                field: "z_mm",
                expected: "finite section heights, strictly increasing",
                got: w[1],
            });
        }
        let n = self.r_mm[0].len();
        for r in &self.r_mm {
            if r.len() != n || n < 64 {
                return Err(Error::TooFewSamples {
                    what: "angles per section, the same in every section (at least 64)",
                    needed: n.max(64),
                    got: r.len(),
                });
            }
            if let Some(bad) = r.iter().find(|v| !(v.is_finite() && **v > 0.0)) {
                return Err(Error::OutOfRange {
                    field: "r_mm",
                    expected: "positive finite radii",
                    got: *bad,
                });
            }
        }
        Ok(n)
    }
}

/// Measures the gear `sections` against the drawing `spec`: profile, helix,
/// pitch, runout, size and the ISO 1328-1:2013 classes (the module doc says
/// how). Errors name the input at fault: a spec outside its range or the
/// standard's scope, sections of the wrong shape, an outline that does not
/// cross the measuring circle 2z times (not z teeth there), a tooth that
/// cannot be followed from section to section, or too few samples in an
/// evaluation range.
pub fn measure(sections: &PolarSections, spec: &GearSpec) -> Result<Measurement, Error> {
    measure_traced(sections, spec, None)
}

/// [`measure`] with the helix, and the profile outside the middle section,
/// traced on the teeth `traced` only (numbered as in the middle section,
/// tooth 0 the first whose left flank crosses the measuring circle at
/// θ ≥ 0), as a gear-measuring machine traces a few teeth; `None`: every
/// tooth. The middle section is measured on every tooth. The other
/// sections need their outlines only about those teeth
/// ([`trace_windows`]).
pub fn measure_traced(
    sections: &PolarSections,
    spec: &GearSpec,
    traced: Option<&[usize]>,
) -> Result<Measurement, Error> {
    let n = sections.check()?;
    let geo = spec.geometry()?;
    let gear = GearData::new(
        spec.teeth,
        spec.normal_module_mm,
        spec.helix_deg,
        spec.face_width_mm,
    )?;
    let middle = geo.middle_section(&sections.z_mm, spec.face_start_mm);
    // A conical gear's middle section has its own drawing; a cylindrical
    // gear's is the spec's.
    let mid_spec = spec.at(sections.z_mm[middle])?;
    let mid_geo = mid_spec.geometry()?;
    let mid = flank::Section::new(&sections.r_mm[middle], n);
    let teeth = flank::find_teeth(&mid, spec.teeth, mid_geo.measuring_diameter_mm / 2.0)?;
    let profile = traces::profiles(&mid, &teeth, &mid_geo, &mid_spec)?;
    let helix_teeth = traced_teeth(traced, teeth.len())?;
    let chosen: Vec<flank::Tooth> = helix_teeth.iter().map(|&t| teeth[t]).collect();
    let followed = traces::follow_teeth(sections, middle, &chosen, &geo, spec)?;
    let helix = match &followed {
        Some(f) => Some(traces::helices(f, &geo, spec)?),
        None => None,
    };
    let profile_by_section = match &followed {
        Some(f) => traces::section_profiles(sections, f, spec)?,
        None => Vec::new(),
    };
    let pitch = traces::pitch(&teeth, &mid_geo)?;
    let (runout, size) = gauge::size_and_runout(&mid, &teeth, &mid_geo, &mid_spec)?;
    let items = grade_items(&gear, &profile, helix.as_ref(), &pitch, &runout)?;
    let overall = items
        .iter()
        .map(|i| i.grade)
        .max()
        .unwrap_or(Grade::WorseThan11);
    Ok(Measurement {
        geometry: mid_geo,
        middle_section_mm: sections.z_mm[middle],
        profile_slope_mean_um: FlankValues::mean_of(&profile, |d| d.slope_um),
        helix_slope_mean_um: helix
            .as_ref()
            .map(|h| FlankValues::mean_of(h, |d: &HelixDeviations| d.slope_um)),
        profile,
        helix,
        helix_teeth,
        profile_by_section,
        pitch,
        runout,
        size,
        items,
        overall,
    })
}

/// The teeth `traced` (every one of `z` when `None`), each checked to be a
/// tooth of the gear.
fn traced_teeth(traced: Option<&[usize]>, z: usize) -> Result<Vec<usize>, Error> {
    let Some(t) = traced else {
        return Ok((0..z).collect());
    };
    match t.iter().find(|&&k| k >= z) {
        Some(&bad) => Err(Error::OutOfRange {
            field: "traced",
            expected: "tooth numbers below the number of teeth",
            got: bad as f64,
        }),
        None if t.is_empty() => Err(Error::TooFewSamples {
            what: "teeth traced",
            needed: 1,
            got: 0,
        }),
        None => Ok(t.to_vec()),
    }
}

/// The teeth a gear-measuring machine traces for profile and helix when
/// it does not trace every one: four about a quarter turn apart (0, z/4,
/// z/2, 3z/4; fewer on a gear of fewer than four teeth).
pub fn four_teeth(z: usize) -> Vec<usize> {
    let mut v = vec![0, z / 4, z / 2, 3 * z / 4];
    v.dedup();
    v
}

/// The index among `z_mm` (increasing section heights) of the section
/// [`measure`] takes as the middle one of `spec`'s face.
pub fn middle_section(z_mm: &[f64], spec: &GearSpec) -> Result<usize, Error> {
    Ok(spec.geometry()?.middle_section(z_mm, spec.face_start_mm))
}

/// Where in each section of `sections` the outline is needed to trace the
/// teeth `traced` ([`measure_traced`]): per section, one window of angle
/// (from, to), rad, about each tooth, centred where the design helix turns
/// the tooth's centre in the middle section. Either side it reaches the
/// design tooth's half angle at the start of the section's profile
/// evaluation range (no flank point a trace reads lies further from the
/// centre: the half angle s_t/d + inv α_t − inv α(r) shrinks as r grows,
/// and the helix is traced further out), plus as much as the traced teeth
/// stand wider than their design there in the middle section (a thick
/// tooth of a shallow cut), a twentieth of a pitch for the helix's drift,
/// and four samples for those a crossing is read from beyond a flank. Only
/// the middle section's outline is read: it must be cut all round.
pub fn trace_windows(
    sections: &PolarSections,
    spec: &GearSpec,
    traced: &[usize],
) -> Result<Vec<Vec<(f64, f64)>>, Error> {
    let n = sections.check()?;
    let geo = spec.geometry()?;
    let middle = geo.middle_section(&sections.z_mm, spec.face_start_mm);
    let mid_geo = spec.at(sections.z_mm[middle])?.geometry()?;
    let mid = flank::Section::new(&sections.r_mm[middle], n);
    let teeth = flank::find_teeth(&mid, spec.teeth, mid_geo.measuring_diameter_mm / 2.0)?;
    let chosen = traced_teeth(Some(traced), teeth.len())?;
    let pitch = std::f64::consts::TAU / f64::from(spec.teeth);
    let turn = traces::helix_turn_per_mm(&geo, spec);
    let z_mid = sections.z_mm[middle];
    // How much wider than its design a traced tooth stands in the middle
    // section at the start of the profile range (the whole walk a trace
    // makes where a flank is not found there).
    let start = mid_geo.profile_range.start_mm;
    let r_start = mid_geo.rb().hypot(start);
    let design = half_tooth(&mid_geo, spec, start);
    let excess = chosen
        .iter()
        .map(|&t| {
            let c = teeth[t].centre();
            let reach = 0.75 * pitch;
            let left = mid.crossing(c, r_start, -1, reach).map_or(reach, |l| c - l);
            let right = mid.crossing(c, r_start, 1, reach).map_or(reach, |r| r - c);
            left.max(right) - design
        })
        .fold(0.0, f64::max);
    let samples = 4.0 * std::f64::consts::TAU / n as f64;
    sections
        .z_mm
        .iter()
        .map(|&z| {
            // The section's own drawing, the middle's measuring diameter
            // (which may lie outside a far section of a steep cone).
            let here = GearSpec {
                measuring_diameter_mm: spec.measuring_diameter_mm,
                ..spec.at(z)?
            }
            .geometry()?;
            let half = half_tooth(&here, spec, here.profile_range.start_mm)
                + excess
                + 0.05 * pitch
                + samples;
            Ok(chosen
                .iter()
                .map(|&t| {
                    let c = teeth[t].centre() + turn * (z - z_mid);
                    (c - half, c + half)
                })
                .collect())
        })
        .collect()
}

/// Half the angle the design tooth of `geo` spans at the radius of roll
/// length `roll_mm`, rad: s_t/d + inv α_t − inv α, the transverse
/// thickness s_t = s_n/cos β at the reference diameter d, cos α_t = d_b/d,
/// tan α = L/r_b at roll length L.
fn half_tooth(geo: &Geometry, spec: &GearSpec, roll_mm: f64) -> f64 {
    let d = geo.reference_diameter_mm;
    let st = geo.design_thickness_mm / spec.helix_deg.to_radians().cos();
    let at = (geo.base_diameter_mm / d).clamp(-1.0, 1.0).acos();
    // At roll length L the pressure angle has tan α = L/r_b.
    let alpha = (roll_mm.max(0.0) / geo.rb()).atan();
    st / d + inv(at) - inv(alpha)
}

/// The value of every graded item (worst over teeth and flanks), its class
/// and the tolerance of that class (of class 11 when it is worse).
fn grade_items(
    gear: &GearData,
    profile: &TeethTraces<ProfileDeviations>,
    helix: Option<&TeethTraces<HelixDeviations>>,
    pitch: &crate::pitch::FlankPair,
    runout: &Runout,
) -> Result<Vec<ItemResult>, Error> {
    let mut values = vec![
        (
            Item::SinglePitch,
            pitch.left.single_max_um.max(pitch.right.single_max_um),
        ),
        (
            Item::CumulativePitch,
            pitch
                .left
                .cumulative_total_um
                .max(pitch.right.cumulative_total_um),
        ),
        (Item::ProfileSlope, profile.worst_signed(|d| d.slope_um)),
        (Item::ProfileForm, profile.worst_signed(|d| d.form_um)),
        (Item::ProfileTotal, profile.worst_signed(|d| d.total_um)),
    ];
    if let Some(h) = helix {
        values.push((Item::HelixSlope, h.worst_signed(|d| d.slope_um)));
        values.push((Item::HelixForm, h.worst_signed(|d| d.form_um)));
        values.push((Item::HelixTotal, h.worst_signed(|d| d.total_um)));
    }
    values.push((Item::Runout, runout.runout_um));
    values
        .into_iter()
        .map(|(item, value_um)| {
            let grade = iso1328::grade(gear, item, value_um)?;
            let class = match grade {
                Grade::Class(c) => c,
                Grade::WorseThan11 => iso1328::Class::COARSEST,
            };
            Ok(ItemResult {
                item,
                value_um,
                grade,
                tolerance_um: iso1328::tolerance_um(gear, item, class),
            })
        })
        .collect()
}

/// The sign of a flank in the deviation formulas: +1 for the right flank
/// (facing +θ), −1 for the left.
fn flank_sign(right: bool) -> f64 {
    if right {
        1.0
    } else {
        -1.0
    }
}

/// h: +1 right hand, −1 left hand, 0 spur.
fn hand_sign(hand: Option<Hand>) -> f64 {
    match hand {
        Some(Hand::Right) => 1.0,
        Some(Hand::Left) => -1.0,
        None => 0.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn four_teeth_stand_a_quarter_turn_apart() {
        assert_eq!(four_teeth(31), vec![0, 7, 15, 23]);
        assert_eq!(four_teeth(8), vec![0, 2, 4, 6]);
        assert_eq!(four_teeth(3), vec![0, 1, 2]);
    }

    #[test]
    fn the_teeth_traced_are_teeth_of_the_gear() {
        assert_eq!(traced_teeth(None, 4).unwrap(), vec![0, 1, 2, 3]);
        assert_eq!(traced_teeth(Some(&[3, 1]), 4).unwrap(), vec![3, 1]);
        let err = traced_teeth(Some(&[0, 4]), 4).unwrap_err().to_string();
        assert!(err.contains("traced") && err.contains('4'), "{err}");
        assert!(traced_teeth(Some(&[]), 4).is_err());
    }
}
