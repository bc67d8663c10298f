"""How far a share measured on a sample can be trusted: k of n, with its 95 % interval.

A robustness study's share of builds that complete the row, and a benchmark's agreement with the
reference, are counts of k in n. On a few dozen designs one design moves an agreement by a point or
more, so a target of 99 % cannot be read off a sample of 60 (59 of 60 is 98.3 %, and any share
between 91 % and 99.7 % would give that count often). Each is printed with its Wilson score
interval: the shares p for which the count seen is within 1.96 standard errors of n·p. It stays
inside [0, 1] and keeps its coverage at shares near 1, where the normal approximation
(``p ± 1.96·sqrt(p(1-p)/n)``) gives a zero-width interval at 100 %.
"""

from __future__ import annotations

import math

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
