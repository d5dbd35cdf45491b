//! The native part of the `veselov` Python package (`veselov._native`).
//!
//! It adds no front end of its own: a scenario (TOML text, possibly written
//! from a Python dict and overridden key by key) is run by the command's
//! library ([`veselov_cli::route::run_text`]) into an output directory,
//! with the same validation, messages, driver, writers and `summary.json`
//! as `veselov run`. The Python layer reads those files back into NumPy
//! arrays. While integrating the GIL is released; the calling thread
//! polls Python's signal handlers and turns Ctrl-C into the run's
//! interruption flag ([`veselov_cli::pipeline::RunJob::interrupt`]).

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
        Err(CliError::Key { key, .. }) => ("scenario", Some(key.clone())),
        Err(CliError::Parse { .. }) => ("scenario", None),
        Err(_) => ("failure", None),
    };
    let key = match (&result, key) {
        (Err(CliError::Parse { message, .. }), None) => key_at(text, message),
        (_, key) => key,
    };
    let message = result.err().map(|e| e.to_string()).unwrap_or_default();
    (outcome.to_string(), message, key)
}

/// Run `work` on a scoped thread with the GIL released; meanwhile poll
/// Python's signal handlers every 50 ms (a `KeyboardInterrupt` sets
/// `interrupt`, other exceptions from handlers set it too and are raised
/// once the work has ended) and report `done` to `progress(done, total)`.
fn attended<T: Send>(
    py: Python<'_>,
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
                        Some(e) if !e.is_instance_of::<PyKeyboardInterrupt>(py) => Err(e),
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

fn job(out: &str, force: bool, interrupt: &Arc<AtomicBool>) -> RunJob {
    RunJob {
        out: Some(PathBuf::from(out)),
        quiet: true,
        force,
        interrupt: Some(interrupt.clone()),
        ..RunJob::default()
    }
}

/// Run scenarios into output directories, in parallel, as `veselov run` does.
///
/// Member ``i`` runs the scenario ``texts[i]`` into the directory ``outs[i]``
/// through the command's library, with the GIL released. The calling thread
/// polls Python's signal handlers meanwhile: Ctrl-C interrupts every member
/// still running. The package's ``veselov.run`` and ``veselov.ensemble`` call
/// this and read the directories back.
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
///
/// Returns
/// -------
/// list of tuple of (str, str, str or None)
///     ``(outcome, message, key)`` per member, in input order. ``outcome``
///     is ``"ok"``; ``"error"`` (the integration failed; partial outputs
///     written); ``"interrupted"``; ``"scenario"`` (an invalid scenario,
///     with ``key`` the dotted key at fault when known); or ``"failure"``
///     (output directory, I/O). ``message`` is the error text (``""`` for
///     ``"ok"``).
///
/// Raises
/// ------
/// ValueError
///     If ``texts`` and ``outs`` differ in length, or ``workers`` is 0.
/// Exception
///     Whatever ``progress`` or a Python signal handler other than
///     Ctrl-C's raised (the members still running are interrupted first).
#[pyfunction]
#[pyo3(signature = (label, texts, outs, force=false, workers=None, progress=None))]
fn run_many(
    py: Python<'_>,
    label: &str,
    texts: Vec<String>,
    outs: Vec<String>,
    force: bool,
    workers: Option<usize>,
    progress: Option<Bound<'_, PyAny>>,
) -> PyResult<Vec<Ended>> {
    if texts.len() != outs.len() {
        return Err(PyValueError::new_err("texts and outs differ in length"));
    }
    if workers == Some(0) {
        return Err(PyValueError::new_err("workers: expected at least 1"));
    }
    let path = Path::new(label);
    let interrupt = Arc::new(AtomicBool::new(false));
    let done = AtomicUsize::new(0);
    let one = |(text, out): (&String, &String)| {
        let r = ended(text, run_text(path, text, job(out, force, &interrupt)));
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
    attended(py, &interrupt, &done, texts.len(), progress.as_ref(), || {
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
/// the study runs. Ctrl-C does not stop it.
///
/// Parameters
/// ----------
/// label : str
///     The name the scenario's messages are attributed to.
/// text : str
///     The scenario, as TOML text.
/// dts : list of float
///     The steps of the study (``--dt``).
/// out : str
///     The output directory.
/// force : bool, optional
///     Write into a non-empty ``out``. Default ``False``.
///
/// Returns
/// -------
/// tuple of (str, str, str or None)
///     ``(outcome, message, key)`` as ``run_many`` gives them for one
///     member: ``"ok"``, ``"error"``, ``"scenario"`` (with ``key``, which
///     is ``"--dt"`` for a bad step) or ``"failure"`` (a field, beam or rod
///     scenario; output directory, I/O).
#[pyfunction]
#[pyo3(signature = (label, text, dts, out, force=false))]
fn verify(py: Python<'_>, label: &str, text: &str, dts: Vec<f64>, out: &str, force: bool) -> PyResult<Ended> {
    let interrupt = AtomicBool::new(false);
    let done = AtomicUsize::new(0);
    let job = VerifyJob {
        dts,
        out: Some(PathBuf::from(out)),
        force,
        quiet: true,
        interrupt: None,
    };
    attended(py, &interrupt, &done, 1, None, || {
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
