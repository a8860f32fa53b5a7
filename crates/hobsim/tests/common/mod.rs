//! Helpers the integration tests share: the real programs, and what a gear
//! measuring machine would read from the cut outlines.
#![allow(dead_code)]

use gearcam_hobsim::cut::{self, Blank, Resolution};
use gearcam_hobsim::hob::{Hob, HobExtras};
use gearcam_hobsim::kinematics::{self, Axes, Gearbox, MachineRates, Segment, Timeline};
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

/// The closed-form set-ups' gear: module 10, α 20°, 20 teeth.
pub(crate) const SET_UP_MN: f64 = 10.0;
/// Its teeth.
pub(crate) const SET_UP_Z: u32 = 20;

/// A right-hand hob of the set-ups' module and pressure angle, reference
/// radius `r0`, addendum and dedendum 1.25·mn, 100 mm long, `gashes`
/// straight gashes, tip corners of radius `corner_mm`.
pub(crate) fn rack_hob(r0: f64, starts: u32, gashes: u32, corner_mm: f64) -> Hob {
    let mn = SET_UP_MN;
    let g0 = (f64::from(starts) * mn / (2.0 * r0)).asin();
    Hob {
        starts,
        hand: 1.0,
        tip_radius_mm: r0 + 1.25 * mn,
        ref_radius_mm: r0,
        root_radius_mm: r0 - 1.25 * mn,
        axial_pitch_mm: std::f64::consts::PI * mn / g0.cos(),
        tan_alpha_x: 20f64.to_radians().tan() / g0.cos(),
        length_mm: 100.0,
        gashes,
        tip_corner_radius_mm: corner_mm,
        cos_lead: g0.cos(),
    }
}

/// The set-ups' spur plunge: the hob at X = r + r0 (no profile shift),
/// Z 50, for `turns` table turns, η = −s_h·γ0, C/B = s_h·z0/z, the hob at
/// 1 turn/s.
pub(crate) fn spur_plunge(h: &Hob, turns: f64) -> Timeline {
    spur_feed(h, 50.0, 50.0, turns)
}

/// One coupled move of the hob at the set-up's centre distance from `z0`
/// to `z1` over `turns` table turns (hob at 1 turn/s), the spur set-up's
/// swivel η = −s_h·γ0 and ratio C/B = s_h·z0/z (`docs/hobbing.md` §2).
pub(crate) fn spur_feed(h: &Hob, z0: f64, z1: f64, turns: f64) -> Timeline {
    let g0 = (f64::from(h.starts) * SET_UP_MN / (2.0 * h.ref_radius_mm)).asin();
    let ratio = h.hand * f64::from(h.starts) / f64::from(SET_UP_Z);
    let at = |z_mm| Axes {
        x_mm: SET_UP_MN * f64::from(SET_UP_Z) / 2.0 + h.ref_radius_mm,
        y_mm: 0.0,
        z_mm,
    };
    Timeline::from_segments(vec![Segment {
        line: 0,
        t0_s: 0.0,
        t1_s: turns / ratio.abs(),
        from: at(z0),
        to: at(z1),
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
