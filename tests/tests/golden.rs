//! Every example's program text, on both dialects, against the text committed
//! in `tests/golden/`: a refactoring that changes one character of a program
//! fails here. A deliberate change is written back with `GEARCAM_BLESS=1
//! cargo test -p gearcam-tests --test golden` and reviewed in the diff.
// Test code: clocks for timeouts, the environment for switches.
#![allow(clippy::disallowed_methods)]

use gearcam_template::Templates;

use gearcam_testkit::examples::{on_machine, valid_hobbing as examples, valid_spiral, valid_wire};
use gearcam_testkit::pipeline::{model_of, spiral_model_of, wire_model_of};

/// Compares `text` with the golden file `file` (or writes it when blessing);
/// the first differing line, if any.
fn compare(file: &std::path::Path, text: &str, bless: bool) -> Option<String> {
    if bless {
        std::fs::create_dir_all(file.parent().unwrap()).unwrap();
        std::fs::write(file, text).unwrap();
        return None;
    }
    let want = std::fs::read_to_string(file)
        .unwrap_or_else(|e| panic!("{}: {e} (bless with GEARCAM_BLESS=1)", file.display()));
    if want == text {
        return None;
    }
    let line = want
        .lines()
        .zip(text.lines())
        .position(|(a, b)| a != b)
        .map_or(want.lines().count().min(text.lines().count()), |i| i);
    Some(format!(
        "{}: first difference at line {}:\n  want {:?}\n  got  {:?}",
        file.display(),
        line + 1,
        want.lines().nth(line),
        text.lines().nth(line)
    ))
}

/// Every spiral example's program, in the form its job and machine choose.
#[test]
fn every_spiral_example_program_is_unchanged() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("golden");
    let bless = std::env::var_os("GEARCAM_BLESS").is_some();
    let mut differ = Vec::new();
    let all = valid_spiral();
    assert!(all.len() >= 6, "{} spiral examples", all.len());
    for (name, text) in all {
        let model = spiral_model_of(&text).unwrap_or_else(|e| panic!("{name}: {e:#?}"));
        let program =
            gearcam_template::spiral::render(&model).unwrap_or_else(|e| panic!("{name}: {e:#?}"));
        let file = dir.join(format!("{}.nc", name.trim_end_matches(".toml")));
        differ.extend(compare(&file, &program.text, bless));
    }
    assert!(differ.is_empty(), "{}", differ.join("\n"));
}

/// Every wire example's program, in the form its job and machine choose
/// (the header's submission line is the test request's, fixed).
#[test]
fn every_wire_example_program_is_unchanged() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("golden");
    let bless = std::env::var_os("GEARCAM_BLESS").is_some();
    let mut differ = Vec::new();
    let all = valid_wire();
    assert!(all.len() >= 5, "{} wire examples", all.len());
    for (name, text) in all {
        let model = wire_model_of(&text).unwrap_or_else(|e| panic!("{name}: {e:#?}"));
        let program =
            gearcam_template::wire::render(&model).unwrap_or_else(|e| panic!("{name}: {e:#?}"));
        let ext = match model.plan.process.program {
            gearcam_proto::WireProgram::ThreeB => "3b",
            gearcam_proto::WireProgram::FourB => "4b",
            gearcam_proto::WireProgram::IsoWire => "iso",
        };
        let file = dir.join(format!("{}.{ext}", name.trim_end_matches(".toml")));
        differ.extend(compare(&file, &program.text, bless));
    }
    assert!(differ.is_empty(), "{}", differ.join("\n"));
}

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
