//! Helpers the integration tests share: the real programs, and what a gear
//! measuring machine would read from the cut outlines.
#![allow(dead_code)]

use gearcam_hobsim::cut::{self, Blank, Resolution};
use gearcam_hobsim::hob::{Hob, HobExtras};
use gearcam_hobsim::kinematics::{self, MachineRates, Timeline};
use gearcam_proto::MachiningModel;

/// A real program and its model from `crates/nc/tests/programs`.
pub(crate) fn program(name: &str) -> (String, MachiningModel) {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../nc/tests/programs/");
    let text = std::fs::read_to_string(format!("{dir}{name}.nc")).expect("program");
    let json = std::fs::read_to_string(format!("{dir}{name}.model.json")).expect("model");
    (text, serde_json::from_str(&json).expect("model reads"))
}

/// The timeline of a program text read back against its model.
pub(crate) fn timeline(text: &str, model: &MachiningModel) -> Timeline {
    let (check, trace) = gearcam_nc::check(text, model);
    assert!(check.ok, "{:?}", check.findings);
    kinematics::from_trace(&trace, model, MachineRates::default()).expect("timeline")
}

/// Cuts the model's blank (sections over its face width) with its hob.
pub(crate) fn cut_program(
    text: &str,
    model: &MachiningModel,
    sections: usize,
    per_tooth: usize,
    res: Resolution,
) -> Blank {
    let tl = timeline(text, model);
    let hob = Hob::from_data(&model.plan.hob, HobExtras::default()).expect("hob");
    let g = &model.plan.gear;
    let h = g.fixture_height_mm;
    let z = Blank::planes(h + 1.0, h + g.face_width_mm - 1.0, sections);
    let r = model.model.blank_od_mm / 2.0;
    let mut blank = Blank::new(z, r, g.teeth as usize * per_tooth).expect("blank");
    cut::cut(&tl, &hob, &mut blank, res).expect("cut");
    blank
}

/// The gaps of an outline: runs of samples below `r_mm`, as (first, last)
/// sample indices (a run may wrap round).
pub(crate) fn gaps(outline: &[f64], r_mm: f64) -> Vec<(usize, usize)> {
    let n = outline.len();
    let Some(start) = (0..n).find(|&i| outline[i] >= r_mm) else {
        return vec![];
    };
    let mut out = vec![];
    let mut run: Option<usize> = None;
    for k in 1..=n {
        let i = (start + k) % n;
        match (outline[i] < r_mm, run) {
            (true, None) => run = Some(i),
            (false, Some(b)) => {
                out.push((b, (i + n - 1) % n));
                run = None;
            }
            _ => {}
        }
    }
    out
}

/// The mean phase of `teeth` gaps: arg Σ exp(i·teeth·θ_gap centre), radians.
pub(crate) fn gap_phase(outline: &[f64], r_mm: f64, teeth: u32) -> f64 {
    let n = outline.len();
    let (mut c, mut s) = (0.0, 0.0);
    for (a, b) in gaps(outline, r_mm) {
        // Threshold crossings interpolated linearly between samples.
        let before = outline[(a + n - 1) % n];
        let after = outline[(b + 1) % n];
        let enter = a as f64 - (r_mm - outline[a]) / (before - outline[a]);
        let leave = b as f64 + (r_mm - outline[b]) / (after - outline[b]);
        let leave = if leave < enter {
            leave + n as f64
        } else {
            leave
        };
        let mid = 0.5 * (enter + leave) * std::f64::consts::TAU / n as f64;
        c += (f64::from(teeth) * mid).cos();
        s += (f64::from(teeth) * mid).sin();
    }
    s.atan2(c)
}
