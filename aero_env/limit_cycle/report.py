"""What ``aero-env cycle`` gives back: one JSON object, and the table made from it.

The object: the scene (``config``, ``frames``, ``last``, ``t_max``, ``fidelity``), the ``row`` (did the
robot reach the last frame; if not, where and why, in the run's own outcome and reason), the
``window`` of catches the statistics cover, one entry per quantity under ``quantities`` (unit,
meaning and :func:`.spread.series_spread`'s statistics), and the verdict ``settled`` with a
sentence ``verdict`` saying why. Every value but ``wall_time`` is the same for the same command.
"""

from __future__ import annotations

from ..results import SimResult
from .catches import CATCH_STATE, QUANTITIES, catch_series, window_of
from .spread import MIN_CATCHES, SETTLE_FACTOR, series_spread

DIGITS = {q.name: q.digits for q in QUANTITIES}  # decimals in the table


def cycle_report(result: SimResult, last: int, config: str | None = None, t_max: float | None = None) -> dict:
    """The ``--json`` object for a run and a window of its ``last`` catches."""
    window = window_of(result, last)
    swings = result.swings
    completed = result.outcome == "completed"
    row = dict(completed=completed, outcome=result.outcome, reason=result.reason, traversals=result.traversals,
               of=result.frames - 1, last_frame=swings[-1].frame if swings else None)
    win = dict(catches=len(window), full=len(window) == last,
               first_frame=swings[window.start].frame if len(window) else None,
               last_frame=swings[window.stop - 1].frame if len(window) else None)
    quantities = {}
    for q in QUANTITIES:
        stats = series_spread(*catch_series(result, q, window))
        quantities[q.name] = dict(label=q.label, unit=q.unit, meaning=q.meaning, catch_state=q.name in CATCH_STATE,
                                  **stats)
    settled, verdict = _verdict(row, win, quantities, last)
    return dict(config=config, frames=result.frames, last=last, t_max=t_max, fidelity=result.fidelity, row=row,
                window=win, quantities=quantities, settled=settled, verdict=verdict, settle_factor=SETTLE_FACTOR,
                sim_time=result.sim_time, wall_time=result.wall_time)


def _verdict(row: dict, win: dict, quantities: dict, last: int) -> tuple[bool, str]:
    if not row["completed"]:
        return False, (f"the row failed after {row['traversals']} of {row['of']} traversals, on frame "
                       f"{row['last_frame']}: {row['outcome']} ({row['reason']})")
    if not win["full"]:
        return False, f"only {win['catches']} catches, fewer than the {last} asked for"
    told = {name: q for name, q in quantities.items() if q["settled"] is not None}
    if not told:
        return False, f"too few catches to tell a trend from the scatter (each quantity needs {MIN_CATCHES})"
    drifting = [name for name, q in told.items() if not q["settled"]]
    if drifting:
        return False, (f"still drifting: {', '.join(drifting)} (trend across the window above "
                       f"{SETTLE_FACTOR:g} std)")
    return True, (f"every quantity's trend across the window is within {SETTLE_FACTOR:g} std "
                  f"({len(told)} quantities, {win['catches']} catches)")


def _num(value, width: int, digits: int) -> str:
    return f"{'-':>{width}}" if value is None else f"{value:{width}.{digits}f}"


def table(doc: dict) -> str:
    """A human-readable summary of :func:`cycle_report`'s object."""
    row, win = doc["row"], doc["window"]
    t_max = f", sim.t_max {doc['t_max']:g} s" if doc["t_max"] is not None else ""
    span = f"frames {win['first_frame']}..{win['last_frame']}" if win["catches"] else "none"
    lines = [f"limit cycle: {doc['config'] or 'scene'}, {doc['frames']} frames{t_max}, fidelity {doc['fidelity']}",
             f"row: {row['outcome']}, {row['traversals']} of {row['of']} traversals ({row['reason']})",
             f"window: the last {win['catches']} catch{'' if win['catches'] == 1 else 'es'} ({span})", "",
             f"{'quantity':<20} {'unit':<6} {'n':>3} {'mean':>9} {'std':>9} {'min':>9} {'max':>9} "
             f"{'trend':>9} {'halves':>9}  settled"]
    for name, q in doc["quantities"].items():
        d = DIGITS.get(name, 4)
        cells = " ".join(_num(q[k], 9, d) for k in ("mean", "std", "min", "max", "trend", "halves"))
        mark = {True: "yes", False: "NO", None: "-"}[q["settled"]]
        lines.append(f"{q['label']:<20} {q['unit']:<6} {q['n']:>3} {cells}  {mark}")
    lines += ["", "trend: the least-squares line's change across the window; halves: mean of the second half "
                  "minus the first",
              f"settled: {'yes' if doc['settled'] else 'NO'}: {doc['verdict']}",
              f"simulated {doc['sim_time']:.3f} s in {doc['wall_time']:.2f} s wall"]
    return "\n".join(lines)

