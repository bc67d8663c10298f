"""The kit as PDF pages to print and cut: every copy of every piece, each whole on one page, and what to buy.

``aero-env sheet CONFIG --out DIR`` writes ``kit-a4.pdf`` and ``kit-letter.pdf``. Page 1 is the bill of
materials (:func:`aero_env.sheet.materials.bill`); the pages after it hold the pieces of
:func:`aero_env.parts.kit.pieces`, one copy per layer to cut (a side card of three layers on a frame of two
cards, eight frames: 48 copies), packed by rectpack (max-rects, turned 90 deg where that packs better) so
that no piece is split between pages. Every page keeps ``MARGIN`` clear at each edge (home printers do not
print the outer 5 mm or so) and carries a 50 mm bar to check the print's scale and its page number. A piece
longer than a page (an upright under a high row) is not drawn; the first page says to cut it by measure.

The lines keep the template's convention (``aero_env/sheet/template.py``): cut red and solid, fold blue and
dashed, marks black. A label above each copy names it and counts it ("side card 3 of 48").
"""

from __future__ import annotations

import io
import math
from dataclasses import dataclass

import rectpack
from reportlab.lib.pagesizes import A4, LETTER
from reportlab.lib.units import mm
from reportlab.pdfbase.pdfmetrics import stringWidth
from reportlab.pdfgen import canvas

from ..parts.kit import Piece, Shape, shapes_extent

PAGES = {"a4": ("A4", A4[0] / mm, A4[1] / mm), "letter": ("US Letter", LETTER[0] / mm, LETTER[1] / mm)}
EDGE = 5.0  # mm: no ink nearer a page's edge than this (what home printers leave unprinted)
MARGIN = EDGE + 3.0  # mm: the pages' clear border, room for a printer's shift and the line widths past EDGE
HEADER = 12.0  # mm: the bar, the page number and the legend at the top of each page
GAP = 3.0  # mm between pieces: room for the scissors
FONT, LABEL_PT, HEAD_PT = "Helvetica", 6.0, 7.0
LABEL = 3.0  # mm: a copy's label line, above the copy
UNIT = 10  # the packer works in whole tenths of a mm
COLOURS = {"cut": (1.0, 0.0, 0.0), "fold": (0.0, 0.0, 1.0), "mark": (0.0, 0.0, 0.0)}
WIDTHS = {"cut": 0.25, "fold": 0.25, "mark": 0.3}  # mm


@dataclass(frozen=True)
class Copy:
    """One copy of a piece to cut: ``n`` of ``total``; ``width`` and ``height`` (mm) are its drawing's extent."""
    piece: Piece
    n: int
    total: int
    x0: float  # the drawing's extent in the piece's own coordinates (mm, y down)
    y0: float
    width: float
    height: float

    @property
    def label(self) -> str:
        return f"{self.piece.name} ({self.n}/{self.total})"


@dataclass(frozen=True)
class Placed:
    """A copy on a page (``page`` counts the pieces' pages from 0): the top-left corner of its box (mm from the
    page's top-left, y down). The box is the copy's label line over its drawing; ``turned``: the whole box turned
    90 deg clockwise, the label then reading down its right-hand side."""
    copy: Copy
    page: int
    x: float
    y: float
    turned: bool


def copies(pieces: list[Piece]) -> list[Copy]:
    """Every copy a build needs: ``count`` pieces of ``layers`` layers each, for every piece cut from card."""
    out = []
    for p in (p for p in pieces if p.cuts):  # not the counterbalance: coins and clay, nothing to cut
        x0, y0, x1, y1 = shapes_extent(p.shapes)
        out += [Copy(p, n, p.cuts, x0, y0, x1 - x0, y1 - y0) for n in range(1, p.cuts + 1)]
    return out


def area(paper: str) -> tuple[float, float]:
    """The printable box of a page (mm): inside the margins, under the header."""
    _, w, h = PAGES[paper]
    return w - 2 * MARGIN, h - 2 * MARGIN - HEADER


def room(c: Copy) -> tuple[float, float]:
    """The room a copy's box takes (mm, unturned, without the gap): its label's line above its drawing, as wide as
    the wider of the two."""
    return max(c.width, stringWidth(c.label, FONT, LABEL_PT) / mm), c.height + LABEL


def fits(c: Copy, paper: str) -> bool:
    (w, h), (aw, ah) = room(c), area(paper)
    return (w <= aw and h <= ah) or (h <= aw and w <= ah)


# the packers tried, fewest pages wins (ties: the first): max-rects with three rules, each on the copies sorted
# by area and by their longer side
PACKERS = [(algo, order) for algo in (rectpack.MaxRectsBssf, rectpack.MaxRectsBaf, rectpack.MaxRectsBl)
           for order in (rectpack.SORT_AREA, rectpack.SORT_LSIDE)]


def _packed(sizes: dict[int, tuple[int, int]], bin_size: tuple[int, int], algo, order) -> list[tuple]:
    packer = rectpack.newPacker(mode=rectpack.PackingMode.Offline, pack_algo=algo, sort_algo=order, rotation=True)
    for i, size in sizes.items():
        packer.add_rect(*size, rid=i)
    packer.add_bin(*bin_size, count=float("inf"))
    packer.pack()
    return packer.rect_list()


def page_count(placed: list[Placed]) -> int:
    """The pages a packing fills (its copies' pages count from 0)."""
    return 1 + max((p.page for p in placed), default=-1)


def pack(cs: list[Copy], paper: str) -> tuple[list[Placed], list[Copy]]:
    """(placed copies, copies too big for a page). Each copy's box and a gap, packed on as few pages as the
    ``PACKERS`` manage; deterministic."""
    aw, ah = area(paper)
    sizes = {i: (math.ceil((room(c)[0] + GAP) * UNIT), math.ceil((room(c)[1] + GAP) * UNIT))
             for i, c in enumerate(cs) if fits(c, paper)}
    too_big = [c for i, c in enumerate(cs) if i not in sizes]
    # the gap right of and below each copy may reach past the area's edge: the bin is one gap larger
    bin_size = (math.floor((aw + GAP) * UNIT), math.floor((ah + GAP) * UNIT))
    best = min((_packed(sizes, bin_size, algo, order) for algo, order in PACKERS),
               key=lambda rects: 1 + max((r[0] for r in rects), default=-1))
    placed = [Placed(cs[i], page, MARGIN + x / UNIT, MARGIN + HEADER + y / UNIT, (w, h) != sizes[i])
              for page, x, y, w, h, i in sorted(best, key=lambda r: (r[0], r[2], r[1]))]
    if len(placed) != len(sizes):
        raise RuntimeError(f"the packer placed {len(placed)} of {len(sizes)} copies")
    return placed, too_big


# ---- drawing ------------------------------------------------------------------------------------------------------
def _to_page(p: Placed, page_h: float):
    """A function from the piece's own mm (y down) to the page's points (reportlab: y up from the bottom)."""
    c = p.copy
    box_h = room(c)[1]

    def at(x, y):
        u, v = x - c.x0, LABEL + y - c.y0  # in the copy's box, from its top-left, y down
        if p.turned:  # 90 deg clockwise: the box's top edge becomes its right-hand edge
            u, v = box_h - v, u
        return (p.x + u) * mm, (page_h - (p.y + v)) * mm

    return at


def draw_label(pdf: canvas.Canvas, p: Placed, page_h: float) -> None:
    pdf.setFillColorRGB(0, 0, 0)
    pdf.setFont(FONT, LABEL_PT)
    base = LABEL - 0.8  # the label's baseline, down from the box's top
    if not p.turned:
        pdf.drawString(p.x * mm, (page_h - p.y - base) * mm, p.copy.label)
        return
    pdf.saveState()
    pdf.translate((p.x + room(p.copy)[1] - base) * mm, (page_h - p.y) * mm)
    pdf.rotate(-90)  # reading down the page
    pdf.drawString(0, 0, p.copy.label)
    pdf.restoreState()


def draw_shape(pdf: canvas.Canvas, s: Shape, at) -> None:
    pdf.setStrokeColorRGB(*COLOURS[s.kind])
    pdf.setLineWidth(WIDTHS[s.kind] * mm)
    pdf.setDash([1.2 * mm, 0.8 * mm] if s.kind == "fold" else [])
    if s.tag == "rect":
        x, y, w, h = s.xy
        corners = [at(x, y), at(x + w, y), at(x + w, y + h), at(x, y + h)]
        path = pdf.beginPath()
        path.moveTo(*corners[0])
        for q in corners[1:]:
            path.lineTo(*q)
        path.close()
        pdf.drawPath(path, stroke=1, fill=0)
    elif s.tag == "circle":
        x, y, r = s.xy
        pdf.circle(*at(x, y), r * mm, stroke=1, fill=0)
    else:  # a line, or a polygon's outline (closed)
        pts = [at(s.xy[k], s.xy[k + 1]) for k in range(0, len(s.xy), 2)]
        path = pdf.beginPath()
        path.moveTo(*pts[0])
        for q in pts[1:]:
            path.lineTo(*q)
        if s.tag == "polygon":
            path.close()
        pdf.drawPath(path, stroke=1, fill=0)


def header(pdf: canvas.Canvas, title: str, page: int, pages: int, page_h: float) -> None:
    """The 50 mm bar, the page number and what to do with the page, inside the top margin's box."""
    y = page_h - MARGIN
    pdf.setFillColorRGB(0, 0, 0)
    pdf.setFont(FONT, HEAD_PT)
    pdf.drawString(MARGIN * mm, (y - 3.0) * mm, f"{title}  -  page {page} of {pages}  -  print at 100 % (no fit to "
                                                f"page): the bar must measure 50 mm")
    pdf.rect(MARGIN * mm, (y - 7.0) * mm, 50 * mm, 2 * mm, stroke=0, fill=1)
    pdf.drawString((MARGIN + 53) * mm, (y - 6.8) * mm, "50 mm")
    pdf.drawString((MARGIN + 70) * mm, (y - 6.8) * mm, "red: cut (holes too)   blue dashed: score, then fold   "
                                                      "black: marks")


LINE = 4.0  # mm: a text line on the bill's page
TEXT_PT = 8.0


def paginate(lines: list[str], paper: str) -> list[list[str]]:
    """The bill's lines wrapped to the page's width and cut into pages."""
    from textwrap import wrap

    aw, ah = area(paper)
    chars = int(aw / (stringWidth("n", FONT, TEXT_PT) / mm))
    wrapped = [part for line in lines for part in (wrap(line, chars, subsequent_indent="    ") or [""])]
    per_page = int(ah // LINE)
    return [wrapped[k:k + per_page] for k in range(0, len(wrapped), per_page)] or [[]]


def kit_pdf(pieces: list[Piece], bill_lines, paper: str, title: str) -> bytes:
    """The kit's PDF on ``paper`` ("a4" or "letter"): the bill of materials (``bill_lines(page name, sheets of
    pieces, copies too big for a page)`` gives its lines), then the pieces' pages."""
    name, page_w, page_h = PAGES[paper]
    placed, too_big = pack(copies(pieces), paper)
    sheets = page_count(placed)
    bill = paginate(bill_lines(name, sheets, too_big), paper)
    total = len(bill) + sheets
    buf = io.BytesIO()
    # invariant: no creation date nor random document id, so the same kit gives the same bytes
    pdf = canvas.Canvas(buf, pagesize=(page_w * mm, page_h * mm), invariant=1)
    pdf.setTitle(title)
    for k, lines in enumerate(bill):
        header(pdf, title, k + 1, total, page_h)
        pdf.setFont(FONT, TEXT_PT)
        for j, line in enumerate(lines):
            pdf.drawString(MARGIN * mm, (page_h - MARGIN - HEADER - (j + 1) * LINE) * mm, line)
        pdf.showPage()
    for sheet in range(sheets):
        header(pdf, title, len(bill) + sheet + 1, total, page_h)
        for p in (q for q in placed if q.page == sheet):
            draw_label(pdf, p, page_h)
            at = _to_page(p, page_h)
            for s in p.copy.piece.shapes:
                draw_shape(pdf, s, at)
        pdf.showPage()
    pdf.save()
    return buf.getvalue()


def kit_pdfs(cfg, title: str, papers=tuple(PAGES)) -> dict[str, bytes]:
    """The kit on each of ``papers``: {"a4": bytes, "letter": bytes}."""
    from ..parts.kit import pieces
    from .materials import bill_lines

    ps = pieces(cfg)

    def bill(name, sheets, too_big):
        return bill_lines(cfg, {name: sheets}, too_big)

    return {paper: kit_pdf(ps, bill, paper, title) for paper in papers}
