//! The `veselov` command: run variational-integrator scenarios from TOML files.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};

use veselov_cli::error::CliError;
use veselov_cli::pipeline::RunJob;
use veselov_cli::route::{run_scenario, verify_scenario};
use veselov_cli::{catalog, keys, redraw, verify};

/// Structure-preserving variational integrators.
#[derive(Parser)]
#[command(name = "veselov", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run a scenario file and write trajectory.csv, summary.json and plots.
    ///
    /// The keys of a scenario file are documented by `veselov keys KIND`
    /// (KIND: mechanics, rigid, lattice, cfk, beam, rod); `veselov new KIND`
    /// prints a commented scenario with every key.
    Run {
        /// The scenario (TOML).
        scenario: PathBuf,
        /// Output directory (overrides `[output] dir`).
        #[arg(long)]
        out: Option<PathBuf>,
        /// No progress bar or final report.
        #[arg(long)]
        quiet: bool,
        /// Overwrite a non-empty output directory (the files an earlier run there recorded in its outputs.json are removed first; other files are kept).
        #[arg(long)]
        force: bool,
        /// Run beyond the preflight limits (1e9 steps, 10 GiB of output).
        #[arg(long)]
        force_large: bool,
        /// Continue the run in DIR from its checkpoint (the outputs are extended in place).
        #[arg(long, value_name = "DIR")]
        resume: Option<PathBuf>,
        /// End the run as interrupted (with a checkpoint) after this many seconds of wall time.
        #[arg(long, value_name = "SECONDS")]
        time_limit: Option<f64>,
        /// Also write a checkpoint whenever this many seconds of wall time have passed since the last.
        #[arg(long, value_name = "SECONDS")]
        checkpoint_seconds: Option<f64>,
    },
    /// List the built-in models with their parameters and defaults.
    Models,
    /// List the methods of every kind with their keys, orders and properties.
    Methods,
    /// The expression language of custom models: names, operators, functions, limits.
    Expressions,
    /// Every scenario key of a kind (or of every kind), as Markdown: type, default, unit, meaning.
    Keys {
        /// mechanics, rigid, lattice, cfk, beam or rod (all kinds if omitted).
        kind: Option<String>,
    },
    /// Print a commented scenario of a kind with every key and its default.
    New {
        /// mechanics, rigid, lattice, cfk, beam or rod.
        kind: String,
    },
    /// Convergence study of the scenario's method.
    ///
    /// Mechanics and rigid bodies: runs at the steps `--dt` against a
    /// reference. Lattice fields, the beam and the rod: runs refining space
    /// and time together (`--refine K` or `--nodes`), each error the
    /// Richardson estimate from the next finer run.
    Verify {
        /// The scenario (TOML).
        scenario: PathBuf,
        /// Mechanics and rigid bodies: comma-separated time steps, e.g. 0.1,0.05,0.025.
        #[arg(long, value_delimiter = ',', allow_negative_numbers = true)]
        dt: Vec<f64>,
        /// Lattice fields, beam, rod: the scenario's nodes and K refinements by a factor 2 (Δx halved, Δt with it at the scenario's Courant or step number).
        #[arg(long, value_name = "K")]
        refine: Option<usize>,
        /// Lattice fields, beam, rod: comma-separated node counts of the runs, e.g. 21,41,81.
        #[arg(long, value_delimiter = ',')]
        nodes: Vec<usize>,
        /// Lattice fields, beam, rod: what the runs compare: field, energy, tip-displacement or frequency (default: field for lattices; frequency for a free–free structure, else tip-displacement).
        #[arg(long)]
        observable: Option<String>,
        /// Output directory (default: the scenario's output directory + /verify).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Overwrite a non-empty output directory (the files an earlier run there recorded in its outputs.json are removed first; other files are kept).
        #[arg(long)]
        force: bool,
        /// Print nothing.
        #[arg(long)]
        quiet: bool,
    },
    /// Redraw the plots of a run (any kind) or a verify study from its output files, and list them.
    Plot {
        /// A run's output directory.
        dir: PathBuf,
        /// svg or png.
        #[arg(long, default_value = "svg")]
        format: String,
    },
}

fn list_models() {
    for m in catalog::MODELS {
        veselov_cli::say!("{}\n    {}", m.name, m.summary);
        if !m.coordinates.is_empty() {
            veselov_cli::say!("    coordinates: {}", m.coordinates.join(", "));
        }
        for p in m.params {
            veselov_cli::say!("    params.{} = {} ({})", p.name, p.default, p.doc);
        }
        veselov_cli::say!("    default initial: {}", m.default_initial);
        if !m.symmetries.is_empty() {
            veselov_cli::say!("    momentum maps: {}", m.symmetries.join(", "));
        }
        veselov_cli::say!("    verify reference: {}", m.reference);
    }
    for m in catalog::STRUCTURES {
        veselov_cli::say!("{}\n    {}", m.name, m.summary);
        veselov_cli::say!("    keys: {}", m.keys);
        veselov_cli::say!("    examples: {}", m.examples);
    }
}

fn list_methods() {
    for m in catalog::METHODS {
        veselov_cli::say!("{}\n    keys: {}\n    {}", m.name, m.keys, m.properties);
    }
    veselov_cli::say!("\nSeparable built-in models (harmonic, pendulum, kepler, henon-heiles) use fixed-point stage");
    veselov_cli::say!("iteration with a Newton fallback; other systems use Newton with the exact Jacobian.");
    for kind in veselov_cli::route::KINDS.iter().filter(|k| k.name() != "mechanics") {
        veselov_cli::say!(
            "\n{} ([method]; all keys: `veselov keys {}`)",
            kind.title(),
            kind.name()
        );
        veselov_cli::say!("{}", keys::method_summary(*kind).trim_end());
    }
    veselov_cli::say!("\nMechanics keys: `veselov keys mechanics`.");
}

/// The kind named `name`, or an error listing the kinds.
fn kind_named(name: &str) -> Result<&'static dyn veselov_cli::kinds::ScenarioKind, CliError> {
    keys::kind_named(name).ok_or_else(|| {
        CliError::Setup(format!(
            "unknown kind `{name}`, expected one of: {}",
            keys::kind_names().join(", ")
        ))
    })
}

fn print_keys(kind: Option<&str>) -> Result<(), CliError> {
    match kind {
        Some(name) => veselov_cli::say!("{}", keys::markdown(kind_named(name)?).trim_end()),
        None => {
            for k in veselov_cli::route::KINDS {
                veselov_cli::say!("{}\n", keys::markdown(*k).trim_end());
            }
        }
    }
    Ok(())
}

fn print_template(kind: &str) -> Result<(), CliError> {
    let text = keys::template(kind_named(kind)?).map_err(|e| CliError::Setup(e.to_string()))?;
    veselov_cli::say!("{}", text.trim_end());
    Ok(())
}

fn plot_dir(dir: &std::path::Path, format: &str) -> Result<(), CliError> {
    let written = redraw::redraw(dir, format)?;
    if written.is_empty() {
        veselov_cli::say!("{}: nothing to draw", dir.display());
    }
    for path in written {
        veselov_cli::say!("wrote {}", path.display());
    }
    Ok(())
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Run {
            scenario,
            out,
            quiet,
            force,
            force_large,
            resume,
            time_limit,
            checkpoint_seconds,
        } => run_scenario(
            &scenario,
            RunJob {
                out,
                quiet,
                force,
                force_large,
                resume,
                time_limit,
                checkpoint_seconds,
                interrupt: None,
                scenario: None,
            },
        ),
        Command::Models => {
            list_models();
            Ok(())
        }
        Command::Methods => {
            list_methods();
            Ok(())
        }
        Command::Keys { kind } => print_keys(kind.as_deref()),
        Command::New { kind } => print_template(&kind),
        Command::Expressions => {
            let text = catalog::expressions_reference();
            veselov_cli::say!("{}", text.strip_suffix('\n').unwrap_or(&text));
            Ok(())
        }
        Command::Verify {
            scenario,
            dt,
            refine,
            nodes,
            observable,
            out,
            force,
            quiet,
        } => verify_scenario(
            &scenario,
            verify::VerifyJob {
                dts: dt,
                refine,
                nodes,
                observable,
                out,
                force,
                quiet,
                interrupt: None,
            },
        ),
        Command::Plot { dir, format } => plot_dir(&dir, &format),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
