//! The whole outline: closed, without a corner but at the tooth's tip edges
//! (and an undercut's crossing), each arc within its piece's tolerance of
//! the theoretical outline measured on dense samples.

use std::f64::consts::TAU;

use gearcam_arcfit::Curve;
use gearcam_geom::plane::rotate;
use gearcam_wire::gear::RackGear;
use gearcam_wire::outline::{outline, Piece, Tolerances};
use gearcam_wire::Segment;

fn gear(m: f64, z: u32, x: f64) -> RackGear {
    RackGear {
        module_mm: m,
        teeth: z,
        pressure_angle_deg: 20.0,
        profile_shift: x,
        addendum_coef: 1.0,
        clearance_coef: 0.25,
        tip_radius_coef: 0.38,
    }
}

const TOL: Tolerances = Tolerances {
    flank_mm: 0.001,
    fillet_mm: 0.005,
    min_radius_mm: 0.0,
};

fn gap(a: (f64, f64), b: (f64, f64)) -> f64 {
    (a.0 - b.0).hypot(a.1 - b.1)
}

/// The largest deviation of the segments from the theoretical outline,
/// each point counted against its nearest piece's tolerance (in units of
/// that tolerance), on 400 points per segment.
fn worst_ratio(o: &gearcam_wire::outline::Outline, segments: &[Segment]) -> f64 {
    let mut worst: f64 = 0.0;
    for s in segments {
        let a = s.arc();
        for i in 0..=400 {
            let (d, piece) = o.distance(a.point_at(a.length * f64::from(i) / 400.0));
            let tol = match piece {
                Piece::Flank | Piece::Tip => TOL.flank_mm,
                Piece::Fillet | Piece::Root => TOL.fillet_mm,
            };
            worst = worst.max(d / tol);
        }
    }
    worst
}

#[test]
fn the_m2_z20_outline_is_closed_smooth_and_within_its_tolerances() {
    let g = gear(2.0, 20, 0.0);
    let o = outline(&g, &TOL).unwrap();
    eprintln!(
        "m2 z20: {} arcs per flank ({:.3} um), {} per fillet ({:.3} um), {} per pitch",
        o.arcs_per_flank,
        o.flank_fit_mm * 1e3,
        o.arcs_per_fillet,
        o.fillet_fit_mm * 1e3,
        o.period.len()
    );
    assert!(o.arcs_per_flank <= 4, "{} arcs per flank", o.arcs_per_flank);
    assert!(!o.undercut);
    let all = o.segments();
    assert_eq!(all.len(), 20 * o.period.len());
    // Closed: each segment starts where the one before ended.
    for (i, s) in all.iter().enumerate() {
        let next = &all[(i + 1) % all.len()];
        assert!(gap(s.to(), next.from()) < 1e-9, "gap after segment {i}");
    }
    // Corners only at the tooth's tip edges: two per pitch.
    let corners = (0..all.len())
        .filter(|&i| {
            let (a, b) = (all[i].arc(), all[(i + 1) % all.len()].arc());
            let turn = (b.start_angle - a.end_angle() + 3.0 * std::f64::consts::PI).rem_euclid(TAU)
                - std::f64::consts::PI;
            turn.abs() > 1e-7
        })
        .count();
    assert_eq!(corners, 2 * 20);
    let worst = worst_ratio(&o, &all);
    assert!(worst <= 1.0, "{worst} of the tolerance");
    // No inflection artefacts: the half space's fillet arcs all turn one
    // way and its flank arcs the other (the involute never changes its
    // sense; the S between them is the true outline's). The period starts
    // with the tip half, then the mirrored flank, fillet, root arc,
    // fillet, flank, tip half; take the second half's fillet and flank.
    let (nf, nk) = (o.arcs_per_fillet, o.arcs_per_flank);
    let start = 1 + nk + nf + 1;
    let fillet: Vec<f64> = o.period[start..start + nf]
        .iter()
        .map(|s| s.arc().curvature)
        .collect();
    let flank: Vec<f64> = o.period[start + nf..start + nf + nk]
        .iter()
        .map(|s| s.arc().curvature)
        .collect();
    assert!(fillet.iter().all(|k| *k > 0.0), "fillet {fillet:?}");
    assert!(flank.iter().all(|k| *k < 0.0), "flank {flank:?}");
}

/// The distance folds a point into the half tooth space: points of the
/// fillet and flank, turned to any tooth and mirrored, are on the outline;
/// points set off along the radius by δ are δ away.
#[test]
fn the_outline_distance_sees_every_tooth_and_both_flanks() {
    let g = gear(1.5, 13, 0.3);
    let o = outline(&g, &TOL).unwrap();
    let (fillet, flank) = (g.fillet(), g.flank());
    let z = 13.0;
    for (k, curve) in [(0u32, &fillet as &dyn Curve), (5, &flank), (12, &flank)] {
        let (t0, t1) = curve.domain();
        for i in 0..=10 {
            let p = curve.point(t0 + (t1 - t0) * f64::from(i) / 10.0);
            // Into the outline's frame (a tooth's middle on +Y), then tooth k.
            let p = rotate(p, std::f64::consts::PI / z - TAU * f64::from(k) / z);
            let mirrored = (-p.0, p.1);
            for q in [p, mirrored] {
                let (d, _) = o.distance(q);
                assert!(d < 1e-6, "tooth {k} point {i}: {d}");
            }
        }
    }
    let (d, piece) = o.distance((0.0, o.figures.tip_radius_mm + 0.25));
    assert!(
        (d - 0.25).abs() < 1e-12 && piece == Piece::Tip,
        "{d} {piece:?}"
    );
}

/// An undercut pinion (z 9): the fillet meets the involute at a corner of
/// the part, so a third corner per flank; still within the tolerances.
#[test]
fn an_undercut_pinion_has_its_corner_and_keeps_its_tolerances() {
    let g = gear(1.0, 9, 0.0);
    let o = outline(&g, &TOL).unwrap();
    assert!(o.undercut);
    let worst = worst_ratio(&o, &o.segments());
    assert!(worst <= 1.0, "{worst} of the tolerance");
}

/// The distance of a point from the square ±5 mm (brute force over its four
/// edges).
fn square_distance(q: (f64, f64)) -> f64 {
    let edge = |a: (f64, f64), b: (f64, f64)| {
        let (dx, dy) = (b.0 - a.0, b.1 - a.1);
        let t = (((q.0 - a.0) * dx + (q.1 - a.1) * dy) / (dx * dx + dy * dy)).clamp(0.0, 1.0);
        (a.0 + t * dx - q.0).hypot(a.1 + t * dy - q.1)
    };
    let c = [(-5.0, 5.0), (5.0, 5.0), (5.0, -5.0), (-5.0, -5.0)];
    (0..4)
        .map(|i| edge(c[i], c[(i + 1) % 4]))
        .fold(f64::INFINITY, f64::min)
}

/// A square run clockwise set off both ways: outside (left) its corners are
/// rounded on the offset, inside (right) they are cut back; every point of
/// either lies the offset from the square, and the path closes.
#[test]
fn a_square_sets_off_outside_round_and_inside_sharp() {
    use gearcam_wire::offset::{offset, Side};
    let c = [(-5.0, 5.0), (5.0, 5.0), (5.0, -5.0), (-5.0, -5.0)];
    let square: Vec<Segment> = (0..4)
        .map(|i| Segment::Line {
            from: c[i],
            to: c[(i + 1) % 4],
        })
        .collect();
    for (side, blocks) in [(Side::Left, 8), (Side::Right, 4)] {
        let path = offset(&square, side, 0.13).unwrap();
        assert_eq!(path.len(), blocks, "{side:?}");
        for (i, s) in path.iter().enumerate() {
            assert!(gap(s.to(), path[(i + 1) % path.len()].from()) < 1e-12);
            let a = s.arc();
            for k in 0..=50 {
                let d = square_distance(a.point_at(a.length * f64::from(k) / 50.0));
                assert!((d - 0.13).abs() < 1e-12, "{side:?} {i}: {d}");
            }
        }
    }
}

/// The punch's and the die's paths of m2 z20 lie the offset from the
/// theoretical outline within the tolerances, close, and go round once
/// clockwise; a wire thicker than the fillet's tightest arc is refused with
/// that arc.
#[test]
fn punch_and_die_paths_keep_the_offset() {
    use gearcam_wire::offset::{offset, Side};
    use gearcam_wire::verify::measure;
    let g = gear(2.0, 20, 0.0);
    let o = outline(&g, &TOL).unwrap();
    let all = o.segments();
    for side in [Side::Left, Side::Right] {
        let path = offset(&all, side, 0.1).unwrap();
        let m = measure(&o, &path, 0.1, 64);
        assert!(m.flank_mm <= TOL.flank_mm, "{side:?} {m:?}");
        assert!(m.fillet_mm <= TOL.fillet_mm, "{side:?} {m:?}");
        assert!(m.closure_mm < 1e-9 && (m.turns + 1.0).abs() < 1e-9, "{m:?}");
    }
    let tightest = o
        .period
        .iter()
        .filter_map(|s| match *s {
            Segment::Arc {
                from,
                centre,
                ccw: true,
                ..
            } => Some((from.0 - centre.0).hypot(from.1 - centre.1)),
            _ => None,
        })
        .fold(f64::INFINITY, f64::min);
    let e = offset(&all, Side::Left, tightest + 0.01).unwrap_err();
    assert!((e.radius_mm - tightest).abs() < 1e-12, "{e}");
}
