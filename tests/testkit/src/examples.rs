//! The example job files of `examples/`: the valid ones, and the invalid ones
//! that name the error code they must get in an `# expect: CODE` line.

use std::path::PathBuf;

/// The `examples/` directory of the checkout.
pub fn dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../examples")
}

/// Every example job file, sorted by name: (file name, text).
pub fn all() -> Vec<(String, String)> {
    let dir = dir();
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.expect("a directory entry").path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    files.sort();
    files
        .into_iter()
        .map(|p| {
            let name = p
                .file_name()
                .expect("a file name")
                .to_string_lossy()
                .into_owned();
            let text =
                std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
            (name, text)
        })
        .collect()
}

/// The error code an invalid example expects (its `# expect:` line).
pub fn expected_code(text: &str) -> Option<&str> {
    text.lines()
        .find_map(|l| l.trim().strip_prefix("# expect:"))
        .map(str::trim)
}

/// The valid examples (without an `# expect:` line).
pub fn valid() -> Vec<(String, String)> {
    all()
        .into_iter()
        .filter(|(_, text)| expected_code(text).is_none())
        .collect()
}

/// True for an example of `family` (a `family = "…"` line).
fn of_family(text: &str, family: &str) -> bool {
    let line = format!("family=\"{family}\"");
    text.lines()
        .any(|l| l.split('#').next().unwrap_or("").replace(' ', "") == line)
}

/// True for a spiral face milling example (`family = "spiral-face"`).
pub fn is_spiral(text: &str) -> bool {
    of_family(text, "spiral-face")
}

/// True for a wire EDM example (`family = "wire-edm"`).
pub fn is_wire(text: &str) -> bool {
    of_family(text, "wire-edm")
}

/// The valid hobbing examples.
pub fn valid_hobbing() -> Vec<(String, String)> {
    valid()
        .into_iter()
        .filter(|(_, t)| !is_spiral(t) && !is_wire(t))
        .collect()
}

/// The valid wire EDM examples.
pub fn valid_wire() -> Vec<(String, String)> {
    valid().into_iter().filter(|(_, t)| is_wire(t)).collect()
}

/// The valid spiral face milling examples.
pub fn valid_spiral() -> Vec<(String, String)> {
    valid().into_iter().filter(|(_, t)| is_spiral(t)).collect()
}

/// The invalid examples, each with the code it must get.
pub fn invalid() -> Vec<(String, String, String)> {
    all()
        .into_iter()
        .filter_map(|(name, text)| {
            let code = expected_code(&text)?.to_string();
            Some((name, text, code))
        })
        .collect()
}

/// The example file called `name` (e.g. `spur_840d.toml`).
pub fn example(name: &str) -> String {
    all()
        .into_iter()
        .find(|(n, _)| n == name)
        .unwrap_or_else(|| panic!("no example {name}"))
        .1
}

/// The job moved to machine `machine` (H01: 840D, H02: FANUC).
pub fn on_machine(text: &str, machine: &str) -> String {
    let line = format!("machine = \"{machine}\"");
    assert!(
        text.contains("machine = \"H01\"") || text.contains("machine = \"H02\""),
        "the job names neither H01 nor H02:\n{text}"
    );
    text.replacen("machine = \"H01\"", &line, 1)
        .replacen("machine = \"H02\"", &line, 1)
}
