//! The README a new user reads first names every
//! command the binary has, the prerequisites and what "confidence" means,
//! and every program's header names the order and when it was submitted.

use gearcam_testkit::gearcam;

fn readme() -> String {
    std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../README.md")).unwrap()
}

/// The subcommands `gearcam [COMMAND] --help` lists (without `help`).
fn subcommands(args: &[&str]) -> Vec<String> {
    let mut a = args.to_vec();
    a.push("--help");
    let (code, out, err) = gearcam(&a);
    assert_eq!(code, Some(0), "{err}");
    out.lines()
        .skip_while(|l| !l.starts_with("Commands:"))
        .skip(1)
        .take_while(|l| l.starts_with("  "))
        .filter_map(|l| l.split_whitespace().next())
        .filter(|c| *c != "help")
        .map(str::to_string)
        .collect()
}

#[test]
fn the_readme_table_has_every_command() {
    let readme = readme();
    let table: Vec<&str> = readme
        .lines()
        .skip_while(|l| !l.starts_with("| command |"))
        .take_while(|l| l.starts_with('|'))
        .collect();
    assert!(table.len() > 10, "no command table in the README");
    let top = subcommands(&[]);
    assert!(top.len() >= 12, "{top:?}");
    for c in &top {
        let with_sub = subcommands(&[c.as_str()]);
        if with_sub.is_empty() || c == "kb" || c == "templates" {
            let cell = format!("`gearcam {c}");
            assert!(
                table.iter().any(|l| l.contains(&cell)),
                "{c} is not in the README's table"
            );
        }
        if c == "program" {
            for s in with_sub {
                let cell = format!("`gearcam program {s}");
                assert!(
                    table.iter().any(|l| l.contains(&cell)),
                    "program {s} is not in the README's table"
                );
            }
        }
    }
}

#[test]
fn the_readme_says_prerequisites_and_confidence() {
    let readme = readme();
    for needed in [
        "## Prerequisites",
        "Rust 1.85",
        "C compiler",
        "GB of disk",
        "Cold build",
        "**Confidence**",
    ] {
        assert!(readme.contains(needed), "the README lacks {needed:?}");
    }
    // The Rust version said is the workspace's.
    let cargo =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../Cargo.toml")).unwrap();
    assert!(
        cargo.contains("rust-version = \"1.85\""),
        "README and Cargo.toml disagree"
    );
}

#[test]
fn the_program_header_names_the_order_and_the_submission() {
    let job = concat!(env!("CARGO_MANIFEST_DIR"), "/../examples/spur_840d.toml");
    let data = tempfile::tempdir().unwrap();
    let (code, out, err) = gearcam(&[
        "check",
        job,
        "--json",
        "--data",
        data.path().to_str().unwrap(),
    ]);
    assert_eq!(code, Some(0), "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let text = v["program"]["text"].as_str().unwrap();
    assert!(
        text.contains("\n; ORDER QTY=20 MATERIAL 20CrMnTi QUALITY GRADE 7\n"),
        "{text}"
    );
    let submitted = text
        .lines()
        .find(|l| l.starts_with("; SUBMITTED "))
        .expect("a submission line");
    assert!(
        submitted.ends_with(&format!(" BY {}", "")) || submitted.contains(" UTC BY "),
        "{submitted}"
    );
}
