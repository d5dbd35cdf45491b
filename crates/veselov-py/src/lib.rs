//! The native part of the `veselov` Python package (`veselov._native`).
//!
//! It adds no front end of its own: a scenario (TOML text, possibly written
//! from a Python dict and overridden key by key) is run by the command's
//! library ([`veselov_cli::route::run_text`]) into an output directory,
//! with the same validation, messages, driver, writers and `summary.json`
//! as `veselov run`. The Python layer reads those files back into NumPy
//! arrays. While integrating the GIL is released; the calling thread
//! polls Python's signal handlers and turns Ctrl-C into the run's
//! interruption flag ([`veselov_cli::pipeline::RunJob::interrupt`],
//! [`veselov_cli::verify::VerifyJob::interrupt`]). Messages are worded
//! for Python: the command line's options become the package's arguments.

mod scenario;

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Condvar, Mutex, PoisonError};
use std::time::Duration;

use pyo3::exceptions::{PyKeyboardInterrupt, PyValueError};
use pyo3::prelude::*;
use rayon::prelude::*;
use veselov_cli::error::CliError;
use veselov_cli::pipeline::RunJob;
use veselov_cli::route::{run_text, verify_text};
use veselov_cli::verify::VerifyJob;
use veselov_cli::{catalog, scenario::key_at};

/// How one run ended: `(outcome, message, key)` where outcome is `ok`,
/// `error` (the integration failed; partial outputs written),
/// `interrupted`, `scenario` (bad scenario; `key` names the key when
/// known) or `failure` (anything else: output directory, I/O).
type Ended = (String, String, Option<String>);

fn ended(text: &str, result: Result<(), CliError>) -> Ended {
    let (outcome, key) = match &result {
        Ok(()) => ("ok", None),
        Err(CliError::Run { .. }) => ("error", None),
        Err(CliError::Interrupted { .. }) => ("interrupted", None),
        Err(CliError::Key { key, .. }) => ("scenario", Some(python_key(key).to_string())),
        Err(CliError::Parse { .. }) => ("scenario", None),
        Err(_) => ("failure", None),
    };
    let key = match (&result, key) {
        (Err(CliError::Parse { message, .. }), None) => key_at(text, message),
        (_, key) => key,
    };
    let message = result.err().map(|e| python_message(&e)).unwrap_or_default();
    (outcome.to_string(), message, key)
}

/// The name a caller from Python gives what the command line calls `key`:
/// an option of `veselov verify` (`--dt`, `--refine`, `--nodes`,
/// `--observable`) is the argument of that name.
fn python_key(key: &str) -> &str {
    key.strip_prefix("--").unwrap_or(key)
}

/// The message of `error` for a caller from Python: the command line's
/// options become the package's arguments (`out=`, `force=True`,
/// `force_large=True`, `dt`, `veselov.resume`). A failed or interrupted run
/// names no directory: the package says where its files are, if they are
/// kept.
fn python_message(error: &CliError) -> String {
    match error {
        CliError::OutputNotEmpty { dir } => format!(
            "output directory {} is not empty; choose another with out= or pass force=True to overwrite \
             (the outputs of an earlier run there are removed first, other files kept)",
            dir.display()
        ),
        CliError::Run { error, .. } => format!("run failed: {error}"),
        CliError::Interrupted { .. } => "run interrupted; outputs valid up to the last row".to_string(),
        CliError::Key { file, key, message } => {
            format!("{}: `{}`: {}", file.display(), python_key(key), python_options(message))
        }
        other => python_options(&other.to_string()),
    }
}

/// `text` with the command line's options that a message may suggest
/// replaced by the package's arguments.
fn python_options(text: &str) -> String {
    text.replace("pass --force-large", "pass force_large=True")
        .replace("(--resume needs", "(veselov.resume needs")
        .replace("`--refine K`", "`refine=K`")
        .replace("`--nodes N1,N2,…`", "`nodes=[N1, N2, …]`")
        .replace("`--dt 0.1,0.05,0.025`", "`dt=[0.1, 0.05, 0.025]`")
        .replace("`--dt`", "`dt`")
        .replace("`--refine`", "`refine`")
        .replace("`--nodes`", "`nodes`")
        .replace("`--observable`", "`observable`")
}

/// Run `work` on a scoped thread with the GIL released; meanwhile poll
/// Python's signal handlers every 50 ms (a `KeyboardInterrupt` sets
/// `interrupt`, other exceptions from handlers set it too and are raised
/// once the work has ended) and report `done` to `progress(done, total)`.
/// A `KeyboardInterrupt` is raised once the work has ended when
/// `raise_interrupt`, else only turned into `interrupt`.
fn attended<T: Send>(
    py: Python<'_>,
    raise_interrupt: bool,
    interrupt: &AtomicBool,
    done: &AtomicUsize,
    total: usize,
    progress: Option<&Bound<'_, PyAny>>,
    work: impl FnOnce() -> T + Send,
) -> PyResult<T> {
    let slot: (Mutex<Option<T>>, Condvar) = (Mutex::new(None), Condvar::new());
    let wait = || {
        let (lock, ready) = &slot;
        let guard = lock.lock().unwrap_or_else(PoisonError::into_inner);
        let (mut guard, _) = ready
            .wait_timeout_while(guard, Duration::from_millis(50), |v| v.is_none())
            .unwrap_or_else(PoisonError::into_inner);
        guard.take()
    };
    std::thread::scope(|s| {
        let handle = s.spawn(|| {
            let value = work();
            *slot.0.lock().unwrap_or_else(PoisonError::into_inner) = Some(value);
            slot.1.notify_all();
        });
        let mut pending: Option<PyErr> = None;
        let mut reported = usize::MAX;
        loop {
            match py.detach(wait) {
                Some(value) => {
                    if let Some(p) = progress {
                        p.call1((done.load(Ordering::Relaxed), total))?;
                    }
                    return match pending {
                        Some(e) if raise_interrupt || !e.is_instance_of::<PyKeyboardInterrupt>(py) => Err(e),
                        _ => Ok(value),
                    };
                }
                None if handle.is_finished() && slot.0.lock().map_or(true, |v| v.is_none()) => {
                    return Err(PyValueError::new_err("the run's thread ended without a result"));
                }
                None => {}
            }
            if let Err(e) = py.check_signals() {
                interrupt.store(true, Ordering::Relaxed);
                pending.get_or_insert(e);
            }
            let now = done.load(Ordering::Relaxed);
            if let Some(p) = progress
                && now != reported
            {
                reported = now;
                if let Err(e) = p.call1((now, total)) {
                    interrupt.store(true, Ordering::Relaxed);
                    pending.get_or_insert(e);
                }
            }
        }
    })
}

/// How `run_many` runs each member: into its directory, or resuming the
/// run in it; with `force` and `force_large` as the command line's options.
#[derive(Clone, Copy)]
struct Options {
    force: bool,
    force_large: bool,
    resume: bool,
}

fn job(out: &str, options: Options, interrupt: &Arc<AtomicBool>) -> RunJob {
    let out = PathBuf::from(out);
    RunJob {
        resume: options.resume.then(|| out.clone()),
        out: Some(out),
        quiet: true,
        force: options.force,
        force_large: options.force_large,
        interrupt: Some(interrupt.clone()),
        ..RunJob::default()
    }
}

/// Run scenarios into output directories, in parallel, as `veselov run` does.
///
/// Member ``i`` runs the scenario ``texts[i]`` into the directory ``outs[i]``
/// (or, with ``resume``, continues the run in it from its checkpoint)
/// through the command's library, with the GIL released. The calling thread
/// polls Python's signal handlers meanwhile: Ctrl-C interrupts every member
/// still running. The package's ``veselov.run``, ``veselov.ensemble`` and
/// ``veselov.resume`` call this and read the directories back.
///
/// Parameters
/// ----------
/// label : str
///     The name the scenarios' messages are attributed to (their file's
///     path, or ``"<string>"``).
/// texts : list of str
///     The scenarios, as TOML text.
/// outs : list of str
///     The output directory of each scenario, ``len(texts)`` of them.
/// force : bool, optional
///     Run in non-empty directories, first removing an earlier run's
///     outputs (``--force``). Default ``False``.
/// workers : int, optional
///     The number of threads, at least 1; default: all cores.
/// progress : callable, optional
///     Called as ``progress(done, total)`` (two ``int``) on the calling
///     thread as members end, and once at the end.
/// resume : bool, optional
///     Continue the run in each directory from its ``checkpoint.json``
///     (``--resume``), with its scenario. Default ``False``.
/// force_large : bool, optional
///     Run beyond the preflight limits (``--force-large``). Default
///     ``False``.
///
/// Returns
/// -------
/// list of tuple of (str, str, str or None)
///     ``(outcome, message, key)`` per member, in input order. ``outcome``
///     is ``"ok"``; ``"error"`` (the integration failed; partial outputs
///     written); ``"interrupted"``; ``"scenario"`` (an invalid scenario,
///     with ``key`` the dotted key at fault when known); or ``"failure"``
///     (output directory, I/O). ``message`` is the error text (``""`` for
///     ``"ok"``), worded for Python (``out=``, ``force=True``); that of an
///     ``"error"`` or ``"interrupted"`` run names no directory.
///
/// Raises
/// ------
/// ValueError
///     If ``texts`` and ``outs`` differ in length, or ``workers`` is 0.
/// Exception
///     Whatever ``progress`` or a Python signal handler other than
///     Ctrl-C's raised (the members still running are interrupted first).
#[pyfunction]
#[pyo3(signature = (label, texts, outs, force=false, workers=None, progress=None, resume=false, force_large=false))]
#[allow(clippy::too_many_arguments)]
fn run_many(
    py: Python<'_>,
    label: &str,
    texts: Vec<String>,
    outs: Vec<String>,
    force: bool,
    workers: Option<usize>,
    progress: Option<Bound<'_, PyAny>>,
    resume: bool,
    force_large: bool,
) -> PyResult<Vec<Ended>> {
    if texts.len() != outs.len() {
        return Err(PyValueError::new_err("texts and outs differ in length"));
    }
    if workers == Some(0) {
        return Err(PyValueError::new_err("workers: expected at least 1"));
    }
    let path = Path::new(label);
    let options = Options {
        force,
        force_large,
        resume,
    };
    let interrupt = Arc::new(AtomicBool::new(false));
    let done = AtomicUsize::new(0);
    let one = |(text, out): (&String, &String)| {
        let r = ended(text, run_text(path, text, job(out, options, &interrupt)));
        done.fetch_add(1, Ordering::Relaxed);
        r
    };
    let pool = match workers {
        Some(n) if texts.len() > 1 => Some(
            rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .map_err(|e| PyValueError::new_err(e.to_string()))?,
        ),
        _ => None,
    };
    attended(py, false, &interrupt, &done, texts.len(), progress.as_ref(), || {
        let members = || -> Vec<Ended> {
            if texts.len() == 1 {
                texts.iter().zip(&outs).map(one).collect()
            } else {
                texts.par_iter().zip(&outs).map(one).collect()
            }
        };
        match &pool {
            Some(pool) => pool.install(members),
            None => members(),
        }
    })
}

/// Convergence study of a scenario's method into a directory, as `veselov verify` does.
///
/// Writes ``convergence.csv`` (columns ``dt, steps, error``, one row per
/// step), ``convergence.svg`` and ``summary.json`` into ``out``; the
/// package's ``veselov.verify`` reads them back. The GIL is released while
/// the study runs. Ctrl-C stops it before its next run (the run in
/// progress is finished first), writing no outputs, and the
/// ``KeyboardInterrupt`` is raised.
///
/// Parameters
/// ----------
/// label : str
///     The name the scenario's messages are attributed to.
/// text : str
///     The scenario, as TOML text.
/// dts : list of float
///     The steps of the study (``--dt``; empty for a refinement).
/// out : str
///     The output directory.
/// force : bool, optional
///     Write into a non-empty ``out``. Default ``False``.
/// refine : int, optional
///     Refinements by a factor 2 (``--refine``).
/// nodes : list of int, optional
///     The node counts of the runs (``--nodes``).
/// observable : str, optional
///     What a refinement compares (``--observable``).
///
/// Returns
/// -------
/// tuple of (str, str, str or None)
///     ``(outcome, message, key)`` as ``run_many`` gives them for one
///     member: ``"ok"``, ``"error"``, ``"scenario"`` (with ``key``, which
///     is ``"dt"``, ``"refine"``, ``"nodes"`` or ``"observable"`` for a bad
///     option) or ``"failure"`` (output directory, I/O).
///
/// Raises
/// ------
/// KeyboardInterrupt
///     On Ctrl-C, once the study has stopped.
/// Exception
///     Whatever another Python signal handler raised (the study is
///     stopped first, in the same way).
#[pyfunction]
#[pyo3(signature = (label, text, dts, out, force=false, refine=None, nodes=Vec::new(), observable=None))]
#[allow(clippy::too_many_arguments)]
fn verify(
    py: Python<'_>,
    label: &str,
    text: &str,
    dts: Vec<f64>,
    out: &str,
    force: bool,
    refine: Option<usize>,
    nodes: Vec<usize>,
    observable: Option<String>,
) -> PyResult<Ended> {
    let interrupt = Arc::new(AtomicBool::new(false));
    let done = AtomicUsize::new(0);
    let job = VerifyJob {
        dts,
        refine,
        nodes,
        observable,
        out: Some(PathBuf::from(out)),
        force,
        quiet: true,
        interrupt: Some(interrupt.clone()),
    };
    attended(py, true, &interrupt, &done, 1, None, || {
        ended(text, verify_text(Path::new(label), text, job))
    })
}

/// A scenario with the keys of a TOML document of overrides replaced.
///
/// A table in ``overrides`` replaces a table key by key (so
/// ``initial = { q = [1.0] }`` keeps ``initial.p``); any other value
/// replaces the key. Numbers are read and written exactly.
///
/// Parameters
/// ----------
/// text : str
///     The scenario, as TOML text.
/// overrides : str
///     The keys to replace, as a TOML document (``veselov.toml_text`` writes
///     one from a dict).
///
/// Returns
/// -------
/// tuple of (str, str, None)
///     ``("ok", merged TOML text, None)``, or ``("scenario", message, None)``
///     when either document is not valid TOML.
#[pyfunction]
fn merge(text: &str, overrides: &str) -> PyResult<Ended> {
    Ok(match scenario::merge(text, overrides) {
        Ok(t) => ("ok".into(), t, None),
        Err(message) => ("scenario".into(), message, None),
    })
}

/// The built-in models: `(name, summary, coordinates, params, default_initial,
/// symmetries, reference)`, params as `(name, default, doc)`.
type ModelRow = (
    &'static str,
    &'static str,
    Vec<&'static str>,
    Vec<(&'static str, f64, &'static str)>,
    &'static str,
    Vec<&'static str>,
    &'static str,
);

/// The command's catalogue of built-in models, as `veselov models` lists them first.
///
/// Returns
/// -------
/// list of tuple
///     One ``(name, summary, coordinates, params, default_initial,
///     symmetries, reference)`` per model: ``name``, ``summary``,
///     ``default_initial`` and ``reference`` are ``str``; ``coordinates``
///     and ``symmetries`` are ``list of str``; ``params`` is a ``list`` of
///     ``(name, default, doc)`` tuples of ``(str, float, str)``. The
///     package's ``veselov.models`` turns them into dicts.
#[pyfunction]
fn models() -> Vec<ModelRow> {
    catalog::MODELS
        .iter()
        .map(|m| {
            (
                m.name,
                m.summary,
                m.coordinates.to_vec(),
                m.params.iter().map(|p| (p.name, p.default, p.doc)).collect(),
                m.default_initial,
                m.symmetries.to_vec(),
                m.reference,
            )
        })
        .collect()
}

/// The structural models (the beam, the rod), as `veselov models` lists them last.
///
/// Returns
/// -------
/// list of tuple of (str, str, str, str)
///     One ``(name, summary, keys, examples)`` per model: the scenario keys
///     it takes as one line of text, and a glob of its example scenarios.
#[pyfunction]
fn structures() -> Vec<(&'static str, &'static str, &'static str, &'static str)> {
    catalog::STRUCTURES
        .iter()
        .map(|m| (m.name, m.summary, m.keys, m.examples))
        .collect()
}

/// The command's catalogue of methods, as `veselov methods` lists them.
///
/// Returns
/// -------
/// list of tuple of (str, str, str)
///     One ``(name, keys, properties)`` per method: its ``method.name``,
///     the ``[method]`` keys it takes, and its order and conservation
///     properties, as text.
#[pyfunction]
fn methods() -> Vec<(&'static str, &'static str, &'static str)> {
    catalog::METHODS
        .iter()
        .map(|m| (m.name, m.keys, m.properties))
        .collect()
}

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(run_many, m)?)?;
    m.add_function(wrap_pyfunction!(verify, m)?)?;
    m.add_function(wrap_pyfunction!(merge, m)?)?;
    m.add_function(wrap_pyfunction!(models, m)?)?;
    m.add_function(wrap_pyfunction!(structures, m)?)?;
    m.add_function(wrap_pyfunction!(methods, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
