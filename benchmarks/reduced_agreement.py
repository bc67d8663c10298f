"""How well the reduced model agrees with the pymunk world on random designs.

    python benchmarks/reduced_agreement.py [CONFIG] [--designs 200] [--seed 1] [--near CONFIG --spread S]
                                           [--cache FILE.json]

Draws ``--designs`` uniformly random actions in [-1, 1]^dim, maps them to designs with
``DesignSpace(cfg).values`` and ``episode_config`` (the nominal draw), and runs each through the
pymunk runner (``aero_env.physics.simulate`` at the config's sim settings) and the whole batch
through ``aero_env.models.reduced.simulate_batch``. The pymunk results are cached in ``--cache``
(keyed by config file, seed and count; a pymunk run takes 0.05-0.6 s), so a second call only
reruns the reduced model. Prints JSON: the fractions with the same traversal count and the same
outcome, Spearman and Pearson correlations of the traversals, the median |error| of the first
detach time and angle (designs that detach in both), the confusion matrix of outcomes, and how
the designs that complete the row in pymunk score in the reduced model. ``--near CONFIG --spread S``
draws the designs near that config's design instead (``aero-env bench accuracy``'s box: ±S of each
action range), where a tuner spends its time once a design works.
"""

from __future__ import annotations

import argparse
import collections
import hashlib
import json
import time
from pathlib import Path

import numpy as np
from scipy.stats import pearsonr, spearmanr

from aero_env.bench.designs import draw_designs
from aero_env.config import load_config
from aero_env.design_space import DesignSpace
from aero_env.models.reduced import OUTCOMES, simulate_batch
from aero_env.physics import simulate

ROOT = Path(__file__).resolve().parents[1]


def cache_key(cfgs) -> str:
    """What the stored pymunk runs are valid for: every design's whole config as simulated, and every source of
    the package (the world, the parts it builds, the design space that drew the designs). A key of paths and
    seeds alone once served runs of other designs after a config's design space changed."""
    src = b"".join(p.read_bytes() for p in sorted((ROOT / "aero_env").rglob("*.py")))
    designs = "\n".join(c.to_yaml() for c in cfgs).encode()
    return f"{len(cfgs)} designs|{hashlib.sha1(designs).hexdigest()[:16]}|{hashlib.sha1(src).hexdigest()[:16]}"


def pymunk_runs(cfgs, cache: Path | None, key: str) -> list[dict]:
    store = json.loads(cache.read_text()) if cache and cache.exists() else {}
    if key not in store:
        runs = []
        for c in cfgs:
            r = simulate(c)
            s = r.swings[0]
            runs.append(dict(traversals=r.traversals, outcome=r.outcome, reason=r.reason, t_detach=s.t_detach,
                             theta1_detach_deg=s.theta1_detach_deg, sim_time=r.sim_time, wall_time=r.wall_time))
        store[key] = runs
        if cache:
            cache.write_text(json.dumps(store))
    return store[key]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("config", nargs="?", default=str(ROOT / "configs" / "paper.yaml"))
    ap.add_argument("--designs", type=int, default=200)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--cache", type=Path, default=Path("/tmp/aero_env_reduced_agreement.json"))
    ap.add_argument("--near", type=Path, help="draw the designs near this config's design")
    ap.add_argument("--spread", type=float, default=0.1, help="with --near: the box's half-width, a fraction of "
                    "each action range")
    ap.add_argument("--details", action="store_true", help="also list every design that disagrees")
    args = ap.parse_args()
    cfg = load_config(args.config)
    if args.near is None:
        space = DesignSpace(cfg)
        actions = np.random.default_rng(args.seed).uniform(-1.0, 1.0, (args.designs, space.dim))
        cfgs = [space.episode_config(space.values(a), space.nominal_draw())[0] for a in actions]
    else:
        cfgs = list(draw_designs(cfg, args.designs, args.seed, near=load_config(args.near),
                                 spread=args.spread).configs)
    pm = pymunk_runs(cfgs, args.cache, cache_key(cfgs))
    t0 = time.perf_counter()
    rd = simulate_batch(cfgs)
    wall = time.perf_counter() - t0

    pt = np.array([r["traversals"] for r in pm])
    po = np.array([r["outcome"] for r in pm])
    ptd = np.array([np.nan if r["t_detach"] is None else r["t_detach"] for r in pm])
    pth = np.array([np.nan if r["theta1_detach_deg"] is None else r["theta1_detach_deg"] for r in pm])
    both = ~np.isnan(ptd) & ~np.isnan(rd.t_detach)
    full = int(cfg.scene.frames) - 1
    completes = pt == full
    confusion = collections.Counter(zip(po.tolist(), rd.outcome.tolist()))
    out = dict(
        config=args.config, designs=args.designs, seed=args.seed, near=str(args.near) if args.near else None,
        spread=args.spread if args.near else None, reduced_wall_s=round(wall, 3),
        pymunk_wall_s=round(sum(r["wall_time"] for r in pm), 2),
        same_traversals=float(np.mean(pt == rd.traversals)), same_outcome=float(np.mean(po == rd.outcome)),
        spearman_traversals=float(spearmanr(pt, rd.traversals)[0]),
        pearson_traversals=float(pearsonr(pt, rd.traversals)[0]),
        detach_in_both=int(both.sum()),
        detach_pymunk_only=int((~np.isnan(ptd) & np.isnan(rd.t_detach)).sum()),
        detach_reduced_only=int((np.isnan(ptd) & ~np.isnan(rd.t_detach)).sum()),
        median_abs_dt_detach_s=float(np.median(np.abs(ptd - rd.t_detach)[both])),
        median_abs_dtheta1_detach_deg=float(np.median(np.abs(pth - rd.theta1_detach_deg)[both])),
        pymunk_full_row=int(completes.sum()),
        reduced_full_row=int((rd.traversals == full).sum()),
        full_row_in_both=int((completes & (rd.traversals == full)).sum()),
        reduced_traversals_of_pymunk_full_rows=rd.traversals[completes].tolist(),
        mean_reduced_traversals_pymunk_full_row=float(np.mean(rd.traversals[completes])) if completes.any() else None,
        mean_reduced_traversals_other=float(np.mean(rd.traversals[~completes])),
        confusion_pymunk_rows_reduced_cols={a: {b: confusion[(a, b)] for b in OUTCOMES} for a in OUTCOMES},
    )
    if args.details:
        out["disagreements"] = [dict(i=i, pymunk=f"{pt[i]} {pm[i]['reason']}", reduced=f"{rd.traversals[i]} "
                                     f"{rd.reason(i)}") for i in range(len(cfgs))
                                if pt[i] != rd.traversals[i] or po[i] != rd.outcome[i]]
    print(json.dumps(out, indent=2))


if __name__ == "__main__":
    main()
