"""Pictures of the toy in 3D, from the same solids ``assembly.glb`` holds: assembled, and exploded across the row.

    python scripts/draw_assembly_3d.py CONFIG OUT_PREFIX    # writes OUT_PREFIX_assembled.png, OUT_PREFIX_exploded.png

``aero-env sheet CONFIG --out PAGE.html`` writes the page; headless Chromium (Debian's, through Playwright) opens
it and the viewer (aero_env/parts/viewer.js) draws each view, so the pictures are what a maker sees in the page.
docs/make-your-own.md, "Assembly", shows the prototype's.
"""

from __future__ import annotations

import contextlib
import io
import sys
import tempfile
from pathlib import Path

from aero_env.cli import main as aero_env

CHROMIUM = "/usr/bin/chromium"
FLAGS = ["--no-sandbox", "--disable-background-networking", "--disable-component-update", "--disable-sync",
         "--no-first-run", "--use-angle=swiftshader", "--enable-unsafe-swiftshader"]
VIEWS = {  # the viewer's settings for each picture (viewer.set): the whole row, then its first two frames and the
    # robot, the stand hidden, with every part moved apart across the row, three times as far from the middle
    "assembled": {"yaw": -0.55, "pitch": 0.35, "explode": 1.0},
    "exploded": {"yaw": -0.7, "pitch": 0.3, "explode": 3.0, "distance": 0.42, "target": [0.03, -0.02, 0.0],
                 "hidden": ["stand", *(f"frame-{i}" for i in range(2, 64))]},
}


def main(config: str, prefix: str) -> None:
    from playwright.sync_api import sync_playwright

    with tempfile.TemporaryDirectory() as tmp:
        page = Path(tmp) / "assembly.html"
        with contextlib.redirect_stdout(io.StringIO()):  # its "wrote ..." names a temporary folder
            if aero_env(["sheet", config, "--out", str(page)]) != 0:
                raise SystemExit(1)
        with sync_playwright() as p:
            browser = p.chromium.launch(executable_path=CHROMIUM, args=FLAGS)
            view = browser.new_page(viewport={"width": 1000, "height": 560})
            view.goto(page.as_uri())
            view.wait_for_function("window.viewer && window.viewer.ready", timeout=60000)
            view.evaluate("document.getElementById('panel').style.display = 'none'")
            for name, settings in VIEWS.items():
                view.evaluate("s => viewer.set(s)", settings)
                view.locator("#view").screenshot(path=f"{prefix}_{name}.png")
                print(f"wrote {prefix}_{name}.png")
            browser.close()


if __name__ == "__main__":
    if len(sys.argv) != 3:
        raise SystemExit("usage: python scripts/draw_assembly_3d.py CONFIG OUT_PREFIX")
    main(sys.argv[1], sys.argv[2])
