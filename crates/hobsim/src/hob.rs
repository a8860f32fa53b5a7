//! The hob's cutting edges.
//!
//! Each gash is a zero-rake plane containing the hob axis; its cutting edges
//! are the hob thread's axial section in that plane: straight-sided teeth of
//! axial pitch p_x = π·mn0/cos γ0, axial pressure angle
//! tan α_x = tan α0/cos γ0, thickness p_x/2 at the reference radius
//! r0 = z0·mn0/(2·sin γ0), from the tip radius da0/2 down to r0 − h_f0.
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
}

impl Default for HobExtras {
    fn default() -> Self {
        HobExtras {
            gashes: 12,
            dedendum_coef: 1.25,
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
        Ok(Hob {
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
        })
    }

    /// Axial advance of the thread per radian of body angle, p, mm/rad.
    pub fn lead_per_rad(&self) -> f64 {
        self.hand * f64::from(self.starts) * self.axial_pitch_mm / std::f64::consts::TAU
    }

    /// Body angle of gash `k`, radians.
    pub fn gash_angle(&self, k: u32) -> f64 {
        std::f64::consts::TAU * f64::from(k) / f64::from(self.gashes)
    }

    /// Outer radius of gash `k`'s edge at axial position `a` (from the
    /// hob's middle, along u): the tip radius on a tooth, down the flank,
    /// the root radius in a gap, and 0 beyond the hob's length.
    pub fn outer_radius(&self, k: u32, a: f64) -> f64 {
        if a.abs() > self.length_mm / 2.0 {
            return 0.0;
        }
        let px = self.axial_pitch_mm;
        let centre = self.lead_per_rad() * self.gash_angle(k);
        let d = (a - centre).rem_euclid(px);
        let d = d.min(px - d);
        let rho = self.ref_radius_mm + (px / 4.0 - d) / self.tan_alpha_x;
        rho.clamp(self.root_radius_mm, self.tip_radius_mm)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn hob() -> Hob {
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

    #[test]
    fn the_next_gash_finds_the_thread_a_twelfth_of_the_lead_on() {
        let h = hob();
        let step = h.axial_pitch_mm / 12.0;
        for a in [-3.0, -1.0, 0.5, 2.0] {
            assert!((h.outer_radius(1, a + step) - h.outer_radius(0, a)).abs() < 1e-9);
        }
    }
}
