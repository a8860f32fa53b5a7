//! The pieces of a pass's curve that `cut::cut` leaves out, because they
//! stand clear of the outline by more than they can bend, change nothing:
//! the same real programs cut with every piece refined to the tolerance
//! (`cut::cut_exhaustive`) give the same outline.

mod common;

use gearcam_hobsim::cut::{self, samples_for, Blank, Resolution};
use gearcam_hobsim::hob::{Hob, HobExtras};

/// Both cuts of program `name` on 3 sections, rays for a 1 µm outline.
fn both(name: &str, res: Resolution) -> (Blank, Blank) {
    let (text, model) = common::program(name);
    let tl = common::timeline(&text, &model);
    let hob = Hob::from_data(&model.plan.hob, HobExtras::default()).expect("hob");
    let g = &model.plan.gear;
    let h = g.fixture_height_mm;
    let z = Blank::planes(h + 1.0, h + g.face_width_mm - 1.0, 3);
    let r = model.model.blank_od_mm / 2.0;
    let fresh = Blank::new(z, r, samples_for(r, 1.0)).expect("blank");
    let (mut skipping, mut every) = (fresh.clone(), fresh);
    cut::cut(&tl, &hob, &mut skipping, res).expect("cut");
    cut::cut_exhaustive(&tl, &hob, &mut every, res).expect("cut");
    (skipping, every)
}

fn largest_difference(a: &Blank, b: &Blank) -> f64 {
    a.r_mm
        .iter()
        .flatten()
        .zip(b.r_mm.iter().flatten())
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

#[test]
#[ignore = "about 20 s in release: cargo test --release -p gearcam-hobsim -- --ignored"]
fn leaving_out_the_clear_pieces_changes_no_outline() {
    let res = Resolution {
        axial_step_mm: 2.0,
        tolerance_mm: 1e-4,
    };
    for name in ["spur_840d", "helical_climb_840d"] {
        let (skipping, every) = both(name, res);
        let d = largest_difference(&skipping, &every);
        assert!(d < 1e-9, "{name}: the outlines differ by {d:.2e} mm");
    }
}
