//! Lattice field scenarios: sine-Gordon, the linear wave equation and φ⁴
//! Klein–Gordon on a 1+1 spacetime lattice, with the schemes of seed 002 §5.
//!
//! ```toml
//! [model]
//! name = "sine-gordon"     # sine-gordon | wave | klein-gordon-phi4
//! params = { m2 = 1.0, lambda = 1.0 }   # klein-gordon-phi4: N = −½m²φ² − ¼λφ⁴
//! [lattice]
//! nodes = 255
//! length = 40.0
//! boundary = "periodic"    # periodic | winding (jump = 2π by default)
//! courant = 0.125          # or: dt = 0.0196…
//! [method]
//! scheme = "triangle"      # triangle | triangle-explicit | rectangle | symmetric-rectangle | vu-quoc-li | guo
//! [initial]
//! kind = "kink-antikink"   # kink-antikink | kink | breather | dalembert
//! [time]
//! t_end = 200.0
//! [output]
//! dir = "out/sg"
//! snapshot_every = 100
//! ```
//!
//! [`schema`] reads and validates the file; [`run`] builds the lattice, the
//! cell rule and the initial levels and marches them, on the fast path (the
//! scheme's own solver, periodic lattices) or the generic one (a cell
//! Lagrangian), with the observer of [`observer`]; [`figures`] draws the
//! energy error, the final waveform and the space–time heat map.

pub mod figures;
pub mod observer;
pub mod run;
pub mod schema;

use std::path::Path;

use super::ScenarioKind;
use crate::error::CliError;
use crate::pipeline::RunJob;
use crate::verify::VerifyJob;
use crate::verify::observe::Observable;
use crate::verify::refine::{Refinable, nodes_at, text_at};
use schema::FIELD_MODELS;

/// The 1+1 lattice-field kind.
pub struct LatticeKind;

impl ScenarioKind for LatticeKind {
    fn name(&self) -> &'static str {
        "lattice"
    }

    fn title(&self) -> &'static str {
        "Field scenarios on a 1+1 space–time lattice"
    }

    fn schema(&self) -> serde_json::Value {
        crate::keys::schema::schema_of::<schema::FieldScenario>()
    }

    fn example(&self) -> (&'static str, &'static str) {
        (
            "sine_gordon.toml",
            include_str!("../../../../../examples/sine_gordon.toml"),
        )
    }

    fn models(&self) -> &'static [&'static str] {
        FIELD_MODELS
    }

    fn check(&self, path: &Path, text: &str) -> Result<(), CliError> {
        schema::LoadedField::parse(path, text).map(drop)
    }

    fn run(&self, path: &Path, text: &str, job: RunJob) -> Result<(), CliError> {
        run::run(path, text, job)
    }

    /// A refinement study at the scenario's Courant number (or its `dt`
    /// divided with the space step), the final field by default.
    fn verify(&self, path: &Path, text: &str, job: VerifyJob) -> Result<(), CliError> {
        self.check(path, text)?;
        let table: toml::Table = crate::scenario::parse_toml(path, text)?;
        let boundary = text_at(&table, "lattice.boundary", "periodic");
        Refinable {
            method: format!("{} scheme", text_at(&table, "method.scheme", "triangle")),
            order: 2,
            nodes_key: "lattice.nodes",
            nodes: nodes_at(&table, "lattice.nodes"),
            closed: matches!(boundary, "dirichlet" | "free"),
            scaled: &["lattice.dt"],
            whole_steps: true,
            outputs: vec![("output.plots", false.into()), ("output.snapshot_every", 0.into())],
            observables: vec![Observable::Field, Observable::Energy],
        }
        .study(path, text, job)
    }
}
