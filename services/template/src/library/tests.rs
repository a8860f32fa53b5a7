use super::*;

fn source(class: &str, version: u32, body: &str) -> String {
    format!(
        "# test template\n@template {class}_840d\n@class {class}\n@dialect sinumerik840d\n@version {version}\n{body}"
    )
}

const CYL: &str = "main :: %{program.file}\n\
    main :: ;$PATH=/_N_MPF_DIR\n\
    conditions if: options.coolant :: {N()} M{mc.coolant_on} ; COOLANT ON\n\
    synchronous/unit :: {N()} R1={nc(u.module)}\n\
    motion/move calc: w = \" X=\" + nc(m.x); v = \"a; b\" if: m.kind == \"rapid\" :: {N()} G0 G90{w}\n\
    motion/move if: m.kind == \"feed\" :: {N()} G1 G94{w} F={nc(m.feed)}\n\
    conditions if: options.coolant :: {N()} M{mc.coolant_off}\n\
    main :: {N()} M30\n";

const CON: &str = "main :: %{program.file}\n\
    main :: ;$PATH=/_N_MPF_DIR\n\
    main :: ; CONE ANGLE {deg(cone)}\n\
    conditions if: options.coolant :: {N()} M{mc.coolant_on} ; COOLANT ON\n\
    synchronous/unit :: {N()} R1={nc(u.module)}\n\
    motion/move when: has(m.x) calc: w = \" X=\" + nc(m.x) :: {N()} G1 G94{w} F={nc(m.feed)}\n\
    main :: {N()} M30\n";

fn file(text: &str) -> TemplateFile {
    stdcode::parse("test.tpl", text).unwrap()
}

fn count(lib: &Library, sql: &str) -> i64 {
    lib.conn.query_row(sql, [], |r| r.get(0)).unwrap()
}

fn import(lib: &mut Library, texts: &[&str]) -> Result<ImportReport, LibraryError> {
    let files: Vec<TemplateFile> = texts.iter().map(|t| file(t)).collect();
    lib.import(&files, texts, 1_700_000_000_000)
}

#[test]
fn two_classes_share_their_similar_lines_and_assemble_back_exactly() {
    let dir = tempfile::tempdir().unwrap();
    let mut lib = Library::open(&dir.path().join("data/templates.db")).unwrap();
    assert_eq!(lib.schema_version().unwrap(), 1);
    let (cyl, con) = (source("cylindrical", 1, CYL), source("conical", 1, CON));
    let report = import(&mut lib, &[&cyl, &con]).unwrap();
    assert_eq!(report.added.len(), 2);
    assert!(report.skipped.is_empty());

    // Shared by both: main %, main $PATH, coolant on, R1, M30 = 5 similar
    // components stored once. Own: cylindrical's 2 moves + coolant off,
    // conical's cone line + move = 5.
    assert_eq!(
        count(
            &lib,
            "SELECT count(*) FROM components WHERE kind = 'similar'"
        ),
        5
    );
    assert_eq!(
        count(
            &lib,
            "SELECT count(*) FROM components WHERE kind = 'similar' AND text = 'main :: {N()} M30'"
        ),
        1
    );
    assert_eq!(
        count(
            &lib,
            "SELECT count(*) FROM components WHERE kind = 'non_similar'"
        ),
        5
    );
    assert_eq!(count(&lib, "SELECT count(*) FROM records"), 15);
    assert_eq!(
        report.components,
        ComponentCount {
            similar: 5,
            non_similar: 5
        }
    );
    // The analysis agrees with the database row for row.
    let total = report.similarity.dialects[0].total;
    assert_eq!(
        (total.lines, total.lines_stored, total.lines_saved),
        (15, 10, 5)
    );

    // Assembly gives back the parsed sources exactly (ID, N, line, clauses).
    assert_eq!(lib.assemble("cylindrical_840d", None).unwrap(), file(&cyl));
    assert_eq!(lib.assemble("conical_840d", Some(1)).unwrap(), file(&con));
    assert_eq!(lib.latest_versions().unwrap(), vec![file(&con), file(&cyl)]);

    // The decision table names T as "module, kind" and keeps S `;`-joined.
    let table = lib.show("cylindrical_840d", None).unwrap();
    assert_eq!(table.rows.len(), 8);
    let r5 = &table.rows[4];
    assert_eq!(r5.t, "motion, non-similar");
    assert_eq!((r5.id, r5.n, r5.scope.as_str()), (5, 1, "move"));
    assert_eq!(
        r5.calc.as_deref(),
        Some("w = \" X=\" + nc(m.x); v = \"a; b\"")
    );
    assert_eq!(r5.out_if.as_deref(), Some("m.kind == \"rapid\""));
    assert_eq!(table.rows[7].t, "main, similar");
    assert_eq!(table.rows[7].n, 3);
    let shown = table.to_string();
    assert!(
        shown.contains("cylindrical_840d version 1 (class cylindrical, sinumerik840d), 8 records"),
        "{shown}"
    );

    let list = lib.list().unwrap();
    assert_eq!(list.len(), 2);
    assert_eq!(list[1].id, "cylindrical_840d");
    assert_eq!(
        (
            list[1].version,
            list[1].records,
            list[1].similar,
            list[1].non_similar
        ),
        (1, 8, 5, 3)
    );
    assert_eq!(list[1].versions, vec![1]);
}

#[test]
fn versions_unchanged_skipped_unbumped_refused_bumped_kept_beside() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("templates.db");
    let mut lib = Library::open(&path).unwrap();
    let (cyl, con) = (source("cylindrical", 1, CYL), source("conical", 1, CON));
    import(&mut lib, &[&cyl, &con]).unwrap();

    // Unchanged: skipped, nothing written.
    let again = import(&mut lib, &[&cyl, &con]).unwrap();
    assert!(again.added.is_empty());
    assert_eq!(again.skipped.len(), 2);
    assert_eq!(count(&lib, "SELECT count(*) FROM template_versions"), 2);

    // Changed text, same @version: refused, naming template, line and versions.
    let changed = source("cylindrical", 1, &CYL.replace("M30", "M2"));
    let e = import(&mut lib, &[&changed]).unwrap_err();
    assert!(
        matches!(e, LibraryError::VersionNotBumped { ref id, line: 5, stored: 1, given: 1 } if id == "cylindrical_840d"),
        "{e:?}"
    );
    let msg = e.to_string();
    assert!(
        msg.contains("template cylindrical_840d, line 5")
            && msg.contains("expected @version 2 or higher, got @version 1: bump @version"),
        "{msg}"
    );

    // Bumped: version 2 beside 1.
    let v2 = source("cylindrical", 2, &CYL.replace("M30", "M2"));
    let r = import(&mut lib, &[&v2, &con]).unwrap();
    assert_eq!(
        r.added,
        vec![Added {
            id: "cylindrical_840d".into(),
            version: 2,
            previous: Some(1),
            records: 8
        }]
    );
    assert_eq!(r.skipped.len(), 1);
    assert_eq!(lib.assemble("cylindrical_840d", None).unwrap(), file(&v2));
    assert_eq!(
        lib.assemble("cylindrical_840d", Some(1)).unwrap(),
        file(&cyl)
    );
    assert_eq!(lib.list().unwrap()[1].versions, vec![1, 2]);
    // M30 is now conical's alone: a non-similar component of conical;
    // version 1 of cylindrical still uses the similar M30, so it stays too.
    assert_eq!(
        count(
            &lib,
            "SELECT count(*) FROM components WHERE text = 'main :: {N()} M30'"
        ),
        2
    );
    assert_eq!(
        lib.show("conical_840d", None).unwrap().rows[6].t,
        "main, non-similar"
    );

    // An older version than the library's latest: refused.
    let e = import(&mut lib, &[&source("cylindrical", 1, "main :: M2\n")]).unwrap_err();
    assert!(
        matches!(
            e,
            LibraryError::VersionBehind {
                stored: 2,
                given: 1,
                ..
            }
        ),
        "{e:?}"
    );

    // Reopening keeps everything; the schema is not migrated twice.
    drop(lib);
    let lib = Library::open(&path).unwrap();
    assert_eq!(lib.assemble("cylindrical_840d", None).unwrap().version, 2);
    assert_eq!(lib.schema_version().unwrap(), 1);
}

#[test]
fn a_line_a_new_version_shares_becomes_similar_for_the_other_class_too() {
    let dir = tempfile::tempdir().unwrap();
    let mut lib = Library::open(&dir.path().join("t.db")).unwrap();
    let (cyl, con) = (source("cylindrical", 1, CYL), source("conical", 1, CON));
    import(&mut lib, &[&cyl, &con]).unwrap();
    let cone = "main :: ; CONE ANGLE {deg(cone)}";
    let sql = format!("SELECT count(*) FROM components WHERE text = '{cone}'");
    assert_eq!(count(&lib, &sql), 1);
    assert_eq!(
        lib.show("conical_840d", None).unwrap().rows[2].t,
        "main, non-similar"
    );

    // Cylindrical version 2 gets conical's own line: it is stored once, as
    // a similar component, and conical's record points at it; conical's
    // non-similar copy is gone and conical still assembles to its source.
    let v2 = source("cylindrical", 2, &format!("{cone}\n{CYL}"));
    let r = import(&mut lib, &[&v2]).unwrap();
    assert_eq!(r.added.len(), 1);
    assert_eq!(count(&lib, &sql), 1);
    assert_eq!(count(&lib, &format!("{sql} AND kind = 'similar'")), 1);
    assert_eq!(
        lib.show("conical_840d", None).unwrap().rows[2].t,
        "main, similar"
    );
    assert_eq!(lib.assemble("conical_840d", None).unwrap(), file(&con));
    assert_eq!(lib.assemble("cylindrical_840d", None).unwrap(), file(&v2));
    assert_eq!(
        lib.assemble("cylindrical_840d", Some(1)).unwrap(),
        file(&cyl)
    );
}

#[test]
fn a_failed_import_stores_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let mut lib = Library::open(&dir.path().join("t.db")).unwrap();
    let cyl = source("cylindrical", 1, CYL);
    import(&mut lib, &[&cyl]).unwrap();
    let con = source("conical", 1, CON);
    let bad = source("cylindrical", 1, "main :: M2\n");
    assert!(import(&mut lib, &[&con, &bad]).is_err());
    assert_eq!(count(&lib, "SELECT count(*) FROM template_versions"), 1);
    assert!(matches!(
        lib.assemble("conical_840d", None),
        Err(LibraryError::NotFound { .. })
    ));
    // A file given twice, or a file that is not its source's parse.
    assert!(matches!(
        import(&mut lib, &[&con, &con]),
        Err(LibraryError::Duplicate { .. })
    ));
    let e = lib.import(&[file(&con)], &[&cyl], 0).unwrap_err();
    assert!(matches!(e, LibraryError::NotItsSource { .. }), "{e:?}");
}

#[test]
fn not_found_names_what_the_library_holds() {
    let dir = tempfile::tempdir().unwrap();
    let mut lib = Library::open(&dir.path().join("t.db")).unwrap();
    let e = lib.show("spur_840d", None).unwrap_err();
    assert!(e.to_string().contains("no templates"), "{e}");
    import(&mut lib, &[&source("cylindrical", 1, CYL)]).unwrap();
    let e = lib.assemble("cylindrical_840d", Some(4)).unwrap_err();
    assert_eq!(
        e.to_string(),
        "template cylindrical_840d version 4: not in the library; it holds cylindrical_840d v1"
    );
}

#[test]
fn the_shipped_standard_code_assembles_back_from_the_library() {
    let sources = crate::builtin::builtin_sources();
    let files: Vec<TemplateFile> = sources
        .iter()
        .map(|(name, text)| stdcode::parse(name, text).unwrap())
        .collect();
    let texts: Vec<&str> = sources.iter().map(|(_, t)| *t).collect();
    let dir = tempfile::tempdir().unwrap();
    let mut lib = Library::open(&dir.path().join("t.db")).unwrap();
    let report = lib.import(&files, &texts, 0).unwrap();
    assert_eq!(report.added.len(), files.len());
    let mut sorted = files.clone();
    sorted.sort_by(|a, b| a.id.cmp(&b.id));
    assert_eq!(lib.latest_versions().unwrap(), sorted);
    // The library stores exactly the components the analysis counts.
    let stored: usize = report
        .similarity
        .dialects
        .iter()
        .map(|d| d.total.lines_stored)
        .sum();
    assert_eq!(
        report.components.similar + report.components.non_similar,
        stored
    );
}

#[test]
fn a_newer_schema_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("t.db");
    drop(Library::open(&path).unwrap());
    let conn = Connection::open(&path).unwrap();
    conn.pragma_update(None, "user_version", 9).unwrap();
    drop(conn);
    assert!(matches!(
        Library::open(&path),
        Err(LibraryError::SchemaTooNew { found: 9, known: 1 })
    ));
}
