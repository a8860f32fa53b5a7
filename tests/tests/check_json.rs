//! The JSON contract of `gearcam check --json`, run as a real process.

use std::process::Command;

use approx::assert_abs_diff_eq;
use gearcam_testkit::bin;

fn check(dir: &std::path::Path, job: &str) -> (i32, serde_json::Value) {
    let path = dir.join("job.toml");
    std::fs::write(&path, job).unwrap();
    let out = Command::new(bin("gearcam"))
        .args([
            "check",
            &path.display().to_string(),
            "--json",
            "--data",
            &dir.join("data").display().to_string(),
        ])
        .output()
        .expect("gearcam check runs");
    let v = serde_json::from_slice(&out.stdout)
        .unwrap_or_else(|e| panic!("no JSON ({e}): {}", String::from_utf8_lossy(&out.stderr)));
    (out.status.code().unwrap_or(-1), v)
}

/// docs/reference.md#worked-self-check: da0 = 80, vc = 100 m/min, z0 = 1, z = 25,
/// fa = 2, mn = 3, β = 15° → Nt = 397.887 rpm, Ni = 15.9155 rpm,
/// differential 0.395446° of C per mm of Z.
const SELF_CHECK: &str = r#"
[job]
machine = "H01"
part_number = "SELF-CHECK"
[gear]
module_mm = 3.0
teeth = 25
helix_angle_deg = 15.0
helix_hand = "right"
face_width_mm = 30.0
fixture_height_mm = 100.0
[hob]
starts = 1
od_mm = 80.0
module_mm = 3.0
lead_angle_deg = 2.3716
hand = "right"
length_mm = 100.0
[process]
cutting_speed_m_min = 100.0
feed_mm_per_rev = 2.0
"#;

#[test]
fn check_json_carries_the_contract_and_the_spec_self_check_numbers() {
    let dir = tempfile::tempdir().unwrap();
    let (code, v) = check(dir.path(), SELF_CHECK);
    assert_eq!(code, 0, "{v:#}");
    assert_eq!(v["ok"], true);
    assert_eq!(v["errors"].as_array().unwrap().len(), 0);
    let m = &v["model"];
    assert_abs_diff_eq!(m["hob_rpm"].as_f64().unwrap(), 397.887, epsilon = 1e-3);
    assert_abs_diff_eq!(
        m["differential_deg_per_mm"].as_f64().unwrap(),
        0.395446,
        epsilon = 1e-6
    );
    // Conventional cut, same hands: Nw = Ni / (1 − fa/Pz), Pz = π·mn·z / sin β.
    let ni = 397.887_357_5 / 25.0;
    assert_abs_diff_eq!(ni, 15.9155, epsilon = 1e-4);
    let pz = std::f64::consts::PI * 3.0 * 25.0 / 15f64.to_radians().sin();
    let nw = ni / (1.0 - 2.0 / pz);
    assert_abs_diff_eq!(m["table_rpm"].as_f64().unwrap(), nw, epsilon = 1e-4);
    assert_abs_diff_eq!(
        m["axial_feed_mm_min"].as_f64().unwrap(),
        2.0 * nw,
        epsilon = 1e-3
    );
    // Swivel: the signed setting angle η = s_g·β − s_h·γ0 of the neutral
    // frame, and H01's axis value A = −η.
    assert_abs_diff_eq!(
        m["swivel_deg"].as_f64().unwrap(),
        15.0 - 2.3716,
        epsilon = 1e-9
    );
    assert_abs_diff_eq!(
        m["swivel_axis_deg"].as_f64().unwrap(),
        -(15.0 - 2.3716),
        epsilon = 1e-9
    );
    // The indexing ratio with its sign (the hob's hand), and ΔH′ as the reach
    // of the finite hob (independent sweep of its tip cylinder, Python:
    // 23.456419 mm for this blank and depth).
    assert_eq!(m["coupling"]["num"], 1);
    assert_eq!(m["coupling"]["den"], 25);
    assert_abs_diff_eq!(
        m["clearance_mm"].as_f64().unwrap(),
        23.456_419,
        epsilon = 1e-5
    );
    // Positions: C and D share X = L; D is below C by b + 2ΔH′ + 2·safety.
    let p = &m["positions"];
    let (cx, cz, dz) = (
        p["C"]["x_mm"].as_f64().unwrap(),
        p["C"]["z_mm"].as_f64().unwrap(),
        p["D"]["z_mm"].as_f64().unwrap(),
    );
    assert_abs_diff_eq!(
        cx,
        m["centre_distance_mm"].as_f64().unwrap(),
        epsilon = 1e-9
    );
    let spread =
        30.0 + 2.0 * m["clearance_mm"].as_f64().unwrap() + 2.0 * m["safety_mm"].as_f64().unwrap();
    assert_abs_diff_eq!(cz - dz, spread, epsilon = 1e-9);
    for key in ["A", "B", "E"] {
        assert!(
            p[key]["x_mm"].is_number() && p[key]["z_mm"].is_number(),
            "{key}"
        );
    }
    // Geometry: d = z·mn / cos β.
    assert_abs_diff_eq!(
        v["geometry"]["d_mm"].as_f64().unwrap(),
        75.0 / 15f64.to_radians().cos(),
        epsilon = 1e-9
    );
    for key in ["db_mm", "da_mm", "df_mm"] {
        assert!(v["geometry"][key].is_number(), "{key}");
    }
    assert_eq!(v["program"]["dialect"], "sinumerik840d");
    assert_eq!(v["program"]["name"], "SELF_CHECK");
    assert!(v["program"]["text"]
        .as_str()
        .unwrap()
        .contains("EGONSYNE(C,\"FINE\",0,\"DCT\",B,0,1,25,Z,0,0.395446,1)"));
    // The template that made it, and its path check, are part of the report.
    assert_eq!(v["program"]["template"]["id"], "cylindrical_840d");
    assert!(v["program"]["template"]["version"].as_u64().unwrap() >= 3);
    assert_eq!(v["program"]["path_check"]["ok"], true);
    assert_eq!(
        v["program"]["path_check"]["findings"]
            .as_array()
            .unwrap()
            .len(),
        0
    );
}

#[test]
fn check_json_mirrors_the_signs_of_a_mirrored_set_up() {
    // Left-hand gear and left-hand hob: the mirror image of SELF_CHECK. η,
    // the indexing ratio and the differential turn; nothing else changes.
    let dir = tempfile::tempdir().unwrap();
    let mirrored = SELF_CHECK
        .replace("helix_hand = \"right\"", "helix_hand = \"left\"")
        .replace("hand = \"right\"", "hand = \"left\"");
    let (code, v) = check(dir.path(), &mirrored);
    assert_eq!(code, 0, "{v:#}");
    let (_, r) = check(dir.path(), SELF_CHECK);
    let (m, r) = (&v["model"], &r["model"]);
    for key in ["swivel_deg", "differential_deg_per_mm"] {
        assert_abs_diff_eq!(
            m[key].as_f64().unwrap(),
            -r[key].as_f64().unwrap(),
            epsilon = 1e-12
        );
    }
    assert_eq!(m["coupling"]["num"], -1);
    for key in [
        "clearance_mm",
        "table_rpm",
        "axial_feed_mm_min",
        "centre_distance_mm",
    ] {
        assert_eq!(m[key], r[key], "{key}");
    }
    let text = v["program"]["text"].as_str().unwrap();
    assert!(
        text.contains("EGONSYNE(C,\"FINE\",0,\"DCT\",B,0,-1,25,Z,0,-0.395446,1)"),
        "{text}"
    );
    assert!(text.contains(" A=12.6284 "), "{text}");
}

#[test]
fn check_json_on_the_fanuc_machine_gives_a_checked_fanuc_program() {
    let dir = tempfile::tempdir().unwrap();
    let job = SELF_CHECK.replace("machine = \"H01\"", "machine = \"H02\"");
    assert!(job.contains("H02"));
    let (code, v) = check(dir.path(), &job);
    assert_eq!(code, 0, "{v:#}");
    assert_eq!(v["program"]["dialect"], "fanuc");
    assert_eq!(v["program"]["template"]["id"], "cylindrical_fanuc");
    assert_eq!(v["program"]["path_check"]["ok"], true);
    let text = v["program"]["text"].as_str().unwrap();
    assert!(text.starts_with("%\nO"), "{text}");
    // FANUC EGB: T teeth, L starts, Q module and P helix angle together.
    assert!(text.contains("G81 T25 L1 Q3.0 P15.0"), "{text}");
    assert!(text.trim_end().ends_with('%'), "{text}");
}

#[test]
fn check_json_lists_every_failed_check_with_its_field() {
    let dir = tempfile::tempdir().unwrap();
    let bad = SELF_CHECK
        .replace(
            "[hob]\nstarts = 1\nod_mm = 80.0\nmodule_mm = 3.0",
            "[hob]\nstarts = 1\nod_mm = 60.0\nmodule_mm = 2.5",
        )
        .replace("[process]", "[process]\ndepth_mm = 12.0");
    let (code, v) = check(dir.path(), &bad);
    assert_eq!(code, 1);
    assert_eq!(v["ok"], false);
    let errors = v["errors"].as_array().unwrap();
    let codes: Vec<&str> = errors.iter().map(|e| e["code"].as_str().unwrap()).collect();
    for expected in ["BASE_PITCH_MISMATCH", "CUT_DEPTH", "HOB_OD_TOO_SMALL"] {
        assert!(
            codes.contains(&expected),
            "{expected} missing from {codes:?}"
        );
    }
    for e in errors {
        for key in ["code", "field", "expected", "got", "message"] {
            assert!(
                e[key].as_str().is_some_and(|s| !s.is_empty()),
                "{key} in {e}"
            );
        }
    }
}

#[test]
fn an_unknown_key_is_an_error_naming_the_key() {
    let dir = tempfile::tempdir().unwrap();
    let (code, v) = check(
        dir.path(),
        &SELF_CHECK.replace("teeth = 25", "teeth = 25\ntooth_count = 25"),
    );
    assert_eq!(code, 1);
    assert_eq!(v["errors"][0]["code"], "JOB_FILE_UNKNOWN_KEY");
    assert_eq!(v["errors"][0]["field"], "gear.tooth_count");
}

/// `gearcam check --simulate` runs the program on the virtual machine:
/// `simulation` carries the predicted class of every ISO 1328-1 item with
/// its tolerance, the size, no safety finding for the example, and the
/// charts are written; a what-if runout of the workpiece shows in runout.
#[test]
fn check_json_simulates_a_hobbing_program_on_request() {
    let dir = tempfile::tempdir().unwrap();
    let example = gearcam_testkit::examples::example("spur_840d.toml");
    let path = dir.path().join("spur.toml");
    std::fs::write(&path, &example).unwrap();
    let run = |extra: &[&str]| -> serde_json::Value {
        let mut args = vec![
            "check".to_string(),
            path.display().to_string(),
            "--json".into(),
            "--simulate".into(),
            "--coarse".into(),
            "--data".into(),
            dir.path().join("data").display().to_string(),
        ];
        args.extend(extra.iter().map(|s| s.to_string()));
        let out = Command::new(bin("gearcam")).args(&args).output().unwrap();
        serde_json::from_slice(&out.stdout)
            .unwrap_or_else(|e| panic!("no JSON ({e}): {}", String::from_utf8_lossy(&out.stderr)))
    };
    let v = run(&[]);
    let sim = &v["simulation"];
    assert_eq!(sim["mode"], "coarse", "{v:#}");
    assert_eq!(sim["sections"], 9);
    assert_eq!(sim["safety"].as_array().unwrap().len(), 0, "{sim:#}");
    let items: Vec<&str> = sim["deviations"]
        .as_array()
        .unwrap()
        .iter()
        .map(|d| d["item"].as_str().unwrap())
        .collect();
    assert_eq!(
        items,
        ["fp", "Fp", "fHα", "ffα", "Fα", "fHβ", "ffβ", "Fβ", "Fr"]
    );
    for d in sim["deviations"].as_array().unwrap() {
        assert!(d["tolerance_um"].as_f64().unwrap() > 0.0, "{d}");
    }
    assert!(sim["grade"].as_u64().is_some(), "{sim:#}");
    assert!(sim["ms"].as_f64().unwrap() > 0.0);
    let (got, design) = (&sim["thickness_mm"][0], &sim["thickness_mm"][1]);
    assert_abs_diff_eq!(
        got.as_f64().unwrap(),
        design.as_f64().unwrap(),
        epsilon = 0.01
    );
    let charts = v["simulation_picture"].as_str().expect("charts written");
    assert!(std::fs::read_to_string(charts).unwrap().starts_with("<svg"));
    // An eccentric workpiece of 20 µm cuts a runout of about twice that.
    let worn = run(&["--table-runout", "0.02"]);
    let fr = |v: &serde_json::Value| {
        v["simulation"]["deviations"]
            .as_array()
            .unwrap()
            .iter()
            .find(|d| d["item"] == "Fr")
            .unwrap()["value_um"]
            .as_f64()
            .unwrap()
    };
    assert_eq!(worn["simulation"]["what_if"][0], "table runout 0.02 mm");
    assert!(fr(&worn) > fr(&v) + 20.0, "Fr {} → {}", fr(&v), fr(&worn));
}
