"""The layout that clears (aero_env/parts/layout.py, issue 49 §2): narrow and wide frames alternating, the narrow
cards cut away where the wide neighbours' handrails and the skewers pass, each cut card fitted to weigh, balance and
swing as the hollow card the world swings. Checked here as a maker would: the card's own polygons weighed by hand
(the shoelace sums written out below), and the whole row turned frame by frame in 3D (the static sweep)."""

from __future__ import annotations

import math

import pytest

from aero_env.config import load_config
from aero_env.parts import build
from aero_env.parts.clearance import static_sweep
from aero_env.parts.layout import nested_layout
from aero_env.parts.solids import assembly, identical_layout

from .conftest import PAPER, per_test_under_mutmut

G = 0.310  # kg/m²
CARD_T = 0.4e-3  # m a layer


def weighed(outline, layers):
    """(mass kg, centre (u, v) mm, inertia about the hole kg·m²) of a card of ``layers`` layers: the shoelace sums
    of its polygons (a hole's polygon winds the other way and counts negative), at the paper's 310 g/m²."""
    a = mu = mv = j = 0.0
    for poly in outline.to_polygons():
        pts = [(float(x), float(y)) for x, y in poly]
        for (x0, y0), (x1, y1) in zip(pts, pts[1:] + pts[:1]):
            cross = x0 * y1 - x1 * y0
            a += cross / 2
            mu += (x0 + x1) * cross / 6
            mv += (y0 + y1) * cross / 6
            j += (x0 * x0 + x0 * x1 + x1 * x1 + y0 * y0 + y0 * y1 + y1 * y1) * cross / 12
    sigma = G * layers
    return sigma * a * 1e-6, (mu / a, mv / a), sigma * j * 1e-12


@pytest.fixture(scope=per_test_under_mutmut)
def row(paper_cfg):
    return nested_layout(paper_cfg)


def test_the_prototypes_narrow_cards_are_cut_and_weigh_and_swing_as_the_hollow_card(row, paper_cfg):
    d = paper_cfg.design
    assert row.found, row.reason
    narrow, wide = row.kinds[0], row.kinds[1]
    assert [k.name for k in row.kinds] == ["narrow", "wide"] * 4
    a13 = 2 * d.m1 / 3 * (d.La**2 + d.Lb**2 - d.La * d.Lb)
    for kind in (narrow, wide):
        mass, (cu, cv), inertia = weighed(kind.outline, kind.layers)
        assert mass == pytest.approx(d.m1 / 2, rel=1e-4), kind.name
        assert inertia == pytest.approx(a13 / 2, rel=1e-4), kind.name
        assert abs(cu) <= 0.01 and abs(cv) <= 0.01, (kind.name, cu, cv)
        assert len(kind.outline.decompose()) == 1  # one piece of card, the hole in it
    # the wide card is the hollow card as it is: no part crosses its plane at this pitch; the narrow one is cut
    assert wide.extents is None and narrow.extents is not None
    hollow = build.side_card(d)
    assert wide.outline.area() == pytest.approx((hollow["length"] * hollow["depth"] - 2 * hollow["window"]
                                                 * hollow["window_depth"] - math.pi * 1.2e-3**2) * 1e6, rel=1e-4)
    # the wide cards stand a gap outside the narrow cards' outer faces
    assert narrow.span == pytest.approx(0.030)
    assert wide.span == pytest.approx(0.030 + 2 * narrow.layers * CARD_T + 2e-3)


def test_the_prototypes_row_in_the_nested_layout_clears_where_the_identical_one_does_not(row, paper_cfg):
    """Every frame turned from rest to its end stop in 1 deg steps against its neighbours (at rest and at their end
    stops) and the stand: no two parts share 1 mm³. The same row with every frame alike collides."""
    assert static_sweep(assembly(paper_cfg, row)) == []
    assert static_sweep(assembly(paper_cfg, identical_layout(paper_cfg)), frames=[3]) != []


def test_each_wide_frames_counterbalance_is_outside_its_cards_and_the_crossbeams_clear_it(row, paper_cfg):
    asm = assembly(paper_cfg, row)
    d = paper_cfg.design
    wide = row.kinds[1]
    outer = wide.span / 2 + wide.layers * CARD_T
    coins = [p for p in asm.frames[1] if p.name.startswith(("counterbalance", "coin seat"))]
    # 7.2 g: two coin seats (0.30 g of card), six coins, 0.90 g of clay
    assert sorted(p.name for p in coins) == ["coin seat (far)", "coin seat (near)", "counterbalance clay (0.9 g)",
                                             "counterbalance coins (far) (3)", "counterbalance coins (near) (3)"]
    for p in coins:
        lo, hi = p.solid.bounding_box()[2], p.solid.bounding_box()[5]
        assert lo >= outer - 1e-12 or hi <= -outer + 1e-12, p.name  # on an outer face, outside the card
    # the narrow frame's counterbalance stays between its cards, each stack on a card's inner face
    inside = [p for p in asm.frames[0] if p.name.startswith(("counterbalance", "coin seat"))]
    assert len(inside) == 5
    assert all(abs(b) <= 0.015 + 1e-12 for p in inside for b in (p.solid.bounding_box()[2], p.solid.bounding_box()[5]))
    beams = [p for p in asm.stand if p.name.startswith("crossbeam")]
    reach = max(abs(b) for p in coins for b in (p.solid.bounding_box()[2], p.solid.bounding_box()[5]))
    assert all(min(abs(p.solid.bounding_box()[2]), abs(p.solid.bounding_box()[5])) >= reach for p in beams)
    assert build.counterbalance_load(d.m3)["coins"] == 6


@pytest.mark.slow
def test_a_stored_solution_the_nested_layout_fits_clears_too():
    """six_coins: a heavier robot, the same frames: its narrow cards fitted, its row clear."""
    cfg = load_config(PAPER.parent / "scenes/solutions/six_coins.yaml")
    row = nested_layout(cfg)
    assert row.found, row.reason
    assert static_sweep(assembly(cfg, row)) == []


def test_the_layout_script_prints_the_kinds_and_the_sweep_and_refuses_bad_arguments_in_one_line(row, capsys):
    """scripts/nested_layout.py (the docs' block): each kind's span, layers and card against the hollow card's,
    and the sweep's count; status 0 when the row clears; a bad --plot or config refused with one line, status 2."""
    import importlib.util

    from .conftest import ROOT

    spec = importlib.util.spec_from_file_location("nested_layout", ROOT / "scripts" / "nested_layout.py")
    script = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(script)
    assert script.main([str(PAPER)]) == 0
    out = capsys.readouterr().out.splitlines()
    narrow = next(ln for ln in out if ln.startswith("narrow "))
    assert narrow.split()[1:4] == ["0,2,4,6", "30.0", str(row.kinds[0].layers)] and "cut away, fitted" in narrow
    assert out[-1].endswith(": 0 parts meet")
    # --identical: every frame alike, their cards in the same planes: parts meet (test_solids.py says where)
    assert script.main([str(PAPER), "--identical"]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[0].endswith("every frame alike, its side cards in the same two planes")
    assert int(out[1].split(": ")[1].split()[0]) > 0 and "meets the side card" in out[2]
    angles = [float(ln.split("theta1 = ")[1].split()[0]) for ln in out[2:10]]
    assert angles == sorted(angles)  # the first meetings first
    for bad in ([str(PAPER), "--plot", "cards.svg"], [str(PAPER.parent / "nope.yaml")],
                [str(PAPER), "--identical", "--plot", "cards.png"]):
        with pytest.raises(SystemExit) as stop:
            script.main(bad)
        assert stop.value.code == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert err[-1].startswith("nested_layout.py: error: ") or "error:" in err[-1]


@pytest.mark.slow
def test_on_a_steep_row_the_handrails_meet_and_the_nested_layout_says_it_finds_none():
    """The prototype's frames on a row that climbs 10 mm a frame (the steep scene before its rest angle was a
    choice): a frame's handrail meets the next frame's resting handrail before the robot lets go, in any layout
    across the row (both span the robot's arm); the nested layout reports that it found no narrow card rather than
    cut one that swings otherwise."""
    cfg = load_config(PAPER.parent / "scenes/steep.yaml")
    meets = static_sweep(assembly(cfg, identical_layout(cfg)), frames=[2])
    rails = [c for c in meets if (c.part, c.other, c.where) == ("handrail", "handrail", "frame 3 at rest")]
    assert len(rails) == 1 and rails[0].angle_deg < 150.0
    row = nested_layout(cfg)
    assert not row.found and row.reason.startswith("a frame's handrail lies in its neighbour's handrail's path")
    assert row.kinds[0].extents is None  # it keeps the hollow card and says so


def test_a_row_whose_narrow_card_fails_says_its_nearest_miss_and_spends_no_fit_on_the_wide_card(monkeypatch):
    """Frames 100 mm long (La = Lb): both kinds' cards are crossed, so both would be fitted. Every fit here fails
    (a stand-in for Nelder-Mead, which takes half a minute to fail on this design), each layer count missing by its
    own amount: the reason names the layer count that came nearest and its misfit, and once the narrow card has
    failed the row is refused whatever the wide card does, so no wide fit is run."""
    import numpy as np

    from aero_env.parts import layout

    cfg = load_config(PAPER, {"design.La": 0.1, "design.Lb": 0.1})
    n = int(build.side_card(cfg.design)["layers"])
    misses = {k: np.array([-0.1 * (1 + abs(k - (n + 1))), -0.2, 0.01, -0.02]) for k in range(1, n + 3)}  # n+1 nearest
    asked = []

    def failing_fit(sc, keep_out, pins):
        asked.append(int(sc["layers"]))
        return None, misses[int(sc["layers"])], None

    monkeypatch.setattr(layout, "fit_cut_card", failing_fit)
    row = layout._build_nested(cfg)
    assert asked == list(layout.layers_tried(n))  # the narrow card's layer counts, once each, and nothing more
    assert not row.found and row.reason == (f"no narrow card cut clear of its neighbours weighs and swings as the "
                                            f"hollow card (nearest, {n + 1} layers: mass -1.0e-01, inertia -2.0e-01, "
                                            f"centre (+0.10, -0.20) mm)")
    assert [kind.extents for kind in row.kinds[:2]] == [None, None]
