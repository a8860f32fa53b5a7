//! The coverage proof against the sampled coverage check, on random faces:
//! radii, tool, step-over, overtravels (negative ones too, ends short of
//! the edges), direction, sense, start angle and chord tolerance. The
//! spiral is placed by the planner's rules written out here without its
//! refusals, so step-overs past the tool's diameter and short ends come
//! out as spirals to check.
//!
//! What must hold, and why:
//!
//! - **Proved means covered.** A face the proof covers has no sampled point
//!   beyond the tool's edge, at any resolution (the proof is sufficient).
//! - **The proof's gap is an upper bound.** The sampled gap (the chords
//!   with the real tool) never exceeds the proof's shortfall: a point's
//!   distance from the path is at most its distance along a ray from the
//!   nearest crossing plus δ.
//! - **Between turns the two agree.** With the edges in hand, the proof's
//!   shortfall L/2 − w and the sampled gap differ by at most the band along
//!   a ray being w / cos β, not w, at the face's largest radius between
//!   turns ((L/2)·(1 − cos β), doubled for the turns' curvature), 2δ, and
//!   the sampling's reach (a point of the face lies within 0.71 of the
//!   resolution of a sample, and the gap is 1-Lipschitz). So a face the
//!   proof refuses by more than that band has a sampled gap.
//! - **At an edge the proof may overstate**, by up to about half a
//!   step-over: its shortfall is the supremum along the rays beside the
//!   spiral's end, where the end point's own disc covers the crescent;
//!   opposite the end the crossing is L/2 nearer and nothing else is near.
//!   So at the outer edge, and at an inner edge whose hole is at least the
//!   tool's radius, the sampled gap is at least the proof's less L/2 and
//!   the band. Around a small hole or the centre the discs of the turns
//!   across the centre cover too, and only the first two rules are held.

use gearcam_spiral::{coverage, prove_coverage, Region, Spiral, Zone};
use proptest::prelude::*;

/// A face and its spiral, as the planner places it (docs/spiral.md) but
/// without its refusals.
#[derive(Debug, Clone)]
struct Case {
    region: Region,
    tool_radius_mm: f64,
    spiral: Spiral,
    tolerance_mm: f64,
}

/// R1 and R2 by the planner's rules for any step-over and overtravels:
/// outside-in from Ro + R + outer to max(Ri + R − L − inner, 0); inside-out
/// from Ri − R − inner (when that is not below the centre) to Ro + R +
/// outer. Turns rounded up.
#[allow(clippy::too_many_arguments)]
fn case(
    ro: f64,
    ri_share: f64,
    rt_share: f64,
    step_share: f64,
    outer: f64,
    inner: f64,
    inside_out: bool,
    clockwise: bool,
    start_deg: f64,
    tolerance_mm: f64,
) -> Case {
    let rt = (ro / 20.0).max(1.0) + rt_share * (ro.min(30.0) - (ro / 20.0).max(1.0));
    let ri = ri_share * ro;
    let l = step_share * 2.0 * rt;
    let far = ro + rt + outer;
    let (r1, r2) = if inside_out && ri - rt - inner >= 0.0 {
        (ri - rt - inner, far)
    } else {
        (far, (ri + rt - l - inner).max(0.0))
    };
    let turns = ((r1 - r2).abs() / l - 1e-9).ceil().max(1.0) as u32;
    Case {
        region: Region {
            outer_radius_mm: ro,
            inner_radius_mm: ri,
        },
        tool_radius_mm: rt,
        spiral: Spiral {
            start_radius_mm: r1,
            end_radius_mm: r2,
            start_angle_deg: start_deg,
            turns,
            sense: if clockwise { -1 } else { 1 },
        },
        tolerance_mm,
    }
}

/// What both checks say of a case.
struct Verdicts {
    proof: gearcam_spiral::CoverageProof,
    sampled: gearcam_spiral::Coverage,
    /// δ, the chords' proven stray from the spiral, mm.
    stray: f64,
    /// The sampling's resolution, mm.
    resolution: f64,
}

fn verdicts(c: &Case) -> Verdicts {
    let (_, points) = c.spiral.chords(c.tolerance_mm);
    let stray = c.spiral.chord_stray_mm(c.tolerance_mm);
    let resolution = c.tool_radius_mm / 6.0;
    Verdicts {
        proof: prove_coverage(&c.region, &c.spiral, c.tool_radius_mm, stray),
        sampled: coverage(&c.region, c.tool_radius_mm, &points, resolution),
        stray,
        resolution,
    }
}

/// The band along a ray is w / cos β: β at the face's largest radius
/// where a gap between turns can lie.
fn inclination_band(c: &Case) -> f64 {
    let l = c.spiral.step_over_mm();
    let r_out = c.spiral.start_radius_mm.max(c.spiral.end_radius_mm);
    let top = (r_out - 0.5 * l).min(c.region.outer_radius_mm).max(1e-9);
    let beta = (l / (std::f64::consts::TAU * top)).atan();
    2.0 * 0.5 * l * (1.0 - beta.cos())
}

/// The two rules every case keeps: proved means no sampled gap, and the
/// sampled gap within the proof's.
fn sound(c: &Case, v: &Verdicts) -> Result<(), TestCaseError> {
    if v.proof.ok {
        prop_assert!(
            v.sampled.max_gap_mm <= 1e-9,
            "proved, yet sampled {:?} for {c:?}: {:?}",
            v.sampled,
            v.proof
        );
    }
    prop_assert!(
        v.sampled.max_gap_mm <= v.proof.max_gap_mm + 1e-9,
        "sampled gap {} over the proof's {} for {c:?}: {:?}",
        v.sampled.max_gap_mm,
        v.proof.max_gap_mm,
        v.proof
    );
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(96))]

    /// Step-overs from 0.3 to 1.3 tool diameters, overtravels that keep
    /// the edges covered: the proof's verdict and gap between turns match
    /// the sampled check's within the stated band.
    #[test]
    fn between_turns_the_proof_and_the_sampled_check_agree(
        ro in 10.0f64..150.0,
        ri_share in prop_oneof![Just(0.0), 0.0f64..0.7],
        rt_share in 0.0f64..1.0,
        step_share in 0.3f64..1.3,
        outer_extra in 0.5f64..3.0,
        inner in 0.2f64..3.0,
        inside_out: bool,
        clockwise: bool,
        start_deg in 0.0f64..360.0,
        tolerance_mm in prop_oneof![Just(0.001), Just(0.005), 0.0005f64..0.01],
    ) {
        // Enough overtravel for any step-over at the end the tool plunges:
        // Ro + R + outer − L + w ≥ Ro, and inside-out
        // Ri − (Ri − R − inner + L − w) ≥ 0.
        let rt_guess = (ro / 20.0).max(1.0) + rt_share * (ro.min(30.0) - (ro / 20.0).max(1.0));
        let past = (step_share * 2.0 * rt_guess - 2.0 * rt_guess).max(0.0);
        let (outer, inner) = (past + outer_extra, past + inner);
        let c = case(ro, ri_share, rt_share, step_share, outer, inner, inside_out, clockwise, start_deg, tolerance_mm);
        let v = verdicts(&c);
        sound(&c, &v)?;
        prop_assert!(v.proof.worst.is_none_or(|z| z == Zone::BetweenTurns), "{:?} {c:?}", v.proof);
        let band = inclination_band(&c) + 2.0 * v.stray + 0.71 * v.resolution + 1e-9;
        if !v.proof.ok {
            prop_assert!(
                v.sampled.max_gap_mm >= v.proof.max_gap_mm - band,
                "the proof's gap {} vs sampled {} (band {band}) for {c:?}",
                v.proof.max_gap_mm,
                v.sampled.max_gap_mm
            );
        }
    }

    /// Step-overs the turns cover, overtravels from minus a step-over
    /// (ends short of the edges) to plus half of one: proved means
    /// covered, the sampled gap is within the proof's, and at the outer
    /// edge, or an inner edge of a hole no smaller than the tool, the
    /// sampled gap is the proof's within half a step-over and the band.
    #[test]
    fn at_the_edges_the_proof_is_sound_and_finds_what_is_left(
        ro in 10.0f64..150.0,
        ri_share in prop_oneof![Just(0.0), 0.0f64..0.7],
        rt_share in 0.0f64..1.0,
        step_share in 0.2f64..0.9,
        outer_share in -1.0f64..0.5,
        inner_share in -1.0f64..0.5,
        inside_out: bool,
        clockwise: bool,
        start_deg in 0.0f64..360.0,
        tolerance_mm in prop_oneof![Just(0.001), 0.0005f64..0.01],
    ) {
        let rt_guess = (ro / 20.0).max(1.0) + rt_share * (ro.min(30.0) - (ro / 20.0).max(1.0));
        let l = step_share * 2.0 * rt_guess;
        let c = case(ro, ri_share, rt_share, step_share, outer_share * l, inner_share * l, inside_out, clockwise, start_deg, tolerance_mm);
        let v = verdicts(&c);
        sound(&c, &v)?;
        // Opposite the spiral's end the edge's crossing is half a step-over
        // nearer than beside it, and nothing but the inclined turn is near
        // the edge there (for the inner edge when the hole is at least the
        // tool's radius): the true gap is at least the proof's less L/2,
        // the inclination there and the sampling's reach.
        let l = c.spiral.step_over_mm();
        let w = v.proof.reach_mm;
        let edge = match v.proof.worst {
            Some(Zone::OuterEdge) => Some(c.region.outer_radius_mm),
            Some(Zone::InnerEdge) if c.region.inner_radius_mm >= c.tool_radius_mm => {
                Some(c.region.inner_radius_mm)
            }
            _ => None,
        };
        if let Some(r) = edge {
            let beta = (l / (std::f64::consts::TAU * r)).atan();
            let band = 0.5 * l
                + 2.0 * (v.proof.max_gap_mm + w) * (1.0 - beta.cos())
                + 2.0 * v.stray
                + 0.71 * v.resolution;
            prop_assert!(
                v.sampled.max_gap_mm >= v.proof.max_gap_mm - band,
                "the proof's gap {} ({:?}) vs sampled {} (band {band}) for {c:?}",
                v.proof.max_gap_mm,
                v.proof.worst,
                v.sampled.max_gap_mm
            );
        }
    }
}

/// The planner's own faces, with the default overtravels and with an inner
/// overtravel of 0: proved, and no sampled gap.
#[test]
fn the_planners_faces_are_proved() {
    for (ro, ri, rt, step) in [
        (100.0, 0.0, 8.0, 12.0),
        (100.0, 20.0, 10.0, 15.0),
        (60.0, 15.0, 8.0, 15.9),
        (90.0, 0.0, 31.5, 38.0),
        (30.0, 5.0, 3.0, 1.0),
    ] {
        for inner in [0.5, 0.0] {
            let far = ro + rt + 2.0;
            let near = f64::max(ri + rt - step - inner, 0.0);
            let c = Case {
                region: Region {
                    outer_radius_mm: ro,
                    inner_radius_mm: ri,
                },
                tool_radius_mm: rt,
                spiral: Spiral {
                    start_radius_mm: far,
                    end_radius_mm: near,
                    start_angle_deg: 30.0,
                    turns: ((far - near) / step - 1e-9).ceil() as u32,
                    sense: -1,
                },
                tolerance_mm: 0.001,
            };
            let v = verdicts(&c);
            assert!(v.proof.ok, "{c:?}: {:?}", v.proof);
            assert!(v.sampled.ok, "{c:?}: {:?}", v.sampled);
        }
    }
}

/// A spiral ending exactly at Ri + R − L (no inner overtravel, a whole
/// number of step-overs): on the rays beside its end the innermost turn
/// stops δ short of the inner edge, and the end's own disc covers that;
/// the proof says so. Ending 3 mm further out leaves a crescent
/// the end's disc cannot cover: refused at the inner edge, and the
/// sampled check finds it.
#[test]
fn the_end_disc_proves_an_end_exactly_at_the_planners_radius() {
    let region = Region {
        outer_radius_mm: 60.0,
        inner_radius_mm: 15.0,
    };
    // 67 → 12 mm in 5 turns: L = 11, R2 = 15 + 8 − 11.
    let spiral = Spiral {
        start_radius_mm: 67.0,
        end_radius_mm: 12.0,
        start_angle_deg: 0.0,
        turns: 5,
        sense: 1,
    };
    let c = Case {
        region,
        tool_radius_mm: 8.0,
        spiral,
        tolerance_mm: 0.001,
    };
    let v = verdicts(&c);
    assert!(v.proof.inner_edge_mm < 0.0, "{:?}", v.proof);
    assert!(v.proof.ok && v.proof.inner_by_end, "{:?}", v.proof);
    assert!(v.sampled.ok, "{:?}", v.sampled);
    let short = Case {
        spiral: Spiral {
            start_radius_mm: 70.0,
            end_radius_mm: 15.0,
            ..spiral
        },
        ..c
    };
    let v = verdicts(&short);
    assert_eq!(v.proof.worst, Some(Zone::InnerEdge), "{:?}", v.proof);
    assert!(!v.proof.ok && !v.proof.inner_by_end, "{:?}", v.proof);
    assert!(v.sampled.max_gap_mm > 0.1, "{:?}", v.sampled);
}
