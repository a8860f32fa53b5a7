//! `gearcam kb`, `gearcam confirm` and the plan section of `gearcam check
//! --json`, run as the real binary on a fresh data directory per test.

use std::path::Path;
use std::process::{Command, Output};

fn gearcam(data: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_gearcam"))
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

#[test]
fn kb_lists_adds_edits_refuses_and_round_trips_csv() {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("data");
    let o = gearcam(&data, &["kb", "list", "hobs"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = stdout(&o);
    assert!(
        out.contains("HOB-M3-80L") && out.contains("(5 hobs)"),
        "{out}"
    );

    let o = gearcam(
        &data,
        &[
            "kb",
            "add",
            "hobs",
            "--set",
            "id=HOB-M2-63",
            "--set",
            "module_mm=2",
            "--set",
            "starts=1",
            "--set",
            "hand=right",
            "--set",
            "lead_angle_deg=2.1",
            "--set",
            "od_mm=63",
            "--set",
            "length_mm=70",
            "--set",
            "usable_length_mm=60",
            "--set",
            "accuracy_class=AA",
            "--set",
            "remaining_life_parts=250",
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout(&o).contains("added hobs HOB-M2-63"));

    // A bad edit: exit 1, every error with field, expected and got.
    let o = gearcam(
        &data,
        &[
            "kb",
            "edit",
            "hobs",
            "HOB-M2-63",
            "--set",
            "starts=two",
            "--set",
            "hand=up",
        ],
    );
    assert_eq!(o.status.code(), Some(1));
    let err = stderr(&o);
    assert!(
        err.contains("field starts: expected an integer in [1, 12], got \"two\""),
        "{err}"
    );
    let o = gearcam(
        &data,
        &["kb", "edit", "hobs", "HOB-M2-63", "--set", "hand=up"],
    );
    assert!(
        stderr(&o).contains("field hand: expected one of right, left, got \"up\""),
        "{}",
        stderr(&o)
    );
    let o = gearcam(
        &data,
        &[
            "kb",
            "edit",
            "machines",
            "H01",
            "--set",
            "limits.max_hob_rpm=1200",
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let o = gearcam(&data, &["kb", "show", "machines", "H01", "--json"]);
    let m: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(m["limits"]["max_hob_rpm"], 1200.0);

    // CSV: export the cases, import a shop's own case file.
    let csv = dir.path().join("cases.csv");
    let o = gearcam(&data, &["kb", "export", "cases", csv.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = std::fs::read_to_string(&csv).unwrap();
    assert_eq!(text.lines().count(), 15, "header + 14 seed cases");
    let shop = dir.path().join("shop.csv");
    std::fs::write(
        &shop,
        "id,material,material_group,module_mm,teeth,face_width_mm,cutting_speed_m_min,feed_mm_per_rev,confidence,provenance\n\
         SHOP-1,20CrMnTi,case_hardening_steel,3,25,30,110,2.4,0.9,shop history 2024\n",
    )
    .unwrap();
    let o = gearcam(&data, &["kb", "import", "cases", shop.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout(&o).contains("1 added, 0 replaced"));
    let o = gearcam(&data, &["kb", "remove", "hobs", "HOB-M2-63"]);
    assert!(o.status.success());
    let o = gearcam(&data, &["kb", "show", "hobs", "HOB-M2-63"]);
    // Not found: exit 3, the one code for an unknown record.
    assert_eq!(o.status.code(), Some(3));
    assert!(stderr(&o).contains("NOT_FOUND"));

    // Confirm names the job it cannot find.
    let o = gearcam(&data, &["confirm", "NO-SUCH-JOB", "--outcome", "ok"]);
    assert_eq!(o.status.code(), Some(3));
    assert!(stderr(&o).contains("UNKNOWN_JOB"), "{}", stderr(&o));
}

/// A job with no process section and no hob: the knowledge base proposes.
const NO_PROCESS: &str = r#"
[job]
machine = "H01"
part_number = "CBR-1"
quantity = 10
[gear]
module_mm = 3.0
teeth = 25
face_width_mm = 30.0
blank_od_mm = 81.0
material = "20CrMnTi"
quality_grade = 7
fixture_height_mm = 100.0
"#;

#[test]
fn check_json_carries_the_proposal_with_cases_similarities_and_sources() {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("data");
    let job = dir.path().join("job.toml");
    std::fs::write(&job, NO_PROCESS).unwrap();
    let o = gearcam(&data, &["check", job.to_str().unwrap(), "--json"]);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout)
        .unwrap_or_else(|e| panic!("no JSON ({e}): {}", stderr(&o)));
    let plan = &v["plan"];
    assert_eq!(plan["class"], "cylindrical");
    assert_eq!(plan["hob_id"], "HOB-M3-80");
    let conf = plan["confidence"].as_f64().unwrap();
    assert!(conf > 0.0 && conf < 1.0, "{conf}");
    let cases = plan["cases"].as_array().unwrap();
    assert_eq!(cases[0]["id"], "SEED-CASE-M3");
    for c in cases {
        let s = c["similarity"].as_f64().unwrap();
        assert!(s > 0.0 && s <= 1.0, "{c}");
    }
    for name in ["cutting_speed_m_min", "feed_mm_per_rev", "cuts"] {
        assert_eq!(plan["values"][name]["source"], "case", "{name}");
        assert!(plan["values"][name]["value"].is_number());
    }
    for (name, val) in plan["values"].as_object().unwrap() {
        let s = val["source"].as_str().unwrap();
        assert!(
            ["job", "case", "machine", "default"].contains(&s),
            "{name}: {s}"
        );
    }
    assert!(plan["hob_choice"]["reason"]
        .as_str()
        .unwrap()
        .contains("class AA fits grade 7"));
    // The same job with an override: the job wins, the proposal is kept.
    std::fs::write(
        &job,
        format!("{NO_PROCESS}[process]\ncutting_speed_m_min = 70.0\n"),
    )
    .unwrap();
    let o = gearcam(&data, &["check", job.to_str().unwrap(), "--json"]);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let plan = &v["plan"];
    assert_eq!(plan["values"]["cutting_speed_m_min"]["value"], 70.0);
    assert_eq!(plan["values"]["cutting_speed_m_min"]["source"], "job");
    assert_eq!(plan["proposed"]["cutting_speed_m_min"]["source"], "case");
    assert_eq!(plan["overridden"][0], "cutting_speed_m_min");
    // The human report shows the cases and the overridden proposal.
    let o = gearcam(&data, &["check", job.to_str().unwrap()]);
    let text = stdout(&o);
    assert!(text.contains("case SEED-CASE-M3 (similarity"), "{text}");
    assert!(
        text.contains("from job  (proposed 90.0000 from case)"),
        "{text}"
    );
}

#[test]
fn kb_shows_the_fanuc_machine_h02_and_check_plans_for_it() {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("data");
    let o = gearcam(&data, &["kb", "list", "machines"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = stdout(&o);
    assert!(out.contains("H01") && out.contains("H02"), "{out}");

    let o = gearcam(&data, &["kb", "show", "machines", "H02", "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let m: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(m["dialect"], "fanuc");
    assert_eq!(m["mcodes"]["coolant_on"], 8);
    assert_eq!(m["mcodes"]["outer_support_on"], 68);
    assert_eq!(m["mcodes"]["program_end"], 30);
    assert_eq!(m["limits"]["max_hob_rpm"], 1000.0);
    assert_eq!(m["limits"]["max_table_rpm"], 100.0);
    assert!(m["source"].as_str().unwrap().contains("EGB"), "{m}");

    // The job names the machine, and so the dialect.
    let job = dir.path().join("job.toml");
    std::fs::write(&job, NO_PROCESS.replace("\"H01\"", "\"H02\"")).unwrap();
    let o = gearcam(&data, &["check", job.to_str().unwrap(), "--json"]);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout)
        .unwrap_or_else(|e| panic!("no JSON ({e}): {}", stderr(&o)));
    assert_eq!(v["plan"]["machine"]["id"], "H02");
    assert_eq!(v["plan"]["machine"]["dialect"], "fanuc");
    assert_eq!(v["plan"]["values"]["safety_mm"]["value"], 3.0);
    assert!(v["model"]["hob_rpm"].as_f64().unwrap() <= 1000.0, "{v:#}");
    for e in v["errors"].as_array().unwrap() {
        assert_eq!(
            e["stage"], "template",
            "only the FANUC template may be missing: {e}"
        );
    }
}

/// `gearcam kb libraries` speaks to a person:
/// each field's type and whether it is required or its default, no Rust
/// `Debug` text.
#[test]
fn kb_libraries_prints_no_rust_debug_text() {
    let dir = tempfile::tempdir().unwrap();
    let o = gearcam(dir.path(), &["kb", "libraries"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    for debug in ["Default(", "Bool(", "Text(", "Real(", "Some("] {
        assert!(!text.contains(debug), "{debug} in:\n{text}");
    }
    assert!(text.contains("true/false default false"), "{text}");
    assert!(text.contains("required"), "{text}");
}

/// `--json` means JSON for `kb libraries` and
/// `kb export` too (they printed text and CSV).
#[test]
fn kb_libraries_and_export_print_json_with_json() {
    let dir = tempfile::tempdir().unwrap();
    let o = gearcam(dir.path(), &["kb", "libraries", "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let libs: serde_json::Value = serde_json::from_str(&stdout(&o)).expect("JSON");
    let hobs = libs
        .as_array()
        .unwrap()
        .iter()
        .find(|l| l["name"] == "hobs")
        .expect("the hobs library");
    assert_eq!(hobs["key"], "id");
    assert!(hobs["fields"]
        .as_array()
        .unwrap()
        .iter()
        .any(|f| f["name"] == "usable_length_mm"));
    let o = gearcam(dir.path(), &["kb", "export", "hobs", "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let records: serde_json::Value = serde_json::from_str(&stdout(&o)).expect("JSON, not CSV");
    assert!(records
        .as_array()
        .unwrap()
        .iter()
        .any(|r| r["id"] == "HOB-M3-80"));
}

/// A file that is not CSV text is blamed, not the knowledge base: a binary
/// file given to `kb import` is CSV_UNREADABLE on the file, and nothing is
/// imported.
#[test]
fn a_binary_import_file_is_blamed_not_the_database() {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("data");
    let binary = dir.path().join("binary.toml");
    std::fs::write(&binary, [0xff_u8, 0xfe, 0x00, 0x9c, 0x80, 0xc3, 0x28]).unwrap();
    let before = stdout(&gearcam(&data, &["kb", "list", "hobs", "--json"]));
    let o = gearcam(
        &data,
        &[
            "kb",
            "import",
            "hobs",
            &binary.display().to_string(),
            "--json",
        ],
    );
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(
        (
            v["errors"][0]["code"].as_str(),
            v["errors"][0]["field"].as_str()
        ),
        (Some("CSV_UNREADABLE"), Some("file")),
        "{v}"
    );
    assert!(
        !stderr(&o).contains("KNOWLEDGE_BASE_ERROR"),
        "{}",
        stderr(&o)
    );
    assert_eq!(
        stdout(&gearcam(&data, &["kb", "list", "hobs", "--json"])),
        before
    );
}
