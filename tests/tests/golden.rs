//! Every example's program text, on both dialects, against the text committed
//! in `tests/golden/`: a refactoring that changes one character of a program
//! fails here. A deliberate change is written back with `GEARCAM_BLESS=1
//! cargo test -p gearcam-tests --test golden` and reviewed in the diff.
// Test code: clocks for timeouts, the environment for switches.
#![allow(clippy::disallowed_methods)]

use gearcam_template::Templates;

use gearcam_testkit::examples::{on_machine, valid as examples};
use gearcam_testkit::pipeline::model_of;

#[test]
fn every_example_program_is_unchanged() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("golden");
    let bless = std::env::var_os("GEARCAM_BLESS").is_some();
    let templates = Templates::builtin();
    let mut differ = Vec::new();
    let mut compared = 0;
    for (name, text) in examples() {
        for machine in ["H01", "H02"] {
            let model = model_of(&on_machine(&text, machine))
                .unwrap_or_else(|e| panic!("{name} on {machine}: {e:#?}"));
            let program = templates
                .render(&model)
                .unwrap_or_else(|e| panic!("{name} on {machine}: {e:#?}"));
            let file = dir.join(format!("{}.{machine}.nc", name.trim_end_matches(".toml")));
            if bless {
                std::fs::create_dir_all(&dir).unwrap();
                std::fs::write(&file, &program.text).unwrap();
                continue;
            }
            let want = std::fs::read_to_string(&file)
                .unwrap_or_else(|e| panic!("{}: {e} (bless with GEARCAM_BLESS=1)", file.display()));
            compared += 1;
            if want != program.text {
                let line = want
                    .lines()
                    .zip(program.text.lines())
                    .position(|(a, b)| a != b)
                    .map_or(
                        want.lines().count().min(program.text.lines().count()),
                        |i| i,
                    );
                differ.push(format!(
                    "{name} on {machine}: first difference at line {}:\n  want {:?}\n  got  {:?}",
                    line + 1,
                    want.lines().nth(line),
                    program.text.lines().nth(line)
                ));
            }
        }
    }
    assert!(differ.is_empty(), "{}", differ.join("\n"));
    assert!(bless || compared >= 20, "{compared} programs compared");
}
