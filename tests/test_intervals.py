"""The 95 % interval printed beside every measured share (aero_env/intervals.py): a robustness study's
completions, a benchmark's agreements. Checked against scipy's and against what an interval is for:
covering the true share."""

from __future__ import annotations

import math

import pytest
from scipy.stats import binomtest

from aero_env.intervals import interval_text, wilson_interval


@pytest.mark.parametrize("k, n", [(0, 1), (0, 10), (3, 10), (87, 100), (100, 100), (1, 3), (499, 1000), (59, 60),
                                  (382, 394), (114, 114)])
def test_the_interval_is_scipys_wilson_interval(k, n):
    ref = binomtest(k, n).proportion_ci(confidence_level=0.95, method="wilson")
    lo, hi = wilson_interval(k, n)
    assert (lo, hi) == pytest.approx((ref.low, ref.high), abs=1e-12) and lo <= k / n <= hi


def test_a_share_of_59_in_60_cannot_tell_98_from_99_percent_and_a_hundred_designs_at_100_percent_still_can_miss():
    # the reason the benchmarks print it: one design in 60 moves the column by 1.7 points, and a perfect score on
    # a small sample does not show a 99 % target met
    lo, hi = wilson_interval(59, 60)
    assert lo < 0.95 and hi > 0.99
    assert wilson_interval(100, 100)[0] < 0.99 < wilson_interval(1000, 1000)[0]
    # the normal approximation's interval at 100 % has no width at all; this one does
    assert wilson_interval(40, 40)[0] < 1.0


@pytest.mark.parametrize("n, p", [(60, 0.97), (300, 0.95), (40, 0.5), (200, 0.99)])
def test_it_covers_the_true_share_about_95_percent_of_the_time(n, p):
    # exact coverage over the binomial distribution of the count, no sampling: the probability that an
    # interval drawn from a sample of n contains p. Wilson's is near 95 % (it oscillates around it).
    coverage = sum(math.comb(n, k) * p ** k * (1 - p) ** (n - k) for k in range(n + 1)
                   if wilson_interval(k, n)[0] <= p <= wilson_interval(k, n)[1])
    assert 0.90 <= coverage <= 0.99, coverage


def test_the_column_and_bad_counts():
    assert interval_text(wilson_interval(59, 60)) == "91.1-99.7" and interval_text(None) == "-"
    for k, n in ((-1, 3), (4, 3), (0, 0)):
        with pytest.raises(ValueError, match=f"k = {k}, n = {n}"):
            wilson_interval(k, n)
