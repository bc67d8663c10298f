"""What a robustness study reports: the share of builds that complete the row (with its Wilson
interval), the outcome counts, and which parameters matter, two ways:

* **single changes**: each tolerance alone at its -end and +end, everything else nominal;
  listed worst first (fewest traversals, then table order), a change that breaks the row
  (traversals below a full row) marked.
* **effects**: from the random draws, the share of completed builds among draws whose factor u
  for that tolerance lies in the lower half of its range (u < 0) against the upper half
  (u >= 0); ``difference = share_high - share_low``, largest ``|difference|`` first. The mean
  traversals of each half come beside it (``traversals_difference`` breaks ties), which still
  ranks the parameters when no draw, or every draw, completes the row.
"""

from __future__ import annotations

from collections import Counter

from ..config import real_field
from ..intervals import wilson_interval
from .draws import INVALID
from .study import Study

MAX_INVALID_REASONS = 3  # distinct invalid-build messages quoted in the report


def _share(flags: list[bool]) -> float | None:
    return sum(flags) / len(flags) if flags else None


def _mean(xs: list[int]) -> float | None:
    return sum(xs) / len(xs) if xs else None


def _diff(lo: float | None, hi: float | None) -> float | None:
    return None if lo is None or hi is None else hi - lo


def _effect(study: Study, j: int) -> dict:
    """One tolerance's effect: completion share and mean traversals in the lower vs upper half of its range."""
    runs, u = study.runs, study.factors[:, j]
    low = [r.traversals for r, x in zip(runs, u) if x < 0.0]
    high = [r.traversals for r, x in zip(runs, u) if x >= 0.0]
    lo, hi = _share([t >= study.full for t in low]), _share([t >= study.full for t in high])
    return dict(name=study.tols[j].name, share_low=lo, share_high=hi, difference=_diff(lo, hi),
                n_low=len(low), n_high=len(high), traversals_low=_mean(low), traversals_high=_mean(high),
                traversals_difference=_diff(_mean(low), _mean(high)))


def effects(study: Study) -> list[dict]:
    """Per varied tolerance, largest |difference| in completion share first (then in mean traversals)."""
    rows = [_effect(study, j) for j, t in enumerate(study.tols) if not t.zero]

    def key(i: int):
        d, dt = rows[i]["difference"], rows[i]["traversals_difference"]
        return d is None, -abs(d or 0.0), -abs(dt or 0.0), i

    return [rows[i] for i in sorted(range(len(rows)), key=key)]


def single_changes(study: Study) -> list[dict]:
    """Each tolerance alone at each end, worst first (fewest traversals, then table order)."""
    rows = []
    for c in study.singles:
        nominal = float(study.cfg.value(c.tol.name))
        value = c.build.values[c.tol.name]
        rows.append(dict(name=c.tol.name, end="+" if c.end > 0 else "-", value=value, delta=value - nominal,
                         traversals=c.run.traversals, outcome=c.run.outcome, breaks=c.run.traversals < study.full))
    order = sorted(range(len(rows)), key=lambda i: (rows[i]["traversals"], i))
    return [rows[i] for i in order]


def summarize(study: Study, wall_time: float) -> dict:
    """The ``aero-env robustness --json`` object."""
    n = len(study.runs)
    k = sum(r.traversals >= study.full for r in study.runs)
    invalid = [r.reason for r in study.runs if r.outcome == INVALID]
    return dict(draws=n, completed=k, share=k / n, share_ci95=list(wilson_interval(k, n)),
                outcomes=dict(sorted(Counter(r.outcome for r in study.runs).items())),
                full_traversals=study.full, fidelity=study.cfg.sim.fidelity,
                nominal=dict(traversals=study.nominal.traversals, outcome=study.nominal.outcome,
                             reason=study.nominal.reason),
                single_changes=single_changes(study), effects=effects(study),
                invalid_reasons=list(dict.fromkeys(invalid))[:MAX_INVALID_REASONS],
                tolerances=[t.to_json() for t in study.tols], seed=study.seed, wall_time=wall_time)


# ---- the table ----
def _pct(x: float | None) -> str:
    return "-" if x is None else f"{100 * x:.1f} %"


def _unit(name: str) -> str:
    unit = real_field(name, "name").metadata["unit"]
    return "" if unit == "-" else unit


def _tol_text(t: dict) -> str:
    parts = ([f"±{100 * t['relative']:g} %"] if t["relative"] else []) + (
        [f"±{t['absolute']:g} {_unit(t['name'])}".rstrip()] if t["absolute"] else [])
    spec = " + ".join(parts) or "0"
    link = f"{spec}, with {', '.join(t['linked'])}" if t["linked"] else spec
    return f"  {t['name']:<24} {link:<18}  {t['reason']}"


def _header(r: dict) -> list[str]:
    lo, hi = r["share_ci95"]
    nom = r["nominal"]
    outcomes = ", ".join(f"{k} {v}" for k, v in r["outcomes"].items())
    lines = [f"{r['draws']} builds drawn within {len(r['tolerances'])} tolerances (seed {r['seed']}), fidelity "
             f"{r['fidelity']}, {r['wall_time']:.1f} s wall",
             f"nominal build: {nom['outcome']}, {nom['traversals']} of {r['full_traversals']} traversals",
             f"completed the row: {r['completed']} of {r['draws']} builds = {_pct(r['share'])} "
             f"(95 % Wilson interval {_pct(lo)} .. {_pct(hi)})",
             f"outcomes: {outcomes}"]
    return lines + [f"  invalid build: {why}" for why in r["invalid_reasons"]]


def _single_lines(r: dict) -> list[str]:
    rows, nom, full = r["single_changes"], r["nominal"], r["full_traversals"]
    broken = [c for c in rows if c["breaks"]]
    lines = ["", f"single changes: each tolerance alone at its -/+ end, all else nominal: {len(broken)} of "
                 f"{len(rows)} break the row"]
    shown = broken
    if nom["traversals"] < full:  # every change "breaks" a row the nominal build already fails: show what differs
        shown = [c for c in rows if (c["traversals"], c["outcome"]) != (nom["traversals"], nom["outcome"])]
        lines.append(f"  the nominal build itself fails ({nom['outcome']}, {nom['traversals']} of {full}); listed: "
                     f"the changes whose traversals or outcome differ from it ({len(shown)})")
    if shown:
        lines.append(f"  {'parameter':<24} {'end':>3} {'delta':>20} {'traversals':>10}  outcome")
    for c in shown:
        delta = f"{c['delta']:+.4g} {_unit(c['name'])}".rstrip()
        lines.append(f"  {c['name']:<24} {c['end']:>3} {delta:>20} {c['traversals']:>5} of {full:<3} {c['outcome']}")
    if shown and len(shown) < len(rows):
        lines.append(f"  the other {len(rows) - len(shown)} " + ("keep the full row" if shown is broken else
                                                                 "end like the nominal build"))
    return lines


def _effect_lines(r: dict) -> list[str]:
    lines = ["", "effects in the random draws: share completing the row (and mean traversals) with the parameter in "
                 "the lower vs upper half of its range, largest difference first",
             f"  {'parameter':<24} {'lower half':>20} {'upper half':>20} {'difference':>17}"]
    for e in r["effects"]:
        diff = "-" if e["difference"] is None else f"{100 * e['difference']:+.1f} %"
        dt = "" if e["traversals_difference"] is None else f" ({e['traversals_difference']:+.2f})"
        halves = [f"{_pct(e['share_' + h]):>8} ({_mean_text(e['traversals_' + h])}) n={e['n_' + h]:<3}"
                  for h in ("low", "high")]
        lines.append(f"  {e['name']:<24} {halves[0]:>20} {halves[1]:>20} {diff + dt:>17}")
    return lines


def _mean_text(x: float | None) -> str:
    return "-" if x is None else f"{x:.2f}"


def table(r: dict) -> str:
    tol_lines = ["", "tolerances (uniform draws):"] + [_tol_text(t) for t in r["tolerances"]]
    return "\n".join(_header(r) + _single_lines(r) + _effect_lines(r) + tol_lines)
