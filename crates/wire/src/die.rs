//! A die job's pure pipeline (docs/wire.md): the job's `[die]` checked
//! ([`check`]), its outline fitted and set off by the wire ([`cut`]), and
//! the figures of `model.die`. The programs and their replay are in
//! [`crate::programs`].

use gearcam_proto::{Code, Problem};
use std::f64::consts::PI;

use gearcam_proto::{Cutter, DiePart, DieSpec, WireProcess};

use crate::gear::{RackGear, ToothSpace};
use crate::offset::{offset, Side};
use crate::outline::{outline, Outline, OutlineError, Piece, Tolerances};
use crate::pinion::PinionGear;
use crate::Segment;
use gearcam_geom::involute::{inv, working_pressure_angle};

/// Fewest teeth accepted: below five the rack's tooth space runs into the
/// next, and the seed's method (one tooth space, rotated) has nothing to
/// repeat.
pub const MIN_TEETH: u32 = 5;
/// Most teeth accepted.
pub const MAX_TEETH: u32 = 1000;
/// The thinnest tooth tip accepted, as a share of the module: gear design
/// rules ask 0.2·m to 0.4·m against a brittle, pointed tip.
pub const MIN_TIP_THICKNESS: f64 = 0.2;
/// Smallest wire arc radius, mm: a control's arc below this is a point.
pub const MIN_ARC_RADIUS_MM: f64 = 0.005;

/// The rack-generated gear of a `[die]`.
pub fn gear_of(die: &DieSpec) -> RackGear {
    RackGear {
        module_mm: die.module_mm,
        teeth: die.teeth,
        pressure_angle_deg: die.pressure_angle_deg,
        profile_shift: die.profile_shift,
        addendum_coef: die.addendum_coef,
        clearance_coef: die.clearance_coef,
        tip_radius_coef: die.cutter_tip_radius_coef,
    }
}

/// The generated tooth space of a `[die]`: by a rack, or by a pinion
/// cutter.
pub fn space_of(die: &DieSpec) -> Box<dyn ToothSpace> {
    let gear = gear_of(die);
    match (die.cutter, die.cutter_teeth) {
        (Cutter::Pinion, Some(z0)) => Box::new(PinionGear {
            gear,
            cutter_teeth: z0,
            cutter_shift: die.cutter_shift,
        }),
        _ => Box::new(gear),
    }
}

/// The tooth's thickness on the tip circle, mm:
/// s_a = d_a·(s/d + inv α − inv α_a), s = m·(π/2 + 2·x·tan α),
/// cos α_a = d_b/d_a.
pub fn tip_thickness_mm(die: &DieSpec) -> f64 {
    let a = die.pressure_angle_deg.to_radians();
    let m = die.module_mm;
    let d = m * f64::from(die.teeth);
    let da = d + 2.0 * (die.addendum_coef + die.profile_shift) * m;
    let s = m * (PI / 2.0 + 2.0 * die.profile_shift * a.tan());
    let aa = (d * a.cos() / da).clamp(-1.0, 1.0).acos();
    da * (s / d + inv(a) - inv(aa))
}

/// The pair's centre distance with the mating gear, mm:
/// a = m·(z1 + z2)/2 · cos α / cos α′, inv α′ = inv α + 2·tan α·(x1 + x2)/(z1 + z2).
pub fn centre_distance_mm(die: &DieSpec) -> Option<f64> {
    let z2 = die.mating_teeth?;
    let a = die.pressure_angle_deg.to_radians();
    let z = f64::from(die.teeth + z2);
    let working = working_pressure_angle(a, a, die.profile_shift + die.mating_shift, z);
    Some(die.module_mm * z / 2.0 * a.cos() / working.cos())
}

/// Every problem of a `[die]` on its own (ranges, the cutter, a pointed
/// tooth), empty when it can be cut.
pub fn check(die: &DieSpec) -> Vec<Problem> {
    let mut out = Vec::new();
    let mut range = |field: &str, v: f64, lo: f64, hi: f64, unit: &str| {
        if !(lo..=hi).contains(&v) {
            out.push(Problem::new(
                Code::DIE_RANGE,
                &format!("die.{field}"),
                format!("{lo} to {hi}{unit}"),
                format!("{v}"),
                "the value is outside what gearcam cuts",
            ));
        }
    };
    range("module_mm", die.module_mm, 0.1, 20.0, " mm");
    range(
        "pressure_angle_deg",
        die.pressure_angle_deg,
        10.0,
        35.0,
        "°",
    );
    range("profile_shift", die.profile_shift, -1.0, 2.0, "");
    range("addendum_coef", die.addendum_coef, 0.5, 1.5, "");
    range("clearance_coef", die.clearance_coef, 0.0, 0.5, "");
    range(
        "cutter_tip_radius_coef",
        die.cutter_tip_radius_coef,
        0.0,
        0.5,
        "",
    );
    range(
        "flank_tolerance_um",
        die.flank_tolerance_um,
        0.5,
        100.0,
        " µm",
    );
    range(
        "fillet_tolerance_um",
        die.fillet_tolerance_um,
        0.5,
        100.0,
        " µm",
    );
    range("thickness_mm", die.thickness_mm, 0.1, 500.0, " mm");
    range("cutter_shift", die.cutter_shift, -1.0, 1.0, "");
    if !(MIN_TEETH..=MAX_TEETH).contains(&die.teeth) {
        out.push(Problem::new(
            Code::DIE_RANGE,
            "die.teeth",
            format!("{MIN_TEETH} to {MAX_TEETH}"),
            die.teeth.to_string(),
            "a gear of fewer teeth has no tooth space of its own to cut and repeat",
        ));
    }
    match (die.cutter, die.cutter_teeth) {
        (Cutter::Pinion, None) => out.push(Problem::new(
            Code::DIE_RANGE,
            "die.cutter_teeth",
            "the pinion cutter's teeth, 10 to 200",
            "none",
            "a pinion-type cutter's fillet depends on its teeth",
        )),
        (Cutter::Pinion, Some(z0)) if !(10..=200).contains(&z0) => out.push(Problem::new(
            Code::DIE_RANGE,
            "die.cutter_teeth",
            "10 to 200",
            z0.to_string(),
            "shaper cutters have 10 to 200 teeth",
        )),
        _ => {}
    }
    // The rack's tip round must lie on the gear's side of the pitch line
    // (its centre below it): above it the round's contact with the gear
    // runs through the pitch point and the envelope degenerates.
    let limit = die.addendum_coef + die.clearance_coef - die.cutter_tip_radius_coef;
    if out.is_empty() && die.cutter == Cutter::Rack && die.profile_shift >= limit {
        out.push(Problem::new(
            Code::DIE_RANGE,
            "die.profile_shift",
            format!("below ha* + c* − ρ* = {limit:.3} (the rack's tip round inside the pitch circle)"),
            format!("{}", die.profile_shift),
            "the rack's tip round would reach past the pitch line: lower the shift or the tip radius",
        ));
    }
    if out.is_empty() && !space_of(die).fillet_meets_involute() {
        out.push(Problem::new(
            Code::UNDERCUT_TOO_DEEP,
            "die.profile_shift",
            "a gear clearly undercut or not: the fillet ending on the involute",
            format!("{} teeth shifted by {}", die.teeth, die.profile_shift),
            "the rack's flank reaches just past the interference point and the fillet ends off the involute: gearcam does not model that outline; change the shift by a tenth",
        ));
    }
    if out.is_empty() {
        let sa = tip_thickness_mm(die);
        let least = MIN_TIP_THICKNESS * die.module_mm;
        if sa < least {
            out.push(Problem::new(
                Code::TIP_TOO_SHARP,
                "die.profile_shift",
                format!("a tooth at least {least:.3} mm thick at the tip ({MIN_TIP_THICKNESS}·m)"),
                format!("{sa:.3} mm"),
                "the tooth comes to a point: lower the profile shift or the addendum",
            ));
        }
    }
    out
}

/// The outline and the wire's path of a die job.
#[derive(Debug, Clone)]
pub struct Cut {
    /// The part's outline.
    pub outline: Outline,
    /// Every segment of the outline, clockwise from the middle of the
    /// tooth on +Y.
    pub contour: Vec<Segment>,
    /// The wire's side of the outline.
    pub side: Side,
    /// Wire radius plus spark gap, mm.
    pub offset_mm: f64,
    /// The wire's path: the contour set off.
    pub path: Vec<Segment>,
}

/// The wire's side for a part: outside the punch (left of a clockwise
/// outline), inside the die's opening (right).
pub fn side_of(part: DiePart) -> Side {
    match part {
        DiePart::Punch => Side::Left,
        DiePart::Die => Side::Right,
    }
}

/// The outline of a checked `[die]` and the wire's path about it.
pub fn cut(die: &DieSpec, process: &WireProcess) -> Result<Cut, Problem> {
    let tol = Tolerances {
        flank_mm: die.flank_tolerance_um / 1000.0,
        fillet_mm: die.fillet_tolerance_um / 1000.0,
        min_radius_mm: MIN_ARC_RADIUS_MM,
    };
    let outline = outline(space_of(die).as_ref(), &tol).map_err(|e| match e {
        OutlineError::Fit { piece, error } => Problem::new(
            Code::ARC_FIT,
            &format!("die.{piece}_tolerance_um"),
            format!("a {piece} within {} arcs", error.max_arcs),
            format!(
                "the best came within {:.3} µm",
                error.best_deviation * 1000.0
            ),
            "no arc spline of the allowed size holds the tolerance: loosen it",
        ),
    })?;
    let contour = outline.segments();
    let side = side_of(die.part);
    let d = process.offset_mm();
    let path = offset(&contour, side, d).map_err(|e| {
        let s = contour[e.index];
        let at = s.from();
        let (_, piece) = outline.distance(at);
        let place = match piece {
            Piece::Fillet | Piece::Root => "root fillet",
            Piece::Flank | Piece::Tip => "flank",
        };
        let tooth = e.index / outline.period.len() + 1;
        Problem::new(
            Code::WIRE_TOO_THICK,
            "wire.wire_diameter_mm",
            format!(
                "a wire radius plus spark gap under {:.4} mm (the tightest radius of the {place})",
                e.radius_mm
            ),
            format!("{d:.4} mm"),
            format!(
                "the wire cannot follow the {place} of tooth {tooth} at ({:.3}, {:.3}) mm: choose a thinner wire",
                at.0, at.1
            ),
        )
    })?;
    Ok(Cut {
        outline,
        contour,
        side,
        offset_mm: d,
        path,
    })
}

/// The length of a path, mm.
pub fn length_mm(path: &[Segment]) -> f64 {
    path.iter().map(|s| s.arc().length).sum()
}
