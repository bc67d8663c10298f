"""The ``aero-env`` command line.

    aero-env simulate CONFIG [--set KEY=VALUE ...] [--json] [--trace FILE.csv] [--plot FILE.png] [--gif FILE.gif]
                             [--labels]
    aero-env compare CONFIG [--set KEY=VALUE ...] [--json] [--plot FILE.png] [--domain-map FILE.png]
    aero-env schema          # every config key with its default, unit, range and meaning
    aero-env calibrate | robustness | cycle CONFIG ...   # fit unknowns; hand-made builds; the limit cycle
    aero-env bench accuracy|effects|throughput ...   # what accuracy costs in time (aero_env.bench)
    aero-env --version

Packages add subcommands through the ``aero_env.commands`` entry-point group: each entry is a
function ``register(subparsers, scene_command)``. The design agents (``aero-env tune``,
``train``, ``evaluate``) come in that way, so this package never imports them; a command reads
its scene and checks its output paths with :mod:`aero_env.scene_args`, not through this module.

Every slip ends with one line on stderr naming the option or key, the value and what is allowed,
and exit status 2 (argparse's own errors too: no usage block, a pointer to ``--help``), its first
word the kind of slip (:func:`error_kind`: ``error:`` for an option, ``file error:`` for a file that
cannot be read, ``config error:`` for a config key or value, ``missing package:`` for an extra the install
left out); Ctrl-C
ends with one line and exit status 130, and SIGTERM (a job scheduler's stop) as Ctrl-C does, with 143.
Every option's help shows its default.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import sys
from importlib.metadata import PackageNotFoundError, entry_points, version

from . import quantities
from .config import ConfigError, MissingExtra, schema_rows
from .scene_args import CSV_SUFFIXES, PLOT_SUFFIXES, check_output, load_scene
from .signals import exit_status, signal_name, sigterm_as_interrupt

__all__ = ["build_parser", "main"]


def package_version() -> str:
    try:
        return version("aero-env")
    except PackageNotFoundError:  # run from a source tree that was never installed
        return "unknown (not installed)"


class HelpFormatter(argparse.ArgumentDefaultsHelpFormatter):
    """Adds "(default: X)" to an option's help unless the help already speaks of its default, or it has
    none to show (None: the help says what absence means; False: a switch)."""

    def _get_help_string(self, action):
        text = action.help or ""
        if ("default" in text.lower() or action.default is None or action.default is False
                or action.default == argparse.SUPPRESS
                or (not action.option_strings and action.nargs not in ("?", "*"))):
            return text
        return f"{text} (default: %(default)s)"


class Parser(argparse.ArgumentParser):
    """argparse with :class:`HelpFormatter` everywhere and one-line errors (exit 2) without the usage block."""

    def __init__(self, *args, **kwargs):
        kwargs.setdefault("formatter_class", HelpFormatter)
        super().__init__(*args, **kwargs)

    def error(self, message):
        self.exit(2, f"{self.prog}: error: {message} (see {self.prog} --help)\n")


def cmd_simulate(args) -> int:
    from .simulation import simulate
    from .render import pose_interval

    check_output(args.trace, "--trace", CSV_SUFFIXES)
    check_output(args.plot, "--plot", PLOT_SUFFIXES)
    check_output(args.gif, "--gif", (".gif",))
    cfg = load_scene(args)
    want_trace = bool(args.trace or args.plot)
    result = simulate(cfg, trace=want_trace, poses_every=pose_interval(cfg.env.render_slowmo) if args.gif else None)
    if args.trace:
        from .render import write_trace_csv

        write_trace_csv(result, args.trace)
    if args.plot:
        from .render import plot_angles

        plot_angles(result, args.plot)
    if args.gif:
        from .render import write_gif

        print(f"aero-env simulate: encoding {len(result.poses or ())} frames to {args.gif} ...", file=sys.stderr,
              flush=True)
        write_gif(result, args.gif, labels=args.labels, slowmo=cfg.env.render_slowmo)
    if args.json:
        print(json.dumps(result.to_json_dict(), indent=2))
    else:
        print(_table(result))
        for name, path in (("trace", args.trace), ("plot", args.plot), ("animation", args.gif)):
            if path:
                print(f"wrote {name}: {path}")
    return 0


def _fmt(v, spec):
    return format("-", f">{spec.split('.')[0]}") if v is None else format(v, spec)


def _table(r) -> str:
    lines = [f"{'frame':>5} {'t_catch':>8} {'t_carried':>9} {'t_detach':>8} {'swing s':>8} {'th1 catch':>9} "
             f"{'th1 detach':>10} {'th2 catch':>9} {'th2 range':>11}"]
    for s in r.swings:
        rng = f"{s.theta2_min_deg:.0f}..{s.theta2_max_deg:.0f}" if s.theta2_min_deg is not None else "-"
        lines.append(f"{s.frame:>5} {_fmt(s.t_catch, '8.3f')} {_fmt(s.t_carried, '9.3f')} {_fmt(s.t_detach, '8.3f')} "
                     f"{_fmt(s.swing_duration, '8.3f')} {_fmt(s.theta1_catch_deg, '9.1f')} "
                     f"{_fmt(s.theta1_detach_deg, '10.1f')} {_fmt(s.theta2_catch_deg, '9.1f')} {rng:>11}")
    e = r.energy
    lines.append("")
    lines.append(f"outcome: {r.outcome} ({r.reason})")
    lines.append(f"traversals: {r.traversals} of {r.frames - 1}   simulated {r.sim_time:.3f} s in {r.wall_time:.3f} s "
                 f"wall ({r.sim_time / max(r.wall_time, 1e-9):.1f}x real time) at fidelity {r.fidelity}")
    if not e:  # nothing was simulated (collides: the kit's parts meet)
        lines.append("energy, health: - (nothing simulated)")
        return "\n".join(lines)
    lines.append(f"energy: initial {e['initial']:.6f} J, final {e['final']:.6f} J, max gain {e['max_gain']:.2e} J, "
                 f"max rise {e['max_rise']:.2e} J")
    h = r.health
    lines.append(f"health: joint drift {h['joint_drift'] * 1e3:.2f} mm, stopper overshoot "
                 f"{h['limit_overshoot_deg']:.2f} deg, hook in a handrail {h['penetration'] * 1e3:.2f} mm (worst)")
    return "\n".join(lines)


def cmd_compare(args) -> int:
    import numpy as np

    from . import compare as cmp

    check_output(args.plot, "--plot", PLOT_SUFFIXES)
    check_output(args.domain_map, "--domain-map", PLOT_SUFFIXES)
    map_masses = sweep_values("--map-masses", args.map_masses, "kg")
    map_ratios = sweep_values("--map-ratios", args.map_ratios, "")
    cfg = load_scene(args)
    summary, runs = cmp.compare(cfg, args.swing)
    which = "swing 0, from rest" if args.swing == 0 else f"swing {args.swing}, caught from a flight"
    if args.plot:
        cmp.plot_comparison(runs, args.plot, title=f"quasi-static vs two-link vs MBD, {which} (dashed: with drag)")
    if args.domain_map:
        masses = np.geomspace(*map_masses[:2], int(map_masses[2])) if map_masses else None
        ratios = np.linspace(*map_ratios[:2], int(map_ratios[2])) if map_ratios else None
        dm = cmp.domain_map(cfg, masses=masses, ratios=ratios)
        cmp.plot_domain_map(dm, args.domain_map, prototype=(cfg.design.m2, cmp.moment_ratio(cfg.design)))
        summary["domain_map"] = dm
    if args.json:
        print(json.dumps(summary, indent=2))
    else:
        st = summary["start"]
        state = (f"theta1 = {st['theta1_deg']:.1f} deg, theta2 = {st['theta2_deg']:.1f} deg, theta1' = "
                 f"{st['omega1']:.2f} rad/s, theta2' = {st['omega2']:.2f} rad/s")
        where = ("the models start from the scene's rest state" if args.swing == 0 else
                 f"the models start {1e3 * st['t']:.1f} ms after the first touch, once the catch has held")
        print(f"{which}: {where}, {state}; compared up to the MBD's detach angle "
              f"{summary['detach_angle_deg']:.1f} deg (times from the catch)")
        print(f"{'model':>13} {'t to angle':>10} {'with drag':>10} {'theta1 where theta1 changes sign':>34} "
              f"{'drag on th1dd':>13}")
        for name, m in summary["models"].items():
            signs = ", ".join(f"{a:.0f}" for a in m["alpha1_sign_changes_deg"]) or "-"
            print(f"{name:>13} {_fmt(m['time_to_detach_angle'], '10.3f')} "
                  f"{_fmt(m['time_to_detach_angle_with_drag'], '10.3f')} {signs:>34} "
                  f"{100 * m['drag_alpha1_change']['relative']:12.2f}%")
        if args.domain_map:
            print(_domain_table(summary["domain_map"]))
        if "paper_points" in summary:
            print("\nthe paper's words on this swing (Sec. 7.3, Figs. 40-43), point by point:")
            print(f"{'point':>24} {'paper':>8} {'+/-':>6} {'MBD':>8} {'unit':>6}  holds")
            for p in summary["paper_points"]:
                tol, holds = p["tolerance"], {True: "yes", False: "NO", None: "not checked"}[p["holds"]]
                print(f"{p['key']:>24} {p['paper_value']:8.2f} {_fmt(tol, '6.2f')} {_fmt(p['ours'], '8.2f')} "
                      f"{p['unit']:>6}  {holds}")
        for name, path in (("plot", args.plot), ("domain map", args.domain_map)):
            if path:
                print(f"wrote {name}: {path}")
    return 0


def sweep_values(option: str, texts, unit: str) -> tuple[float, float, float] | None:
    """LO HI N of a domain-map axis as numbers, LO and HI in ``unit`` with or without a unit as ``--set`` takes them
    (``4g 60g 7`` is 0.004 0.06 7 kg), checked: 0 < LO < HI and N a whole number in [2, 1000]."""
    if texts is None:
        return None
    values = []
    for name, text, in_unit in zip(("LO", "HI", "N"), texts, (unit, unit, "")):
        try:
            v = quantities.parse(text, in_unit)
        except quantities.UnitError as exc:
            raise ConfigError(f"{option} {' '.join(texts)}: {name} = {text!r}: {exc}") from None
        if v is None:
            raise ConfigError(f"{option} {' '.join(texts)}: {name} = {text!r}: must be a number"
                              + (f" ({in_unit}, or with a unit: {', '.join(quantities.units_for(in_unit))})" if in_unit
                                 else ""))
        values.append(v)
    _check_sweep(option, tuple(values))
    return tuple(values)


def _check_sweep(option: str, triple) -> None:
    """LO HI N of a domain-map axis: 0 < LO < HI and N a whole number >= 2."""
    lo, hi, n = triple
    if not 0 < lo < hi:
        raise ConfigError(f"{option} {lo:g} {hi:g} {n:g}: needs 0 < LO < HI")
    if not float(n).is_integer() or not 2 <= n <= 1000:
        raise ConfigError(f"{option} {lo:g} {hi:g} {n:g}: N = {n:g} must be a whole number in [2, 1000]")


def _domain_table(dm) -> str:
    """Per moment ratio: at how many robot masses each model is within tolerance, and the MBD traverses."""
    rows = {}
    for p in dm["points"]:
        rows.setdefault(round(p["ratio"], 4), []).append(p)
    lines = [f"\ndomain map (first swing, from rest): points within {100 * dm['tolerance']:.0f} % of the MBD's time, "
             f"of the robot masses sampled",
             f"{'(m3·La)/(m2·Lb)':>16} {'masses':>7} {'quasi-static':>13} {'two-link':>9} {'MBD traverses':>14}"]
    for ratio, pts in sorted(rows.items()):
        n = len(pts)
        lines.append(f"{ratio:16.3f} {n:7d} {sum(p['quasi_static_within'] for p in pts):13d} "
                     f"{sum(p['two_link_within'] for p in pts):9d} {sum(p['mbd_traverses'] for p in pts):14d}")
    return "\n".join(lines)


def cmd_schema(_args) -> int:
    rows = schema_rows()
    print("Values are SI in the unit shown. In a YAML config and in --set a number may carry its unit instead "
          "(design.m2=7.71g, design.La='48.3 mm', design.spring_k='0.877 N*mm/rad', design.rest_angle_deg='55 deg'); "
          "a plain number is always in the unit shown.\n")
    print("| key | default | unit | allowed | meaning |")
    print("|---|---|---|---|---|")
    for key, default, unit, allowed, doc in rows:
        print(f"| `{key}` | {default} | {unit} | {allowed} | {doc} |")
    return 0


def _scene_command(sub, name: str, help_text: str) -> argparse.ArgumentParser:
    """A subcommand that reads a scene config, with its overrides and a JSON switch."""
    sp = sub.add_parser(name, help=help_text, description=help_text)
    sp.add_argument("config", help="scene YAML (e.g. configs/paper.yaml)")
    sp.add_argument("--set", action="append", metavar="KEY=VALUE",
                    help="override a config value (repeatable); a number may carry its unit, e.g. design.m2=7.71g, "
                         "'design.spring_k=0.877 N*mm/rad' (plain numbers are SI; aero-env schema lists the keys)")
    sp.add_argument("--json", action="store_true", help="print one JSON object instead of the table")
    return sp


def build_parser() -> argparse.ArgumentParser:
    ap = Parser(prog="aero-env", description="The paper-craft aerial acrobat robot, simulated.")
    ap.add_argument("--version", action="version", version=f"%(prog)s {package_version()}",
                    help="print the installed version and exit")
    sub = ap.add_subparsers(dest="command", required=True, metavar="COMMAND")
    sp = _scene_command(sub, "simulate", "run a scene along its row of swing frames")
    sp.add_argument("--trace", metavar="FILE.csv", help="write the time trace as CSV")
    sp.add_argument("--plot", metavar="FILE.png", help="plot theta1 and theta2 against time (the paper's Fig. 40)")
    sp.add_argument("--gif", metavar="FILE.gif", help="animate the machine (env.render_slowmo times slower than real time)")
    sp.add_argument("--labels", action="store_true", help="--gif: name the parts and say the slow-motion factor "
                                                          "(a classroom's animation)")
    sp.set_defaults(func=cmd_simulate)
    cp = _scene_command(sub, "compare", "quasi-static vs two-link vs MBD on one scene (the paper's Figs. 40, 42, 43)")
    cp.add_argument("--swing", type=int, default=1, metavar="N",
                    help="which swing: 0 starts from rest, 1 is the first caught from a flight, "
                         "the swing the paper measures (Sec. 7.3)")
    cp.add_argument("--plot", metavar="FILE.png", help="draw theta, omega and theta'' of the three models")
    cp.add_argument("--domain-map", metavar="FILE.png",
                    help="sweep robot mass and frame energy over the first swing, from rest (the paper's Fig. 29)")
    cp.add_argument("--map-masses", nargs=3, metavar=("LO", "HI", "N"),
                    help="robot masses m2 for the map, log-spaced: kg, or with a unit as --set takes it (4g 60g 7) "
                         "(default: compare.MAP_MASSES, 4-60 g, 7)")
    cp.add_argument("--map-ratios", nargs=3, metavar=("LO", "HI", "N"),
                    help="counterbalance moment / robot moment (m3·La)/(m2·Lb) for the map "
                         "(default: compare.MAP_RATIOS, 0.6-0.95, 8)")
    cp.set_defaults(func=cmd_compare)
    sc = sub.add_parser("schema", help="print the config schema as a Markdown table")
    sc.set_defaults(func=cmd_schema)
    from .bench.commands import register as register_bench
    from .bench.scenes import register as register_scenes
    from .calibration.command import register as register_calibrate
    from .limit_cycle.command import register as register_cycle
    from .robustness.command import register as register_robustness
    from .sheet.command import register as register_sheet

    for register in (register_bench, register_calibrate, register_cycle, register_robustness, register_scenes,
                     register_sheet):
        register(sub, _scene_command)
    for entry in sorted(entry_points(group="aero_env.commands"), key=lambda e: e.name):
        entry.load()(sub, _scene_command)
    return ap


def error_kind(message: str) -> str:
    """What a refusal's line calls itself, by what it names first: ``error`` for a command-line option (as
    argparse's own errors: ``--designs = '0': ...``, ``--plot 'x/p.png': ...``), ``file error`` for a file that
    cannot be read as YAML (``config file 'x.yaml': not found``), ``config error`` for a config key or value
    (``design.Lb = ...``)."""
    if message.startswith("-"):
        return "error"
    if re.match(r"[a-z]+ file '", message):
        return "file error"
    return "config error"


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    try:
        with sigterm_as_interrupt():  # a scheduler's SIGTERM stops the command as Ctrl-C does
            return args.func(args)
    except ConfigError as exc:
        kind = "missing package" if isinstance(exc, MissingExtra) else error_kind(str(exc))
        print(f"aero-env: {kind}: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt as stop:  # commands that keep something (tune, train) say what before this
        print(f"aero-env {args.command}: {signal_name(stop)}", file=sys.stderr)
        return exit_status(stop)
    except BrokenPipeError:  # `aero-env schema | head`: the reader has what it wanted; no traceback
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())  # so the exit's flush cannot raise again
        return 141  # the shell's status for a process ended by SIGPIPE


if __name__ == "__main__":
    sys.exit(main())
