"""The 95 % interval printed beside every measured share (aero_env/intervals.py): a robustness study's
completions, a benchmark's agreements. Checked against scipy's and against what an interval is for:
covering the true share. And the IQM over runs x blocks with its bootstrap interval (rl_vs_tuning.py's table),
against scipy's trimmed mean and on shares whose interval is known."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.stats import binomtest, trim_mean

from aero_env.intervals import block_shares, interval_text, iqm_interval, wilson_interval


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


# ---- the IQM and its interval (benchmarks/rl_vs_tuning.py's table) ----
# Skewed shares: most runs near 0.2, a few near 1 (a method that works on some seeds). Their IQM (the mean of the
# middle half) and their mean differ by far more than rounding, so a statistic that is a mean fails here.
SKEWED = np.array([[0.1, 0.2, 0.2, 0.3, 0.2], [0.2, 0.1, 0.3, 0.2, 0.2], [0.2, 0.3, 0.1, 0.2, 1.0],
                   [1.0, 0.9, 1.0, 1.0, 0.9]])


def test_the_iqm_is_the_mean_of_the_middle_half_worked_by_hand():
    # 2 runs x 4 blocks, eight values 1..7 and 100: the middle half of the sorted values is 3, 4, 5, 6
    shares = np.array([[7.0, 1.0, 100.0, 4.0], [3.0, 6.0, 2.0, 5.0]])
    iqm, (lo, hi) = iqm_interval(shares, reps=500)
    assert iqm == 4.5 and shares.mean() == 16.0
    assert lo <= iqm <= hi


def test_the_iqm_is_scipys_trimmed_mean_on_skewed_shares():
    iqm, (lo, hi) = iqm_interval(SKEWED, reps=2000)
    assert iqm == pytest.approx(trim_mean(SKEWED.ravel(), 0.25), rel=1e-12)
    assert abs(iqm - SKEWED.mean()) > 0.05  # skewed: the mean is not it
    assert SKEWED.min() <= lo <= iqm <= hi <= SKEWED.max() and hi > lo


def test_the_interval_of_equal_shares_is_that_share_and_a_seed_gives_the_same_interval():
    assert iqm_interval(np.full((3, 4), 0.75), reps=300) == (0.75, [0.75, 0.75])  # every resample is the same
    # reproducible by its seed, another seed resamples otherwise, and numpy's global generator is left as it was
    np.random.seed(123)
    before = np.random.random()
    np.random.seed(123)
    first = iqm_interval(SKEWED, seed=3, reps=500)
    assert np.random.random() == before
    assert iqm_interval(SKEWED, seed=3, reps=500) == first and iqm_interval(SKEWED, seed=4, reps=500)[1] != first[1]


def test_the_interval_resamples_the_blocks_too():
    """rliable's stratified bootstrap with task_bootstrap: the blocks are drawn again with replacement, and the runs
    within each. One block all 0 and one all 1 across runs: a resample draws both blocks (IQM 0.5, half the time),
    or one of them twice (0 or 1, a quarter each), so the 95 % interval is [0, 1] around the IQM of 0.5."""
    two_blocks = np.array([[0.0, 1.0], [0.0, 1.0], [0.0, 1.0], [0.0, 1.0]])
    assert iqm_interval(two_blocks, reps=2000) == (0.5, [0.0, 1.0])
    iqm, (lo, hi) = iqm_interval(SKEWED, reps=2000)
    assert lo < iqm < hi


def test_block_shares_are_each_runs_share_in_consecutive_blocks():
    whole = np.array([[1, 0, 1, 1, 0, 0, 1], [0, 0, 0, 1, 1, 1, 1]], dtype=bool)
    # numpy's array_split: 7 contexts in 3 blocks of 3, 2 and 2
    assert block_shares(whole, 3).tolist() == [[2 / 3, 1 / 2, 1 / 2], [0.0, 1.0, 1.0]]
    assert block_shares(whole, 7).tolist() == whole.astype(float).tolist()
    assert block_shares(whole, 1).tolist() == [[4 / 7], [4 / 7]]


def test_the_bounds_at_none_and_all_are_exactly_0_and_1():
    # at k = 0 the formula's lower bound is 0 only up to rounding (a hair above it for 544 of the n <= 3000), and at
    # k = n its upper bound 1 likewise: the interval states them exactly
    for n in range(1, 400):
        assert wilson_interval(0, n)[0] == 0.0 and wilson_interval(n, n)[1] == 1.0, n
        assert 0.0 < wilson_interval(1, n)[0] and wilson_interval(n - 1, n)[1] < 1.0 or n == 1


def test_the_iqm_is_computed_in_double_precision_with_the_default_seed_and_its_reps():
    shares = (np.array([[1, 2, 3], [4, 5, 60]], dtype=np.float32) / np.float32(7))
    iqm, _ = iqm_interval(shares, reps=300)
    assert iqm == trim_mean(shares.astype(np.float64).ravel(), 0.25)  # the float32 values, averaged in float64
    assert iqm_interval(SKEWED, reps=300) == iqm_interval(SKEWED, seed=0, reps=300)
    lo, hi = iqm_interval(SKEWED, reps=1)[1]  # one resample: its IQM is both ends
    assert lo == hi


def test_the_iqm_interval_leaves_no_warning_behind():
    import warnings

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        iqm_interval(SKEWED, reps=200)
    assert [str(w.message) for w in caught] == []
