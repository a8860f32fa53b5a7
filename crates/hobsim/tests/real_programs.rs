//! Real programs run on the virtual machine: the cut gear has the model's
//! teeth, root and helix.

mod common;

use gearcam_hobsim::cut::Resolution;

const COARSE: Resolution = Resolution {
    axial_step_mm: 1.0,
    tolerance_mm: 1e-3,
};

#[test]
fn the_spur_program_cuts_25_teeth_to_the_root_diameter() {
    let (text, model) = common::program("spur_840d");
    let blank = common::cut_program(&text, &model, 9, 24, COARSE);
    let geo = &model.geometry;
    for (j, outline) in blank.r_mm.iter().enumerate() {
        let gaps = common::gaps(outline, geo.d_mm / 2.0);
        assert_eq!(
            gaps.len(),
            25,
            "section {j}: {} gaps at the reference circle",
            gaps.len()
        );
        let root = outline.iter().cloned().fold(f64::MAX, f64::min);
        // The hob's tip reaches X − da0/2 = df/2 (73.75 − 40 = 33.75), never
        // deeper; a section between two feed marks keeps up to f²/(4·da0)
        // (docs/simulation.md), 2²/320 = 0.0125 mm, plus the sampling.
        let df2 = geo.df_mm / 2.0;
        assert!(
            root > df2 - 1e-3 && root < df2 + 0.0125 + 0.01,
            "section {j}: root radius {root}"
        );
    }
    // A spur gear's gaps stand at the same angles in every section.
    let phases: Vec<f64> = blank
        .r_mm
        .iter()
        .map(|o| common::gap_phase(o, geo.d_mm / 2.0, 25))
        .collect();
    for p in &phases {
        let d = (p - phases[0] + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU)
            - std::f64::consts::PI;
        assert!(d.abs() < 0.05, "phases {phases:?}");
    }
}

/// The helical program: the gaps turn with height along the gear's helix,
/// θ(z) = θ₀ + s_g·2π·z/Pz (`docs/hobbing.md` §2), left hand here.
#[test]
fn the_helical_program_cuts_the_left_hand_helix() {
    let (text, model) = common::program("helical_climb_840d");
    let blank = common::cut_program(&text, &model, 9, 16, COARSE);
    let geo = &model.geometry;
    let z = model.plan.gear.teeth;
    let lead = geo.lead_mm.expect("helical lead");
    let s_g = -1.0;
    let r = geo.d_mm / 2.0;
    for (j, outline) in blank.r_mm.iter().enumerate() {
        assert_eq!(common::gaps(outline, r).len(), z as usize, "section {j}");
    }
    let p0 = common::gap_phase(&blank.r_mm[0], r, z);
    for (j, outline) in blank.r_mm.iter().enumerate().skip(1) {
        let dz = blank.z_mm[j] - blank.z_mm[0];
        let want = s_g * std::f64::consts::TAU * dz / lead * f64::from(z);
        let got = common::gap_phase(outline, r, z) - p0;
        let d = (got - want + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU)
            - std::f64::consts::PI;
        assert!(d.abs() < 0.02, "section {j}: phase off by {d} rad (z·θ)");
    }
}
