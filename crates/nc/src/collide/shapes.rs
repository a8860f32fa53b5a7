//! The solids of the clearance check, each given by its support function,
//! and their level sets.
//!
//! The signed depth of a point in a convex solid K is φ_K(p) = dist(p, ∂K)
//! inside and −dist(p, K) outside (minus the signed distance function). Its
//! level set {φ_K ≥ s} is K shrunk by s for s ≥ 0 (the inner parallel body)
//! and K grown by a ball of radius −s for s < 0; the check finds the deepest
//! point of one solid in the other by asking for which levels a level set
//! still meets the other solid (`super::depth`). The level sets of both
//! solids here are again solids of the same kind, with closed-form supports:
//!
//! - **The hob's tip cylinder** (radius r, half length h, axis u): inside,
//!   the nearest boundary point lies on the mantle or on an end face, so
//!   φ = min(r − w, h − |a|) with a the axial and w the radial coordinate,
//!   and {φ ≥ s} is the cylinder of radius r − s and half length h − s.
//! - **A frustum about the table axis z** (radius R(z) linear from r_lo at
//!   z_lo to r_hi at z_hi, slope k): a solid of revolution, so the nearest
//!   boundary point of an inside point lies in its own meridian half-plane,
//!   where the section is a convex quadrilateral whose axis edge is not
//!   boundary; the distance to the boundary is the least distance to the
//!   other three edges' lines, φ = min((R(z) − ρ)·cos α, z − z_lo,
//!   z_hi − z) with cos α = 1/√(1 + k²), and {φ ≥ s} is the frustum
//!   z_lo + s ≤ z ≤ z_hi − s, ρ ≤ R(z) − s·√(1 + k²) (ending in an apex
//!   where that radius reaches 0).
//! - **Half-infinite cylinders** (table, tailstock) are cut to a finite
//!   frustum for each sweep ([`Solid::finite_for`]) without changing φ on the
//!   sweep or the distance to it.

use super::P3;

/// A convex set given by its support function.
pub(crate) trait Support {
    /// A point x of the set that maximises n·x, with the sweep parameter
    /// τ ∈ [0, 1] of the pose it belongs to (0 for a set that does not move).
    fn support(&self, n: &P3) -> (P3, f64);
    /// A point of the set.
    fn inner(&self) -> P3;
}

/// The hob's tip cylinder (possibly shrunk to a level) swept along a straight
/// move: the points c0 + τ·d + a·u + w with τ ∈ [0, 1], |a| ≤ half, w ⊥ u,
/// |w| ≤ r. With a constant tilt the hob is a rigid translate of one
/// cylinder along the move, so this is the whole swept solid (the Minkowski
/// sum of the cylinder and the segment), and convex.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Sweep {
    /// Centre at the start of the move.
    pub(crate) start: P3,
    /// Travel of the centre along the move.
    pub(crate) travel: P3,
    /// Unit axis.
    pub(crate) axis: P3,
    /// Radius.
    pub(crate) r: f64,
    /// Half length.
    pub(crate) half: f64,
}

impl Sweep {
    /// The level set {φ ≥ s}, s ≥ 0, of every pose: the cylinder shrunk by
    /// s, or `None` when nothing of it is that deep.
    pub(crate) fn level(&self, s: f64) -> Option<Sweep> {
        let (r, half) = (self.r - s, self.half - s);
        (r >= 0.0 && half >= 0.0).then_some(Sweep { r, half, ..*self })
    }

    /// How far the cylinder reaches below (and above) its centre along z.
    fn z_reach(&self) -> f64 {
        let uz = self.axis[2].abs().min(1.0);
        self.half * uz + self.r * (1.0 - uz * uz).sqrt()
    }

    /// Lowest and highest z of the swept solid.
    pub(crate) fn z_range(&self) -> (f64, f64) {
        let (a, b) = (self.start[2], self.start[2] + self.travel[2]);
        let reach = self.z_reach();
        (a.min(b) - reach, a.max(b) + reach)
    }

    /// The signed depth φ of a point in the cylinder at sweep parameter τ
    /// (the module's formula; outside, minus the distance to the cylinder:
    /// the nearest point lies in the point's plane through the axis, on the
    /// rectangle |a| ≤ half, w ≤ r of that section).
    pub(crate) fn depth_at(&self, tau: f64, q: &P3) -> f64 {
        let v = q - (self.start + self.travel * tau);
        let a = v.dot(&self.axis).abs();
        let w = (v - self.axis * v.dot(&self.axis)).norm();
        if a <= self.half && w <= self.r {
            (self.r - w).min(self.half - a)
        } else {
            -(w - self.r).max(0.0).hypot((a - self.half).max(0.0))
        }
    }
}

impl Support for Sweep {
    fn support(&self, n: &P3) -> (P3, f64) {
        let along = n.dot(&self.axis);
        // Twice: for n nearly along the axis the first difference keeps a
        // rounding residue along the axis as large as itself, which would
        // put the rim point off the end face.
        let radial = n - self.axis * along;
        let radial = radial - self.axis * radial.dot(&self.axis);
        let norm = radial.norm();
        let mut p = self.start + self.axis * (self.half * along.signum());
        if norm > 1e-300 {
            p += radial * (self.r / norm);
        }
        if n.dot(&self.travel) > 0.0 {
            (p + self.travel, 1.0)
        } else {
            (p, 0.0)
        }
    }

    fn inner(&self) -> P3 {
        self.start + self.travel * 0.5
    }
}

/// A finite frustum about the z axis, grown by a ball of radius `grow`:
/// the convex hull of its two end discs, plus the ball.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Frustum {
    pub(crate) z_lo: f64,
    pub(crate) z_hi: f64,
    pub(crate) r_lo: f64,
    pub(crate) r_hi: f64,
    pub(crate) grow: f64,
}

impl Frustum {
    /// The level set {φ ≥ s} (see the module's derivation), or `None` when
    /// nothing of the frustum is that deep.
    pub(crate) fn level(&self, s: f64) -> Option<Frustum> {
        if s < 0.0 {
            return Some(Frustum { grow: -s, ..*self });
        }
        let height = self.z_hi - self.z_lo;
        let k = if height > 0.0 {
            (self.r_hi - self.r_lo) / height
        } else {
            0.0
        };
        let inset = s * (1.0 + k * k).sqrt();
        let (mut z_lo, mut z_hi) = (self.z_lo + s, self.z_hi - s);
        if z_lo > z_hi {
            return None;
        }
        let mut r_lo = self.r_lo + k * s - inset;
        let mut r_hi = self.r_hi - k * s - inset;
        if r_lo < 0.0 && r_hi < 0.0 {
            return None;
        }
        // The radius is linear in z: where it passes 0, the level set ends in
        // an apex (k ≠ 0 there, since the radii differ in sign).
        if r_lo < 0.0 {
            z_lo -= r_lo / k;
            r_lo = 0.0;
        } else if r_hi < 0.0 {
            z_hi -= r_hi / k;
            r_hi = 0.0;
        }
        Some(Frustum {
            z_lo,
            z_hi,
            r_lo,
            r_hi,
            grow: 0.0,
        })
    }
}

impl Frustum {
    /// The signed depth φ of a point in the frustum (`grow` aside): inside,
    /// the module's formula; outside, minus the distance, found in the
    /// point's meridian half-plane as the distance to the section's three
    /// edges other than the axis (the nearest point of a convex polygon from
    /// outside lies on its boundary, and never inside the axis edge for a
    /// point with ρ ≥ 0).
    pub(crate) fn depth_of(&self, p: &P3) -> f64 {
        let rho = p[0].hypot(p[1]);
        let z = p[2];
        let height = self.z_hi - self.z_lo;
        let k = if height > 0.0 {
            (self.r_hi - self.r_lo) / height
        } else {
            0.0
        };
        let radius = self.r_lo + k * (z - self.z_lo);
        if z >= self.z_lo && z <= self.z_hi && rho <= radius {
            return ((radius - rho) / (1.0 + k * k).sqrt())
                .min(z - self.z_lo)
                .min(self.z_hi - z);
        }
        let q = (rho, z);
        let lo = (0.0, self.z_lo);
        let rim_lo = (self.r_lo, self.z_lo);
        let rim_hi = (self.r_hi, self.z_hi);
        let hi = (0.0, self.z_hi);
        -segment_distance(q, lo, rim_lo)
            .min(segment_distance(q, rim_lo, rim_hi))
            .min(segment_distance(q, rim_hi, hi))
    }
}

/// Distance from a point to a segment in the plane.
fn segment_distance(q: (f64, f64), a: (f64, f64), b: (f64, f64)) -> f64 {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let len2 = dx * dx + dy * dy;
    let t = if len2 > 0.0 {
        (((q.0 - a.0) * dx + (q.1 - a.1) * dy) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (q.0 - a.0 - t * dx).hypot(q.1 - a.1 - t * dy)
}

impl Support for Frustum {
    fn support(&self, n: &P3) -> (P3, f64) {
        let m = n[0].hypot(n[1]);
        let (cx, cy) = if m > 1e-300 {
            (n[0] / m, n[1] / m)
        } else {
            (0.0, 0.0)
        };
        let (z, r) = if m * self.r_hi + n[2] * self.z_hi >= m * self.r_lo + n[2] * self.z_lo {
            (self.z_hi, self.r_hi)
        } else {
            (self.z_lo, self.r_lo)
        };
        let mut p = P3::new(cx * r, cy * r, z);
        if self.grow > 0.0 {
            let len = n.norm();
            if len > 1e-300 {
                p += n * (self.grow / len);
            }
        }
        (p, 0.0)
    }

    fn inner(&self) -> P3 {
        P3::new(0.0, 0.0, 0.5 * (self.z_lo + self.z_hi))
    }
}

/// An obstacle: the solid of revolution about the table axis with radius
/// varying linearly from `r_lo` at `z_lo` to `r_hi` at `z_hi`; `z_lo` may be
/// −∞ and `z_hi` +∞ (then the radius is constant).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Solid {
    /// Lower face, mm (−∞: none).
    pub z_lo: f64,
    /// Upper face, mm (+∞: none).
    pub z_hi: f64,
    /// Radius at the lower face, mm.
    pub r_lo: f64,
    /// Radius at the upper face, mm.
    pub r_hi: f64,
}

impl Solid {
    /// The solid cut to a finite frustum for a sweep whose z range is
    /// [z_min, z_max]. An infinite lower face goes to
    /// z′ = z_min − R_max − 1 (or lower): every point of the solid is at
    /// most R_max deep, so for every point p of the sweep the new face's term
    /// p_z − z′ > R_max never is the least of φ's terms, and φ on the sweep
    /// does not change; a point of the solid below z′ has a nearer point
    /// straight above it on the new face for every point of the sweep, so no
    /// distance to the sweep changes either. The upper face likewise.
    pub(crate) fn finite_for(&self, z_min: f64, z_max: f64) -> Frustum {
        let reach = self.r_lo.max(self.r_hi) + 1.0;
        let z_lo = if self.z_lo.is_finite() {
            self.z_lo
        } else {
            (z_min - reach).min(self.z_hi - 1.0)
        };
        let z_hi = if self.z_hi.is_finite() {
            self.z_hi
        } else {
            (z_max + reach).max(z_lo + 1.0)
        };
        Frustum {
            z_lo,
            z_hi,
            r_lo: self.r_lo,
            r_hi: self.r_hi,
            grow: 0.0,
        }
    }
}

/// An upper bound of φ of a frustum over a sweep whose z range is
/// [z_min, z_max]: φ is the least of its terms, so it is at most the largest
/// value of each term over the sweep, z_hi − z_min, z_max − z_lo and R_max
/// for the mantle's term, and at most half the height (the lesser of the
/// two faces' terms).
pub(crate) fn depth_bound(f: &Frustum, z_min: f64, z_max: f64) -> f64 {
    (f.z_hi - z_min)
        .min(z_max - f.z_lo)
        .min(f.r_lo.max(f.r_hi))
        .min(0.5 * (f.z_hi - f.z_lo))
}
