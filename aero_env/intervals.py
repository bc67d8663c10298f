"""How far a share measured on a sample can be trusted: k of n, with its 95 % interval.

A robustness study's share of builds that complete the row, and a benchmark's agreement with the
reference, are counts of k in n. On a few dozen designs one design moves an agreement by a point or
more, so a target of 99 % cannot be read off a sample of 60 (59 of 60 is 98.3 %, and any share
between 91 % and 99.7 % would give that count often). Each is printed with its Wilson score
interval: the shares p for which the count seen is within 1.96 standard errors of n·p. It stays
inside [0, 1] and keeps its coverage at shares near 1, where the normal approximation
(``p ± 1.96·sqrt(p(1-p)/n)``) gives a zero-width interval at 100 %.

A benchmark over training seeds (``benchmarks/rl_vs_tuning.py``) plays every seed of a method on the same
hold-out contexts: its outcomes are a matrix, seeds x contexts, with two sources of chance, which seeds training
drew and which contexts the hold-out set drew. Its share is the plain mean of that matrix, and
:func:`seeds_then_contexts` gives its 95 % interval by a two-level bootstrap: the seeds are drawn again with
replacement, then the contexts, and the drawn seeds play the drawn contexts. Because every seed played the same
contexts, one draw of contexts serves all the seeds of a resample (a context hard for one seed is hard for all:
drawn apart for each seed it would count as independent ones, and the interval would narrow by up to sqrt(seeds)
where context difficulty dominates; ``contexts="per seed"`` gives that interval, for comparison).
:func:`difference_interval` gives the same for the difference between two methods, paired on the contexts (both
played them) and not on the seeds (one method's seed 3 has nothing to do with another's).

:func:`iqm_interval` is rliable's interquartile mean with its stratified-bootstrap interval, over runs: the
benchmark gives it over the per-seed shares, a typical training run's share with the best and worst quarter of
the seeds set aside. rliable is in the ``bench`` and ``test`` extras only, so it is imported there, when asked.
"""

from __future__ import annotations

import math
import warnings

import numpy as np

Z95 = 1.959963984540054  # the standard normal's 97.5th percentile


def wilson_interval(k: int, n: int, z: float = Z95) -> tuple[float, float]:
    """The Wilson score interval of a share of ``k`` successes in ``n`` trials (95 % by default)."""
    if not 0 <= k <= n or n < 1:
        raise ValueError(f"wilson_interval: k = {k}, n = {n}: need 0 <= k <= n and n >= 1")
    p, z2 = k / n, z * z
    centre = (p + z2 / (2 * n)) / (1 + z2 / n)
    half = z * math.sqrt(p * (1 - p) / n + z2 / (4 * n * n)) / (1 + z2 / n)
    # at k = 0 or k = n the bound is the share itself: round-off must not put it a hair inside
    return (0.0 if k == 0 else max(0.0, centre - half)), (1.0 if k == n else min(1.0, centre + half))


def interval_text(bounds) -> str:
    """'92.1-97.1': an interval (shares) in per cent, for a table's column; '-' for None."""
    return "-" if bounds is None else f"{100 * bounds[0]:.1f}-{100 * bounds[1]:.1f}"


BOOTSTRAP_REPS = 20_000  # bootstrap resamples for a benchmark's intervals


def iqm_interval(shares: np.ndarray, seed: int = 0, reps: int = BOOTSTRAP_REPS) -> tuple[float, list[float]]:
    """IQM and 95 % stratified-bootstrap interval (rliable) of ``shares`` (runs x tasks; the benchmark gives one
    column, each training seed's share). The IQM is the mean of the middle half of all the values (scipy's
    ``trim_mean(x, 0.25)`` over the flattened array)."""
    from rliable import library as rly, metrics

    scores = {"m": np.asarray(shares, dtype=np.float64)}
    # rliable 1.2 resamples with numpy's global generator whatever random_state says (np.random.choice in
    # StratifiedBootstrap.update_indices), so the interval is made reproducible by seeding that, then restoring it
    kept = np.random.get_state()
    np.random.seed(seed)
    try:
        with warnings.catch_warnings():  # arch 7 warns that the random_state= rliable passes will go
            warnings.filterwarnings("ignore", "random_state is deprecated", FutureWarning)
            point, ci = rly.get_interval_estimates(scores, lambda x: np.array([metrics.aggregate_iqm(x)]),
                                                   reps=reps, task_bootstrap=True,
                                                   random_state=np.random.RandomState(seed))
    finally:
        np.random.set_state(kept)
    return float(point["m"][0]), [float(ci["m"][0][0]), float(ci["m"][1][0])]


def _outcome_matrix(outcomes, name: str) -> np.ndarray:
    m = np.asarray(outcomes, dtype=np.float64)
    if m.ndim != 2 or m.size == 0 or not np.isfinite(m).all():
        raise ValueError(f"{name}: need a finite seeds x contexts matrix with at least one of each, got shape "
                         f"{m.shape}")
    return m


def _draw_counts(rng: np.random.Generator, n: int, size: int) -> np.ndarray:
    """How often each of ``n`` items is drawn in ``size`` resamples of ``n`` draws with replacement (rows of
    multinomial counts, the same law as counting ``n`` uniform indices)."""
    return rng.multinomial(n, np.full(n, 1.0 / n), size=size).astype(np.float64)


CHUNK = 2_000  # resamples drawn at once (bounds the memory of a per-seed draw of contexts)


def _chunk_sizes(reps: int):
    """``reps`` resamples as chunks of at most :data:`CHUNK`."""
    for start in range(0, reps, CHUNK):
        yield min(CHUNK, reps - start)


def _drawn_seeds(rng: np.random.Generator, s: int, size: int) -> np.ndarray:
    """For each of ``size`` resamples, the ``s`` seeds drawn with replacement, slot by slot (size x S)."""
    return rng.integers(0, s, size=(size, s))


def _resampled_share(m: np.ndarray, picks: np.ndarray, counts: np.ndarray) -> np.ndarray:
    """Each resample's share: the mean over its drawn seeds (``picks``, size x S) of their shares on its drawn
    contexts (``counts``, size x C, one draw played by every seed)."""
    per_seed = m @ counts.T / m.shape[1]  # (S, size): each seed's share on each resample's contexts
    return np.take_along_axis(per_seed.T, picks, axis=1).mean(axis=1)


def seeds_then_contexts(outcomes, seed: int = 0, reps: int = BOOTSTRAP_REPS,
                        contexts: str = "shared") -> tuple[float, list[float]]:
    """The mean of ``outcomes`` (training seeds x hold-out contexts; 1 = a whole row) and its 95 % percentile
    interval by a bootstrap over seeds, then contexts (module docstring). ``contexts="shared"``: one draw of
    contexts per resample, played by every seed drawn (the seeds played the same contexts); ``"per seed"``: a draw
    for each seed slot. Reproducible by ``seed``."""
    m = _outcome_matrix(outcomes, "seeds_then_contexts")
    if contexts not in ("shared", "per seed"):
        raise ValueError(f"seeds_then_contexts: contexts = {contexts!r}: 'shared' or 'per seed'")
    rng = np.random.default_rng(seed)
    s, c = m.shape
    stats = []
    for size in _chunk_sizes(reps):
        picks = _drawn_seeds(rng, s, size)
        if contexts == "shared":
            stats.append(_resampled_share(m, picks, _draw_counts(rng, c, size)))
        else:
            counts = _draw_counts(rng, c, size * s).reshape(size, s, c)  # a draw of contexts per slot
            stats.append(np.einsum("rkc,rkc->rk", m[picks], counts).mean(axis=1) / c)
    return float(m.mean()), _percentiles(np.concatenate(stats))


def difference_interval(a, b, seed: int = 0, reps: int = BOOTSTRAP_REPS) -> tuple[float, list[float]]:
    """The difference of the means of two methods' ``outcomes`` (each seeds x the same hold-out contexts), a - b,
    and its 95 % interval: each method's seeds drawn on their own, one draw of contexts shared by both (paired on
    the contexts both played)."""
    ma, mb = _outcome_matrix(a, "difference_interval"), _outcome_matrix(b, "difference_interval")
    if ma.shape[1] != mb.shape[1]:
        raise ValueError(f"difference_interval: {ma.shape[1]} and {mb.shape[1]} contexts: both methods must have "
                         f"played the same hold-out contexts")
    rng = np.random.default_rng(seed)
    stats = []
    for size in _chunk_sizes(reps):
        pa, pb = _drawn_seeds(rng, ma.shape[0], size), _drawn_seeds(rng, mb.shape[0], size)
        counts = _draw_counts(rng, ma.shape[1], size)  # one draw of contexts for both methods
        stats.append(_resampled_share(ma, pa, counts) - _resampled_share(mb, pb, counts))
    return float(ma.mean() - mb.mean()), _percentiles(np.concatenate(stats))


def _percentiles(stats: np.ndarray) -> list[float]:
    lo, hi = np.quantile(stats, [0.025, 0.975])
    return [float(lo), float(hi)]
