//! The process rules: depth, face width, shift compensation, synchronisation.

use super::{BlankGeometry, SafetyFinding, SafetyKind};
use crate::hob::Hob;
use crate::kinematics::{Segment, Timeline};

/// Depth shortfall ignored, mm (the programs print X to 0.001 mm).
pub const DEPTH_TOL_MM: f64 = 0.005;

/// Mismatch of a shift's table turn ignored, mm of arc at the blank's radius.
pub const SHIFT_TOL_MM: f64 = 0.005;

/// A coupled feed with the hob turning: the moves that generate teeth.
fn cutting(s: &Segment) -> bool {
    s.gearbox.is_some() && s.feed && s.hob_rev_s != 0.0 && s.t1_s > s.t0_s
}

/// The X a segment commands, on the ideal machine, less the blank's taper
/// at its Z: X as if at the lower face, so a conical gear's feed along its
/// cone keeps one depth, beyond its small end too (where the cone line runs
/// on to finish that face). Beyond the large end the taper is that face's:
/// the hob holding X there cuts no deeper than at the face. Along the
/// straight move this is piecewise linear, so its range is taken at the
/// ends and where Z crosses the large-end face. Depth and face width are
/// what the program commands, whatever the what-if errors (a runout would
/// move X with the hob's angle at each end point and make a full-depth
/// move look shallow).
fn x_range(tl: &Timeline, i: usize, blank: &BlankGeometry) -> (f64, f64) {
    let s = &tl.segments()[i];
    let (a, b) = (
        tl.nominal_pose_in(i, s.t0_s).axes,
        tl.nominal_pose_in(i, s.t1_s).axes,
    );
    let (lo, hi) = (blank.z_lo_mm, blank.z_hi_mm);
    // The radius grows towards the large end.
    let large = if blank.taper < 0.0 { lo } else { hi };
    // Z held at the large-end face beyond it.
    let depth = |x: f64, z: f64| {
        let z = if large == lo { z.max(lo) } else { z.min(hi) };
        x - blank.taper * (z - lo)
    };
    let (da, db) = (depth(a.x_mm, a.z_mm), depth(b.x_mm, b.z_mm));
    let mut range = (da.min(db), da.max(db));
    if (a.z_mm - large) * (b.z_mm - large) < 0.0 {
        let f = (large - a.z_mm) / (b.z_mm - a.z_mm);
        let x = depth(a.x_mm + f * (b.x_mm - a.x_mm), large);
        range = (range.0.min(x), range.1.max(x));
    }
    range
}

/// Depth: the deepest X of the coupled feed against the plunge depth
/// X_p = r_f + r_a0 (the hob's tip circle touching the root circle). Face
/// width: the Z range the hob centre covers at full depth (X within
/// [`DEPTH_TOL_MM`] of the deepest, and the crowning higher on a crowned
/// gear) must hold the faces and the generating
/// zone's run-out beyond each, |sin η|·h/(2·tan α_x): the hob's deepest
/// point stands at its centre's height (the tip cylinder is nearest the gear
/// axis at a = 0 along u), and the flanks of a gap of depth h are generated
/// over h/tan α_x along u (the path of contact of the rack, projected on
/// its pitch line), half on either side of the centre, which the tilt η
/// turns out of the transverse plane by sin η.
/// Only the segments `i` with `mine[i]` count: the moves made with the
/// gear's own hob.
pub(super) fn depth_and_face(
    tl: &Timeline,
    hob: &Hob,
    blank: &BlankGeometry,
    mine: &[bool],
    out: &mut Vec<SafetyFinding>,
) {
    let cuts: Vec<usize> = (0..tl.segments().len())
        .filter(|&i| mine[i] && cutting(&tl.segments()[i]))
        .collect();
    // Along a cone the hob's tip stands ra0/cos δ = ra0·√(1 + taper²) from
    // its centre in a transverse section (gearcam_model::path::cone_offsets).
    let tip = hob.tip_radius_mm * blank.taper.hypot(1.0);
    let plunge = blank.root_radius_mm + tip;
    let Some(&deepest) = cuts
        .iter()
        .min_by(|&&a, &&b| x_range(tl, a, blank).0.total_cmp(&x_range(tl, b, blank).0))
    else {
        out.push(SafetyFinding {
            kind: SafetyKind::DepthNotReached,
            line: tl.segments().last().map_or(0, |s| s.line),
            what: "no coupled feed move with the hob turning".into(),
            why: "the program cuts no teeth".into(),
        });
        return;
    };
    let x_min = x_range(tl, deepest, blank).0;
    let line = tl.segments()[deepest].line;
    if x_min > plunge + DEPTH_TOL_MM {
        out.push(SafetyFinding {
            kind: SafetyKind::DepthNotReached,
            line,
            what: format!(
                "the deepest coupled feed stands at X {x_min:.3}, the plunge depth is X {plunge:.3} (root radius {:.3} + the hob tip's reach {:.3} from its centre)",
                blank.root_radius_mm, tip
            ),
            why: format!("the gaps stay {:.3} mm short of the root", x_min - plunge),
        });
    }
    let depth = blank.outer_radius_mm - blank.root_radius_mm;
    let mut spans: Vec<(f64, f64)> = Vec::new();
    let mut run = 0.0f64;
    for &i in &cuts {
        let s = &tl.segments()[i];
        if x_range(tl, i, blank).1 > x_min + DEPTH_TOL_MM + blank.crowning_mm {
            continue;
        }
        run = run.max(s.eta_rad.sin().abs() * depth / (2.0 * hob.tan_alpha_x));
        spans.push((s.from.z_mm.min(s.to.z_mm), s.from.z_mm.max(s.to.z_mm)));
    }
    spans.sort_by(|a, b| a.0.total_cmp(&b.0));
    if let Some(throat) = blank.throat_z_mm {
        // A worm wheel: its teeth are enveloped by the hob standing in the
        // throat plane at full depth, which a radial feed reaches at its
        // end (and a tangential one holds).
        let in_throat = cuts.iter().any(|&i| {
            let s = &tl.segments()[i];
            let (a, b) = (s.from.z_mm.min(s.to.z_mm), s.from.z_mm.max(s.to.z_mm));
            x_range(tl, i, blank).0 <= x_min + DEPTH_TOL_MM
                && a <= throat + DEPTH_TOL_MM
                && b >= throat - DEPTH_TOL_MM
        });
        if !in_throat {
            out.push(SafetyFinding {
                kind: SafetyKind::FaceWidthNotCovered,
                line,
                what: format!(
                    "at full depth the hob centre never stands in the throat plane Z {throat:.3}"
                ),
                why: "the worm wheel's teeth are not enveloped where the worm will run".into(),
            });
        }
        return;
    }
    let (lo, hi) = (blank.z_lo_mm - run, blank.z_hi_mm + run);
    let mut covered = false;
    let mut cur: Option<(f64, f64)> = None;
    for (a, b) in spans {
        cur = match cur {
            Some((c0, c1)) if a <= c1 + 1e-9 => Some((c0, c1.max(b))),
            _ => Some((a, b)),
        };
        if let Some((c0, c1)) = cur {
            covered |= c0 <= lo + 1e-9 && c1 >= hi - 1e-9;
        }
    }
    if !covered {
        out.push(SafetyFinding {
            kind: SafetyKind::FaceWidthNotCovered,
            line,
            what: format!(
                "at full depth the hob centre does not cover Z {lo:.3} to {hi:.3} in one run (the faces {:.3} to {:.3} and the run-out {run:.3})",
                blank.z_lo_mm, blank.z_hi_mm
            ),
            why: "part of the face width is not cut to full depth".into(),
        });
    }
}

/// A shift ΔY along u with the hob angle standing moves the thread by ΔY:
/// the thread is A = Y + p·(ψ − B) + j·p_x (p = s_h·z0·p_x/2π, ψ the angle
/// about u), so (Y + ΔY, B) cuts as (Y, B − ΔY/p), a hob turn of −ΔY/p,
/// which the table must follow by ΔC = −(C/B)·ΔY/p. A coupled cutting move
/// whose table turn for its shift (C per Y·ΔY plus a FANUC correction)
/// differs from it by more than [`SHIFT_TOL_MM`] at the blank's radius,
/// while the hob is in the blank, puts the cut in other gaps. Only the
/// segments `i` with `mine[i]` count.
pub(super) fn shifts(
    tl: &Timeline,
    hob: &Hob,
    blank: &BlankGeometry,
    mine: &[bool],
    out: &mut Vec<SafetyFinding>,
) {
    let p = hob.hand * f64::from(hob.starts) * hob.axial_pitch_mm / std::f64::consts::TAU;
    for (i, s) in tl.segments().iter().enumerate() {
        let dy = s.to.y_mm - s.from.y_mm;
        let Some(g) = s
            .gearbox
            .filter(|_| mine[i] && cutting(s) && dy.abs() > 1e-6)
        else {
            continue;
        };
        let turned = g.c_per_y_rad_mm * dy + s.c_extra_rad;
        let needed = -g.c_per_b * dy / p;
        let miss = blank.outer_radius_mm * (turned - needed).abs();
        if miss <= SHIFT_TOL_MM {
            continue;
        }
        let env = blank.envelope();
        let solid = super::solid(hob);
        if super::contact::along(tl, i, solid, &env, super::PEN_TOL_MM).is_none() {
            continue;
        }
        out.push(SafetyFinding {
            kind: SafetyKind::UncompensatedShift,
            line: s.line,
            what: format!(
                "the shift {dy:.3} mm turns the table {:.6} rad, it needs {:.6} rad (−(C/B)·ΔY/p)",
                turned, needed
            ),
            why: format!(
                "the cut moves {miss:.3} mm along the blank's circumference: it lands in other gaps"
            ),
        });
    }
}

/// A unit coupled again after it cut, with an unknown phase.
pub(super) fn couplings(tl: &Timeline, out: &mut Vec<SafetyFinding>) {
    for c in tl.couplings().iter().filter(|c| c.phase_unknown) {
        out.push(SafetyFinding {
            kind: SafetyKind::UnsynchronisedCoupling,
            line: c.line,
            what: format!(
                "the coupling couples the unit again after the cut of line {}'s coupling without synchronised positions on both",
                c.reference_line
            ),
            why: format!(
                "the table's phase is unknown; the worst case, half a pitch ({:.6} rad), cuts double teeth",
                c.offset_rad
            ),
        });
    }
}
