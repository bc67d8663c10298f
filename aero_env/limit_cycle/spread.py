"""The statistics of one per-catch series: spread, drift, and whether it has settled.

* spread: ``mean``, ``std`` (sample, ddof=1), ``min``, ``max``;
* drift: ``slope`` of the least-squares line through (frame number, value), per catch, and
  ``trend`` = slope·(last frame - first frame), the change the line makes across the window;
  ``halves``: the mean of the second half minus that of the first (the middle value of an odd
  count in neither);
* ``settled``: ``|trend| <= SETTLE_FACTOR·std`` (plus round-off, ``ROUND_OFF``·max(1, |mean|), so that a
  constant series settles), None with fewer than ``MIN_CATCHES`` values.

Why twice the std: values scattered about a fixed cycle give a trend whose standard error is
std·sqrt(12(n-1)/(n(n+1))), 0.48·std for n = 50, so they pass by four standard errors; a pure linear
drift has std = |trend|·sqrt((n+1)/(12(n-1))), 0.29·|trend| for n = 50, so it fails (its trend is
3.4 std); a drift plus scatter passes only while the drift across the window stays below about 2.4
times the scatter.
"""

from __future__ import annotations

import math

import numpy as np

SETTLE_FACTOR = 2.0
ROUND_OFF = 1e-9  # relative: a least-squares slope through equal values is zero only to round-off
MIN_CATCHES = 4  # below this a line through the values cannot be told from their scatter


def series_spread(frames: list[int], values: list[float]) -> dict:
    """The statistics of one series (frame numbers rising); None where the count is too small."""
    n = len(values)
    out = dict(n=n, mean=None, std=None, min=None, max=None, slope=None, trend=None, halves=None, settled=None)
    if n == 0:
        return out
    y = np.asarray(values, dtype=float)
    out.update(mean=float(y.mean()), min=float(y.min()), max=float(y.max()))
    if n < 2:
        return out
    x = np.asarray(frames, dtype=float)
    slope = float(np.polyfit(x, y, 1)[0]) if x[-1] > x[0] else 0.0
    half = n // 2
    out.update(std=float(y.std(ddof=1)), slope=slope, trend=slope * float(x[-1] - x[0]),
               halves=float(y[n - half:].mean() - y[:half].mean()))
    if n >= MIN_CATCHES and all(math.isfinite(out[k]) for k in ("std", "trend")):
        allowed = SETTLE_FACTOR * out["std"] + ROUND_OFF * max(1.0, abs(out["mean"]))
        out["settled"] = bool(abs(out["trend"]) <= allowed)
    return out
