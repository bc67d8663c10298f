"""``aero-env sheet``: a maker's build sheet and 1:1 template, read back against the config."""

import re
import xml.dom.minidom

import pytest

from aero_env.cli import main
from aero_env.sheet.parts import card_pair, lines

from .conftest import PAPER

SHORT_ROW = ["--set", "scene.frames=3"]


def _row(sheet: str, what: str) -> str:
    m = re.search(rf"^\| [^|]+ \| {re.escape(what)} \| (.+) \|$", sheet, re.M)
    assert m, what
    return m.group(1)


def test_the_md_sheet_gives_the_configs_parts_in_mm_and_g(tmp_path, capsys):
    out = tmp_path / "sheet.md"
    assert main(["sheet", str(PAPER), "--out", str(out), "--draws", "0", "--set", "design.La=0.0501",
                 "--set", "design.m3=0.0065", *SHORT_ROW]) == 0
    sheet = out.read_text()
    assert _row(sheet, "skewer hole to counterbalance (La)") == "50.1 mm"
    assert _row(sheet, "mass at (La, h) (m3)") == "6.50 g (6.5 one-yen coins)"
    # the torso's card is what the robot's 7.71 g leaves after the arm, coins and handrail
    assert _row(sheet, "torso strip below the axle / its card (m2 less the parts listed here)") == \
        "39.1 mm / 2.00 g (2.0 one-yen coins)"
    assert "0.877 N·mm/rad (linear)" in sheet and "0.92 N·mm" in sheet  # k·60 deg, the paper's sanity check
    assert "In the simulated world this design" in sheet and "Robustness: not assessed" in sheet


def test_the_card_pair_is_the_table_3_pair_nearest_the_friction(paper_cfg):
    assert card_pair(0.542, 0.409)[0].startswith("white arm on gray")
    assert card_pair(0.29, 0.15)[0].startswith("gray arm on gray")
    far = {ln.what: ln.value for ln in lines(paper_cfg.replace({"design.mu_s": 1.2, "design.mu_k": 0.9}))}
    assert far["the card pair that gives the friction"].startswith("no card pair of Table 3")


def test_the_sheet_reports_the_designs_robustness(tmp_path):
    out = tmp_path / "sheet.md"
    assert main(["sheet", str(PAPER), "--out", str(out), "--draws", "4", *SHORT_ROW]) == 0
    m = re.search(r"Robustness: \*\*(\d+) of 4\*\*", out.read_text())
    assert m and 0 <= int(m.group(1)) <= 4
    # a design that cannot complete its row is said to, and no hand-made build of it completes it either
    assert main(["sheet", str(PAPER), "--out", str(out), "--draws", "4", "--set", "design.m3=0.02", *SHORT_ROW]) == 0
    text = out.read_text()
    assert "does not complete" in text and "**0 of 4**" in text


def test_the_svg_template_is_one_to_one(tmp_path, paper_cfg):
    out = tmp_path / "t.svg"
    assert main(["sheet", str(PAPER), "--out", str(out)]) == 0
    doc = xml.dom.minidom.parse(str(out)).documentElement
    width = float(doc.getAttribute("width").removesuffix("mm"))
    assert doc.getAttribute("viewBox").split()[2] == f"{width:.1f}"  # one user unit is one millimetre
    rects = [float(r.getAttribute("width")) for r in doc.getElementsByTagName("rect")]
    d = paper_cfg.design
    for length in (d.La + d.Lb, d.arm_length, d.torso_length, d.notch_back_face + d.notch_front_face):
        assert any(r == pytest.approx(length * 1e3, abs=0.01) for r in rects), length
    assert 50.0 in rects  # the scale bar
    coins = [c for c in doc.getElementsByTagName("circle") if c.getAttribute("stroke") == "gray"]
    assert float(coins[0].getAttribute("r")) == pytest.approx(d.coin_radius * 1e3)


@pytest.mark.parametrize("out, needle", [("nodir/sheet.md", "does not exist"), ("sheet.txt", "suffix '.txt'")])
def test_a_bad_out_is_refused_before_any_work(tmp_path, monkeypatch, capsys, out, needle):
    monkeypatch.chdir(tmp_path)
    import aero_env.simulation

    monkeypatch.setattr(aero_env.simulation, "simulate", lambda *a, **k: pytest.fail("simulated"))
    assert main(["sheet", str(PAPER), "--out", out]) == 2
    err = capsys.readouterr().err.strip()
    assert needle in err and len(err.splitlines()) == 1
