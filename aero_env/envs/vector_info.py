"""Per-episode infos as one vector info, and the runs of a reduced-model batch as per-design run dicts.

:func:`stack_infos` gives what Gymnasium's ``VectorEnv._add_info`` builds when every sub-env's info is
added in turn (``SyncVectorEnv`` does that), for infos that share their keys, as here: each key an array
with one entry per sub-env (the dtype rule is Gymnasium's: ``int``, ``float``, ``bool`` and numpy
scalars give an array of that type, dicts recurse, anything else an object array), beside a ``_key``
mask. It builds each array once instead of assigning N entries one at a time.
"""

from __future__ import annotations

from typing import Sequence

import numpy as np

__all__ = ["stack_infos", "stack_values", "stack_columns", "scatter_infos", "batch_runs", "batch_infos"]

# Gymnasium's _add_info gives a typed array to exactly these types (and numpy scalars); others go in objects.
_TYPED_SCALARS = (int, float, bool)


def stack_values(values: Sequence) -> np.ndarray:
    """One info key's values, one per sub-env, as ``VectorEnv._add_info`` stores them."""
    first = values[0]
    if type(first) in _TYPED_SCALARS or issubclass(type(first), np.number):
        out = np.zeros(len(values), dtype=type(first))
        out[:] = values  # as _add_info's item assignments: None becomes NaN in a float array
        return out
    if isinstance(first, np.ndarray):
        return np.stack(values).astype(first.dtype, copy=False)
    out = np.full(len(values), None, dtype=object)
    for i, v in enumerate(values):  # item by item: a list value must stay one entry, not a new axis
        out[i] = v
    return out


def stack_infos(infos: Sequence[dict]) -> dict:
    """The vector info of per-sub-env ``infos`` that share their keys, every ``_key`` mask all True."""
    return stack_columns(_by_key(infos), len(infos))


def _by_key(infos: Sequence[dict]) -> dict:
    """Infos that share their keys, turned by key: each key's values one per info (a dict of such, nested)."""
    return {key: _by_key([info[key] for info in infos]) if isinstance(first, dict) else [info[key] for info in infos]
            for key, first in infos[0].items()}


def stack_columns(columns: dict, n: int) -> dict:
    """:func:`stack_infos` of ``n`` sub-envs' infos given by key, each key's values one per sub-env (a list, or a
    dict of such for a dict-valued key), without a dict per sub-env: the same arrays and masks."""
    out: dict = {}
    for key, values in columns.items():
        out[key] = stack_columns(values, n) if isinstance(values, dict) else stack_values(values)
        out[f"_{key}"] = np.ones(n, dtype=np.bool_)
    return out


def scatter_infos(parts: Sequence[tuple[np.ndarray, dict]], n: int) -> dict:
    """One vector info of ``n`` sub-envs from ``parts``, each ``(rows, info)``: the vector info of sub-envs ``rows``
    (ascending; one entry per row, every mask True), the parts' rows disjoint and the parts in the order of their
    first row. What ``VectorEnv._add_info`` builds when each sub-env's info is added in sub-env order (a NEXT_STEP
    step that resets some sub-envs and runs the others): keys in the order first met, each array made on the first
    part that has the key (of that part's dtype; zeros, or None in an object array, where no part sets it) and its
    ``_key`` mask True on the rows that set it."""
    out: dict = {}
    for rows, info in parts:
        _scatter(out, info, np.asarray(rows), n)
    return out


def _scatter(out: dict, info: dict, rows: np.ndarray, n: int) -> None:
    for key, value in info.items():
        if key.startswith("_") and key[1:] in info:
            continue  # a mask: set beside its key
        if isinstance(value, dict):
            array = out.get(key, {})
            _scatter(array, value, rows, n)
        else:
            array = out.get(key)
            if array is None:
                array = (np.full(n, None, dtype=object) if value.dtype == object
                         else np.zeros((n, *value.shape[1:]), dtype=value.dtype))
            array[rows] = value
        mask = out.get(f"_{key}", np.zeros(n, dtype=np.bool_))
        mask[rows] = True
        out[key], out[f"_{key}"] = array, mask


def batch_infos(batch, fidelity: str, design: dict, context: dict, as_built: dict, n: int) -> dict:
    """The vector info of a reduced step's finished episodes, ``stack_infos`` of each one's
    :func:`~aero_env.envs.aerial_acrobat.episode_info` of its :func:`batch_runs` entry, built from the batch's
    arrays and the episodes' field arrays (``design``, ``context``, ``as_built``: key -> n values) with no dict
    per episode: the same keys, order, dtypes and values (``tests/test_vector_env.py``)."""
    # batch.miss(i) for each run: None where the run completed or has no finite miss (the batch holds NaN there)
    miss = [None if m != m else m for m in batch.miss_distance.tolist()]
    columns = dict(traversals=batch.traversals.tolist(), frames=[int(batch.frames)] * n,
                   outcome=[str(o) for o in batch.outcome.tolist()], reason=[batch.reason(i) for i in range(n)],
                   sim_time=batch.sim_time.tolist(), miss_distance=miss, fidelity=[fidelity] * n,
                   design={k: v.tolist() for k, v in design.items()}, context=context,
                   as_built={k: v.tolist() for k, v in as_built.items()})
    return stack_columns(columns, n)


def batch_runs(batch, fidelity: str) -> list[dict]:
    """Each design's run from a :class:`aero_env.models.reduced.BatchResult`, as the fields of
    ``SimResult.to_json_dict()`` that a batch keeps, in that order: ``traversals``, ``frames``, ``outcome``,
    ``reason``, ``sim_time``, ``miss_distance`` (None where the run completed or has none) and ``fidelity``.
    A batch keeps no per-swing records, energy bookkeeping or health (the single env's ``swings``,
    ``energy``, ``health``) and no wall time."""
    traversals = batch.traversals.tolist()
    outcomes = batch.outcome.tolist()
    sim_times = batch.sim_time.tolist()
    runs = []
    for i in range(len(batch)):
        runs.append(dict(traversals=int(traversals[i]), frames=int(batch.frames), outcome=str(outcomes[i]),
                         reason=batch.reason(i), sim_time=float(sim_times[i]), miss_distance=batch.miss(i),
                         fidelity=fidelity))
    return runs
