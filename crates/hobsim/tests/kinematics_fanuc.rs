//! FANUC EGB programs (`G81 T L [Q P]` … `G80`) on the virtual machine: the
//! same teeth, root and helix as the 840D programs of `real_programs.rs`.

mod common;

use gearcam_hobsim::cut::Resolution;
use gearcam_proto::MachiningModel;

const COARSE: Resolution = Resolution {
    axial_step_mm: 1.0,
    tolerance_mm: 1e-3,
};

/// A FANUC program and its model from `crates/hobsim/tests/programs`.
fn fanuc(name: &str) -> (String, MachiningModel) {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/programs/");
    let text = std::fs::read_to_string(format!("{dir}{name}.nc")).expect("program");
    let json = std::fs::read_to_string(format!("{dir}{name}.model.json")).expect("model");
    (text, serde_json::from_str(&json).expect("model reads"))
}

fn wrap(d: f64) -> f64 {
    (d + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI
}

#[test]
fn the_fanuc_spur_program_cuts_25_teeth_to_the_root_diameter() {
    let (text, model) = fanuc("spur_fanuc");
    assert!(text.contains("G81 T25 L1") && text.contains("G80"));
    let blank = common::cut_program(&text, &model, 9, 24, COARSE);
    let geo = &model.geometry;
    let df2 = geo.df_mm / 2.0;
    for (j, outline) in blank.r_mm.iter().enumerate() {
        let gaps = common::gaps(outline, geo.d_mm / 2.0);
        assert_eq!(gaps.len(), 25, "section {j}: {} gaps", gaps.len());
        let root = outline.iter().cloned().fold(f64::MAX, f64::min);
        // As the 840D spur test: the tip reaches df/2, never deeper; a
        // feed mark f²/(4·da0) = 2²/320 mm plus the sampling above.
        assert!(
            root > df2 - 1e-3 && root < df2 + 0.0125 + 0.01,
            "section {j}: root radius {root}"
        );
    }
    let p0 = common::gap_phase(&blank.r_mm[0], geo.d_mm / 2.0, 25);
    for (j, o) in blank.r_mm.iter().enumerate() {
        let d = wrap(common::gap_phase(o, geo.d_mm / 2.0, 25) - p0);
        assert!(
            d.abs() < 0.05,
            "section {j}: spur gaps turned by {d} rad (z·θ)"
        );
    }
}

/// Right-hand β 15° cut climb with a left-hand hob (`L-1`, `P15.0`): the
/// gaps turn with height as θ(z) = θ₀ + s_g·2π·z/Pz, s_g = +1.
#[test]
fn the_fanuc_helical_program_cuts_the_right_hand_helix() {
    let (text, model) = fanuc("helical_climb_fanuc");
    assert!(text.contains("G81 T25 L-1 Q3.0 P15.0"));
    let blank = common::cut_program(&text, &model, 9, 16, COARSE);
    let geo = &model.geometry;
    let z = model.plan.gear.teeth;
    let lead = geo.lead_mm.expect("helical lead");
    let r = geo.d_mm / 2.0;
    for (j, outline) in blank.r_mm.iter().enumerate() {
        assert_eq!(common::gaps(outline, r).len(), z as usize, "section {j}");
        let root = outline.iter().cloned().fold(f64::MAX, f64::min);
        assert!(
            root > geo.df_mm / 2.0 - 2e-3 && root < geo.df_mm / 2.0 + 0.03,
            "section {j}: root radius {root}"
        );
    }
    let p0 = common::gap_phase(&blank.r_mm[0], r, z);
    for (j, outline) in blank.r_mm.iter().enumerate().skip(1) {
        let dz = blank.z_mm[j] - blank.z_mm[0];
        let want = std::f64::consts::TAU * dz / lead * f64::from(z);
        let d = wrap(common::gap_phase(outline, r, z) - p0 - want);
        assert!(d.abs() < 0.02, "section {j}: phase off by {d} rad (z·θ)");
    }
}
