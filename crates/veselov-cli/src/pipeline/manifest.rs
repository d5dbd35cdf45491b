//! `outputs.json`: the files a run wrote into its output directory, so that
//! `--force` removes those and nothing else.
//!
//! A run notes the directory's files (length and modification time) when
//! it opens it; every file that is new or changed when it records its
//! outputs (once its files are open, at each checkpoint, and when it ends,
//! however it ends) is its own, and is added to the list. A resumed run
//! keeps the list of the parts before it; `veselov plot DIR` adds the
//! figures it draws. The file is replaced atomically:
//!
//! ```json
//! { "files": ["energy.csv", "snapshots.npy", "summary.json", …] }
//! ```
//!
//! `--force` then removes the listed files (plain names in the directory,
//! never a path elsewhere) and the list. A directory written by an earlier
//! version of the command has no list: there the files named as runs name
//! their outputs ([`is_run_output`]) are removed, if the directory holds a
//! run's `summary.json` or `checkpoint.json` (otherwise nothing is
//! removed: the directory holds no run, only files of its own).

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::time::SystemTime;

use serde_json::json;

use crate::error::CliError;
use crate::output::is_run_output;

/// The record's file name in an output directory.
pub const FILE: &str = "outputs.json";

fn io(path: &Path, e: impl ToString) -> CliError {
    CliError::Io {
        path: path.to_path_buf(),
        message: e.to_string(),
    }
}

/// The regular files of a directory (by name) with their length and
/// modification time, as found at one moment.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Snapshot(BTreeMap<String, (u64, Option<SystemTime>)>);

impl Snapshot {
    /// The files of `dir` now (none if it cannot be read).
    pub fn take(dir: &Path) -> Self {
        let Ok(entries) = std::fs::read_dir(dir) else {
            return Self::default();
        };
        Self(
            entries
                .filter_map(Result::ok)
                .filter_map(|e| {
                    let name = e.file_name().into_string().ok()?;
                    let meta = e.metadata().ok().filter(std::fs::Metadata::is_file)?;
                    Some((name, (meta.len(), meta.modified().ok())))
                })
                .collect(),
        )
    }

    /// The names of the files of `now` that are not in `self` or differ.
    fn written_since<'a>(&'a self, now: &'a Self) -> impl Iterator<Item = &'a String> + 'a {
        now.0
            .iter()
            .filter(|(name, meta)| self.0.get(*name) != Some(*meta))
            .map(|(name, _)| name)
    }
}

/// Whether `name` may be listed: a plain file name in the directory (no
/// separator, not `.` or `..`), not hidden (the lock, temporary files) and
/// not the record itself.
fn listable(name: &str) -> bool {
    !name.is_empty() && !name.starts_with('.') && !name.contains(['/', '\\']) && name != FILE
}

/// The files `dir`'s record lists (`Ok(None)` if it has none).
///
/// # Errors
/// [`CliError::Io`] naming the record if it exists but cannot be read as one.
pub fn recorded(dir: &Path) -> Result<Option<BTreeSet<String>>, CliError> {
    let path = dir.join(FILE);
    let text = match std::fs::read_to_string(&path) {
        Ok(text) => text,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(e) => return Err(io(&path, e)),
    };
    let bad = || {
        io(
            &path,
            "not a record of a run's files (expected {\"files\": [names…]}); remove the earlier outputs by hand \
             or choose another directory",
        )
    };
    let value: serde_json::Value = serde_json::from_str(&text).map_err(|_| bad())?;
    let files = value
        .get("files")
        .and_then(serde_json::Value::as_array)
        .ok_or_else(bad)?;
    files
        .iter()
        .map(|f| f.as_str().filter(|n| listable(n)).map(str::to_owned).ok_or_else(bad))
        .collect::<Result<_, _>>()
        .map(Some)
}

/// Add to `dir`'s record the files written since `before` (kept: the
/// files it lists already).
///
/// # Errors
/// [`CliError::Io`] if the record cannot be written.
pub fn record(dir: &Path, before: &Snapshot) -> Result<(), CliError> {
    let now = Snapshot::take(dir);
    let mut files = recorded(dir).ok().flatten().unwrap_or_default();
    let count = files.len();
    files.extend(before.written_since(&now).filter(|n| listable(n)).cloned());
    if files.len() == count && dir.join(FILE).exists() {
        return Ok(());
    }
    let path = dir.join(FILE);
    let tmp = dir.join(format!(".{FILE}.tmp"));
    crate::output::write_json(&tmp, &json!({ "files": files }))?;
    std::fs::rename(&tmp, &path).map_err(|e| io(&path, e))
}

/// Remove from `dir` the outputs of the run before: the files its record
/// lists and the record, or, without a record, the files named as run
/// outputs if the directory holds a run ([`module docs`](self)). Files it
/// does not name, and subdirectories, are kept.
///
/// # Errors
/// [`CliError::Io`] naming the record that cannot be read or a file that
/// cannot be removed.
pub fn remove_earlier_outputs(dir: &Path) -> Result<(), CliError> {
    let remove = |name: &str| {
        let path = dir.join(name);
        match std::fs::symlink_metadata(&path) {
            Ok(meta) if !meta.is_dir() => std::fs::remove_file(&path).map_err(|e| io(&path, e)),
            _ => Ok(()),
        }
    };
    if let Some(files) = recorded(dir)? {
        for name in &files {
            remove(name)?;
        }
        return remove(FILE);
    }
    let holds_a_run = ["summary.json", "checkpoint.json"]
        .iter()
        .any(|f| dir.join(f).is_file());
    if !holds_a_run {
        return Ok(());
    }
    let entries = std::fs::read_dir(dir).map_err(|e| io(dir, e))?;
    for entry in entries {
        let entry = entry.map_err(|e| io(dir, e))?;
        if let Some(name) = entry.file_name().to_str().filter(|n| is_run_output(n)) {
            remove(name)?;
        }
    }
    Ok(())
}

/// Make `dir` ready for a run: create it, or refuse if it holds files (its
/// lock aside: the run's own, taken first) and `force` is off. With
/// `force`, the files an earlier run wrote there are removed first (those
/// its `outputs.json` lists; see [`remove_earlier_outputs`]),
/// so that none of them is taken for an output of the new run; other files
/// and subdirectories are kept.
pub fn prepare_dir(dir: &Path, force: bool) -> Result<PathBuf, CliError> {
    if dir.exists() {
        let mut entries = std::fs::read_dir(dir)
            .map_err(crate::output::io(dir))?
            .filter(|e| !matches!(e, Ok(e) if e.file_name() == super::lock::FILE));
        if entries.next().is_some() && !force {
            return Err(CliError::OutputNotEmpty { dir: dir.to_path_buf() });
        }
        if force {
            remove_earlier_outputs(dir)?;
        }
    } else {
        std::fs::create_dir_all(dir).map_err(crate::output::io(dir))?;
    }
    // Probe writability now, before any computation.
    let probe = dir.join(".veselov-write-test");
    std::fs::write(&probe, b"").map_err(crate::output::io(dir))?;
    std::fs::remove_file(&probe).map_err(crate::output::io(dir))?;
    Ok(dir.to_path_buf())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_scratch::Scratch;

    #[test]
    fn only_what_a_run_wrote_is_recorded_and_removed() {
        let dir = Scratch::new("manifest");
        std::fs::write(dir.join("field_9.png"), b"mine").expect("user file");
        std::fs::write(dir.join("notes.txt"), b"mine").expect("user file");
        let before = Snapshot::take(&dir);
        std::fs::write(dir.join("energy.csv"), b"t,energy\n").expect("output");
        std::fs::write(dir.join("field_0.png"), b"drawn").expect("output");
        std::fs::write(dir.join(".veselov.lock"), b"pid 1\n").expect("lock");
        record(&dir, &before).expect("record");
        let listed = recorded(&dir).expect("readable").expect("a record");
        assert_eq!(listed.into_iter().collect::<Vec<_>>(), ["energy.csv", "field_0.png"]);
        // A later record keeps the earlier names.
        let later = Snapshot::take(&dir);
        std::fs::write(dir.join("summary.json"), b"{}").expect("output");
        record(&dir, &later).expect("record");
        assert_eq!(recorded(&dir).expect("readable").expect("a record").len(), 3);
        remove_earlier_outputs(&dir).expect("removed");
        let left: BTreeSet<String> = Snapshot::take(&dir).0.into_keys().collect();
        assert_eq!(
            left.into_iter().collect::<Vec<_>>(),
            [".veselov.lock", "field_9.png", "notes.txt"]
        );
    }

    #[test]
    fn a_record_naming_paths_elsewhere_is_refused() {
        let dir = Scratch::new("manifest-paths");
        for files in [r#"["../x"]"#, r#"["a/b"]"#, r#"[".."]"#, "[1]", r#""x""#] {
            std::fs::write(dir.join(FILE), format!("{{\"files\": {files}}}")).expect("record");
            let e = remove_earlier_outputs(&dir).expect_err(files);
            assert!(e.to_string().contains(FILE), "{e}");
        }
    }

    #[test]
    fn without_a_record_only_a_directory_holding_a_run_is_cleaned_by_name() {
        let dir = Scratch::new("manifest-none");
        std::fs::write(dir.join("field_9.png"), b"mine").expect("user file");
        remove_earlier_outputs(&dir).expect("nothing to remove");
        assert!(dir.join("field_9.png").exists());
        std::fs::write(dir.join("summary.json"), b"{}").expect("an older run");
        remove_earlier_outputs(&dir).expect("removed by name");
        assert!(!dir.join("field_9.png").exists() && !dir.join("summary.json").exists());
    }
}
