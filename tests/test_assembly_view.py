"""``assembly.html``: the row's model in a page a browser opens from the disk, shown by headless Chromium.

The page must draw the same model ``assembly.glb`` holds (its groups and its triangles, read from the .glb by
hand in tests/test_solids.py's reader), with nothing from the network, and its panel must hide and explode."""

import shutil

import numpy as np
import pytest

from aero_env.cli import main

from .conftest import PAPER
from .test_solids import mesh_of, read_glb, world_nodes

CHROMIUM = "/usr/bin/chromium"
# WebGL2 in a headless browser: SwiftShader, the software renderer Chromium ships
FLAGS = ["--no-sandbox", "--disable-background-networking", "--disable-component-update", "--disable-sync",
         "--no-first-run", "--use-angle=swiftshader", "--enable-unsafe-swiftshader"]


@pytest.fixture(scope="module")
def page(tmp_path_factory):
    if shutil.which(CHROMIUM) is None:
        pytest.fail(f"{CHROMIUM} is missing: run scripts/ensure-system-packages (Debian's chromium)", pytrace=False)
    from playwright.sync_api import sync_playwright

    out = tmp_path_factory.mktemp("view")
    assert main(["sheet", str(PAPER), "--out", str(out / "assembly.glb")]) == 0
    assert main(["sheet", str(PAPER), "--out", str(out / "assembly.html")]) == 0
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, args=FLAGS)
        pg = browser.new_page(viewport={"width": 900, "height": 600})
        errors, requests = [], []
        pg.on("pageerror", lambda e: errors.append(str(e)))
        pg.on("request", lambda r: requests.append(r.url))
        pg.goto((out / "assembly.html").as_uri())
        pg.wait_for_function("window.viewer && window.viewer.ready", timeout=30000)
        yield pg, out, errors, requests
        browser.close()


def shot(pg) -> np.ndarray:
    from io import BytesIO

    from PIL import Image

    return np.asarray(Image.open(BytesIO(pg.locator("#view").screenshot())).convert("RGB")).astype(int)


def test_the_page_shows_the_models_groups_and_every_triangle_with_nothing_from_the_network(page):
    pg, out, errors, requests = page
    assert errors == []
    assert requests == [(out / "assembly.html").as_uri()]  # the page itself, nothing else
    gltf, binary = read_glb((out / "assembly.glb").read_bytes())
    roots = [gltf["nodes"][i]["name"] for i in gltf["scenes"][0]["nodes"]]
    assert pg.evaluate("viewer.groups") == roots
    triangles = sum(len(mesh_of(gltf, binary, node)[1]) for _, node in world_nodes(gltf).values() if "mesh" in node)
    assert pg.evaluate("viewer.triangles") == triangles
    lo, hi = pg.evaluate("viewer.bounds")
    assert hi[0] - lo[0] > 0.5  # metres: the 8-frame row is over half a metre long


def test_the_model_is_drawn_and_the_panel_hides_and_explodes(page):
    pg, *_ = page
    pg.evaluate("viewer.set({explode: 1, hidden: []})")
    whole = shot(pg)
    drawn = (np.abs(whole - 255).sum(axis=2) > 30).mean()
    assert 0.05 < drawn < 0.9  # the row fills part of the view, not none and not all
    # the stand is brown: hiding it takes its pixels away
    stand = np.array([115, 97, 77])  # the stand's colour, shaded: near it within the light's range

    def brownish(img):
        return ((np.abs(img - stand) < 60).all(axis=2)).mean()

    pg.evaluate("viewer.set({hidden: ['stand']})")
    assert brownish(shot(pg)) < 0.2 * brownish(whole)
    assert pg.evaluate("document.querySelector('input[data-group=stand]').checked") is False
    pg.evaluate("viewer.set({hidden: [], explode: 3})")
    exploded = shot(pg)
    assert (np.abs(exploded - whole).sum(axis=2) > 30).mean() > 0.02  # the parts moved apart
