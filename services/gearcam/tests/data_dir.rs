//! Which data directory a command uses is never a guess: every command that
//! uses one names it as an absolute path, says when it makes and seeds a new
//! knowledge base there, and takes it from `--data`, else `GEARCAM_DATA`,
//! else `./gearcam-data`. Through the real binary, in fresh folders.

use std::path::Path;
use std::process::{Command, Output};

fn gearcam(cwd: &Path, env: Option<&Path>, args: &[&str]) -> Output {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_gearcam"));
    cmd.current_dir(cwd).args(args).env_remove("GEARCAM_DATA");
    if let Some(d) = env {
        cmd.env("GEARCAM_DATA", d);
    }
    cmd.output().expect("gearcam runs")
}

fn example(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(name)
        .canonicalize()
        .unwrap()
        .display()
        .to_string()
}

#[test]
fn every_command_names_its_data_directory_and_a_new_knowledge_base() {
    let dir = tempfile::tempdir().unwrap();
    let root = dir.path().canonicalize().unwrap();
    let job = example("spur_840d.toml");
    let here = root.join("gearcam-data");

    // The working directory's default: named, absolute, and new.
    let o = gearcam(&root, None, &["check", &job, "--json"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains(&format!(
            "data directory {} has no knowledge base",
            here.display()
        )) && err.contains("seeded"),
        "{err}"
    );
    // Standard output stays the report.
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["ok"], true);
    // Again: the same directory, no longer new.
    let o = gearcam(&root, None, &["kb", "list", "machines"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains(&format!("data directory {}", here.display())),
        "{err}"
    );
    assert!(!err.contains("no knowledge base"), "{err}");

    // GEARCAM_DATA from another folder: that directory, not the folder's.
    let shop = root.join("shop");
    let elsewhere = root.join("elsewhere");
    std::fs::create_dir(&elsewhere).unwrap();
    let o = gearcam(&elsewhere, Some(&shop), &["check", &job]);
    assert!(o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains(&shop.display().to_string()), "{err}");
    assert!(shop.join("knowledge.db").exists());
    assert!(!elsewhere.join("gearcam-data").exists());
    // --data wins over GEARCAM_DATA.
    let o = gearcam(
        &elsewhere,
        Some(&shop),
        &["kb", "list", "machines", "--data", "local"],
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains(&elsewhere.join("local").display().to_string()),
        "{err}"
    );
}
