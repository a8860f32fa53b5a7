//! The hob's cutting edges.
//!
//! Each gash is a zero-rake plane containing the hob axis; its cutting edges
//! are the hob thread's axial section in that plane: straight-sided teeth of
//! axial pitch p_x = π·mn0/cos γ0, axial pressure angle
//! tan α_x = tan α0/cos γ0, thickness p_x/2 at the reference radius
//! r0 = z0·mn0/(2·sin γ0), from the tip radius da0/2 down to r0 − h_f0,
//! the tips' corners rounded with the radius r_c of the basic rack's root
//! fillet (a circle of radius r_c in the thread's normal section, whose
//! axial lengths are the normal ones over cos γ0).
//! The thread is body-fixed: a point of the thread at body angle φ has the
//! axial position a = p·φ + j·p_x (j integer), p = s_h·z0·p_x/2π, so a
//! right-handed hob turn moves the thread by −p·dτ along u
//! (`docs/hobbing.md` §2).

use gearcam_proto::{Hand, HobData};

use crate::SimError;

/// Data the hob record does not carry, with defaults.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HobExtras {
    /// Number of gashes (cutting edges around the hob); default 12.
    pub gashes: u32,
    /// Tooth depth below the reference radius, in modules; default 1.25.
    pub dedendum_coef: f64,
    /// Radius of the rounded corners at the tips of the hob's teeth, in
    /// modules, in the thread's normal section; default 0.38, the root
    /// fillet radius ρ_fP of the basic rack profile A of ISO 53:1998
    /// (α 20°, h_aP 1·m, h_fP 1.25·m), which is the tool's tip radius.
    pub tip_corner_coef: f64,
}

impl Default for HobExtras {
    fn default() -> Self {
        HobExtras {
            gashes: 12,
            dedendum_coef: 1.25,
            tip_corner_coef: 0.38,
        }
    }
}

/// The hob as the simulation sees it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hob {
    /// Starts z0.
    pub starts: u32,
    /// Hand sign s_h (+1 right, −1 left).
    pub hand: f64,
    /// Tip radius da0/2, mm.
    pub tip_radius_mm: f64,
    /// Reference radius r0, mm.
    pub ref_radius_mm: f64,
    /// Root radius of the teeth, mm.
    pub root_radius_mm: f64,
    /// Axial pitch p_x, mm.
    pub axial_pitch_mm: f64,
    /// tan of the axial pressure angle.
    pub tan_alpha_x: f64,
    /// Length of the hob, mm (teeth within ±length/2 of its middle).
    pub length_mm: f64,
    /// Number of gashes.
    pub gashes: u32,
    /// Radius of the rounded tip corners in the normal section, mm (0:
    /// sharp corners).
    pub tip_corner_radius_mm: f64,
    /// cos γ0: axial lengths are normal-section lengths over cos γ0.
    pub cos_lead: f64,
}

impl Hob {
    /// The hob of a plan's hob record.
    pub fn from_data(h: &HobData, extras: HobExtras) -> Result<Hob, SimError> {
        if extras.gashes == 0 {
            return Err(SimError::Parameter("gashes", "must be at least 1"));
        }
        if h.starts == 0 || h.module_mm <= 0.0 || h.lead_angle_deg <= 0.0 {
            return Err(SimError::Parameter(
                "hob",
                "needs starts, module and lead angle > 0",
            ));
        }
        let g0 = h.lead_angle_deg.to_radians();
        let r0 = f64::from(h.starts) * h.module_mm / (2.0 * g0.sin());
        let tip_corner_radius_mm = extras.tip_corner_coef * h.module_mm;
        if tip_corner_radius_mm.is_nan() || tip_corner_radius_mm < 0.0 {
            return Err(SimError::Parameter("tip_corner_coef", "must be ≥ 0"));
        }
        let hob = Hob {
            starts: h.starts,
            hand: match h.hand {
                Hand::Right => 1.0,
                Hand::Left => -1.0,
            },
            tip_radius_mm: h.od_mm / 2.0,
            ref_radius_mm: r0,
            root_radius_mm: r0 - extras.dedendum_coef * h.module_mm,
            axial_pitch_mm: std::f64::consts::PI * h.module_mm / g0.cos(),
            tan_alpha_x: h.pressure_angle_deg.to_radians().tan() / g0.cos(),
            length_mm: h.length_mm,
            gashes: extras.gashes,
            tip_corner_radius_mm,
            cos_lead: g0.cos(),
        };
        if hob.corner().is_none() {
            return Err(SimError::Parameter(
                "tip_corner_coef",
                "the corner radius is larger than the tooth tip allows",
            ));
        }
        Ok(hob)
    }

    /// The tip corner's circle in the normal section, measured from the
    /// tooth centre: (x_0, y_0), the distance of its centre along the pitch
    /// line and above the reference radius. It touches the tip line
    /// y = H (H = r_a0 − r0) from below, y_0 = H − r_c, and the flank line
    /// x + y·tan α0 = p_n/4 from inside, so its centre stands r_c from the
    /// flank: (p_n/4 − x_0 − y_0·tan α0)·cos α0 = r_c, x_0 = p_n/4 −
    /// (H − r_c)·tan α0 − r_c/cos α0. None when the two corners of a tooth
    /// would overlap (x_0 < 0) or the circle reaches below the root.
    fn corner(&self) -> Option<(f64, f64)> {
        let rc = self.tip_corner_radius_mm;
        let tan_a = self.tan_alpha_x * self.cos_lead;
        let cos_a = 1.0 / (1.0 + tan_a * tan_a).sqrt();
        let pn = self.axial_pitch_mm * self.cos_lead;
        let big_h = self.tip_radius_mm - self.ref_radius_mm;
        let x0 = pn / 4.0 - (big_h - rc) * tan_a - rc / cos_a;
        let y0 = big_h - rc;
        (x0 >= 0.0 && self.ref_radius_mm + y0 - rc >= self.root_radius_mm).then_some((x0, y0))
    }

    /// Axial advance of the thread per radian of body angle, p, mm/rad.
    pub fn lead_per_rad(&self) -> f64 {
        self.hand * f64::from(self.starts) * self.axial_pitch_mm / std::f64::consts::TAU
    }

    /// Body angle of gash `k`, radians.
    pub fn gash_angle(&self, k: u32) -> f64 {
        std::f64::consts::TAU * f64::from(k) / f64::from(self.gashes)
    }

    /// The axial positions within `a_lo..=a_hi` where gash `k`'s edge
    /// profile changes from one smooth piece to the next: [`Edge::knots`].
    pub fn knots(&self, k: u32, a_lo: f64, a_hi: f64) -> Vec<f64> {
        self.edge(k).knots(a_lo, a_hi)
    }

    /// Outer radius of gash `k`'s edge at axial position `a` (from the
    /// hob's middle, along u): the tip radius on a tooth, down the flank,
    /// the root radius in a gap, and 0 beyond the hob's length.
    pub fn outer_radius(&self, k: u32, a: f64) -> f64 {
        self.edge(k).radius(a)
    }

    /// Gash `k`'s edge profile, with what every evaluation needs worked out
    /// once.
    pub fn edge(&self, k: u32) -> Edge {
        let px = self.axial_pitch_mm;
        let corner = match (self.tip_corner_radius_mm > 0.0, self.corner()) {
            (true, Some((x0, y0))) => {
                let rc = self.tip_corner_radius_mm;
                let tan_a = self.tan_alpha_x * self.cos_lead;
                let cos_a = 1.0 / (1.0 + tan_a * tan_a).sqrt();
                Some(Corner {
                    land_end: x0 / self.cos_lead,
                    arc_end: (x0 + rc * cos_a) / self.cos_lead,
                    x0,
                    centre_radius: self.ref_radius_mm + y0,
                    rc,
                })
            }
            _ => None,
        };
        Edge {
            half_length: self.length_mm / 2.0,
            pitch: px,
            inv_pitch: 1.0 / px,
            centre: self.lead_per_rad() * self.gash_angle(k),
            ref_radius: self.ref_radius_mm,
            inv_tan_alpha: 1.0 / self.tan_alpha_x,
            tip: self.tip_radius_mm,
            root: self.root_radius_mm,
            cos_lead: self.cos_lead,
            corner,
        }
    }
}

/// One gash's edge profile ([`Hob::edge`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Edge {
    half_length: f64,
    pitch: f64,
    inv_pitch: f64,
    /// Axial position of a tooth's centre, mm.
    centre: f64,
    ref_radius: f64,
    inv_tan_alpha: f64,
    tip: f64,
    root: f64,
    cos_lead: f64,
    corner: Option<Corner>,
}

/// A rounded tip corner: where the tip land and the arc end (axial
/// distances from the tooth's centre), and the arc in the normal section.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Corner {
    land_end: f64,
    arc_end: f64,
    /// The arc centre's distance from the tooth's centre in the normal
    /// section, and its radius from the hob axis.
    x0: f64,
    centre_radius: f64,
    rc: f64,
}

impl Edge {
    /// `n` axial positions spread over `lo..hi` (each moved on by
    /// `offset`), less those within 10⁻³ mm of a knot: where a central
    /// difference of the profile stays on one smooth piece (tests).
    #[cfg(test)]
    pub(crate) fn off_knots(&self, lo: f64, hi: f64, n: u32, offset: f64) -> Vec<f64> {
        let knots = self.knots(lo, hi);
        (0..n)
            .map(|i| lo + (hi - lo) * f64::from(i) / f64::from(n) + offset)
            .filter(|a| knots.iter().all(|k| (k - a).abs() >= 1e-3))
            .collect()
    }

    /// The axial positions within `a_lo..=a_hi` where the profile changes
    /// from one smooth piece to the next (tip land, corner arc, flank, root;
    /// the hob's ends), sorted, with `a_lo` and `a_hi`. Between two
    /// neighbours [`Edge::radius`] is a line or one arc.
    pub fn knots(&self, a_lo: f64, a_hi: f64) -> Vec<f64> {
        let mut out = Vec::new();
        self.knots_into(a_lo, a_hi, &mut out);
        out
    }

    /// [`Edge::knots`] into `out` (cleared first), without sorting: the
    /// piece ends of one tooth all lie within half a pitch of its centre
    /// (the bottom of a gap without root land at half a pitch after it), so
    /// the teeth in order, each with its ends from the far left to the far
    /// right, are in order.
    pub fn knots_into(&self, a_lo: f64, a_hi: f64, out: &mut Vec<f64>) {
        out.clear();
        let half = self.half_length;
        let (a_lo, a_hi) = (a_lo.max(-half), a_hi.min(half));
        if a_lo > a_hi {
            return;
        }
        let px = self.pitch;
        let tan_a = 1.0 / self.inv_tan_alpha;
        // Distances from a tooth's centre where a piece ends, in order: the
        // tip land and the corner arc (or the sharp tip), then the flank at
        // the root.
        let root_end = px / 4.0 + (self.ref_radius - self.root) * tan_a;
        let tip_end = px / 4.0 - (self.tip - self.ref_radius) * tan_a;
        let mut buf = [0.0; 3];
        let ends: &mut [f64] = match &self.corner {
            Some(c) => {
                buf = [c.land_end, c.arc_end, root_end];
                &mut buf
            }
            None => {
                buf[..2].copy_from_slice(&[tip_end, root_end]);
                &mut buf[..2]
            }
        };
        // A sharp tooth whose flanks meet below the tip radius comes to a
        // point at its centre; flanks that meet above the root radius make
        // the bottom of the gap half a pitch on.
        let apex = self.corner.is_none() && tip_end <= 0.0;
        let bottom = root_end >= px / 2.0;
        ends.sort_unstable_by(f64::total_cmp);
        let inside = |d: &&f64| **d > 0.0 && **d < px / 2.0;
        let n0 = ((a_lo - self.centre) / px).floor() as i64 - 1;
        let n1 = ((a_hi - self.centre) / px).ceil() as i64 + 1;
        out.push(a_lo);
        let mut push = |a: f64| {
            if a > a_lo && a < a_hi && out.last().is_none_or(|l| a - l >= 1e-12) {
                out.push(a);
            }
        };
        for n in n0..=n1 {
            let c = self.centre + px * n as f64;
            ends.iter().rev().filter(inside).for_each(|d| push(c - d));
            if apex {
                push(c);
            }
            ends.iter().filter(inside).for_each(|d| push(c + d));
            if bottom {
                push(c + px / 2.0);
            }
        }
        if out.last().is_some_and(|l| a_hi - l >= 1e-12) {
            out.push(a_hi);
        }
    }

    /// True when `a` lies on a rounded tip corner's arc (which cuts only the
    /// root fillet of the gear).
    #[inline]
    pub fn on_corner(&self, a: f64) -> bool {
        let Some(c) = &self.corner else {
            return false;
        };
        let d = self.off_centre(a);
        d > c.land_end && d < c.arc_end
    }

    /// The distance of `a` from the nearest tooth centre, 0..pitch/2.
    #[inline]
    fn off_centre(&self, a: f64) -> f64 {
        let u = (a - self.centre) * self.inv_pitch;
        // floor(u) by truncation (a call to floor is slower on a baseline
        // x86-64 target); |u| is a few hundred pitches at most.
        let t = u as i64 as f64;
        let frac = u - if t > u { t - 1.0 } else { t };
        self.pitch * frac.min(1.0 - frac)
    }

    /// dρ/da of [`Edge::radius`] at `a` on the side `dir` (+1: towards
    /// larger a, −1: smaller), taken just inside the piece there, so at a
    /// knot it is the slope of the piece on that side.
    pub fn slope(&self, a: f64, dir: f64) -> f64 {
        let a = a + dir * 1e-9;
        if a.abs() > self.half_length {
            return 0.0;
        }
        let u = (a - self.centre) * self.inv_pitch;
        let frac = u - u.floor();
        // d grows away from the nearest tooth centre.
        let (d, dd) = if frac <= 0.5 {
            (self.pitch * frac, 1.0)
        } else {
            (self.pitch * (1.0 - frac), -1.0)
        };
        if let Some(c) = &self.corner {
            if d <= c.land_end {
                return 0.0;
            }
            if d <= c.arc_end {
                let dx = d * self.cos_lead - c.x0;
                let root = (c.rc * c.rc - dx * dx).max(1e-30).sqrt();
                return -dx * self.cos_lead / root * dd;
            }
        }
        let rho = self.ref_radius + (self.pitch / 4.0 - d) * self.inv_tan_alpha;
        if rho >= self.tip || rho <= self.root {
            0.0
        } else {
            -self.inv_tan_alpha * dd
        }
    }

    /// Outer radius at axial position `a`: [`Hob::outer_radius`].
    #[inline]
    pub fn radius(&self, a: f64) -> f64 {
        if a.abs() > self.half_length {
            return 0.0;
        }
        let d = self.off_centre(a);
        if let Some(c) = &self.corner {
            // In the normal section (axial lengths times cos γ0): past the
            // tip land, down the corner's arc to where it touches the flank.
            if d <= c.land_end {
                return self.tip;
            }
            if d <= c.arc_end {
                let dx = d * self.cos_lead - c.x0;
                return c.centre_radius + (c.rc * c.rc - dx * dx).max(0.0).sqrt();
            }
        }
        let rho = self.ref_radius + (self.pitch / 4.0 - d) * self.inv_tan_alpha;
        rho.clamp(self.root, self.tip)
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A one-start hob of 80 mm with 12 gashes and sharp tips, module 3.
    pub(crate) fn hob() -> Hob {
        Hob {
            starts: 1,
            hand: 1.0,
            tip_radius_mm: 40.0,
            ref_radius_mm: 36.25,
            root_radius_mm: 32.5,
            axial_pitch_mm: 9.43,
            tan_alpha_x: 20f64.to_radians().tan(),
            length_mm: 100.0,
            gashes: 12,
            tip_corner_radius_mm: 0.0,
            cos_lead: 1.0,
        }
    }

    /// The knots come out in order without a sort: exactly what sorting
    /// every tooth's piece ends over the interval gives, for sharp, rounded
    /// and pointed teeth and gaps without root land, every gash, and
    /// intervals from none to many teeth wide; and the radius has a kink
    /// (a jump of its slope) only at a knot.
    #[test]
    fn the_knots_come_in_order_and_are_where_the_pieces_change() {
        let base = hob();
        let hobs = [
            base,
            Hob {
                tip_corner_radius_mm: 0.6,
                ..base
            },
            Hob {
                tip_corner_radius_mm: 1.2,
                ..base
            },
            // Flanks that meet below the tip radius, and above the root.
            Hob {
                tip_radius_mm: 43.25,
                ..base
            },
            Hob {
                root_radius_mm: 29.25,
                ..base
            },
        ];
        let (mut compared, mut kinks) = (0, 0);
        for h in &hobs {
            for k in 0..h.gashes {
                let e = h.edge(k);
                for i in 0..200 {
                    let lo = -60.0 + 0.537 * f64::from(i);
                    let hi = lo + 0.291 * f64::from(i % 37);
                    let got = e.knots(lo, hi);
                    assert_eq!(got, sorted_knots(&e, lo, hi), "{lo}..{hi}, gash {k}");
                    compared += got.len();
                }
                let all = e.knots(-50.0, 50.0);
                let step = 1e-3;
                for j in 0..100_000 {
                    let a = -49.9 + step * f64::from(j);
                    let jump = (e.slope(a + step, -1.0) - e.slope(a, 1.0)).abs();
                    if jump > 100.0 * step {
                        assert!(
                            all.iter().any(|&kn| kn >= a && kn <= a + step),
                            "a kink within {a}..{} that is no knot",
                            a + step
                        );
                        kinks += 1;
                    }
                }
            }
        }
        assert!(
            compared > 40_000 && kinks > 1000,
            "{compared} knots, {kinks} kinks"
        );
    }

    /// Every tooth's piece ends over `lo..hi`, the ends of the interval,
    /// sorted, each kept once (within 10⁻¹²).
    fn sorted_knots(e: &Edge, lo: f64, hi: f64) -> Vec<f64> {
        let (lo, hi) = (lo.max(-e.half_length), hi.min(e.half_length));
        if lo > hi {
            return vec![];
        }
        let tan_a = 1.0 / e.inv_tan_alpha;
        let mut ends: Vec<f64> = match &e.corner {
            Some(c) => vec![c.land_end, c.arc_end],
            None => vec![e.pitch / 4.0 - (e.tip - e.ref_radius) * tan_a],
        };
        ends.push(e.pitch / 4.0 + (e.ref_radius - e.root) * tan_a);
        let apex = e.corner.is_none() && ends[0] <= 0.0;
        let bottom = ends[ends.len() - 1] >= e.pitch / 2.0;
        let mut out = vec![lo, hi];
        for n in -40..=40 {
            let c = e.centre + e.pitch * f64::from(n);
            for &d in ends.iter().filter(|&&d| d > 0.0 && d < e.pitch / 2.0) {
                out.extend([c - d, c + d]);
            }
            out.extend(apex.then_some(c));
            out.extend(bottom.then_some(c + e.pitch / 2.0));
        }
        let mut out: Vec<f64> = out
            .into_iter()
            .enumerate()
            .filter(|&(i, a)| i < 2 || (a > lo && a < hi))
            .map(|(_, a)| a)
            .collect();
        out.sort_by(f64::total_cmp);
        out.dedup_by(|a, b| (*a - *b).abs() < 1e-12);
        out
    }

    /// The slope is the radius's derivative on every piece (a central
    /// difference away from the knots), with a rounded and a sharp tip.
    #[test]
    fn the_slope_is_the_derivative_of_the_radius() {
        for corner in [0.0, 1.0] {
            let h = Hob {
                tip_corner_radius_mm: corner,
                ..hob()
            };
            let e = h.edge(0);
            let mut checked = 0;
            for a in e.off_knots(-20.0, 20.0, 4000, 1e-3) {
                let d = 1e-6;
                let fd = (e.radius(a + d) - e.radius(a - d)) / (2.0 * d);
                for dir in [1.0, -1.0] {
                    assert!(
                        (e.slope(a, dir) - fd).abs() < 1e-4,
                        "a {a}: {} vs {fd}",
                        e.slope(a, dir)
                    );
                }
                checked += 1;
            }
            assert!(checked > 3000);
        }
    }

    #[test]
    fn the_tooth_is_half_a_pitch_thick_at_the_reference_radius() {
        let h = hob();
        let hw = h.axial_pitch_mm / 4.0;
        assert!((h.outer_radius(0, hw) - h.ref_radius_mm).abs() < 1e-9);
        assert!((h.outer_radius(0, -hw) - h.ref_radius_mm).abs() < 1e-9);
        assert_eq!(h.outer_radius(0, 0.0), h.tip_radius_mm);
        assert_eq!(h.outer_radius(0, h.axial_pitch_mm / 2.0), h.root_radius_mm);
        assert_eq!(h.outer_radius(0, 60.0), 0.0);
    }

    /// A hob of module 10 with the ISO 53 profile A corner (r_c 3.8 mm):
    /// the rounded profile keeps r_c·(1/sin((90° + α)/2) − 1) away from the
    /// sharp corner's vertex (the corner's interior angle is 90° + α0, and a
    /// circle tangent to both sides of an angle 2β stands r_c/sin β from
    /// its vertex), meets the tip land and the flank without a step, and is
    /// the sharp profile away from the corner.
    #[test]
    fn the_tip_corner_is_rounded_with_the_basic_rack_radius() {
        let alpha = 20f64.to_radians();
        let sharp = Hob {
            starts: 1,
            hand: 1.0,
            tip_radius_mm: 512.5,
            ref_radius_mm: 500.0,
            root_radius_mm: 487.5,
            axial_pitch_mm: std::f64::consts::PI * 10.0,
            tan_alpha_x: alpha.tan(),
            length_mm: 100.0,
            gashes: 12,
            tip_corner_radius_mm: 0.0,
            cos_lead: 1.0,
        };
        let round = Hob {
            tip_corner_radius_mm: 3.8,
            ..sharp
        };
        assert!(round.corner().is_some());
        // The vertex: the flank meets the tip line at x = p/4 − H·tan α.
        let h = 12.5;
        let xv = sharp.axial_pitch_mm / 4.0 - h * alpha.tan();
        let mut nearest = f64::MAX;
        let n = 20_000;
        for i in 0..=n {
            let x = xv - 3.0 + 6.0 * f64::from(i) / f64::from(n);
            let y = round.outer_radius(0, x) - 500.0;
            nearest = nearest.min(((x - xv).powi(2) + (y - h).powi(2)).sqrt());
            // No step anywhere: neighbouring samples 0.3 µm apart.
            let y2 = round.outer_radius(0, x + 3e-4) - 500.0;
            assert!((y2 - y).abs() < 1e-3, "step at {x}");
        }
        let want = 3.8 * (1.0 / ((std::f64::consts::FRAC_PI_2 + alpha) / 2.0).sin() - 1.0);
        assert!((nearest - want).abs() < 1e-6, "{nearest} vs {want}");
        for x in [0.0, 0.5, xv + 4.0, 7.0, sharp.axial_pitch_mm / 2.0] {
            if (x - xv).abs() > 3.5 {
                assert_eq!(round.outer_radius(0, x), sharp.outer_radius(0, x), "x {x}");
            }
        }
    }

    #[test]
    fn the_next_gash_finds_the_thread_a_twelfth_of_the_lead_on() {
        let h = hob();
        let step = h.axial_pitch_mm / 12.0;
        for a in [-3.0, -1.0, 0.5, 2.0] {
            assert!((h.outer_radius(1, a + step) - h.outer_radius(0, a)).abs() < 1e-9);
        }
    }
}
