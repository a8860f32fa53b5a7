//! What-if machine errors: offsets and runouts laid over the programmed pose.
//!
//! Every error is a rigid displacement of the hob relative to the workpiece,
//! written in the pose's own coordinates (X, Y along u, Z, η). The pose can
//! hold any translation of the hob: the machine's ŷ lies in the plane of u
//! and ẑ, ŷ = (u + sin η·ẑ)/cos η, and w = u × e1 = (0, sin η, cos η) is
//! w = tan η·u + ẑ/cos η (check: tan η·(0, cos η, −sin η) + (0, 0, 1/cos η)
//! = (0, sin η, cos η)). So a translation d of the hob centre becomes
//! ΔX = d·x̂, and its ŷ and w parts become ΔY (along u) and ΔZ as above.
//! (A translation along u is a Y shift: the hob body moves along its axis.)
//! `docs/simulation.md` §7 writes the models down.

use super::Pose;

/// Machine errors for a what-if run; all zero by default (the ideal machine).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct MachineErrors {
    /// Centre-distance offset, mm, added to X.
    pub centre_distance_mm: f64,
    /// Swivel offset, degrees, added to η.
    pub swivel_deg: f64,
    /// Radial runout of the hob, mm: the hob's axis stands this far off the
    /// spindle axis, in a direction fixed in the hob, so the hob centre is
    /// displaced by e_r·(cos(B + φ_r)·e1 + sin(B + φ_r)·w) (once per turn).
    pub hob_radial_mm: f64,
    /// Phase φ_r of the radial runout, degrees (from e1, right-handed about u).
    pub hob_radial_phase_deg: f64,
    /// Axial runout of the hob, mm: the hob moves along u by
    /// e_a·cos(B + φ_a) (once per turn).
    pub hob_axial_mm: f64,
    /// Phase φ_a of the axial runout, degrees.
    pub hob_axial_phase_deg: f64,
    /// Table runout, mm: the workpiece axis stands this far off the table
    /// axis, at workpiece angle φ_t, and turns with C.
    pub table_mm: f64,
    /// Workpiece angle φ_t of the table runout, degrees.
    pub table_phase_deg: f64,
}

impl MachineErrors {
    /// True when every error is zero.
    pub fn is_zero(&self) -> bool {
        *self == MachineErrors::default()
    }

    /// The pose `p` of the ideal machine on a machine with these errors.
    ///
    /// - η += swivel offset, X += centre-distance offset (the swivel turns
    ///   the head about the swivel axis through the hob centre at Y 0, so a
    ///   shifted hob's middle swings with it).
    /// - Hob radial runout: the eccentric hob turns about the spindle axis;
    ///   a body point p_b is at c + R_u(B)·(e_off + p_b), that is
    ///   c + R_u(B)·e_off plus R_u(B)·p_b: the ideal hob translated by
    ///   R_u(B)·e_off = e_r·(cos(B + φ_r)·e1 + sin(B + φ_r)·w), since
    ///   R_u(B)·e1 = cos B·e1 + sin B·w.
    /// - Hob axial runout: Y += e_a·cos(B + φ_a).
    /// - Table runout: a workpiece direction at angle θ_w stands at machine
    ///   angle θ_w − C, so the gear's axis stands at v = e_t·(cos(φ_t − C),
    ///   sin(φ_t − C), 0); seen from the gear the hob is translated by −v.
    ///   The hob centre's distance to the gear axis is then
    ///   √((X − e_t·cos ψ)² + (e_t·sin ψ)²) ≈ X − e_t·cos(C − φ_t), ψ = φ_t − C.
    pub fn apply(&self, p: Pose) -> Pose {
        if self.is_zero() {
            return p;
        }
        let mut q = p;
        q.eta_rad += self.swivel_deg.to_radians();
        q.axes.x_mm += self.centre_distance_mm;
        let (se, ce) = q.eta_rad.sin_cos();
        // A translation (dx, d_y_machine, d_w) of the hob centre.
        let mut dx = 0.0;
        let mut dy_machine = 0.0;
        let mut dw = 0.0;
        let mut du = 0.0;
        let br = q.b_rad + self.hob_radial_phase_deg.to_radians();
        dx -= self.hob_radial_mm * br.cos();
        dw += self.hob_radial_mm * br.sin();
        du += self.hob_axial_mm * (q.b_rad + self.hob_axial_phase_deg.to_radians()).cos();
        let psi = self.table_phase_deg.to_radians() - q.c_rad;
        dx -= self.table_mm * psi.cos();
        dy_machine -= self.table_mm * psi.sin();
        // ŷ = (u + sin η·ẑ)/cos η, w = tan η·u + ẑ/cos η.
        q.axes.x_mm += dx;
        q.axes.y_mm += du + dy_machine / ce + dw * se / ce;
        q.axes.z_mm += dy_machine * se / ce + dw / ce;
        q
    }
}
