"""Veselov from Python: the ``veselov`` command's scenario runs as NumPy arrays.

Every run goes through the command's own library (the same parsing,
validation, messages, driver and writers as ``veselov run``) into an output
directory; the files are then read back, so the arrays equal the command's
files bit for bit.

>>> import veselov
>>> r = veselov.run("examples/kepler.toml")
>>> r.status, r["energy"][-1]

``run``, ``ensemble``, ``verify``, ``models``, ``methods``; ``veselov.dask``
maps ensembles onto a ``dask.distributed`` cluster.
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
    """A run could not start or write its files (output directory, I/O)."""


class ScenarioError(VeselovError, ValueError):
    """A bad scenario; ``key`` is the dotted key at fault (``None`` when the
    message names no key, e.g. a TOML syntax error outside any assignment)."""

    def __init__(self, message: str, key: Optional[str] = None):
        super().__init__(message)
        self.key = key


class Result:
    """The outputs of one run.

    * ``status``: ``"ok"``, ``"error"`` (the run failed mid-way: the arrays
      hold the rows computed before the failure) or ``"interrupted"``;
    * ``summary``: ``summary.json`` as a dict; ``message``: the error text;
    * ``tables``: ``{file stem: {column: array}}`` for every CSV file;
    * ``arrays``: ``{file stem: array}`` for every NPY file;
    * ``r[name]``: a column of ``trajectory.csv`` (or of the only table),
      ``"stem.column"`` for another table, or an NPY file's stem;
    * ``dir``: the output directory when it was kept (``out=``).
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
        """The names ``r[name]`` accepts."""
        main = self._main()
        names = list(main)
        for stem, table in self.tables.items():
            if table is not main:
                names.extend(f"{stem}.{c}" for c in table)
        names.extend(s for s in self.arrays if s not in names)
        return names

    def __getitem__(self, name: str) -> np.ndarray:
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
    """The outputs of a run in ``dir`` (written by ``veselov run`` or ``veselov.run``)."""
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
    """The TOML document of a scenario dict (dotted keys allowed)."""
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
    """Run a scenario (a path, TOML text or a dict with the command's schema).

    With ``out`` the command's files (CSV/NPY, ``summary.json``, plots) stay
    in that directory (``force=True`` runs in a non-empty one, first
    removing the outputs an earlier run wrote there and keeping other
    files); without
    it, the run writes to a temporary directory, without plots, which is
    removed once read. A bad scenario raises :class:`ScenarioError`. Ctrl-C
    ends the run with ``status == "interrupted"`` and the rows computed so far.
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
    """Run ``scenario`` once per dict of ``overrides`` (keys dotted, e.g.
    ``{"initial.q": [1, 0], "model.params.epsilon": 0.3}``) in parallel on
    ``workers`` threads (default: all cores), the GIL released; the results
    come in input order. ``progress=True`` prints a count to stderr, a
    callable is called as ``progress(done, total)``. With ``out``, member
    ``i`` keeps its files in ``out/member-<i>``.
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
    """``veselov verify``: the convergence study of the scenario's method at
    the steps ``dt``; ``r.tables["convergence"]`` and ``r.summary`` (with the
    fitted order)."""
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
    """The built-in models with ``params`` (as ``veselov models`` lists them
    first); the beam and the rod are in :func:`structures`."""
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
    """The structural models, the beam and the Cosserat rod, with their tables
    of keys and their example scenarios (as ``veselov models`` lists them
    last)."""
    return [
        {"name": n, "summary": s, "keys": k, "examples": e}
        for n, s, k, e in _native.structures()
    ]


def methods() -> list:
    """The methods (as ``veselov methods`` lists them)."""
    return [{"name": n, "keys": k, "properties": p} for n, k, p in _native.methods()]
