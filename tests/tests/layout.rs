//! The shape of the code, checked on the source tree so that it cannot drift:
//!
//! - no import loop between the modules of a crate (module A using
//!   `crate::b` while b uses `crate::a`, directly or through others);
//! - no source file over 800 lines, tests apart (a file's `#[cfg(test)] mod
//!   tests` block, and `tests.rs` files, do not count);
//! - no key expression spelled outside `proto/src/keys.rs`;
//! - no citation of the former specification kept outside the repository
//!   (its section marks): the domain reference is `docs/`;
//! - the demo and the tests resolve the same features of every dependency
//!   they share, so the README's two commands share one build.
//!
//! Comments do not count as uses: a doc link to another module is not an
//! import.
// Test code: `CARGO` (set by cargo) names the cargo that runs the tests.
#![allow(clippy::disallowed_methods)]

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

const MAX_LINES: usize = 800;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// Every crate's `src` directory.
fn crate_sources() -> Vec<PathBuf> {
    let root = root();
    let mut dirs = vec![root.join("proto/src")];
    for group in ["crates", "services"] {
        let mut found: Vec<PathBuf> = std::fs::read_dir(root.join(group))
            .unwrap()
            .map(|e| e.unwrap().path().join("src"))
            .filter(|p| p.is_dir())
            .collect();
        found.sort();
        dirs.extend(found);
    }
    dirs
}

fn rust_files(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            out.extend(rust_files(&p));
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
    out.sort();
    out
}

/// The code of a file without its test module and without comments.
fn code(path: &Path) -> Vec<String> {
    if path.file_name().is_some_and(|n| n == "tests.rs") {
        return Vec::new();
    }
    let text = std::fs::read_to_string(path).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    let end = lines
        .windows(2)
        .position(|w| w[0].trim() == "#[cfg(test)]" && w[1].trim_start().starts_with("mod tests"))
        .unwrap_or(lines.len());
    lines[..end]
        .iter()
        .filter(|l| !l.trim_start().starts_with("//"))
        .map(|l| l.to_string())
        .collect()
}

/// The top-level module a file belongs to (`validate/limits.rs` → `validate`),
/// `None` for the crate root.
fn top_module(src: &Path, file: &Path) -> Option<String> {
    let rel = file.strip_prefix(src).unwrap();
    let first = rel
        .components()
        .next()?
        .as_os_str()
        .to_string_lossy()
        .into_owned();
    let name = first.trim_end_matches(".rs").to_string();
    (name != "lib" && name != "main").then_some(name)
}

/// `crate::x` paths in a line of code.
fn crate_paths(line: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut rest = line;
    while let Some(i) = rest.find("crate::") {
        let after = &rest[i + "crate::".len()..];
        let name: String = after
            .chars()
            .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
            .collect();
        let preceded = rest[..i]
            .chars()
            .last()
            .is_some_and(|c| c.is_ascii_alphanumeric() || c == '_');
        if !preceded && !name.is_empty() {
            out.push(name);
        }
        rest = after;
    }
    out
}

/// The module graph of a crate: module → the modules it uses.
fn module_graph(src: &Path) -> BTreeMap<String, BTreeSet<String>> {
    let files = rust_files(src);
    let modules: BTreeSet<String> = files.iter().filter_map(|f| top_module(src, f)).collect();
    let mut graph: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for f in &files {
        let Some(m) = top_module(src, f) else {
            continue;
        };
        let uses = graph.entry(m.clone()).or_default();
        for line in code(f) {
            for used in crate_paths(&line) {
                if used != m && modules.contains(&used) {
                    uses.insert(used);
                }
            }
        }
    }
    graph
}

/// A cycle of the graph, if it has one.
fn cycle(graph: &BTreeMap<String, BTreeSet<String>>) -> Option<Vec<String>> {
    fn visit(
        g: &BTreeMap<String, BTreeSet<String>>,
        v: &str,
        path: &mut Vec<String>,
        done: &mut BTreeSet<String>,
    ) -> Option<Vec<String>> {
        if let Some(i) = path.iter().position(|p| p == v) {
            let mut c = path[i..].to_vec();
            c.push(v.to_string());
            return Some(c);
        }
        if done.contains(v) {
            return None;
        }
        path.push(v.to_string());
        for w in g.get(v).into_iter().flatten() {
            if let Some(c) = visit(g, w, path, done) {
                return Some(c);
            }
        }
        path.pop();
        done.insert(v.to_string());
        None
    }
    let mut done = BTreeSet::new();
    graph
        .keys()
        .find_map(|v| visit(graph, v, &mut Vec::new(), &mut done))
}

/// The paths to `prefix` + a name in a line of code (`super::` or
/// `crate::library::`): the names.
fn paths_after(line: &str, prefix: &str) -> Vec<String> {
    line.match_indices(prefix)
        .filter_map(|(at, _)| {
            // A path's first segment only: not `a::super::x`, not the
            // second `super::` of `super::super::x`, which names the
            // grandparent's module, not a sibling.
            let preceded = line[..at]
                .chars()
                .last()
                .is_some_and(|c| c.is_ascii_alphanumeric() || c == '_' || c == ':');
            let name: String = line[at + prefix.len()..]
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                .collect();
            (!preceded && !name.is_empty() && name != "super").then_some(name)
        })
        .collect()
}

/// For every folder of modules below a crate's root (`library/`): the
/// graph of its sibling modules (`defs`, `milling`, `wire`) through the
/// paths one writes to another, `super::milling::…` or
/// `crate::library::milling::…`.
fn sibling_graphs(src: &Path) -> Vec<(PathBuf, BTreeMap<String, BTreeSet<String>>)> {
    fn folders(dir: &Path, out: &mut Vec<PathBuf>) {
        for e in std::fs::read_dir(dir).unwrap().flatten() {
            if e.path().is_dir() {
                out.push(e.path());
                folders(&e.path(), out);
            }
        }
    }
    let mut dirs = Vec::new();
    folders(src, &mut dirs);
    let mut out = Vec::new();
    for dir in dirs {
        // The folder's modules: `x.rs` and `x/mod.rs`, each with its file.
        let mut modules: BTreeMap<String, PathBuf> = BTreeMap::new();
        for e in std::fs::read_dir(&dir).unwrap().flatten() {
            let path = e.path();
            let name = e.file_name().to_string_lossy().into_owned();
            if path.is_dir() && path.join("mod.rs").is_file() {
                modules.insert(name, path.join("mod.rs"));
            } else if let Some(stem) = name.strip_suffix(".rs") {
                if stem != "mod" {
                    modules.insert(stem.to_string(), path);
                }
            }
        }
        let rel = dir.strip_prefix(src).unwrap();
        let crate_path = format!(
            "crate::{}::",
            rel.components()
                .map(|c| c.as_os_str().to_string_lossy().into_owned())
                .collect::<Vec<_>>()
                .join("::")
        );
        let mut graph: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
        for (m, file) in &modules {
            let uses = graph.entry(m.clone()).or_default();
            for line in code(file) {
                for used in paths_after(&line, "super::")
                    .into_iter()
                    .chain(paths_after(&line, &crate_path))
                {
                    if &used != m && modules.contains_key(&used) {
                        uses.insert(used);
                    }
                }
            }
        }
        out.push((dir, graph));
    }
    out
}

#[test]
fn no_crate_has_an_import_loop() {
    let mut loops = Vec::new();
    for src in crate_sources() {
        if let Some(c) = cycle(&module_graph(&src)) {
            loops.push(format!("{}: {}", src.display(), c.join(" → ")));
        }
        for (dir, graph) in sibling_graphs(&src) {
            if let Some(c) = cycle(&graph) {
                loops.push(format!("{}: {}", dir.display(), c.join(" → ")));
            }
        }
    }
    assert!(loops.is_empty(), "import loops:\n{}", loops.join("\n"));
}

#[test]
fn the_loop_finder_finds_a_loop() {
    // The check above would pass vacuously if it could not see a loop.
    let mut g: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    g.entry("render".into()).or_default().insert("expr".into());
    g.entry("expr".into()).or_default().insert("params".into());
    g.entry("params".into())
        .or_default()
        .insert("render".into());
    assert_eq!(
        cycle(&g).unwrap(),
        ["expr", "params", "render", "expr"].map(String::from)
    );
    g.get_mut("params").unwrap().clear();
    assert_eq!(cycle(&g), None);
    assert_eq!(
        crate_paths("use crate::render::format_fixed; x = crate::expr::f(); notcrate::y"),
        ["render", "expr"].map(String::from)
    );
    assert_eq!(
        paths_after(
            "use super::defs::f; super::super::x; a::super::y",
            "super::"
        ),
        ["defs"].map(String::from)
    );
}

#[test]
fn no_source_file_is_over_800_lines_of_code() {
    let mut long = Vec::new();
    for src in crate_sources() {
        for f in rust_files(&src) {
            if f.file_name().is_some_and(|n| n == "tests.rs") {
                continue;
            }
            let text = std::fs::read_to_string(&f).unwrap();
            let lines: Vec<&str> = text.lines().collect();
            let end = lines
                .windows(2)
                .position(|w| {
                    w[0].trim() == "#[cfg(test)]" && w[1].trim_start().starts_with("mod tests")
                })
                .unwrap_or(lines.len());
            if end > MAX_LINES {
                long.push(format!("{}: {end} lines", f.display()));
            }
        }
    }
    assert!(
        long.is_empty(),
        "over {MAX_LINES} lines:\n{}",
        long.join("\n")
    );
}

#[test]
fn key_expressions_are_spelled_only_in_proto_keys() {
    let keys = root().join("proto/src/keys.rs");
    let mut found = Vec::new();
    for src in crate_sources() {
        for f in rust_files(&src) {
            if f.canonicalize().unwrap() == keys.canonicalize().unwrap() {
                continue;
            }
            for line in code(&f) {
                if line.contains("\"gearcam/v1") || line.contains("keys::PREFIX") {
                    found.push(format!("{}: {}", f.display(), line.trim()));
                }
            }
        }
    }
    assert!(
        found.is_empty(),
        "keys outside proto/src/keys.rs:\n{}",
        found.join("\n")
    );
}

/// Every text file of the repository that a person reads or a build uses:
/// sources, docs, configurations, scripts (not `target/`, not `.git/`).
fn text_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        let path = e.path();
        let name = e.file_name().to_string_lossy().into_owned();
        if path.is_dir() {
            if !matches!(name.as_str(), "target" | ".git") {
                text_files(&path, out);
            }
        } else if ["rs", "md", "toml", "py", "json5", "sh", "tpl"]
            .iter()
            .any(|ext| name.ends_with(&format!(".{ext}")))
            || name == "run"
        {
            out.push(path);
        }
    }
}

/// The line cites an issue by number (`issue 12`, `Issues 5`) or the old
/// specification by name (`SPEC`), which are not in the repository.
fn cites_outside(line: &str) -> bool {
    let lower = line.to_lowercase();
    let by_number = ["issue ", "issues "].iter().any(|w| {
        lower.match_indices(w).any(|(at, _)| {
            let before = lower[..at].chars().next_back();
            let word_start = before.is_none_or(|c| !c.is_alphanumeric());
            word_start && lower[at + w.len()..].starts_with(|c: char| c.is_ascii_digit())
        })
    });
    let spec = line.match_indices("SPEC").any(|(at, _)| {
        let before = line[..at].chars().next_back();
        let after = line[at + 4..].chars().next();
        before.is_none_or(|c| !c.is_alphanumeric() && c != '_')
            && after.is_none_or(|c| !c.is_alphanumeric() && c != '_')
    });
    by_number || spec
}

/// The code and the docs say what they do and why in their own words:
/// no citation of an issue's number or of the old specification, which a
/// reader of the repository cannot open.
#[test]
fn nothing_cites_an_issue_or_the_old_specification() {
    let mut files = Vec::new();
    text_files(&root(), &mut files);
    let this = Path::new(file!()).file_name().expect("this file's name");
    let mut found = Vec::new();
    for f in files.iter().filter(|f| f.file_name() != Some(this)) {
        let Ok(text) = std::fs::read_to_string(f) else {
            continue;
        };
        for (i, line) in text.lines().enumerate() {
            if cites_outside(line) {
                found.push(format!("{}:{}: {}", f.display(), i + 1, line.trim()));
            }
        }
    }
    assert!(files.len() > 100, "the walk found {} files", files.len());
    assert!(
        found.is_empty(),
        "citations of issues or of a specification outside the repository:\n{}",
        found.join("\n")
    );
}

#[test]
fn the_citation_finder_finds_citations() {
    for line in [
        "// Issue 12, point 7: exit codes",
        "see issues 5 and 6",
        "(the SPEC's formula)",
        "per SPEC §4.2",
    ] {
        assert!(cites_outside(line), "{line}");
    }
    for line in [
        "the job spec (JobSpec)",
        "an issue with the hob",
        "tissue 5",
        "SPECIAL_CASE",
        "eclipse-zenoh/zenoh#2557",
    ] {
        assert!(!cites_outside(line), "{line}");
    }
}

/// `{package version} → features` of the resolved dependency graph.
fn features(args: &[&str]) -> BTreeMap<String, BTreeSet<String>> {
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let run = |offline: bool| {
        let mut cmd = std::process::Command::new(&cargo);
        cmd.current_dir(root()).arg("tree").args(args);
        cmd.args(["--prefix", "none", "-f", "{p} {f}"]);
        if offline {
            cmd.arg("--offline");
        }
        cmd.output().expect("cargo tree runs")
    };
    let out = Some(run(true))
        .filter(|o| o.status.success())
        .unwrap_or_else(|| run(false));
    assert!(
        out.status.success(),
        "cargo tree: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let mut map: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for line in String::from_utf8_lossy(&out.stdout).lines() {
        let parts: Vec<&str> = line.split(' ').collect();
        if parts.len() < 2 || parts[1].starts_with('(') {
            continue;
        }
        let feats = parts[2..].join(" ").replace("(*)", "").trim().to_string();
        map.entry(format!("{} {}", parts[0], parts[1]))
            .or_default()
            .insert(feats);
    }
    map
}

#[test]
fn the_demo_and_the_tests_share_one_build() {
    // `cargo run -- demo` builds the gearcam binary's normal dependencies;
    // `cargo test --workspace` resolves every package with its dev-
    // dependencies. Where a dependency of the demo gets other features in the
    // tests, cargo builds it (and everything above it) twice.
    let demo = features(&["-p", "gearcam", "-e", "normal,build"]);
    let tests = features(&["--workspace"]);
    let differ: Vec<String> = demo
        .iter()
        .filter_map(|(k, f)| {
            let t = tests.get(k)?;
            (t != f).then(|| format!("{k}: demo {f:?}, tests {t:?}"))
        })
        .collect();
    assert!(
        differ.is_empty(),
        "features differ (add them to the feature unification in services/bus/Cargo.toml):\n{}",
        differ.join("\n")
    );
}

/// The source folder of each workspace crate, by the name code uses for it
/// (`gearcam_template` → `services/template/src`).
fn crate_dirs() -> BTreeMap<String, PathBuf> {
    let mut out = BTreeMap::new();
    for src in crate_sources() {
        let manifest = src.parent().unwrap().join("Cargo.toml");
        let text = std::fs::read_to_string(&manifest).unwrap();
        let name = text
            .lines()
            .find_map(|l| l.trim().strip_prefix("name = \""))
            .and_then(|l| l.strip_suffix('"'))
            .unwrap_or_else(|| panic!("no package name in {}", manifest.display()));
        out.insert(name.replace('-', "_"), src);
    }
    out
}

/// True when `name` is defined, or re-exported, in `file`.
fn defines(file: &Path, name: &str) -> bool {
    let text = std::fs::read_to_string(file).unwrap_or_default();
    let word = |line: &str, at: usize| {
        let end = at + name.len();
        !line[..at].ends_with(|c: char| c.is_alphanumeric() || c == '_')
            && !line[end..].starts_with(|c: char| c.is_alphanumeric() || c == '_')
    };
    text.lines().any(|line| {
        let l = line.trim_start();
        line.match_indices(name).any(|(at, _)| {
            word(line, at)
                && (["fn", "struct", "enum", "const", "type", "trait", "static", "mod"]
                    .iter()
                    .any(|k| line[..at].trim_end().ends_with(k))
                    || l.starts_with("pub use")
                    || l.starts_with(&format!("{name}(")) // an enum variant
                    || l.starts_with(&format!("{name} {{"))
                    || l.starts_with(&format!("{name},")))
        })
    })
}

/// What is wrong with a Rust path written in the docs
/// (`gearcam_knowledge::plan::choose_hob`), or `None` when its module
/// exists and defines its last name. A segment with no module file of its
/// own is a type, and the name is looked up in the module that holds it.
fn rust_path_problem(path: &str, crates: &BTreeMap<String, PathBuf>) -> Option<String> {
    let segs: Vec<&str> = path.trim_end_matches("()").split("::").collect();
    let dir = crates.get(segs[0])?;
    let (mut dir, mut file) = (dir.clone(), dir.join("lib.rs"));
    if !file.is_file() {
        file = dir.join("main.rs");
    }
    for (i, seg) in segs[1..segs.len() - 1].iter().enumerate() {
        if dir.join(format!("{seg}.rs")).is_file() {
            file = dir.join(format!("{seg}.rs"));
            dir = dir.join(seg);
        } else if dir.join(seg).join("mod.rs").is_file() {
            file = dir.join(seg).join("mod.rs");
            dir = dir.join(seg);
        } else if i + 2 < segs.len() - 1 || !seg.starts_with(char::is_uppercase) {
            return Some(format!("no module {seg}"));
        }
    }
    let name = segs[segs.len() - 1];
    let in_folder = std::fs::read_dir(&dir)
        .map(|d| {
            d.flatten().any(|e| {
                e.path().extension().is_some_and(|x| x == "rs") && defines(&e.path(), name)
            })
        })
        .unwrap_or(false);
    (!defines(&file, name) && !in_folder).then(|| format!("{name} is not in {}", file.display()))
}

/// Every repository path and every path into gearcam's crates written in
/// backticks in the docs exists: a doc that names a file or a function
/// that moved or never was sends its reader nowhere.
#[test]
fn the_docs_name_files_and_functions_that_exist() {
    const TOPS: [&str; 8] = [
        "services/",
        "crates/",
        "proto/",
        "deploy/",
        "docs/",
        "tests/",
        "examples/",
        ".ci/",
    ];
    let root = root();
    let crates = crate_dirs();
    let mut docs: Vec<PathBuf> = std::fs::read_dir(root.join("docs"))
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "md"))
        .collect();
    for f in [
        "README.md",
        "deploy/README.md",
        "proto/README.md",
        "tests/tests/README.md",
    ] {
        docs.push(root.join(f));
    }
    let mut missing = Vec::new();
    for doc in &docs {
        let text = std::fs::read_to_string(doc).unwrap();
        for (n, line) in text.lines().enumerate() {
            for tok in line.split('`').skip(1).step_by(2) {
                let tok = tok.split('#').next().unwrap_or_default();
                let tok = tok.trim_end_matches(['.', ',', ';', ':']);
                if tok.contains([' ', '{', '*', '…', '|', '<', '[']) {
                    continue;
                }
                let problem = if TOPS.iter().any(|t| tok.starts_with(t)) {
                    let path = tok.split(':').next().unwrap_or_default();
                    let here = doc.parent().unwrap().join(path);
                    (!root.join(path).exists() && !here.exists())
                        .then(|| "no such file".to_string())
                } else if tok.contains("::") && crates.contains_key(tok.split("::").next().unwrap())
                {
                    rust_path_problem(tok, &crates)
                } else {
                    None
                };
                if let Some(p) = problem {
                    missing.push(format!("{}:{}: `{tok}`: {p}", doc.display(), n + 1));
                }
            }
        }
    }
    assert!(docs.len() > 8, "{} docs read", docs.len());
    assert!(
        missing.is_empty(),
        "the docs name what is not there:\n{}",
        missing.join("\n")
    );
}

/// `docs/architecture.md` lists every crate of the workspace by its folder,
/// so a newcomer finds each one there.
#[test]
fn the_architecture_page_lists_every_crate() {
    let page = std::fs::read_to_string(root().join("docs/architecture.md")).unwrap();
    let missing: Vec<String> = crate_sources()
        .iter()
        .map(|src| {
            let folder = src.parent().unwrap().strip_prefix(root()).unwrap();
            format!("{}/", folder.display())
        })
        .filter(|folder| !page.contains(&format!("\n{folder}")))
        .collect();
    assert!(
        missing.is_empty(),
        "crates missing from docs/architecture.md: {missing:?}"
    );
}

/// The shared libraries (`proto`, `crates/*`) depend, in any section of
/// their manifests, only on `proto` and on one another: never on a service
/// or on the test support, which sit above them.
#[test]
fn the_shared_libraries_depend_on_nothing_above_them() {
    let root = root();
    let mut shared = vec![root.join("proto")];
    let mut crates: Vec<PathBuf> = std::fs::read_dir(root.join("crates"))
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.join("Cargo.toml").is_file())
        .collect();
    crates.sort();
    shared.extend(crates);
    let name_of = |dir: &Path| {
        let text = std::fs::read_to_string(dir.join("Cargo.toml")).unwrap();
        text.lines()
            .find_map(|l| l.trim().strip_prefix("name = \""))
            .and_then(|l| l.strip_suffix('"'))
            .unwrap()
            .to_string()
    };
    let allowed: BTreeSet<String> = shared.iter().map(|d| name_of(d)).collect();
    let mut upward = Vec::new();
    for dir in &shared {
        let text = std::fs::read_to_string(dir.join("Cargo.toml")).unwrap();
        for line in text.lines() {
            let dep = line.split(['=', '.']).next().unwrap_or_default().trim();
            if dep.starts_with("gearcam") && !allowed.contains(dep) {
                upward.push(format!("{} → {dep}", name_of(dir)));
            }
        }
    }
    assert!(allowed.len() >= 5, "{allowed:?}");
    assert!(
        upward.is_empty(),
        "shared libraries depending on what is above them: {upward:?}"
    );
}

/// The longest function allowed outside tests, in lines from its `fn` to
/// its closing brace.
const MAX_FUNCTION_LINES: usize = 120;

/// `line` declares a function (any visibility, `const`/`async`/`unsafe`):
/// its name.
fn declared_fn(line: &str) -> Option<&str> {
    let mut rest = line.trim_start();
    for prefix in [
        "pub(crate) ",
        "pub(super) ",
        "pub ",
        "const ",
        "async ",
        "unsafe ",
    ] {
        rest = rest.strip_prefix(prefix).unwrap_or(rest);
    }
    let rest = rest.strip_prefix("fn ")?;
    let name: &str = rest
        .split(|c: char| !(c.is_alphanumeric() || c == '_'))
        .next()
        .unwrap_or_default();
    (!name.is_empty()).then_some(name)
}

/// The braces of `line` that count (outside strings, characters and a
/// trailing comment): +1 for `{`, −1 for `}`. `in_string` carries an open
/// string literal across lines.
fn brace_balance(line: &str, in_string: &mut bool) -> i64 {
    let chars: Vec<char> = line.chars().collect();
    let mut depth = 0;
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        if *in_string {
            match c {
                '\\' => i += 1,
                '"' => *in_string = false,
                _ => {}
            }
        } else {
            match c {
                '"' => *in_string = true,
                '/' if chars.get(i + 1) == Some(&'/') => break,
                // A character literal: 'x' or '\x' (a lifetime has no closing quote).
                '\'' if chars.get(i + 2) == Some(&'\'') => i += 2,
                '\'' if chars.get(i + 1) == Some(&'\\') => {
                    while i + 1 < chars.len() && chars[i + 1] != '\'' {
                        i += 1;
                    }
                    i += 1;
                }
                '{' => depth += 1,
                '}' => depth -= 1,
                _ => {}
            }
        }
        i += 1;
    }
    depth
}

/// Every function of `lines` with a body: its name, first line (1-based)
/// and length in lines, from its `fn` to its closing brace.
fn functions(lines: &[String]) -> Vec<(String, usize, usize)> {
    let mut out = Vec::new();
    for (start, line) in lines.iter().enumerate() {
        let Some(name) = declared_fn(line) else {
            continue;
        };
        let (mut depth, mut opened, mut in_string) = (0i64, false, false);
        for (k, l) in lines.iter().enumerate().skip(start) {
            if !opened && depth == 0 && l.trim_end().ends_with(';') && !l.contains('{') {
                break; // a declaration without a body
            }
            depth += brace_balance(l, &mut in_string);
            opened |= depth > 0;
            if opened && depth == 0 {
                out.push((name.to_string(), start + 1, k - start + 1));
                break;
            }
        }
    }
    out
}

/// The files that hold only tests: `tests.rs` and every module declared
/// under `#[cfg(test)]` in its own file.
fn test_only_files(files: &[PathBuf]) -> BTreeSet<PathBuf> {
    let mut out = BTreeSet::new();
    for f in files {
        let text = std::fs::read_to_string(f).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        for w in lines.windows(2) {
            let decl = w[1].trim();
            if w[0].trim() != "#[cfg(test)]" || !decl.ends_with(';') {
                continue;
            }
            let name = decl.trim_end_matches(';').rsplit(' ').next().unwrap();
            let dir = f.parent().unwrap();
            let stem = f.file_stem().unwrap().to_string_lossy();
            let base = if ["lib", "main", "mod"].contains(&stem.as_ref()) {
                dir.to_path_buf()
            } else {
                dir.join(stem.as_ref())
            };
            out.insert(base.join(format!("{name}.rs")));
            out.insert(base.join(name).join("mod.rs"));
        }
    }
    out
}

/// Every function outside tests in the crates' sources, longest first.
fn all_functions() -> Vec<(usize, String)> {
    let mut found = Vec::new();
    for src in crate_sources() {
        let files = rust_files(&src);
        let tests = test_only_files(&files);
        for f in files.iter().filter(|f| !tests.contains(*f)) {
            let text = std::fs::read_to_string(f).unwrap();
            let lines: Vec<String> = code_with_comments(&text);
            for (name, at, len) in functions(&lines) {
                found.push((len, format!("{}:{at} {name}", f.display())));
            }
        }
    }
    found.sort_by(|a, b| b.cmp(a));
    found
}

/// The lines of a file before its `#[cfg(test)] mod tests`, comments kept
/// (a function's length counts its comments).
fn code_with_comments(text: &str) -> Vec<String> {
    let lines: Vec<&str> = text.lines().collect();
    let end = lines
        .windows(2)
        .position(|w| w[0].trim() == "#[cfg(test)]" && w[1].trim_start().starts_with("mod tests"))
        .unwrap_or(lines.len());
    lines[..end].iter().map(|l| l.to_string()).collect()
}

#[test]
fn no_function_outside_tests_is_over_120_lines() {
    let all = all_functions();
    if std::env::var_os("GEARCAM_LONGEST").is_some() {
        for (len, at) in all.iter().take(15) {
            println!("{len:5} {at}");
        }
    }
    let long: Vec<String> = all
        .iter()
        .filter(|(len, _)| *len > MAX_FUNCTION_LINES)
        .map(|(len, at)| format!("{at}: {len} lines"))
        .collect();
    assert!(
        long.is_empty(),
        "functions over {MAX_FUNCTION_LINES} lines (split them by what they do):\n{}",
        long.join("\n")
    );
}

#[test]
fn the_function_measure_finds_bodies_and_their_ends() {
    let text = r#"
pub(crate) fn short(a: u32) -> u32 {
    let brace = '{';
    let s = "}}} {";
    a + 1 // }
}

fn long<'a>(
    x: &'a str,
) -> &'a str
where
    'a: 'a,
{
    if x.is_empty() {
        x
    } else {
        x
    }
}
trait T {
    fn declared(&self);
}
"#;
    let lines: Vec<String> = text.lines().map(str::to_string).collect();
    assert_eq!(
        functions(&lines),
        [("short".to_string(), 2, 5), ("long".to_string(), 8, 12)]
    );
}
