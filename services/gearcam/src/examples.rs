//! The example jobs bundled into the binary (`gearcam demo`), one or more per
//! gear class, and the invalid ones with the error code each must get. The
//! tests read the same list (and check it holds every file of `examples/`).

/// The example jobs `gearcam demo` submits, bundled into the binary: one or
/// more per gear class, every spiral face milling variant (circle,
/// annulus, planar spiral groove; each program form), and wire EDM punches
/// and dies (3B, 4B, ISO; a quarter, a whole odd gear, an undercut pinion).
pub const VALID: &[(&str, &str)] = &[
    (
        "examples/spur_840d.toml",
        include_str!("../../../examples/spur_840d.toml"),
    ),
    (
        "examples/spur_by_part_840d.toml",
        include_str!("../../../examples/spur_by_part_840d.toml"),
    ),
    (
        "examples/helical_840d.toml",
        include_str!("../../../examples/helical_840d.toml"),
    ),
    (
        "examples/helical_climb_840d.toml",
        include_str!("../../../examples/helical_climb_840d.toml"),
    ),
    (
        "examples/helical_left_840d.toml",
        include_str!("../../../examples/helical_left_840d.toml"),
    ),
    (
        "examples/helical_climb_fanuc.toml",
        include_str!("../../../examples/helical_climb_fanuc.toml"),
    ),
    (
        "examples/multi_cut_shift_840d.toml",
        include_str!("../../../examples/multi_cut_shift_840d.toml"),
    ),
    (
        "examples/conical_840d.toml",
        include_str!("../../../examples/conical_840d.toml"),
    ),
    (
        "examples/crowned_840d.toml",
        include_str!("../../../examples/crowned_840d.toml"),
    ),
    (
        "examples/crowned_parabolic_840d.toml",
        include_str!("../../../examples/crowned_parabolic_840d.toml"),
    ),
    (
        "examples/worm_wheel_840d.toml",
        include_str!("../../../examples/worm_wheel_840d.toml"),
    ),
    (
        "examples/worm_wheel_tangential_840d.toml",
        include_str!("../../../examples/worm_wheel_tangential_840d.toml"),
    ),
    (
        "examples/helical_shift_fanuc.toml",
        include_str!("../../../examples/helical_shift_fanuc.toml"),
    ),
    (
        "examples/multi_gear_840d.toml",
        include_str!("../../../examples/multi_gear_840d.toml"),
    ),
    (
        "examples/face_annulus_fanuc.toml",
        include_str!("../../../examples/face_annulus_fanuc.toml"),
    ),
    (
        "examples/face_circle_arcs_fanuc.toml",
        include_str!("../../../examples/face_circle_arcs_fanuc.toml"),
    ),
    (
        "examples/face_chords_fanuc.toml",
        include_str!("../../../examples/face_chords_fanuc.toml"),
    ),
    (
        "examples/face_circle_linuxcnc.toml",
        include_str!("../../../examples/face_circle_linuxcnc.toml"),
    ),
    (
        "examples/groove_fanuc.toml",
        include_str!("../../../examples/groove_fanuc.toml"),
    ),
    (
        "examples/groove_linuxcnc.toml",
        include_str!("../../../examples/groove_linuxcnc.toml"),
    ),
    (
        "examples/die_m2z20_3b.toml",
        include_str!("../../../examples/die_m2z20_3b.toml"),
    ),
    (
        "examples/punch_m2z20_4b.toml",
        include_str!("../../../examples/punch_m2z20_4b.toml"),
    ),
    (
        "examples/die_m1z40_iso.toml",
        include_str!("../../../examples/die_m1z40_iso.toml"),
    ),
    (
        "examples/punch_m15z23_3b.toml",
        include_str!("../../../examples/punch_m15z23_3b.toml"),
    ),
    (
        "examples/punch_pinion_undercut_iso.toml",
        include_str!("../../../examples/punch_pinion_undercut_iso.toml"),
    ),
];

/// Invalid jobs `gearcam demo` submits to show typed refusals; each file names
/// the error code it must get in a `# expect: CODE` line.
pub const INVALID: &[(&str, &str)] = &[
    (
        "examples/invalid_base_pitch.toml",
        include_str!("../../../examples/invalid_base_pitch.toml"),
    ),
    (
        "examples/invalid_two_classes.toml",
        include_str!("../../../examples/invalid_two_classes.toml"),
    ),
    (
        "examples/invalid_crowning.toml",
        include_str!("../../../examples/invalid_crowning.toml"),
    ),
    (
        "examples/invalid_shift_range.toml",
        include_str!("../../../examples/invalid_shift_range.toml"),
    ),
    (
        "examples/invalid_curved_tooth.toml",
        include_str!("../../../examples/invalid_curved_tooth.toml"),
    ),
    (
        "examples/invalid_unknown_part.toml",
        include_str!("../../../examples/invalid_unknown_part.toml"),
    ),
    (
        "examples/invalid_face_inner_radius.toml",
        include_str!("../../../examples/invalid_face_inner_radius.toml"),
    ),
    (
        "examples/invalid_face_step_over.toml",
        include_str!("../../../examples/invalid_face_step_over.toml"),
    ),
    (
        "examples/invalid_face_tool_too_large.toml",
        include_str!("../../../examples/invalid_face_tool_too_large.toml"),
    ),
    (
        "examples/invalid_groove_turns.toml",
        include_str!("../../../examples/invalid_groove_turns.toml"),
    ),
    (
        "examples/invalid_face_on_hobbing_machine.toml",
        include_str!("../../../examples/invalid_face_on_hobbing_machine.toml"),
    ),
    (
        "examples/invalid_die_teeth.toml",
        include_str!("../../../examples/invalid_die_teeth.toml"),
    ),
    (
        "examples/invalid_die_tip_too_sharp.toml",
        include_str!("../../../examples/invalid_die_tip_too_sharp.toml"),
    ),
    (
        "examples/invalid_die_wire_too_thick.toml",
        include_str!("../../../examples/invalid_die_wire_too_thick.toml"),
    ),
];

/// The code an invalid example expects (its `# expect:` line).
pub fn expected_code(text: &str) -> Option<&str> {
    text.lines()
        .find_map(|l| l.trim().strip_prefix("# expect:"))
        .map(str::trim)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The bundled lists hold every file of `examples/`, each in the right
    /// list, with the text of the file.
    #[test]
    fn the_bundle_is_the_examples_directory() {
        let bundled: Vec<(String, String)> = VALID
            .iter()
            .chain(INVALID)
            .map(|(path, text)| {
                let name = path.trim_start_matches("examples/").to_string();
                (name, text.to_string())
            })
            .collect();
        let mut sorted = bundled.clone();
        sorted.sort();
        assert_eq!(sorted, gearcam_testkit::examples::all());
        for (_, text) in VALID {
            assert_eq!(expected_code(text), None);
        }
        for (path, text) in INVALID {
            assert!(expected_code(text).is_some(), "{path}");
        }
    }
}
