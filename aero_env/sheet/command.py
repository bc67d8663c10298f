"""``aero-env sheet``: from a config to what to cut.

    aero-env sheet CONFIG --out DIR|FILE.md|FILE.svg|FILE.json|FILE.glb [--draws N] [--seed S] [--set KEY=VALUE ...]

A folder: all of them, as ``DIR/sheet.md``, ``DIR/template.svg``, ``DIR/parts.json``, ``DIR/assembly.glb``,
``DIR/assembly.html``, ``DIR/kit-a4.pdf`` and ``DIR/kit-letter.pdf`` (the folder is made if missing; an earlier
sheet in it is written over, as a file would be).

- ``.json``: every piece of the kit (``aero_env/parts/kit.py``): how many to cut, its layers and card, what is
  added to it, its mass, and the model field it makes up.
- ``.md``: every part in mm and g (and 1-yen coins), the card pair that gives the friction, where the
  counterbalance goes, the spring as the paper measures it, whether the design completes its row, whether its
  parts clear each other through every frame's swing (``aero_env/parts/clearance.py``), and its robustness: the
  share of hand-made builds (``aero-env robustness``'s tolerances) that still complete it, the bench checks, and
  a troubleshooting table in the maker's words and units (what is seen, its cause, the change at the bench).
- ``.svg``: the template to print and cut (``template.py``): every part at 1:1 and the stand to scale.
- ``.pdf``: the kit to print on card (``kit_pdf.py``): a bill of materials, then every copy of every piece,
  packed whole onto pages of ``--paper`` (A4 or US Letter).
- ``.glb``: the row as 3D solids in metres (``aero_env/parts/solids.py``, ``gltf.py``), the frames at rest and
  the robot where the world starts it; ``.html``: the same model in a page any browser opens from the disk
  (``aero_env/parts/viewer.py``).

The output path and the stand are checked before any work; the layout's fit (seconds, up to a minute where no
card fits) and the robustness builds show their progress on stderr (``--no-progress``: none).
"""

from __future__ import annotations

import time
from pathlib import Path

from ..config import Config, ConfigError
from ..files import write_atomically, write_text_atomically
from ..scene_args import add_seed
from .kit_pdf import PAGES

DEFAULT_DRAWS = 50
DEFAULT_SEED = 0
FORMATS = (".md", ".svg", ".json", ".glb", ".html", ".pdf")


def register(sub, scene_command) -> None:
    sp = scene_command(sub, "sheet", "a build sheet (.md) and a 1:1 cutting template (.svg) for a design")
    sp.add_argument("--out", required=True, metavar="DIR|FILE.md|FILE.svg|FILE.json|FILE.glb|FILE.html|FILE.pdf",
                    help="a folder for all (sheet.md, template.svg, parts.json, assembly.glb, assembly.html, "
                         "kit-a4.pdf, kit-letter.pdf), or one file")
    sp.add_argument("--paper", choices=sorted(PAGES), default="a4",
                    help="the page size of a single FILE.pdf (a folder gets both; default a4)")
    sp.add_argument("--draws", type=int, default=DEFAULT_DRAWS,
                    help=f"hand-made builds drawn for the robustness line of a .md sheet; 0 skips it "
                         f"(default {DEFAULT_DRAWS})")
    add_seed(sp, DEFAULT_SEED, f"seed of the draws (default {DEFAULT_SEED})")
    sp.add_argument("--compare", metavar="CONFIG.yaml",
                    help="another design on the same scene (e.g. the one a robust tune started from): its share of "
                         "the same hand-made builds is shown beside this design's")
    sp.add_argument("--no-progress", action="store_true",
                    help="nothing on stderr while the layout is fitted and the robustness builds run")
    sp.set_defaults(func=cmd_sheet)


SHEET_NAME, TEMPLATE_NAME, PARTS_NAME, ASSEMBLY_NAME = "sheet.md", "template.svg", "parts.json", "assembly.glb"
VIEWER_NAME = "assembly.html"


def markdown(cfg: Config, config_name: str, draws: int, seed: int, template: str | None = None,
             progress: bool = False, compare: tuple[str, Config] | None = None) -> str:
    from ..simulation import simulate
    from .parts import lines

    rows = ["| part | what | value |", "|---|---|---|"]
    rows += [f"| {ln.part} | {ln.what} | {ln.value} |" for ln in lines(cfg)]
    r = simulate(cfg)
    verdict = (f"**In the simulated world this design {'completes' if r.outcome == 'completed' else 'does not complete'} "
               f"its row**: {r.traversals} of {r.frames - 1} transfers ({r.outcome}: {r.reason}).")
    from .troubleshoot import frame_balance, table

    robust = robustness_line(cfg, config_name, draws, seed, progress, compare)
    return "\n".join([f"# Build sheet: {config_name}", "", verdict, "", robust, "",
                      *rows, "",
                      "## What to buy", "", *buy_lines(cfg), "",
                      "## Do the parts clear each other?", "", *clearance_lines(cfg), "",
                      "## Bench checks", "",
                      "- **The spring**: the bench check in the table above (a load at the hook tip, the arm's turn).",
                      f"- **The frame's balance**: {frame_balance(cfg)}.", "",
                      "## If the row does not complete", "",
                      "What you see, its likely cause, and the change at the bench, with a value to aim for; then "
                      "each part's window, in which the world completes this design's row with everything else as "
                      "drawn, its margins, and whether a hand-made toy's tolerance fits in them "
                      "(`aero_env/sheet/troubleshoot.py`: each value walked out from the design's own until the row "
                      "fails, to 0.1 g, 2 % and 0.5 deg, and on to the end of its reach):", "",
                      *table(cfg), "",
                      "Lengths are measured along the card. The model is 2D: a part's width across follows from "
                      "its mass (aero_env/parts/build.py says how each is built). The friction pair is the paper's Table 3 (JIS K7125, 0.4 mm 310 g/m² card). "
                      + (f"The template to print at 100 % is [{template}]({template})." if template else
                         "`aero-env sheet CONFIG --out DIR` writes this sheet with its template."), ""])


def robustness_line(cfg: Config, config_name: str, draws: int, seed: int, progress: bool = False,
                    compare: tuple[str, Config] | None = None) -> str:
    """The share of ``draws`` hand-made builds that complete the row; with ``compare`` (a name and a config on
    the same scene), that design's share of the same builds beside it (the same seed draws the same errors).
    ``progress``: a bar of the builds on stderr."""
    if draws == 0:
        return "Robustness: not assessed (`--draws 0`)."
    from ..robustness.progress import RunProgress
    from ..intervals import wilson_interval
    from ..robustness.study import completed_builds
    from ..robustness.tolerances import DEFAULT_TOLERANCES

    def completed(c: Config, label: str) -> int:
        return completed_builds(c, DEFAULT_TOLERANCES, draws, seed, progress=RunProgress(label, progress))

    k = completed(cfg, "sheet: robustness")
    lo, hi = wilson_interval(k, draws)
    line = (f"Robustness: **{k} of {draws}** builds within a hand-made toy's tolerances complete the row "
            f"({100 * k / draws:.0f} %, 95 % interval {100 * lo:.0f}-{100 * hi:.0f} %; "
            f"`aero-env robustness {config_name} --draws {draws} --seed {seed}` says which parts matter most).")
    if compare is None:
        return line
    name, other = compare
    j = completed(other, "sheet: robustness of --compare")
    return line + f" The same {draws} builds of {name}: **{j} of {draws}** ({100 * j / draws:.0f} %)."


def buy_lines(cfg: Config) -> list[str]:
    """The bill of materials as the sheet's list, the card counted in sheets of both page sizes."""
    from .kit_pdf import copies, pack, page_count
    from .materials import bill_lines
    from ..parts.kit import pieces

    cs = copies(pieces(cfg))
    sheets, too_big = {}, []
    for paper, (name, _, _) in PAGES.items():
        placed, too_big = pack(cs, paper)
        sheets[name] = page_count(placed)
    return [f"- {line}" for line in bill_lines(cfg, sheets, too_big, in_pdf=False) if line]


CONTACTS_SHOWN = 8  # the sheet lists the first meetings; aero-env sheet --out FILE.glb writes the model to look at


def clearance_lines(cfg: Config) -> list[str]:
    """The static sweep's verdict in the sheet: each frame turned from rest to its end stop against the other
    frames (at rest and at their end stops) and the stand."""
    from ..parts.clearance import TOUCH, static_sweep
    from ..parts.layout import nested_refusal
    from ..parts.solids import assembly

    asm = assembly(cfg)
    contacts = static_sweep(asm)
    refused = nested_refusal(cfg)
    layout = (f"{asm.layout.name}, narrow and wide frames alternating" if not refused else
              f"{asm.layout.name}, every frame alike: the nested layout does not serve this design, as {refused}")
    head = (f"Each frame turned from rest to its end stop in 1 deg steps against the other frames (at rest and at "
            f"their end stops) and the stand, as 3D solids in the kit's layout ({layout}; `assembly.glb` shows "
            f"it):")
    if not contacts:
        return [head + f" **the parts clear** (no two share more than {TOUCH * 1e9:.0f} mm³)."]
    frames = sorted({c.frame for c in contacts})
    first = min(contacts, key=lambda c: c.angle_deg)
    lines = [head + f" **the parts collide**: {len(contacts)} pairs of parts meet, on {len(frames)} of "
             f"{len(asm.frames)} frames, the first at theta1 = {first.angle_deg:.0f} deg "
             f"(this toy cannot be built as drawn).", ""]
    lines += [f"- {c.line()}" for c in sorted(contacts, key=lambda c: (c.angle_deg, c.frame))[:CONTACTS_SHOWN]]
    if len(contacts) > CONTACTS_SHOWN:
        lines.append(f"- and {len(contacts) - CONTACTS_SHOWN} more")
    return lines


def assembly_bytes(cfg: Config) -> bytes:
    """The row as ``assembly.glb``: the frames at rest, the robot where the world starts it."""
    from ..parts.gltf import glb
    from ..parts.solids import assembly
    from ..physics.world import World

    frames, axle, torso, arm = World(cfg).pose()
    return glb(assembly(cfg), frames, (axle, torso, arm))


def viewer_html(model: bytes, config_name: str) -> str:
    from ..parts.viewer import html

    return html(model, f"aero-env: {config_name}, the row in 3D")


def parts_text(cfg: Config, config_name: str) -> str:
    import json

    from ..parts.kit import parts_json

    return json.dumps(parts_json(cfg, config_name), indent=2) + "\n"


def fit_layout(cfg: Config, stream=None) -> None:
    """Work out the kit's layout now, saying so on ``stream`` (stderr) where it is not kept from before: the fit of
    the nested layout's cards takes seconds, and half a minute or more where no card fits, in silence otherwise."""
    import sys

    from ..parts.layout import is_kept, nested_layout

    if is_kept(cfg):
        return
    stream = stream or sys.stderr
    print("aero-env sheet: fitting the side cards of the nested layout ...", file=stream, flush=True)
    t = time.perf_counter()
    row = nested_layout(cfg)
    verdict = "found" if row.found else "none found: every frame is drawn alike (the sheet says why)"
    print(f"aero-env sheet: the nested layout: {verdict}, in {time.perf_counter() - t:.1f} s", file=stream, flush=True)


def cmd_sheet(args) -> int:
    from ..parts.kit import check_counterbalance, check_stand
    from ..scene_args import check_output, check_output_dir, load_scene
    from .kit_pdf import kit_pdfs
    from .template import svg

    out = Path(args.out)
    folder = out.suffix == "" or out.is_dir()
    if folder:  # like a file, the folder's own sheet.md and template.svg are written over
        check_output_dir(out, "--out", overwrite=True)
    else:
        check_output(args.out, "--out", FORMATS)
    if isinstance(args.draws, bool) or args.draws < 0:
        raise ConfigError(f"--draws {args.draws}: must be a whole number >= 0 (0 skips the robustness line)")
    cfg = load_scene(args)
    compare = None
    if args.compare is not None:
        from ..config import load_config
        from ..design_space import changes_outside_tunables

        if not Path(args.compare).is_file():
            raise ConfigError(f"--compare {args.compare!r}: no such config file")
        other = load_config(args.compare)
        differs = changes_outside_tunables(cfg, other)
        if differs:
            raise ConfigError(f"--compare {args.compare!r}: not the same scene and robot, only another design "
                              f"({', '.join(differs[:4])}{' ...' if len(differs) > 4 else ''} differ)")
        compare = (args.compare, other)
    check_stand(cfg)  # before the layout's fit: a row the stand cannot hold is refused at once
    check_counterbalance(cfg)  # and a counterbalance lighter than its coin seats
    t0 = time.perf_counter()
    progress = not args.no_progress
    if progress:
        fit_layout(cfg)
    # every text is made before the first file is written: a run stopped in the robustness builds (Ctrl-C, a
    # failure) leaves no template without its sheet
    if folder:
        pdfs = kit_pdfs(cfg, f"aero-env kit: {args.config}")
        model = assembly_bytes(cfg)
        files = {**{out / f"kit-{paper}.pdf": data for paper, data in pdfs.items()},
                 out / ASSEMBLY_NAME: model, out / VIEWER_NAME: viewer_html(model, args.config),
                 out / PARTS_NAME: parts_text(cfg, args.config),
                 out / TEMPLATE_NAME: svg(cfg),
                 out / SHEET_NAME: markdown(cfg, args.config, args.draws, args.seed, TEMPLATE_NAME, progress, compare)}
        out.mkdir(parents=True, exist_ok=True)
    elif out.suffix == ".glb":
        files = {out: assembly_bytes(cfg)}
    elif out.suffix == ".html":
        files = {out: viewer_html(assembly_bytes(cfg), args.config)}
    elif out.suffix == ".pdf":
        files = {out: kit_pdfs(cfg, f"aero-env kit: {args.config}", (args.paper,))[args.paper]}
    elif out.suffix == ".svg":
        files = {out: svg(cfg)}
    elif out.suffix == ".json":
        files = {out: parts_text(cfg, args.config)}
    else:
        files = {out: markdown(cfg, args.config, args.draws, args.seed, progress=progress, compare=compare)}
    for path, content in files.items():
        if isinstance(content, bytes):
            write_atomically(path, lambda f, content=content: f.write(content), "kit file")
        else:
            write_text_atomically(path, content, "kit file")
    written = ", ".join(str(path) for path in reversed(files))
    print(f"wrote {written} in {time.perf_counter() - t0:.1f} s")
    return 0
