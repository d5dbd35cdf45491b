//! The lock of an output directory: `.veselov.lock`, which a run creates
//! there before it touches anything (atomically: it is created only if it
//! does not exist) and removes when it ends, however it ends (completed,
//! failed, interrupted). A second run into the same directory meanwhile is
//! refused with an error naming the directory and the process that holds
//! it, so that two runs never write into one directory.
//!
//! The lock holds the process id of its run and, on Linux, that process's
//! start time (from `/proc/<pid>/stat`). A lock whose process is no longer
//! running (no `/proc/<pid>`, a zombie, or another process since given the
//! same id, told by its start time) was left by a run that was killed: it
//! is stale, and the next run replaces it with a note. Where `/proc` is
//! missing (other systems), a lock is taken as held; removing it by hand
//! frees the directory.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::{Duration, SystemTime};

use crate::error::CliError;

/// The lock's file name in an output directory.
pub const FILE: &str = ".veselov.lock";

/// How long a lock file that cannot be read yet (just created, its content
/// not yet written) is taken as held.
const BEING_WRITTEN: Duration = Duration::from_secs(10);

/// The lock of an output directory, held while this value lives: dropping
/// it removes the lock file.
#[derive(Debug)]
pub struct DirLock {
    path: PathBuf,
}

/// The process that holds a lock, as its file records it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Holder {
    pid: u32,
    /// Start time of the process (clock ticks after boot), where known.
    started: Option<u64>,
}

impl Holder {
    /// This process.
    fn current() -> Self {
        let pid = std::process::id();
        Self {
            pid,
            started: start_time(pid),
        }
    }

    /// The lock file's text.
    fn text(&self) -> String {
        match self.started {
            Some(t) => format!("pid {}\nstarted {t}\n", self.pid),
            None => format!("pid {}\n", self.pid),
        }
    }

    /// The holder a lock file's `text` records (`None` if it records none).
    fn parse(text: &str) -> Option<Self> {
        let mut pid = None;
        let mut started = None;
        for line in text.lines() {
            match line.split_once(' ') {
                Some(("pid", v)) => pid = v.trim().parse().ok(),
                Some(("started", v)) => started = v.trim().parse().ok(),
                _ => {}
            }
        }
        Some(Self { pid: pid?, started })
    }

    /// Whether the holder may still be running: `false` only when it is
    /// known not to be.
    fn running(&self) -> bool {
        if !Path::new("/proc/self").exists() {
            // No way to tell here: the lock is taken as held.
            return true;
        }
        let Ok(stat) = std::fs::read_to_string(format!("/proc/{}/stat", self.pid)) else {
            return false;
        };
        let Some(fields) = stat_fields(&stat) else {
            return true;
        };
        // A zombie or a dead process has ended.
        if matches!(fields.first(), Some(&("Z" | "X" | "x"))) {
            return false;
        }
        match (self.started, fields.get(19).and_then(|t| t.parse::<u64>().ok())) {
            // The id now names another process.
            (Some(then), Some(now)) => then == now,
            _ => true,
        }
    }
}

/// The fields of a `/proc/<pid>/stat` line after the command name (which
/// is in parentheses and may hold spaces): the state first, then the
/// parent's id, …; the start time is the 20th.
fn stat_fields(stat: &str) -> Option<Vec<&str>> {
    let (_, rest) = stat.rsplit_once(')')?;
    Some(rest.split_whitespace().collect())
}

/// The start time of process `pid` (clock ticks after boot), on Linux.
fn start_time(pid: u32) -> Option<u64> {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
    stat_fields(&stat)?.get(19)?.parse().ok()
}

fn io(path: &Path, e: impl ToString) -> CliError {
    CliError::Io {
        path: path.to_path_buf(),
        message: e.to_string(),
    }
}

impl DirLock {
    /// Lock `dir` (which exists) for this process's run, replacing a stale
    /// lock (with a note on standard error unless `quiet`).
    ///
    /// # Errors
    /// [`CliError::Locked`] if another run holds the directory;
    /// [`CliError::Io`] if the lock file cannot be written.
    pub fn acquire(dir: &Path, quiet: bool) -> Result<Self, CliError> {
        let path = dir.join(FILE);
        let me = Holder::current();
        // A few rounds: a stale lock removed here may be taken by another
        // run before this one creates its own.
        for _ in 0..4 {
            match std::fs::OpenOptions::new().write(true).create_new(true).open(&path) {
                Ok(mut file) => {
                    let lock = Self { path: path.clone() };
                    file.write_all(me.text().as_bytes())
                        .and_then(|()| file.flush())
                        .map_err(|e| io(&path, e))?;
                    return Ok(lock);
                }
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {}
                Err(e) => return Err(io(&path, format!("cannot lock the output directory: {e}"))),
            }
            let text = match std::fs::read_to_string(&path) {
                Ok(text) => text,
                // Removed meanwhile: try again.
                Err(e) if e.kind() == std::io::ErrorKind::NotFound => continue,
                Err(e) => return Err(io(&path, e)),
            };
            match Holder::parse(&text) {
                Some(holder) if holder.running() => {
                    return Err(CliError::Locked {
                        dir: dir.to_path_buf(),
                        pid: Some(holder.pid),
                    });
                }
                Some(holder) => {
                    if remove_stale(&path, &text)? && !quiet {
                        eprintln!(
                            "note: {} held the lock of process {}, which is no longer running (a run that \
                             was killed); it is replaced",
                            path.display(),
                            holder.pid
                        );
                    }
                }
                None => {
                    // Just created by another run, which has not yet
                    // written its id; or a file left without one.
                    let age = std::fs::metadata(&path)
                        .and_then(|m| m.modified())
                        .ok()
                        .and_then(|m| SystemTime::now().duration_since(m).ok());
                    if age.is_none_or(|a| a < BEING_WRITTEN) {
                        return Err(CliError::Locked {
                            dir: dir.to_path_buf(),
                            pid: None,
                        });
                    }
                    remove_stale(&path, &text)?;
                }
            }
        }
        Err(CliError::Locked {
            dir: dir.to_path_buf(),
            pid: None,
        })
    }
}

/// Remove the stale lock `path` if it still holds `text` (another run may
/// have replaced it meanwhile: that lock stays). It is first moved aside
/// (atomically), so that a lock created in its place is never removed.
/// Returns whether the stale lock was removed.
fn remove_stale(path: &Path, text: &str) -> Result<bool, CliError> {
    let aside = path.with_extension(format!("lock.stale-{}", std::process::id()));
    match std::fs::rename(path, &aside) {
        Ok(()) => {}
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(false),
        Err(e) => return Err(io(path, format!("cannot replace a stale lock: {e}"))),
    }
    let moved = std::fs::read_to_string(&aside).unwrap_or_default();
    if moved == text {
        std::fs::remove_file(&aside).map_err(|e| io(&aside, e))?;
        return Ok(true);
    }
    // Another run's fresh lock: put it back (unless yet another took its
    // place, which then holds the directory).
    let _ = std::fs::hard_link(&aside, path);
    let _ = std::fs::remove_file(&aside);
    Ok(false)
}

impl Drop for DirLock {
    fn drop(&mut self) {
        // Only a lock this process holds is removed.
        let ours = std::fs::read_to_string(&self.path)
            .ok()
            .and_then(|t| Holder::parse(&t))
            .is_some_and(|h| h.pid == std::process::id());
        if ours {
            let _ = std::fs::remove_file(&self.path);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_scratch::Scratch;

    #[test]
    fn a_lock_is_exclusive_and_removed_when_dropped() {
        let dir = Scratch::new("lock-exclusive");
        let lock = DirLock::acquire(&dir, true).expect("first lock");
        let text = std::fs::read_to_string(dir.join(FILE)).expect("lock file");
        assert!(text.contains(&format!("pid {}", std::process::id())), "{text}");
        let second = DirLock::acquire(&dir, true).expect_err("held");
        assert!(
            matches!(second, CliError::Locked { pid: Some(p), .. } if p == std::process::id()),
            "{second}"
        );
        drop(lock);
        assert!(!dir.join(FILE).exists());
        drop(DirLock::acquire(&dir, true).expect("free again"));
    }

    #[test]
    fn a_lock_of_a_process_that_ended_is_replaced() {
        let dir = Scratch::new("lock-stale");
        if !Path::new("/proc/self").exists() {
            return;
        }
        // A process id no process has: beyond the kernel's largest.
        std::fs::write(dir.join(FILE), "pid 4294967295\nstarted 1\n").expect("stale lock");
        let lock = DirLock::acquire(&dir, true).expect("stale lock replaced");
        let text = std::fs::read_to_string(dir.join(FILE)).expect("lock file");
        assert!(text.contains(&format!("pid {}", std::process::id())), "{text}");
        drop(lock);
        // This process's id with another start time: the id was reused.
        let me = Holder::current();
        let reused = Holder {
            pid: me.pid,
            started: me.started.map(|t| t + 1),
        };
        assert!(me.running());
        assert_eq!(reused.running(), me.started.is_none());
    }

    #[test]
    fn a_lock_being_written_is_held_and_an_old_empty_one_is_not() {
        let dir = Scratch::new("lock-empty");
        std::fs::write(dir.join(FILE), "").expect("empty lock");
        assert!(matches!(
            DirLock::acquire(&dir, true),
            Err(CliError::Locked { pid: None, .. })
        ));
        let file = std::fs::File::options().write(true).open(dir.join(FILE)).expect("open");
        file.set_modified(SystemTime::now() - 2 * BEING_WRITTEN)
            .expect("age it");
        drop(DirLock::acquire(&dir, true).expect("an old empty lock is stale"));
    }

    #[test]
    fn the_holder_round_trips_through_its_text() {
        let h = Holder {
            pid: 42,
            started: Some(7),
        };
        assert_eq!(Holder::parse(&h.text()), Some(h));
        assert_eq!(Holder::parse("nonsense"), None);
        assert_eq!(
            stat_fields("12 (a b) c) S 1 2 3").map(|f| f.first().copied()),
            Some(Some("S"))
        );
    }
}
