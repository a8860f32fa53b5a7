//! The root fillet the rounded tip corners of the hob's teeth cut
//! (`docs/simulation.md` §4): against the exact sweep of the rounded edges,
//! computed by `sweep` with its own profile (the sharp tooth opened by a
//! disc of radius r_c), not the corner formula of `hob`.

mod common;
mod sweep;

use gearcam_hobsim::cut::{self, Blank, Resolution};

const MN: f64 = 10.0;
const Z: u32 = 20;
const R0: f64 = 500.0;

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
    let h = common::rack_hob(R0, 1, 32, 0.38 * MN);
    let tl = common::spur_plunge(&h, 1.05);
    let n = 1usize << 16;
    let mut blank = Blank::new(vec![50.0], 110.0, n).expect("blank");
    let res = Resolution {
        axial_step_mm: 0.1,
        tolerance_mm: 1e-6,
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
