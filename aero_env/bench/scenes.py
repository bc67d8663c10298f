"""``aero-env scenes``: the suite of scenes that search is measured on, each with a design known to solve it.

    aero-env scenes [--dir configs/scenes] [--designs N] [--seed S] [--workers W] [--no-reference] [--json]

A scene is a config in ``--dir`` (a maker's situation: a steeper row, the slippery card, a heavier
robot...); its solution is the complete config ``solutions/NAME.yaml`` beside it, a design that
search found (``aero-env tune``) with the scene itself left as it is. For each scene the command
reports what a benchmark needs to mean something:

- ``prototype_traversals``: the scene as given (the paper's design in the maker's situation);
- ``random_full_row_share``: the share of ``--designs`` designs drawn uniformly from the scene's
  action box that complete the row (its difficulty: what search must beat);
- ``solution_traversals``: the stored solution at the scene's own fidelity (``mbd``) and re-checked
  at ``reference``, so the answer is not an artefact of the step;
- ``solution_kit``: whether the kit drawn for the stored solution clears as its frames turn
  (:func:`aero_env.parts.clearance.kit_clearance`, what ``scene.effects.clearance`` asks): ``clears``, or
  ``collides`` and its first meeting, so a solution a maker cannot build is seen as such.

A scene without a stored solution is listed with ``solution: null``: it is not a benchmark.
"""

from __future__ import annotations

import json
import os
import time
from dataclasses import asdict, dataclass
from pathlib import Path

from ..config import ConfigError, load_config
from ..design_space import changes_outside_tunables
from ..process_pool import worker_pool
from ..scene_args import add_seed
from .designs import check_counts, draw_designs

DEFAULT_DIR = "configs/scenes"
DEFAULT_DESIGNS = 100
DEFAULT_SEED = 0
REFERENCE = "reference"


@dataclass(frozen=True)
class SceneFigures:
    name: str
    config: str
    full_row: int  # traversals that make the whole row
    prototype_traversals: int
    prototype_outcome: str
    random_designs: int
    random_full_row_share: float
    solution: str | None
    solution_traversals: dict  # fidelity -> traversals
    solution_changes_scene: list  # keys outside the scene's tunables that the solution changed (none: a fair answer)
    solution_kit: str = ""  # "clears", or "collides: " and the first meeting of the solution's kit's parts


def scene_paths(folder: str | os.PathLike) -> list[Path]:
    """The suite's scene configs, by name; refuses a folder with none."""
    d = Path(folder)
    if not d.is_dir():
        raise ConfigError(f"--dir {str(folder)!r}: not a folder of scene configs")
    paths = sorted(d.glob("*.yaml"))
    if not paths:
        raise ConfigError(f"--dir {str(folder)!r}: holds no scene (*.yaml)")
    return paths


def solution_path(scene: Path) -> Path:
    return scene.parent / "solutions" / scene.name


def _traversals(cfg) -> tuple[int, str]:
    from ..simulation import simulate

    r = simulate(cfg)
    return r.traversals, r.outcome


def measure(scene: Path, designs: int, seed: int, pool, reference: bool) -> SceneFigures:
    cfg = load_config(scene)
    full = cfg.scene.frames - 1
    proto, outcome = _traversals(cfg)
    sample = draw_designs(cfg, designs, seed)
    runs = list(pool.map(_traversals, sample.configs)) if pool else [_traversals(c) for c in sample.configs]
    share = sum(t == full for t, _ in runs) / designs
    sol, sol_traversals, changed, kit = solution_path(scene), {}, [], ""
    if sol.exists():
        solved = load_config(sol)
        changed = changes_outside_tunables(cfg, solved)
        sol_traversals[solved.sim.fidelity] = _traversals(solved)[0]
        if reference:
            sol_traversals[REFERENCE] = _traversals(load_config(sol, {"sim.fidelity": REFERENCE}))[0]
        kit = _kit(solved)
    return SceneFigures(scene.stem, str(scene), full, proto, outcome, designs, share,
                        str(sol) if sol.exists() else None, sol_traversals, changed, kit)


def _kit(cfg) -> str:
    from ..parts.clearance import kit_clearance

    verdict = kit_clearance(cfg)
    return "clears" if verdict.clears else f"collides: {verdict.first.line()}"


def suite(folder: str | os.PathLike = DEFAULT_DIR, designs: int = DEFAULT_DESIGNS, seed: int = DEFAULT_SEED,
          workers: int = 1, reference: bool = True) -> list[SceneFigures]:
    paths = scene_paths(folder)
    if workers == 1:
        return [measure(p, designs, seed, None, reference) for p in paths]
    with worker_pool(workers) as pool:
        return [measure(p, designs, seed, pool, reference) for p in paths]


def table(rows: list[SceneFigures], wall: float) -> str:
    lines = [f"{'scene':18} {'prototype':>9} {'random':>8} {'solution':>9} {'reference':>9} {'its kit':>8}  "
             f"solution config",
             f"{'':18} {'(row)':>9} {'full row':>8} {'(mbd)':>9} {'':>9} {'':>8}"]
    for r in rows:
        sol = r.solution_traversals
        mbd = next((v for k, v in sol.items() if k != REFERENCE), None)
        lines.append(f"{r.name:18} {f'{r.prototype_traversals}/{r.full_row}':>9} {r.random_full_row_share:>8.0%} "
                     f"{(f'{mbd}/{r.full_row}' if mbd is not None else '-'):>9} "
                     f"{(f'{sol[REFERENCE]}/{r.full_row}' if REFERENCE in sol else '-'):>9} "
                     f"{(r.solution_kit.split(':')[0] or '-'):>8}  {r.solution or 'none'}"
                     + (f" (NOT A SOLUTION: it changes {', '.join(r.solution_changes_scene)})"
                        if r.solution_changes_scene else ""))
    n = rows[0].random_designs if rows else 0
    lines.append(f"random: the share of {n} uniformly drawn designs completing the row; its kit: whether the parts of "
                 f"the kit drawn for the solution clear as its frames turn (scene.effects.clearance); "
                 f"{wall:.1f} s wall")
    lines += [f"  {r.name}'s kit collides: {r.solution_kit.split(': ', 1)[1]}" for r in rows
              if r.solution_kit.startswith("collides")]
    return "\n".join(lines)


def register(sub, scene_command) -> None:
    sp = sub.add_parser("scenes", help="the scene suite search is measured on: difficulty and a known solution each")
    sp.add_argument("--dir", default=DEFAULT_DIR, help=f"folder of scene configs (default {DEFAULT_DIR})")
    sp.add_argument("--designs", type=int, default=DEFAULT_DESIGNS,
                    help=f"uniformly random designs per scene for its difficulty (default {DEFAULT_DESIGNS})")
    add_seed(sp, DEFAULT_SEED, f"seed of the random designs (default {DEFAULT_SEED})")
    sp.add_argument("--workers", type=int, default=os.cpu_count() or 1, help="processes (default: one per core)")
    sp.add_argument("--no-reference", action="store_true", help="skip the solutions' re-check at reference")
    sp.add_argument("--json", action="store_true", help="one JSON list instead of the table")
    sp.set_defaults(func=cmd_scenes)


def cmd_scenes(args) -> int:
    check_counts(designs=args.designs, workers=args.workers)
    scene_paths(args.dir)  # refused before any work
    t0 = time.perf_counter()
    rows = suite(args.dir, args.designs, args.seed, args.workers, not args.no_reference)
    print(json.dumps([asdict(r) for r in rows], indent=2) if args.json else table(rows, time.perf_counter() - t0))
    return 0
