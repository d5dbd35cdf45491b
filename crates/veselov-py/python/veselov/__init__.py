"""Veselov from Python: the ``veselov`` command's scenario runs as NumPy arrays.

Every run goes through the command's own library (the same parsing,
validation, messages, driver and writers as ``veselov run``) into an output
directory; the files are then read back, so the arrays equal the command's
files bit for bit. Every array is a ``numpy.ndarray`` of ``float64``.

A *scenario* is a path (``str`` or ``os.PathLike``) to a TOML file, TOML
text (a ``str`` containing a newline or ``=``), or a mapping with the
command's schema (nested tables, or dotted keys such as ``"method.dt"``);
``veselov.Scenario`` is that type.

Functions: :func:`run`, :func:`ensemble`, :func:`verify`,
:func:`read_dir`, :func:`toml_text`, :func:`models`, :func:`structures`,
:func:`methods`; classes: :class:`Result`, :class:`ScenarioError`,
:class:`VeselovError`. :func:`veselov.dask.ensemble` maps ensembles onto a
``dask.distributed`` cluster. ``help(veselov.run)`` (and so on) shows each
one's parameters, return values and array shapes.

Examples
--------
>>> import veselov
>>> r = veselov.run("examples/kepler.toml")
>>> r.status, r["energy"][-1]
"""

from __future__ import annotations

import json
import os
import shutil
import sys
import tempfile
from pathlib import Path
from typing import Any, Callable, Iterable, Mapping, Optional, Sequence, Union

import numpy as np

from . import _native

__all__ = [
    "ScenarioError",
    "VeselovError",
    "Result",
    "run",
    "ensemble",
    "verify",
    "models",
    "structures",
    "methods",
    "read_dir",
]

__version__ = _native.__version__

Scenario = Union[str, os.PathLike, Mapping[str, Any]]


class VeselovError(RuntimeError):
    """A run could not start or write its files.

    Raised for an output directory that cannot be used (not empty without
    ``force=True``, a file, not writable), for I/O errors, and for a
    scenario that a command does not take (e.g. :func:`verify` of a field,
    beam or rod scenario). A run that fails or is interrupted once started
    raises nothing: it returns a :class:`Result` whose ``status`` says so.

    Parameters
    ----------
    message : str
        The command's error text (``str(e)``).

    See Also
    --------
    ScenarioError : The subclass raised for an invalid scenario.
    """


class ScenarioError(VeselovError, ValueError):
    """An invalid scenario: TOML syntax, an unknown key, a wrong type or value.

    Both a :class:`VeselovError` and a ``ValueError``. The message is the
    command's, prefixed with ``member <i>:`` (ensembles) or ``override <i>:``
    (an override that cannot be merged) where that applies.

    Parameters
    ----------
    message : str
        The error text (``str(e)``).
    key : str or None, optional
        The dotted key at fault, e.g. ``"method.dt"``.

    Attributes
    ----------
    key : str or None
        The dotted key at fault (``"method.dt"``, ``"initial.q"``); ``None``
        when the message names no key, e.g. a TOML syntax error outside any
        assignment or an unreadable scenario file.

    Examples
    --------
    >>> try:
    ...     veselov.run({"model": {"name": "kepler"},
    ...                  "method": {"name": "midpoint", "dt": -1.0},
    ...                  "time": {"t_end": 1.0}})
    ... except veselov.ScenarioError as e:
    ...     print(e.key)
    method.dt
    """

    def __init__(self, message: str, key: Optional[str] = None):
        super().__init__(message)
        self.key = key


class Result:
    """The outputs of one run (or one convergence study), as NumPy arrays.

    Returned by :func:`run`, :func:`ensemble`, :func:`verify`,
    :func:`read_dir` and :func:`veselov.dask.ensemble`. Each CSV file of
    the output directory becomes a table of columns, each NPY file an
    array. Every array is a C-contiguous ``numpy.ndarray`` of ``float64``
    holding the file's numbers bit for bit (integer-valued columns such as
    ``steps`` or ``level`` included). Which files there are depends on the
    kind of scenario: see Notes.

    ``r[name]`` gives one array by name, ``name in r`` tests for one and
    ``r.keys()`` lists them: a column of ``trajectory.csv`` (or of the
    run's only table) by its name, a column of another table as
    ``"stem.column"``, or an NPY file by its stem.

    Parameters
    ----------
    status : str
        How the run ended: ``"ok"``, ``"error"`` or ``"interrupted"``.
    message : str
        The error text; ``""`` for a run that ended well.
    summary : dict
        ``summary.json`` as parsed by :func:`json.loads`.
    tables : dict of str to dict of str to numpy.ndarray
        ``{file stem: {column: values}}``.
    arrays : dict of str to numpy.ndarray
        ``{file stem: array}``.
    dir : pathlib.Path or None, optional
        The output directory, when it was kept.

    Attributes
    ----------
    status : str
        ``"ok"``; ``"error"`` (the run failed mid-way, e.g. a Newton
        failure or a blow-up: the arrays hold the rows computed before the
        failure, ``summary["failure"]`` says where); or ``"interrupted"``
        (Ctrl-C: the rows computed so far).
    message : str
        The error text of a failed run; ``""`` otherwise.
    summary : dict
        ``summary.json`` as a dict (str keys; values are numbers, str,
        bool, ``None``, lists or dicts): ``status``, ``steps``,
        ``t_final``, ``energy_error_max``, ... by kind of run (the book's
        "summary.json and run status" page lists them). ``{}`` when the
        directory has none.
    tables : dict of str to dict of str to numpy.ndarray
        ``{stem: {column: values}}`` for each file ``<stem>.csv``, stems
        in file-name order and columns in the file's order. Each ``values``
        is a ``numpy.ndarray`` of ``float64``, shape ``(n_rows,)``, with
        ``n_rows`` the file's number of data rows (the same for every column
        of a table; 0 for a header-only file).
    arrays : dict of str to numpy.ndarray
        ``{stem: array}`` for each file ``<stem>.npy``: ``float64``, C order,
        in the shape written (see Notes); the first axis is the rows
        (records or snapshots).
    dir : pathlib.Path or None
        The output directory when the files were kept (``out=``); ``None``
        when the run wrote to a temporary directory, since removed, and for
        a :class:`Result` returned by :func:`read_dir`.

    See Also
    --------
    read_dir : Read the outputs of a run made by the command line.

    Notes
    -----
    The files of each kind of run (the book's "Output files" page has the
    details). Below ``n_rows`` is the number of rows written (one at the
    start, every ``output.every`` steps and at the end; fewer for a run
    that failed or was interrupted), and every column is
    ``float64, shape (n_rows,)``.

    Lagrangian mechanics (``N`` coordinates, ``M`` momentum maps):
        ``tables["trajectory"]``: columns ``t``, the ``N`` coordinates by
        name (``x, y`` for Kepler; ``q0, q1, ...`` if a name would clash),
        the ``N`` momenta ``p_<q>``, ``energy``, ``M`` columns ``J_<name>``,
        then ``work`` (forced systems only), then ``h`` and
        ``discrete_energy`` (variable-step ``sem-*`` methods only).
        With ``output.formats`` including ``"npy"``,
        ``arrays["trajectory"]`` holds the same numbers, shape
        ``(n_rows, n_columns)`` with ``n_columns = 2 + 2*N + M`` (+1 forced,
        +2 variable-step), columns in the order above; with ``"npy"`` alone
        there is no ``trajectory`` table, only this array.
    Rigid bodies:
        ``tables["trajectory"]`` (and ``arrays["trajectory"]``, shape
        ``(n_rows, n_columns)``): ``t``, ``R00 ... R22`` (the attitude, row
        by row), ``x0 x1 x2`` (SE(3) only), ``Pi0 Pi1 Pi2``, ``P0 P1 P2``
        (SE(3) only), ``energy``, ``pi_x pi_y pi_z``, ``p_x p_y p_z``
        (SE(3) only), the conserved ``J_*``, ``orthogonality_defect``.
    1+1 lattice fields (``nodes`` lattice nodes):
        ``tables["energy"]``: ``t, energy`` and, for the periodic wave
        equation or the complex Klein-Gordon field, a charge column
        (``shift_charge`` or ``phase_charge``); ``tables["snapshot_times"]``: ``t``, shape
        ``(n_snapshots,)``; ``arrays["snapshots"]``: shape
        ``(n_snapshots, nodes)``, or ``(n_snapshots, nodes, 2)`` (real and
        imaginary parts) for the complex field.
    2+1 fields on the CFK lattice (an ``nx`` by ``ny`` grid):
        ``tables["energy"]``: ``t, energy``; ``tables["momentum"]``:
        ``t, p_x, p_y`` and a charge column for the wave equation or the
        complex field; ``tables["snapshot_times"]``: ``t``;
        ``arrays["snapshots"]``: shape ``(n_snapshots, nx, ny)``, or
        ``(n_snapshots, nx, ny, 2)`` for the complex field.
    The beam (``cross_nodes`` nodes across each level, in
    ``summary["cross_nodes"]``):
        ``tables["energy"]``: ``level, t, energy`` (``s`` for ``t`` in
        space evolution); ``tables["momentum"]``: ``level, t``,
        ``J_wx J_wy J_wz J_vx J_vy J_vz``,
        ``Jdomain_wx ... Jdomain_vz``; ``arrays["frames"]``: shape
        ``(n_rows, cross_nodes, 12)``, the rotation matrix row by row (9)
        then the position (3), in m.
    The Cosserat rod (``nodes`` material points, ``summary["nodes"]``):
        ``tables["energy"]``: ``t, energy``; ``tables["momentum"]``:
        ``t, P_x, P_y, P_z, L_x, L_y, L_z``; ``arrays["centerline"]``: shape
        ``(n_rows, nodes, 3)`` (m); ``arrays["frames"]``: shape
        ``(n_rows, nodes, 9)``, the frame row by row.
    Convergence studies (:func:`verify`, ``n_dt`` steps):
        ``tables["convergence"]``: ``dt, steps, error``, each shape
        ``(n_dt,)``; ``arrays`` is empty.

    Runs with more than one table and no ``trajectory`` (fields, the beam,
    the rod) have no bare column names: ``r["energy.energy"]``,
    ``r["momentum.P_x"]``.

    Examples
    --------
    >>> r = veselov.run("examples/kepler.toml")
    >>> r.status
    'ok'
    >>> r["t"].shape == r["energy"].shape == (len(r["t"]),)
    True
    >>> r.arrays["trajectory"].shape[1] == len(r.tables["trajectory"])
    True
    """

    def __init__(self, status, message, summary, tables, arrays, dir=None):
        self.status = status
        self.message = message
        self.summary = summary
        self.tables = tables
        self.arrays = arrays
        self.dir = dir

    def _main(self):
        if "trajectory" in self.tables:
            return self.tables["trajectory"]
        if len(self.tables) == 1:
            return next(iter(self.tables.values()))
        return {}

    def keys(self):
        """The names that ``r[name]`` accepts.

        Returns
        -------
        list of str
            The columns of the main table (``trajectory``, or the only
            table) by name, in file order; then ``"stem.column"`` for the
            columns of every other table; then the stems of the NPY files
            (``"trajectory"`` included when it was written).
        """
        main = self._main()
        names = list(main)
        for stem, table in self.tables.items():
            if table is not main:
                names.extend(f"{stem}.{c}" for c in table)
        names.extend(s for s in self.arrays if s not in names)
        return names

    def __getitem__(self, name: str) -> np.ndarray:
        """One output by name: ``r[name]``.

        Parameters
        ----------
        name : str
            A column of the main table (``"t"``, ``"energy"``), a column of
            another table as ``"stem.column"`` (``"energy.energy"``,
            ``"snapshot_times.t"``), or the stem of an NPY file
            (``"snapshots"``, ``"centerline"``). :meth:`keys` lists them.

        Returns
        -------
        numpy.ndarray of float64
            A column: shape ``(n_rows,)``. An NPY file: its own shape, e.g.
            ``(n_rows, n_columns)`` for ``trajectory``,
            ``(n_snapshots, nodes)`` for ``snapshots``, ``(n_rows, nodes, 3)``
            for ``centerline`` (see the class's Notes). The array is the
            one held in ``tables`` or ``arrays``, not a copy.

        Raises
        ------
        KeyError
            If ``name`` is none of these; the message lists the names.
        """
        main = self._main()
        if name in main:
            return main[name]
        stem, _, column = name.partition(".")
        if column and stem in self.tables and column in self.tables[stem]:
            return self.tables[stem][column]
        if name in self.arrays:
            return self.arrays[name]
        raise KeyError(f"{name!r}: not an output of this run; it has {', '.join(self.keys())}")

    def __contains__(self, name: str) -> bool:
        """Whether ``r[name]`` would return an array: ``name in r``.

        Parameters
        ----------
        name : str
            A name as :meth:`__getitem__` takes it.

        Returns
        -------
        bool
            ``True`` if ``name`` is one of :meth:`keys`.
        """
        try:
            self[name]
            return True
        except KeyError:
            return False

    def __repr__(self):
        return f"<veselov.Result status={self.status!r} outputs={self.keys()}>"


def _read_csv(path: Path) -> dict:
    with open(path, "r", encoding="utf-8") as f:
        header = f.readline().strip()
        columns = header.split(",") if header else []
        # float() parses the shortest round-trip form exactly.
        rows = [[float(x) for x in line.split(",")] for line in f if line.strip()]
    data = np.array(rows, dtype=np.float64).reshape(len(rows), len(columns))
    return {c: np.ascontiguousarray(data[:, i]) for i, c in enumerate(columns)}


def read_dir(dir: Union[str, os.PathLike], status: Optional[str] = None, message: str = "") -> Result:
    """Read the outputs of a run from its directory.

    Reads the directory written by ``veselov run`` (or by :func:`run` with
    ``out=``, or ``veselov verify``): ``summary.json``, every ``*.csv`` file
    into ``tables`` and every ``*.npy`` file into ``arrays``. Other files
    (plots, ``checkpoint.json``) are ignored. Where a CSV file and a 2-D NPY
    file of the same stem have the same number of columns (``trajectory``
    with ``output.formats = ["csv", "npy"]``), the table's columns are taken
    from the NPY file: the same numbers, read faster.

    Parameters
    ----------
    dir : str or os.PathLike
        The run's output directory.
    status : str, optional
        The status to report; by default ``summary["status"]``, or
        ``"error"`` when the summary has no ``status`` (a directory without
        ``summary.json``, or one written by ``veselov verify``).
    message : str, optional
        The error text to report (default ``""``).

    Returns
    -------
    Result
        The outputs: ``tables`` of ``float64`` columns of shape
        ``(n_rows,)`` and ``arrays`` of ``float64`` in their files' shapes
        (see :class:`Result`). Its ``dir`` is ``None``.

    Raises
    ------
    FileNotFoundError
        If ``dir`` does not exist.
    ValueError
        If a CSV file holds something other than numbers, or
        ``summary.json`` is not JSON (``json.JSONDecodeError``).

    See Also
    --------
    run : Run a scenario and read its outputs.

    Examples
    --------
    >>> r = veselov.read_dir("out/kepler")   # after `veselov run examples/kepler.toml`
    >>> r["t"].dtype, r["t"].ndim
    (dtype('float64'), 1)
    """
    d = Path(dir)
    summary_path = d / "summary.json"
    summary = json.loads(summary_path.read_text(encoding="utf-8")) if summary_path.exists() else {}
    tables, arrays = {}, {}
    for f in sorted(d.iterdir()):
        if f.suffix == ".npy":
            arrays[f.stem] = np.load(f)
    for f in sorted(d.iterdir()):
        if f.suffix != ".csv":
            continue
        same = arrays.get(f.stem)
        with open(f, "r", encoding="utf-8") as fh:
            columns = fh.readline().strip().split(",")
        if same is not None and same.ndim == 2 and same.shape[1] == len(columns):
            # The NPY file holds the same rows as the CSV file, bit for bit
            # (both are written from one row); reading it is much faster.
            tables[f.stem] = {c: np.ascontiguousarray(same[:, i]) for i, c in enumerate(columns)}
        else:
            tables[f.stem] = _read_csv(f)
    if status is None:
        status = summary.get("status", "error")
    return Result(status, message, summary, tables, arrays)


def _scenario_text(scenario: Scenario) -> "tuple[str, str]":
    """``(label, TOML text)`` of a path, a TOML string or a dict."""
    if isinstance(scenario, Mapping):
        return "<dict>", toml_text(scenario)
    if isinstance(scenario, os.PathLike) or (
        isinstance(scenario, str) and "\n" not in scenario and "=" not in scenario
    ):
        path = Path(scenario)
        try:
            return str(path), path.read_text(encoding="utf-8")
        except OSError as e:
            raise ScenarioError(f"{path}: {e.strerror or e}") from None
    if isinstance(scenario, str):
        return "<string>", scenario
    raise TypeError(f"scenario: expected a path, a TOML string or a dict, got {type(scenario).__name__}")


def _toml_value(v: Any, key: str) -> str:
    if isinstance(v, (bool, np.bool_)):
        return "true" if v else "false"
    if isinstance(v, (int, np.integer)):
        return str(int(v))
    if isinstance(v, (float, np.floating)):
        x = float(v)
        if x != x:
            return "nan"
        if x in (float("inf"), float("-inf")):
            return "inf" if x > 0 else "-inf"
        return float.__repr__(x)  # the shortest string that reads back exactly
    if isinstance(v, str):
        return json.dumps(v)  # a TOML basic string
    if isinstance(v, Mapping):
        return "{ " + ", ".join(f"{json.dumps(str(k))} = {_toml_value(x, f'{key}.{k}')}" for k, x in v.items()) + " }"
    if isinstance(v, (list, tuple, np.ndarray)):
        return "[" + ", ".join(_toml_value(x, f"{key}[{i}]") for i, x in enumerate(v)) + "]"
    raise ScenarioError(f"`{key}`: {type(v).__name__} has no TOML form", key)


def _nested(overrides: Mapping[str, Any]) -> dict:
    """Dotted keys (``"initial.q"``) as nested dicts."""
    out: dict = {}
    for k, v in overrides.items():
        *path, last = str(k).split(".")
        d = out
        for p in path:
            d = d.setdefault(p, {})
            if not isinstance(d, dict):
                raise ScenarioError(f"`{k}`: `{p}` is not a table", str(k))
        if isinstance(v, Mapping) and isinstance(d.get(last), dict):
            d[last].update(_nested(v))
        else:
            d[last] = _nested(v) if isinstance(v, Mapping) else v
    return out


def toml_text(scenario: Mapping[str, Any]) -> str:
    """The TOML document of a scenario mapping.

    Dotted keys become nested tables (``{"method.dt": 0.1}`` is
    ``method = { dt = 0.1 }``) and merge with a table given under the same
    name. Floats are written in their shortest exact form (so they read
    back bit for bit); NumPy scalars and arrays are written as numbers and
    (nested) arrays.

    Parameters
    ----------
    scenario : Mapping[str, Any]
        The scenario: values ``bool``, ``int``, ``float``, ``str``
        (NumPy scalars too), mappings, and lists, tuples or
        ``numpy.ndarray`` of these.

    Returns
    -------
    str
        The TOML text: one line ``"key" = value`` per top-level key, tables
        inline.

    Raises
    ------
    ScenarioError
        If a value has no TOML form (``None``, an object), with ``key`` the
        dotted key; or if a dotted key goes through a key that is not a
        table.

    Examples
    --------
    >>> print(veselov.toml_text({"method.dt": 0.5, "initial.q": [0.1, 2]}), end="")
    "method" = { "dt" = 0.5 }
    "initial" = { "q" = [0.1, 2] }
    """
    return "".join(f"{json.dumps(k)} = {_toml_value(v, k)}\n" for k, v in _nested(scenario).items())


def _override(label: str, text: str, overrides: Mapping[str, Any], index: Optional[int] = None) -> str:
    outcome, value, key = _native.merge(text, toml_text(overrides))
    if outcome != "ok":
        where = f"override {index}: " if index is not None else ""
        raise ScenarioError(f"{label}: {where}{value}", key)
    return value


def _outcome(status, message, key, out, keep, index=None) -> Result:
    if status == "scenario":
        raise ScenarioError(message if index is None else f"member {index}: {message}", key)
    if status == "failure":
        raise VeselovError(message)
    result = read_dir(out, status, message)
    if keep:
        result.dir = Path(out)
    return result


def run(scenario: Scenario, out: Optional[Union[str, os.PathLike]] = None, force: bool = False) -> Result:
    """Run a scenario and return its outputs as NumPy arrays.

    The scenario is parsed, validated and run by the command's library, as
    ``veselov run`` does, with the GIL released while it integrates. With
    ``out`` the command's files (CSV/NPY, ``summary.json``,
    ``checkpoint.json``, plots) stay in that directory; without it, the run
    writes to a temporary directory, without plots, which is removed once
    read. A run that fails mid-way or is interrupted (Ctrl-C) raises
    nothing: it returns the rows computed so far with ``status`` ``"error"``
    or ``"interrupted"``.

    Parameters
    ----------
    scenario : str, os.PathLike or Mapping[str, Any]
        A path to a TOML file; TOML text (a ``str`` containing a newline or
        ``=``); or a mapping with the command's schema, nested tables or
        dotted keys (``{"method.dt": 0.01}``), written by :func:`toml_text`.
    out : str or os.PathLike, optional
        The output directory to keep the files in (created if needed).
        The scenario's ``output.dir`` is not used.
    force : bool, optional
        Run in a non-empty ``out``, first removing the outputs an earlier
        run wrote there (other files are kept). Default ``False``.

    Returns
    -------
    Result
        ``status``, ``summary``, ``message``; ``tables`` of ``float64``
        columns, each of shape ``(n_rows,)``; ``arrays`` of ``float64`` in
        their files' shapes (``trajectory``: ``(n_rows, n_columns)``,
        ``snapshots``: ``(n_snapshots, nodes)``, ...; :class:`Result` lists
        them by kind of run); ``dir`` is ``Path(out)`` or ``None``.

    Raises
    ------
    ScenarioError
        If the scenario is invalid (syntax, unknown key, wrong type or
        value) or its file cannot be read; ``e.key`` names the key.
    VeselovError
        If the run cannot start or write its files: ``out`` is a file, is
        not empty without ``force``, is not writable, or another I/O error.
    TypeError
        If ``scenario`` is none of a path, a ``str`` or a mapping.

    See Also
    --------
    ensemble : Many runs of one scenario with overrides, in parallel.
    read_dir : The outputs of a run made by the command line.

    Notes
    -----
    Ctrl-C (SIGINT, or interrupting a Jupyter kernel) is turned into the
    run's interruption: the ``KeyboardInterrupt`` is not raised. An
    exception raised by another Python signal handler also interrupts the
    run, and is raised once it has ended.

    Examples
    --------
    >>> r = veselov.run("examples/kepler.toml")
    >>> r.status, r["t"].shape == r["energy"].shape
    ('ok', True)
    >>> r = veselov.run({
    ...     "model": {"name": "pendulum"},
    ...     "method": {"name": "galerkin-gauss", "stages": 2, "dt": 0.05},
    ...     "time": {"t_end": 20.0},
    ...     "initial": {"q": [2.5], "p": [0.0]},
    ... })
    >>> list(r.tables["trajectory"])
    ['t', 'theta', 'p_theta', 'energy']
    """
    label, text = _scenario_text(scenario)
    return _run_members(label, [text], out, force, workers=None, progress=None)[0]


def _run_members(label, texts, out, force, workers, progress) -> list:
    keep = out is not None
    if keep:
        root = Path(out)
        dirs = [root] if len(texts) == 1 else [root / f"member-{i:05d}" for i in range(len(texts))]
    else:
        root = Path(tempfile.mkdtemp(prefix="veselov-"))
        dirs = [root / f"member-{i:05d}" for i in range(len(texts))]
        texts = [_override(label, t, {"output.plots": False}) for t in texts]
    try:
        ended = _native.run_many(label, texts, [str(d) for d in dirs], force, workers, progress)
        return [
            _outcome(s, m, k, d, keep, i if len(texts) > 1 else None)
            for i, ((s, m, k), d) in enumerate(zip(ended, dirs))
        ]
    finally:
        if not keep:
            shutil.rmtree(root, ignore_errors=True)


def _print_progress(done: int, total: int) -> None:
    sys.stderr.write(f"\rveselov.ensemble: {done}/{total} runs")
    if done == total:
        sys.stderr.write("\n")
    sys.stderr.flush()


def ensemble(
    scenario: Scenario,
    overrides: Sequence[Mapping[str, Any]],
    workers: Optional[int] = None,
    out: Optional[Union[str, os.PathLike]] = None,
    progress: Union[bool, Callable[[int, int], Any]] = False,
) -> list:
    """Run a scenario once per set of overrides, in parallel.

    Member ``i`` is ``scenario`` with the keys of ``overrides[i]`` replaced
    (a mapping value merges into the table key by key, so
    ``{"initial": {"q": [1, 0]}}`` keeps ``initial.p``). The members run on
    ``workers`` threads with the GIL released, and each result equals, bit
    for bit, the :func:`run` of its merged scenario alone.

    Parameters
    ----------
    scenario : str, os.PathLike or Mapping[str, Any]
        The base scenario, as :func:`run` takes it.
    overrides : Sequence[Mapping[str, Any]]
        One mapping per member, keys dotted or nested, e.g.
        ``{"initial.q": [1.0, 0.0], "model.params.epsilon": 0.3}``; ``{}``
        runs the scenario as it is.
    workers : int, optional
        The number of threads (at least 1); default: all cores.
    out : str or os.PathLike, optional
        A directory in which member ``i`` keeps its files, in
        ``out/member-<i>`` (``i`` on five digits: ``member-00000``).
        Default: temporary directories, without plots, removed once read.
    progress : bool or callable, optional
        ``True`` prints ``veselov.ensemble: <done>/<total> runs`` to
        standard error; a callable is called as ``progress(done, total)``
        (two ``int``) on the calling thread as members end, and once at the
        end. Default ``False``: no report.

    Returns
    -------
    list of Result
        ``len(overrides)`` results, in the order of ``overrides``, each as
        :func:`run` returns it (``float64`` arrays in their files' shapes;
        ``dir`` is ``out/member-<i>`` or ``None``); ``[]`` for no overrides.

    Raises
    ------
    ScenarioError
        If an override cannot be merged (``override <i>: ...``, raised
        before any run) or a member's scenario is invalid
        (``member <i>: ...``, raised once every member has ended; the
        other members' results are then not returned). ``e.key`` names the
        key.
    VeselovError
        If a member cannot start or write its files (e.g. ``out/member-<i>``
        is not empty).
    ValueError
        If ``workers`` is 0.
    TypeError
        If ``scenario`` is none of a path, a ``str`` or a mapping.

    See Also
    --------
    run : One run.
    veselov.dask.ensemble : The same on a ``dask.distributed`` cluster.

    Notes
    -----
    Ctrl-C interrupts every member still running (their ``status`` is
    ``"interrupted"``) without raising. An exception raised by ``progress``
    interrupts the members still running and is raised once they have
    ended.

    Examples
    --------
    >>> import numpy as np
    >>> starts = np.random.default_rng(1).uniform(-4, 4, (100, 2))
    >>> runs = veselov.ensemble(
    ...     "examples/van_der_pol.toml",
    ...     [{"initial.q": list(q), "time.t_end": 1.0} for q in starts],
    ...     workers=2,
    ... )
    >>> final = np.array([[r["q1"][-1], r["q2"][-1]] for r in runs])
    >>> final.shape, final.dtype
    ((100, 2), dtype('float64'))
    """
    label, text = _scenario_text(scenario)
    texts = [_override(label, text, o, i) for i, o in enumerate(overrides)]
    if not texts:
        return []
    report = _print_progress if progress is True else (progress or None)
    if len(texts) == 1 and out is not None:
        out = Path(out) / "member-00000"
    return _run_members(label, texts, out, False, workers, report)


def verify(
    scenario: Scenario,
    dt: Iterable[float],
    out: Optional[Union[str, os.PathLike]] = None,
    force: bool = False,
) -> Result:
    """Convergence study of a scenario's method, as ``veselov verify`` does.

    Runs the scenario's model and method once per step in ``dt`` and
    measures each run's error at the final time against a reference (the
    exact solution where the model has one, otherwise a fine run: see
    ``verify_reference`` in :func:`models`), then fits the order. Takes
    Lagrangian mechanics and rigid-body scenarios only.

    Parameters
    ----------
    scenario : str, os.PathLike or Mapping[str, Any]
        The scenario, as :func:`run` takes it.
    dt : iterable of float
        The steps to try, e.g. ``[0.1, 0.05, 0.025]``. A fixed-step
        method uses the nearest step that divides the run's time span in
        a whole number of steps.
    out : str or os.PathLike, optional
        The directory to keep ``convergence.csv``, ``convergence.svg`` and
        ``summary.json`` in. Default: a temporary directory, removed.
    force : bool, optional
        Write into a non-empty ``out``. Default ``False``.

    Returns
    -------
    Result
        ``status`` ``"ok"``; ``tables["convergence"]``: columns ``dt``
        (the steps used), ``steps`` and ``error`` (``NaN`` for a run that
        failed), each ``numpy.ndarray`` of ``float64``, shape
        ``(len(dt),)``, so that ``r["dt"]`` works; ``arrays`` empty;
        ``summary`` with ``method``, ``order_claimed`` (int),
        ``order_fitted`` (float or ``None``), ``order_reached`` (bool),
        ``fit_dt_range``, ``local_rates``, ``dt``, ``errors`` (lists of
        float), ``reference`` and ``t_end``; ``dir`` is ``Path(out)`` or
        ``None``.

    Raises
    ------
    ScenarioError
        If the scenario is invalid; or if a step in ``dt`` is not a finite
        number > 0 or asks for too many steps, with ``e.key == "--dt"``.
    VeselovError
        If the scenario is a lattice field, the beam or the rod (not
        taken), or ``out`` cannot be written.
    TypeError
        If ``scenario`` is none of a path, a ``str`` or a mapping.

    See Also
    --------
    run : One run of the scenario.

    Notes
    -----
    A study is not interrupted by Ctrl-C: it runs to its end, and the
    ``KeyboardInterrupt`` is not raised.

    Examples
    --------
    >>> study = veselov.verify("examples/harmonic.toml", dt=[0.1, 0.05, 0.025])
    >>> study["error"].shape, study.summary["order_claimed"]
    ((3,), 2)
    """
    label, text = _scenario_text(scenario)
    keep = out is not None
    root = Path(out) if keep else Path(tempfile.mkdtemp(prefix="veselov-"))
    try:
        status, message, key = _native.verify(label, text, [float(h) for h in dt], str(root), force)
        return _outcome(status, message, key, root, keep)
    finally:
        if not keep:
            shutil.rmtree(root, ignore_errors=True)


def models() -> list:
    """The catalogue of built-in models, as ``veselov models`` lists them first.

    The Lagrangian-mechanics, rigid-body and lattice-field models, with
    their parameters; the beam and the rod, whose keys are of another kind,
    are in :func:`structures`.

    Returns
    -------
    list of dict
        One dict per model, in the command's order, with keys:

        ``name`` : str
            The ``model.name`` to give, e.g. ``"kepler"``.
        ``summary`` : str
            One line: the system and its Lagrangian.
        ``coordinates`` : list of str
            The names of the coordinates, i.e. of the trajectory's
            coordinate columns; ``[]`` for rigid bodies, fields and
            ``custom`` (whose scenario names its own).
        ``params`` : dict of str to dict
            ``{param: {"default": float, "doc": str}}`` for the keys of
            ``model.params``.
        ``default_initial`` : str
            The initial data used when the scenario gives none.
        ``momentum_maps`` : list of str
            The conserved momentum maps and charges: a name for mechanics
            (``"angular"``, written as the column ``J_angular``), column
            names with a note for rigid bodies and fields
            (``"J_z (vertical spatial angular momentum)"``); ``[]`` for
            none.
        ``verify_reference`` : str
            What :func:`verify` measures the error against.

    See Also
    --------
    structures : The beam and the rod.
    methods : The integration methods.

    Examples
    --------
    >>> kepler = next(m for m in veselov.models() if m["name"] == "kepler")
    >>> kepler["coordinates"], kepler["params"]["eccentricity"]["default"]
    (['x', 'y'], 0.5)
    """
    return [
        {
            "name": name,
            "summary": summary,
            "coordinates": list(coords),
            "params": {p: {"default": d, "doc": doc} for p, d, doc in params},
            "default_initial": initial,
            "momentum_maps": list(symmetries),
            "verify_reference": reference,
        }
        for name, summary, coords, params, initial, symmetries, reference in _native.models()
    ]


def structures() -> list:
    """The structural models, as ``veselov models`` lists them last.

    The geometrically exact beam and the Cosserat rod, which take tables of
    keys of their own rather than ``model.params``.

    Returns
    -------
    list of dict
        One dict per model (``"beam"``, ``"cosserat-rod"``) with keys:

        ``name`` : str
            The ``model.name`` to give.
        ``summary`` : str
            One line describing the model.
        ``keys`` : str
            The scenario keys it takes, by table, as one line of text
            (``"[model] length, nodes, ...; [method] ...; ..."``).
        ``examples`` : str
            The example scenarios, as a glob (``"examples/beam_*.toml"``).

    See Also
    --------
    models : The other built-in models.
    methods : The integration methods.
    """
    return [
        {"name": n, "summary": s, "keys": k, "examples": e}
        for n, s, k, e in _native.structures()
    ]


def methods() -> list:
    """The catalogue of integration methods, as ``veselov methods`` lists them.

    Returns
    -------
    list of dict
        One dict per method with keys:

        ``name`` : str
            The ``method.name`` to give (``"midpoint"``,
            ``"galerkin-gauss"``, ``"sem-midpoint"``, ...); the last entry
            describes the Lie-group trapezoid that rigid-body models use.
        ``keys`` : str
            The ``[method]`` keys it takes, with their ranges and defaults,
            as text (``"dt"``, ``"dt, stages = 2..10 (default 3)"``, ...).
        ``properties`` : str
            Its order and what it conserves, as text.

    See Also
    --------
    models : The built-in models.
    structures : The beam and the rod.

    Examples
    --------
    >>> [m["name"] for m in veselov.methods()][:2]
    ['midpoint', 'trapezoid']
    """
    return [{"name": n, "keys": k, "properties": p} for n, k, p in _native.methods()]
