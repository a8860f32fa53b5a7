//! Group-technology classes of gears (docs/knowledge.md#group-technology-classes, seed 000 §2.1) and the rule
//! that puts a job into one of them.
//!
//! The class tree: cylindrical (spur, helical), conical involute, worm wheel,
//! crowned and curved-tooth are unit classes; multi-gear is derived (two or
//! more units on one part, each of its own unit class). A job file marks its
//! class with one of the `[gear.cone]`, `[gear.crowning]`, `[gear.worm_wheel]`,
//! `[gear.curved_tooth]` tables, or with `[[units]]`; none of them means
//! cylindrical.

use serde::{Deserialize, Serialize};

use crate::job::{GearSpec, UnitSpec};

/// A gear class of the group-technology tree.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Default, Serialize, Deserialize,
)]
#[serde(rename_all = "snake_case")]
pub enum GearClass {
    /// Spur and helical gears: axial (or radial-axial) hobbing, the patent's model.
    #[default]
    Cylindrical,
    /// Conical involute gears (beveloids): X follows Z along the cone angle.
    Conical,
    /// Worm wheels: radial or tangential infeed.
    WormWheel,
    /// Crowned (barrel) gears: X follows Z on the crowning curve.
    Crowned,
    /// Gears with a curved tooth trace: classified, not yet programmable.
    CurvedTooth,
    /// Two or more units on one part, each of its own unit class.
    MultiGear,
}

impl GearClass {
    /// Every class, in the order of the tree.
    pub const ALL: [GearClass; 6] = [
        GearClass::Cylindrical,
        GearClass::Conical,
        GearClass::WormWheel,
        GearClass::Crowned,
        GearClass::CurvedTooth,
        GearClass::MultiGear,
    ];

    /// The class's name as written in plans, models and template ids.
    pub fn as_str(self) -> &'static str {
        match self {
            GearClass::Cylindrical => "cylindrical",
            GearClass::Conical => "conical",
            GearClass::WormWheel => "worm_wheel",
            GearClass::Crowned => "crowned",
            GearClass::CurvedTooth => "curved_tooth",
            GearClass::MultiGear => "multi_gear",
        }
    }

    /// The class of a name written by [`GearClass::as_str`].
    pub fn parse(name: &str) -> Option<GearClass> {
        GearClass::ALL.into_iter().find(|c| c.as_str() == name)
    }

    /// True when gearcam can compute a machining model for the class.
    pub fn programmable(self) -> bool {
        self != GearClass::CurvedTooth
    }
}

impl std::fmt::Display for GearClass {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// Every unit-class marker a gear carries, in priority order (curved tooth,
/// worm wheel, conical, crowned). More than one is a contradiction the model
/// service reports; none means cylindrical.
pub fn unit_markers(gear: &GearSpec) -> Vec<GearClass> {
    let mut found = Vec::new();
    if gear.curved_tooth.is_some() {
        found.push(GearClass::CurvedTooth);
    }
    if gear.worm_wheel.is_some() {
        found.push(GearClass::WormWheel);
    }
    if gear.cone.is_some() {
        found.push(GearClass::Conical);
    }
    if gear.crowning.is_some() {
        found.push(GearClass::Crowned);
    }
    found
}

/// The unit class of one gear: its first marker, or cylindrical.
pub fn unit_class(gear: &GearSpec) -> GearClass {
    unit_markers(gear)
        .first()
        .copied()
        .unwrap_or(GearClass::Cylindrical)
}

/// The class of a job whose (resolved) gear is `gear`: multi-gear when it has
/// `[[units]]`, else the unit class of its gear.
pub fn classify(gear: &GearSpec, units: &[UnitSpec]) -> GearClass {
    if units.is_empty() {
        unit_class(gear)
    } else {
        GearClass::MultiGear
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::job::JobSpec;

    fn class_of(s: &JobSpec) -> GearClass {
        let h = s.hobbing().expect("a hobbing job");
        classify(h.gear.as_ref().expect("a gear"), &h.units)
    }

    /// A job from JSON: a spur gear plus `gear_extra` keys in `[gear]` and
    /// `top_extra` keys at the top level.
    fn spec(gear_extra: &str, top_extra: &str) -> JobSpec {
        let text = format!(
            r#"{{"job": {{"machine": "H01", "part_number": "P"}},
                "gear": {{"module_mm": 2.0, "teeth": 19, "face_width_mm": 20.0,
                          "fixture_height_mm": 40.0 {gear_extra}}} {top_extra}}}"#
        );
        serde_json::from_str(&text).unwrap_or_else(|e| panic!("{e}\n{text}"))
    }

    #[test]
    fn a_job_without_markers_is_cylindrical() {
        assert_eq!(class_of(&spec("", "")), GearClass::Cylindrical);
    }

    #[test]
    fn each_marker_names_its_class() {
        for (extra, class) in [
            (r#", "cone": {"angle_deg": 6.5}"#, GearClass::Conical),
            (r#", "crowning": {"amount_mm": 0.02}"#, GearClass::Crowned),
            (
                r#", "worm_wheel": {"infeed": "radial"}"#,
                GearClass::WormWheel,
            ),
            (
                r#", "curved_tooth": {"trace_radius_mm": 100.0}"#,
                GearClass::CurvedTooth,
            ),
        ] {
            assert_eq!(class_of(&spec(extra, "")), class, "{extra}");
        }
        let units = r#", "units": [{"z_offset_mm": 40.0, "gear": {"module_mm": 2.0,
            "teeth": 30, "face_width_mm": 15.0, "fixture_height_mm": 40.0}}]"#;
        assert_eq!(class_of(&spec("", units)), GearClass::MultiGear);
    }

    #[test]
    fn several_markers_are_all_listed_in_priority_order() {
        let s = spec(
            r#", "cone": {"angle_deg": 6.5}, "curved_tooth": {"trace_radius_mm": 80.0}"#,
            "",
        );
        assert_eq!(
            unit_markers(s.hobbing().unwrap().gear.as_ref().unwrap()),
            vec![GearClass::CurvedTooth, GearClass::Conical]
        );
        assert_eq!(class_of(&s), GearClass::CurvedTooth);
    }

    #[test]
    fn names_round_trip_and_only_curved_teeth_are_not_programmable() {
        for c in GearClass::ALL {
            assert_eq!(GearClass::parse(c.as_str()), Some(c));
            assert_eq!(c.programmable(), c != GearClass::CurvedTooth);
        }
        assert_eq!(GearClass::parse("bevel"), None);
    }
}
