"""The ``aero-env calibrate`` subcommand.

    aero-env calibrate CONFIG (--trace FILE.csv | --targets FILE.yaml) --fit KEY=LOW:HIGH [--fit ...]
                       [--swing N] [--trials N] [--seed S] [--out calibrated.yaml] [--json] [--plot FILE.png]
                       [--set KEY=VALUE ...]

Every input is checked before the first simulation (one line naming the field, the value and
what is allowed, exit 2): the options, the output folders, the scene, the reference file, the
``--fit`` ranges and every corner of their box, and that the scene has a swing N that can end in
a slip-off. A fit whose best trial still has no usable swing N (a miss) is reported, writes no
``--out`` and exits 1.
"""

from __future__ import annotations

import json
import sys

from ..config import Config, ConfigError, pymunk_fidelities
from ..scene_args import add_seed, check_not_the_config, check_output, whole_number
from . import report
from .fit import check_box, fit, parse_fits, require_optuna
from .measured import MeasuredSwing, load_measured
from .targets import load_targets

DEFAULT_SWING = 1  # the first swing entered from a flight: the one the paper measures (Sec. 7.3)
DEFAULT_TRIALS = 60
MAX_TRIALS = 100_000
MAX_SWING = 100_000  # far beyond any row; the scene's frames bound it
PLOT_SUFFIXES = (".png", ".pdf", ".svg")


def register(sub, scene_command) -> None:
    cp = scene_command(sub, "calibrate", "fit the model's unknowns to a measured swing (--trace) or to the "
                                         "paper's figures (--targets)")
    cp.add_argument("--trace", metavar="FILE.csv", help="a measured swing: columns t (s, 0 at the catch), theta1_deg, "
                    "optional theta2_deg, rows until the slip-off (a Kinovea export); or a whole run written by "
                    "aero-env simulate --trace (the --swing's rows are taken)")
    cp.add_argument("--targets", metavar="FILE.yaml", help="figures with tolerances, e.g. configs/paper_targets.yaml")
    cp.add_argument("--fit", action="append", metavar="KEY=LOW:HIGH",
                    help="a real-valued design or scene key and its search range (repeatable; one key: grid + "
                         "golden section, several: CMA-ES)")
    cp.add_argument("--swing", metavar="N", help=f"the swing to fit (default: the targets file's swing, else "
                    f"{DEFAULT_SWING}: the first one entered from a flight; 0 starts from rest). Tip: --set "
                    f"scene.frames=N+2 ends each run soon after swing N")
    cp.add_argument("--trials", metavar="N", default=str(DEFAULT_TRIALS),
                    help=f"simulations the search may run (default {DEFAULT_TRIALS})")
    add_seed(cp, 0, "CMA-ES seed (default 0; a one-key fit needs none)")
    cp.add_argument("--out", metavar="FILE.yaml", help="write the whole config with the fitted values")
    cp.add_argument("--plot", metavar="FILE.png", help="the fitted angles against the measurement or targets")
    cp.set_defaults(func=cmd_calibrate)


def cmd_calibrate(args) -> int:
    from ..scene_args import load_scene

    trials = whole_number("--trials", args.trials, 1, MAX_TRIALS)
    seed = args.seed
    check_output(args.out, "--out", (".yaml", ".yml"))
    check_not_the_config(args.out, "--out", args.config)
    check_output(args.plot, "--plot", PLOT_SUFFIXES)
    reference = _reference(args)
    cfg = load_scene(args)
    keys = parse_fits(args.fit)
    check_box(cfg, keys)
    swing = _swing(args.swing, reference, cfg)
    if isinstance(reference, MeasuredSwing):
        reference = reference.swing_of(swing)  # a whole run (simulate --trace): that swing's rows
    _check_traceable(cfg)
    if len(keys) > 1:
        require_optuna()

    show = sys.stderr.isatty()
    result = fit(cfg, keys, reference, swing, trials, seed, progress=_progress if show else None)
    if show:
        print(file=sys.stderr)
    doc = report.to_json_dict(result, reference, swing, seed)
    if args.out and not doc["miss"]:  # a miss has no calibrated values to write
        report.write_config(cfg, result, doc, args.out)
    if args.plot:
        report.plot_fit(doc, result.best.swing, reference, args.plot)
    print(json.dumps(doc, indent=2) if args.json else report.table(doc))
    if not args.json:
        for name, path in (("calibrated config", None if doc["miss"] else args.out), ("plot", args.plot)):
            if path:
                print(f"wrote {name}: {path}")
    return 1 if doc["miss"] else 0



def _reference(args):
    if bool(args.trace) == bool(args.targets):
        raise ConfigError("calibrate: give exactly one of --trace FILE.csv (a measured swing) or --targets FILE.yaml "
                          "(figures with tolerances)")
    return load_measured(args.trace) if args.trace else load_targets(args.targets)


def _swing(text, reference, cfg: Config) -> int:
    """--swing, else the targets file's swing, else DEFAULT_SWING; it must be able to end in a slip-off."""
    last = cfg.scene.frames - 2  # the last frame's catch ends the run: its swing never slips off
    if text is not None:
        swing = whole_number("--swing", text, 0, MAX_SWING)
    else:
        swing = getattr(reference, "swing", None)
        swing = DEFAULT_SWING if swing is None else swing
    if swing > last:
        raise ConfigError(f"--swing {swing}: scene.frames = {cfg.scene.frames} has swings 0..{last} that end in a "
                          f"slip-off (the last frame's catch ends the run), allowed [0, {last}]")
    return swing


def _check_traceable(cfg: Config) -> None:
    if cfg.sim.model != "mbd":
        raise ConfigError(f"sim.fidelity = {cfg.sim.fidelity!r}: calibrate needs a trace, which only the pymunk "
                          f"fidelities record ({pymunk_fidelities()})")


def _progress(done: int, best: float) -> None:
    print(f"\r  trial {done}: best score {best:.4g}", end="", file=sys.stderr, flush=True)
