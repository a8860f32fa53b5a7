//! Profile, helix and pitch traces from the outlines.
//!
//! **Profile.** A right flank (facing +θ) of a design tooth is the involute
//! θ(r) = C − inv α(r), cos α = rb/r; a left flank is θ(r) = C′ + inv α(r).
//! Two involutes of one base circle turned by Δθ about the axis are a
//! distance rb·Δθ apart along every base tangent, which is their common
//! normal in the transverse plane (a point at roll length L on one and the
//! point on the other on the same tangent differ by rb·Δθ in roll length).
//! A measured flank point at angle θ at radius r lies on the involute turned
//! by Δθ = θ − (C − inv α(r)) from the design: its deviation normal to the
//! involute, +material towards the space the flank faces, is
//! e = n·rb·Δθ = rb·(n·θ + inv α(r)) − n·rb·C with n = +1 for the right
//! flank and −1 for the left (a left flank with more material lies at
//! smaller θ). The constant drops out of Fα, fHα and ffα; inv α is computed
//! from the roll length L = √(r² − rb²) as L/rb − atan(L/rb). On the flank
//! surface the normal deviation is e·cos βb (spec [`super::Direction`]).
//!
//! **Helix.** At the measuring radius the design flank is at
//! θ(z) = θ₀ + h·z·tan βb / rb (h = +1 right hand, −1 left, 0 spur;
//! tan βb / rb = tan β / r, one lead for every radius); a deviation e along
//! the base tangent turns it by n·e/rb, so
//! e(z) = n·(rb·θ(z) − h·z·tan βb) + const, the convention of
//! [`crate::helix`]. A crowned design flank stands Cβ·(1 − (2z/b − 1)²)
//! further out ([`GearSpec::helix_crowning_mm`]), which is taken off: the
//! deviations are from the crowned design. So is a conical gear's taper:
//! where its rack stood Δ further out the flank stands Δ·sin αt further
//! into its space along the base tangent (the rack's flank, at αn to the
//! radial in its normal plane, moves Δ·sin αn along its own normal, which
//! is Δ·sin αn / cos βb = Δ·sin αt along the transverse base tangent).
//!
//! **Pitch.** Each flank's angle at the measuring circle, converted by
//! [`crate::pitch::positions_from_angles`] to µm of arc from nominal.

use super::flank::{self, Section, Tooth};
use super::report::{FlankValues, SectionProfile, TeethTraces};
use super::{flank_sign, hand_sign, Direction, GearSpec, Geometry, PolarSections};
use crate::helix::{evaluate_helix, HelixDeviations};
use crate::pitch::{evaluate_flanks, positions_from_angles, FlankPair};
use crate::profile::{evaluate_profile, ProfileDeviations};
use crate::Error;
use std::f64::consts::TAU;

/// Points per profile trace, evenly spaced in roll length over the
/// evaluation range (a GMM records a few hundred).
pub(super) const PROFILE_POINTS: usize = 241;

/// The factor from the transverse deviation to the reported one.
fn direction_factor(geo: &Geometry, spec: &GearSpec) -> f64 {
    match spec.direction {
        Direction::Transverse => 1.0,
        Direction::Normal => geo.base_helix_deg.to_radians().cos(),
    }
}

/// The profile deviations of both flanks of the teeth `teeth` of the
/// section `mid` (every tooth, or those traced).
pub(super) fn profiles(
    mid: &Section<'_>,
    teeth: &[Tooth],
    geo: &Geometry,
    spec: &GearSpec,
) -> Result<TeethTraces<ProfileDeviations>, Error> {
    let range = geo.profile_range;
    let trace = |tooth: &Tooth, right: bool| {
        let steps = (0, PROFILE_POINTS as i64 - 1);
        let z = spec.teeth as usize;
        let (xs, es) = profile_points(mid, tooth, right, z, steps, geo, spec);
        evaluate_profile(&xs, &es, range)
    };
    let mut out = TeethTraces::default();
    for tooth in teeth {
        out.left.push(trace(tooth, false)?);
        out.right.push(trace(tooth, true)?);
    }
    Ok(out)
}

/// The points of one flank's profile trace in `mid`: roll lengths (mm)
/// and the deviations there (µm, +material, in the spec's direction). The
/// roll lengths are those of `steps`, k = first..=last, at
/// L = start + k·(end − start)/([`PROFILE_POINTS`] − 1) of the evaluation
/// range (k = 0..[`PROFILE_POINTS`] − 1 spans it; a chart goes beyond),
/// where the outline crosses the radius; the deviations are offset so the
/// first point with k ≥ 0 is 0. A tooth of `teeth` is walked from its
/// centre towards the flank, at most ¾ of a pitch.
pub(super) fn profile_points(
    mid: &Section<'_>,
    tooth: &Tooth,
    right: bool,
    teeth: usize,
    steps: (i64, i64),
    geo: &Geometry,
    spec: &GearSpec,
) -> (Vec<f64>, Vec<f64>) {
    let rb = geo.rb();
    let range = geo.profile_range;
    let reach = 0.75 * TAU / teeth as f64;
    let um = 1000.0 * direction_factor(geo, spec);
    let n = flank_sign(right);
    let (mut xs, mut es, mut first) = (Vec::new(), Vec::new(), None);
    let walk = mid.walk(tooth.centre(), n as i64, reach);
    for k in steps.0..=steps.1 {
        let l = range.start_mm
            + (range.end_mm - range.start_mm) * k as f64 / (PROFILE_POINTS - 1) as f64;
        let rho = rb.hypot(l);
        if let Some(theta) = walk.crossing(rho) {
            let inv = l / rb - (l / rb).atan();
            if k >= 0 && first.is_none() {
                first = Some(es.len());
            }
            xs.push(l);
            es.push(rb * (n * theta + inv));
        }
    }
    // Offsets change none of the deviations; taking the first in the range
    // keeps the numbers small before they are scaled to µm.
    let e0 = es.get(first.unwrap_or(0)).copied().unwrap_or(0.0);
    let es: Vec<f64> = es.iter().map(|e| (e - e0) * um).collect();
    (xs, es)
}

/// The teeth followed through the sections of the face.
#[derive(Debug, Clone)]
pub(super) struct Followed {
    /// The indices of the sections in the face (and the middle one).
    pub(super) index: Vec<usize>,
    /// Their heights, mm.
    pub(super) z_mm: Vec<f64>,
    /// Per tooth followed, its flanks at the measuring radius in those
    /// sections.
    pub(super) teeth: Vec<Vec<Tooth>>,
}

/// The flank angles at the measuring radius of the teeth `teeth` (every
/// tooth of the middle section, or those traced) in each section of the
/// face, followed from the middle section up and down: in the next
/// section the tooth is looked for where the design helix turns it, and
/// found by going out from there to both flanks. `None` when fewer than
/// three sections lie in the helix evaluation range (a spur gear simulated
/// in one section): then neither helix nor per-section profiles.
pub(super) fn follow_teeth(
    sections: &PolarSections,
    middle: usize,
    teeth: &[Tooth],
    geo: &Geometry,
    spec: &GearSpec,
) -> Result<Option<Followed>, Error> {
    let range = geo.helix_range;
    let in_range = sections
        .z_mm
        .iter()
        .filter(|z| {
            let x = *z - spec.face_start_mm;
            x >= range.start_mm.min(range.end_mm) && x <= range.start_mm.max(range.end_mm)
        })
        .count();
    if in_range < 3 {
        return Ok(None);
    }
    let n = sections.r_mm[0].len();
    let (lo, hi) = (spec.face_start_mm, spec.face_start_mm + spec.face_width_mm);
    let inside: Vec<usize> = (0..sections.z_mm.len())
        .filter(|&j| (lo..=hi).contains(&sections.z_mm[j]) || j == middle)
        .collect();
    let rho = geo.measuring_diameter_mm / 2.0;
    let turn = helix_turn_per_mm(geo, spec);
    let pitch = TAU / f64::from(spec.teeth);
    let at = inside.iter().position(|&j| j == middle).unwrap_or(0);
    let mut found: Vec<Vec<Option<Tooth>>> = vec![vec![None; inside.len()]; teeth.len()];
    for (t, tooth) in teeth.iter().enumerate() {
        found[t][at] = Some(*tooth);
        let order = (at + 1..inside.len()).chain((0..at).rev());
        for k in order {
            let prev = if k > at { k - 1 } else { k + 1 };
            let was = found[t][prev].ok_or(Error::TooFewSamples {
                what: "sections",
                needed: 1,
                got: 0,
            })?;
            let dz = sections.z_mm[inside[k]] - sections.z_mm[inside[prev]];
            let sec = Section::new(&sections.r_mm[inside[k]], n);
            let tooth = flank::tooth_near(&sec, was.centre() + turn * dz, rho, pitch).ok_or(
                Error::OutOfRange {
                    field: "sections",
                    expected:
                        "every tooth found again in the next section where the helix turns it",
                    got: sections.z_mm[inside[k]],
                },
            )?;
            found[t][k] = Some(tooth);
        }
    }
    let z_mm: Vec<f64> = inside.iter().map(|&j| sections.z_mm[j]).collect();
    let teeth = found
        .into_iter()
        .map(|v| v.into_iter().flatten().collect())
        .collect();
    Ok(Some(Followed {
        index: inside,
        z_mm,
        teeth,
    }))
}

/// How far the design helix turns a tooth per mm up the axis, rad/mm:
/// h·tan β / r at the reference circle (one lead at every radius).
pub(super) fn helix_turn_per_mm(geo: &Geometry, spec: &GearSpec) -> f64 {
    hand_sign(spec.hand) * spec.helix_deg.to_radians().tan() / (geo.reference_diameter_mm / 2.0)
}

/// The helix deviations of both flanks of every tooth followed.
pub(super) fn helices(
    followed: &Followed,
    geo: &Geometry,
    spec: &GearSpec,
) -> Result<TeethTraces<HelixDeviations>, Error> {
    let range = geo.helix_range;
    let mut out = TeethTraces::default();
    for flanks in &followed.teeth {
        for right in [false, true] {
            let (x, e) = helix_points(followed, flanks, right, geo, spec);
            let d = evaluate_helix(&x, &e, range)?;
            if right {
                out.right.push(d);
            } else {
                out.left.push(d);
            }
        }
    }
    Ok(out)
}

/// The points of one flank's helix trace: heights from the reference face
/// (mm, one per section followed) and the deviations there (µm, +material,
/// in the spec's direction), offset so the first is 0. `flanks` is the
/// tooth's flanks in each section of `followed`.
pub(super) fn helix_points(
    followed: &Followed,
    flanks: &[Tooth],
    right: bool,
    geo: &Geometry,
    spec: &GearSpec,
) -> (Vec<f64>, Vec<f64>) {
    let rb = geo.rb();
    let tan_bb = geo.base_helix_deg.to_radians().tan();
    let h = hand_sign(spec.hand);
    let um = 1000.0 * direction_factor(geo, spec);
    let x: Vec<f64> = followed
        .z_mm
        .iter()
        .map(|z| z - spec.face_start_mm)
        .collect();
    let n = flank_sign(right);
    let b = spec.face_width_mm;
    let crowning = |x: f64| spec.helix_crowning_mm * (1.0 - (2.0 * x / b - 1.0).powi(2));
    let sin_at = (geo.base_diameter_mm / geo.reference_diameter_mm)
        .acos()
        .sin();
    let taper = |x: f64| spec.rack_offset_mm(spec.face_start_mm + x) * sin_at;
    let e: Vec<f64> = flanks
        .iter()
        .zip(&x)
        .map(|(t, &x)| {
            let theta = if right { t.right } else { t.left };
            n * (rb * theta - h * x * tan_bb) - crowning(x) - taper(x)
        })
        .collect();
    let e0 = e.first().copied().unwrap_or(0.0);
    let e: Vec<f64> = e.iter().map(|v| (v - e0) * um).collect();
    (x, e)
}

/// The profile deviations in every section of the face, each tooth's
/// traces started from its middle there as followed and evaluated over
/// that section's own evaluation range ([`GearSpec::at`]), summarised per
/// section.
pub(super) fn section_profiles(
    sections: &PolarSections,
    followed: &Followed,
    spec: &GearSpec,
) -> Result<Vec<SectionProfile>, Error> {
    let n = sections.r_mm[0].len();
    let mut out = Vec::with_capacity(followed.index.len());
    for (k, &j) in followed.index.iter().enumerate() {
        let sec = Section::new(&sections.r_mm[j], n);
        let teeth: Vec<Tooth> = followed.teeth.iter().map(|t| t[k]).collect();
        // The section's own drawing; its profile needs no measuring circle
        // (the middle's, which `at` keeps for the helix, may lie outside
        // the teeth of a far section of a steep cone).
        let here = GearSpec {
            measuring_diameter_mm: spec.measuring_diameter_mm,
            ..spec.at(sections.z_mm[j])?
        };
        let p = profiles(&sec, &teeth, &here.geometry()?, &here)?;
        out.push(SectionProfile {
            z_mm: followed.z_mm[k],
            slope_um: p.worst_signed(|d| d.slope_um),
            form_um: p.worst_signed(|d| d.form_um),
            total_um: p.worst_signed(|d| d.total_um),
            slope_mean_um: FlankValues::mean_of(&p, |d| d.slope_um),
        });
    }
    Ok(out)
}

/// Single and cumulative pitch deviations of both flanks at the measuring
/// circle, from the teeth found there.
pub(super) fn pitch(teeth: &[Tooth], geo: &Geometry) -> Result<FlankPair, Error> {
    let deg = |f: fn(&Tooth) -> f64| teeth.iter().map(|t| f(t).to_degrees()).collect::<Vec<_>>();
    let left = positions_from_angles(&deg(|t| t.left), geo.measuring_diameter_mm);
    let right = positions_from_angles(&deg(|t| t.right), geo.measuring_diameter_mm);
    evaluate_flanks(&left, &right)
}
