//! The kinds of scenario the command runs, one folder each: its schema, its
//! jobs with their observers, and its figures. Every kind implements
//! [`ScenarioKind`], on which [`crate::route`] dispatches.

pub mod beam;
pub mod cfk;
pub mod lattice;
pub mod mechanics;
pub mod rigid;
pub mod rod;
pub mod structure;

use std::path::Path;

use crate::error::CliError;
use crate::pipeline::RunJob;
use crate::verify::VerifyJob;

/// A kind of scenario: the `[model] name`s it runs, and its `veselov run`
/// and `veselov verify`.
pub trait ScenarioKind: Sync {
    /// The kind's name in `veselov keys KIND` and `veselov new KIND`.
    fn name(&self) -> &'static str;

    /// The kind in a few words, the title of its key reference.
    fn title(&self) -> &'static str;

    /// The JSON schema of the kind's scenario file, derived from the structs
    /// its parser reads (see [`crate::keys`]).
    fn schema(&self) -> serde_json::Value;

    /// The shipped example `veselov new KIND` starts from: its file name in
    /// `examples/` and its text.
    fn example(&self) -> (&'static str, &'static str);

    /// The `[model] name`s of the kind.
    fn models(&self) -> &'static [&'static str];

    /// Whether the scenario `table`, whose `[model] name` is `model`, is of
    /// this kind: by default, whether `model` is one of
    /// [`models`](Self::models).
    fn takes(&self, model: &str, table: &toml::Table) -> bool {
        let _ = table;
        self.models().contains(&model)
    }

    /// `veselov run`: parse and validate the scenario `text` (attributed to
    /// `path`, for messages and the default output directory), build the
    /// kind's job and run it into the job's directory.
    fn run(&self, path: &Path, text: &str, job: RunJob) -> Result<(), CliError>;

    /// Parse and validate the scenario `text` without running it (the checks
    /// `run` makes before its first step that do not need the model built).
    fn check(&self, path: &Path, text: &str) -> Result<(), CliError>;

    /// `veselov verify`: the convergence study of the scenario `text`, or
    /// the reason the kind takes none.
    fn verify(&self, path: &Path, text: &str, job: VerifyJob) -> Result<(), CliError>;
}
