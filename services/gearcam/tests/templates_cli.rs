//! `gearcam templates analyze|import|list|show`, run as the real binary on a
//! fresh template directory and data directory per test.

use std::path::Path;
use std::process::{Command, Output};

fn gearcam(data: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_gearcam"))
        .arg("templates")
        .args(args)
        .arg("--data")
        .arg(data)
        .output()
        .expect("gearcam runs")
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn template(class: &str, version: u32, body: &str) -> String {
    format!(
        "# {class}: a small standard code for the test\n@template {class}_840d\n@class {class}\n\
         @dialect sinumerik840d\n@version {version}\n{body}"
    )
}

const CYLINDRICAL: &str = "main :: %{program.file}\n\
    main :: ;$PATH=/_N_MPF_DIR\n\
    synchronous/unit :: {N()} EGON({ax.table},\"FINE\",{ax.hob},{k.coupling.num},{k.coupling.den})\n\
    motion/move if: m.kind == \"feed\" :: {N()} G1 G90 {ax.axial}={nc(m.z)} F={nc(m.feed)}\n\
    main :: {N()} M{mc.program_end}\n";

const CONICAL: &str = "main :: %{program.file}\n\
    main :: ;$PATH=/_N_MPF_DIR\n\
    synchronous/unit :: {N()} EGON({ax.table},\"FINE\",{ax.hob},{k.coupling.num},{k.coupling.den})\n\
    motion/move if: m.kind == \"feed\" :: {N()} G1 G90 {ax.radial}={nc(m.x)} {ax.axial}={nc(m.z)} F={nc(m.feed)}\n\
    main :: {N()} M{mc.program_end}\n";

#[test]
fn analyze_import_list_show_and_versions() {
    let dir = tempfile::tempdir().unwrap();
    let src = dir.path().join("standard");
    let data = dir.path().join("data");
    std::fs::create_dir(&src).unwrap();
    let cyl = src.join("cylindrical_840d.tpl");
    std::fs::write(&cyl, template("cylindrical", 1, CYLINDRICAL)).unwrap();
    std::fs::write(
        src.join("conical_840d.tpl"),
        template("conical", 1, CONICAL),
    )
    .unwrap();
    std::fs::write(src.join("README.md"), "not a template").unwrap();
    let srcs = src.to_str().unwrap();

    // analyze: 10 lines, 4 shared by both classes (stored once), 2 own.
    let o = gearcam(&data, &["analyze", srcs]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = stdout(&o);
    assert!(
        out.contains("sinumerik840d: 2 class(es): conical, cylindrical"),
        "{out}"
    );
    assert!(out.contains("S [all] main :: ;$PATH=/_N_MPF_DIR"), "{out}");
    assert!(out.contains("N conical #4: motion/move"), "{out}");
    let o = gearcam(&data, &["analyze", srcs, "--json"]);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let total = &v["dialects"][0]["total"];
    assert_eq!(
        (
            &total["lines"],
            &total["lines_stored"],
            &total["lines_saved"]
        ),
        (&10.into(), &6.into(), &4.into())
    );
    assert_eq!(v["dialects"][0]["modules"][0]["module"], "main");
    // Analyze touches no database.
    assert!(!data.join("templates.db").exists());

    // The shipped standard code, compiled into the binary.
    let o = gearcam(&data, &["analyze"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout(&o).contains("sinumerik840d:"), "{}", stdout(&o));

    // import, then again: unchanged.
    let o = gearcam(&data, &["import", srcs]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = stdout(&o);
    assert!(
        out.contains("stored cylindrical_840d version 1 (5 records)"),
        "{out}"
    );
    assert!(
        out.contains("the library holds 4 similar and 2 non-similar components"),
        "{out}"
    );
    let o = gearcam(&data, &["import", srcs]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stdout(&o).contains("unchanged cylindrical_840d version 1 (skipped)"),
        "{}",
        stdout(&o)
    );

    // list and show.
    let o = gearcam(&data, &["list"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = stdout(&o);
    assert!(
        out.contains("conical_840d") && out.contains("(2 templates)"),
        "{out}"
    );
    let o = gearcam(&data, &["show", "cylindrical_840d"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = stdout(&o);
    assert!(
        out.contains("cylindrical_840d version 1 (class cylindrical, sinumerik840d), 5 records"),
        "{out}"
    );
    assert!(out.contains("motion, non-similar"), "{out}");
    let o = gearcam(&data, &["show", "cylindrical_840d", "--json"]);
    let t: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(t["rows"][2]["t"], "synchronous, similar");
    assert_eq!(t["rows"][3]["out_if"], "m.kind == \"feed\"");

    // A changed template without a new @version: refused, naming the file and
    // the @version line; nothing stored.
    let changed = CYLINDRICAL.replace("G90", "G91");
    std::fs::write(&cyl, template("cylindrical", 1, &changed)).unwrap();
    let o = gearcam(&data, &["import", srcs]);
    assert_eq!(o.status.code(), Some(1), "{}", stdout(&o));
    let err = stderr(&o);
    assert!(
        err.contains(&format!(
            "{}: template cylindrical_840d, line 5",
            cyl.display()
        )) && err.contains("expected @version 2 or higher, got @version 1: bump @version"),
        "{err}"
    );

    // Bumped: version 2 beside version 1.
    std::fs::write(&cyl, template("cylindrical", 2, &changed)).unwrap();
    let o = gearcam(&data, &["import", srcs]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stdout(&o).contains("stored cylindrical_840d version 2 (5 records; version 1 kept)"),
        "{}",
        stdout(&o)
    );
    let o = gearcam(&data, &["list", "--json"]);
    let list: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(list[1]["id"], "cylindrical_840d");
    assert_eq!(list[1]["version"], 2);
    assert_eq!(list[1]["versions"], serde_json::json!([1, 2]));
    // The table shows versions as versions (`v1 v2`), not
    // as a count or a decimal number (`1,2`).
    let o = gearcam(&data, &["list"]);
    let out = stdout(&o);
    let header = out.lines().next().unwrap();
    assert!(
        header.contains("current") && header.contains("stored versions"),
        "{out}"
    );
    let row = out
        .lines()
        .find(|l| l.starts_with("cylindrical_840d"))
        .unwrap();
    assert!(row.contains(" v2 ") && row.contains("v1 v2"), "{row}");
    assert!(!row.contains("1,2"), "{row}");
    let o = gearcam(&data, &["show", "cylindrical_840d", "--version", "1"]);
    assert!(stdout(&o).contains("G1 G90"), "{}", stdout(&o));
    let o = gearcam(&data, &["show", "cylindrical_840d"]);
    assert!(stdout(&o).contains("G1 G91"), "{}", stdout(&o));

    // Unknown template: not found (3), with what the library holds.
    let o = gearcam(&data, &["show", "spur_840d"]);
    assert_eq!(o.status.code(), Some(3));
    assert!(
        stderr(&o).contains("it holds conical_840d v1, cylindrical_840d v1 v2"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn a_template_that_does_not_parse_is_named_with_file_line_expected_and_got() {
    let dir = tempfile::tempdir().unwrap();
    let src = dir.path().join("std");
    std::fs::create_dir(&src).unwrap();
    let bad = src.join("crowned_840d.tpl");
    std::fs::write(
        &bad,
        template("crowned", 1, "main :: M30\nmotion/tooth :: G1\n"),
    )
    .unwrap();
    let o = gearcam(&dir.path().join("data"), &["import", src.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1));
    let err = stderr(&o);
    assert!(
        err.contains(&format!(
            "{}:7: expected a scope (part, unit, cut, move), got tooth\n",
            bad.display()
        )),
        "{err}"
    );
    assert!(!dir.path().join("data/templates.db").exists());

    // An empty directory is refused too.
    let empty = dir.path().join("empty");
    std::fs::create_dir(&empty).unwrap();
    let o = gearcam(
        &dir.path().join("data"),
        &["analyze", empty.to_str().unwrap()],
    );
    assert_eq!(o.status.code(), Some(1));
    assert!(
        stderr(&o).contains("expected template sources (*.tpl)"),
        "{}",
        stderr(&o)
    );
}

/// The spiral and wire families' programs name their form as a template
/// (`template spiral-fanuc-macro v1`); `templates list` and `show` know
/// them too, beside the library's templates.
#[test]
fn templates_of_every_family_are_listed_and_shown() {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("data");
    let o = gearcam(&data, &["list"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = stdout(&o);
    for id in [
        "spiral-fanuc-macro",
        "spiral-linuxcnc",
        "wire-3b",
        "wire-iso-wire",
    ] {
        assert!(out.contains(id), "{id}: {out}");
    }
    let o = gearcam(&data, &["list", "--json"]);
    let list: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert!(
        list.as_array()
            .unwrap()
            .iter()
            .any(|t| t["id"] == "wire-iso-wire"
                && t["generated"] == true
                && t["family"] == "wire-edm"),
        "{list}"
    );
    let o = gearcam(&data, &["show", "spiral-fanuc-macro"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stdout(&o).contains("spiral-fanuc-macro version 1 (family spiral-face, fanuc)"),
        "{}",
        stdout(&o)
    );
    let o = gearcam(&data, &["show", "wire-iso-wire", "--version", "2"]);
    assert_eq!(o.status.code(), Some(3), "{}", stderr(&o));
}
