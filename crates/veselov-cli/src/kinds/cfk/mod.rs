//! Fields in 2+1 dimensions on the CFK simplicial lattice (`[lattice] kind =
//! "cfk"`): the density 𝓛 = ½(φ_t² − |∇φ|²) + N(φ) discretized by the
//! midpoint rule on the simplices of x_a = Δx(v_a − w/3), t = wΔt/3
//! (w = v₀ + v₁ + v₂), periodic in both space directions, and marched vertex
//! by vertex by the core's Cauchy integrator.
//!
//! ```toml
//! [model]
//! name = "sine-gordon"          # sine-gordon | wave | klein-gordon-phi4 | klein-gordon-complex
//! [lattice]
//! kind = "cfk"
//! space_dimension = 2
//! nodes = [48, 48]              # nodes per space axis (periodic)
//! spacing = 0.25                # Δx
//! courant = 0.4                 # Δt/Δx (or dt = …)
//! [initial]
//! kind = "pulse"                # pulse | standing-wave | plane-wave (complex field)
//! amplitude = 4.0
//! [time]
//! t_end = 10.0
//! [output]
//! snapshot_every = 5            # time steps Δt between snapshots
//! checkpoint_every = 100        # time steps Δt between checkpoints (0: at the end only)
//! ```
//!
//! Outputs: `energy.csv` (t, energy: the cell energies of one slab of
//! duration Δt divided by Δt), `momentum.csv` (t, p_x, p_y — the field's
//! momentum −∫φ_t∇φ, not exactly conserved, since lattice translations are
//! discrete symmetries — then the level momenta of the vertical symmetries,
//! conserved to round-off: `shift_momentum` of the wave equation,
//! `phase_charge` of the complex field), `snapshots.npy` (snapshots × nx × ny
//! [× 2]), `snapshot_times.csv`, `summary.json`, `energy_error.svg` and heat
//! maps `field_<k>.png` of a few snapshots spread over the run.

//!
//! The march is the core's Cauchy integrator of seed 003 §4
//! ([`veselov::field::cauchy`]). [`schema`] reads and validates the file;
//! [`run`] builds the initial levels and marches them with the observer of
//! [`observer`]; [`figures`] draws the energy error and the heat maps.

pub mod figures;
pub mod observer;
pub mod run;
pub mod schema;

use std::path::Path;

use super::ScenarioKind;
use super::lattice::schema::FIELD_MODELS;
use crate::error::CliError;
use crate::pipeline::RunJob;
use crate::verify::VerifyJob;
use crate::verify::observe::Observable;
use crate::verify::refine::{Refinable, nodes_at};

/// Whether a field scenario (its TOML `table`) asks for a CFK lattice.
pub fn is_cfk(table: &toml::Table) -> bool {
    table
        .get("lattice")
        .and_then(|l| l.get("kind"))
        .and_then(|k| k.as_str())
        .is_some_and(|k| k == "cfk")
}

/// The CFK-lattice field kind: the field models, on a `[lattice]` of
/// `kind = "cfk"`.
pub struct CfkKind;

impl ScenarioKind for CfkKind {
    fn name(&self) -> &'static str {
        "cfk"
    }

    fn title(&self) -> &'static str {
        "Field scenarios on a CFK lattice (2+1 dimensions)"
    }

    fn schema(&self) -> serde_json::Value {
        crate::keys::schema::schema_of::<schema::CfkScenario>()
    }

    fn example(&self) -> (&'static str, &'static str) {
        (
            "sine_gordon_2d.toml",
            include_str!("../../../../../examples/sine_gordon_2d.toml"),
        )
    }

    fn models(&self) -> &'static [&'static str] {
        FIELD_MODELS
    }

    fn takes(&self, model: &str, table: &toml::Table) -> bool {
        self.models().contains(&model) && is_cfk(table)
    }

    fn check(&self, path: &Path, text: &str) -> Result<(), CliError> {
        schema::Setup::parse(path, text).map(drop)
    }

    fn run(&self, path: &Path, text: &str, job: RunJob) -> Result<(), CliError> {
        run::run(path, text, job)
    }

    /// A refinement study of both space axes and time at the scenario's
    /// Courant number (or its `dt` divided with the spacing), the final
    /// field by default.
    fn verify(&self, path: &Path, text: &str, job: VerifyJob) -> Result<(), CliError> {
        self.check(path, text)?;
        let table: toml::Table = crate::scenario::parse_toml(path, text)?;
        Refinable {
            method: "CFK midpoint rule".into(),
            order: 2,
            nodes_key: "lattice.nodes",
            nodes: nodes_at(&table, "lattice.nodes"),
            closed: false,
            scaled: &["lattice.dt", "lattice.spacing"],
            whole_steps: true,
            outputs: vec![("output.plots", false.into()), ("output.snapshot_every", 0.into())],
            observables: vec![Observable::Field, Observable::Energy],
        }
        .study(path, text, job)
    }
}
