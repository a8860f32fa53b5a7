//! The closed-form clearance of the path check against its independent
//! reference, the sampled sweep (`clearance/sampled.rs`), on random hobs,
//! obstacles (blanks, cones, table, fixture, tailstock) and moves placed
//! where the hob often enters.
//!
//! The closed form gives certified bounds lo ≤ D* ≤ hi and a witness point;
//! the reference gives the depth of real points at real poses. So:
//!
//! - no sampled point lies deeper than the closed form's upper bound (the
//!   closed form misses nothing the samples find);
//! - the closed form's witness is a point of one solid at the pose it names,
//!   as deep in the other as its lower bound says, by the reference's own
//!   depth functions;
//! - the two agree within 1 µm: the refined samples reach the lower bound;
//! - each finds the collisions (depth beyond `PEN_TOL`) the other finds.
//!
//! The same on every move of real programs (`tests/programs/`), wherever the
//! hob comes near a solid.

#[path = "clearance/sampled.rs"]
mod sampled;

use gearcam_nc::collide_hook::{depth, moves, Depth, HobMove, Solid};
use gearcam_proto::MachiningModel;
use proptest::prelude::*;
use sampled::{obstacle_depth, Pose};

/// The path check's tolerance (`collide::PEN_TOL`), mm.
const PEN_TOL: f64 = 0.002;

fn solid() -> impl Strategy<Value = Solid> {
    let cylinder = (0.0..200.0f64, 5.0..80.0f64, 10.0..150.0f64).prop_map(|(z, w, r)| Solid {
        z_lo: z,
        z_hi: z + w,
        r_lo: r,
        r_hi: r,
    });
    let cone = (
        0.0..200.0f64,
        5.0..80.0f64,
        20.0..150.0f64,
        0.05..0.6f64,
        any::<bool>(),
    )
        .prop_map(|(z, w, r, tan, large_below)| {
            let small = (r - w * tan).max(2.0);
            let (r_lo, r_hi) = if large_below { (r, small) } else { (small, r) };
            Solid {
                z_lo: z,
                z_hi: z + w,
                r_lo,
                r_hi,
            }
        });
    let table = (100.0..600.0f64).prop_map(|r| Solid {
        z_lo: f64::NEG_INFINITY,
        z_hi: 0.0,
        r_lo: r,
        r_hi: r,
    });
    let fixture = (10.0..200.0f64, 10.0..80.0f64).prop_map(|(h, r)| Solid {
        z_lo: 0.0,
        z_hi: h,
        r_lo: r,
        r_hi: r,
    });
    let tailstock = (50.0..300.0f64, 10.0..60.0f64).prop_map(|(z, r)| Solid {
        z_lo: z,
        z_hi: f64::INFINITY,
        r_lo: r,
        r_hi: r,
    });
    prop_oneof![cylinder, cone, table, fixture, tailstock]
}

/// A hob and a straight move (or a swivel, `turn_deg` ≠ 0) through a point
/// near the solid's surface.
fn hob_move(s: Solid, turn_deg: f64) -> impl Strategy<Value = HobMove> {
    let rmax = s.r_lo.max(s.r_hi);
    let (z_lo, z_hi) = match (s.z_lo.is_finite(), s.z_hi.is_finite()) {
        (true, true) => (s.z_lo, s.z_hi),
        (false, _) => (s.z_hi - 20.0, s.z_hi),
        (_, false) => (s.z_lo, s.z_lo + 20.0),
    };
    (
        10.0..60.0f64,
        10.0..100.0f64,
        -40.0..40.0f64,
        -turn_deg..=turn_deg,
        0.0..1.0f64,
        0.0..1.0f64,
        -30.0..30.0f64,
        (
            0.0..120.0f64,
            0.0..std::f64::consts::TAU,
            -1.0..1.0f64,
            0.0..1.0f64,
        ),
    )
        .prop_map(
            move |(r, half, eta, turn, fx, fz, shift, (len, phi, dy, at))| {
                let reach = r.hypot(half);
                // The target: X from the axis to beyond the solid by the hob's
                // radius, Z around the solid's faces by the hob's reach.
                let x = fx * (rmax + r + 10.0);
                let z = z_lo - reach + fz * (z_hi - z_lo + 2.0 * reach);
                let dir = [phi.cos(), phi.sin(), dy * 10.0];
                let (before, after) = (len * at, len * (1.0 - at));
                HobMove {
                    from: [
                        x - dir[0] * before,
                        z - dir[1] * before,
                        shift - dir[2] * at,
                    ],
                    to: [
                        x + dir[0] * after,
                        z + dir[1] * after,
                        shift + dir[2] * (1.0 - at),
                    ],
                    eta_from_deg: eta,
                    eta_to_deg: eta + turn,
                    radius: r,
                    half_length: half,
                }
            },
        )
}

/// The closed form's witness, checked by the reference's depth functions:
/// a point of one solid at the named pose, as deep in the other as `lo`.
fn witness_holds(m: &HobMove, s: &Solid, d: &Depth) -> Result<(), String> {
    let pose = Pose::at(m, d.t);
    let (own, other) = if d.hob_point {
        (pose.depth_of(d.at), obstacle_depth(s, d.at))
    } else {
        (obstacle_depth(s, d.at), pose.depth_of(d.at))
    };
    if own < -1e-6 {
        return Err(format!("witness {d:?} is not a point of its solid: {own}"));
    }
    if other < d.lo - 1e-6 {
        return Err(format!("witness {d:?} is only {other} deep"));
    }
    Ok(())
}

/// The closed form against the sampled sweep on one move and solid, its
/// bounds at most `tol` apart.
fn agree(m: &HobMove, s: &Solid, tol: f64) -> Result<(), String> {
    let d = depth(m, s);
    let r = sampled::depth(m, s);
    let fail = |what: String| Err(format!("{what}\n  move {m:?}\n  solid {s:?}"));
    if !(d.lo <= d.hi && d.hi - d.lo <= tol) {
        return fail(format!("bounds not closed: {d:?}"));
    }
    witness_holds(m, s, &d)?;
    if r.depth > d.hi + 1e-9 {
        return fail(format!(
            "a sampled point {:?} at t {} is {} deep, beyond the closed form's {d:?}",
            r.at, r.t, r.depth
        ));
    }
    if d.lo - r.depth > 1e-3 {
        return fail(format!(
            "the samples reach {} ({:?} at t {}), the closed form {d:?}",
            r.depth, r.at, r.t
        ));
    }
    // Findings: each finds what the other finds (beyond the 1 µm band).
    if (r.depth > PEN_TOL && d.hi <= PEN_TOL) || (d.lo > PEN_TOL + 1e-3 && r.depth <= PEN_TOL) {
        return fail(format!("one finds a collision, the other not: {r:?} {d:?}"));
    }
    Ok(())
}

/// The names of the real programs of `tests/programs/`.
const PROGRAMS: [&str; 7] = [
    "spur_840d",
    "two_units_five_cuts_840d",
    "conical_840d",
    "helical_climb_840d",
    "worm_wheel_tangential_840d",
    "crowned_840d",
    "helical_shift_fanuc",
];

/// A program of `tests/programs/` and its model.
fn program(name: &str) -> (MachiningModel, String) {
    let dir = format!("{}/tests/programs", env!("CARGO_MANIFEST_DIR"));
    let read = |ext: &str| {
        std::fs::read_to_string(format!("{dir}/{name}.{ext}"))
            .unwrap_or_else(|e| panic!("{name}.{ext}: {e}"))
    };
    let model = serde_json::from_str(&read("model.json"))
        .unwrap_or_else(|e| panic!("{name}.model.json (see tests/programs/README.md): {e}"));
    (model, read("nc"))
}

/// Every move of real programs (what the shipped templates write for
/// examples): the programs are clear, and wherever the hob comes within 5 mm
/// of a solid the closed form and the sampled sweep agree (further off, the
/// closed form's separation is its own proof).
#[test]
fn real_programs_agree_with_the_sampled_sweep() {
    let mut near = 0;
    for name in PROGRAMS {
        let (m, text) = program(name);
        let (check, trace) = gearcam_nc::check(&text, &m);
        assert!(check.ok, "{name}: {:#?}", check.findings);
        for mv in moves(&m, &trace) {
            for (what, solid) in &mv.solids {
                if depth(&mv.hob, solid).hi < -5.0 {
                    continue;
                }
                near += 1;
                let tol = if mv.hob.eta_from_deg == mv.hob.eta_to_deg {
                    1e-4
                } else {
                    1e-3
                };
                agree(&mv.hob, solid, tol)
                    .unwrap_or_else(|e| panic!("{name}, line {} against {what}: {e}", mv.line));
            }
        }
    }
    assert!(near > 10, "only {near} moves come near a solid");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// Straight moves with the tilt kept: bounds 0.1 µm apart.
    #[test]
    fn straight_moves_agree_with_the_sampled_sweep(
        (s, m) in solid().prop_flat_map(|s| (Just(s), hob_move(s, 0.0)))
    ) {
        agree(&m, &s, 1e-4).map_err(TestCaseError::fail)?;
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(16))]

    /// Moves that swivel the hob by up to 15°: bounds 1 µm apart.
    #[test]
    fn swivel_moves_agree_with_the_sampled_sweep(
        (s, m) in solid().prop_flat_map(|s| (Just(s), hob_move(s, 15.0)))
    ) {
        agree(&m, &s, 1e-3).map_err(TestCaseError::fail)?;
    }
}
