//! Helpers shared by the in-process template tests: the example job files,
//! a job moved to another machine, and a job's model through the seeded
//! knowledge base and the model.
#![allow(dead_code)]

use std::path::PathBuf;

use gearcam_proto::{JobId, JobRequest, JobSpec, MachiningModel};

/// The valid example job files (those without an `# expect:` line), by name.
pub fn examples() -> Vec<(String, String)> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../examples");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    files.sort();
    files
        .into_iter()
        .map(|p| {
            let name = p.file_name().unwrap().to_string_lossy().into_owned();
            (name, std::fs::read_to_string(&p).unwrap())
        })
        .filter(|(_, text)| !text.contains("# expect:"))
        .collect()
}

/// The valid example called `name`.
pub fn example(name: &str) -> String {
    examples()
        .into_iter()
        .find(|(n, _)| n == name)
        .unwrap_or_else(|| panic!("no example {name}"))
        .1
}

/// The job on machine `machine` (H01: 840D, H02: FANUC).
pub fn on_machine(text: &str, machine: &str) -> String {
    let line = format!("machine = \"{machine}\"");
    text.replace("machine = \"H01\"", &line)
        .replace("machine = \"H02\"", &line)
}

/// The job's model: planned by the seeded knowledge base, computed by the model.
pub fn model_of(text: &str) -> Result<MachiningModel, Vec<gearcam_proto::JobError>> {
    let spec: JobSpec = toml::from_str(text).unwrap_or_else(|e| panic!("{e}\n{text}"));
    let req = JobRequest {
        job_id: JobId::new("TEMPLATE-TEST-1").unwrap(),
        submitted_at_ms: 0,
        submitted_by: "test".into(),
        spec,
    };
    let conn = gearcam_knowledge::db::open_in_memory().unwrap();
    let plan = gearcam_knowledge::plan::plan(&conn, &req)?;
    gearcam_model::compute(&plan)
}
