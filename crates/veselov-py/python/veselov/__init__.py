"""Veselov from Python: the ``veselov`` command's scenario runs as NumPy arrays.

Every run goes through the command's own library (the same parsing,
validation, messages, driver and writers as ``veselov run``) into an output
directory; the files are then read back, so the arrays equal the command's
files bit for bit. Every array is a ``numpy.ndarray`` of ``float64``.

A *scenario* is a path (``str`` or ``os.PathLike``) to a TOML file, TOML
text, or a mapping with the command's schema (nested tables, or dotted keys
such as ``"method.dt"``); ``veselov.Scenario`` is that type. A ``str`` is
read as a path when it names an existing file, or when it is one line
ending in ``.toml``; otherwise a ``str`` containing a newline or ``=`` is
TOML text, and any other ``str`` is a path (a missing file raises
:class:`ScenarioError`). So ``"sweep/lr=0.1/scenario.toml"`` is a path and
``'model = { name = "kepler" }'`` is TOML text.

Functions: :func:`run`, :func:`ensemble`, :func:`resume`, :func:`verify`,
:func:`read_dir`, :func:`toml_text`, :func:`models`, :func:`structures`,
:func:`methods`; classes: :class:`Result` (a read-only mapping of names to
arrays), :class:`ScenarioError`, :class:`VeselovError`.
:func:`veselov.dask.ensemble` maps ensembles onto a ``dask.distributed``
cluster. ``help(veselov.run)`` (and so on) shows each one's parameters,
return values and array shapes.

Examples
--------
>>> import veselov
>>> r = veselov.run("examples/kepler.toml")
>>> r.status, r["energy"][-1]
"""

from __future__ import annotations

import collections
import collections.abc
import json
import numbers
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
    "resume",
    "verify",
    "models",
    "structures",
    "methods",
    "read_dir",
]

__version__ = _native.__version__

Scenario = Union[str, os.PathLike, Mapping[str, Any]]

# The scenario a run was made from, written beside its checkpoint by
# `run` and `ensemble`, and read by `resume`.
_RUN_SCENARIO = "run-scenario.toml"


class VeselovError(RuntimeError):
    """A run could not start or write its files.

    Raised for an output directory that cannot be used (not empty without
    ``force=True``, a file, not writable), for I/O errors, for a checkpoint
    that :func:`resume` cannot continue, and for a scenario that a command
    does not take. A run that fails or is interrupted once started raises
    nothing: it returns a :class:`Result` whose ``status`` says so.

    Parameters
    ----------
    message : str
        The error text (``str(e)``).
    member : int or None, optional
        The index of the ensemble member at fault.

    Attributes
    ----------
    member : int or None
        The index of the ensemble member at fault, counted in the whole
        ensemble (:func:`ensemble`, :func:`veselov.dask.ensemble`; the
        message then starts with ``member <i>:``); ``None`` outside
        ensembles.
    results : list or None
        Set on the error an ensemble raises (``on_error="raise"``): one
        entry per member, in input order, the member's :class:`Result` or
        the :class:`VeselovError` it raised, so that the members that ran
        are not lost. ``None`` otherwise, and for an override raised
        before any member ran.

    See Also
    --------
    ScenarioError : The subclass raised for an invalid scenario.
    """

    def __init__(self, message: str, member: Optional[int] = None):
        super().__init__(message)
        self.member = member
        self.results: Optional[list] = None


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
    member : int or None, optional
        The index of the ensemble member at fault.

    Attributes
    ----------
    key : str or None
        The dotted key at fault (``"method.dt"``, ``"initial.q"``, or
        ``"dt"`` for a step given to :func:`verify`); ``None`` when the
        message names no key, e.g. a TOML syntax error outside any
        assignment or an unreadable scenario file.
    member : int or None
        As for :class:`VeselovError`.
    results : list or None
        As for :class:`VeselovError`.

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

    def __init__(self, message: str, key: Optional[str] = None, member: Optional[int] = None):
        super().__init__(message, member)
        self.key = key


class Result(collections.abc.Mapping):
    """The outputs of one run (or one convergence study), as NumPy arrays.

    Returned by :func:`run`, :func:`ensemble`, :func:`resume`,
    :func:`verify`, :func:`read_dir` and :func:`veselov.dask.ensemble`.
    Each CSV file of the output directory becomes a table of columns, each
    NPY file an array. Every array is a C-contiguous ``numpy.ndarray`` of
    ``float64`` holding the file's numbers bit for bit (integer-valued
    columns such as ``steps`` or ``level`` included). Which files there are
    depends on the kind of scenario: see Notes.

    A ``Result`` is a read-only ``collections.abc.Mapping`` from names to
    arrays: ``r[name]``, ``name in r``, ``len(r)``, ``iter(r)``,
    ``r.keys()``, ``r.values()``, ``r.items()``, ``r.get(name)`` and
    ``dict(r)`` work as for a dict. The names (:meth:`keys`, in this
    order) are:

    * the columns of the main table (``trajectory.csv``, or the run's only
      table) by name;
    * the columns of the other tables by name where no other table has a
      column of that name (``"energy"``, ``"P_x"`` for the rod), else as
      ``"stem.column"`` (``"energy.t"``, ``"momentum.t"``);
    * the NPY files by stem (``"trajectory"``, ``"snapshots"``,
      ``"centerline"``, ``"frames"``);
    * ``"rotation_matrices"``, where the run has rotations (see Notes).

    ``r["stem.column"]`` also works for every column of every table (so
    ``r["energy.energy"]`` and ``r["energy"]`` are the same array), without
    being listed twice. ``status``, ``message``, ``summary``, ``tables``,
    ``arrays`` and ``dir`` are attributes, not keys.

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
        (Ctrl-C: the rows computed so far; :func:`resume` continues it).
    message : str
        The error text of a failed or interrupted run; ``""`` otherwise.
        For an interrupted run with a checkpoint it says where the
        checkpoint is and how to continue (``veselov.resume('<dir>')``).
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
        The output directory when the files were kept: ``out=``, the
        directory :func:`resume` continued, or the temporary directory of
        a run without ``out=`` that was interrupted with a checkpoint
        (kept so that it can be resumed; remove it when done). ``None``
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
        ``r["rotation_matrices"]``: the attitudes as matrices, shape
        ``(n_rows, 3, 3)``, ``r["rotation_matrices"][k, i, j]`` being
        ``R<i><j>`` of row ``k``.
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
        then the position (3), in m. ``r["rotation_matrices"]``: the
        rotations, shape ``(n_rows, cross_nodes, 3, 3)``.
    The Cosserat rod (``nodes`` material points, ``summary["nodes"]``):
        ``tables["energy"]``: ``t, energy``; ``tables["momentum"]``:
        ``t, P_x, P_y, P_z, L_x, L_y, L_z``; ``arrays["centerline"]``: shape
        ``(n_rows, nodes, 3)`` (m); ``arrays["frames"]``: shape
        ``(n_rows, nodes, 9)``, the frame row by row.
        ``r["rotation_matrices"]``: the frames as matrices, shape
        ``(n_rows, nodes, 3, 3)`` (a view of ``arrays["frames"]``).
    Convergence studies (:func:`verify`, ``n_dt`` steps):
        ``tables["convergence"]``: ``dt, steps, error``, each shape
        ``(n_dt,)``; ``arrays`` is empty.

    ``rotation_matrices`` is computed from the files when first asked
    for, and is the only name that is not a file's column or array.

    Two results compare equal only if they are the same object (``==``
    compares no arrays).

    Examples
    --------
    >>> r = veselov.run("examples/kepler.toml")
    >>> r.status
    'ok'
    >>> r["t"].shape == r["energy"].shape == (len(r["t"]),)
    True
    >>> r.arrays["trajectory"].shape[1] == len(r.tables["trajectory"])
    True
    >>> rod = veselov.run("examples/rod_timoshenko.toml")
    >>> "energy" in rod, rod["energy"] is rod["energy.energy"]
    (True, True)
    >>> {name: a.shape for name, a in rod.items()}["rotation_matrices"][-2:]
    (3, 3)
    """

    def __init__(self, status, message, summary, tables, arrays, dir=None):
        self.status = status
        self.message = message
        self.summary = summary
        self.tables = tables
        self.arrays = arrays
        self.dir = dir
        self._computed: dict = {}

    # Results are compared and hashed by identity, as before they were
    # mappings: comparing the arrays of two runs is the caller's choice.
    __hash__ = object.__hash__

    def __eq__(self, other):
        return self is other

    def __ne__(self, other):
        return self is not other

    def _main_stem(self) -> Optional[str]:
        if "trajectory" in self.tables:
            return "trajectory"
        if len(self.tables) == 1:
            return next(iter(self.tables))
        return None

    def _derivable(self) -> dict:
        """``{name: function returning the array}`` of the arrays computed
        from the files (``rotation_matrices``)."""
        rows = [f"R{i}{j}" for i in range(3) for j in range(3)]
        traj = self.tables.get("trajectory", {})
        if all(c in traj for c in rows):
            return {"rotation_matrices": lambda: np.stack([traj[c] for c in rows], axis=-1).reshape(-1, 3, 3)}
        flat = self.arrays.get("trajectory")
        if (
            flat is not None
            and "trajectory" not in self.tables
            and "orthogonality_defect_max" in self.summary
            and flat.ndim == 2
            and flat.shape[1] >= 10
        ):
            # A rigid-body run written as NPY only: t, then R00 ... R22.
            return {"rotation_matrices": lambda: np.ascontiguousarray(flat[:, 1:10]).reshape(-1, 3, 3)}
        frames = self.arrays.get("frames")
        if frames is not None and frames.ndim == 3 and frames.shape[2] in (9, 12):
            n, nodes = frames.shape[:2]
            return {"rotation_matrices": lambda: np.ascontiguousarray(frames[:, :, :9]).reshape(n, nodes, 3, 3)}
        return {}

    def _index(self) -> dict:
        """``{name: where}``: ``("column", stem, column)``, ``("array",
        stem)`` or ``("computed", name)``, in the order of :meth:`keys`."""
        index: dict = {}
        main = self._main_stem()
        if main is not None:
            for c in self.tables[main]:
                index[c] = ("column", main, c)
        derivable = self._derivable()
        others = [(stem, table) for stem, table in self.tables.items() if stem != main]
        counts = collections.Counter(c for _, table in others for c in table)
        for stem, table in others:
            for c in table:
                bare = c not in index and counts[c] == 1 and c not in self.arrays and c not in derivable
                index[c if bare else f"{stem}.{c}"] = ("column", stem, c)
        for stem in self.arrays:
            index.setdefault(stem, ("array", stem))
        for name in derivable:
            index.setdefault(name, ("computed", name))
        return index

    def keys(self):
        """The names that ``r[name]`` accepts, each array's once.

        Returns
        -------
        collections.abc.KeysView
            A view of the names, in this order: the columns of the main
            table (``trajectory``, or the only table) by name, in file
            order; the columns of the other tables, by name where no other
            table has a column of that name, else as ``"stem.column"``;
            the stems of the NPY files (``"trajectory"`` included when it
            was written); ``"rotation_matrices"`` where the run has
            rotations. ``list(r.keys())`` lists them.
        """
        return collections.abc.KeysView(self)

    def __iter__(self):
        """Iterate over the names of :meth:`keys`: ``for name in r``.

        Returns
        -------
        iterator of str
            The names, in the order of :meth:`keys`.
        """
        return iter(self._index())

    def __len__(self) -> int:
        """The number of names in :meth:`keys`: ``len(r)``.

        Returns
        -------
        int
            How many arrays the result holds, each counted once.
        """
        return len(self._index())

    def __getitem__(self, name: str) -> np.ndarray:
        """One output by name: ``r[name]``.

        Parameters
        ----------
        name : str
            One of :meth:`keys` (``"t"``, ``"energy"``, ``"snapshots"``,
            ``"rotation_matrices"``), or any table's column as
            ``"stem.column"`` (``"energy.energy"``, ``"snapshot_times.t"``).

        Returns
        -------
        numpy.ndarray of float64
            A column: shape ``(n_rows,)``. An NPY file: its own shape, e.g.
            ``(n_rows, n_columns)`` for ``trajectory``,
            ``(n_snapshots, nodes)`` for ``snapshots``, ``(n_rows, nodes, 3)``
            for ``centerline`` (see the class's Notes). The array is the
            one held in ``tables`` or ``arrays``, not a copy.
            ``rotation_matrices``: shape ``(n_rows, 3, 3)`` (rigid bodies)
            or ``(n_rows, nodes, 3, 3)`` (beam, rod), computed once.

        Raises
        ------
        KeyError
            If ``name`` is none of these; the message lists the names.
        """
        where = self._index().get(name) if isinstance(name, str) else None
        if where is None and isinstance(name, str):
            stem, _, column = name.partition(".")
            if column and column in self.tables.get(stem, {}):
                where = ("column", stem, column)
        if where is None:
            raise KeyError(f"{name!r}: not an output of this run; it has {', '.join(self)}")
        if where[0] == "column":
            return self.tables[where[1]][where[2]]
        if where[0] == "array":
            return self.arrays[where[1]]
        if name not in self._computed:
            self._computed[name] = self._derivable()[name]()
        return self._computed[name]

    def __contains__(self, name: object) -> bool:
        """Whether ``r[name]`` would return an array: ``name in r``.

        Parameters
        ----------
        name : str
            A name as :meth:`__getitem__` takes it.

        Returns
        -------
        bool
            ``True`` if ``name`` is one of :meth:`keys` or a table's
            ``"stem.column"``.
        """
        if not isinstance(name, str):
            return False
        if name in self._index():
            return True
        stem, _, column = name.partition(".")
        return bool(column) and column in self.tables.get(stem, {})

    def __repr__(self):
        return f"<veselov.Result status={self.status!r} outputs={list(self)}>"


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

    Reads the directory written by ``veselov run`` or ``veselov verify``
    (or by :func:`run`, :func:`ensemble` or :func:`verify` with ``out=``):
    ``summary.json``, every ``*.csv`` file into ``tables`` and every
    ``*.npy`` file into ``arrays``. Other files (plots,
    ``checkpoint.json``, ``run-scenario.toml``) are ignored. Where a CSV file and a 2-D NPY
    file of the same stem have the same number of columns (``trajectory``
    with ``output.formats = ["csv", "npy"]``), the table's columns are taken
    from the NPY file: the same numbers, read faster.

    Parameters
    ----------
    dir : str or os.PathLike
        The run's output directory.
    status : str, optional
        The status to report. By default ``summary["status"]`` for a run;
        ``"ok"`` for a convergence study (a directory of ``veselov verify``
        or :func:`verify`, whose summary has ``order_claimed`` and no
        ``status``: it is written only once the study has ended); and
        ``"error"`` for a directory without ``summary.json`` (a run that
        did not get to write one).
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
        if "status" in summary:
            status = summary["status"]
        elif "order_claimed" in summary:
            status = "ok"  # a convergence study, whose summary has no status
        else:
            status = "error"
    return Result(status, message, summary, tables, arrays)


def _scenario_text(scenario: Scenario) -> "tuple[str, str]":
    """``(label, TOML text)`` of a path, a TOML string or a dict (the rule
    is the module's: a ``str`` naming an existing file, or one line ending
    in ``.toml``, is a path)."""
    if isinstance(scenario, Mapping):
        return "<dict>", toml_text(scenario)
    if isinstance(scenario, str):
        one_line = "\n" not in scenario and "\r" not in scenario
        is_path = one_line and ("=" not in scenario or scenario.rstrip().endswith(".toml") or _is_file(scenario))
        if not is_path:
            return "<string>", scenario
    elif not isinstance(scenario, os.PathLike):
        raise TypeError(f"scenario: expected a path, a TOML string or a dict, got {type(scenario).__name__}")
    path = Path(scenario)
    try:
        return str(path), path.read_text(encoding="utf-8")
    except OSError as e:
        raise ScenarioError(f"{path}: {e.strerror or e}") from None


def _is_file(name: str) -> bool:
    try:
        return os.path.isfile(name)
    except (OSError, ValueError):  # a name the system cannot take (NUL, too long)
        return False


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
    where = f"override {index}: " if index is not None else ""
    try:
        document = toml_text(overrides)
    except ScenarioError as e:
        raise ScenarioError(f"{label}: {where}{e}", e.key, index) from None
    outcome, value, key = _native.merge(text, document)
    if outcome != "ok":
        raise ScenarioError(f"{label}: {where}{value}", key, index)
    return value


def _temporary_note(message: str, root: Optional[Path]) -> str:
    """``message``, saying so where it names a temporary directory that is
    removed."""
    if root is not None and str(root) in message:
        return f"{message} (in a temporary directory, since removed; out= chooses the directory)"
    return message


def _outcome(status, message, key, d: Path, text: str, keep: bool, member, root) -> Result:
    """The :class:`Result` of a run that ended as ``status`` in ``d`` (a
    kept ``out`` when ``keep``, else a temporary directory under ``root``),
    or the error it raised. An interrupted run with a checkpoint keeps its
    directory, temporary or not, and its message says how to continue. The
    scenario is written beside a checkpoint that is kept, for
    :func:`resume`."""
    prefix = "" if member is None else f"member {member}: "
    if status == "scenario":
        return ScenarioError(prefix + message, key, member)
    if status == "failure":
        return VeselovError(prefix + _temporary_note(message, None if keep else root), member)
    checkpoint = (d / "checkpoint.json").is_file()
    kept = keep or (status == "interrupted" and checkpoint)
    if kept and checkpoint:
        try:
            (d / _RUN_SCENARIO).write_text(text, encoding="utf-8")
        except OSError:
            pass  # resume then needs the scenario passed
    if status == "error" and keep:
        message = f"{message} (partial results written to {d})"
    elif status == "interrupted" and checkpoint:
        where = "a checkpoint written in" if keep else "the run's directory, with its checkpoint, is kept in"
        message = f"{message}; {where} {d}: continue with veselov.resume({str(d)!r})"
    result = read_dir(d, status, message)
    if kept:
        result.dir = d
    return result


def _run_members(
    label: str,
    jobs: list,
    out: Optional[Union[str, os.PathLike]],
    single: bool,
    force: bool = False,
    workers: Optional[int] = None,
    progress: Optional[Callable[[int, int], Any]] = None,
    resume: bool = False,
    force_large: bool = False,
) -> list:
    """Run ``jobs``, a list of ``(member index, TOML text)``, into ``out``
    (``single``: ``out`` itself, else ``out/member-<index>``), or into a
    temporary directory, without plots, removed once read (except the
    directories of interrupted runs with a checkpoint). Returns one
    :class:`Result` or :class:`VeselovError` per job, in order."""
    keep = out is not None
    if keep:
        root = Path(out)
    else:
        jobs = [(i, _override(label, t, {"output.plots": False})) for i, t in jobs]
        root = Path(tempfile.mkdtemp(prefix="veselov-"))
    dirs = [root if single and keep else root / f"member-{i:05d}" for i, _ in jobs]
    kept = set()
    try:
        ended = _native.run_many(
            label, [t for _, t in jobs], [str(d) for d in dirs], force, workers, progress, resume, force_large
        )
        outcomes = []
        for (i, text), d, (status, message, key) in zip(jobs, dirs, ended):
            outcome = _outcome(status, message, key, d, text, keep, None if single else i, root)
            if isinstance(outcome, Result) and outcome.dir is not None:
                kept.add(d)
            outcomes.append(outcome)
        return outcomes
    finally:
        if not keep:
            _remove_temporary(root, kept)


def _remove_temporary(root: Path, kept: set) -> None:
    """Remove the temporary directory ``root``, but for the member
    directories in ``kept``."""
    if not kept:
        shutil.rmtree(root, ignore_errors=True)
        return
    try:
        children = list(root.iterdir())
    except OSError:
        return
    for child in children:
        if child not in kept:
            shutil.rmtree(child, ignore_errors=True)


def _one(outcomes: list) -> Result:
    """The result of a single run, or its error raised."""
    outcome = outcomes[0]
    if isinstance(outcome, BaseException):
        raise outcome
    return outcome


def run(
    scenario: Scenario,
    out: Optional[Union[str, os.PathLike]] = None,
    force: bool = False,
    force_large: bool = False,
) -> Result:
    """Run a scenario and return its outputs as NumPy arrays.

    The scenario is parsed, validated and run by the command's library, as
    ``veselov run`` does, with the GIL released while it integrates. With
    ``out`` the command's files (CSV/NPY, ``summary.json``,
    ``checkpoint.json``, plots) stay in that directory, with the scenario
    as run in ``run-scenario.toml`` (for :func:`resume`); without it, the
    run writes to a temporary directory, without plots, which is removed
    once read. A run that fails mid-way or is interrupted (Ctrl-C) raises
    nothing: it returns the rows computed so far with ``status`` ``"error"``
    or ``"interrupted"``. An interrupted run's directory, with its
    checkpoint, is kept even when it is temporary; its ``message`` says
    where and how to continue (``veselov.resume('<dir>')``).

    Parameters
    ----------
    scenario : str, os.PathLike or Mapping[str, Any]
        A path to a TOML file; TOML text; or a mapping with the command's
        schema, nested tables or dotted keys (``{"method.dt": 0.01}``),
        written by :func:`toml_text`. A ``str`` is a path when it names an
        existing file or is one line ending in ``.toml``; otherwise it is
        TOML text if it contains a newline or ``=``, a path if not.
    out : str or os.PathLike, optional
        The output directory to keep the files in (created if needed).
        The scenario's ``output.dir`` is not used.
    force : bool, optional
        Run in a non-empty ``out``, first removing the outputs an earlier
        run wrote there (other files are kept). Default ``False``.
    force_large : bool, optional
        Run beyond the preflight limits (more than 1e9 steps or 10 GiB of
        output), which are otherwise refused with a :class:`ScenarioError`
        naming the key. Default ``False``.

    Returns
    -------
    Result
        ``status``, ``summary``, ``message``; ``tables`` of ``float64``
        columns, each of shape ``(n_rows,)``; ``arrays`` of ``float64`` in
        their files' shapes (``trajectory``: ``(n_rows, n_columns)``,
        ``snapshots``: ``(n_snapshots, nodes)``, ...; :class:`Result` lists
        them by kind of run); ``dir`` is ``Path(out)``, the kept temporary
        directory of an interrupted run, or ``None``.

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
    resume : Continue an interrupted (or extend a finished) run.
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
    return _one(_run_members(label, [(0, text)], out, True, force=force, force_large=force_large))


def _recorded_scenario(d: Path) -> "tuple[str, str]":
    """``(label, text)`` of the scenario of the run in ``d``: the one
    :func:`run` recorded there, else the file its summary names."""
    recorded = d / _RUN_SCENARIO
    if recorded.is_file():
        return str(recorded), recorded.read_text(encoding="utf-8")
    try:
        named = json.loads((d / "summary.json").read_text(encoding="utf-8")).get("scenario")
    except (OSError, ValueError, AttributeError):
        named = None
    if isinstance(named, str) and _is_file(named):
        return named, Path(named).read_text(encoding="utf-8")
    raise VeselovError(
        f"{d}: no scenario recorded for this run (no {_RUN_SCENARIO}, and its summary names no scenario file "
        "that exists here); pass scenario=, the scenario it was started with"
    )


def resume(
    dir: Union[str, os.PathLike],
    scenario: Optional[Scenario] = None,
    overrides: Optional[Mapping[str, Any]] = None,
    force_large: bool = False,
) -> Result:
    """Continue a run from the checkpoint in its directory, as ``veselov run --resume`` does.

    The run in ``dir`` (interrupted by Ctrl-C, or finished and to be
    extended by a later ``time.t_end``) continues from its
    ``checkpoint.json``, its files extended in place, with the GIL
    released; the result is bit for bit that of the run made without
    stopping. Any kind of run can be resumed.

    Parameters
    ----------
    dir : str or os.PathLike
        The run's output directory: the ``out`` of :func:`run`, an
        ensemble member's ``out/member-<i>``, the kept temporary
        directory an interrupted run's ``message`` and ``dir`` name, or
        the directory of ``veselov run``.
    scenario : str, os.PathLike or Mapping[str, Any], optional
        The scenario the run was started with, as :func:`run` takes it.
        Default: the one recorded in ``dir/run-scenario.toml`` by
        :func:`run` and :func:`ensemble`; for a run of the command line,
        the scenario file its ``summary.json`` names, if that path exists
        from here.
    overrides : Mapping[str, Any], optional
        Keys to replace in the scenario (dotted or nested, as
        :func:`ensemble` takes them), e.g. ``{"time.t_end": 200.0}`` to
        extend the run. Only ``time.t_end``, ``time.steps``,
        ``output.checkpoint_every``, ``output.dir`` and ``output.plots``
        may differ from the run's own scenario; a run whose step is
        ``t_end / n`` (fixed-step mechanics with ``t_end``, the beam, the
        rod) keeps its step, so ``t_end`` grows by whole steps.
    force_large : bool, optional
        Run beyond the preflight limits, as :func:`run`. Default ``False``.

    Returns
    -------
    Result
        The whole run's outputs (the rows before the checkpoint and
        after), as :func:`run` returns them: ``tables`` of ``float64``
        columns of shape ``(n_rows,)``, ``arrays`` in their files' shapes;
        ``status`` ``"ok"``, ``"error"`` or ``"interrupted"`` (Ctrl-C again:
        resume again); ``dir`` is ``Path(dir)``.

    Raises
    ------
    ScenarioError
        If the scenario is invalid, or differs from the run's in a key that
        may not change (``e.key`` names the first such key), or asks for a
        shorter run than the checkpoint's.
    VeselovError
        If ``dir`` holds no readable checkpoint, or no scenario is recorded
        there and none is given.
    TypeError
        If ``scenario`` is none of a path, a ``str`` or a mapping.

    See Also
    --------
    run : The run; an interrupted one says how to resume it.

    Examples
    --------
    >>> r = veselov.run("examples/kepler.toml", out="out/kepler")   # Ctrl-C
    >>> r.status
    'interrupted'
    >>> r = veselov.resume("out/kepler")
    >>> r.status
    'ok'
    >>> longer = veselov.resume("out/kepler", overrides={"time.t_end": 2 * 314.1592653589793})
    >>> longer["t"][-1] == 2 * 314.1592653589793
    True
    """
    d = Path(dir)
    if not d.is_dir():
        raise VeselovError(f"{d}: not a directory (resume needs the directory of a run with a checkpoint)")
    label, text = _scenario_text(scenario) if scenario is not None else _recorded_scenario(d)
    if overrides:
        text = _override(label, text, overrides)
    return _one(_run_members(label, [(0, text)], d, True, resume=True, force_large=force_large))


def _print_progress(done: int, total: int) -> None:
    sys.stderr.write(f"\rveselov.ensemble: {done}/{total} runs")
    if done == total:
        sys.stderr.write("\n")
    sys.stderr.flush()


_ON_ERROR = ("raise", "keep")


def _check_on_error(on_error: str) -> None:
    if on_error not in _ON_ERROR:
        raise ValueError(f"on_error: expected one of {', '.join(map(repr, _ON_ERROR))}, got {on_error!r}")


def _settle(outcomes: list, on_error: str) -> list:
    """``outcomes`` (a :class:`Result` or :class:`VeselovError` per member)
    as ``on_error`` asks: the list, or the first member's error raised with
    the list as its ``results``."""
    if on_error == "raise":
        failed = next((o for o in outcomes if isinstance(o, VeselovError)), None)
        if failed is not None:
            failed.results = outcomes
            raise failed
    return outcomes


def _ensemble(
    label: str,
    text: str,
    overrides: Sequence[Mapping[str, Any]],
    workers: Optional[int] = None,
    out: Optional[Union[str, os.PathLike]] = None,
    progress: Optional[Callable[[int, int], Any]] = None,
    force: bool = False,
    on_error: str = "raise",
    force_large: bool = False,
    first: int = 0,
) -> list:
    """:func:`ensemble` of the scenario ``text`` (attributed to ``label``),
    its members numbered from ``first`` (a batch of a larger ensemble), an
    override that cannot be merged raised at once with ``on_error="raise"``
    and the members' errors left in the list."""
    outcomes: list = [None] * len(overrides)
    jobs = []
    for k, o in enumerate(overrides):
        try:
            jobs.append((first + k, _override(label, text, o, first + k)))
        except ScenarioError as e:
            if on_error == "raise":
                raise
            outcomes[k] = e
    skipped = len(overrides) - len(jobs)
    if progress is not None and skipped:
        report = progress
        progress = lambda done, total: report(done + skipped, total + skipped)  # noqa: E731
    if jobs:
        ran = _run_members(label, jobs, out, False, force, workers, progress, False, force_large)
        for (i, _), outcome in zip(jobs, ran):
            outcomes[i - first] = outcome
    return outcomes


def ensemble(
    scenario: Scenario,
    overrides: Sequence[Mapping[str, Any]],
    workers: Optional[int] = None,
    out: Optional[Union[str, os.PathLike]] = None,
    progress: Union[bool, Callable[[int, int], Any]] = False,
    force: bool = False,
    on_error: str = "raise",
    force_large: bool = False,
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
        Default: temporary directories, without plots, removed once read
        (but for those of interrupted members, kept with their checkpoint
        for :func:`resume`).
    progress : bool or callable, optional
        ``True`` prints ``veselov.ensemble: <done>/<total> runs`` to
        standard error; a callable is called as ``progress(done, total)``
        (two ``int``) on the calling thread as members end, and once at the
        end. Default ``False``: no report.
    force : bool, optional
        Run in non-empty ``out/member-<i>`` directories, first removing the
        outputs an earlier run wrote there. Default ``False``.
    on_error : {"raise", "keep"}, optional
        What to do when members cannot run: an override that cannot be
        merged, an invalid merged scenario, an output directory that cannot
        be used. ``"raise"`` (default): raise the error of the first such
        member (lowest index) once every member has ended, with
        ``e.results`` holding every member's outcome, so the members that
        ran are not lost (an override that cannot be merged is raised at
        once, before any run, with ``e.results`` ``None``). ``"keep"``:
        raise nothing and return each such member's error in its place.
    force_large : bool, optional
        Run beyond the preflight limits, as :func:`run`. Default ``False``.

    Returns
    -------
    list of Result
        ``len(overrides)`` results, in the order of ``overrides``, each as
        :func:`run` returns it (``float64`` arrays in their files' shapes;
        ``dir`` is ``out/member-<i>``, a kept temporary directory, or
        ``None``); ``[]`` for no overrides. With ``on_error="keep"``, a
        member that could not run is its :class:`ScenarioError` or
        :class:`VeselovError` instead (``e.member == i``). A member that
        failed mid-way or was interrupted is a :class:`Result` whose
        ``status`` says so, whatever ``on_error``.

    Raises
    ------
    ScenarioError
        With ``on_error="raise"``: if an override cannot be merged
        (``<scenario>: override <i>: ...``, before any run), or a member's
        merged scenario is invalid (``member <i>: ...``, once every member
        has ended). ``e.key`` names the key, ``e.member`` the member,
        ``e.results`` the members' outcomes.
    VeselovError
        With ``on_error="raise"``: if a member cannot start or write its
        files (e.g. ``out/member-<i>`` is not empty without ``force``),
        with ``e.member`` and ``e.results`` as above.
    ValueError
        If ``workers`` is 0 or ``on_error`` is neither ``"raise"`` nor
        ``"keep"``.
    TypeError
        If ``scenario`` is none of a path, a ``str`` or a mapping.

    See Also
    --------
    run : One run.
    resume : Continue an interrupted member from its directory.
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
    >>> runs = veselov.ensemble("examples/kepler.toml", [{}, {"method.dt": -1.0}], on_error="keep")
    >>> [type(r).__name__ for r in runs], runs[1].member
    (['Result', 'ScenarioError'], 1)
    """
    _check_on_error(on_error)
    label, text = _scenario_text(scenario)
    report = _print_progress if progress is True else (progress or None)
    outcomes = _ensemble(label, text, list(overrides), workers, out, report, force, on_error, force_large)
    return _settle(outcomes, on_error)


def _steps(dt: Any) -> list:
    """The steps of :func:`verify` as a list of float."""
    expected = "dt: expected a number or a sequence of numbers (e.g. [0.1, 0.05, 0.025])"
    if isinstance(dt, (str, bytes)):
        raise TypeError(f"{expected}, got {type(dt).__name__}")
    if np.ndim(dt) == 0:
        items = [dt.item() if isinstance(dt, np.ndarray) else dt]
    else:
        try:
            items = list(dt)
        except TypeError:
            raise TypeError(f"{expected}, got {type(dt).__name__}") from None
    steps = []
    for i, h in enumerate(items):
        if isinstance(h, (bool, np.bool_)) or not isinstance(h, numbers.Real):
            raise TypeError(f"{expected}; dt[{i}] is {type(h).__name__}")
        steps.append(float(h))
    if not steps:
        raise ScenarioError("dt: expected at least one step", "dt")
    return steps


def verify(
    scenario: Scenario,
    dt: Optional[Union[float, Iterable[float]]] = None,
    out: Optional[Union[str, os.PathLike]] = None,
    force: bool = False,
    *,
    refine: Optional[int] = None,
    nodes: Optional[Iterable[int]] = None,
    observable: Optional[str] = None,
) -> Result:
    """Convergence study of a scenario's method, as ``veselov verify`` does.

    Mechanics and rigid bodies: runs the scenario's model and method once
    per step in ``dt`` and measures each run's error at the final time
    against a reference (the exact solution where the model has one,
    otherwise a fine run: see ``verify_reference`` in :func:`models`),
    then fits the order.

    Lattice fields, the beam and the rod: runs the scenario refined in
    space and time together (``refine`` or ``nodes``), each run as
    :func:`run` runs it, and measures the ``observable`` of each run
    against the next finer one (a Richardson estimate of its error), then
    fits the order in the space step.

    Parameters
    ----------
    scenario : str, os.PathLike or Mapping[str, Any]
        The scenario, as :func:`run` takes it.
    dt : float or iterable of float, optional
        Mechanics and rigid bodies: the steps to try, e.g. ``[0.1, 0.05,
        0.025]`` (a list, tuple, NumPy array, ...), or one step (a
        number). A fixed-step method uses the nearest step that divides
        the run's time span in a whole number of steps.
    out : str or os.PathLike, optional
        The directory to keep ``convergence.csv``, ``convergence.svg`` and
        ``summary.json`` in (and the runs of a refinement, in
        ``level-<k>``). Default: a temporary directory, removed.
    force : bool, optional
        Write into a non-empty ``out``. Default ``False``.
    refine : int, optional
        Lattice fields, beam, rod: the scenario's nodes and ``refine``
        refinements by a factor 2 (``--refine``; 2 to 12).
    nodes : iterable of int, optional
        Lattice fields, beam, rod: the node counts of the runs instead
        (``--nodes``; three at least, increasing).
    observable : str, optional
        Lattice fields, beam, rod: ``"field"``, ``"energy"``,
        ``"tip-displacement"`` or ``"frequency"`` (``--observable``;
        default: the field for lattices, the first frequency of a free–free
        structure, else the tip displacement).

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
        If the scenario is invalid; or if ``dt`` is empty, or a step is not
        a finite number > 0 or asks for too many steps, with
        ``e.key == "dt"``; or if the refinement options are missing or
        wrong for the kind, with ``e.key`` ``"refine"``, ``"nodes"``,
        ``"observable"`` or ``"dt"``.
    VeselovError
        If ``out`` cannot be written.
    TypeError
        If ``scenario`` is none of a path, a ``str`` or a mapping; or if
        ``dt`` is neither a number nor an iterable of numbers (a ``str``
        included).
    KeyboardInterrupt
        On Ctrl-C, once the study has stopped (see Notes).

    See Also
    --------
    run : One run of the scenario.

    Notes
    -----
    Ctrl-C stops the study before its next run (the run in progress, one
    per step, is finished first) and raises ``KeyboardInterrupt``; no
    outputs are written.

    Examples
    --------
    >>> study = veselov.verify("examples/harmonic.toml", dt=[0.1, 0.05, 0.025])
    >>> study["error"].shape, study.summary["order_claimed"]
    ((3,), 2)
    """
    steps = [] if dt is None else _steps(dt)
    counts = [] if nodes is None else [int(n) for n in nodes]
    label, text = _scenario_text(scenario)
    keep = out is not None
    root = Path(out) if keep else Path(tempfile.mkdtemp(prefix="veselov-"))
    try:
        status, message, key = _native.verify(
            label, text, steps, str(root), force, refine, counts, observable
        )
        if status == "scenario":
            raise ScenarioError(message, key)
        if status == "failure":
            raise VeselovError(_temporary_note(message, None if keep else root))
        result = read_dir(root, status, message)
        if keep:
            result.dir = root
        return result
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
