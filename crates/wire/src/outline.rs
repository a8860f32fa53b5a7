//! The whole outline of a gear as arcs (docs/wire.md): the root arc, the
//! fitted fillet and flank, and the tip arc of one half tooth space,
//! mirrored about the tooth's axis into one tooth pitch, and turned z times
//! about the centre.
//!
//! The flank is fitted first with its start tangent free (an involute
//! starting near its base circle turns fast there; holding its exact
//! tangent costs arcs). The fillet is fitted after it, from the deepest
//! point with the root circle's tangent to the flank spline's first point
//! and tangent exactly (its last two arcs are a biarc), so the outline has
//! no corner there; with undercut the fillet and the involute meet at a
//! corner of the part itself, and the fillet ends on it with its own
//! tangent.
//!
//! The outline runs clockwise about the gear's centre (the material on the
//! right of travel) and starts in the middle of a tooth's tip on +Y.

use gearcam_geom::plane::{mirror, rotate};
use std::f64::consts::{FRAC_PI_2, PI, TAU};

use gearcam_arcfit::{fit, Curve, FitError, Options};

use crate::gear::{Figures, Flank, ToothSpace};
use crate::polyline::Fillet;
use crate::Segment;

/// The fit's tolerances, mm.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tolerances {
    /// On the flank (the involute that meshes).
    pub flank_mm: f64,
    /// On the root fillet.
    pub fillet_mm: f64,
    /// The smallest arc radius allowed.
    pub min_radius_mm: f64,
}

/// The outline of a gear and what its fit took.
#[derive(Debug, Clone)]
pub struct Outline {
    /// One tooth pitch, clockwise from the middle of the tooth on +Y to
    /// the middle of the next.
    pub period: Vec<Segment>,
    /// Teeth.
    pub teeth: u32,
    /// The gear's figures.
    pub figures: Figures,
    /// Whether the flank is undercut.
    pub undercut: bool,
    /// Arcs per flank.
    pub arcs_per_flank: usize,
    /// Arcs per fillet.
    pub arcs_per_fillet: usize,
    /// The flank fit's deviation from the involute (exact distance), mm.
    pub flank_fit_mm: f64,
    /// The fillet fit's deviation from the fillet, mm.
    pub fillet_fit_mm: f64,
    flank: Flank,
    fillet: Fillet,
    /// The fillet's smallest and largest radius, mm.
    fillet_radii: (f64, f64),
    /// The root arc's polar angles (from the fillet's start to the space's
    /// axis) in the half-space frame.
    root_from: f64,
    /// The tip arc's polar angles (from the tooth's axis to the flank's end).
    tip_to: f64,
    /// The root and tip arcs' end points in the fit's frame.
    root_ends: [(f64, f64); 2],
    tip_ends: [(f64, f64); 2],
}

/// Why there is no outline.
#[derive(Debug, Clone, PartialEq)]
pub enum OutlineError {
    /// A piece could not be fitted within its tolerance.
    Fit {
        /// `flank` or `fillet`.
        piece: &'static str,
        /// What the fit reached.
        error: FitError,
    },
}

impl std::fmt::Display for OutlineError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            OutlineError::Fit { piece, error } => write!(f, "the {piece}: {error}"),
        }
    }
}

impl std::error::Error for OutlineError {}

/// Samples of the fillet for its distance (a sagitta below 1 nm for the
/// fillets gearcam cuts: `Sampled::sag`).
const FILLET_SAMPLES: usize = 1024;

/// A segment mirrored about the line through the origin at `angle` and
/// run the other way.
fn mirrored_back(s: &Segment, angle: f64) -> Segment {
    s.reflect(|p| mirror(p, angle)).reversed()
}

fn concentric(from: (f64, f64), to: (f64, f64)) -> Segment {
    Segment::Arc {
        from,
        to,
        centre: (0.0, 0.0),
        ccw: false,
    }
}

/// The outline of `gear` within `tol`.
pub fn outline(gear: &dyn ToothSpace, tol: &Tolerances) -> Result<Outline, OutlineError> {
    let figures = gear.figures();
    let flank = gear.flank();
    let exact_fillet = gear.fillet_curve();
    let fillet = Fillet::new(exact_fillet.as_ref(), FILLET_SAMPLES);
    let undercut = gear.undercut();
    let mut o = Options::tolerance(tol.flank_mm);
    o.min_radius = tol.min_radius_mm;
    let flank_fit = fit(&flank, &o).map_err(|error| OutlineError::Fit {
        piece: "flank",
        error,
    })?;
    let first = flank_fit.arcs[0];
    let (p0, p1) = exact_fillet.domain();
    let deepest = exact_fillet.point(p0);
    let on_axis = deepest.0.abs() < 1e-9;
    let mut o = Options::tolerance(tol.fillet_mm);
    o.min_radius = tol.min_radius_mm;
    o.start_point = Some(deepest);
    // With a root arc the fillet starts on its tangent; where the two
    // fillets meet on the space's axis, at a corner.
    o.start_angle = (!on_axis).then(|| exact_fillet.tangent_angle(p0));
    o.end_point = Some(first.start);
    o.end_angle = Some(if undercut {
        exact_fillet.tangent_angle(p1)
    } else {
        first.start_angle
    });
    let fillet_fit = fit(&fillet, &o).map_err(|error| OutlineError::Fit {
        piece: "fillet",
        error,
    })?;
    let mut half: Vec<Segment> = Vec::new();
    if !on_axis {
        half.push(concentric((0.0, figures.root_radius_mm), deepest));
    }
    half.extend(fillet_fit.arcs.iter().map(Segment::of_arc));
    half.extend(flank_fit.arcs.iter().map(Segment::of_arc));
    let z = f64::from(gear.teeth());
    let tooth_axis = FRAC_PI_2 - PI / z;
    let edge = half.last().expect("segments").to();
    let ra = edge.0.hypot(edge.1);
    half.push(concentric(edge, rotate((0.0, ra), -PI / z)));
    // The period from the tooth's axis: the half mirrored about it, run
    // backwards (to the next space's axis), then the half turned by one
    // pitch; the two root arcs either side of the space's axis are one.
    let pitch = TAU / z;
    let mut period: Vec<Segment> = half
        .iter()
        .rev()
        .map(|s| mirrored_back(s, tooth_axis))
        .collect();
    let turned: Vec<Segment> = half.iter().map(|s| s.map(|p| rotate(p, -pitch))).collect();
    let mut rest = turned.into_iter();
    if !on_axis {
        let root = rest.next().expect("a root arc");
        let last = period.pop().expect("a root arc");
        period.push(concentric(last.from(), root.to()));
    }
    period.extend(rest);
    // Start in the middle of the tooth on +Y.
    let period = period
        .iter()
        .map(|s| s.map(|p| rotate(p, PI / z)))
        .collect();
    Ok(Outline {
        period,
        teeth: gear.teeth(),
        figures,
        undercut,
        arcs_per_flank: flank_fit.arcs.len(),
        arcs_per_fillet: fillet_fit.arcs.len(),
        flank_fit_mm: flank_fit.max_deviation,
        fillet_fit_mm: fillet_fit.max_deviation,
        flank,
        fillet_radii: {
            let (t0, t1) = fillet.domain();
            let (lo, hi) = (0..=200)
                .map(|i| {
                    let p = fillet.point(t0 + (t1 - t0) * f64::from(i) / 200.0);
                    p.0.hypot(p.1)
                })
                .fold((f64::INFINITY, 0.0f64), |(lo, hi), r| {
                    (lo.min(r), hi.max(r))
                });
            // A margin for the fillet between the samples.
            (lo - 0.01, hi + 0.01)
        },
        fillet,
        root_from: deepest.1.atan2(deepest.0),
        tip_to: edge.1.atan2(edge.0),
        root_ends: {
            let at = |b: f64| {
                (
                    figures.root_radius_mm * b.cos(),
                    figures.root_radius_mm * b.sin(),
                )
            };
            [at(deepest.1.atan2(deepest.0)), at(FRAC_PI_2)]
        },
        tip_ends: {
            let at = |b: f64| {
                (
                    figures.tip_radius_mm * b.cos(),
                    figures.tip_radius_mm * b.sin(),
                )
            };
            [at(FRAC_PI_2 - PI / z), at(edge.1.atan2(edge.0))]
        },
    })
}

/// `x.rem_euclid(p)` (p > 0) to the bit, mostly without the remainder's
/// long division.
///
/// `x % p` is exact: x − m·p for m = trunc(x/p) taken exactly, a number
/// that is representable; so the fused multiply-add of −m, p and x (one
/// rounding of the exact x − m·p) gives it exactly whenever the quotient
/// rounded in floating point truncates to that same m. When it does not
/// (x/p within a rounding of a whole number) the result is x − (m ± 1)·p,
/// which lies outside (−p, p) or has the other sign than x: those, and a
/// zero (whose sign `%` takes from x), take `%` itself. Then, as
/// `rem_euclid` does, a negative remainder gains p.
fn rem_euclid(x: f64, p: f64) -> f64 {
    let m = (x / p).trunc();
    let r = (-m).mul_add(p, x);
    let r = if r != 0.0 && r.abs() < p && (r > 0.0) == (x > 0.0) {
        r
    } else {
        x % p
    };
    if r < 0.0 {
        r + p
    } else {
        r
    }
}

/// Which part of the theoretical outline is nearest a point.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Piece {
    /// The root circle.
    Root,
    /// The root fillet.
    Fillet,
    /// The involute flank.
    Flank,
    /// The tip circle.
    Tip,
}

impl Outline {
    /// Every segment, the period turned z times clockwise.
    pub fn segments(&self) -> Vec<Segment> {
        let pitch = TAU / f64::from(self.teeth);
        (0..self.teeth)
            .flat_map(|k| {
                let a = -pitch * f64::from(k);
                self.period.iter().map(move |s| s.map(|p| rotate(p, a)))
            })
            .collect()
    }

    /// The distance from `q` to the theoretical outline (the involute
    /// exactly, the fillet on 4,096 chords), and the nearest piece: `q` is
    /// folded into the half tooth space by the gear's symmetry.
    pub fn distance(&self, q: (f64, f64)) -> (f64, Piece) {
        self.distance_at((q.0 * q.0 + q.1 * q.1).sqrt(), q.1.atan2(q.0))
    }

    /// [`Outline::distance`] of the point at radius `r` and polar angle
    /// `polar` (radians), for a caller that has them: the flank's distance
    /// is taken from the folded angle itself, and the folded point is
    /// worked out only where an end point or the fillet needs it.
    pub(crate) fn distance_at(&self, r: f64, polar: f64) -> (f64, Piece) {
        let z = f64::from(self.teeth);
        // The angle from the first space's axis (π/2 + π/z), folded into
        // (−π/z, 0] by whole pitches and the mirror about that axis; the
        // point is then the fit frame's, the space's axis on +Y, on the
        // circle of its radius.
        let d = rem_euclid(polar - FRAC_PI_2, TAU / z) - PI / z;
        let a = FRAC_PI_2 - d.abs();
        let folded = std::cell::OnceCell::new();
        let q = || *folded.get_or_init(|| (r * a.cos(), r * a.sin()));
        // An arc of the root or tip circle: the radial gap within its
        // angles, else the nearer end point (the ends computed once).
        let circle = |radius: f64, lo: f64, hi: f64, ends: &[(f64, f64); 2]| {
            if (lo..=hi).contains(&a) {
                (r - radius).abs()
            } else {
                let q = q();
                let end = |e: &(f64, f64)| ((q.0 - e.0).powi(2) + (q.1 - e.1).powi(2)).sqrt();
                end(&ends[0]).min(end(&ends[1]))
            }
        };
        let f = &self.figures;
        // The flank first; a circle's arc is at least |r − its radius|
        // away (its ends lie on the circle, to a rounding far below
        // `MARGIN`), so one whose gap exceeds the nearest so far by more
        // than that can neither be the nearest nor tie with it, and is not
        // measured (its ends need the folded point's sine and cosine).
        const MARGIN: f64 = 1e-9;
        let flank = self.flank.distance_polar(r, a, q);
        let root = if (r - f.root_radius_mm).abs() - MARGIN > flank {
            f64::INFINITY
        } else {
            circle(f.root_radius_mm, self.root_from, FRAC_PI_2, &self.root_ends)
        };
        let tip = if (r - f.tip_radius_mm).abs() - MARGIN > flank.min(root) {
            f64::INFINITY
        } else {
            circle(
                f.tip_radius_mm,
                FRAC_PI_2 - PI / z,
                self.tip_to,
                &self.tip_ends,
            )
        };
        let best = [
            (root, Piece::Root),
            (flank, Piece::Flank),
            (tip, Piece::Tip),
        ]
        .into_iter()
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .expect("three pieces");
        // The fillet lies between two radii: a point further from that
        // band than the best so far is nearer another piece (the fillet's
        // chord search is the dearest of the four).
        let (lo, hi) = self.fillet_radii;
        let bound = (lo - r).max(r - hi).max(0.0);
        if bound >= best.0 {
            return best;
        }
        let fillet = (self.fillet.distance(q()), Piece::Fillet);
        if fillet.0 < best.0 {
            fillet
        } else {
            best
        }
    }
}

impl Outline {
    /// Points of the theoretical outline of the tooth space
    /// counter-clockwise of the tooth on +Y, from the middle of that tooth
    /// to the middle of the next: `n` points per piece (root arc, fillet,
    /// flank, tip arc), each side.
    pub fn theory_space(&self, n: usize) -> Vec<(f64, f64)> {
        let z = f64::from(self.teeth);
        let f = &self.figures;
        let arc = |r: f64, a0: f64, a1: f64| -> Vec<(f64, f64)> {
            (0..=n)
                .map(|i| {
                    let a = a0 + (a1 - a0) * i as f64 / n as f64;
                    (r * a.cos(), r * a.sin())
                })
                .collect()
        };
        let along = |c: &dyn Curve| -> Vec<(f64, f64)> {
            let (t0, t1) = c.domain();
            (0..=n)
                .map(|i| c.point(t0 + (t1 - t0) * i as f64 / n as f64))
                .collect()
        };
        // The right half in the fit's frame, from the space's axis to the
        // tooth's, then turned so the tooth's axis is +Y.
        let mut half = arc(f.root_radius_mm, FRAC_PI_2, self.root_from);
        half.extend(along(&self.fillet));
        half.extend(along(&self.flank));
        half.extend(arc(f.tip_radius_mm, self.tip_to, FRAC_PI_2 - PI / z));
        let right: Vec<(f64, f64)> = half.iter().map(|&p| rotate(p, PI / z)).collect();
        // The left half: the right mirrored about the space's axis.
        let axis = FRAC_PI_2 + PI / z;
        let mut out: Vec<(f64, f64)> = right.iter().rev().copied().collect();
        out.extend(right.iter().map(|&p| mirror(p, axis)));
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gear::RackGear;

    /// The distance from the polar angle (the flank's from θb − a, the
    /// folded point built only where needed) against the way it was first
    /// taken: the folded point built, each piece's own distance of it.
    /// Points round a whole gear, on and off the outline, agree within
    /// 10⁻¹² mm and on the nearest piece.
    #[test]
    fn the_polar_distance_is_the_pieces_distance() {
        let gear = RackGear {
            module_mm: 2.0,
            teeth: 23,
            pressure_angle_deg: 20.0,
            profile_shift: 0.2,
            addendum_coef: 1.0,
            clearance_coef: 0.25,
            tip_radius_coef: 0.38,
        };
        let tol = Tolerances {
            flank_mm: 0.001,
            fillet_mm: 0.005,
            min_radius_mm: 0.005,
        };
        let o = outline(&gear, &tol).unwrap();
        let z = f64::from(o.teeth);
        let f = &o.figures;
        let mut n = 0;
        for i in 0..4000 {
            let polar = TAU * f64::from(i) / 4000.0 - PI;
            for k in 0..=20 {
                let r = f.root_radius_mm - 0.3
                    + (f.tip_radius_mm - f.root_radius_mm + 0.6) * f64::from(k) / 20.0;
                let (d, piece) = o.distance((r * polar.cos(), r * polar.sin()));
                // The fold and each piece, written out.
                let p = (r * polar.cos(), r * polar.sin());
                let fold = (p.1.atan2(p.0) - FRAC_PI_2).rem_euclid(TAU / z) - PI / z;
                let a = FRAC_PI_2 - fold.abs();
                let q = (r * a.cos(), r * a.sin());
                let flank = o.flank.distance(q);
                if piece == Piece::Flank {
                    assert!((d - flank).abs() < 1e-12, "{r} {polar}: {d} vs {flank}");
                    n += 1;
                } else {
                    assert!(d <= flank + 1e-12, "{r} {polar}: {d} vs {flank}");
                }
            }
        }
        assert!(n > 10_000, "{n} points nearest the flank");
    }

    /// The remainder by a fused multiply-add against `rem_euclid`: angles
    /// of every size and sign (whole multiples, their neighbours a unit in
    /// the last place away, zeros of both signs) by the pitches of 5 to
    /// 1000 teeth, to the bit.
    #[test]
    fn the_remainder_is_rem_euclids() {
        let mut seed: u64 = 11;
        let mut rnd = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut n = 0;
        for z in [5.0, 7.0, 20.0, 23.0, 40.0, 97.0, 1000.0] {
            let p = TAU / z;
            let mut xs = vec![0.0, -0.0, p, -p, 2.0 * p, -3.0 * p];
            for k in -40..=40 {
                let m = f64::from(k) * p;
                xs.extend([m, m.next_up(), m.next_down(), m + 0.5 * p]);
            }
            for _ in 0..20_000 {
                xs.push((rnd() - 0.5) * 20.0);
                xs.push((rnd() - 0.5) * 1e-6);
            }
            for x in xs {
                let (a, b) = (rem_euclid(x, p), x.rem_euclid(p));
                assert_eq!(a.to_bits(), b.to_bits(), "{x} by {p}: {a} vs {b}");
                n += 1;
            }
        }
        assert!(n > 200_000);
    }

    /// The nearest piece as first taken: the folded point built, all four
    /// pieces measured (the fillet too), the first of equal minima among
    /// root, flank and tip, the fillet only when strictly nearer.
    fn every_piece(o: &Outline, r: f64, polar: f64) -> (f64, Piece) {
        let z = f64::from(o.teeth);
        let d = (polar - FRAC_PI_2).rem_euclid(TAU / z) - PI / z;
        let a = FRAC_PI_2 - d.abs();
        let q = (r * a.cos(), r * a.sin());
        let circle = |radius: f64, lo: f64, hi: f64, ends: &[(f64, f64); 2]| {
            if (lo..=hi).contains(&a) {
                (r - radius).abs()
            } else {
                let end = |e: &(f64, f64)| ((q.0 - e.0).powi(2) + (q.1 - e.1).powi(2)).sqrt();
                end(&ends[0]).min(end(&ends[1]))
            }
        };
        let f = &o.figures;
        let best = [
            (
                circle(f.root_radius_mm, o.root_from, FRAC_PI_2, &o.root_ends),
                Piece::Root,
            ),
            (o.flank.distance_polar(r, a, || q), Piece::Flank),
            (
                circle(f.tip_radius_mm, FRAC_PI_2 - PI / z, o.tip_to, &o.tip_ends),
                Piece::Tip,
            ),
        ]
        .into_iter()
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .unwrap();
        let fillet = o.fillet.distance(q);
        if fillet < best.0 {
            (fillet, Piece::Fillet)
        } else {
            best
        }
    }

    /// The pieces the distance skips (a circle's arc further than the
    /// nearest so far, the fillet beyond its band) change nothing: on two
    /// gears, at points all round them from inside the root circle to
    /// outside the tip circle, the same distance to the bit and the same
    /// piece as every piece measured.
    #[test]
    fn skipping_far_pieces_changes_nothing() {
        for (m, z, x) in [(2.0, 23, 0.2), (2.0, 40, 0.0), (0.8, 9, 0.5)] {
            let gear = RackGear {
                module_mm: m,
                teeth: z,
                pressure_angle_deg: 20.0,
                profile_shift: x,
                addendum_coef: 1.0,
                clearance_coef: 0.25,
                tip_radius_coef: 0.38,
            };
            let tol = Tolerances {
                flank_mm: 0.001,
                fillet_mm: 0.005,
                min_radius_mm: 0.005,
            };
            let o = outline(&gear, &tol).unwrap();
            let f = o.figures;
            let mut pieces = [0usize; 4];
            for i in 0..3000 {
                let polar = TAU * f64::from(i) / 3000.0 - PI + 1e-4;
                for k in 0..=40 {
                    let r = f.root_radius_mm - 0.2 * m
                        + (f.tip_radius_mm - f.root_radius_mm + 0.4 * m) * f64::from(k) / 40.0;
                    let fast = o.distance_at(r, polar);
                    let all = every_piece(&o, r, polar);
                    assert_eq!(fast.0.to_bits(), all.0.to_bits(), "{r} {polar}");
                    assert_eq!(fast.1, all.1, "{r} {polar}");
                    pieces[fast.1 as usize] += 1;
                }
            }
            // Every piece is the nearest somewhere.
            assert!(pieces.iter().all(|&n| n > 100), "{pieces:?}");
        }
    }
}
