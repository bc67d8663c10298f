"""``kit-a4.pdf`` and ``kit-letter.pdf``: every copy of every piece, whole on one page, no ink near an edge, and a
bill of materials that reads back against the config.

The PDFs are read here with pypdf (their drawing operators and text) and rasterised with PDFium, neither of which
wrote them; the expected counts and sizes are the config's, worked out here or read off the kit's pieces."""

import math
import re

import numpy as np
import pypdfium2 as pdfium
import pytest
from pypdf import PdfReader
from pypdf.generic import ContentStream

from aero_env.cli import main
from aero_env.parts.kit import parts_json, pieces

from .conftest import PAPER, per_test_under_mutmut
from .test_kit_readback import card_half_length, crossbeam_gap, hollow_card

PT = 25.4 / 72  # mm per PDF point
PAGE_MM = {"a4": (210.0, 297.0), "letter": (215.9, 279.4)}
EDGE = 5.0  # mm: no ink nearer an edge (issue 49)
GRAMMAGE, CARD_T = 0.310, 0.4e-3


@pytest.fixture(scope=per_test_under_mutmut)
def kit(tmp_path_factory):
    """A folder with the two PDFs as ``aero-env sheet --out FILE.pdf`` writes each (a folder's are the same bytes:
    test_sheet.py)."""
    out = tmp_path_factory.mktemp("kit")
    for paper in ("a4", "letter"):
        assert main(["sheet", str(PAPER), "--out", str(out / f"kit-{paper}.pdf"), "--paper", paper]) == 0
    return out


def red_polygons(reader: PdfReader, page) -> list[list[tuple[float, float]]]:
    """Every closed straight-sided path stroked red on a page, its corners in mm from the bottom-left."""
    out, path, colour, ctm, stack = [], [], None, np.eye(3), []
    for operands, op in ContentStream(page.get_contents(), reader).operations:
        if op == b"q":
            stack.append(ctm)
        elif op == b"Q":
            ctm = stack.pop()
        elif op == b"cm":
            a, b, c, d, e, f = (float(v) for v in operands)
            ctm = np.array([[a, b, 0], [c, d, 0], [e, f, 1]]) @ ctm
        elif op == b"RG":
            colour = tuple(float(v) for v in operands)
        elif op in (b"m", b"l"):
            x, y, _ = np.array([float(operands[0]), float(operands[1]), 1.0]) @ ctm
            path = [(x * PT, y * PT)] if op == b"m" else path + [(x * PT, y * PT)]
        elif op == b"c":
            path = None  # a curve: a circle, not an outline
        elif op in (b"S", b"s"):
            if path and colour == (1.0, 0.0, 0.0) and len(path) >= 3:
                out.append(path)
            path = []
    return out


def sizes_drawn(kit, paper, windows=False, corners=(4,)):
    """(size of each red outline of so many ``corners``, rounded to 0.1 mm and sorted, with its page) over the
    pieces' pages; an outline inside another is a window cut out of that piece, listed instead with ``windows``.
    A rectangle has 4 corners; a cut-away side card's outline more (``corners=range(5, 10**4)``)."""
    reader = PdfReader(kit / f"kit-{paper}.pdf")
    found = []
    for k, page in enumerate(reader.pages):
        boxes = []
        for poly in red_polygons(reader, page):
            xs, ys = [p[0] for p in poly], [p[1] for p in poly]
            if len(poly) in corners:
                boxes.append((min(xs), min(ys), max(xs), max(ys)))
        for b in boxes:
            inside = any(o != b and o[0] < b[0] and o[1] < b[1] and b[2] < o[2] and b[3] < o[3] for o in boxes)
            if inside == windows:
                found.append((tuple(sorted((round(b[2] - b[0], 1), round(b[3] - b[1], 1)))), k))
    return reader, found


@pytest.mark.parametrize("paper", ["a4", "letter"])
def test_every_page_is_its_paper_and_every_copy_a_build_needs_is_whole_on_one(kit, paper, paper_cfg):
    reader, found = sizes_drawn(kit, paper)
    w, h = PAGE_MM[paper]
    for page in reader.pages:
        assert float(page.mediabox.width) * PT == pytest.approx(w, abs=0.01)
        assert float(page.mediabox.height) * PT == pytest.approx(h, abs=0.01)
    # every piece cut from card, count x layers copies of its outline (its first cut rectangle), each drawn whole:
    # four corners on one page, inside the 5 mm the printer leaves
    expected, cut_expected = {}, {}
    for p in pieces(paper_cfg):
        if p.layers:
            rect = next((s for s in p.shapes if s.tag == "rect" and s.kind == "cut"), None)
            if rect is None:  # a cut-away side card: its outline's extent
                xs = [v for s in p.shapes if s.tag == "polygon" for v in s.xy[0::2]]
                ys = [v for s in p.shapes if s.tag == "polygon" for v in s.xy[1::2]]
                size = tuple(sorted((round(max(xs) - min(xs), 1), round(max(ys) - min(ys), 1))))
                cut_expected[size] = cut_expected.get(size, 0) + p.count * p.layers
                continue
            size = tuple(sorted((round(rect.xy[2], 1), round(rect.xy[3], 1))))
            expected[size] = expected.get(size, 0) + p.count * p.layers
    drawn = {}
    for size, _ in found:
        drawn[size] = drawn.get(size, 0) + 1
    assert drawn == expected
    cut_drawn = {}
    for size, _ in sizes_drawn(kit, paper, corners=range(5, 10**4))[1]:
        cut_drawn[size] = cut_drawn.get(size, 0) + 1
    assert cut_drawn == cut_expected
    # the prototype's side cards, worked out in test_kit_readback (the article's hollow frame), each with its two
    # windows cut out: two for each wide frame (1, 3, ...); the narrow frames' are cut away where their neighbours
    # pass, two for each of theirs
    d, frames = paper_cfg.design, paper_cfg.scene.frames
    length = 2 * card_half_length(d)
    layers, depth, end = hollow_card(d)
    copies = 2 * (frames // 2) * layers
    assert drawn[tuple(sorted((round(length, 1), round(depth, 1))))] == copies
    window = tuple(sorted((round(length / 2 - end - 3.0, 1), round(depth - 6.0, 1))))  # hub bar 6 mm, strips 3 mm
    assert [size for size, _ in sizes_drawn(kit, paper, windows=True)[1]] == [window] * 2 * copies
    narrow = next(p for p in pieces(paper_cfg) if p.id == "part-frame-side-card-narrow")
    assert sum(cut_drawn.values()) == 2 * ((frames + 1) // 2) * narrow.layers
    for k, page in enumerate(reader.pages):
        boxes = []
        for poly in red_polygons(reader, page):
            assert all(EDGE <= x <= w - EDGE and EDGE <= y <= h - EDGE for x, y in poly), (k, poly)
            boxes.append((min(p[0] for p in poly), min(p[1] for p in poly), max(p[0] for p in poly),
                          max(p[1] for p in poly)))
        boxes = [b for b in boxes if not any(o != b and o[0] < b[0] and o[1] < b[1] and b[2] < o[2] and b[3] < o[3]
                                             for o in boxes)]  # the windows lie inside their piece
        # no outline overlaps another: each copy can be cut out whole (a hole's circle is no outline)
        for i, a in enumerate(boxes):
            for b in boxes[i + 1:]:
                assert a[2] <= b[0] or b[2] <= a[0] or a[3] <= b[1] or b[3] <= a[1], (k, a, b)


@pytest.mark.parametrize("paper", ["a4", "letter"])
def test_no_ink_within_5_mm_of_an_edge_and_a_50_mm_bar_and_page_number_on_every_page(kit, paper):
    doc = pdfium.PdfDocument(kit / f"kit-{paper}.pdf")
    px = 2  # pixels a mm: a 0.25 mm line still greys its pixel
    pages = [np.asarray(doc[k].render(scale=px / PT).to_pil().convert("L")) for k in range(len(doc))]
    doc.close()
    reader = PdfReader(kit / f"kit-{paper}.pdf")
    for k, image in enumerate(pages):
        ink = image < 250
        band = int(EDGE * px)
        assert not (ink[:band].any() or ink[-band:].any() or ink[:, :band].any() or ink[:, -band:].any()), k
        assert ink.any()
        text = reader.pages[k].extract_text()
        assert f"page {k + 1} of {len(pages)}" in text and "the bar must measure 50 mm" in text
        # the bar: the one filled black rectangle, 50 mm long
        ops = ContentStream(reader.pages[k].get_contents(), reader).operations
        bars = [float(o[2]) * PT for o, op in ops if op == b"re"]
        assert bars == [pytest.approx(50.0, abs=1e-3)]


def test_each_copy_is_labelled_once_and_the_bill_reads_back_against_the_config(kit, paper_cfg):
    reader = PdfReader(kit / "kit-a4.pdf")
    pages = [p.extract_text() for p in reader.pages]
    labels = re.findall(r"^ *(.+) \((\d+)/(\d+)\)$", "\n".join(pages[1:]), re.M)
    for p in pieces(paper_cfg):
        if p.layers:
            mine = sorted(int(n) for name, n, total in labels if name == p.name and int(total) == p.count * p.layers)
            assert mine == list(range(1, p.count * p.layers + 1)), p.name
    bill = " ".join(pages[0].split())
    d, s = paper_cfg.design, paper_cfg.scene
    assert f"Card: {len(pages) - 1} A4 sheets of 0.4 mm, 310 g/m² card" in bill
    seats = 2 * 22e-3**2 * 0.310  # kg: each counterbalance's two coin seats (squares of card 22 mm a side)
    per = math.floor((d.m3 - seats) / 1e-3 + 1e-9)
    assert f"One-yen coins (1.00 g, 20 mm across): {s.frames * per + round(d.coin_mass / 1e-3)} " in bill
    clay = d.m3 - seats - per * 1e-3
    assert (f"Modelling clay: {s.frames * clay * 1e3:.1f} g ({clay * 1e3:.2f} g per counterbalance: weigh it with the "
            f"counterbalance's 2 coin seats, {(clay + seats) * 1e3:.2f} g together, on a kitchen scale") in bill
    # mm: the crossbeams' inner faces apart (clear of every frame's parts), 3 layers each, 2 mm proud each end
    across = crossbeam_gap(paper_cfg, parts_json(paper_cfg)) + 2 * 3 * 0.4 + 2 * 2
    assert (f"{s.frames} x {across:.0f} mm (rotation axis), {2 * s.frames} x {across:.0f} mm (stopper), 1 x " in bill)
    per_stock = 150 // math.ceil(across)
    axle = float(re.search(r"1 x (\d+) mm \(robot's axle\)", bill).group(1))
    stock = math.ceil(s.frames / per_stock) + math.ceil(2 * s.frames / per_stock) + 1
    assert f"; {stock} skewers 15 cm long give them all." in bill and axle <= 150


def test_the_same_kit_is_the_same_bytes(kit, tmp_path):
    assert main(["sheet", str(PAPER), "--out", str(tmp_path / "again.pdf")]) == 0
    assert (tmp_path / "again.pdf").read_bytes() == (kit / "kit-a4.pdf").read_bytes()


def test_a_piece_longer_than_a_page_is_cut_by_measure_and_said_so_on_the_first_page(tmp_path, paper_cfg):
    """A row whose first axis stands half a metre up: its uprights (510 mm and more) fit no page; the kit draws the
    rest and the bill says how to cut them, by measure."""
    out = tmp_path / "tall.pdf"
    assert main(["sheet", str(PAPER), "--out", str(out), "--set", "scene.floor_drop=0.5"]) == 0
    reader = PdfReader(out)
    bill = " ".join(reader.pages[0].extract_text().split())
    assert "Cut by measure (longer than a page): upright under the first axis, 6 copies of 10.0 x 510.0 mm." in bill
    labels = "\n".join(p.extract_text() for p in reader.pages[1:])
    # the wide frames' side cards: 4 frames, 2 cards each of the hollow card's layers
    copies = 4 * 2 * hollow_card(paper_cfg.design)[0]
    assert "upright under the first axis (" not in labels
    assert f"swing frame side card, wide frames ({copies}/{copies})" in labels


@pytest.mark.parametrize("config", sorted((PAPER.parent / "scenes/solutions").glob("*.yaml")), ids=lambda p: p.stem)
def test_every_stored_solutions_kit_prints_whole(config, tmp_path):
    """Each stored scene solution's kit: every copy on a page inside the margins, none overlapping, each labelled."""
    from aero_env.config import load_config

    out = tmp_path / "kit.pdf"
    assert main(["sheet", str(config), "--out", str(out)]) == 0
    reader = PdfReader(out)
    cfg = load_config(config)
    needed = sum(p.count * p.layers for p in pieces(cfg) if p.layers)
    labels = re.findall(r"\((\d+)/(\d+)\)$", "\n".join(p.extract_text() for p in reader.pages[1:]), re.M)
    assert len(labels) == needed
    for page in reader.pages:
        for poly in red_polygons(reader, page):
            assert all(EDGE <= x <= 210 - EDGE and EDGE <= y <= 297 - EDGE for x, y in poly)
