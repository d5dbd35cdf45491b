//! The Cosserat rod (`[model] name = "cosserat-rod"`, seed 003 §6): the
//! rod's discrete Lagrangian on the leapfrog CFK lattice (Prop. 6.5, with
//! the split vertex step, or Q_sym), marched by the core's Cauchy
//! integrator of seed 003 §4 on the library's rod ([`veselov::models::rod`]).
//!
//! [`schema`] holds the scenario's tables (with [`motion`], the expressions
//! of a centreline and of driven ends) and [`setup`] validates them into the
//! rod ([`body`]: its parameters), its lattice, ends and loads, from the
//! initial motion ([`initial`]: a [`shape`] moved rigidly, or expressions in
//! s and t); [`run`]
//! marches it with the observer of [`observer`]; [`figures`] draws the
//! centreline, the momenta and the energy.

pub mod body;
pub mod figures;
pub mod initial;
pub mod motion;
pub mod observer;
pub mod run;
pub mod schema;
pub mod setup;
pub mod shape;

use std::path::Path;

use super::ScenarioKind;
use crate::error::CliError;
use crate::pipeline::RunJob;
use crate::verify::VerifyJob;
use crate::verify::refine::{Refinable, text_at};
use schema::ROD_MODEL;

/// The Cosserat-rod kind.
pub struct RodKind;

impl ScenarioKind for RodKind {
    fn name(&self) -> &'static str {
        "rod"
    }

    fn title(&self) -> &'static str {
        "Cosserat rod scenarios"
    }

    fn schema(&self) -> serde_json::Value {
        crate::keys::schema::schema_of::<schema::RodScenario>()
    }

    fn example(&self) -> (&'static str, &'static str) {
        (
            "rod_cantilever_centred.toml",
            include_str!("../../../../../examples/rod_cantilever_centred.toml"),
        )
    }

    fn models(&self) -> &'static [&'static str] {
        &[ROD_MODEL]
    }

    fn check(&self, path: &Path, text: &str) -> Result<(), CliError> {
        setup::RodSetup::parse(path, text).map(drop)
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
        let method = format!(
            "rod, {} shear frame, {} quadrature",
            text_at(&table, "method.shear_frame", "vertex"),
            text_at(&table, "method.quadrature", "vertex")
        );
        Refinable::structure(method, &table).study(path, text, job)
    }
}
