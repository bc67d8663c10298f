"""``aero-env sheet``: a maker's build sheet and 1:1 template, read back against the config."""

import math
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
    # no fractional coin; the two coin seats (squares 22 mm a side of 310 g/m² card: 0.300 g) part of m3
    assert _row(sheet, "mass at (La, h) (m3)") == "6 one-yen coins + 0.20 g clay + 2 coin seats (6.50 g)"
    # the torso's card is what the robot's 7.71 g leaves after the arm, coins and handrail
    assert _row(sheet, "torso below the axle / its card (m2 less the parts listed here)") == \
        "39.1 mm / 2.00 g, 6 layers glued flat"
    # the handrail's angle as the template draws it: from the frame line, and from the horizontal (the config's)
    assert _row(sheet, "the L's bisector at rest: from the frame line / from the horizontal / opening") == \
        "+9.7 deg / 64.7 deg / 90 deg"
    assert "one-yen coins)" not in sheet and not re.search(r"\d\.\d+ one-yen", sheet)
    assert "0.877 N·mm/rad (linear)" in sheet and "0.92 N·mm" in sheet  # k·60 deg, the paper's sanity check
    assert "5.0 mm wide, 20.0 mm free between two 5 mm glue tabs" in sheet  # the prototype's strip
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
    assert m and int(m.group(1)) == _completed_builds(PAPER, 4, 0, {"scene.frames": 3})
    # a design that cannot complete its row is said to, and no hand-made build of it completes it either
    assert main(["sheet", str(PAPER), "--out", str(out), "--draws", "4", "--set", "design.m3=0.02", *SHORT_ROW]) == 0
    text = out.read_text()
    assert "does not complete" in text and "**0 of 4**" in text


def _completed_builds(path, draws: int, seed: int, over: dict) -> int:
    """The sheet's robustness count worked out another way: the ``draws`` hand-made builds the robustness study
    draws with ``seed`` (its default tolerances), each simulated here, and the ones that complete the row counted."""
    from aero_env.config import load_config
    from aero_env.robustness.study import draw_builds
    from aero_env.robustness.tolerances import DEFAULT_TOLERANCES
    from aero_env.simulation import simulate

    cfg = load_config(path, over)
    builds = draw_builds(cfg, tuple(DEFAULT_TOLERANCES), draws, seed)[1]
    return sum(b.config is not None and simulate(b.config).traversals == cfg.scene.frames - 1 for b in builds)


def _part(doc, name):
    return next(g for g in doc.getElementsByTagName("g") if g.getAttribute("id") == name)


def _f(el, attr):
    return float(el.getAttribute(attr))


def test_the_svg_template_is_one_to_one(tmp_path, paper_cfg):
    out = tmp_path / "t.svg"
    assert main(["sheet", str(PAPER), "--out", str(out)]) == 0
    doc = xml.dom.minidom.parse(str(out)).documentElement
    width = float(doc.getAttribute("width").removesuffix("mm"))
    assert doc.getAttribute("viewBox").split()[2] == f"{width:.1f}"  # one user unit is one millimetre
    d = paper_cfg.design
    frame = _part(doc, "part-frame-side-card-wide")
    hole = frame.getElementsByTagName("circle")[0]
    seat = frame.getElementsByTagName("line")[0]
    assert _f(hole, "cx") - _f(seat, "x1") == pytest.approx(d.Lb * 1e3, abs=0.01)
    arm = _part(doc, "part-arm")
    fold = arm.getElementsByTagName("line")[0]
    assert _f(fold, "x1") - _f(arm.getElementsByTagName("circle")[0], "cx") == pytest.approx(d.arm_length * 1e3, abs=0.01)
    torso = _part(doc, "part-torso")
    card, axle, coins = torso.getElementsByTagName("rect")[0], *torso.getElementsByTagName("circle")
    assert _f(card, "width") - _f(axle, "cx") == pytest.approx(d.torso_length * 1e3, abs=0.01)
    assert _f(coins, "r") == pytest.approx(d.coin_radius * 1e3)
    assert _f(coins, "cx") + _f(coins, "r") == pytest.approx(_f(card, "width"), abs=0.01)  # flush with the bottom
    rail = _part(doc, "part-handrail-narrow").getElementsByTagName("rect")[0]
    assert _f(rail, "height") == pytest.approx((d.notch_back_face + d.notch_front_face) * 1e3, abs=0.01)
    assert any(r.getAttribute("class") == "scale-bar" and _f(r, "width") == 50.0 for r in doc.getElementsByTagName("rect"))


def _spring_strips(svg_path):
    """(cut length, width) in mm of each leaf-spring strip the template says to cut: the strip drawn, as many times
    as its caption's "cut N strip(s)"."""
    doc = xml.dom.minidom.parse(str(svg_path)).documentElement
    n = int(re.search(r"LEAF SPRING: cut (\d+) strip", open(svg_path).read()).group(1))
    return [(_f(r, "width"), _f(r, "height")) for r in _part(doc, "part-leaf-spring").getElementsByTagName("rect")] * n


def _bending_k(strips, tab_mm=5.0):
    """The strips' torque per radian by the pure-bending law written out here: n·D·w/L, L the free length."""
    from aero_env.parts.card import PAPER_CARD

    D = PAPER_CARD.bending_stiffness
    return sum(D * (w * 1e-3) / ((cut - 2 * tab_mm) * 1e-3) for cut, w in strips)


def test_the_cards_bending_stiffness_is_the_fit_on_the_papers_spring():
    from aero_env.parts.card import PAPER_CARD, PAPER_SPRING_K, PROTOTYPE_STRIP, fit_bending_stiffness

    # the stored value is the fit's (scripts/fit_card_bending.py), rounded: it cannot go stale
    assert PAPER_CARD.bending_stiffness == pytest.approx(fit_bending_stiffness(PAPER_SPRING_K, PROTOTYPE_STRIP),
                                                         rel=1e-3)


@pytest.mark.parametrize("k", [8.77e-4, 5e-4, 1.5e-3, 3.5e-3])
def test_the_spring_strip_on_the_template_gives_the_designs_stiffness(tmp_path, k):
    out = tmp_path / "t.svg"
    assert main(["sheet", str(PAPER), "--out", str(out), "--set", f"design.spring_k={k}"]) == 0
    strips = _spring_strips(out)
    assert _bending_k(strips) == pytest.approx(k, rel=0.01)
    for cut, w in strips:
        assert 3.0 - 1e-9 <= w <= 8.0 + 1e-9  # cuts cleanly with scissors, and no wider than 8 mm
        assert cut - 10.0 <= 25.0 + 1e-9  # ends a glue tab before the hook (30 mm arm)
    if k == 8.77e-4:  # the paper's 0.877 N·mm/rad: the prototype's strip, one layer
        assert strips == [(30.0, 5.0)]


@pytest.mark.parametrize("k, why", [(6e-3, "use a thicker card"), (1.5e-4, "use a thinner card")])
def test_a_spring_no_strip_can_make_is_said_so(tmp_path, k, why):
    assert main(["sheet", str(PAPER), "--out", str(tmp_path / "kit"), "--draws", "0", *SHORT_ROW,
                 "--set", f"design.spring_k={k}"]) == 0
    sheet = (tmp_path / "kit" / "sheet.md").read_text()
    assert "**none fits**" in sheet and why in sheet
    assert _spring_strips_or_none(tmp_path / "kit" / "template.svg") is None
    assert "LEAF SPRING: no strip of this card fits" in (tmp_path / "kit" / "template.svg").read_text()


def _spring_strips_or_none(svg_path):
    doc = xml.dom.minidom.parse(str(svg_path)).documentElement
    return next((g for g in doc.getElementsByTagName("g") if g.getAttribute("id") == "part-leaf-spring"), None)


def test_the_bench_check_is_the_arms_turn_under_the_papers_loads(paper_cfg):
    rows = {ln.what.split(" (")[0]: ln.value for ln in lines(paper_cfg)}
    bench = rows["bench check"]
    # the bag alone (0.3 g) at the hook tip of a 30 mm arm on 0.877 N·mm/rad: 0.3e-3·9.81·0.03/8.77e-4 rad
    assert bench.startswith("0.30 g: 6 deg, 0.80 g: 15 deg")  # 5.77 and 15.4 deg
    assert bench.endswith("3.30 g: 63 deg")  # the first load past the full bend of 60 deg


def test_one_command_writes_the_sheet_and_its_template(tmp_path, capsys):
    kit = tmp_path / "kit"
    assert main(["sheet", str(PAPER), "--out", str(kit), "--draws", "0", *SHORT_ROW]) == 0
    assert sorted(p.name for p in kit.iterdir()) == ["assembly.glb", "assembly.html", "kit-a4.pdf", "kit-letter.pdf",
                                                     "parts.json", "sheet.md", "template.svg"]
    for paper in ("a4", "letter"):  # a folder's kit is the one a single --out FILE.pdf --paper writes
        assert main(["sheet", str(PAPER), "--out", str(tmp_path / "one.pdf"), "--paper", paper, *SHORT_ROW]) == 0
        assert (tmp_path / "one.pdf").read_bytes() == (kit / f"kit-{paper}.pdf").read_bytes()
    assert "[template.svg](template.svg)" in (kit / "sheet.md").read_text()
    (kit / "notes.txt").write_text("mine")  # a folder with the maker's own files: the sheet writes beside them
    assert main(["sheet", str(PAPER), "--out", str(kit), "--draws", "0", *SHORT_ROW, "--set", "design.La=0.05"]) == 0
    assert "| 50.0 mm |" in (kit / "sheet.md").read_text() and (kit / "notes.txt").read_text() == "mine"
    (tmp_path / "file").write_text("")
    assert main(["sheet", str(PAPER), "--out", str(tmp_path / "file"), "--draws", "0"]) == 2
    assert "is a file; give a folder" in capsys.readouterr().err


def test_the_sheets_builds_show_their_progress_on_stderr(tmp_path, capsys):
    argv = ["sheet", str(PAPER), "--out", str(tmp_path / "kit"), "--draws", "3", *SHORT_ROW]
    assert main(argv) == 0
    out, err = capsys.readouterr()
    done = re.findall(r"sheet: robustness: +100%.* (\d+)/(\d+) ", err)  # the bar ends with every run done
    assert done and done[-1][0] == done[-1][1], err
    assert out.startswith("wrote ") and len(out.splitlines()) == 1  # stdout keeps its one line
    assert main([*argv, "--no-progress"]) == 0
    assert capsys.readouterr().err == ""


@pytest.mark.parametrize("out, needle", [("nodir/sheet.md", "does not exist"), ("sheet.txt", "suffix '.txt'")])
def test_a_bad_out_is_refused_before_any_work(tmp_path, monkeypatch, capsys, out, needle):
    monkeypatch.chdir(tmp_path)
    import aero_env.simulation

    monkeypatch.setattr(aero_env.simulation, "simulate", lambda *a, **k: pytest.fail("simulated"))
    assert main(["sheet", str(PAPER), "--out", out]) == 2
    err = capsys.readouterr().err.strip()
    assert needle in err and len(err.splitlines()) == 1


def test_the_sheet_compares_another_design_on_the_same_builds(tmp_path, capsys):
    import json

    from .conftest import ROOT

    solution, scene = ROOT / "configs/scenes/solutions/six_coins.yaml", ROOT / "configs/scenes/six_coins.yaml"
    out = tmp_path / "sheet.md"
    assert main(["sheet", str(solution), "--out", str(out), "--draws", "3", "--seed", "4", "--compare", str(scene),
                 "--no-progress"]) == 0
    line = next(ln for ln in out.read_text().splitlines() if ln.startswith("Robustness:"))
    capsys.readouterr()
    # each design's share, as `aero-env robustness` counts it on the same seed's builds
    counts = []
    for path in (solution, scene):
        assert main(["robustness", str(path), "--draws", "3", "--seed", "4", "--json", "--no-progress"]) == 0
        counts.append(json.loads(capsys.readouterr().out)["completed"])
    assert line.startswith(f"Robustness: **{counts[0]} of 3**")
    assert line.endswith(f"The same 3 builds of {scene}: **{counts[1]} of 3** ({100 * counts[1] / 3:.0f} %).")
    assert counts[0] > counts[1]  # the solution survives builds the prototype on six coins does not
    # another robot is not another design
    assert main(["sheet", str(solution), "--out", str(out), "--compare", str(ROOT / "configs/paper.yaml")]) == 2
    assert "not the same scene and robot, only another design (design.coin_mass, design.m2 differ)" in \
        capsys.readouterr().err


# ---- the spring strip's stiffness, by the bending law written out here ----
# card.py's model: a strip of width w with free length L between its glue lines, n strips stacked loose, gives a
# torque n·D·w·Δα / L (pure bending), D the card's bending stiffness per unit width. D is the one fitted constant:
# the paper's K_T = 0.877 N·mm/rad (Fig. 22) on the assumed prototype strip, 5 mm wide and 20 mm free.
def _torque_per_radian(D, strip):
    return strip.layers * D * strip.width / strip.free_length


@pytest.mark.parametrize("k, arm_mm, bend_deg, how", [
    (8.77e-4, 30.0, 60.0, "width"),  # the prototype: the free length kept, the width chosen
    (3.5e-3, 30.0, 60.0, "layers"),  # too stiff for one strip 8 mm wide: stacked
    (5e-3, 30.0, 30.0, "shorter"),  # too stiff for three: full width, shorter (a 30 deg bend allows it)
    (3e-4, 50.0, 60.0, "longer"),  # too soft for a 3 mm strip 20 mm long: longer (a 50 mm arm has room)
])
def test_the_planned_strip_gives_the_stiffness_asked_for_and_the_plan_says_so(k, arm_mm, bend_deg, how):
    from aero_env.parts.card import PAPER_CARD
    from aero_env.parts.spring_strip import plan_strip

    D = PAPER_CARD.bending_stiffness
    assert D == pytest.approx(0.877e-3 * 20e-3 / 5e-3, rel=1e-3)  # the card's constant is the fit written out
    plan = plan_strip(k, PAPER_CARD, arm_mm * 1e-3, math.radians(bend_deg))
    st = plan.strip
    assert st is not None, plan.why_not
    assert {"width": st.layers == 1 and st.free_length == 20e-3 and 2e-3 < st.width < 8e-3,
            "layers": st.layers > 1 and st.free_length == 20e-3,
            "shorter": st.layers == 3 and st.width == 8e-3 and st.free_length < 20e-3,
            "longer": st.layers == 1 and st.width == 3e-3 and st.free_length > 20e-3}[how], st
    # the strip to cut gives k by the law, and the stiffness the plan reports (the template prints it) is the law's
    assert _torque_per_radian(D, st) == pytest.approx(k, rel=1e-12)
    assert plan.stiffness == pytest.approx(_torque_per_radian(D, st), rel=1e-12)


@pytest.mark.parametrize("law", ["linear", "stiffening"])
@pytest.mark.parametrize("k", [8.77e-4, 1.5e-3, 3.5e-3])
def test_the_template_prints_the_stiffness_its_strip_gives(paper_cfg, k, law):
    from aero_env.parts.card import PAPER_CARD
    from aero_env.parts.kit import spring

    cfg = paper_cfg.replace({"design.spring_k": k, "scene.effects.spring_law": law})
    d = cfg.design
    bend = math.radians(d.alpha_max_deg - d.alpha_min_deg)
    # the linear stiffness the strip must have: k itself, or for the stiffening law (torque k/2·Δα²) the one with
    # the same torque at full bend, k·bend/2
    linear = k if law == "linear" else k * bend / 2
    caption = " ".join(spring(cfg, PAPER_CARD).caption)
    m = re.search(r"\(([0-9.]+) N·mm/rad\)", caption)
    assert m, caption
    assert float(m.group(1)) == pytest.approx(linear * 1e3, abs=0.0005)  # printed to 3 decimals
    # and the strip it draws gives that by the law (widths and free length as printed, 0.1 mm)
    w, free = (float(x) for x in re.search(r"([0-9.]+) mm wide, ([0-9.]+) mm free", caption).groups())
    n = int(re.search(r"cut (\d+) strip", caption).group(1))
    assert n * PAPER_CARD.bending_stiffness * w / free == pytest.approx(linear, rel=0.02)


def test_a_tuned_value_reads_as_a_maker_reads_it(paper_cfg):
    """What ``aero-env tune`` prints beside each best value: mm, g, whole coins and clay, the card pair."""
    from aero_env.sheet.parts import workbench

    assert workbench("design.La", 0.0484137, paper_cfg) == "48.4 mm"
    # the counterbalance less its two coin seats (0.300 g): 7 coins and 0.18 g of clay; the robot's coins have no seat
    assert workbench("design.m3", 0.00747632, paper_cfg) == "7 one-yen coins + 0.18 g clay + 2 coin seats (7.48 g)"
    assert workbench("design.coin_mass", 0.00447632, paper_cfg) == "4 one-yen coins + 0.48 g clay (4.48 g)"
    assert workbench("design.m1", 0.0024, paper_cfg) == "2.40 g"
    assert workbench("design.spring_k", 1.3232e-3, paper_cfg) == "1.323 N·mm/rad"
    # a friction is read with its own design's mu_k: 0.29/0.15 is gray/gray (0.283/0.149), 2 % off in mu_s
    gray = paper_cfg.with_values({"design.mu_s": 0.29, "design.mu_k": 0.15})
    assert workbench("design.mu_s", 0.29, gray) == "nearest card pair: gray arm on gray handrail, 2 % off"
    assert workbench("design.rest_angle_deg", 55.0, paper_cfg) == ""


SEEN = {"falls short": "fell_short", "does not hook on": "missed_catch", "never lets go": "no_detach",
        "never turns": "stalled"}  # what the maker sees, in the sheet's words, and the world's outcome
KNOB = {"counterbalance": ("design.m3", 1e-4), "spring": ("design.spring_k", None),
        "rest": ("design.rest_angle_deg", 0.5)}  # the maker's step: 0.1 g, 2 %, 0.5 deg
SI = {"g": 1e-3, "N·mm/rad": 1e-3, "deg": 1.0}  # the printed unit to the field's


def _values(text: str) -> list[float]:
    """The field values a cell states, in SI: "6.7 g", "(below 50.5 deg)", "(1.295 N·mm/rad)"."""
    return [float(x) * SI[u] for x, u in re.findall(r"([0-9.]+) (g|deg|N·mm/rad)\b", text)]


def test_the_troubleshooting_table_is_what_the_world_does_at_its_edges(paper_cfg):
    """Each symptom row, read back from the table's words, is re-run here: at the edge its cause names the row
    completes, and one maker's step (0.1 g, 2 %, 0.5 deg) beyond it the world shows what the row says the maker
    sees, on that transfer; a cause "far" out is what the world shows at the value it names. Each part's window
    completes at both edges; its margins are yours less the edges, and "fits" says whether a hand-made toy's
    tolerance (3 % of m3, 15 % of the spring, 2 deg, written out here) fits in both. The stopper's hole moves
    round its arc by its distance from the axis hole per radian (in the hollow card's window, against the hub
    bar)."""
    from aero_env.sheet.troubleshoot import table
    from aero_env.simulation import simulate

    from .test_kit_readback import hollow_card

    lines = table(paper_cfg)
    split = lines.index("")
    rows = [r for r in lines[2:split]]
    assert rows, lines
    d = paper_cfg.design
    assert hollow_card(d)[2] is not None  # the article's hollow side card (test_kit_readback works it out)
    # its rest stopper meets the hub bar's edge (3 mm off the axis, a skewer's radius more) at (travel + 15 deg)/2
    mm_per_deg = 4.0 / math.cos(math.radians(d.stop_angle_deg - d.rest_angle_deg + 15.0) / 2) * math.pi / 180
    kinds = set()
    for row in rows:
        seen, cause, change = (c.strip() for c in row.strip("|").split("|"))
        outcome = next(o for words, o in SEEN.items() if words in seen)
        transfer = int(re.search(r"\(transfer (\d+): frame (\d+) to frame (\d+)\)", seen).group(1))
        key, step = next(v for k, v in KNOB.items() if cause.startswith(k))
        value = _values(cause)[-1]
        if key == "design.rest_angle_deg":  # the hole's move round its arc, in mm, for the degrees it states
            arc = float(re.search(r"the hole (?:more than )?([0-9.]+) mm", cause).group(1))
            assert arc == pytest.approx(abs(value - d.rest_angle_deg) * mm_per_deg, abs=0.051), row
        up = "too heavy" in cause or "too stiff" in cause or "too high" in cause
        assert ("take clay off" in change or "narrower" in change or "down its arc" in change) == up, row
        if "far too" in cause:
            past = simulate(paper_cfg.replace({key: value}))
        else:
            assert simulate(paper_cfg.replace({key: value})).outcome == "completed", row
            beyond = (value * 1.02 if up else value / 1.02) if step is None else value + (step if up else -step)
            past = simulate(paper_cfg.replace({key: beyond}))
        assert (past.outcome, past.traversals + 1) == (outcome, transfer), (row, past.reason)
        kinds.add(outcome)
    assert {"missed_catch", "fell_short", "stalled", "no_detach"} <= kinds  # every symptom the issue names
    # the windows
    tolerance = {"design.m3": 0.03 * d.m3, "design.spring_k": 0.15 * d.spring_k, "design.rest_angle_deg": 2.0}
    windows = lines[split + 3:]
    assert len(windows) == 3
    for row in windows:
        part, window, yours, margins, toy = (c.strip() for c in row.strip("|").split("|"))
        key, _ = next(v for k, v in KNOB.items() if part.startswith(k))
        lo, hi = _values(window)[:2]
        here = _values(yours)[0]
        assert here == pytest.approx(paper_cfg.value(key), rel=1e-3)
        for edge, open_end in ((lo, "or less" in window), (hi, "or more" in window)):
            if not open_end:
                assert simulate(paper_cfg.replace({key: edge})).outcome == "completed", row
        down, up = _values(margins)
        digit = {"design.m3": 0.05e-3, "design.spring_k": 0.5e-6, "design.rest_angle_deg": 0.05}[key]  # half a digit
        assert down == pytest.approx(here - lo, abs=digit) and up == pytest.approx(hi - here, abs=digit), row
        assert ("fits" in toy and "does not fit" not in toy) == (min(here - lo, hi - here) >= tolerance[key]), row


@pytest.mark.parametrize("dT", [0.0, 2e-4, -3e-4])
def test_the_frame_balance_check_brackets_the_counterbalances_moment(paper_cfg, dT):
    from aero_env.sheet.troubleshoot import frame_balance

    cfg = paper_cfg.replace({"design.dT": dT})
    d, text = cfg.design, frame_balance(cfg)
    lo, hi = (int(n) for n in re.search(r"with (\d+) one-yen coins .* with (\d+) seat-down", text).groups())
    # held level, the moments about the skewer (N·m): the counterbalance at La turns it counterbalance-down; the
    # handrail's card and n 1 g coins at the seat (Lb), and the frame's own dT (Eq. 1's sign), seat-down
    moment = lambda n: d.m3 * 9.81 * d.La - (d.handrail_mass + n * 1e-3) * 9.81 * d.Lb - d.dT  # noqa: E731
    assert hi == lo + 1 and moment(lo) > 0 > moment(hi)
    at = float(re.search(r"balances at (-?[0-9.]+)\)", text).group(1))
    assert moment(at) == pytest.approx(0.0, abs=0.05e-3 * 9.81 * d.Lb)  # to the printed tenth of a coin


def test_the_sheet_says_while_it_fits_the_layout_and_only_then(tmp_path, capsys):
    """The layout's fit takes seconds (half a minute or more where no card fits) in silence otherwise: the sheet
    says on stderr that it is fitting and what it found, once per design (a kept layout costs nothing and says
    nothing), and nothing with --no-progress; stdout keeps its one line."""
    from aero_env.parts.clearance import forget_verdicts

    found, refused = PAPER.parent / "scenes/solutions/steep.yaml", PAPER.parent / "steep_solution.yaml"
    for config, verdict in ((found, "found"), (refused, "none found: every frame is drawn alike (the sheet says why)")):
        forget_verdicts()
        assert main(["sheet", str(config), "--out", str(tmp_path / "t.svg")]) == 0
        out, err = capsys.readouterr()
        said = err.splitlines()
        assert said[0] == "aero-env sheet: fitting the side cards of the nested layout ..." and len(said) == 2, err
        assert re.fullmatch(rf"aero-env sheet: the nested layout: {re.escape(verdict)}, in \d+\.\d s", said[1])
        assert out.startswith("wrote ") and len(out.splitlines()) == 1
        assert main(["sheet", str(config), "--out", str(tmp_path / "t.svg")]) == 0  # kept: nothing to say
        assert capsys.readouterr().err == ""
    forget_verdicts()
    assert main(["sheet", str(found), "--out", str(tmp_path / "t.svg"), "--no-progress"]) == 0
    assert capsys.readouterr().err == ""


def test_a_row_the_stand_cannot_hold_is_refused_before_the_layout_is_fitted(tmp_path, capsys, monkeypatch):
    """The stand's check comes first: a row falling below the uprights' foot is one line at once, not after the
    layout's fit (which the crossbeams' gap needs, before the uprights are drawn)."""
    from aero_env.parts import layout
    from aero_env.parts.clearance import forget_verdicts

    forget_verdicts()

    def no_fit(cfg):
        raise AssertionError("the layout was fitted before the stand was checked")

    monkeypatch.setattr(layout, "_build_nested", no_fit)
    assert main(["sheet", str(PAPER), "--out", str(tmp_path / "kit"), "--set", "scene.rise=-0.0205"]) == 2
    assert capsys.readouterr().err == (
        "aero-env: config error: scene.rise = -0.0205: over 8 frames the last axis would stand 6.5 mm above the base "
        "(scene.floor_drop = 0.15); the stand needs at least 10 mm, allowed rise >= -0.02 m\n")
    assert not (tmp_path / "kit").exists()
