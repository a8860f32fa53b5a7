//! The approach clearance ΔH′ of the finite hob over the blank (docs/hobbing.md):
//! the hob's frame in the gear's, the scan with edge bisection, and the
//! clearance at each face of a unit.

use super::*;

/// The homogeneous transform from the hob frame (Xd, Yd, Zd; Yd the hob
/// axis, tilted by γ against the gear end face) to the gear frame (Xg, Yg,
/// Zg; Zg the gear axis), with the hob centre at (L, 0, Z0) (the patent's):
///
/// ```text
/// ⎡Xg⎤   ⎡−1    0      0    L ⎤ ⎡Xd⎤
/// ⎢Yg⎥ = ⎢ 0  cos γ  sin γ  0 ⎥ ⎢Yd⎥
/// ⎢Zg⎥   ⎢ 0 −sin γ  cos γ  Z0⎥ ⎢Zd⎥
/// ⎣1 ⎦   ⎣ 0    0      0    1 ⎦ ⎣1 ⎦
/// ```
pub fn hob_to_gear(swivel_deg: f64, centre_distance_mm: f64, hob_height_mm: f64) -> Matrix4<f64> {
    let (s, c) = swivel_deg.to_radians().sin_cos();
    #[rustfmt::skip]
    let m = Matrix4::new(
        -1.0, 0.0, 0.0, centre_distance_mm,
        0.0, c, s, 0.0,
        0.0, -s, c, hob_height_mm,
        0.0, 0.0, 0.0, 1.0,
    );
    m
}

/// The approach-clearance problem: how far the tilted hob reaches below its
/// centre over the blank when it stands at its final centre distance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Clearance {
    /// Blank outside diameter Da1 at the face the hob approaches, mm (R = Da1/2).
    pub blank_od_mm: f64,
    /// Hob outside diameter da0, mm (r = da0/2).
    pub hob_od_mm: f64,
    /// Radial depth h, mm (L = R + r − h).
    pub depth_mm: f64,
    /// Hob swivel, degrees; only its magnitude γ = |η| matters (a tilt either
    /// way is the mirror image: the reach moves to the other side of the blank).
    pub swivel_deg: f64,
    /// Hob length, mm: hob points lie within ±length/2 of the centre along
    /// its axis.
    pub hob_length_mm: f64,
}

/// The solution of a [`Clearance`] problem.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClearanceSolution {
    /// ΔH′, the largest reach below the hob centre over the blank disc, mm
    /// (no safety distance).
    pub clearance_mm: f64,
    /// The hob-frame x of the lowest point, mm.
    pub x_mm: f64,
    /// The hob-axial coordinate y of the lowest point, mm.
    pub hob_axial_mm: f64,
    /// True when no point of the hob's tip cylinder lies over the blank disc,
    /// so the unbounded maximum was taken (the larger, safe value).
    pub length_bound_ignored: bool,
}

impl Clearance {
    fn radii(&self) -> (f64, f64, f64) {
        let big_r = self.blank_od_mm / 2.0;
        let r = self.hob_od_mm / 2.0;
        (big_r, r, big_r + r - self.depth_mm)
    }

    /// Final centre distance L = R + r − h, mm.
    pub fn centre_distance_mm(&self) -> f64 {
        self.radii().2
    }

    /// The interval (L − R, r) of x, clipped to where both roots are real.
    pub fn domain(&self) -> (f64, f64) {
        let (big_r, r, l) = self.radii();
        ((l - big_r).max(-r), r.min(l + big_r))
    }

    /// (√(r² − x²), √(R² − (L − x)²)): the depth of the hob's tip cylinder
    /// below its axis at x, and the half chord of the blank disc there.
    fn roots(&self, x: f64) -> (f64, f64) {
        let (big_r, r, l) = self.radii();
        (
            (r * r - x * x).max(0.0).sqrt(),
            (big_r * big_r - (l - x) * (l - x)).max(0.0).sqrt(),
        )
    }

    /// ΔH(x) = √(r² − x²)/cos γ + √(R² − (L − x)²)·tan γ, mm: the reach of an
    /// unbounded hob at x. (The patent prints the factor cos γ − tan γ·sin γ
    /// = cos 2γ/cos γ instead of 1/cos γ, too small for every γ > 0.)
    ///
    /// Derivation: a tip-cylinder point (x, y, −s), s = √(r² − x²), lies
    /// s·cos γ + y·sin γ below the hob centre and over the blank at gear
    /// Yg = y·cos γ − s·sin γ; the reach grows with y, so the lowest point
    /// over the disc (|Yg| ≤ w) has Yg = w.
    pub fn delta_h(&self, x: f64) -> f64 {
        let g = self.swivel_deg.abs().to_radians();
        let (s, w) = self.roots(x);
        s / g.cos() + w * g.tan()
    }

    /// Hob-axial coordinate y = (√(R² − (L − x)²) + √(r² − x²)·sin γ)/cos γ of
    /// the unbounded hob's lowest point at x, mm.
    pub fn hob_axial_mm(&self, x: f64) -> f64 {
        let g = self.swivel_deg.abs().to_radians();
        let (s, w) = self.roots(x);
        (w + s * g.sin()) / g.cos()
    }

    /// The reach at x of the hob of finite length, with the hob-axial y of
    /// its lowest point over the disc; `None` when no point of the hob at x
    /// lies over the blank disc.
    pub fn reach_at(&self, x: f64) -> Option<(f64, f64)> {
        let (big_r, _, l) = self.radii();
        if (l - x).abs() > big_r {
            return None;
        }
        let g = self.swivel_deg.abs().to_radians();
        let (sin_g, cos_g) = g.sin_cos();
        let (s, w) = self.roots(x);
        let half = self.hob_length_mm / 2.0;
        let y_hi = ((w + s * sin_g) / cos_g).min(half);
        let y_lo = ((-w + s * sin_g) / cos_g).max(-half);
        (y_hi >= y_lo).then_some((y_hi * sin_g + s * cos_g, y_hi))
    }

    /// The contact point at x in gear coordinates (hob centre at height 0).
    pub fn contact_in_gear_frame(&self, x: f64) -> Vector4<f64> {
        let (_, r, l) = self.radii();
        let z = -(r * r - x * x).max(0.0).sqrt();
        let y = self.hob_axial_mm(x);
        hob_to_gear(self.swivel_deg.abs(), l, 0.0) * Vector4::new(x, y, z, 1.0)
    }

    /// ΔH′ = the largest [`Self::reach_at`] over the domain: a dense scan of
    /// [`CLEARANCE_SAMPLES`] points (end points included), golden-section
    /// refinement around the best sample, and the edges of the window where
    /// the hob lies over the disc found by bisection (the maximum may sit
    /// on one). When no point of the hob lies over the disc, the unbounded
    /// maximum of [`Self::delta_h`] is taken (never smaller, so safe).
    pub fn solve(&self) -> ClearanceSolution {
        let (lo, hi) = self.domain();
        if hi.partial_cmp(&lo) != Some(std::cmp::Ordering::Greater) {
            // No overlap of hob and blank (h ≤ 0): nothing to clear.
            return ClearanceSolution {
                clearance_mm: 0.0,
                x_mm: hi,
                hob_axial_mm: 0.0,
                length_bound_ignored: false,
            };
        }
        let bounded = |x: f64| self.reach_at(x).map_or(f64::NEG_INFINITY, |v| v.0);
        let mut best = self.maximise(lo, hi, &bounded);
        if best.1 == f64::NEG_INFINITY {
            let free = |x: f64| self.delta_h(x);
            let best = self.maximise(lo, hi, &free);
            return ClearanceSolution {
                clearance_mm: best.1,
                x_mm: best.0,
                hob_axial_mm: self.hob_axial_mm(best.0),
                length_bound_ignored: true,
            };
        }
        let inside = |x: f64| self.reach_at(x).is_some();
        let n = CLEARANCE_SAMPLES;
        let step = (hi - lo) / (n - 1) as f64;
        let at = |i: usize| if i == n - 1 { hi } else { lo + step * i as f64 };
        let mut was = inside(lo);
        for i in 1..n {
            let now = inside(at(i));
            if now != was {
                let (mut a, mut b) = if was {
                    (at(i - 1), at(i))
                } else {
                    (at(i), at(i - 1))
                };
                // a is inside, b outside.
                for _ in 0..60 {
                    let m = (a + b) / 2.0;
                    if inside(m) {
                        a = m;
                    } else {
                        b = m;
                    }
                }
                let v = bounded(a);
                if v > best.1 {
                    best = (a, v);
                }
            }
            was = now;
        }
        ClearanceSolution {
            clearance_mm: best.1,
            x_mm: best.0,
            hob_axial_mm: self.reach_at(best.0).map_or(0.0, |v| v.1),
            length_bound_ignored: false,
        }
    }

    /// Dense scan then golden section; returns (argmax, max).
    fn maximise(&self, lo: f64, hi: f64, f: &dyn Fn(f64) -> f64) -> (f64, f64) {
        let n = CLEARANCE_SAMPLES;
        let step = (hi - lo) / (n - 1) as f64;
        let at = |i: usize| if i == n - 1 { hi } else { lo + step * i as f64 };
        let (mut best_i, mut best) = (0, f(lo));
        for i in 1..n {
            let v = f(at(i));
            if v > best {
                best_i = i;
                best = v;
            }
        }
        if best == f64::NEG_INFINITY {
            return (lo, best);
        }
        let mut a = at(best_i.saturating_sub(1));
        let mut b = at((best_i + 1).min(n - 1));
        let inv_phi = (5f64.sqrt() - 1.0) / 2.0;
        let mut c = b - inv_phi * (b - a);
        let mut d = a + inv_phi * (b - a);
        let (mut fc, mut fd) = (f(c), f(d));
        for _ in 0..80 {
            if b - a <= 1e-12 * (1.0 + hi.abs()) {
                break;
            }
            if fc >= fd {
                b = d;
                d = c;
                fd = fc;
                c = b - inv_phi * (b - a);
                fc = f(c);
            } else {
                a = c;
                c = d;
                fc = fd;
                d = a + inv_phi * (b - a);
                fd = f(d);
            }
        }
        let x_mid = (a + b) / 2.0;
        let (x_best, v_best) =
            [(x_mid, f(x_mid)), (c, fc), (d, fd)]
                .into_iter()
                .fold(
                    (at(best_i), best),
                    |acc, p| if p.1 > acc.1 { p } else { acc },
                );
        (x_best, v_best)
    }
}

/// The blank diameter the hob meets at one face (top or bottom): a
/// cylinder's everywhere; a cone's is smaller by 2·b·tan δ at its small end.
/// The depth there is [`face_clearance`]'s.
pub(super) fn end_blank_od(u: &Unit, blank_od_mm: f64, top: bool) -> f64 {
    match (u.class, u.gear.cone.as_ref()) {
        (GearClass::Conical, Some(cone)) => {
            let large_on_top = cone.large_end == gearcam_proto::LargeEnd::Top;
            if large_on_top == top {
                blank_od_mm
            } else {
                blank_od_mm - 2.0 * u.gear.face_width_mm * cone.angle_deg.to_radians().tan()
            }
        }
        _ => blank_od_mm,
    }
}

/// ΔH′ at one face (top or bottom) of a unit's blank: a cone's at that
/// face's own blank radius (the end the hob approaches may be the small one)
/// and at the depth the hob stands at where it leaves or meets the cone line
/// beyond that face: at the small end the line runs on ra0·sin δ, deeper by
/// that times tan δ, and stands r0·(1/cos δ − 1) further out everywhere
/// ([`crate::path::cone_offsets`]); at the large end the lift alone, which
/// leaves the hob shallower, is not taken off.
pub(super) fn face_clearance(u: &Unit, eta: f64, blank: f64, depth: f64, top: bool) -> f64 {
    let deeper = match (u.class, u.gear.cone.as_ref()) {
        (GearClass::Conical, Some(cone))
            if (cone.large_end == gearcam_proto::LargeEnd::Top) != top =>
        {
            let (lift, overtravel) =
                crate::path::cone_offsets(cone.angle_deg, super::hob_radii(u.hob));
            overtravel * cone.angle_deg.to_radians().tan() - lift
        }
        _ => 0.0,
    };
    Clearance {
        blank_od_mm: end_blank_od(u, blank, top),
        hob_od_mm: u.hob.od_mm,
        depth_mm: depth + deeper,
        swivel_deg: eta,
        hob_length_mm: u.hob.length_mm,
    }
    .solve()
    .clearance_mm
}
