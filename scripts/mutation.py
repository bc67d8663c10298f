"""Mutation testing of the kit, the design space, the statistics and the interrupts: mutmut, module by module, and its score.

    python scripts/mutation.py [MODULE.py ...] [--max-children N] [--report | --survivors] [--show] [--min-score 90]

mutmut (pinned in the ``test`` extra) copies ``[tool.mutmut].source_paths`` into ``mutants/``, changes one thing at
a time in each module of ``only_mutate`` (a comparison, a constant, an argument, a string) and runs, for each such
mutant, only the tests that reached the function it changed, out of the fast files in
``pytest_add_cli_args_test_selection`` (pyproject.toml; never the whole suite). A mutant the tests notice is killed;
one they do not survived. A survivor is either a gap in the tests, or a change that cannot change what the code
does (an equivalent mutant): those are listed, each with the line mutmut wrote and the reason, in
``scripts/mutation_equivalents.toml`` (its ``change``: the line mutmut wrote, checked against the mutant). The score of a module is (killed + timed out + listed equivalents) / all its
mutants; the project keeps it at 90 % or more on each (DEVELOPERS.md, "Mutation testing", gives the last run).

With no MODULE every module of ``only_mutate`` is run. ``--report`` runs nothing and scores the results mutmut
stored (``mutants/``); ``--survivors`` runs again only the mutants the stored results leave open (after a test was
added). The exit status is 1 when a module scores below ``--min-score``, or when a listed
equivalent no longer matches its mutant (the code changed: look at it again).

A module joins the run by adding its path to ``only_mutate`` and its fast test files to
``pytest_add_cli_args_test_selection``; the next run forgets what mutmut cached for the old selection.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import time
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
EQUIVALENTS = Path(__file__).with_name("mutation_equivalents.toml")
KILLED, TIMEOUT, SURVIVED = {1, 3}, {36, -24, 24, 152, 255}, {0}


def configured() -> dict:
    return tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["mutmut"]


def mutant_prefix(path: str) -> str:
    """``aero_env/sheet/parts.py`` -> ``aero_env.sheet.parts.``: how mutmut names that module's mutants."""
    return path.removesuffix(".py").replace("/", ".") + "."


def results(path: str) -> dict[str, int | None]:
    """mutmut's stored exit code of every mutant of ``path`` (None: not run)."""
    meta = ROOT / "mutants" / (path + ".meta")
    if not meta.exists():
        return {}
    return json.loads(meta.read_text())["exit_code_by_key"]


def equivalents() -> dict[str, dict]:
    if not EQUIVALENTS.exists():
        return {}
    return {e["mutant"]: e for e in tomllib.loads(EQUIVALENTS.read_text()).get("equivalent", [])}


def diff(mutant: str) -> str:
    """The mutant's change as mutmut shows it (its ``-``/``+`` lines)."""
    from mutmut.mutation.diff_apply import get_diff_for_mutant

    text = get_diff_for_mutant(mutant)
    return "\n".join(ln for ln in text.splitlines() if ln[:1] in "+-" and ln[:3] not in ("+++", "---"))


def written(mutant: str) -> str:
    """The lines mutmut wrote for the mutant (its diff's ``+`` lines), stripped: what an equivalent's ``change`` is."""
    return "\n".join(ln[1:].strip() for ln in diff(mutant).splitlines() if ln.startswith("+"))


def refresh_copies(cfg: dict) -> None:
    """mutmut copies the sources into mutants/ once and later regenerates only the modules it mutates: bring every
    other file there up to date with the working tree, so the mutants run with today's code around them."""
    mutated = {str(Path(p)) for p in cfg["only_mutate"]}
    for src in cfg["source_paths"]:
        for path in (ROOT / src).rglob("*"):
            rel = path.relative_to(ROOT)
            if not path.is_file() or "__pycache__" in rel.parts or str(rel) in mutated:
                continue
            copy = ROOT / "mutants" / rel
            if not copy.exists() or copy.read_bytes() != path.read_bytes():
                copy.parent.mkdir(parents=True, exist_ok=True)
                shutil.copy2(path, copy)


def forget_stale_state(cfg: dict) -> None:
    """What mutmut keeps in mutants/ and would wrongly reuse after the configuration changed: a module newly in
    ``only_mutate`` whose plain copy is there (mutmut calls it unmodified and makes no mutants of it), and the map
    from tests to the functions they reach when the test selection changed or a mutated module is newer than the
    map (a mutant no listed test reached before would count as untested)."""
    for path in cfg["only_mutate"]:
        copy = ROOT / "mutants" / path
        if copy.exists() and not copy.with_name(copy.name + ".meta").exists():
            copy.unlink()
    seen = ROOT / "mutants" / "aero-env-mutmut-config.json"
    now = json.dumps(cfg, sort_keys=True)
    stats = ROOT / "mutants" / "mutmut-stats.json"
    if seen.exists() and seen.read_text() != now:
        stats.unlink(missing_ok=True)
    # a function added to a mutated module since the map was made is in no test's list: its every mutant would
    # count as untested (mutmut keeps the map while the tests' files are unchanged)
    if stats.exists() and any((ROOT / p).stat().st_mtime > stats.stat().st_mtime for p in cfg["only_mutate"]):
        stats.unlink()
    seen.parent.mkdir(exist_ok=True)
    seen.write_text(now)


def run(path: str, max_children: int, addopts: str = "", names: list[str] | None = None) -> float:
    """``mutmut run`` on every mutant of ``path`` (or on ``names`` only); returns the wall time. Output goes to
    mutants/<module>.log."""
    log = ROOT / "mutants" / (mutant_prefix(path) + "log")
    log.parent.mkdir(exist_ok=True)
    env = {**os.environ, "PYTEST_ADDOPTS": f"{os.environ.get('PYTEST_ADDOPTS', '')} {addopts}".strip()}
    t0 = time.perf_counter()
    with open(log, "w") as out:
        done = subprocess.run([str(Path(sys.executable).with_name("mutmut")), "run", "--max-children",
                               str(max_children), *(names or [mutant_prefix(path) + "*"])], cwd=ROOT, stdout=out,
                              stderr=subprocess.STDOUT, env=env)
    if done.returncode != 0 or not results(path) or None in results(path).values():
        sys.exit(f"mutation: mutmut run on {path} ended with status {done.returncode} before testing every mutant; "
                 f"see {log} (a selected test that fails unmutated stops it: run them with pytest)")
    return time.perf_counter() - t0


def score(path: str, listed: dict[str, dict]) -> tuple[dict, list[str], list[str]]:
    """Counts for ``path``, the survivors not listed as equivalent, and listed equivalents that no longer hold."""
    codes = results(path)
    prefix = mutant_prefix(path)
    counts = dict(total=len(codes), killed=0, timeout=0, equivalent=0, survived=0, not_run=0, other=0)
    open_, stale = [], []
    for name, code in sorted(codes.items()):
        if code in KILLED:
            counts["killed"] += 1
        elif code in TIMEOUT:
            counts["timeout"] += 1
        elif code is None:
            counts["not_run"] += 1
            open_.append(name)
        elif code in SURVIVED or code in (5, 33):  # survived, or no test reached it
            entry = listed.get(name)
            if entry is not None and entry["change"].strip() == written(name):
                counts["equivalent"] += 1
            else:
                counts["survived"] += 1
                open_.append(name)
                if entry is not None:
                    stale.append(f"{name}: listed as {entry['change']!r}, but mutmut now shows\n{diff(name)}")
        else:
            counts["other"] += 1
            open_.append(name)
    for name in listed:
        if name.startswith(prefix) and name in codes and codes[name] in KILLED | TIMEOUT:
            stale.append(f"{name}: listed as equivalent, but the tests now kill it (take it off the list)")
    detected = counts["killed"] + counts["timeout"] + counts["equivalent"]
    counts["score"] = detected / counts["total"] if counts["total"] else 0.0
    return counts, open_, stale


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("modules", nargs="*", help="paths from [tool.mutmut].only_mutate (default: all of them)")
    ap.add_argument("--max-children", type=int, default=2, help="mutants tested at once (default 2)")
    ap.add_argument("--report", action="store_true", help="run nothing; score what mutmut stored in mutants/")
    ap.add_argument("--survivors", action="store_true",
                    help="run again only the mutants the last run left open (after adding tests)")
    ap.add_argument("--min-score", type=float, default=90.0, help="per cent a module must reach (default 90)")
    ap.add_argument("--show", action="store_true", help="print each open survivor's change")
    ap.add_argument("--pytest-addopts", default="", metavar="OPTS",
                    help="more pytest options for this run (e.g. --deselect a test another change broke)")
    args = ap.parse_args()
    os.chdir(ROOT)  # mutmut reads its configuration and mutants/ from here
    mutated = configured()["only_mutate"]
    modules = args.modules or mutated
    unknown = [m for m in modules if m not in mutated]
    if unknown:
        sys.exit(f"mutation: {', '.join(unknown)}: not in [tool.mutmut].only_mutate (pyproject.toml); add it there, "
                 f"with its fast test files in pytest_add_cli_args_test_selection")
    listed = equivalents()
    failed = False
    rows = []
    if not args.report:
        refresh_copies(configured())
        forget_stale_state(configured())
    for path in modules:
        names = None
        if args.survivors:
            names = score(path, listed)[1]
            if not names:
                rows.append((path, score(path, listed)[0], 0.0))
                continue
        wall = None if args.report else run(path, args.max_children, args.pytest_addopts, names)
        counts, open_, stale = score(path, listed)
        rows.append((path, counts, wall))
        failed |= 100 * counts["score"] < args.min_score or bool(stale)
        for line in stale:
            print(f"STALE {line}")
        if args.show:
            for name in open_:
                print(f"OPEN {name}\n{diff(name) if results(path).get(name) is not None else '(not run)'}")
    print(f"{'module':34} {'mutants':>7} {'killed':>6} {'timeout':>7} {'equiv':>5} {'survived':>8} {'score':>6}"
          f" {'wall':>7}")
    for path, c, wall in rows:
        print(f"{path:34} {c['total']:7d} {c['killed']:6d} {c['timeout']:7d} {c['equivalent']:5d} "
              f"{c['survived'] + c['not_run'] + c['other']:8d} {100 * c['score']:5.1f}% "
              f"{'-' if wall is None else f'{wall / 60:.1f} min':>7}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
