"""The layout that clears, for one config: narrow and wide frames alternating, the cards a neighbour's part crosses
cut away and fitted to weigh and swing as the hollow card (aero_env/parts/layout.py), then the whole row turned frame
by frame in 3D against its neighbours and the stand (aero_env/parts/clearance.py).

    python scripts/nested_layout.py configs/paper.yaml [--plot docs/nested_cards.png]
    python scripts/nested_layout.py configs/paper.yaml --identical

Prints each kind of frame (its side cards' span, layers, whether cut, what the card weighs, where its centre is, how
it swings, against the hollow card's) and the parts that still meet. ``--identical`` turns the row with every frame
alike instead (its side cards in the same two planes: what the kit drew before the nested layout, and what it draws
where no nested layout serves a design), to show what meets. Exit status 0 when the row clears (with ``--identical``:
when the sweep ran), 1 when a card could not be fitted or parts still meet, 2 on a bad argument.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))


def main(argv: list[str] | None = None) -> int:
    from aero_env.config import ConfigError, load_config
    from aero_env.parts import build
    from aero_env.parts.clearance import static_sweep
    from aero_env.parts.layout import identical_layout, moments, nested_layout
    from aero_env.parts.solids import assembly

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("config")
    parser.add_argument("--plot", help="draw both kinds of side card (a .png)")
    parser.add_argument("--identical", action="store_true",
                        help="turn the row with every frame alike (its cards in the same two planes) instead")
    args = parser.parse_args(argv)
    if args.plot and args.identical:
        parser.error("--plot draws the nested layout's cards: not with --identical")
    if args.plot and not args.plot.endswith(".png"):
        parser.error(f"--plot {args.plot!r}: a .png file")
    try:
        cfg = load_config(args.config)
    except (ConfigError, OSError) as e:
        parser.error(str(e))
    d = cfg.design
    if args.identical:
        contacts = static_sweep(assembly(cfg, identical_layout(cfg)))
        print(f"{args.config}: every frame alike, its side cards in the same two planes")
        report(contacts)
        return 0  # a picture of what meets, not a verdict on the kit
    start = time.perf_counter()
    row = nested_layout(cfg)
    fitted = time.perf_counter() - start
    sc = build.side_card(d)
    print(f"{args.config}: the nested layout, worked out in {fitted:.1f} s")
    print(f"the hollow card: {sc['mass'] * 1e3:.3f} g, {sc['I_axis'] * 1e7:.3f} g·cm² about its hole, "
          f"{int(sc['layers'])} layers")
    print("kind     frames  span mm  layers  card                mass g   centre mm (u, v)   g·cm²")
    for kind, served in row.by_kind():
        area, su, sv, j = moments(kind.outline)
        sigma = build.GRAMMAGE * kind.layers
        frames = ",".join(str(i) for i in served)
        what = "cut away, fitted" if kind.extents is not None else "hollow, as it is"
        print(f"{kind.name:8} {frames:7} {kind.span * 1e3:7.1f} {kind.layers:7d}  {what:18} {sigma * area * 1e-3:7.3f}"
              f"   ({round(su / area, 3) + 0.0:+.3f}, {round(sv / area, 3) + 0.0:+.3f})   {sigma * j * 1e-5:7.3f}")
    if not row.found:
        print(f"no layout that clears: {row.reason}")
    contacts = static_sweep(assembly(cfg, row))
    report(contacts)
    if args.plot:
        plot(row, args.plot)
        print(f"wrote plot: {args.plot}")
    return 0 if row.found and not contacts else 1


def report(contacts) -> None:
    """The static sweep's count, then its first meetings by angle."""
    print(f"static sweep (1 deg steps, every frame against its neighbours at rest and at their end stops, and the "
          f"stand): {len(contacts)} parts meet" + (":" if contacts else ""))
    for c in sorted(contacts, key=lambda c: (c.angle_deg, c.frame))[:8]:
        print("  " + c.line())
    if len(contacts) > 8:
        print(f"  and {len(contacts) - 8} more")


def plot(row, path: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    for ax, kind in zip(axes, row.kinds[:2]):
        for poly in kind.outline.to_polygons():
            p = np.vstack([poly, poly[:1]])
            ax.plot(p[:, 0], p[:, 1], "k-", lw=1)
        ax.set_title(f"{kind.name} frames: {kind.layers} layers, {'cut away' if kind.extents else 'hollow'}")
        ax.set_aspect("equal")
        ax.grid(True, lw=0.3)
        ax.set_xlabel("mm along the frame line (the counterbalance to the right)")
    axes[0].set_ylabel("mm across")
    fig.tight_layout()
    tmp = Path(path).with_suffix(".tmp.png")
    fig.savefig(tmp, dpi=90)
    tmp.replace(path)
    plt.close(fig)


if __name__ == "__main__":
    sys.exit(main())
