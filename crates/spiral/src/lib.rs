//! Spiral face milling, the pure model (seed 001; docs/spiral.md): a
//! circular face (inner radius 0), an annular face, or a planar spiral
//! groove, milled along an Archimedean spiral of the tool centre.
//!
//! The tool centre follows, in polar coordinates about the face's centre,
//!
//! ```text
//! R(θ) = R1 + (R2 − R1)·(θ − θ0) / (360°·n)      θ from θ0 to θ0 + 360°·n
//! ```
//!
//! from radius R1 to R2 in n turns, so each turn moves the tool by the
//! step-over L = |R2 − R1| / n. This crate decides R1, R2 and n from the
//! region, the tool and the overtravels ([`plan`]), and gives what the
//! programs and their checks need: the path length in closed form
//! ([`Spiral::length`]), the chords within a tolerance ([`Spiral::chords`])
//! and the proof in closed form that every point of the region lies under
//! the tool somewhere along the path ([`prove_coverage`]), held in the tests
//! to the sampled check ([`coverage`]).
//!
//! Lengths are mm, angles degrees at the interface (radians inside).
//!
//! # Layout
//!
//! - this file: the plan, the spiral, its length, chords and their measured
//!   deviation;
//! - `coverage`: the coverage proof and the sampled check;
//! - `near`: the nearest point of the spiral by Newton's method, for the
//!   arc fit and the chords' measure;
//! - [`arcs`]: tangent arcs within the tolerance; [`groove`]: the planar
//!   spiral groove;
//! - [`fanuc`], [`linuxcnc`]: the programs; [`macrob`] (with
//!   `macrob_expr`): the Macro B and LinuxCNC subset replay; [`verify`]: a
//!   program checked against the model; [`picture`]: the SVG.
#![forbid(unsafe_code)]

pub mod arcs;
mod coverage;
pub mod fanuc;
pub mod groove;
pub mod linuxcnc;
pub mod macrob;
mod macrob_expr;
mod near;
pub mod picture;
pub mod verify;

use gearcam_proto::Code;
use gearcam_proto::Problem;
use serde::{Deserialize, Serialize};

pub use coverage::{coverage, prove_coverage, Coverage, CoverageProof, Zone};

/// The face to mill: a circle (`inner_radius_mm` = 0) or an annulus.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Region {
    /// Outer radius Ro, mm.
    pub outer_radius_mm: f64,
    /// Inner radius Ri, mm (0: a full circle).
    pub inner_radius_mm: f64,
}

/// Which way the spiral runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Direction {
    /// From outside the face inwards: the tool enters the material
    /// gradually from outside (the seed's way).
    OutsideIn,
    /// From the inner edge outwards.
    InsideOut,
}

/// What the spiral is asked to do.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SpiralSpec {
    /// The face.
    pub region: Region,
    /// Tool radius rt, mm.
    pub tool_radius_mm: f64,
    /// Largest step-over between turns, mm (the turns are rounded up, so
    /// the step-over used is at most this).
    pub step_over_mm: f64,
    /// Outer overtravel: the tool centre starts (or ends) this far beyond
    /// Ro + rt, so the tool enters the material gradually from outside, mm.
    pub outer_overtravel_mm: f64,
    /// Inner overtravel: how far past the inner edge the tool goes, so no
    /// ring is left at the inner edge, mm. On a full circle the spiral stops
    /// when the tool covers the centre (centre radius rt − this).
    pub inner_overtravel_mm: f64,
    /// Polar angle θ0 of the start point, degrees.
    pub start_angle_deg: f64,
    /// Outside-in or inside-out.
    pub direction: Direction,
}

/// The tool-centre spiral: R(θ) from R1 at θ0 to R2 after `turns` turns.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Spiral {
    /// R1, the centre's start radius, mm.
    pub start_radius_mm: f64,
    /// R2, the centre's end radius, mm.
    pub end_radius_mm: f64,
    /// θ0, degrees.
    pub start_angle_deg: f64,
    /// n, turns (a whole number, ≥ 1).
    pub turns: u32,
    /// The direction of rotation as seen from +Z: +1 counter-clockwise, −1 clockwise.
    pub sense: i8,
}

/// The spiral for `spec`, or every input error found (typed, naming the
/// field, the expected and the given value).
///
/// Outside-in, counter-clockwise from +Z (the rotation sense is the
/// machine's choice of climb or conventional milling; [`Spiral::sense`]):
/// R1 = Ro + rt + outer overtravel (the tool starts clear of the face),
/// R2 = max(Ri + rt − L − inner overtravel, 0): the spiral is a step-over
/// further out one turn before its end, so this is the largest end radius
/// that leaves no ring at the inner edge (on a full circle, Ri = 0, no
/// centre island and no useless path around the centre). Inside-out starts
/// in the hole, R1 = Ri − rt − inner overtravel (the tool plunges clear of
/// the material; a hole too small for that is refused), and ends at
/// Ro + rt + outer overtravel. n = ⌈|R1 − R2| / L⌉.
pub fn plan(spec: &SpiralSpec) -> Result<Spiral, Vec<Problem>> {
    let mut errors = face_and_tool_errors(spec);
    errors.extend(milling_errors(spec));
    if !errors.is_empty() {
        return Err(errors);
    }
    let (r1, r2) = centre_radii(spec)?;
    let l = spec.step_over_mm;
    let turns = ((r1 - r2).abs() / l - 1e-9).ceil().max(1.0) as u32;
    Ok(Spiral {
        start_radius_mm: r1,
        end_radius_mm: r2,
        start_angle_deg: spec.start_angle_deg,
        turns,
        sense: 1,
    })
}

/// A finite number above zero.
fn positive(v: f64) -> bool {
    v.is_finite() && v > 0.0
}

/// The face and the tool checked: a positive outer radius, an inner radius
/// of 0 (a full circle) or below the outer, a positive tool radius no
/// larger than the face.
fn face_and_tool_errors(spec: &SpiralSpec) -> Vec<Problem> {
    let mut errors = Vec::new();
    let Region {
        outer_radius_mm: ro,
        inner_radius_mm: ri,
    } = spec.region;
    let rt = spec.tool_radius_mm;
    if !positive(ro) {
        errors.push(Problem::new(
            Code::SPIRAL_RANGE,
            "face.outer_radius_mm",
            "a radius > 0 mm",
            format!("{ro}"),
            "the face's outer radius must be positive",
        ));
    }
    if !(ri.is_finite() && ri >= 0.0) {
        errors.push(Problem::new(
            Code::SPIRAL_RANGE,
            "face.inner_radius_mm",
            "0 (a full circle) or a radius > 0 mm",
            format!("{ri}"),
            "the inner radius is 0 for a full circle",
        ));
    } else if positive(ro) && ri >= ro {
        errors.push(Problem::new(
            Code::SPIRAL_RANGE,
            "face.inner_radius_mm",
            format!("less than the outer radius {ro} mm"),
            format!("{ri}"),
            "an annulus's inner radius is below its outer radius",
        ));
    }
    if !positive(rt) {
        errors.push(Problem::new(
            Code::SPIRAL_RANGE,
            "mill.radius_mm",
            "a radius > 0 mm",
            format!("{rt}"),
            "the tool's radius must be positive",
        ));
    } else if positive(ro) && rt > ro {
        errors.push(Problem::new(
            Code::SPIRAL_RANGE,
            "mill.radius_mm",
            format!("at most the face's outer radius {ro} mm"),
            format!("{rt}"),
            "a tool larger than the face: mill it in one plunge, not with a spiral",
        ));
    }
    errors
}

/// The milling data checked: a positive step-over below the tool's
/// diameter, overtravels of 0 mm or more, a finite start angle.
fn milling_errors(spec: &SpiralSpec) -> Vec<Problem> {
    let mut errors = Vec::new();
    let rt = spec.tool_radius_mm;
    let l = spec.step_over_mm;
    if !positive(l) {
        errors.push(Problem::new(
            Code::SPIRAL_RANGE,
            "milling.step_over_mm",
            "a step-over > 0 mm",
            format!("{l}"),
            "the step-over sets the number of turns; it must be positive",
        ));
    } else if positive(rt) && l >= 2.0 * rt {
        errors.push(Problem::new(
            Code::SPIRAL_RANGE,
            "milling.step_over_mm",
            format!("less than the tool's diameter {} mm", 2.0 * rt),
            format!("{l}"),
            "a step-over of the tool's diameter or more leaves material between the turns",
        ));
    }
    for (v, field) in [
        (spec.outer_overtravel_mm, "milling.outer_overtravel_mm"),
        (spec.inner_overtravel_mm, "milling.inner_overtravel_mm"),
    ] {
        if !(v.is_finite() && v >= 0.0) {
            errors.push(Problem::new(
                Code::SPIRAL_RANGE,
                field,
                "0 mm or more",
                format!("{v}"),
                "an overtravel is a distance",
            ));
        }
    }
    if !spec.start_angle_deg.is_finite() {
        errors.push(Problem::new(
            Code::SPIRAL_RANGE,
            "milling.start_angle_deg",
            "an angle in degrees",
            format!("{}", spec.start_angle_deg),
            "the start angle must be a number",
        ));
    }
    errors
}

/// R1 and R2 of a checked spec, in the direction it runs: the outer radius
/// clear of the face and the largest inner radius that leaves no ring; a
/// spiral without length, or an inside-out spiral whose hole has no room
/// to plunge, is refused.
fn centre_radii(spec: &SpiralSpec) -> Result<(f64, f64), Vec<Problem>> {
    let Region {
        outer_radius_mm: ro,
        inner_radius_mm: ri,
    } = spec.region;
    let rt = spec.tool_radius_mm;
    let l = spec.step_over_mm;
    let outer = ro + rt + spec.outer_overtravel_mm;
    // A spiral reaches its end radius only at its end angle: one turn
    // earlier it is a step-over further out. So the inner edge is covered
    // all around only if R2 + L − rt ≤ Ri, i.e. R2 ≤ Ri + rt − L; the inner
    // overtravel is a margin beyond that. On a full circle (Ri = 0) the same
    // rule keeps the last turn within rt of the centre.
    let inner = (ri + rt - l - spec.inner_overtravel_mm).max(0.0);
    if outer - inner <= 0.0 {
        return Err(vec![Problem::new(
            Code::SPIRAL_RANGE,
            "mill.radius_mm",
            "a tool that leaves room for a spiral",
            format!("{rt}"),
            "the spiral has no length",
        )]);
    }
    match spec.direction {
        Direction::OutsideIn => Ok((outer, inner)),
        Direction::InsideOut => {
            // The tool plunges in the hole, clear of the material, as
            // outside-in it plunges clear of the outer edge: its centre
            // rt plus the inner overtravel inside the inner edge. A hole
            // smaller than that leaves no place to plunge.
            let start = ri - rt - spec.inner_overtravel_mm;
            if start < 0.0 {
                return Err(vec![Problem::new(
                    Code::SPIRAL_RANGE,
                    "milling.direction",
                    format!(
                        "outside-in, or inside-out on a hole of radius at least the tool's radius plus the inner overtravel, {} mm",
                        rt + spec.inner_overtravel_mm
                    ),
                    format!("inside-out with an inner radius of {ri} mm"),
                    "inside-out the tool plunges in the hole; in a smaller hole it would plunge into the face's material",
                )]);
            }
            Ok((start, outer))
        }
    }
}

impl Spiral {
    /// The step-over used, |R2 − R1| / n, mm.
    pub fn step_over_mm(&self) -> f64 {
        (self.end_radius_mm - self.start_radius_mm).abs() / f64::from(self.turns)
    }

    /// Total sweep, radians.
    fn sweep(&self) -> f64 {
        std::f64::consts::TAU * f64::from(self.turns)
    }

    /// dR/dφ (φ in radians from θ0), mm per radian.
    fn b(&self) -> f64 {
        (self.end_radius_mm - self.start_radius_mm) / self.sweep()
    }

    /// The centre's radius after turning `phi` radians from θ0.
    pub fn radius_at(&self, phi: f64) -> f64 {
        self.start_radius_mm + self.b() * phi
    }

    /// The centre's point after turning `phi` radians from θ0, mm.
    pub fn point_at(&self, phi: f64) -> (f64, f64) {
        let r = self.radius_at(phi);
        let a = self.start_angle_deg.to_radians() + f64::from(self.sense) * phi;
        (r * a.cos(), r * a.sin())
    }

    /// Arc length of the centre path in closed form, mm: with r = a + bφ,
    /// ds = √(r² + b²) dφ, and ∫√(r² + b²) dr / b =
    /// [r·√(r² + b²) + b²·ln(r + √(r² + b²))] / (2b).
    pub fn length(&self) -> f64 {
        let b = self.b();
        if b.abs() < 1e-15 {
            return self.start_radius_mm * self.sweep();
        }
        let f = |r: f64| {
            let h = (r * r + b * b).sqrt();
            (r * h + b * b * (r + h).ln()) / (2.0 * b)
        };
        (f(self.end_radius_mm) - f(self.start_radius_mm)).abs()
    }

    /// The chord points of the path, with a constant angle step small enough
    /// that no chord strays more than `tolerance_mm` from the spiral at its
    /// largest radius (sagitta r·(1 − cos(Δφ/2)) ≤ tolerance; the spiral's
    /// own curvature is within 0.1 % of a circle's here). Returns the angle
    /// step (degrees) and the points, the first at θ0 and the last at the end.
    pub fn chords(&self, tolerance_mm: f64) -> (f64, Vec<(f64, f64)>) {
        let n = self.chord_count(tolerance_mm);
        let dphi = self.sweep() / n as f64;
        let points = (0..=n).map(|i| self.point_at(dphi * i as f64)).collect();
        (dphi.to_degrees(), points)
    }

    /// How far the spiral strays from its chords at `tolerance_mm`, at
    /// most, mm: a proven bound for the coverage proof, where the chords'
    /// rule takes a circle's sagitta. Between a chord's ends at φi and
    /// φi + Δφ the error e(φ) = S(φ) − (the chord's point at the same
    /// share) vanishes at both ends and has e″ = S″, so
    /// |e(φ)| ≤ max|S″|·Δφ²/8 (linear interpolation's error, the Green's
    /// function of e″ having the integral (φ − φi)(φi + Δφ − φ)/2); with
    /// S = r·(cos a, sin a), S″ = 2b·sense·n − r·u (u radial, n normal to
    /// it), |S″| = √(r² + 4b²), largest at the largest radius.
    pub fn chord_stray_mm(&self, tolerance_mm: f64) -> f64 {
        let dphi = self.sweep() / self.chord_count(tolerance_mm) as f64;
        let r_max = self.start_radius_mm.max(self.end_radius_mm);
        let b = self.b();
        dphi * dphi / 8.0 * (r_max * r_max + 4.0 * b * b).sqrt()
    }

    /// How many chords [`Spiral::chords`] takes at `tolerance_mm`.
    pub fn chord_count(&self, tolerance_mm: f64) -> usize {
        let r_max = self.start_radius_mm.max(self.end_radius_mm);
        let step = 2.0 * (1.0 - tolerance_mm / r_max).clamp(-1.0, 1.0).acos();
        (self.sweep() / step).ceil().max(1.0) as usize
    }
}

/// The largest distance of the chords from the true spiral, mm, measured
/// densely: every chord sampled at 15 points between its ends, each
/// against the spiral between the chord's ends (the nearest spiral point
/// by Newton's method from the spiral's point at the same share, which is
/// within a micro-radian of it on chords this short): an independent check
/// of [`Spiral::chords`]' tolerance, which takes the sagitta of a circle.
pub fn chord_deviation(spiral: &Spiral, points: &[(f64, f64)]) -> f64 {
    let n = points.len().saturating_sub(1).max(1);
    let dphi = spiral.sweep() / n as f64;
    let frame = near::Frame::of(spiral);
    let step = (frame.sense * dphi / 16.0).sin_cos();
    let mut worst: f64 = 0.0;
    for (i, w) in points.windows(2).enumerate() {
        let (lo, hi) = (dphi * i as f64, dphi * (i + 1) as f64);
        let (s0, c0) = frame.angle(lo).sin_cos();
        let mut cs = (c0, s0);
        for k in 1..16 {
            let t = k as f64 / 16.0;
            cs = near::turned(cs, step);
            let (x, y) = (
                w[0].0 + t * (w[1].0 - w[0].0),
                w[0].1 + t * (w[1].1 - w[0].1),
            );
            let guess = lo + dphi * t;
            worst = worst.max(frame.nearest((x, y), guess, cs, lo, hi));
        }
    }
    worst
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec(ro: f64, ri: f64, rt: f64, step: f64) -> SpiralSpec {
        SpiralSpec {
            region: Region {
                outer_radius_mm: ro,
                inner_radius_mm: ri,
            },
            tool_radius_mm: rt,
            step_over_mm: step,
            outer_overtravel_mm: 2.0,
            inner_overtravel_mm: 1.0,
            start_angle_deg: 0.0,
            direction: Direction::OutsideIn,
        }
    }

    #[test]
    fn the_spiral_starts_clear_of_the_face_and_ends_past_the_inner_edge() {
        let s = plan(&spec(100.0, 20.0, 10.0, 15.0)).unwrap();
        assert_eq!(s.start_radius_mm, 112.0); // Ro + rt + outer overtravel
        assert_eq!(s.end_radius_mm, 14.0); // Ri + rt − L − inner overtravel
        assert_eq!(s.turns, 7); // ⌈98 / 15⌉
        assert!(s.step_over_mm() <= 15.0);
        let c = plan(&spec(100.0, 0.0, 10.0, 6.0)).unwrap();
        assert_eq!(c.end_radius_mm, 3.0); // rt − L − 1: the last turn stays within rt of the centre
        let inside_out = plan(&SpiralSpec {
            direction: Direction::InsideOut,
            ..spec(100.0, 20.0, 10.0, 15.0)
        })
        .unwrap();
        // Ri − rt − inner overtravel: the tool plunges in the hole.
        assert_eq!(
            (inside_out.start_radius_mm, inside_out.end_radius_mm),
            (9.0, 112.0)
        );
        assert_eq!(inside_out.turns, 7); // ⌈103 / 15⌉
                                         // A hole smaller than the tool leaves no place to plunge.
        let e = plan(&SpiralSpec {
            direction: Direction::InsideOut,
            ..spec(100.0, 10.0, 10.0, 15.0)
        })
        .unwrap_err();
        assert_eq!(e[0].field, "milling.direction");
    }

    #[test]
    fn bad_input_is_refused_on_its_field() {
        let fields = |s: SpiralSpec| -> Vec<String> {
            plan(&s)
                .unwrap_err()
                .iter()
                .map(|e| e.field.clone())
                .collect()
        };
        assert_eq!(fields(spec(50.0, 50.0, 5.0, 5.0)), ["face.inner_radius_mm"]);
        assert_eq!(fields(spec(50.0, 0.0, 5.0, 10.0)), ["milling.step_over_mm"]);
        assert_eq!(fields(spec(50.0, 0.0, 60.0, 5.0)), ["mill.radius_mm"]);
        assert_eq!(fields(spec(50.0, 0.0, 5.0, 0.0)), ["milling.step_over_mm"]);
        let e = &plan(&spec(50.0, 0.0, 5.0, 12.0)).unwrap_err()[0];
        assert_eq!(
            (e.code.as_str(), e.expected.as_str(), e.got.as_str()),
            ("SPIRAL_RANGE", "less than the tool's diameter 10 mm", "12")
        );
    }

    /// The closed-form length against a numeric sum of the chords at 0.1 µm.
    #[test]
    fn the_length_in_closed_form_matches_a_dense_sum() {
        for s in [
            spec(100.0, 20.0, 10.0, 15.0),
            spec(100.0, 0.0, 8.0, 6.0),
            spec(30.0, 5.0, 3.0, 1.0),
        ] {
            let spiral = plan(&s).unwrap();
            let (_, pts) = spiral.chords(1e-4);
            let sum: f64 = pts
                .windows(2)
                .map(|w| ((w[1].0 - w[0].0).powi(2) + (w[1].1 - w[0].1).powi(2)).sqrt())
                .sum();
            assert!(
                (spiral.length() - sum).abs() / sum < 1e-6,
                "{} vs {sum}",
                spiral.length()
            );
        }
    }

    /// Seed 001's comparison (docs/spiral.md): radius 20 → 100 mm with a 10 mm
    /// step-over needs about 1,907 chords at 5 µm and 4,264 at 1 µm.
    #[test]
    fn chords_within_the_tolerance_and_the_published_counts() {
        let spiral = Spiral {
            start_radius_mm: 100.0,
            end_radius_mm: 20.0,
            start_angle_deg: 0.0,
            turns: 8,
            sense: 1,
        };
        for (tol, expected) in [(0.005, 1907.0), (0.001, 4264.0)] {
            let (_, pts) = spiral.chords(tol);
            let n = (pts.len() - 1) as f64;
            // A constant angle step for the largest radius: a few % more
            // chords than a step that grows as the radius falls.
            assert!(n >= expected && n < expected * 1.9, "{tol}: {n} chords");
            let dev = chord_deviation(&spiral, &pts);
            assert!(dev <= tol * 1.001, "{tol}: deviation {dev}");
        }
    }

    /// The chords' proven stray against the spiral's points' distance
    /// from the chords, measured: 31 points of the spiral between each
    /// chord's ends, each against that chord and its neighbours. The bound
    /// holds and is within 1 % of the measure.
    #[test]
    fn the_chords_stray_bounds_the_spirals_distance_from_them() {
        for (spiral, tol) in [
            (
                Spiral {
                    start_radius_mm: 110.0,
                    end_radius_mm: 0.0,
                    start_angle_deg: 0.0,
                    turns: 10,
                    sense: 1,
                },
                0.001,
            ),
            (
                Spiral {
                    start_radius_mm: 20.4,
                    end_radius_mm: 0.0,
                    start_angle_deg: 30.0,
                    turns: 2,
                    sense: -1,
                },
                0.005,
            ),
        ] {
            let (_, pts) = spiral.chords(tol);
            let n = pts.len() - 1;
            let dphi = spiral.sweep() / n as f64;
            let seg = |i: usize, p: (f64, f64)| {
                let (a, b) = (pts[i], pts[i + 1]);
                let (dx, dy) = (b.0 - a.0, b.1 - a.1);
                let t =
                    (((p.0 - a.0) * dx + (p.1 - a.1) * dy) / (dx * dx + dy * dy)).clamp(0.0, 1.0);
                (a.0 + t * dx - p.0).hypot(a.1 + t * dy - p.1)
            };
            let mut worst: f64 = 0.0;
            for i in 0..n {
                for k in 1..32 {
                    let p = spiral.point_at(dphi * (i as f64 + k as f64 / 32.0));
                    let d = (i.saturating_sub(1)..(i + 2).min(n))
                        .map(|j| seg(j, p))
                        .fold(f64::INFINITY, f64::min);
                    worst = worst.max(d);
                }
            }
            let bound = spiral.chord_stray_mm(tol);
            assert!(
                worst <= bound && bound <= 1.01 * worst,
                "{worst} vs {bound}"
            );
        }
    }

    #[test]
    fn the_coverage_check_proves_a_face_and_finds_a_ring() {
        let region = Region {
            outer_radius_mm: 60.0,
            inner_radius_mm: 15.0,
        };
        let spiral = plan(&spec(60.0, 15.0, 8.0, 12.0)).unwrap();
        let (_, pts) = spiral.chords(0.005);
        let c = coverage(&region, 8.0, &pts, 0.5);
        assert!(c.ok, "{c:?}");
        // A full circle too: no island at the centre.
        let disc = Region {
            outer_radius_mm: 60.0,
            inner_radius_mm: 0.0,
        };
        let (_, pts) = plan(&spec(60.0, 0.0, 8.0, 12.0)).unwrap().chords(0.005);
        let c = coverage(&disc, 8.0, &pts, 0.5);
        assert!(c.ok, "{c:?}");
        // A step-over wider than the tool leaves a ring between the turns:
        // the check finds it (the planner refuses it; built by hand here).
        let wide = Spiral { turns: 3, ..spiral };
        assert!(wide.step_over_mm() > 16.0);
        let (_, pts) = wide.chords(0.005);
        let c = coverage(&region, 8.0, &pts, 0.5);
        assert!(!c.ok && c.max_gap_mm > 1.0, "{c:?}");
        // Ending where the tool's edge just reaches the inner edge (the
        // naive end, Ri + rt) leaves a crescent there: one turn before its
        // end the spiral is a step-over further out.
        let short = Spiral {
            end_radius_mm: 15.0 + 8.0,
            ..spiral
        };
        let (_, pts) = short.chords(0.005);
        let c = coverage(&region, 8.0, &pts, 0.5);
        assert!(!c.ok, "{c:?}");
        let (x, y) = c.worst_point;
        assert!(((x * x + y * y).sqrt() - 15.0).abs() < 3.1, "{c:?}");
    }
}
