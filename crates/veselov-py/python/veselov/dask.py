"""Ensembles on a ``dask.distributed`` cluster.

Dask is optional: this module does not import it; the caller creates the
``dask.distributed.Client`` and passes it to :func:`ensemble`. Each task
runs one batch of members in-process on a worker through the package's
ensemble runner (on that worker's threads), and the results are gathered
in input order, equal to those of a local :func:`veselov.ensemble`. A
member that cannot run is reported with its index in the whole ensemble
and its scenario file, as locally. ``help(veselov.dask.ensemble)`` shows
its parameters.
"""

from __future__ import annotations

from typing import Any, Mapping, Optional, Sequence

from . import Scenario, _check_on_error, _ensemble, _scenario_text, _settle

__all__ = ["ensemble"]


def _batch(label: str, text: str, overrides: list, workers: Optional[int], first: int, force_large: bool) -> list:
    # Members that cannot run come back as their errors, so that a batch
    # returns every member's outcome; the client applies `on_error`.
    return _ensemble(label, text, overrides, workers, on_error="keep", force_large=force_large, first=first)


def ensemble(
    client: Any,
    scenario: Scenario,
    overrides: Sequence[Mapping[str, Any]],
    batch: int = 64,
    workers_per_task: Optional[int] = 1,
    on_error: str = "raise",
    force_large: bool = False,
) -> list:
    """Run a scenario once per set of overrides on a Dask cluster.

    The scenario is read on the client and sent to the workers as TOML
    text, with its file name for messages (so the workers need the
    ``veselov`` package, not the scenario file). The members are cut into
    batches of ``batch``; each batch is one task, run on its worker as
    :func:`veselov.ensemble` runs members. The results equal those of
    ``veselov.ensemble(scenario, overrides)``, bit for bit, and so do the
    errors: a member that cannot run is named by its index in the whole
    ensemble (``member <i>:``, ``e.member``), with the scenario's path.

    Parameters
    ----------
    client : dask.distributed.Client
        The client of the cluster to run on.
    scenario : str, os.PathLike or Mapping[str, Any]
        The base scenario, as :func:`veselov.run` takes it.
    overrides : Sequence[Mapping[str, Any]]
        One mapping per member (dotted or nested keys), as
        :func:`veselov.ensemble` takes them.
    batch : int, optional
        Members per task, at least 1. Default 64.
    workers_per_task : int or None, optional
        Threads each task uses on its worker; ``None`` for all the worker
        machine's cores. Default 1: Dask's own worker threads give the
        parallelism.
    on_error : {"raise", "keep"}, optional
        As for :func:`veselov.ensemble`, applied once every batch has
        ended: ``"raise"`` (default) raises the error of the first member
        that could not run, with ``e.results`` holding every member's
        outcome (a :class:`veselov.Result` or the member's error);
        ``"keep"`` returns the errors in place of those members' results.
    force_large : bool, optional
        Run beyond the preflight limits, as :func:`veselov.run`. Default
        ``False``.

    Returns
    -------
    list of Result
        ``len(overrides)`` results in the order of ``overrides``, each as
        :func:`veselov.run` returns it (``float64`` arrays in their files'
        shapes; see :class:`veselov.Result`), ``dir`` ``None``. With
        ``on_error="keep"``, a member that could not run is its
        :class:`veselov.ScenarioError` or :class:`veselov.VeselovError`.

    Raises
    ------
    ValueError
        If ``batch`` is less than 1, or ``on_error`` is neither ``"raise"``
        nor ``"keep"``.
    veselov.ScenarioError
        If the scenario is invalid or cannot be read (on the client); or,
        with ``on_error="raise"``, a member's overrides cannot be merged or
        make it invalid (``e.member``, ``e.key``, ``e.results``).
    veselov.VeselovError
        With ``on_error="raise"``, if a member cannot run or write its
        files (``e.member``, ``e.results``).
    TypeError
        If ``scenario`` is none of a path, a ``str`` or a mapping.

    See Also
    --------
    veselov.ensemble : The same on this machine's threads.

    Examples
    --------
    >>> from dask.distributed import Client
    >>> import veselov.dask
    >>> client = Client("scheduler-address:8786")
    >>> runs = veselov.dask.ensemble(
    ...     client, "examples/van_der_pol.toml",
    ...     [{"initial.q": [1.0, 0.0]}, {"initial.q": [2.0, 0.0]}], batch=64)
    >>> [r.status for r in runs]
    ['ok', 'ok']
    """
    if batch < 1:
        raise ValueError(f"batch: expected at least 1, got {batch}")
    _check_on_error(on_error)
    label, text = _scenario_text(scenario)
    members = [dict(o) for o in overrides]
    starts = list(range(0, len(members), batch))
    futures = client.map(
        _batch,
        [label] * len(starts),
        [text] * len(starts),
        [members[i : i + batch] for i in starts],
        [workers_per_task] * len(starts),
        starts,
        [force_large] * len(starts),
        pure=False,
    )
    results = []
    for part in client.gather(futures):
        results.extend(part)
    return _settle(results, on_error)
