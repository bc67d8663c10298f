"""What to change when the built toy fails, and by how much, in the maker's words and units: computed by the world
for this design.

A maker who sees the robot stall, fall short, miss a catch or never let go changes one of three things at the
bench: the counterbalance's clay (m3, weighed in g), the spring strip (its width in mm, which sets its stiffness),
or the rest stopper's hole in the crossbeam (mm round its arc about the axis hole, which sets the rest angle).
For each, :func:`windows` walks the design's value outward in both directions, simulating the design's own row at
its own fidelity, until the row no longer completes, then halves the last step down to what a maker can set
(0.1 g of clay, 2 % of the spring, 0.5 deg of rest angle). Each edge names what the maker sees just beyond it;
the walk goes on past the edge to the end of its reach and notes each other thing the maker would see first
further out (a counterbalance heavy enough that the frame never turns, say). The table is keyed by what the
maker sees, in words: the change to make, with a value to aim for (the window's middle), and the window with its
margins, flagged when a margin is narrower than a hand-made toy's tolerance (``aero-env robustness``'s).

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
    further: tuple = ()  # (value, outcome, frame): each other outcome first met further out, on the coarse steps


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
    further, seen = [], {bad_outcome}
    for j in range(int(k) + 1, int(limit + 1e-9) + 1):  # on out, coarse steps: what else the maker could see
        ok, outcome, frame = _completes(cfg, knob.key, at(j))
        if not ok and outcome and outcome not in seen:
            further.append((at(j), outcome, frame))
            seen.add(outcome)
    def steps(v: float) -> float:  # at()'s inverse: how many steps out ``v`` lies
        if knob.additive is not None:
            return (v - base) / (direction * knob.additive)
        return math.log(v / base) / (direction * math.log(knob.factor))

    while True:
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
        # the edge as printed (rounded inwards) must complete too: where the row fails there, between the design and
        # the edge the walk found (the window has a hole), that is the edge, and the halving goes on inside it
        printed = _inward(knob, at(good), -direction)
        if good == 0.0 or not bad_outcome or steps(printed) <= 0.0:
            break
        ok, outcome, frame = _completes(cfg, knob.key, printed)
        if ok or not outcome:
            break
        good, bad, bad_outcome, bad_frame = 0.0, steps(printed), outcome, frame
    return Edge(at(good), bad_outcome, bad_frame, tuple(further))


def windows(cfg: Config) -> dict[str, tuple[Edge, Edge]] | None:
    """Each knob's (lower, upper) edge around the design, or None when the design itself does not complete its
    row (there is no window to report around it)."""
    from ..simulation import simulate

    if simulate(cfg).outcome != "completed":
        return None
    return {k.key: (_edge(cfg, k, -1), _edge(cfg, k, +1)) for k in KNOBS}


_PRINT = {"g": (1e3, 1), "N·mm/rad": (1e3, 3), "deg": (1.0, 1)}  # to the printed unit, decimals


def _inward(knob: Knob, v: float, inward: int) -> float:
    """``v`` rounded to the printed digits towards the inside of a window (``inward`` +1: up, the lower edge; -1:
    down, the upper edge), in the field's unit: the printed edge lies inside the window the walk found."""
    scale, decimals = _PRINT[knob.show]
    x, q = v * scale, 10.0**decimals
    x = math.ceil(x * q - 1e-9) / q if inward > 0 else math.floor(x * q + 1e-9) / q
    return x / scale


def _fmt(knob: Knob, v: float, inward: int = 0) -> str:
    """``v`` in the unit a maker reads; ``inward`` +1 (a window's lower edge) rounds up, -1 rounds down."""
    scale, decimals = _PRINT[knob.show]
    x = (_inward(knob, v, inward) if inward else v) * scale
    return f"{x:.{decimals}f} {knob.show}"


SEEN = {  # what a maker sees for each outcome, in words
    "fell_short": "the robot lets go too early or too low and falls short of the next handrail",
    "missed_catch": "the robot reaches the next handrail but does not hook on (it flies past or bounces off)",
    "no_detach": "the robot never lets go: it rides the frame round to its end stop",
    "stalled": "the robot hangs and the frame never turns, or turns back before the robot lets go",
    "unstable": "(the world could not follow this build: a time step too large for it)",
    "timeout": "(the world ran out of time: report it)",
    "collides": "the frames, or their parts, run into each other as they turn",
}


def seen_text(outcome: str, frame: int) -> str:
    """What the maker sees and where: "... (transfer 2: frame 1 to frame 2)"."""
    return f"{SEEN.get(outcome, outcome)} (transfer {frame + 1}: frame {frame} to frame {frame + 1})"


def tolerance(knob: Knob, cfg: Config) -> tuple[float, str]:
    """(the maker's tolerance on this knob in its field's unit, its reason): aero-env robustness's default."""
    from ..robustness.tolerances import DEFAULT_TOLERANCES

    t = next(t for t in DEFAULT_TOLERANCES if t.name == knob.key)
    return t.relative * abs(cfg.value(knob.key)) + t.absolute, t.reason


def stopper_arc(cfg: Config) -> float:
    """mm round its arc that the rest stopper's hole moves for one degree of rest angle (the hole turns with the
    rest angle about the axis hole, at its distance from it)."""
    from ..parts.build import stopper_offsets

    rest, _ = stopper_offsets(cfg.design)
    return math.hypot(*rest) * 1e3 * math.pi / 180.0


NO_STRIP = "no strip of this card makes it"


def strip_text(cfg: Config, k: float) -> str:
    """The spring strip a maker cuts for stiffness ``k`` (the kit's plan): its width, its free length and stack."""
    from ..parts.kit import spring_plan

    plan = spring_plan(cfg.replace({"design.spring_k": k}))
    if plan.strip is None:
        return NO_STRIP
    st = plan.strip
    return (f"{st.width * 1e3:.1f} mm wide, {st.free_length * 1e3:.1f} mm free"
            + (f", {st.layers} stacked" if st.layers > 1 else ""))


def bench_value(knob: Knob, cfg: Config, v: float, inward: int = 0) -> str:
    """A knob's value as the maker sets it at the bench: g of counterbalance, a strip, a stopper hole's place."""
    if knob.key == "design.m3":
        return _fmt(knob, v, inward)
    if knob.key == "design.spring_k":
        strip = strip_text(cfg, v)
        return (f"a strip {strip} ({_fmt(knob, v, inward)})" if strip != NO_STRIP else
                f"{_fmt(knob, v, inward)} ({strip})")
    arc = (v - cfg.value(knob.key)) * stopper_arc(cfg)
    where = "as drawn" if abs(arc) < 0.05 else f"{abs(arc):.1f} mm {'up' if arc > 0 else 'down'} its arc"
    return f"the hole {where} ({_fmt(knob, v, inward)})"


def past_text(knob: Knob, cfg: Config, value: float, direction: int, far: bool) -> str:
    """Where the maker's build is when it sees a failure: past an edge (``far`` False: just beyond ``value``, the
    window's edge) or out at ``value`` and beyond (``far``: the first coarse step where the walk met it)."""
    field = _fmt(knob, value, 0 if far else -direction)
    side = ("below", "less") if direction < 0 else ("above", "more")
    if knob.key == "design.m3":
        return f"{field} and {side[1]}" if far else f"{side[0]} {field}"
    if knob.key == "design.spring_k":
        strip = strip_text(cfg, value)
        like = f"a strip {strip}" if strip != NO_STRIP else strip
        word = "softer" if direction < 0 else "stiffer"
        return (f"as {word[:-2]} as {like} ({field}) or {word}" if far else f"{word} than {like} ({side[0]} {field})")
    arc = abs(value - cfg.value(knob.key)) * stopper_arc(cfg)
    way = "down" if direction < 0 else "up"
    return (f"the hole {arc:.1f} mm or more {way} its arc ({field} and {side[1]})" if far else
            f"the hole more than {arc:.1f} mm {way} its arc ({side[0]} {field})")


PART = {"design.m3": "counterbalance", "design.spring_k": "spring strip",
        "design.rest_angle_deg": "rest stopper's hole (the rest angle)"}
TOO = {("design.m3", -1): "counterbalance too light", ("design.m3", 1): "counterbalance too heavy",
       ("design.spring_k", -1): "spring too soft", ("design.spring_k", 1): "spring too stiff",
       ("design.rest_angle_deg", -1): "rest angle too low", ("design.rest_angle_deg", 1): "rest angle too high"}
FIX = {("design.m3", -1): "add clay", ("design.m3", 1): "take clay off",
       ("design.spring_k", -1): "cut a wider strip", ("design.spring_k", 1): "cut a narrower strip",
       ("design.rest_angle_deg", -1): "move the rest stopper's hole up its arc round the axis hole",
       ("design.rest_angle_deg", 1): "move the rest stopper's hole down its arc round the axis hole"}


def table(cfg: Config) -> list[str]:
    """The troubleshooting tables, markdown: what a maker sees (in words), its likely cause and the change at the
    bench, keyed by what is seen; then each part's window, with its margins against a hand-made toy's tolerance."""
    w = windows(cfg)
    if w is None:
        return ["This design does not complete its row in the world, so there is no window around it to "
                "troubleshoot: tune it first (`aero-env tune`)."]
    rows: dict[str, list[str]] = {}
    parts = ["| part | the row completes with | yours | margins (down / up) | a hand-made toy |",
             "|---|---|---|---|---|"]
    for knob in KNOBS:
        lo, hi = w[knob.key]
        here = cfg.value(knob.key)
        walked = (knob.reach if knob.additive is not None else None)
        low_v = lo.value if lo.value is not None else (here - walked if walked else here / knob.reach)
        high_v = hi.value if hi.value is not None else (here + walked if walked else here * knob.reach)
        low_end = bench_value(knob, cfg, low_v, +1) + ("" if lo.value is not None else " or less")
        high_end = bench_value(knob, cfg, high_v, -1) + ("" if hi.value is not None else " or more")
        tol, reason = tolerance(knob, cfg)
        scale, decimals = _PRINT[knob.show]
        # the margins between yours and the printed edges (which lie inside the window)
        down, up = here - _inward(knob, low_v, +1), _inward(knob, high_v, -1) - here
        fits = ("fits" if min(down, up) >= tol else
                "**does not fit: the window is narrower; build this part with care**")
        parts.append(f"| {PART[knob.key]} | {low_end} to {high_end} | {bench_value(knob, cfg, here)} | "
                     f"{_fmt(knob, down)} / {_fmt(knob, up)} | ±{tol * scale:.{decimals}f} "
                     f"{knob.show} ({reason}): {fits} |")
        aim = bench_value(knob, cfg, 0.5 * (low_v + high_v))
        for direction, edge in ((-1, lo), (1, hi)):
            # past this edge the maker sees its outcome, and further out the others met on the walk's coarse steps
            found = [(edge.outcome, edge.frame, edge.value, "")] if edge.outcome else []
            found += [(o, f, v, "far ") for v, o, f in edge.further]
            for outcome, frame, value, far in found:
                cause = TOO[(knob.key, direction)].replace("too", "far too") if far else TOO[(knob.key, direction)]
                where = past_text(knob, cfg, value, direction, bool(far))
                rows.setdefault(seen_text(outcome, frame), []).append(
                    f"{cause}: {where} | {FIX[(knob.key, direction)]}: aim for {aim}")
    lines = ["| you see | likely cause (this design, in the world) | change at the bench |", "|---|---|---|"]
    for seen in sorted(rows):
        for change in rows[seen]:
            lines.append(f"| {seen} | {change} |")
    return lines + ["", *parts]


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
