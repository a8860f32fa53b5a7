//! The tolerances against values computed by hand from the formulas (the
//! arithmetic is written out beside each), the rounding rule at its band
//! edges, the class lookup and the scope.

use super::*;
use approx::assert_relative_eq;

/// z = 40, mn = 3 mm, spur, b = 30 mm: d = 120 mm.
fn gear() -> GearData {
    GearData::new(40, 3.0, 0.0, 30.0).unwrap()
}

fn class(a: u8) -> Class {
    Class::new(a).unwrap()
}

#[test]
fn class5_values_match_the_hand_computation() {
    let g = gear();
    assert_relative_eq!(g.reference_diameter_mm, 120.0, epsilon = 1e-12);
    // √120 = 10.954451, √30 = 5.477226.
    let hand = [
        (Item::SinglePitch, 6.32),          // 0.12 + 1.2 + 5
        (Item::CumulativePitch, 20.364948), // 0.24 + 6.024948 + 2.1 + 12
        (Item::ProfileSlope, 5.32),         // 1.2 + 0.12 + 4
        (Item::ProfileForm, 6.65),          // 1.65 + 5
        (Item::ProfileTotal, 8.516156),     // √(28.3024 + 44.2225)
        (Item::HelixSlope, 6.464752),       // 0.547723 + 1.917029 + 4
        (Item::HelixForm, 7.231564),        // 0.766812 + 2.464752 + 4
        (Item::HelixTotal, 9.699924),       // √(41.793012 + 52.295504)
        (Item::Runout, 18.328453),          // 0.9 · 20.364948
    ];
    for (item, want) in hand {
        assert_relative_eq!(class5_um(&g, item), want, max_relative = 1e-6);
    }
}

#[test]
fn rounded_tolerances_of_classes_1_5_6_7_11() {
    let g = gear();
    // (class, item, unrounded by hand, rounded by hand)
    let hand = [
        (5, Item::SinglePitch, 6.32, 6.5),
        (5, Item::CumulativePitch, 20.364948, 20.0),
        (5, Item::ProfileSlope, 5.32, 5.5),
        (5, Item::ProfileForm, 6.65, 6.5),
        (5, Item::ProfileTotal, 8.516156, 8.5),
        (5, Item::HelixSlope, 6.464752, 6.5),
        (5, Item::HelixForm, 7.231564, 7.0),
        (5, Item::HelixTotal, 9.699924, 9.5),
        (5, Item::Runout, 18.328453, 18.0),
        (6, Item::SinglePitch, 8.937830, 9.0), // 6.32 · 1.414214
        (6, Item::CumulativePitch, 28.800386, 29.0),
        (6, Item::ProfileTotal, 12.043662, 12.0),
        (7, Item::SinglePitch, 12.64, 13.0), // 6.32 · 2
        (7, Item::CumulativePitch, 40.729896, 41.0),
        (7, Item::ProfileSlope, 10.64, 11.0),
        (7, Item::ProfileForm, 13.3, 13.0),
        (1, Item::SinglePitch, 1.58, 1.6), // 6.32 / 4
        (1, Item::CumulativePitch, 5.091237, 5.0),
        (1, Item::ProfileSlope, 1.33, 1.3),
        (1, Item::ProfileForm, 1.6625, 1.7),
        (11, Item::SinglePitch, 50.56, 51.0), // 6.32 · 8
        (11, Item::CumulativePitch, 162.919584, 163.0),
    ];
    for (a, item, raw, rounded) in hand {
        assert_relative_eq!(unrounded_um(&g, item, class(a)), raw, max_relative = 1e-6);
        assert_eq!(
            tolerance_um(&g, item, class(a)),
            rounded,
            "class {a} {item:?}"
        );
    }
}

#[test]
fn the_rounding_rule_at_its_band_edges() {
    for (raw, want) in [
        (12.49, 12.0),
        (12.5, 13.0),
        (10.4, 10.0), // above 10: integer
        (10.0, 10.0), // 10 itself is in the 0.5 band
        (9.74, 9.5),
        (9.76, 10.0),
        (7.2, 7.0),
        (7.3, 7.5),
        (5.0, 5.0),
        (4.96, 5.0), // below 5: 0.1 µm
        (4.94, 4.9),
        (1.25, 1.3),
        (0.04, 0.0),
    ] {
        assert_eq!(round_um(raw), want, "{raw}");
    }
}

#[test]
fn the_step_between_classes_is_root_two() {
    let g = gear();
    for item in Item::ALL {
        for a in 1..=10 {
            let ratio = unrounded_um(&g, item, class(a + 1)) / unrounded_um(&g, item, class(a));
            assert_relative_eq!(ratio, std::f64::consts::SQRT_2, max_relative = 1e-12);
        }
        assert_relative_eq!(unrounded_um(&g, item, class(5)), class5_um(&g, item));
    }
}

#[test]
fn a_deviation_meets_the_finest_class_whose_tolerance_it_does_not_exceed() {
    let g = gear();
    let fp = Item::SinglePitch;
    // fpT: class 5 6.5, class 6 9.0, class 7 13, class 11 51 (above).
    assert_eq!(grade(&g, fp, 0.0).unwrap(), Grade::Class(class(1)));
    assert_eq!(grade(&g, fp, 6.5).unwrap(), Grade::Class(class(5)));
    assert_eq!(grade(&g, fp, 6.6).unwrap(), Grade::Class(class(6)));
    assert_eq!(grade(&g, fp, 9.0).unwrap(), Grade::Class(class(6)));
    assert_eq!(grade(&g, fp, 9.01).unwrap(), Grade::Class(class(7)));
    assert_eq!(grade(&g, fp, 51.0).unwrap(), Grade::Class(class(11)));
    assert_eq!(grade(&g, fp, 51.5).unwrap(), Grade::WorseThan11);
    // A slope is ±: −5.5 µm meets fHαT = 5.5 of class 5.
    assert_eq!(
        grade(&g, Item::ProfileSlope, -5.5).unwrap(),
        Grade::Class(class(5))
    );
    assert!(grade(&g, fp, f64::NAN).is_err());
}

#[test]
fn the_overall_grade_is_the_worst_item() {
    let g = gear();
    let measured = [
        (Item::SinglePitch, 6.0),      // class 5
        (Item::CumulativePitch, 29.0), // class 6
        (Item::ProfileTotal, 17.0),    // FαT class 7 = 17.03 → 17: class 7
        (Item::HelixTotal, 1.0),       // class 1 or so
    ];
    assert_eq!(
        overall_grade(&g, &measured).unwrap(),
        Grade::Class(class(7))
    );
    assert!(overall_grade(&g, &[]).is_err());
    let bad = [(Item::SinglePitch, 6.0), (Item::Runout, 1000.0)];
    assert_eq!(overall_grade(&g, &bad).unwrap(), Grade::WorseThan11);
}

#[test]
fn inputs_outside_the_scope_name_the_field_the_range_and_the_value() {
    let field = |r: Result<GearData, Error>| match r {
        Err(Error::OutOfRange { field, got, .. }) => (field, got),
        other => panic!("{other:?}"),
    };
    assert_eq!(field(GearData::new(4, 3.0, 0.0, 30.0)), ("teeth", 4.0));
    assert_eq!(
        field(GearData::new(1001, 3.0, 0.0, 30.0)),
        ("teeth", 1001.0)
    );
    assert_eq!(
        field(GearData::new(40, 0.4, 0.0, 30.0)),
        ("normal_module_mm", 0.4)
    );
    assert_eq!(
        field(GearData::new(40, 3.0, -46.0, 30.0)),
        ("helix_deg", -46.0)
    );
    assert_eq!(
        field(GearData::new(40, 3.0, 0.0, 3.9)),
        ("face_width_mm", 3.9)
    );
    assert_eq!(
        field(GearData::new(40, 3.0, 0.0, f64::NAN)).0,
        "face_width_mm"
    );
    // z = 1000, mn = 20: d = 20 000 mm.
    assert_eq!(
        field(GearData::new(1000, 20.0, 0.0, 30.0)),
        ("reference_diameter_mm", 20_000.0)
    );
    // z = 5, mn = 0.5: d = 2.5 mm.
    assert_eq!(
        field(GearData::new(5, 0.5, 0.0, 30.0)).0,
        "reference_diameter_mm"
    );
    let msg = GearData::new(40, 3.0, 0.0, 3.9).unwrap_err().to_string();
    assert!(
        msg.contains("face_width_mm") && msg.contains("4 mm ≤ b ≤ 1200 mm") && msg.contains("3.9"),
        "{msg}"
    );
    assert!(Class::new(0).is_err() && Class::new(12).is_err() && Class::new(11).is_ok());
    // Edges of the scope are inside it.
    assert!(GearData::new(5, 1.0, 45.0, 4.0).is_ok());
    assert!(GearData::new(1000, 15.0, 0.0, 1200.0).is_ok());
}
