"""``assembly.html``: the row's ``assembly.glb`` in a page that any browser opens from the disk.

The page carries the model (the .glb, base64) and its viewer (``viewer.js``: WebGL2, no library, no network),
so it is one file a maker can open, e-mail or put on a web page. Drag to turn, wheel to zoom, a panel to hide
groups and explode the parts across the row.
"""

from __future__ import annotations

import base64
from html import escape
from pathlib import Path

VIEWER = Path(__file__).with_name("viewer.js")


def html(glb: bytes, title: str) -> str:
    """A self-contained page showing ``glb``."""
    return f"""<!doctype html>
<html lang="en"><head><meta charset="utf-8"><title>{escape(title)}</title>
<style>
  html, body {{ margin: 0; height: 100%; font: 13px sans-serif; }}
  #view {{ width: 100vw; height: 100vh; display: block; }}
  #panel {{ position: absolute; top: 8px; left: 8px; background: #ffffffdd; padding: 6px 10px; border-radius: 4px; }}
</style></head>
<body>
<canvas id="view"></canvas>
<div id="panel"><b>{escape(title)}</b><br>
  <span id="status">loading</span><br>
  explode <input id="explode" type="range" min="1" max="4" step="0.1" value="1"><br>
  <div id="groups"></div>
  drag: turn, wheel: zoom
</div>
<script id="model" type="application/octet-stream">{base64.b64encode(glb).decode("ascii")}</script>
<script>
{VIEWER.read_text()}
</script>
</body></html>
"""
