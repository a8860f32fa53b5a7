//! A program's name follows one rule on every control that names programs by
//! text, and a name a control refuses is refused before anything is
//! planned, naming `[job] program_name`. Through real service processes on
//! loopback and the real `gearcam check`.

use gearcam_testkit::{examples, gearcam, Cluster};

/// The example job `file` with its part number replaced by `part` and, when
/// given, its own program name.
fn with_part(file: &str, part: &str, program_name: Option<&str>) -> String {
    let text = examples::example(file);
    let mut out = String::new();
    for line in text.lines() {
        if line.trim_start().starts_with("part_number") {
            out.push_str(&format!("part_number = {part:?}\n"));
            if let Some(name) = program_name {
                out.push_str(&format!("program_name = {name:?}\n"));
            }
        } else if !line.trim_start().starts_with("program_name") {
            out.push_str(line);
            out.push('\n');
        }
    }
    assert!(out.contains(&format!("part_number = {part:?}")), "{file}");
    out
}

/// A part number that looks like a path becomes the same name on an 840D,
/// a LinuxCNC mill and a 3B wire machine (upper case where the control
/// wants it), and each agent stores it under that name.
#[test]
fn a_path_like_part_number_makes_one_name_on_every_control() {
    let mut cluster = Cluster::start();
    cluster.start_agent_for("M02");
    cluster.start_agent_for("W01");
    for (example, stored) in [
        ("spur_840d.toml", "H01/programs/_N_ETC_X_MPF"),
        ("face_circle_linuxcnc.toml", "M02/programs/etc_x.ngc"),
        ("die_m2z20_3b.toml", "W01/programs/etc_x.3b"),
    ] {
        let job = cluster.job_file(example, &with_part(example, "../../etc/x", None));
        let (_, v) = cluster.submit_wait(&job);
        assert_eq!(
            v["state"],
            "delivered",
            "{example}: {v}\n{}",
            cluster.logs()
        );
        assert!(
            cluster.dir().join(stored).is_file(),
            "{example}: {stored} missing; {v}"
        );
    }
}

/// A job's own name the control refuses (`<script>` on the LinuxCNC mill,
/// a path on the 840D, a name on the 3B machine) is refused by the
/// knowledge service, the first stage, with the field and the way out;
/// `gearcam check` refuses it the same way without the bus.
#[test]
fn a_name_the_control_refuses_is_refused_before_planning() {
    let mut cluster = Cluster::start();
    cluster.start_agent_for("M02");
    cluster.start_agent_for("W01");
    let data = cluster.dir().join("check-data").display().to_string();
    for (example, name) in [
        ("face_circle_linuxcnc.toml", "<script>"),
        ("spur_840d.toml", "../../etc/x"),
        ("die_m2z20_3b.toml", "a/b"),
    ] {
        let job = cluster.job_file(example, &with_part(example, "P-1", Some(name)));
        let (out, v) = cluster.submit_wait(&job);
        assert_eq!(out.status.code(), Some(1), "{example}: {v}");
        assert_eq!(v["state"], "failed", "{example}: {v}");
        let e = &v["errors"][0];
        assert_eq!(
            (e["stage"].as_str(), e["code"].as_str(), e["field"].as_str()),
            (
                Some("knowledge"),
                Some("INVALID_PROGRAM_NAME"),
                Some("job.program_name")
            ),
            "{example}: {v}"
        );
        assert_eq!(e["got"], name, "{example}: {v}");
        assert!(
            e["message"]
                .as_str()
                .is_some_and(|m| m.contains("[job] program_name")),
            "{example}: {v}"
        );
        let path = job.display().to_string();
        let (code, out, err) = gearcam(&["check", &path, "--json", "--data", &data]);
        assert_eq!(code, Some(1), "{example}: {err}");
        let c: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
        assert_eq!(c["errors"][0]["code"], "INVALID_PROGRAM_NAME", "{c}");
        assert_eq!(c["errors"][0]["stage"], "knowledge", "{c}");
    }
    // Nothing was stored on any machine.
    for machine in ["H01", "M02", "W01"] {
        let dir = cluster.dir().join(machine).join("programs");
        let files = std::fs::read_dir(&dir).map_or(0, Iterator::count);
        assert_eq!(files, 0, "{}", dir.display());
    }
}
