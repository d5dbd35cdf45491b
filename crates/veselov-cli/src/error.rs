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
    /// The integration failed; partial outputs were written.
    #[error("run failed: {error} (partial results written to {})", dir.display())]
    Run {
        /// What stopped the run.
        error: veselov::Error,
        /// Where the partial results are.
        dir: PathBuf,
    },
    /// The run was interrupted (signal or time limit); outputs are valid up to their last row.
    #[error("run interrupted; outputs valid up to the last row and a checkpoint written in {} (continue with --resume)", dir.display())]
    Interrupted {
        /// The output directory.
        dir: PathBuf,
    },
    /// A library error outside a run (setting up the system or method).
    #[error("{0}")]
    Setup(String),
}
