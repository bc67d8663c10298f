"""Print the energy budget of one transfer and the catch that the paper's swing duration implies.

    python scripts/energy_budget.py [CONFIG] [--frame N] [--target 0.62] [--set KEY=VALUE ...] [--json]
    python scripts/energy_budget.py [CONFIG] --sweep KEY=V1,V2,...   # a candidate mechanism's effect

The budget (aero_env/physics/energy_budget.py says how it is booked): at each event of the flight
from frame N-1 and the swing on frame N, the energy of each part in mJ, and what was lost since
the previous event. Then the fraction of the kinetic energy at the catch that the paper's swing
duration (0.62 s, Sec. 7.3) needs, found by rerunning the swing with that energy scaled.

``--sweep`` runs the whole row at each value of one key (a candidate dissipation: the spring's damping,
the skewer's friction) and prints the outcome and the flight-entered swings' median duration and
slip-off angle beside the paper's 0.62 s and 165 deg.
"""

from __future__ import annotations

import argparse
import json
import math

from aero_env.config import load_config
from aero_env.config.loading import parse_override
from aero_env.physics.energy_budget import PARTS, implied_catch_keep, transfer_budget

HEAD = ("robot KE", "robot PE", "spring", "frame KE", "frame PE", "prev KE", "prev PE", "total",
        "loss", "in step", "friction", "prev loss")
RELATIVE = ("robot_pe", "frame_pe", "prev_pe", "total")  # printed as the change since the first event


def table(budget: dict) -> str:
    ev, i = budget["events"], budget["frame"]
    width = max(len(e["event"]) for e in ev)
    lines = [f"frame {i}: energies in mJ (PE and total: change since the first event); 'frame' is frame {i}, "
             f"'prev' frame {i - 1}",
             f"loss: lost by robot, spring and frame {i} since the previous event; in step: of it, in the "
             f"event's own step (an impact); friction: of it, the skewer's and the axle's Coulomb friction; "
             f"prev loss: frame {i - 1}'s",
             f"{'event':<{width}} {'t s':>7} " + " ".join(f"{h:>9}" for h in HEAD)]
    for e in ev:
        vals = [e[k] - (ev[0][k] if k in RELATIVE else 0.0) for k in (*PARTS, "total")]
        vals += [e["loss"], e["loss_in_step"], e["friction"], e["prev_loss"]]
        lines.append(f"{e['event']:<{width}} {e['t']:7.4f} " + " ".join(f"{1e3 * v:9.3f}" for v in vals))
    return "\n".join(lines)


def where_it_goes(budget: dict) -> str:
    """The transfer's losses (robot, spring, caught frame): the impacts by kind, friction and the rest."""
    kinds = {"the arm on its alpha_min stop": "alpha_min", "the hook's touches": "touch",
             "the arm on its alpha_max stop": "alpha_max"}
    ev = budget["events"][1:]
    impact: dict[str, float] = {}
    for e in ev:  # each step's loss once: events of one step (a touch and a strike together) share a label
        label = " and ".join(lab for lab, key in kinds.items() if key in e["event"])
        if label:
            impact[label] = impact.get(label, 0.0) + e["loss_in_step"]
    total, friction = sum(e["loss"] for e in ev), sum(e["friction"] for e in ev)
    rest = total - sum(impact.values()) - friction
    return (f"robot, spring and frame {budget['frame']} lose {1e3 * total:.3f} mJ from detach to detach: in the "
            f"steps of impacts, " + ", ".join(f"{label} {1e3 * v:.3f}" for label, v in impact.items())
            + f"; skewer and axle friction {1e3 * friction:.3f}; the rest (hook friction, contact between the "
            f"events) {1e3 * rest:.3f} mJ")


WHERE = {"catch": "the catch", "alpha_max": "the arm's first strike on (or rest at) its alpha_max stop after the catch"}


def sentence(keep: dict) -> str:
    y, w, where = 1e3 * keep["kept_ke"], 1e3 * keep["flight_ke"], WHERE[keep["at"]]
    if keep["f"] is not None:
        return (f"scaled at {where}: the paper's {keep['target']} s needs the catch to keep {100 * keep['f']:.1f} % "
                f"of the {y:.3f} mJ the world keeps ({1e3 * keep['needed_ke']:.3f} mJ of the flight's {w:.3f} mJ)")
    return (f"scaled at {where}: the paper's {keep['target']} s is out of reach, {keep['note']}; the world keeps "
            f"{y:.3f} mJ of kinetic energy there (the flight brings {w:.3f} mJ)")


def durations(keep: dict) -> str:
    return (f"swing duration with the kinetic energy at {WHERE[keep['at']]} times f: "
            + ", ".join(f"f = {f:g}: {d:.4f} s" for f, d in keep["durations"].items())
            + f" (the simulated swing: {keep['simulated_duration']:.4f} s)")


def sweep(cfg, spec: str) -> str:
    """One line per value of a key: the row's outcome and the flight-entered swings' medians."""
    import numpy as np

    from aero_env.config import ConfigError
    from aero_env.simulation import simulate

    key, _, values = spec.partition("=")
    if not values:
        raise SystemExit(f"error: --sweep {spec!r}: must be KEY=V1,V2,... (e.g. design.spring_damping=0,0.02)")
    lines = [f"{key:>28} {'outcome':>13} {'traversals':>10} {'swing s (median, 1..)':>22} {'slip-off deg':>12}"]
    for v in values.split(","):
        try:
            r = simulate(cfg.replace({key: float(v)}))
        except (ConfigError, ValueError) as exc:
            raise SystemExit(f"error: --sweep {key}={v}: {exc}")
        sw = [s for s in r.swings[1:] if s.swing_duration is not None]
        dur = f"{np.median([s.swing_duration for s in sw]):.3f}" if sw else "-"
        ang = f"{np.median([s.theta1_detach_deg for s in sw]):.1f}" if sw else "-"
        lines.append(f"{v:>28} {r.outcome:>13} {r.traversals:>6} of {r.frames - 1} {dur:>22} {ang:>12}")
    lines.append(f"{'the paper (Sec. 7.3)':>28} {'completed':>13} {'':>10} {'0.62':>22} {'165':>12}")
    return "\n".join(lines)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("config", nargs="?", default="configs/paper.yaml")
    ap.add_argument("--frame", type=int, default=1, help="the flight-entered swing to book (default 1)")
    ap.add_argument("--target", type=float, default=0.62, help="the swing duration to match, s (default 0.62)")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", help="override a config value")
    ap.add_argument("--json", action="store_true", help="print the budget and the keep as JSON")
    ap.add_argument("--sweep", metavar="KEY=V1,V2,...", help="the row at each value of KEY instead of the budget")
    args = ap.parse_args()
    cfg = load_config(args.config, dict(parse_override(s) for s in args.set))
    if args.sweep:
        print(sweep(cfg, args.sweep))
        return
    budget = transfer_budget(cfg, args.frame)
    keeps = [implied_catch_keep(cfg, args.frame, args.target, at) for at in WHERE]
    if args.json:
        keeps = [{**k, "durations": {str(f): d if math.isfinite(d) else None for f, d in k["durations"].items()}}
                 for k in keeps]  # no detach: null
        print(json.dumps({"budget": budget, "keep": keeps}, indent=1))
        return
    print(table(budget))
    print()
    print(f"flight: the robot carries {1e3 * budget['flight_ke']:.3f} mJ of kinetic energy just before the first "
          f"touch (t = {budget['t_first_touch']:.4f} s); robot, spring and frame {args.frame} lose "
          f"{1e3 * budget['catch_loss']:.3f} mJ from then to the catch (t = {budget['t_catch']:.4f} s), where robot "
          f"and frame carry {1e3 * budget['kept_ke']:.3f} mJ of kinetic energy")
    print(where_it_goes(budget))
    for keep in keeps:
        print(durations(keep))
        print(sentence(keep))


if __name__ == "__main__":
    main()
