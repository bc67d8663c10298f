"""How far a share measured on a sample can be trusted: k of n, with its 95 % interval.

A robustness study's share of builds that complete the row, and a benchmark's agreement with the
reference, are counts of k in n. On a few dozen designs one design moves an agreement by a point or
more, so a target of 99 % cannot be read off a sample of 60 (59 of 60 is 98.3 %, and any share
between 91 % and 99.7 % would give that count often). Each is printed with its Wilson score
interval: the shares p for which the count seen is within 1.96 standard errors of n·p. It stays
inside [0, 1] and keeps its coverage at shares near 1, where the normal approximation
(``p ± 1.96·sqrt(p(1-p)/n)``) gives a zero-width interval at 100 %.

A benchmark over training seeds (``benchmarks/rl_vs_tuning.py``) reports a method's share as the interquartile
mean over (seeds x blocks of contexts), :func:`block_shares`, with rliable's stratified-bootstrap interval,
:func:`iqm_interval`. rliable is in the ``bench`` and ``test`` extras only, so it is imported there, when asked.
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


BOOTSTRAP_REPS = 20_000  # rliable's bootstrap resamples for an IQM's interval


def iqm_interval(shares: np.ndarray, seed: int = 0, reps: int = BOOTSTRAP_REPS) -> tuple[float, list[float]]:
    """IQM and 95 % stratified-bootstrap interval (rliable) of ``shares`` (runs x blocks of contexts). The IQM is the
    mean of the middle half of all the values (scipy's ``trim_mean(x, 0.25)`` over the flattened array)."""
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


def block_shares(whole_rows: np.ndarray, strata: int) -> np.ndarray:
    """Per run, the whole-row share in each of ``strata`` consecutive blocks of hold-out contexts."""
    return np.array([[float(np.mean(b)) for b in np.array_split(row, strata)] for row in whole_rows])
