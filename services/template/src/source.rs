//! Reading a template directory: the only I/O of this library, done once at start.
//!
//! Every file named `{id}.tpl` (e.g. `cylindrical_840d.tpl`, the standard-code
//! format of [`crate::stdcode`]) in the directory is a template with that id;
//! sub-directories and other files are ignored. A template from the directory
//! replaces the library's template of the same id for this run, so a shop can try
//! its own revision of `cylindrical_840d` before importing it.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use crate::error::TemplateError;
use crate::render::TemplateSource;

/// Reads every `*.tpl` file of `dir` (not recursively), sorted by id.
pub fn read_dir(dir: &Path) -> Result<Vec<TemplateSource>, TemplateError> {
    let io = |path: &Path, source| TemplateError::Io {
        path: path.to_path_buf(),
        source,
    };
    let mut found: BTreeMap<String, (PathBuf, String)> = BTreeMap::new();
    for entry in std::fs::read_dir(dir).map_err(|e| io(dir, e))? {
        let path = entry.map_err(|e| io(dir, e))?.path();
        let Some(file_name) = path.file_name().and_then(|n| n.to_str()) else {
            continue;
        };
        if !path.is_file() || !file_name.ends_with(".tpl") {
            continue;
        }
        let id = file_name.split('.').next().unwrap_or_default().to_string();
        let text = std::fs::read_to_string(&path).map_err(|e| io(&path, e))?;
        if let Some((first, _)) = found.get(&id) {
            return Err(TemplateError::DuplicateId {
                id,
                first: first.clone(),
                second: path,
            });
        }
        found.insert(id, (path, text));
    }
    Ok(found
        .into_iter()
        .map(|(id, (_, source))| TemplateSource { id, source })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_tpl_files_by_id_and_ignores_others() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("conical_840d.tpl"), "@version 2\nX").unwrap();
        std::fs::write(dir.path().join("README.md"), "not a template").unwrap();
        let sources = read_dir(dir.path()).unwrap();
        assert_eq!(sources.len(), 1);
        assert_eq!(sources[0].id, "conical_840d");
        assert_eq!(sources[0].source, "@version 2\nX");
    }

    #[test]
    fn rejects_two_files_with_one_id() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("conical_840d.tpl"), "@version 1").unwrap();
        std::fs::write(dir.path().join("conical_840d.old.tpl"), "@version 1").unwrap();
        let err = read_dir(dir.path()).unwrap_err();
        assert!(matches!(err, TemplateError::DuplicateId { ref id, .. } if id == "conical_840d"));
    }

    #[test]
    fn names_the_missing_directory() {
        let err = read_dir(Path::new("/nonexistent/gearcam-templates")).unwrap_err();
        assert!(
            err.to_string().contains("/nonexistent/gearcam-templates"),
            "{err}"
        );
    }
}
