//! Errors of the command-line tool: every message names the file and key at fault.

use std::path::PathBuf;

use thiserror::Error;

/// What can go wrong in the `veselov` command.
#[derive(Debug, Error)]
pub enum CliError {
    /// The scenario file is not valid TOML or does not match the schema.
    #[error("{}: {message}", file.display())]
    Parse {
        /// Scenario file.
        file: PathBuf,
        /// The parser's message, with line and column.
        message: String,
    },
    /// A key has a bad value.
    #[error("{}: `{key}`: {message}", file.display())]
    Key {
        /// Scenario file.
        file: PathBuf,
        /// Dotted key path.
        key: String,
        /// What was expected.
        message: String,
    },
    /// Reading or writing a file failed.
    #[error("{}: {message}", path.display())]
    Io {
        /// The file or directory.
        path: PathBuf,
        /// The system's message.
        message: String,
    },
    /// The output directory already holds files.
    #[error("output directory {} is not empty; choose another with --out or pass --force to overwrite", dir.display())]
    OutputNotEmpty {
        /// The directory.
        dir: PathBuf,
    },
    /// Another run holds the output directory's lock
    /// ([`lock`](crate::pipeline::lock)).
    #[error(
        "output directory {} is in use by another run ({}); wait for it to end or choose another directory \
         with --out (if no run is using it, remove {})",
        dir.display(),
        match pid {
            Some(pid) => format!("process {pid}"),
            None => "its lock is being created".to_string(),
        },
        dir.join(crate::pipeline::lock::FILE).display()
    )]
    Locked {
        /// The directory.
        dir: PathBuf,
        /// The process holding it, where its lock names one.
        pid: Option<u32>,
    },
    /// The integration failed; partial outputs were written.
    #[error("run failed: {error} (partial results written to {})", dir.display())]
    Run {
        /// What stopped the run.
        error: veselov::Error,
        /// Where the partial results are.
        dir: PathBuf,
    },
    /// The run was interrupted (signal or time limit); outputs are valid up
    /// to their last row. Its plots are not drawn, so that the command
    /// exits at once.
    #[error(
        "run interrupted; outputs valid up to the last row and a checkpoint written in {} (continue with \
         --resume){}",
        dir.display(),
        if *plots_skipped {
            format!("; plots not drawn: draw them with `veselov plot {}`", dir.display())
        } else {
            String::new()
        }
    )]
    Interrupted {
        /// The output directory.
        dir: PathBuf,
        /// Whether the run was to draw plots (and skipped them).
        plots_skipped: bool,
    },
    /// `--resume` of a run that has already completed: nothing is done and
    /// its outputs are left as they are. Not a failure: `veselov run`
    /// reports it as a note and exits with success.
    #[error(
        "the run in {} is already complete (its checkpoint stands at step {step} and its summary.json \
         says \"ok\"): nothing to resume, its outputs are left as they are; to continue it, raise \
         time.t_end (or time.steps) and resume again",
        dir.display()
    )]
    AlreadyComplete {
        /// The run's output directory.
        dir: PathBuf,
        /// The step its checkpoint stands at.
        step: u64,
    },
    /// A library error outside a run (setting up the system or method).
    #[error("{0}")]
    Setup(String),
}
