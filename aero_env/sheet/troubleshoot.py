"""What to change when the built toy fails, and by how much: computed by the world for this design.

A maker who sees the robot stall, fall short, miss a catch or never let go changes one of three
things at the bench: the counterbalance's clay (m3), the spring strip (its stiffness), or the
stopper skewer that holds the frame's rest angle. For each, :func:`windows` walks the design's
value outward in both directions, simulating the design's own row at its own fidelity, until the
row no longer completes, then halves the last step down to what a maker can set (0.1 g of clay,
2 % of the spring, 0.5 deg of rest angle). Each edge of the window names the outcome just beyond
it, so the table is keyed by what the maker sees: that outcome, the part that leads there, which
way to change it, and the window the row completes in.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..config import Config, ConfigError


@dataclass(frozen=True)
class Knob:
    key: str
    what: str  # the part at the bench
    additive: float | None  # coarse step, in the field's unit (None: multiplicative)
    factor: float | None  # coarse factor for multiplicative steps
    resolution: float  # the halving stops at this (absolute, or relative for multiplicative knobs)
    reach: float  # how far to walk: absolute, or the factor's bound
    show: str  # how to print a value


KNOBS = (
    Knob("design.m3", "counterbalance (clay)", 5e-4, None, 1e-4, 5e-3, "g"),
    Knob("design.spring_k", "spring strip", None, 1.25, 0.02, 4.0, "N·mm/rad"),
    Knob("design.rest_angle_deg", "rest angle (the stopper skewer)", 2.0, None, 0.5, 15.0, "deg"),
)


@dataclass(frozen=True)
class Edge:
    value: float | None  # the last value that still completes the row (None: the walk reached its reach)
    outcome: str  # just beyond it ("" when the walk never failed)
    frame: int  # the transfer that failed (traversals so far)


def _completes(cfg: Config, key: str, value: float) -> tuple[bool, str, int]:
    from ..simulation import simulate

    try:
        c = cfg.replace({key: value})
    except ConfigError:
        return False, "", -1  # outside what the config allows: the walk's end, no outcome to report
    r = simulate(c)
    return r.outcome == "completed", r.outcome, r.traversals


def _edge(cfg: Config, knob: Knob, direction: int) -> Edge:
    base = cfg.value(knob.key)

    def at(k: float) -> float:
        if knob.additive is not None:
            return base + direction * knob.additive * k
        return base * knob.factor ** (direction * k)

    good, k, limit = 0.0, 1.0, (knob.reach / knob.additive if knob.additive else math.log(knob.reach, knob.factor))
    bad_outcome, bad_frame = "", -1
    while k <= limit + 1e-9:
        ok, outcome, frame = _completes(cfg, knob.key, at(k))
        if not ok:
            bad_outcome, bad_frame = outcome, frame
            break
        good, k = k, k + 1.0
    else:
        return Edge(None, "", -1)
    bad = k
    # halve between the last value that completes and the first that does not, to the maker's resolution
    while True:
        lo, hi = at(good), at(bad)
        gap = abs(hi - lo) if knob.additive is not None else abs(hi / lo - 1.0)
        if gap <= knob.resolution or not bad_outcome:
            break
        mid = 0.5 * (good + bad)
        ok, outcome, frame = _completes(cfg, knob.key, at(mid))
        if ok:
            good = mid
        elif outcome:
            bad, bad_outcome, bad_frame = mid, outcome, frame
        else:
            bad = mid
    return Edge(at(good), bad_outcome, bad_frame)


def windows(cfg: Config) -> dict[str, tuple[Edge, Edge]] | None:
    """Each knob's (lower, upper) edge around the design, or None when the design itself does not complete its
    row (there is no window to report around it)."""
    from ..simulation import simulate

    if simulate(cfg).outcome != "completed":
        return None
    return {k.key: (_edge(cfg, k, -1), _edge(cfg, k, +1)) for k in KNOBS}


_PRINT = {"g": (1e3, 1), "N·mm/rad": (1e3, 3), "deg": (1.0, 1)}  # to the printed unit, decimals


def _fmt(knob: Knob, v: float, inward: int = 0) -> str:
    """``v`` in the unit a maker reads; ``inward`` +1 (a window's lower edge) rounds up, -1 rounds down, so the
    printed edge lies inside the window the walk found."""
    scale, decimals = _PRINT[knob.show]
    x, q = v * scale, 10.0**decimals
    x = math.ceil(x * q - 1e-9) / q if inward > 0 else math.floor(x * q + 1e-9) / q if inward < 0 else x
    return f"{x:.{decimals}f} {knob.show}"


_WAY = {("design.m3", -1): "lighter: take clay off", ("design.m3", 1): "heavier: add clay",
        ("design.spring_k", -1): "softer: a narrower strip", ("design.spring_k", 1): "stiffer: a wider strip",
        ("design.rest_angle_deg", -1): "lower: move the stopper down", ("design.rest_angle_deg", 1):
        "higher: move the stopper up"}


def table(cfg: Config) -> list[str]:
    """The troubleshooting table, markdown rows, keyed by the outcome a maker sees."""
    w = windows(cfg)
    if w is None:
        return ["This design does not complete its row in the world, so there is no window around it to "
                "troubleshoot: tune it first (`aero-env tune`)."]
    rows: dict[str, list[str]] = {}
    for knob in KNOBS:
        lo, hi = w[knob.key]
        here = _fmt(knob, cfg.value(knob.key))
        walked = (knob.reach if knob.additive is not None else None)
        low_end = _fmt(knob, lo.value, +1) if lo.value is not None else (
            f"{_fmt(knob, cfg.value(knob.key) - walked if walked else cfg.value(knob.key) / knob.reach)} or less")
        high_end = _fmt(knob, hi.value, -1) if hi.value is not None else (
            f"{_fmt(knob, cfg.value(knob.key) + walked if walked else cfg.value(knob.key) * knob.reach)} or more")
        window = f"{low_end} to {high_end}"
        for direction, edge in ((-1, lo), (1, hi)):
            if not edge.outcome:
                continue
            seen = f"{edge.outcome} (transfer {edge.frame + 1})"
            # the maker sees the outcome past this edge: the way back into the window is the other direction
            rows.setdefault(seen, []).append(
                f"{knob.what}: {_WAY[(knob.key, -direction)]} | {window} (yours: {here})")
    lines = ["| you see | change | the row completes (this design, in the world) |", "|---|---|---|"]
    for seen in sorted(rows):
        for change in rows[seen]:
            lines.append(f"| {seen} | {change} |")
    return lines


def frame_balance(cfg: Config) -> str:
    """The frame's bench check: held level by its skewer, counterbalance and handrail on, no robot, how many one-yen
    coins on the handrail's seat tip it seat-down (its counterbalance's moment against the seat's lever)."""
    from ..parts.build import YEN_COIN

    from ..units import GRAVITY

    d = cfg.design
    # held level, the moments about the skewer: the counterbalance's (at La) against the handrail's card and n coins
    # at the seat (at Lb), and the frame's own dT (positive turns it seat-down, as the robot does)
    n = (d.m3 * d.La - d.handrail_mass * d.Lb - d.dT / GRAVITY) / (YEN_COIN * d.Lb)
    lo = math.ceil(n) - 1  # the most coins that still leave it counterbalance-down
    return (f"hold the frame level on its skewer, counterbalance and handrail on: with {lo} one-yen coins on the "
            f"handrail's seat it still turns counterbalance-down, with {lo + 1} seat-down (it balances at {n:.1f})")
