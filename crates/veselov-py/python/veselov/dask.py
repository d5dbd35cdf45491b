"""Ensembles on a ``dask.distributed`` cluster (Dask is optional: it is
imported only by the caller, who passes the client).

Each task runs one batch of members in-process on a worker through
:func:`veselov.ensemble` (on that worker's threads), and the results are
gathered in input order, equal to those of a local ensemble.
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
    """Run ``scenario`` once per dict of ``overrides`` on the cluster of
    ``client`` (a ``dask.distributed.Client``), ``batch`` members per task,
    each task using ``workers_per_task`` threads on its worker (default 1:
    Dask's own worker threads give the parallelism). Results in input order.
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
