"""The bill of materials: what to buy and prepare for a design's row, read off the kit's pieces.

Card by the sheet (the kit's PDF pages, each a sheet of card: print on it, or print on paper and glue the
page onto card), the one-yen coins, the modelling clay in g, the bamboo skewers by count and length (and how
many skewers as sold that makes), the glue (the faces the laminated pieces glue together) and the base board.
"""

from __future__ import annotations

import math

from ..config import Config
from ..parts import build
from ..parts.kit import Piece, base_board, pieces, skewer_lengths

SKEWER_STOCK = 0.15  # m: a bamboo skewer as sold (15 cm; longer ones give more pieces each)


def card_area(ps: list[Piece]) -> float:
    """m² of card in every copy the kit cuts: each piece's outline less its holes, times its layers and count."""
    return sum(p.card_area_m2 * p.cuts for p in ps)


def glued_area(ps: list[Piece]) -> float:
    """m² of card faces glued to each other in the laminated pieces: (layers - 1) faces per piece."""
    return sum(p.card_area_m2 * max(p.layers - 1, 0) * p.count for p in ps)


def skewer_pieces(cfg: Config) -> list[tuple[str, int, float]]:
    """(what, how many, length in m) of each skewer piece the row needs."""
    lengths, frames = skewer_lengths(cfg), cfg.scene.frames
    return [("rotation axis", frames, lengths["axis"]), ("stopper", 2 * frames, lengths["stopper"]),
            ("robot's axle", 1, lengths["axle"])]


def stock_skewers(cfg: Config) -> int:
    """Skewers as sold (``SKEWER_STOCK`` long) that give every piece: each cut into as many pieces of one length
    as fit, a length's pieces never mixed on one skewer (the simple way to cut them)."""
    return sum(math.ceil(n / max(1, int(SKEWER_STOCK // length))) for _, n, length in skewer_pieces(cfg))


def bill_lines(cfg: Config, sheets: dict[str, int], too_big=(), in_pdf: bool = True) -> list[str]:
    """The bill, one line per thing to buy or prepare. ``sheets``: the kit's pages of pieces on each paper size
    (e.g. {"A4": 7}); ``too_big``: the kit's copies too long for a page, cut by measure. ``in_pdf``: the bill
    heads the kit's PDF (else it is the sheet's, which points to the PDFs)."""
    d, s = cfg.design, cfg.scene
    ps = pieces(cfg)
    load = build.counterbalance_load(d.m3)
    coins, clay, seats = int(load["coins"]), float(load["clay"]), float(load["seats"])
    stack = build.coin_stack(d)
    robot_coins, whole = stack["coins"], stack["whole"]
    n_copies = sum(p.cuts for p in ps)
    paper = " or ".join(f"{n} {name}" for name, n in sheets.items())
    pages = ("the pages after this one" if in_pdf else
             "the pieces' pages of kit-a4.pdf or kit-letter.pdf (beside this sheet)")
    lines = [
        *(("WHAT TO BUY AND PREPARE", "") if in_pdf else ()),
        f"Card: {paper} sheets of 0.4 mm, 310 g/m² card (the paper's JOHOKU WB310g, or any card of that weight), "
        f"{card_area(ps) * 1e4:.0f} cm² of it in {n_copies} pieces. Print {pages} on the card, or "
        f"print them on paper and glue each page onto a sheet of card before cutting.",
        f"One-yen coins (1.00 g, 20 mm across): {s.frames * coins + (round(robot_coins) if whole else 0)} "
        f"({coins} per counterbalance x {s.frames} frames"
        + (f", {round(robot_coins)} on the robot's torso)." if whole else
           f"); the robot's torso carries {d.coin_mass * 1e3:.2f} g of coins or metal."),
        f"Modelling clay: {s.frames * clay * 1e3:.1f} g ({clay * 1e3:.2f} g per counterbalance: weigh it with the "
        f"counterbalance's {build.COIN_SEATS} coin seats, {(clay + seats) * 1e3:.2f} g together, on a kitchen scale "
        f"that reads 0.1 g)." if clay > 0 else "Modelling clay: none (the counterbalances are whole coins and their "
        "coin seats).",
        f"Bamboo skewers, {build.SKEWER_D * 1e3:.0f} mm across: "
        + ", ".join(f"{n} x {length * 1e3:.0f} mm ({what})" for what, n, length in skewer_pieces(cfg))
        + f"; {stock_skewers(cfg)} skewers {SKEWER_STOCK * 1e2:.0f} cm long give them all.",
        f"Glue: white (PVA) glue or a glue stick for {glued_area(ps) * 1e4:.0f} cm² of laminated faces (each piece "
        f"of several layers is that many copies glued flat), the handrail's and the spring's tabs, and the stand.",
        "Base: a stiff, level board {:.0f} x {:.0f} mm.".format(*(x * 1e3 for x in base_board(cfg))),
    ]
    for c in too_big:
        lines.append(f"Cut by measure (longer than a page): {c.piece.name}, {c.total} copies of "
                     f"{c.width:.1f} x {c.height:.1f} mm.")
    lines += ["", "Tools: scissors or a craft knife and a ruler, a Ø2.4 mm punch or drill for the holes, a pencil, "
              "a kitchen scale." + (" The sheet (sheet.md) says how each piece goes together." if in_pdf else "")]
    return lines
