"""The kit (``aero-env sheet CONFIG --out DIR``'s template.svg and parts.json), read back independently.

The card of each piece is measured here on the SVG's own cut outlines, by geometry written out in
this file (a rectangle's w·h, a circle's pi·r², a polygon's shoelace; an outline inside another is a
hole), never by the code that draws them. That area, times the piece's layers and the card's
grammage, plus what parts.json says is added to it, must be its mass; and the pieces that make up a
model field must add up to the config's value. For the prototype and every stored scene solution.
"""

import json
import math
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from aero_env.cli import main
from aero_env.config import load_config

from .conftest import per_test_under_mutmut

ROOT = Path(__file__).resolve().parents[1]
SVG = "{http://www.w3.org/2000/svg}"
CONFIGS = [ROOT / "configs/paper.yaml", *sorted((ROOT / "configs/scenes/solutions").glob("*.yaml"))]
GRAMMAGE = 0.310  # kg/m²: the paper's card, JOHOKU WB310g (Sec. 6), written out here




def _outline(el) -> tuple[float, tuple[float, float, float, float]]:
    """(area mm², bounding box) of one cut element."""
    tag = el.tag.removeprefix(SVG)
    f = lambda k: float(el.get(k))  # noqa: E731
    if tag == "rect":
        x, y, w, h = f("x"), f("y"), f("width"), f("height")
        return w * h, (x, y, x + w, y + h)
    if tag == "circle":
        cx, cy, r = f("cx"), f("cy"), f("r")
        return math.pi * r * r, (cx - r, cy - r, cx + r, cy + r)
    if tag == "polygon":
        pts = [tuple(map(float, p.split(","))) for p in el.get("points").split()]
        a = 0.5 * abs(sum(x0 * y1 - x1 * y0 for (x0, y0), (x1, y1) in zip(pts, pts[1:] + pts[:1])))
        xs, ys = [p[0] for p in pts], [p[1] for p in pts]
        return a, (min(xs), min(ys), max(xs), max(ys))
    raise AssertionError(f"a cut {tag} this test cannot measure")


def _inside(a, b) -> bool:
    return a[0] >= b[0] and a[1] >= b[1] and a[2] <= b[2] and a[3] <= b[3] and a != b


def card_areas(svg_path) -> dict[str, float]:
    """Each ``part-`` group's card in m²: its cut outlines less the outlines inside them (holes). Translations
    do not change an area, and the kit draws at 1:1 with no scaling (checked)."""
    root = ET.parse(svg_path).getroot()
    out = {}
    for g in root.iter(SVG + "g"):
        if not (g.get("id") or "").startswith("part-"):
            continue
        for sub in g.iter():
            assert "scale" not in (sub.get("transform") or ""), "a part drawn at other than 1:1"
        cuts = [_outline(el) for el in g.iter() if el.get("class") == "cut"]
        area = 0.0
        for a, box in cuts:
            hole = any(_inside(box, other) for _, other in cuts)
            area += -a if hole else a
        out[g.get("id")] = area * 1e-6
    return out


@pytest.fixture(scope=per_test_under_mutmut, params=CONFIGS, ids=lambda p: p.stem)
def kit(request, tmp_path_factory):
    d = tmp_path_factory.mktemp(request.param.stem)
    assert main(["sheet", str(request.param), "--out", str(d / "template.svg")]) == 0
    assert main(["sheet", str(request.param), "--out", str(d / "parts.json")]) == 0
    return request.param, d / "template.svg", json.loads((d / "parts.json").read_text())


def test_every_piece_weighs_its_card_as_drawn_plus_what_is_added(kit):
    _, svg, parts = kit
    areas = card_areas(svg)
    assert sorted(areas) == sorted(p["id"] for p in parts["parts"])
    for p in parts["parts"]:
        assert p["grammage_kg_m2"] == GRAMMAGE
        card = areas[p["id"]] * p["layers"] * p["grammage_kg_m2"]
        added = sum(a["mass_kg"] for a in p["added"])
        assert card + added == pytest.approx(p["mass_kg"], rel=0.03), p["name"]


def test_the_pieces_add_up_to_the_models_masses(kit):
    path, _, parts = kit
    cfg = load_config(path)
    made: dict[str, float] = {}
    frames = cfg.scene.frames
    for p in parts["parts"]:
        # a piece made for some frames only (the nested layout's narrow or wide frames) makes its field for those
        served = p["count"] / p["per_unit"] if p["sets"] in ("design.m1", "design.handrail_mass") else frames
        assert p["share"] == pytest.approx(served / frames, rel=1e-12) or p["sets"] not in ("design.m1",), p["name"]
        for key in [p["sets"], *p.get("part_of", [])]:
            made[key] = made.get(key, 0.0) + p["mass_kg"] * p["per_unit"] * served / frames
    assert {"design.m1", "design.m3", "design.arm_mass", "design.m2", "design.handrail_mass"} <= set(made)
    for key in ("design.m1", "design.m2", "design.m3", "design.arm_mass", "design.handrail_mass"):
        assert made[key] == pytest.approx(cfg.value(key), rel=0.03), key


def test_the_prototype_reaches_table_1_part_by_part():
    """Table 1 (and its text): frame 4 g, arm 1.5 g, torso 2 g, coins 4 g, counterbalance 7.2 g, handrail 0.21 g."""
    from aero_env.parts.kit import pieces

    by = {p.name: p for p in pieces(load_config(ROOT / "configs/paper.yaml"))}
    # the nested layout: the narrow frames' cut cards and the wide frames' hollow ones, each pair the frame's 4 g
    for kind in ("narrow", "wide"):
        assert 2 * by[f"swing frame side card, {kind} frames"].mass_kg == pytest.approx(4.0e-3, rel=0.03)
        assert by[f"handrail, {kind} frames"].mass_kg == pytest.approx(0.21e-3, rel=0.03)
    assert by["arm"].mass_kg == pytest.approx(1.5e-3, rel=0.03)
    torso = by["torso"]
    assert torso.card_area_m2 * torso.layers * GRAMMAGE == pytest.approx(2.0e-3, rel=0.03)
    assert sum(kg for _, kg in torso.added) == pytest.approx(4.0e-3, rel=0.03)
    # the counterbalance on its two coin seats (squares of card 22 mm a side, one layer)
    seats = 2 * 22e-3**2 * GRAMMAGE
    assert by["coin seat"].mass_kg * 2 == pytest.approx(seats, rel=1e-12)
    assert by["counterbalance"].mass_kg + seats == pytest.approx(7.2e-3, rel=1e-12)


def test_the_template_is_in_mm_and_marks_cuts_and_folds_by_class(kit):
    _, svg, _ = kit
    root = ET.parse(svg).getroot()
    w, h = root.get("width"), root.get("height")
    assert w.endswith("mm") and h.endswith("mm")
    assert root.get("viewBox").split() == ["0", "0", w.removesuffix("mm"), h.removesuffix("mm")]
    for g in root.iter(SVG + "g"):
        if (g.get("id") or "").startswith("part-"):
            drawn = [el for el in g.iter() if el.tag.removeprefix(SVG) in ("rect", "circle", "line", "polygon")]
            assert all(el.get("class") in ("cut", "fold", "mark") for el in drawn), g.get("id")
            # a plotter tells the layers apart by colour: every cut one colour, every fold another
            assert len({el.get("stroke") for el in drawn if el.get("class") == "cut"}) <= 1
            assert {el.get("stroke") for el in drawn if el.get("class") == "fold"} <= {"#0000ff"}


def test_the_world_swings_the_pieces_the_template_draws(tmp_path):
    """The frame's and the arm's bodies in the pymunk world carry the mass and inertia of the pieces as drawn: the
    side card's rectangle and hole and the arm's plate read off the template, their layers off parts.json, the
    second moments written out here (a rectangle about its centre (w² + h²)/12 per unit mass; a disc r²/2)."""
    from aero_env.physics.world import World
    from aero_env.units import INERTIA, LENGTH, MASS

    cfg = load_config(ROOT / "configs/paper.yaml")
    main(["sheet", str(ROOT / "configs/paper.yaml"), "--out", str(tmp_path / "t.svg")])
    main(["sheet", str(ROOT / "configs/paper.yaml"), "--out", str(tmp_path / "p.json")])
    parts = {p["id"]: p for p in json.loads((tmp_path / "p.json").read_text())["parts"]}
    root = ET.parse(tmp_path / "t.svg").getroot()
    group = {g.get("id"): g for g in root.iter(SVG + "g")}

    def plate(gid):
        rect = next(group[gid].iter(SVG + "rect"))
        hole = next(el for el in group[gid].iter(SVG + "circle") if el.get("class") == "cut")
        w, h, r = (float(el.get(k)) * 1e-3 for el, k in ((rect, "width"), (rect, "height"), (hole, "r")))
        sigma = GRAMMAGE * parts[gid]["layers"]
        return sigma, w, h, r, float(hole.get("cx")) * 1e-3 - float(rect.get("x")) * 1e-3

    d = cfg.design
    sigma, w, h, r, hole_x = plate("part-frame-side-card-wide")
    assert hole_x == pytest.approx(w / 2, abs=1e-5)  # the hole at the card's middle: it balances on the skewer
    card_I = 2 * sigma * (w * h * (w**2 + h**2) / 12 - math.pi * r**4 / 2)
    card_m = 2 * sigma * (w * h - math.pi * r**2)
    # the article's hollow frame: every further cut rectangle is a window, its card and its inertia taken off
    card = group["part-frame-side-card-wide"]  # the wide frames' card is the hollow card, whole
    outline, *windows = (el for el in card.iter(SVG + "rect") if el.get("class") == "cut")
    assert len(windows) == 2
    hole = next(el for el in group["part-frame-side-card-wide"].iter(SVG + "circle") if el.get("class") == "cut")
    for win in windows:
        x, y, ww, wh = (float(win.get(k)) * 1e-3 for k in ("x", "y", "width", "height"))
        cx, cy = x + ww / 2 - float(hole.get("cx")) * 1e-3, y + wh / 2 - float(hole.get("cy")) * 1e-3
        card_I -= 2 * sigma * ww * wh * ((ww**2 + wh**2) / 12 + cx**2 + cy**2)
        card_m -= 2 * sigma * ww * wh
    assert card_I == pytest.approx(2 * d.m1 / 3 * (d.La**2 + d.Lb**2 - d.La * d.Lb), rel=1e-3)  # A13, as drawn
    world = World(cfg)
    body = world.frames[0].body
    about_axis = (body.moment + body.mass * body.center_of_gravity.length_squared) / INERTIA
    expected = card_I + d.m3 * (d.La**2 + d.h**2) + d.handrail_mass * d.Lb**2
    assert body.mass / MASS == pytest.approx(card_m + d.m3 + d.handrail_mass, rel=1e-3)  # the SVG draws to 0.01 mm
    assert about_axis == pytest.approx(expected, rel=1e-3)

    sigma, w, h, r, hole_x = plate("part-arm")  # drawn along x: w is the arm's net length, h its width across
    lip = w - hole_x - d.arm_length  # the hook's lip, folded at the tip
    rod_m, lip_m, hole_m = sigma * h * (w - lip), sigma * h * lip, sigma * math.pi * r**2
    rod_x = (w - lip) / 2 - hole_x  # the plate's centre from the axle, along the arm
    com = (rod_m * rod_x + lip_m * d.arm_length) / (rod_m + lip_m - hole_m)
    arm_I = rod_m * ((w - lip) ** 2 / 12 + (rod_x - com) ** 2) + lip_m * (d.arm_length - com) ** 2 - hole_m * com**2
    arm = world.robot.arm
    assert arm.mass / MASS == pytest.approx(d.arm_mass, rel=1e-6)
    assert arm.center_of_gravity.x / LENGTH == pytest.approx(com, rel=1e-3)
    assert arm.moment / INERTIA == pytest.approx(arm_I, rel=1e-3)


def test_the_crossbeam_lays_out_the_rows_axes_and_stoppers_at_1_to_1(tmp_path):
    """Read off the template alone: the axis holes lie pitch-and-rise apart along the beam, and a skewer in each
    stopper hole holds a side card (its hub bar read off the template too) at the rest angle and at the end stop:
    its centre a skewer's radius off the hub bar's edge, inside the window. Every segment of a long row, and
    segments that share their end axis."""
    cfg = load_config(ROOT / "configs/paper.yaml")
    d, s = cfg.design, cfg.scene
    main(["sheet", str(ROOT / "configs/paper.yaml"), "--out", str(tmp_path / "t.svg")])
    root = ET.parse(tmp_path / "t.svg").getroot()
    groups = {g.get("id"): g for g in root.iter(SVG + "g") if (g.get("id") or "").startswith("part-")}
    _, left, right = sorted((float(r.get("x")), float(r.get("width")))
                            for r in groups["part-frame-side-card-wide"].iter(SVG + "rect")
                            if r.get("class") == "cut")  # the outline, then its two windows (the hollow card)
    hub = right[0] - (left[0] + left[1])  # mm: the bar between the windows, the hole in it
    travel = math.radians(d.stop_angle_deg - d.rest_angle_deg + 15.0)  # with the 15 deg the rest stopper may move
    beams = sorted((k for k in groups if k.startswith("part-crossbeam-")), key=lambda k: int(k.rsplit("-", 1)[1]))
    assert beams, sorted(groups)
    beta = math.atan2(s.rise, s.pitch)
    step = math.hypot(s.pitch, s.rise) * 1e3

    def holds(offset_mm, angle_deg, falls):
        """A skewer at this offset from the axis (beam mm, v up) holds the card at ``angle_deg``."""
        u, v = offset_mm
        x, y = u * math.cos(beta) - v * math.sin(beta), u * math.sin(beta) + v * math.cos(beta)  # level world, mm
        a = math.radians(angle_deg)
        along, across = x * math.cos(a) + y * math.sin(a), -x * math.sin(a) + y * math.cos(a)
        # the SVG gives every coordinate to 0.01 mm, so 0.05 mm; a skewer's radius (1 mm) off the hub bar's edge,
        # each turning through the window over the travel: half of it off the frame line
        return (along == pytest.approx(hub / 2 + 1.0, abs=0.05)
                and abs(across) == pytest.approx((hub / 2 + 1.0) * math.tan(travel / 2), abs=0.05)
                and math.copysign(1, across) == falls)

    axes_seen = []
    for k in beams:
        holes = [(float(c.get("cx")), -float(c.get("cy"))) for c in groups[k].iter(SVG + "circle")
                 if c.get("class") == "cut"]
        rows: dict[float, list[float]] = {}
        for x, y in holes:
            rows.setdefault(round(y, 1), []).append(x)
        assert len(rows) == 3 and len({len(v) for v in rows.values()}) == 1, rows
        found = []
        for axis_y, xs in rows.items():
            xs = sorted(xs)
            assert all(b - a == pytest.approx(step, abs=0.02) for a, b in zip(xs, xs[1:]))
            others = [(y, sorted(v)[0] - xs[0]) for y, v in rows.items() if y != axis_y]
            # the rest stopper above the frame line at rest (the hub bar turns back into it), the end one below
            rest = [o for o in others if holds((o[1], o[0] - axis_y), d.rest_angle_deg, +1)]
            stop = [o for o in others if holds((o[1], o[0] - axis_y), d.stop_angle_deg, -1)]
            if rest and stop:
                found.append(len(xs))
        assert len(found) == 1, (k, rows)
        axes_seen.append(found[0])
    # consecutive segments share an axis, so the row's frames are the segments' axes less the shared ones
    assert sum(axes_seen) - (len(beams) - 1) == s.frames
