//! The geometrically exact beam on SE(3) (`[model] name = "beam"`, seed
//! 000): seed 000's multisymplectic Lie-group integrator on the library's
//! beam ([`veselov::models::beam`]), marching in time, or in space on the
//! paper's time grid and prescribed columns (seed 000 §5).
//!
//! [`schema`] holds the scenario's tables and [`setup`] validates them into
//! the beam; [`run`] marches it with the observer of [`observer`];
//! [`figures`] draws the centreline, the momentum map and the energy.

pub mod band;
pub mod figures;
pub mod observer;
pub mod run;
pub mod schema;
pub mod setup;
pub mod start;

use std::path::Path;

use super::ScenarioKind;
use crate::error::CliError;
use crate::pipeline::RunJob;
use crate::verify::VerifyJob;
use crate::verify::refine::{Refinable, text_at};
use schema::BEAM_MODEL;

/// The beam kind.
pub struct BeamKind;

impl ScenarioKind for BeamKind {
    fn name(&self) -> &'static str {
        "beam"
    }

    fn title(&self) -> &'static str {
        "Geometrically exact beam scenarios"
    }

    fn schema(&self) -> serde_json::Value {
        crate::keys::schema::schema_of::<schema::BeamScenario>()
    }

    fn example(&self) -> (&'static str, &'static str) {
        (
            "beam_cantilever.toml",
            include_str!("../../../../../examples/beam_cantilever.toml"),
        )
    }

    fn models(&self) -> &'static [&'static str] {
        &[BEAM_MODEL]
    }

    fn check(&self, path: &Path, text: &str) -> Result<(), CliError> {
        setup::BeamSetup::parse(path, text).map(drop)
    }

    fn run(&self, path: &Path, text: &str, job: RunJob) -> Result<(), CliError> {
        run::run(path, text, job)
    }

    /// A refinement study of the nodes and the time step at the
    /// scenario's step rule (its `time.dt` divided with the space step):
    /// the tip displacement, or the first frequency of a free–free
    /// vibration, by default.
    fn verify(&self, path: &Path, text: &str, job: VerifyJob) -> Result<(), CliError> {
        self.check(path, text)?;
        let table: toml::Table = crate::scenario::parse_toml(path, text)?;
        if text_at(&table, "method.evolution", "time") != "time" {
            return Err(crate::scenario::key_error(
                path,
                "method.evolution",
                "`veselov verify` refines time evolution; space evolution runs on the fixed time grid of its \
                 prescribed columns",
            ));
        }
        let method = format!("beam, {} retraction", text_at(&table, "method.retraction", "cayley"));
        Refinable::structure(method, &table).study(path, text, job)
    }
}
