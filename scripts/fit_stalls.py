"""How long the nested layout's card fit goes without progress, in the starts that fit and in those that do not.

    python scripts/fit_stalls.py [--random N]

For the kits the read-back tests draw (tests/test_kit_readback.py's variants and stored solutions), the two stored
designs whose kit is refused, and N random designs of the prototype's space (seed 0): each fit start's cards cut
and its longest run of cards without a 1 % gain on its best misfit. It is why the fit has no stall cut-off: a start
that fails runs 1,300-4,800 cards, but two starts that fitted (random designs 8 and 16) first went 488 and 587 cards
without such a gain, so a cut-off that saved much time would have refused layouts that are found.
"""

from __future__ import annotations

import argparse
import sys
import time
import warnings
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from aero_env.bench.designs import draw_designs  # noqa: E402
from aero_env.config import load_config  # noqa: E402
from aero_env.parts import layout  # noqa: E402
from tests.test_kit_readback import SOLUTIONS, VARIANTS  # noqa: E402

GAIN = 0.01  # a start "progresses" when its best misfit shrinks by this fraction


def cases(n_random: int):
    paper = ROOT / "configs" / "paper.yaml"
    for name, over in VARIANTS.items():
        yield f"variant {name}", load_config(paper, dict(kv.split("=", 1) for kv in over))
    for path in SOLUTIONS:
        yield f"solution {path.stem}", load_config(path)
    for name in ("steep_solution", "small_frames"):
        yield f"config {name}", load_config(ROOT / "configs" / f"{name}.yaml")
    for i, cfg in enumerate(draw_designs(load_config(paper), n_random, 0).configs):
        yield f"random {i}", cfg


def longest_stall(costs: list[float]) -> int:
    """The most cards in a row without a ``GAIN`` gain on the best so far."""
    best, since, longest = np.inf, 0, 0
    for value in costs:
        since += 1
        if value < best * (1.0 - GAIN):
            best, since = value, 0
        longest = max(longest, since)
    return longest


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--random", type=int, default=20, help="random designs of the prototype's space (seed 0)")
    args = parser.parse_args()
    warnings.simplefilter("ignore")
    plain = layout.minimize
    starts: list[tuple[bool, int, int]] = []  # (fitted, cards, longest stall) of each start

    def traced(fun, x0, **kw):
        costs: list[float] = []

        def counted(p):
            try:
                value = fun(p)
            except Exception:  # the fit's "this card fits" signal
                starts.append((True, len(costs) + 1, longest_stall(costs)))
                raise
            costs.append(value)
            return value

        run = plain(counted, x0, **kw)
        starts.append((False, len(costs), longest_stall(costs)))
        return run

    layout.minimize = traced
    fitted_stalls, failed_cards = [], []
    print(f"{'case':32} {'layout':>8} {'s':>6}  starts: fitted (cards, longest stall) | not fitted (cards)")
    for name, cfg in cases(args.random):
        starts.clear()
        t = time.perf_counter()
        row = layout._build_nested(cfg)
        took = time.perf_counter() - t
        ok = [(c, s) for f, c, s in starts if f]
        bad = [c for f, c, _ in starts if not f]
        fitted_stalls += [s for _, s in ok]
        failed_cards += bad
        print(f"{name:32} {'found' if row.found else 'refused':>8} {took:6.1f}  {ok} | {bad}")
    print(f"longest stall of a start that fitted: {max(fitted_stalls, default=0)} cards "
          f"({len(fitted_stalls)} starts); starts that did not fit ran {min(failed_cards, default=0)}-"
          f"{max(failed_cards, default=0)} cards (median {int(np.median(failed_cards)) if failed_cards else 0}, "
          f"{len(failed_cards)} starts)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
