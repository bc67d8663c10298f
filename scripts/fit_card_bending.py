"""Fit the card's bending stiffness D on a measured leaf-spring strip (aero_env/parts/card.py).

    python scripts/fit_card_bending.py                      # the paper's 0.877 N·mm/rad, prototype strip
    python scripts/fit_card_bending.py --k 0.95 --width 4 --length 18   # your own bench measurement

One measurement, one unknown: D = k·L / (n·w) for a strip of width w, free length L (between its glue
lines) and n loose layers, whose stiffness k you measured as the paper does (Fig. 18: a load at the arm's
tip and the arm's turn). The paper gives k for its prototype but not the strip's size: the defaults are
the assumed PROTOTYPE_STRIP. Put the printed D in aero_env/parts/card.py's PAPER_CARD (or your card's).
"""

import argparse

from aero_env.parts.card import PAPER_CARD, PAPER_SPRING_K, PROTOTYPE_STRIP, Strip, fit_bending_stiffness


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--k", type=float, default=PAPER_SPRING_K * 1e3, help="measured stiffness, N·mm/rad (default: the paper's)")
    ap.add_argument("--width", type=float, default=PROTOTYPE_STRIP.width * 1e3, help="strip width, mm")
    ap.add_argument("--length", type=float, default=PROTOTYPE_STRIP.free_length * 1e3, help="free length, mm")
    ap.add_argument("--layers", type=int, default=PROTOTYPE_STRIP.layers, help="strips stacked loose")
    a = ap.parse_args()
    for name, v in (("--k", a.k), ("--width", a.width), ("--length", a.length), ("--layers", a.layers)):
        if not v > 0:
            ap.error(f"{name} {v}: must be > 0")
    strip = Strip(width=a.width * 1e-3, free_length=a.length * 1e-3, layers=a.layers)
    D = fit_bending_stiffness(a.k * 1e-3, strip)
    modulus = 12 * D / PAPER_CARD.thickness**3
    print(f"strip {a.width:g} mm x {a.length:g} mm free, {a.layers} layer(s), measured {a.k:g} N·mm/rad")
    print(f"bending stiffness D = {D:.4g} N·m (per unit width); stored: {PAPER_CARD.bending_stiffness:.4g} N·m")
    print(f"as a solid {PAPER_CARD.thickness * 1e3:g} mm sheet: E = 12·D/t³ = {modulus / 1e9:.2f} GPa")


if __name__ == "__main__":
    main()
