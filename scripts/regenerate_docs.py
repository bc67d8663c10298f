"""Rerun every command the docs quote and write its output back, so no number in them goes stale.

A quoted run in ``README.md`` or ``docs/*.md`` is a marker line with the command, then a fenced
block that this script owns:

    <!-- run: aero-env simulate configs/paper.yaml -->
    ```text
    (the command's output, rewritten on every regeneration)
    ```

Commands run from the repository root with the project's venv on PATH, one at a time (timings
in the output are of a 2-core machine doing nothing else). A command that writes a figure
(``--plot docs/compare.png``) regenerates the figure too. A command that fails stops the script
with its error and leaves every page as it was.

    python scripts/regenerate_docs.py                  # every page
    python scripts/regenerate_docs.py docs/physics.md  # one page
    python scripts/regenerate_docs.py --list           # the commands, without running them
    python scripts/regenerate_docs.py docs/fidelity.md --only step_agreement  # only the blocks whose command has it
"""

from __future__ import annotations

import argparse
import os
import re
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
MARKER = re.compile(r"^<!-- run: (?P<cmd>.+?) -->\n```(?P<lang>\w*)\n(?P<body>.*?)^```$", re.M | re.S)
PAGES = ("README.md", "docs/*.md")


def pages(names: list[str]) -> list[Path]:
    if names:
        return [ROOT / n for n in names]
    found = []
    for pattern in PAGES:
        found.extend(sorted(ROOT.glob(pattern)))
    return found


def shown(page: Path) -> str:
    """The page's path as the repository names it (a page outside the repository: as given)."""
    return str(page.relative_to(ROOT)) if page.is_relative_to(ROOT) else str(page)


def run(cmd: str) -> str:
    env = dict(os.environ, PATH=f"{ROOT / '.venv' / 'bin'}{os.pathsep}{os.environ.get('PATH', '')}",
               COLUMNS="100")
    # pipefail: a quoted `cmd | tail -1` whose cmd fails must fail, not quote an empty block
    proc = subprocess.run(["bash", "-o", "pipefail", "-c", cmd], cwd=ROOT, env=env, capture_output=True, text=True)
    if proc.returncode != 0:
        sys.exit(f"regenerate_docs: `{cmd}` exited {proc.returncode}:\n{proc.stderr.strip()}")
    return proc.stdout.rstrip("\n")


def regenerate(page: Path, only: str | None = None) -> str:
    text = page.read_text()

    def fill(m: re.Match) -> str:
        if only is not None and only not in m["cmd"]:
            return m.group(0)  # left as it was
        t0 = time.perf_counter()
        out = run(m["cmd"])
        print(f"  {time.perf_counter() - t0:6.1f} s  {m['cmd']}", file=sys.stderr)
        return f"<!-- run: {m['cmd']} -->\n```{m['lang']}\n{out}\n```"

    return MARKER.sub(fill, text)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("pages", nargs="*", help="pages to regenerate (default: README.md and docs/*.md)")
    ap.add_argument("--list", action="store_true", help="print the quoted commands and stop")
    ap.add_argument("--only", metavar="TEXT", help="rerun only the commands that contain TEXT (the others' blocks "
                    "stay as they are): for a block just added or changed")
    args = ap.parse_args(argv)
    todo = pages(args.pages)
    missing = [str(p) for p in todo if not p.is_file()]
    if missing:
        sys.exit(f"regenerate_docs: no such page: {', '.join(missing)}")
    (ROOT / "out").mkdir(exist_ok=True)  # the docs' commands write there (git ignores it), as a reader's would
    if args.list:
        for page in todo:
            for m in MARKER.finditer(page.read_text()):
                if args.only is None or args.only in m["cmd"]:
                    print(f"{shown(page)}: {m['cmd']}")
        return 0
    new = {}
    for page in todo:  # every command first: a failure leaves every page as it was
        print(shown(page), file=sys.stderr)
        new[page] = regenerate(page, args.only)
    for page, text in new.items():
        page.write_text(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
