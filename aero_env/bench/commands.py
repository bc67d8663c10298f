"""The ``aero-env bench`` subcommands."""

from __future__ import annotations

import json
import sys


def register(sub, scene_command) -> None:
    bp = sub.add_parser("bench", help="what accuracy costs in time: fidelities, effects, throughput")
    bsub = bp.add_subparsers(dest="bench", required=True)

    ap = scene_command(bsub, "accuracy", "every fidelity on the same random designs, against reference")
    ap.add_argument("--designs", type=int, default=50, help="random designs from the action space (default 50)")
    ap.add_argument("--seed", type=int, default=0, help="seed of the design draw (default 0)")
    ap.add_argument("--repeats", type=int, default=3, help="runs per design and fidelity; the median is kept")
    ap.add_argument("--fidelities", metavar="A,B,...", help="a subset of the ladder (reference is always added)")
    ap.add_argument("--check-reference", action="store_true",
                    help="also run reference/2 (half the step, twice the iterations): is the reference converged?")
    ap.add_argument("--plot", metavar="FILE.png", help="the accuracy/time Pareto front")
    ap.set_defaults(func=cmd_accuracy)

    ep = scene_command(bsub, "effects", "each effect's cost in time and whether it changes outcomes")
    ep.add_argument("--designs", type=int, default=30)
    ep.add_argument("--seed", type=int, default=0)
    ep.add_argument("--repeats", type=int, default=3)
    ep.set_defaults(func=cmd_effects)

    op = scene_command(bsub, "overhead", "the Python layer's cost over bare space.step calls, piece by piece")
    op.add_argument("--repeats", type=int, default=5)
    op.set_defaults(func=cmd_overhead)

    tp = bsub.add_parser("throughput", help="environment episodes per second with 1 and 2 vector workers")
    tp.add_argument("config", nargs="?", default=None, help="scene YAML (default: the prototype)")
    tp.add_argument("--set", action="append", metavar="KEY=VALUE", help="override a config value (repeatable)")
    tp.add_argument("--episodes", type=int, default=40)
    tp.add_argument("--repeats", type=int, default=3)
    tp.add_argument("--seed", type=int, default=0)
    tp.add_argument("--json", action="store_true")
    tp.set_defaults(func=cmd_throughput)


def _emit(args, report, table) -> int:
    print(json.dumps(report, indent=2) if args.json else table(report))
    return 0


def cmd_accuracy(args) -> int:
    from ..cli import load_scene
    from .accuracy import accuracy, plot_pareto, table

    def progress(name, runs):
        print(f"  {name}: {sum(runs.wall):.1f} s for {len(runs.wall)} designs", file=sys.stderr, flush=True)

    cfg = load_scene(args)
    fids = [f.strip() for f in args.fidelities.split(",")] if args.fidelities else None
    report = accuracy(cfg, designs=args.designs, seed=args.seed, repeats=args.repeats, fidelities=fids,
                      check_reference=args.check_reference, progress=progress)
    if args.plot:
        plot_pareto(report, args.plot)
        report["plot"] = args.plot
    return _emit(args, report, table)


def cmd_effects(args) -> int:
    from ..cli import load_scene
    from .effects import effects, table

    return _emit(args, effects(load_scene(args), designs=args.designs, seed=args.seed, repeats=args.repeats), table)


def cmd_throughput(args) -> int:
    from ..cli import load_scene
    from .throughput import table, throughput

    report = throughput(load_scene(args), episodes=args.episodes, repeats=args.repeats, seed=args.seed)
    return _emit(args, report, table)


def cmd_overhead(args) -> int:
    from ..cli import load_scene
    from .overhead import overhead, table

    return _emit(args, overhead(load_scene(args), repeats=args.repeats), table)
