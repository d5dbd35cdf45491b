//! Scratch directories for the tests (the unit tests' and, through a
//! `#[path]` module, the command-line tests'): a fresh directory per test,
//! removed when its guard is dropped in a passing test and kept for
//! inspection when the test fails.

use std::ffi::OsStr;
use std::path::{Path, PathBuf};

/// A path inside a fresh temporary directory `veselov-<pid>-<name>`, which
/// is removed when the guard is dropped unless the thread is panicking.
pub struct Scratch {
    root: PathBuf,
    path: PathBuf,
}

impl Scratch {
    /// A fresh, empty directory for the test `name` (unique within the
    /// process).
    ///
    /// # Panics
    /// If the directory cannot be created.
    pub fn new(name: &str) -> Self {
        let root = std::env::temp_dir().join(format!("veselov-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&root);
        std::fs::create_dir_all(&root).expect("create the scratch directory");
        Self {
            path: root.clone(),
            root,
        }
    }

    /// The same scratch directory seen at `root/relative` (not created).
    #[allow(dead_code)] // the command-line tests' (the unit tests do not need it)
    pub fn at(mut self, relative: &str) -> Self {
        self.path = self.root.join(relative);
        self
    }
}

impl std::ops::Deref for Scratch {
    type Target = Path;
    fn deref(&self) -> &Path {
        &self.path
    }
}

impl AsRef<Path> for Scratch {
    fn as_ref(&self) -> &Path {
        &self.path
    }
}

impl AsRef<OsStr> for Scratch {
    fn as_ref(&self) -> &OsStr {
        self.path.as_os_str()
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        if !std::thread::panicking() {
            let _ = std::fs::remove_dir_all(&self.root);
        }
    }
}
