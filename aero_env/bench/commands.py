"""The ``aero-env bench`` subcommands."""

from __future__ import annotations

import json
import sys

from ..config import ConfigError, load_config
from ..scene_args import PLOT_SUFFIXES, add_seed, check_output, load_scene

SPREAD = 0.1  # bench accuracy --near: the default half-width of the box, a fraction of each action range


def register(sub, scene_command) -> None:
    bp = sub.add_parser("bench", help="what accuracy costs in time: fidelities, effects, throughput")
    bsub = bp.add_subparsers(dest="bench", required=True, metavar="BENCH")

    ap = scene_command(bsub, "accuracy", "every fidelity on the same random designs, against reference")
    ap.add_argument("--designs", type=int, default=50, help="random designs from the action space")
    add_seed(ap, 0, "seed of the design draw")
    ap.add_argument("--repeats", type=int, default=3, help="runs per design and fidelity; the median time is kept")
    ap.add_argument("--fidelities", metavar="A,B,...",
                    help="a subset of the ladder, comma-separated (absent: all of it; reference is always added)")
    ap.add_argument("--check-reference", action="store_true",
                    help="also run reference/2 (half the step, twice the iterations): is the reference converged?")
    ap.add_argument("--plot", metavar="FILE.png", help="the accuracy/time Pareto front")
    ap.add_argument("--near", metavar="CONFIG",
                    help="draw the designs near this config's design (its tunable values) instead of over the whole "
                         "action box: where tuners spend their time")
    ap.add_argument("--spread", type=float, default=None,
                    help=f"with --near: the box's half-width, a fraction of each action range, in (0, 1] (default "
                         f"{SPREAD})")
    ap.set_defaults(func=cmd_accuracy)

    ep = scene_command(bsub, "effects", "each effect's cost in time and whether it changes outcomes")
    ep.add_argument("--designs", type=int, default=30, help="random designs from the action space")
    add_seed(ep, 0, "seed of the design draw")
    ep.add_argument("--repeats", type=int, default=3, help="runs per design and effect; the median time is kept")
    ep.add_argument("--effects", metavar="NAME,...",
                    help="only these effects, comma-separated (default every one; clearance costs seconds a design)")
    ep.set_defaults(func=cmd_effects)

    op = scene_command(bsub, "overhead", "the Python layer's cost over bare space.step calls, piece by piece")
    op.add_argument("--repeats", type=int, default=5, help="runs of each piece; the median time is kept")
    op.set_defaults(func=cmd_overhead)

    tp = bsub.add_parser("throughput", help="designs per second at every fidelity, batched and one at a time, and "
                                            "with 1 and 2 vector workers")
    tp.add_argument("config", nargs="?", default=None, help="scene YAML (absent: the prototype's defaults)")
    tp.add_argument("--set", action="append", metavar="KEY=VALUE",
                    help="override a config value (repeatable); a number may carry its unit, e.g. design.m2=7.71g")
    tp.add_argument("--episodes", type=int, default=40,
                    help="designs per measurement, one at a time and through the process pool")
    tp.add_argument("--batch", type=int, default=1000, help="designs in the reduced vector env's one call")
    tp.add_argument("--pool-workers", type=int, default=None,
                    help="processes of the vector env's pool at a pymunk fidelity (absent: one per core)")
    tp.add_argument("--repeats", type=int, default=3, help="measurements; the median is kept")
    add_seed(tp, 0, "first episode seed")
    tp.add_argument("--json", action="store_true", help="print one JSON object instead of the table")
    tp.set_defaults(func=cmd_throughput)


def _emit(args, report, table) -> int:
    print(json.dumps(report, indent=2) if args.json else table(report))
    return 0


class DesignProgress:
    """Progress of ``bench accuracy`` on stderr (stdout stays the table or the JSON): on a terminal a bar
    over the designs of the fidelity being run, rewritten in place; each finished fidelity one line."""

    WIDTH = 24

    def __init__(self, stream=None):
        self.stream = stream or sys.stderr
        self.tty = self.stream.isatty()

    def design(self, name: str, done: int, total: int) -> None:
        if self.tty:
            full = self.WIDTH * done // max(total, 1)
            bar = "#" * full + "." * (self.WIDTH - full)
            print(f"\r  {name:>12} [{bar}] {done}/{total} designs", end="", file=self.stream, flush=True)

    def fidelity(self, name: str, runs) -> None:
        start = "\r\033[K" if self.tty else ""
        print(f"{start}  {name:>12}: {sum(runs.wall):.1f} s for {len(runs.wall)} designs", file=self.stream,
              flush=True)


def cmd_accuracy(args) -> int:
    from .accuracy import accuracy, fidelity_overrides, plot_pareto, table

    check_output(args.plot, "--plot", PLOT_SUFFIXES)
    fids = [f.strip() for f in args.fidelities.split(",")] if args.fidelities else None
    for name in fids or ():
        fidelity_overrides(name)  # an unknown fidelity is refused before any design runs
    if args.near is None and args.spread is not None:
        raise ConfigError(f"--spread {args.spread!r}: only with --near CONFIG (the design the box is around)")
    spread = SPREAD if args.spread is None else args.spread  # its range is checked where the designs are drawn
    cfg = load_scene(args)
    near = load_config(args.near) if args.near else None
    bar = DesignProgress()
    report = accuracy(cfg, designs=args.designs, seed=args.seed, repeats=args.repeats, fidelities=fids,
                      check_reference=args.check_reference, progress=bar.fidelity, on_design=bar.design,
                      near=near, spread=spread, near_name=args.near)
    if args.plot:
        plot_pareto(report, args.plot)
        report["plot"] = args.plot
    return _emit(args, report, table)


def cmd_effects(args) -> int:
    from .effects import effects, pick_effects, table

    names = pick_effects(args.effects)  # a name that is no effect: one line, before any run
    return _emit(args, effects(load_scene(args), designs=args.designs, seed=args.seed, repeats=args.repeats,
                               names=names), table)


def cmd_throughput(args) -> int:
    from .throughput import table, throughput

    report = throughput(load_scene(args), episodes=args.episodes, repeats=args.repeats, seed=args.seed,
                        batch=args.batch, pool_workers=args.pool_workers)
    return _emit(args, report, table)


def cmd_overhead(args) -> int:
    from .overhead import overhead, table

    return _emit(args, overhead(load_scene(args), repeats=args.repeats), table)
