use super::*;
use crate::db;
use gearcam_proto::Hand;

#[test]
fn every_flat_librarys_table_has_exactly_the_librarys_fields() {
    let conn = db::open_in_memory().unwrap();
    for lib in library::LIBRARIES.iter().filter(|l| !l.fields.is_empty()) {
        let mut stmt = conn
            .prepare(&format!(
                "SELECT name FROM pragma_table_info('{}')",
                lib.table
            ))
            .unwrap();
        let mut columns: Vec<String> = stmt
            .query_map([], |r| r.get(0))
            .unwrap()
            .collect::<Result<_, _>>()
            .unwrap();
        columns.sort();
        let mut fields: Vec<&str> = lib.fields.iter().map(|f| f.name).collect();
        fields.sort_unstable();
        assert_eq!(columns, fields, "{}", lib.name);
    }
}

#[test]
fn the_typed_readers_read_every_seeded_record() {
    let conn = db::open_in_memory().unwrap();
    let ids = |lib: &library::Library| -> Vec<String> {
        library::list(&conn, lib)
            .unwrap()
            .iter()
            .map(|r| library::cell(&r[lib.key]))
            .collect()
    };
    let cases = cases(&conn).unwrap();
    assert_eq!(
        cases.iter().map(|c| c.id.clone()).collect::<Vec<_>>(),
        ids(&library::CASES)
    );
    let bevel = cases.iter().find(|c| c.id == "SEED000-BEVEL-CBR").unwrap();
    assert_eq!(bevel.class, gearcam_proto::GearClass::Conical);
    assert_eq!(bevel.operation, gearcam_proto::Operation::Rough);
    assert_eq!(bevel.outcome, CaseOutcome::Ok);
    assert_eq!(bevel.allowance_mm, Some(2.5));
    assert_eq!(bevel.machine, None);
    let hobs = hobs(&conn).unwrap();
    assert_eq!(
        hobs.iter().map(|h| h.id.clone()).collect::<Vec<_>>(),
        ids(&library::HOBS)
    );
    assert_eq!(hob(&conn, "HOB-M3-80L").unwrap().unwrap().hand, Hand::Left);
    assert_eq!(
        workpieces(&conn)
            .unwrap()
            .iter()
            .map(|w| w.part_number.clone())
            .collect::<Vec<_>>(),
        ids(&library::WORKPIECES)
    );
    let hg = workpiece(&conn, "HG-3003-L").unwrap().unwrap();
    assert_eq!((hg.helix_hand, hg.profile_shift), (Some(Hand::Left), 0.2));
    assert_eq!(
        materials(&conn).unwrap().len(),
        ids(&library::MATERIALS).len()
    );
    let m = material(&conn, " 20crmnti ").unwrap().unwrap();
    assert_eq!(
        (m.name.as_str(), m.material_group.as_str(), m.hardness_hb),
        ("20CrMnTi", "case_hardening_steel", Some(180.0))
    );
    assert_eq!(weights(&conn).unwrap().len(), crate::cbr::FEATURES.len());
    assert_eq!(
        classes(&conn).unwrap().len(),
        ids(&library::CLASSES_LIB).len()
    );
    assert!(jobs(&conn).unwrap().is_empty());
    assert_eq!(machines(&conn).unwrap().len(), 2);
}

#[test]
fn an_unreadable_value_names_the_library_the_record_and_the_field() {
    let conn = db::open_in_memory().unwrap();
    let message = |e: KnowledgeError| match e {
        KnowledgeError::Record {
            library,
            id,
            field,
            detail,
        } => (library, id, field, detail),
        other => panic!("not a record error: {other}"),
    };
    // A text where a number belongs.
    conn.execute("UPDATE hobs SET od_mm = 'big' WHERE id = 'HOB-M2-70'", [])
        .unwrap();
    let (lib, id, field, detail) = message(hobs(&conn).unwrap_err());
    assert_eq!(
        (lib, id.as_str(), field.as_str()),
        ("hobs", "HOB-M2-70", "od_mm")
    );
    assert!(detail.contains("Text"), "{detail}");
    // A text that is not one of the field's choices.
    conn.execute(
        "UPDATE cases SET cut_mode = 'sideways' WHERE id = 'SEED-CASE-M3'",
        [],
    )
    .unwrap();
    let e = cases(&conn).unwrap_err();
    assert_eq!(
        e.to_string(),
        "cases record \"SEED-CASE-M3\", field cut_mode: \"sideways\" is not one of conventional, climb"
    );
    // A number out of the type's range.
    conn.execute(
        "UPDATE workpieces SET teeth = -3 WHERE part_number = 'SP-1001'",
        [],
    )
    .unwrap();
    let (lib, id, field, _) = message(workpiece(&conn, "SP-1001").unwrap_err());
    assert_eq!(
        (lib, id.as_str(), field.as_str()),
        ("workpieces", "SP-1001", "teeth")
    );
    // A machine profile without a field names its path.
    conn.execute(
        "UPDATE machines SET profile_json = json_remove(profile_json, '$.limits.max_hob_rpm') WHERE id = 'H02'",
        [],
    )
    .unwrap();
    let (lib, id, field, detail) = message(machines(&conn).unwrap_err());
    assert_eq!(
        (lib, id.as_str(), field.as_str()),
        ("machines", "H02", "profile_json.limits")
    );
    assert!(detail.contains("missing field `max_hob_rpm`"), "{detail}");
}
