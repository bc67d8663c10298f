"""The 95 % interval printed beside every measured share (aero_env/intervals.py): a robustness study's
completions, a benchmark's agreements. Checked against scipy's and against what an interval is for:
covering the true share. The benchmark's mean over seeds x contexts with its two-level bootstrap interval, and the
paired difference between methods, against the laws those resamples follow exactly (binomial counts, enumerated
seed draws). And rliable's IQM with its bootstrap interval, against scipy's trimmed mean and on shares whose
interval is known."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from scipy.stats import binom, binomtest, trim_mean

from aero_env.intervals import (difference_interval, interval_text, iqm_interval, seeds_then_contexts,
                                wilson_interval)


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


# ---- the mean over seeds x contexts and its two-level interval (benchmarks/rl_vs_tuning.py's table) ----

def _binomial_bounds(n: int, p: float) -> list[float]:
    """The 2.5th and 97.5th percentiles of Binomial(n, p) / n: the law of a share of n outcomes redrawn with
    replacement from outcomes whose share is p."""
    return [binom.ppf(0.025, n, p) / n, binom.ppf(0.975, n, p) / n]


def test_one_seed_is_a_bootstrap_of_its_contexts_whose_law_is_binomial():
    one = np.zeros((1, 200))
    one[0, :150] = 1.0
    mean, (lo, hi) = seeds_then_contexts(one)
    assert mean == 0.75
    # 200 contexts redrawn from 150 whole rows: Binomial(200, 0.75) / 200, percentiles 0.69 and 0.81; the bootstrap's
    # 20,000 resamples land on them or one context beside
    want = _binomial_bounds(200, 0.75)
    assert abs(lo - want[0]) <= 0.005 and abs(hi - want[1]) <= 0.005, (lo, hi, want)


def test_the_seeds_are_drawn_again():
    """One seed that always makes the row and one that never does: a resample draws both (0.5, half the time) or
    one of them twice (0 or 1, a quarter each); the contexts cannot move it. The interval is [0, 1]."""
    assert seeds_then_contexts(np.array([[1.0] * 8, [0.0] * 8])) == (0.5, [0.0, 1.0])
    # seeds whose every context gives the same outcome: the interval is the law of a mean of 4 seeds drawn with
    # replacement from shares 0.25, 0.5, 0.75, 1, enumerated (256 equally likely draws)
    shares = np.array([0.25, 0.5, 0.75, 1.0])
    means = np.sort([np.mean(shares[list(d)]) for d in np.ndindex(4, 4, 4, 4)])
    cdf = np.searchsorted(means, means, side="right") / len(means)
    lo_want, hi_want = means[np.argmax(cdf >= 0.025)], means[np.argmax(cdf >= 0.975)]
    # a matrix with those shares, each seed's 8 contexts 2, 4, 6 or 8 whole rows, the same 8 contexts for all
    # seeds: contexts redrawn still move each seed's share; with every context alike they cannot
    flat = np.repeat(shares[:, None], 8, axis=1)
    assert seeds_then_contexts(flat) == (0.625, [lo_want, hi_want])


def test_every_seed_plays_the_contexts_drawn_once_and_per_seed_draws_them_apart():
    """Ten seeds with the same outcomes: half the contexts always make the row, half never. The seeds are alike, so
    only the contexts move the share: one draw of 200 contexts for all seeds gives Binomial(200, 0.5) / 200; a draw
    for each seed averages 10 independent draws, Binomial(2000, 0.5) / 2000, about sqrt(10) narrower."""
    alike = np.tile((np.arange(200) < 100).astype(float), (10, 1))
    mean, (lo, hi) = seeds_then_contexts(alike)
    want = _binomial_bounds(200, 0.5)
    assert mean == 0.5 and abs(lo - want[0]) <= 0.005 and abs(hi - want[1]) <= 0.005, (lo, hi, want)
    mean, (lo, hi) = seeds_then_contexts(alike, contexts="per seed")
    want = _binomial_bounds(2000, 0.5)
    assert mean == 0.5 and abs(lo - want[0]) <= 0.002 and abs(hi - want[1]) <= 0.002, (lo, hi, want)


def test_equal_outcomes_have_no_spread_and_a_seed_fixes_the_interval():
    assert seeds_then_contexts(np.ones((3, 50))) == (1.0, [1.0, 1.0])
    assert seeds_then_contexts(np.zeros((1, 7)), contexts="per seed") == (0.0, [0.0, 0.0])
    rng = np.random.default_rng(5)
    m = (rng.random((6, 40)) < 0.7).astype(float)
    assert seeds_then_contexts(m, seed=3, reps=3000) == seeds_then_contexts(m, seed=3, reps=3000)
    assert seeds_then_contexts(m, seed=3, reps=3000)[1] != seeds_then_contexts(m, seed=4, reps=3000)[1]
    assert seeds_then_contexts(m)[0] == m.mean()


def test_a_difference_is_paired_on_the_contexts_and_not_on_the_seeds():
    rng = np.random.default_rng(8)
    one = (rng.random((1, 100)) < 0.6).astype(float)
    # the same seed on the same contexts: every resample draws the same contexts for both, a difference of 0 always
    assert difference_interval(one, one) == (0.0, [0.0, 0.0])
    # one context more for a: exactly 0.01 ahead on the whole set, and in a resample by how often that context was
    # drawn, Binomial(100, 0.01) / 100: 0 to 0.03
    better = one.copy()
    better[0, np.flatnonzero(one[0] == 0)[0]] = 1.0
    d, (lo, hi) = difference_interval(better, one)
    assert d == pytest.approx(0.01, abs=1e-12) and [lo, hi] == pytest.approx(_binomial_bounds(100, 0.01), abs=1e-12)
    # the seeds are each method's own: a's and b's always/never seeds are drawn apart, so a - b is -1 with chance
    # (1/4)(1/4) = 1/16 > 2.5 %, and the interval is [-1, 1] (paired on the seeds it would be 0)
    mixed = np.array([[1.0] * 5, [0.0] * 5])
    assert difference_interval(mixed, mixed) == (0.0, [-1.0, 1.0])
    # a method with one seed against one with two
    assert difference_interval(np.ones((1, 5)), mixed) == (0.5, [0.0, 1.0])


@pytest.mark.parametrize("call, said", [
    (lambda: seeds_then_contexts(np.ones(5)), "seeds_then_contexts: need a finite seeds x contexts matrix"),
    (lambda: seeds_then_contexts(np.ones((0, 5))), "shape (0, 5)"),
    (lambda: seeds_then_contexts(np.array([[1.0, np.nan]])), "need a finite"),
    (lambda: seeds_then_contexts(np.ones((2, 2)), contexts="each"), "contexts = 'each': 'shared' or 'per seed'"),
    (lambda: difference_interval(np.ones((2, 3)), np.ones((2, 4))), "3 and 4 contexts"),
])
def test_bad_outcomes_are_refused_in_one_line(call, said):
    with pytest.raises(ValueError, match=re.escape(said)):
        call()


# ---- the IQM and its interval (the IQM of the seeds in benchmarks/rl_vs_tuning.py's table) ----
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
