"""Ensembles on a ``dask.distributed`` cluster.

Dask is optional: this module does not import it; the caller creates the
``dask.distributed.Client`` and passes it to :func:`ensemble`. Each task
runs one batch of members in-process on a worker through
:func:`veselov.ensemble` (on that worker's threads), and the results are
gathered in input order, equal to those of a local ensemble.
``help(veselov.dask.ensemble)`` shows its parameters.
"""

from __future__ import annotations

from typing import Any, Mapping, Optional, Sequence

from . import Scenario, _scenario_text, ensemble as _local_ensemble

__all__ = ["ensemble"]


def _batch(text: str, overrides: list, workers: Optional[int]) -> list:
    return _local_ensemble(text, overrides, workers=workers)


def ensemble(
    client: Any,
    scenario: Scenario,
    overrides: Sequence[Mapping[str, Any]],
    batch: int = 64,
    workers_per_task: Optional[int] = 1,
) -> list:
    """Run a scenario once per set of overrides on a Dask cluster.

    The scenario is read on the client and sent to the workers as TOML
    text (so the workers need the ``veselov`` package, not the scenario
    file). The members are cut into batches of ``batch``; each batch is
    one task, run on its worker by :func:`veselov.ensemble`. The results
    equal those of ``veselov.ensemble(scenario, overrides)``, bit for bit.

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

    Returns
    -------
    list of Result
        ``len(overrides)`` results in the order of ``overrides``, each as
        :func:`veselov.run` returns it (``float64`` arrays in their files'
        shapes; see :class:`veselov.Result`), ``dir`` ``None``.

    Raises
    ------
    ValueError
        If ``batch`` is less than 1.
    veselov.ScenarioError
        If the scenario is invalid or cannot be read (on the client), or a
        member's overrides make it invalid (raised on the worker, re-raised
        by ``client.gather``; ``member <i>`` then counts within the batch).
    veselov.VeselovError
        If a member cannot run or write its files.
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
    _, text = _scenario_text(scenario)
    members = [dict(o) for o in overrides]
    batches = [members[i : i + batch] for i in range(0, len(members), batch)]
    futures = client.map(_batch, [text] * len(batches), batches, [workers_per_task] * len(batches), pure=False)
    results = []
    for part in client.gather(futures):
        results.extend(part)
    return results
