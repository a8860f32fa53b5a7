//! The hob's tip cylinder against a solid of revolution about the table axis,
//! along one move, by sampling with a certified step.
//!
//! The hob is the solid cylinder of radius r = da0/2 over its length L
//! around its axis u, its middle at (X, 0, Z) + Y·u. Its surface (the
//! lateral surface and both end discs) is sampled at spacing at most h along
//! u and along every circle (radial rings h apart on the end discs), so every
//! surface point is within h of a sample. An obstacle is a cylinder about
//! the table axis (radius R, heights z_lo..z_hi, either end possibly
//! infinite); its signed distance, negative inside, is exact:
//! d = max(ρ − R, z_lo − z, z − z_hi) inside, √(max(ρ − R, 0)² +
//! max(z_lo − z, z − z_hi, 0)²) outside, ρ = √(x² + y²). A conical blank's
//! frustum (radius R(z) = R + k·(z − z_lo) between finite ends) is a
//! trapezoid in the (ρ, z) half-plane, and a point's nearest point of a
//! solid of revolution lies in its own half-plane: inside, the distance is
//! the nearest of the three edges' lines, (ρ − R(z))/√(1 + k²) for the
//! slanted one; outside, the nearest of the three edges.
//!
//! A signed distance is 1-Lipschitz, so at one pose the hob's surface is at
//! least d_min − h from the obstacle (d_min the samples' least). Within a
//! move the hob translates (the tilt η stands); moving on by δ of the
//! centre moves every hob point by δ (plus twice the runouts, which turn with
//! B and C). The walk along the move takes the next pose δ = d_min − h on,
//! at least h: every penetration deeper than 2·h + twice the runouts is
//! found (a sample stands inside), and a pose found inside is a real contact.
//! A first bound from the hob's circumscribed sphere (radius √(r² + L²/4))
//! skips the sampling far from the obstacle. The obstacle inside the hob
//! without meeting its surface (a thin obstacle through the hob's bore) is
//! not looked for.

use crate::kinematics::{Pose, Timeline};

/// A solid of revolution about the table axis: radius and heights, mm.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cylinder {
    /// Radius, mm.
    pub radius_mm: f64,
    /// Lower end, mm (may be −∞).
    pub z_lo_mm: f64,
    /// Upper end, mm (may be +∞).
    pub z_hi_mm: f64,
    /// Radius change per mm up from `radius_mm` at `z_lo_mm` (a cone's
    /// frustum; both ends finite), 0 for a cylinder.
    pub taper: f64,
}

impl Cylinder {
    /// Signed distance from (x, y, z), negative inside.
    pub fn signed_distance(&self, p: [f64; 3]) -> f64 {
        // Square roots rather than `hypot`: these lengths are millimetres,
        // far from overflow, and the check runs at every sample of every move.
        let rho = (p[0] * p[0] + p[1] * p[1]).sqrt();
        if self.taper != 0.0 {
            return self.frustum_distance(rho, p[2]);
        }
        let dr = rho - self.radius_mm;
        let dz = (self.z_lo_mm - p[2]).max(p[2] - self.z_hi_mm);
        if dr <= 0.0 && dz <= 0.0 {
            dr.max(dz)
        } else {
            let (r, z) = (dr.max(0.0), dz.max(0.0));
            (r * r + z * z).sqrt()
        }
    }

    /// The signed distance of the frustum from the point at radius `rho`
    /// and height `z`.
    fn frustum_distance(&self, rho: f64, z: f64) -> f64 {
        let (lo, hi) = (self.z_lo_mm, self.z_hi_mm);
        let r_lo = self.radius_mm;
        let r_hi = r_lo + self.taper * (hi - lo);
        let side = (rho - r_lo - self.taper * (z - lo)) / self.taper.hypot(1.0);
        let dz = (lo - z).max(z - hi);
        if side <= 0.0 && dz <= 0.0 {
            return side.max(dz);
        }
        // The distance from (rho, z) to the edge from a to b.
        let edge = |a: (f64, f64), b: (f64, f64)| {
            let (ex, ey) = (b.0 - a.0, b.1 - a.1);
            let (px, py) = (rho - a.0, z - a.1);
            let t = ((px * ex + py * ey) / (ex * ex + ey * ey)).clamp(0.0, 1.0);
            (px - t * ex).hypot(py - t * ey)
        };
        edge((0.0, lo), (r_lo, lo))
            .min(edge((r_lo, lo), (r_hi, hi)))
            .min(edge((0.0, hi), (r_hi, hi)))
    }
}

/// Sample spacing on the hob's surface, mm.
pub const SAMPLE_MM: f64 = 0.5;

/// The hob as sampled: tip radius and length, mm.
#[derive(Debug, Clone, Copy)]
pub(super) struct HobSolid {
    pub(super) radius_mm: f64,
    pub(super) length_mm: f64,
}

/// The deepest contact found along a move: depth (mm) and time (s).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Contact {
    pub(super) depth_mm: f64,
    pub(super) t_s: f64,
    pub(super) pose: Pose,
}

/// The hob's middle and its frame (u, e1, w) at a pose.
fn frame(p: &Pose) -> ([f64; 3], [f64; 3], [f64; 3], [f64; 3]) {
    let (se, ce) = p.eta_rad.sin_cos();
    let u = [0.0, ce, -se];
    let e1 = [-1.0, 0.0, 0.0];
    let w = [0.0, se, ce];
    let y = p.axes.y_mm;
    let c = [p.axes.x_mm, y * u[1], p.axes.z_mm + y * u[2]];
    (c, u, e1, w)
}

/// The least signed distance over the samples of the hob's surface at `pose`.
fn least_distance(hob: HobSolid, pose: &Pose, ob: &Cylinder) -> f64 {
    let (c, u, e1, w) = frame(pose);
    let r = hob.radius_mm;
    let half = hob.length_mm / 2.0;
    let n_phi = ((std::f64::consts::TAU * r / SAMPLE_MM).ceil() as usize).max(8);
    let n_a = ((hob.length_mm / SAMPLE_MM).ceil() as usize).max(1);
    let n_rho = ((r / SAMPLE_MM).ceil() as usize).max(1);
    let point = |a: f64, rho: f64, (s, co): (f64, f64)| {
        let k = |i: usize| c[i] + a * u[i] + rho * (co * e1[i] + s * w[i]);
        [k(0), k(1), k(2)]
    };
    let mut least = f64::INFINITY;
    for j in 0..n_phi {
        let sc = (std::f64::consts::TAU * j as f64 / n_phi as f64).sin_cos();
        for i in 0..=n_a {
            let a = -half + hob.length_mm * i as f64 / n_a as f64;
            least = least.min(ob.signed_distance(point(a, r, sc)));
        }
        for k in 0..n_rho {
            let rho = r * k as f64 / n_rho as f64;
            for a in [-half, half] {
                least = least.min(ob.signed_distance(point(a, rho, sc)));
            }
        }
    }
    least
}

/// The deepest sampled contact of the hob with `ob` along segment `seg`,
/// if any sample stands deeper than `tol_mm` inside.
pub(super) fn along(
    tl: &Timeline,
    seg: usize,
    hob: HobSolid,
    ob: &Cylinder,
    tol_mm: f64,
) -> Option<Contact> {
    let s = &tl.segments()[seg];
    let e = tl.errors();
    let wobble = 2.0 * (e.hob_radial_mm.abs() + e.hob_axial_mm.abs() + e.table_mm.abs());
    let sphere = hob.radius_mm.hypot(hob.length_mm / 2.0);
    let (c0, ..) = frame(&tl.nominal_pose_in(seg, s.t0_s));
    let (c1, ..) = frame(&tl.nominal_pose_in(seg, s.t1_s));
    let travel =
        ((c1[0] - c0[0]).powi(2) + (c1[1] - c0[1]).powi(2) + (c1[2] - c0[2]).powi(2)).sqrt();
    let dur = s.t1_s - s.t0_s;
    let mut deepest: Option<Contact> = None;
    let mut f = 0.0f64;
    loop {
        let t = s.t0_s + f * dur;
        let pose = tl.pose_in(seg, t);
        let (c, ..) = frame(&pose);
        let far = ob.signed_distance(c) - sphere - wobble;
        let clear = if far > SAMPLE_MM {
            far
        } else {
            let d = least_distance(hob, &pose, ob);
            if d < -tol_mm && deepest.is_none_or(|x| -d > x.depth_mm) {
                deepest = Some(Contact {
                    depth_mm: -d,
                    t_s: t,
                    pose,
                });
            }
            d - SAMPLE_MM - wobble
        };
        if f >= 1.0 || travel <= 0.0 || dur <= 0.0 {
            break;
        }
        f = (f + clear.max(SAMPLE_MM) / travel).min(1.0);
    }
    deepest
}
