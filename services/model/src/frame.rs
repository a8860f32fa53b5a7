//! The machine-neutral kinematic frame of hobbing: hands as signs, every
//! coupling derived from one frame, then mapped to a machine by its profile
//! (`docs/hobbing.md`, "Signs", has the derivation).
//!
//! # The frame
//!
//! - Z is the gear (table) axis, pointing up from the table plane; X points
//!   from the gear axis to the hob centre, which sits at (L, 0, Z).
//! - The hob axis direction is u = (0, cos η, −sin η): η is the setting angle,
//!   a right-handed turn about the direction from the hob centre to the gear
//!   axis (−X), starting with the hob axis parallel to the gear end face.
//! - The table angle C counts clockwise seen from above the table; the hob
//!   angle B counts right-handed about u; the shift Y moves the hob along u.
//! - Hands are signs: s_g = +1 right-hand gear, −1 left-hand, 0 spur;
//!   s_h = +1 right-hand hob, −1 left-hand.
//!
//! # The rules (each derived in `docs/hobbing.md` and tested numerically)
//!
//! - Setting angle: η = s_g·β − s_h·γ0 lays the hob thread along the gear's
//!   tooth line at the pitch point.
//! - Indexing: C/B = s_h·z0/z (the hob's hand alone).
//! - Differential: C per Z = s_g·360·sin β/(π·mn·z) degrees per mm, the
//!   gear's helix alone (hob hand and cut mode do not enter).
//! - Shift: a shift along u is a screw motion of the hob thread, equal to a
//!   hob turn of −1/p per mm (p the hob's signed lead parameter, its sign
//!   the hob's hand); through the indexing ratio this gives
//!   C per Y = −360·cos γ0/(π·mn0·z), the same for both hands.
//!
//! Mirroring the whole set-up in the plane of the gear axis and the centre
//! line swaps both hands and turns η, C/B and C per Z; C per Y keeps its sign
//! because the mirror turns both the table's sense and the shift's direction
//! along the (mirrored) hob axis. The tests check every rule against a direct
//! computation of the tooth phase, not against these formulas.

use std::f64::consts::PI;

use gearcam_proto::{GearSpec, Hand, HobData, MachineSettings, Ratio};

use crate::geometry::is_spur;

/// s_h: +1 for a right-hand hob, −1 for a left-hand one.
pub fn hob_sign(hob: &HobData) -> f64 {
    match hob.hand {
        Hand::Right => 1.0,
        Hand::Left => -1.0,
    }
}

/// s_g: +1 for a right-hand gear, −1 for a left-hand one, 0 for a spur gear
/// (or a gear without a hand, which validation allows only for spur gears).
pub fn gear_sign(gear: &GearSpec) -> f64 {
    match gear.helix_hand {
        _ if is_spur(gear) => 0.0,
        Some(Hand::Right) => 1.0,
        Some(Hand::Left) => -1.0,
        None => 0.0,
    }
}

/// The signed setting angle η = s_g·|β| − s_h·|γ0|, degrees.
pub fn setting_angle_deg(gear: &GearSpec, hob: &HobData) -> f64 {
    gear_sign(gear) * gear.helix_angle_deg.abs() - hob_sign(hob) * hob.lead_angle_deg.abs()
}

fn gcd(mut a: u32, mut b: u32) -> u32 {
    while b != 0 {
        (a, b) = (b, a % b);
    }
    a
}

/// The indexing ratio C/B = s_h·z0/z, reduced and exact, in the neutral frame.
pub fn indexing(hob: &HobData, teeth: u32) -> Ratio {
    let g = gcd(hob.starts, teeth).max(1);
    let num = i32::try_from(hob.starts / g).unwrap_or(i32::MAX);
    Ratio {
        num: if hob.hand == Hand::Left { -num } else { num },
        den: teeth / g,
    }
}

/// The differential C per Z = s_g·360·sin|β|/(π·mn·z), degrees of table per
/// mm of hob travel along the gear axis, in the neutral frame (0 for spur).
pub fn differential_deg_per_mm(gear: &GearSpec) -> f64 {
    let beta = gear.helix_angle_deg.abs().to_radians();
    gear_sign(gear) * 360.0 * beta.sin() / (PI * gear.module_mm * f64::from(gear.teeth))
}

/// The shift compensation C per Y = −360·cos γ0/(π·mn0·z), degrees of table
/// per mm of hob shift along u, in the neutral frame.
pub fn shift_compensation_deg_per_mm(hob: &HobData, teeth: u32) -> f64 {
    -360.0 * hob.lead_angle_deg.abs().to_radians().cos() / (PI * hob.module_mm * f64::from(teeth))
}

/// The couplings as one machine programs them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MachineCouplings {
    /// Swivel axis value: swivel_sign·η + swivel_offset, degrees.
    pub swivel_axis_deg: f64,
    /// C per B in the machine's directions: table_sign·hob_sign·s_h·z0/z.
    pub c_per_b: Ratio,
    /// C per Z in the machine's directions: table_sign·differential.
    pub c_per_z_deg_per_mm: f64,
    /// C per Y in the machine's directions: table_sign·shift_sign·compensation.
    pub c_per_y_deg_per_mm: f64,
}

/// Maps the neutral η, C/B, C per Z and C per Y to the machine's axes
/// (programmed C = table_sign·C, B = hob_sign·B, Y = shift_sign·Y,
/// A = swivel_sign·η + swivel_offset; Z is the height above the table in both).
pub fn to_machine(
    settings: &MachineSettings,
    eta_deg: f64,
    indexing: Ratio,
    c_per_z: f64,
    c_per_y: f64,
) -> MachineCouplings {
    let tb = settings.table_sign * settings.hob_sign;
    MachineCouplings {
        swivel_axis_deg: settings.swivel_sign * eta_deg + settings.swivel_offset_deg,
        c_per_b: Ratio {
            num: if tb < 0.0 {
                -indexing.num
            } else {
                indexing.num
            },
            den: indexing.den,
        },
        c_per_z_deg_per_mm: settings.table_sign * c_per_z,
        c_per_y_deg_per_mm: settings.table_sign * settings.shift_sign * c_per_y,
    }
}

#[cfg(test)]
mod tests {
    //! The rules checked against a first-principles computation of the tooth
    //! phase, not against themselves: a gear tooth surface is invariant under
    //! the gear's screw motion, so a point's phase
    //! ψ = atan2(y, x) − s_g·2π·z/Pz (counter-clockwise, radians) is the same
    //! all along one tooth line. A hob motion keeps cutting the same gaps when
    //! the table turns by the change of ψ of the hob's pitch point.

    use super::*;
    use crate::fixtures;
    use approx::assert_relative_eq;

    /// The hob axis direction u in the neutral frame.
    fn u(eta_deg: f64) -> [f64; 3] {
        let e = eta_deg.to_radians();
        [0.0, e.cos(), -e.sin()]
    }

    /// The tooth-line direction of the gear at the pitch point (r, 0, 0): a
    /// helix (r cos t, r sin t, p t) of hand s_g has tangent (0, r, s_g·p)
    /// up to its sense.
    fn tooth_line(s_g: f64, beta_deg: f64) -> [f64; 3] {
        let b = beta_deg.to_radians();
        [0.0, s_g * b.sin(), b.cos()]
    }

    /// The hob thread direction at the point of the hob nearest the gear axis:
    /// a helix of hand s_h about u through that point, built from the frame
    /// (e1 towards the gear axis, e2 = u × e1) without the η formula.
    fn thread(s_h: f64, gamma0_deg: f64, eta_deg: f64) -> [f64; 3] {
        let uu = u(eta_deg);
        let e1 = [-1.0, 0.0, 0.0];
        let e2 = [
            uu[1] * e1[2] - uu[2] * e1[1],
            uu[2] * e1[0] - uu[0] * e1[2],
            uu[0] * e1[1] - uu[1] * e1[0],
        ];
        let g = gamma0_deg.to_radians();
        let (c, s) = (g.cos(), s_h * g.sin());
        [
            c * e2[0] + s * uu[0],
            c * e2[1] + s * uu[1],
            c * e2[2] + s * uu[2],
        ]
    }

    fn parallel(a: [f64; 3], b: [f64; 3]) -> f64 {
        let cross = [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ];
        (cross[0].powi(2) + cross[1].powi(2) + cross[2].powi(2)).sqrt()
    }

    /// Phase ψ of a point, counter-clockwise radians.
    fn phase(p: [f64; 3], s_g: f64, lead: f64) -> f64 {
        p[1].atan2(p[0]) - s_g * 2.0 * PI * p[2] / lead
    }

    /// The clockwise table turn (radians) that keeps the tooth under the
    /// gear's pitch point after the hob's pitch point moves by `d` along
    /// `dir`: minus the phase change of the moved point.
    fn table_turn(g: &GearSpec, dir: [f64; 3], d: f64) -> f64 {
        let geo = crate::geometry::geometry(g);
        let (r, lead, s_g) = (
            geo.d_mm / 2.0,
            geo.lead_mm.unwrap_or(f64::INFINITY),
            gear_sign(g),
        );
        let moved = [r + d * dir[0], d * dir[1], d * dir[2]];
        -(phase(moved, s_g, lead) - phase([r, 0.0, 0.0], s_g, lead))
    }

    fn gear(beta: f64, hand: Option<Hand>) -> GearSpec {
        let mut g = fixtures::gear();
        g.helix_angle_deg = beta;
        g.helix_hand = hand;
        g
    }

    fn hob(hand: Hand) -> HobData {
        HobData {
            hand,
            ..fixtures::hob()
        }
    }

    fn cases() -> Vec<(f64, Option<Hand>, Hand)> {
        let mut v = Vec::new();
        for beta in [0.0, 8.0, 15.0, 30.0] {
            for gh in [Hand::Right, Hand::Left] {
                for hh in [Hand::Right, Hand::Left] {
                    v.push((beta, (beta != 0.0).then_some(gh), hh));
                }
            }
        }
        v
    }

    #[test]
    fn setting_angle_lays_the_thread_along_the_tooth_line() {
        for (beta, gh, hh) in cases() {
            let (g, h) = (gear(beta, gh), hob(hh));
            let eta = setting_angle_deg(&g, &h);
            let t = thread(hob_sign(&h), h.lead_angle_deg, eta);
            let line = tooth_line(gear_sign(&g), beta);
            assert!(
                parallel(t, line) < 1e-12,
                "β {beta} {gh:?} hob {hh:?}: η {eta}"
            );
            // The patent's rule γ = −(|β| ∓ |γ0|) read with one machine sign
            // (η = −γ) fits only right-hand gears and spur gears cut with a
            // right-hand hob; the mirror images get the wrong swivel.
            let gamma_old = if gh.is_none_or(|g| g == hh) {
                -(beta - h.lead_angle_deg)
            } else {
                -(beta + h.lead_angle_deg)
            };
            let old_fits =
                parallel(thread(hob_sign(&h), h.lead_angle_deg, -gamma_old), line) < 1e-9;
            let right_handed_setup = gh == Some(Hand::Right) || (gh.is_none() && hh == Hand::Right);
            assert_eq!(old_fits, right_handed_setup, "β {beta} {gh:?} hob {hh:?}");
        }
    }

    #[test]
    fn indexing_follows_the_hob_hand_alone() {
        // A hob turn dτ is a screw motion of its thread: the thread moves by
        // −p·dτ along u. The table must turn the tooth by the phase change of
        // that displacement at the pitch point (r, 0, 0).
        for (beta, gh, hh) in cases() {
            let (g, h) = (gear(beta, gh), hob(hh));
            let eta = setting_angle_deg(&g, &h);
            // Signed lead parameter of the hob: axial lead / 2π with its hand.
            let p = hob_sign(&h) * f64::from(h.starts) * PI * h.module_mm
                / h.lead_angle_deg.to_radians().cos()
                / (2.0 * PI);
            let dtau = 1e-6;
            // Clockwise table turn per hob turn.
            let ratio = table_turn(&g, u(eta), -p * dtau) / dtau;
            let want = indexing(&h, g.teeth);
            assert_relative_eq!(
                ratio,
                f64::from(want.num) / f64::from(want.den),
                max_relative = 1e-5
            );
        }
    }

    #[test]
    fn differential_follows_the_gear_hand_alone() {
        for (beta, gh, hh) in cases() {
            let g = gear(beta, gh);
            // The hob rises by dz (whatever its hand, hh): the tooth line
            // must pass its pitch point at the new height.
            let _ = hh;
            let dz = 1e-4;
            let cw_deg_per_mm = table_turn(&g, [0.0, 0.0, 1.0], dz).to_degrees() / dz;
            assert_relative_eq!(cw_deg_per_mm, differential_deg_per_mm(&g), epsilon = 1e-9);
        }
        // The worked self-check (docs/reference.md#worked-self-check):
        // mn 3, z 25, β 15° → 0.395446 °/mm.
        let g = gear(15.0, Some(Hand::Right));
        assert_relative_eq!(differential_deg_per_mm(&g), 0.395446, epsilon = 5e-7);
        let g = gear(15.0, Some(Hand::Left));
        assert_relative_eq!(differential_deg_per_mm(&g), -0.395446, epsilon = 5e-7);
    }

    #[test]
    fn shift_compensation_keeps_the_tooth_phase_including_the_axial_part() {
        // A shift dY along u moves the pitch point by dY·u: a tangential part
        // dY·cos η and, on a swivelled hob, an axial part −dY·sin η that a
        // helical gear's tooth line turns into phase too (the differential).
        for (beta, gh, hh) in cases() {
            let (g, h) = (gear(beta, gh), hob(hh));
            let eta = setting_angle_deg(&g, &h);
            let dy = 1e-5;
            let uu = u(eta);
            let cw_deg_per_mm = table_turn(&g, uu, dy).to_degrees() / dy;
            let r = crate::geometry::geometry(&g).d_mm / 2.0;
            assert_relative_eq!(
                cw_deg_per_mm,
                shift_compensation_deg_per_mm(&h, g.teeth),
                max_relative = 1e-6
            );
            if beta > 0.0 {
                // Without the axial part the compensation would be wrong.
                let tangential_only = -(uu[1] / r).to_degrees();
                assert!((tangential_only - cw_deg_per_mm).abs() > 1e-4);
            }
        }
    }

    #[test]
    fn machine_mapping_applies_each_axis_sign() {
        let mut s = fixtures::plan().machine.settings;
        s.swivel_sign = -1.0;
        s.swivel_offset_deg = 90.0;
        s.table_sign = -1.0;
        s.hob_sign = 1.0;
        s.shift_sign = -1.0;
        let m = to_machine(&s, 12.5, Ratio { num: -1, den: 25 }, 0.4, -1.5);
        assert_eq!(m.swivel_axis_deg, 77.5);
        assert_eq!(m.c_per_b, Ratio { num: 1, den: 25 });
        assert_eq!(m.c_per_z_deg_per_mm, -0.4);
        assert_eq!(m.c_per_y_deg_per_mm, -1.5);
    }
}
