"""The cutting template, rendered by a real browser (headless Chromium through Playwright).

A check of the XML text cannot see what a printer will: these tests ask Chromium for the page's
rendered size, the 50 mm bar's, every caption's box against every other caption and every part,
and whether each hole lies inside its card. Chromium is Debian's (``scripts/ensure-system-packages``
installs it); the tests fail with one line when it is missing, they never skip.
"""

import shutil

import pytest

from aero_env.cli import main

from .conftest import PAPER

PX_PER_MM = 96 / 25.4  # CSS: 96 px to the inch
CHROMIUM = "/usr/bin/chromium"
FLAGS = ["--no-sandbox", "--disable-gpu", "--disable-background-networking", "--disable-component-update",
         "--disable-sync", "--no-first-run"]


@pytest.fixture(scope="module")
def browser():
    if shutil.which(CHROMIUM) is None:
        pytest.fail(f"{CHROMIUM} is missing: run scripts/ensure-system-packages (Debian's chromium)", pytrace=False)
    from playwright.sync_api import sync_playwright

    with sync_playwright() as p:
        b = p.chromium.launch(executable_path=CHROMIUM, args=FLAGS)
        yield b
        b.close()


# Everything the tests read, measured by the browser in CSS pixels.
MEASURE = """() => {
  const box = e => { const r = e.getBoundingClientRect(); return [r.left, r.top, r.right, r.bottom]; };
  const svg = document.documentElement;
  const holes = [];
  for (const g of document.querySelectorAll('g.part')) {
    const outline = g.querySelector('rect, polygon');
    for (const c of g.querySelectorAll('circle')) {
      if (c.getAttribute('class') !== 'cut') continue;  // a hole: a cut circle inside its card
      const cx = +c.getAttribute('cx'), cy = +c.getAttribute('cy'), r = +c.getAttribute('r');
      let inside = true;
      for (let k = 0; k < 16; k++) {
        const p = svg.createSVGPoint();
        p.x = cx + r * Math.cos(k * Math.PI / 8); p.y = cy + r * Math.sin(k * Math.PI / 8);
        inside = inside && outline.isPointInFill(p);
      }
      holes.push([g.id, inside]);
    }
  }
  return {
    size: [svg.getBoundingClientRect().width, svg.getBoundingClientRect().height],
    stated: [svg.getAttribute('width'), svg.getAttribute('height')],
    bar: box(document.querySelector('rect.scale-bar')),
    captions: [...document.querySelectorAll('text.caption')].map(t => [t.textContent, box(t)]),
    parts: [...document.querySelectorAll('g.part')].map(g => [g.id, box(g)]),
    holes,
  };
}"""


def _render(browser, path):
    page = browser.new_page()
    page.goto(path.as_uri())
    m = page.evaluate(MEASURE)
    page.close()
    return m


def _overlap(a, b, pad=0.5) -> bool:
    return a[0] < b[2] - pad and b[0] < a[2] - pad and a[1] < b[3] - pad and b[1] < a[3] - pad


@pytest.mark.parametrize("overrides", [[], ["--set", "design.h=-0.009", "--set", "design.spring_k=3e-3",
                                            "--set", "scene.frames=12"]], ids=["paper", "other"])
def test_the_template_renders_at_its_stated_size_with_every_part_and_no_overlap(tmp_path, browser, overrides):
    assert main(["sheet", str(PAPER), "--out", str(tmp_path / "kit"), "--draws", "0", *overrides]) == 0
    m = _render(browser, tmp_path / "kit" / "template.svg")
    w_mm, h_mm = (float(s.removesuffix("mm")) for s in m["stated"])
    assert m["size"][0] == pytest.approx(w_mm * PX_PER_MM, abs=0.5)
    assert m["size"][1] == pytest.approx(h_mm * PX_PER_MM, abs=0.5)
    bar = m["bar"]
    assert bar[2] - bar[0] == pytest.approx(50 * PX_PER_MM, abs=0.2)  # the print's check
    # it prints at 100 % on A4 (210 x 297 mm) and US Letter (215.9 x 279.4 mm) with 10 mm margins: no printer
    # shrinks it to fit the width, and no piece is taller than a page, so a page break never cuts one in two
    for paper_w, paper_h in ((210.0, 297.0), (215.9, 279.4)):
        assert w_mm <= paper_w - 20.0
        for name, box in m["parts"]:
            assert (box[3] - box[1]) / PX_PER_MM <= paper_h - 20.0, name

    names = {name for name, _ in m["parts"]}
    beams = {n for n in names if n.startswith("part-crossbeam-")}
    # the frames' pieces: one side card and one handrail for every frame, or (the nested layout, the prototype's)
    # each for the narrow frames and for the wide
    frames = {"part-frame-side-card", "part-handrail"}
    nested = {f"{p}-{k}" for p in frames for k in ("narrow", "wide")}
    assert beams and names - beams - frames - nested == {"part-upright-first", "part-upright-last", "stand",
                                                         "part-counterbalance", "part-coin-seat", "part-arm",
                                                         "part-torso", "part-leaf-spring"}
    assert names & (frames | nested) in (frames, nested) and (names >= nested or overrides)
    caps = m["captions"]
    for i, (text, box) in enumerate(caps):
        for other, obox in caps[i + 1:]:
            assert not _overlap(box, obox), f"caption {text!r} overlaps {other!r}"
        for name, pbox in m["parts"]:
            assert not _overlap(box, pbox), f"caption {text!r} overlaps part {name}"
        assert box[2] <= m["size"][0] and box[0] >= 0, f"caption {text!r} runs off the page"
    # the frame's skewer hole, the arm's and torso's axle holes and the crossbeams' skewer holes, each wholly inside
    # its card
    cards = {n for n in names if n.startswith("part-frame-side-card")}  # a hole inside its outline, cut away or not
    assert {name for name, _ in m["holes"]} == {"part-arm", "part-torso"} | cards | beams
    assert all(inside for _, inside in m["holes"]), m["holes"]
