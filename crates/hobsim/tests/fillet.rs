//! The root fillet the rounded tip corners of the hob's teeth cut
//! (`docs/simulation.md` §4): against the exact sweep of the rounded edges,
//! computed by `sweep` with its own profile (the sharp tooth opened by a
//! disc of radius r_c), not the corner formula of `hob`.

mod sweep;

use gearcam_hobsim::cut::{self, Blank, Resolution};
use gearcam_hobsim::hob::Hob;
use gearcam_hobsim::kinematics::{Axes, Gearbox, Segment, Timeline};

const PI: f64 = std::f64::consts::PI;
const MN: f64 = 10.0;
const Z: u32 = 20;
const R0: f64 = 500.0;

/// The hob: module 10, α 20°, addendum 1.25·mn, tip corners r_c = 0.38·mn
/// (ISO 53 profile A), 32 gashes, right hand, one start.
fn hob() -> Hob {
    let g0 = (MN / (2.0 * R0)).asin();
    Hob {
        starts: 1,
        hand: 1.0,
        tip_radius_mm: R0 + 1.25 * MN,
        ref_radius_mm: R0,
        root_radius_mm: R0 - 1.25 * MN,
        axial_pitch_mm: PI * MN / g0.cos(),
        tan_alpha_x: 20f64.to_radians().tan() / g0.cos(),
        length_mm: 100.0,
        gashes: 32,
        tip_corner_radius_mm: 0.38 * MN,
        cos_lead: g0.cos(),
    }
}

/// The plunge at zero profile shift (X = r + r0) for 1.05 table turns.
fn plunge(h: &Hob) -> Timeline {
    let g0 = (MN / (2.0 * R0)).asin();
    let ratio = 1.0 / f64::from(Z);
    let at = Axes {
        x_mm: MN * f64::from(Z) / 2.0 + R0,
        y_mm: 0.0,
        z_mm: 50.0,
    };
    Timeline::from_segments(vec![Segment {
        line: 0,
        t0_s: 0.0,
        t1_s: 1.05 / ratio,
        from: at,
        to: at,
        eta_rad: -h.hand * g0,
        hob_rev_s: 1.0,
        gearbox: Some(Gearbox {
            c_per_b: ratio,
            c_per_z_rad_mm: 0.0,
            c_per_y_rad_mm: 0.0,
        }),
        c_extra_rad: 0.0,
        feed: true,
    }])
    .expect("timeline")
}

/// The fillet of a tooth space half a turn from where the plunge starts,
/// from 0.1 mm above the root circle (r − 12.5) to 93.5 mm (the involute
/// begins at 94.1 mm, where the rack's straight flank ends, 10.0 mm below
/// its pitch line: √(r² + (10/sin α)² − 2·r·10)), on both sides of the
/// space: the simulated outline is the exact sweep of the rounded edges
/// within 0.2 µm radially (the strips' straight edges across the corner's
/// arc, 0.01 mm apart, and the steepness of the fillet's upper end).
#[test]
#[ignore = "about 60 s in release: cargo test --release -p gearcam-hobsim -- --ignored"]
fn the_root_fillet_is_the_sweep_of_the_rounded_tip_corners() {
    let h = hob();
    let tl = plunge(&h);
    let n = 1usize << 16;
    let mut blank = Blank::new(vec![50.0], 110.0, n).expect("blank");
    let res = Resolution {
        axial_step_mm: 0.01,
        sweep_steps: 3,
    };
    cut::cut(&tl, &h, &mut blank, res).expect("cut");
    let outline = &blank.r_mm[0];
    let r = MN * f64::from(Z) / 2.0;
    let big_h = 12.5;
    // The space half a turn on: its falling flank crosses the pitch circle
    // after sample n/2, its rising flank next.
    let enter = (n / 2..n)
        .find(|&i| outline[i - 1] >= r && outline[i] < r)
        .expect("a space");
    let leave = (enter..n)
        .find(|&i| outline[i - 1] < r && outline[i] >= r)
        .expect("its end");
    let fillet: Vec<usize> = (enter..leave)
        .filter(|&i| (r - big_h + 0.1..93.5).contains(&outline[i]))
        .collect();
    assert!(fillet.len() > 100, "{} fillet samples", fillet.len());
    let mut worst: f64 = 0.0;
    for &i in fillet.iter().step_by(fillet.len() / 16) {
        let got = outline[i];
        let want = sweep::reference_radius(&tl, &h, 50.0, blank.theta(i), got - 0.1, got + 0.1);
        worst = worst.max((got - want).abs());
    }
    eprintln!(
        "{} fillet samples: largest difference {worst:.2e} mm",
        fillet.len()
    );
    assert!(worst < 2e-4, "{worst} mm");
}
