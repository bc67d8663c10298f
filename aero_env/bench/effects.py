"""``aero-env bench effects``: what each effect a scene can switch on costs, and what it changes.

Each effect is toggled against the scene as configured, on the same designs and at the scene's
own fidelity; everything else stays as it is:

| effect                    | scene as configured (paper.yaml)  | toggled                       |
|---------------------------|-----------------------------------|-------------------------------|
| ``drag``                  | ``effects.drag: false``           | ``true``                      |
| ``static_kinetic``        | ``effects.friction: static_kinetic`` | ``kinetic`` (one coefficient, no per-step switch) |
| ``live_frames``           | ``effects.live_frames: 1``        | ``3`` (two more frames in the space) |
| ``pivot_friction``        | ``design.pivot_friction: 1.185e-4``| ``0`` (no motor at any skewer) |
| ``axle_friction``         | ``design.axle_friction: 4.5e-5``  | ``0`` (no motor at the arm's axle) |
| ``spring_damping``        | ``design.spring_damping: 0``      | ``0.02`` (a card spring's loss)  |
| ``clearance``             | ``effects.clearance: false``      | ``true`` (the kit swept first)   |

``clearance`` is timed cold: each design's first check (its layout fitted, its row swept), once per design, with
nothing kept from an earlier design; a design seen again (another seed, the same row) costs only its run.
The two dry frictions are design values, not switches: "on" is each drawn design's own value
(``SCENE_VALUE``), "off" is 0, which builds no part (see ``physics.swing_frame.coulomb_friction``).

For each: the median wall time per design with the effect and without it, their ratio (the
effect's cost), and the designs whose traversal count the effect changes.
"""

from __future__ import annotations

from ..config import Config, ConfigError
from ..parts.clearance import forget_verdicts
from ..physics.kernels import load_kernels
from ..simulation import simulate
from .designs import check_counts, draw_designs, median_time

SCENE_VALUE = "as configured"  # "on" is the design's own value of the key

EFFECTS = {
    "drag": ("scene.effects.drag", True, False),
    "static_kinetic": ("scene.effects.friction", "static_kinetic", "kinetic"),
    "live_frames": ("scene.effects.live_frames", 3, 1),
    "pivot_friction": ("design.pivot_friction", SCENE_VALUE, 0.0),
    "axle_friction": ("design.axle_friction", SCENE_VALUE, 0.0),
    # the leaf spring card's internal loss, a damping ratio of the size paper's loss tangent gives
    "spring_damping": ("design.spring_damping", 0.02, 0.0),
    "clearance": ("scene.effects.clearance", True, False),
}
COLD = ("clearance",)  # effects whose cost is a design's first check: timed once, nothing kept from before


def pick_effects(text: str | None) -> tuple[str, ...]:
    """``--effects``: the named effects in :data:`EFFECTS`' order (None: every one); a name that is none of them is
    a one-line ConfigError naming the allowed ones."""
    if text is None:
        return tuple(EFFECTS)
    names = [n.strip() for n in text.split(",") if n.strip()]
    unknown = [n for n in names if n not in EFFECTS]
    if unknown or not names:
        raise ConfigError(f"--effects {text!r}: {', '.join(unknown) or 'no name'} is not an effect; allowed: "
                          f"{', '.join(EFFECTS)}")
    return tuple(n for n in EFFECTS if n in names)


def effects(cfg: Config, designs: int = 30, seed: int = 0, repeats: int = 3, names=tuple(EFFECTS)) -> dict:
    check_counts(designs=designs, repeats=repeats)
    sample = draw_designs(cfg, designs, seed)
    load_kernels()  # the pymunk world's compiled parts load once, outside every timed run
    rows = []
    for name, (key, on, off) in ((n, EFFECTS[n]) for n in names):
        walls = {"on": 0.0, "off": 0.0}
        traversals = {"on": [], "off": []}
        for c in sample.configs:
            for state, value in (("on", on), ("off", off)):
                run_cfg = c if value is SCENE_VALUE else c.replace({key: value})
                if name in COLD and state == "on":  # this design's first check, the others' kept as they were
                    forget_verdicts(run_cfg)
                wall, r = median_time(lambda: simulate(run_cfg), 1 if name in COLD else repeats)
                walls[state] += wall
                traversals[state].append(r.traversals)
        changed = [i for i, (a, b) in enumerate(zip(traversals["on"], traversals["off"])) if a != b]
        rows.append(dict(effect=name, key=key, on=on, off=off, scene=cfg.value(key),
                         wall_per_design_on=walls["on"] / designs, wall_per_design_off=walls["off"] / designs,
                         cost_ratio=walls["on"] / walls["off"], outcomes_changed=len(changed),
                         changed_designs=changed))
    return dict(designs=designs, seed=seed, repeats=repeats, fidelity=cfg.sim.fidelity, effects=rows)


def table(report: dict) -> str:
    lines = [f"{report['designs']} designs (seed {report['seed']}) at fidelity {report['fidelity']}, median of "
             f"{report['repeats']} runs each",
             f"{'effect':>15} {'on':>15} {'off':>15} {'s/design on':>12} {'s/design off':>13} {'cost':>6} "
             f"{'outcomes changed':>17}"]
    for r in report["effects"]:
        lines.append(f"{r['effect']:>15} {str(r['on']):>15} {str(r['off']):>15} {r['wall_per_design_on']:12.4f} "
                     f"{r['wall_per_design_off']:13.4f} {r['cost_ratio']:5.2f}x "
                     f"{r['outcomes_changed']:>8} of {report['designs']}")
    return "\n".join(lines)
