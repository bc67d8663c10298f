"""What a command's arguments name: the scene config with its ``--set`` overrides, and the paths it writes.

Every ``aero-env`` subcommand, this package's and the agents', reads its scene with
:func:`load_scene` and checks every path it will write with :func:`check_output` (a file) or
:func:`check_output_dir` (a run's folder) before any work starts, so that a slip in a path ends
with one line and exit status 2 instead of a traceback after the work (``tune --out nodir/best.yaml``
used to run all its trials first). Options that several commands share are defined here once
(:func:`add_seed`, :func:`whole`), so that each is refused in the same words by every command,
by argparse, before the command's first line runs. Nothing here imports the command line.
"""

from __future__ import annotations

import argparse
import os
from pathlib import Path
from typing import Iterable

from .config import Config, ConfigError, load_config, parse_override

PLOT_SUFFIXES = (".png", ".pdf", ".svg", ".jpg", ".jpeg")  # what matplotlib's savefig writes by name
YAML_SUFFIXES = (".yaml", ".yml")
CSV_SUFFIXES = (".csv",)
MAX_SEED = 2**31 - 1  # numpy's and torch's seeds take more; Optuna's samplers and SB3 take up to this


def whole(lo: int, hi: int):
    """An argparse ``type`` for a whole number in [lo, hi]: a slip (``-3`` for a seed, ``2.5`` for a count) is
    argparse's one-line error naming the option, the value and the range, before the command runs."""
    def parse(text: str) -> int:
        value = _whole_in(text, lo, hi)
        if value is None:
            raise argparse.ArgumentTypeError(f"{text!r}: must be a whole number in [{lo}, {hi}]")
        return value

    parse.__name__ = f"whole number in [{lo}, {hi}]"  # what argparse names in its own messages
    return parse


def _whole_in(text, lo: int, hi: int) -> int | None:
    """``text`` as a whole number in [lo, hi] (decimal, as written: ``1.5`` and ``x`` are not), else None."""
    try:
        value = int(str(text), 10)
    except ValueError:
        return None
    return value if lo <= value <= hi else None


def add_seed(parser, default: int, help_text: str) -> None:
    """The ``--seed`` option, as every command defines it: a whole number in [0, MAX_SEED]."""
    parser.add_argument("--seed", type=whole(0, MAX_SEED), default=default, metavar="S", help=help_text)


def load_scene(args) -> Config:
    """The config a scene command names (``args.config``), with its ``--set`` overrides (``args.set``)."""
    overrides = dict(parse_override(s) for s in getattr(args, "set", None) or [])
    return load_config(args.config, overrides)


def whole_number(option: str, text, lo: int, hi: int, why: str = "") -> int:
    """An option's whole number within [lo, hi], or a ConfigError naming it (and ``why`` the range, if given)."""
    value = _whole_in(text, lo, hi)
    if value is None:
        raise ConfigError(f"{option} = {text!r}: must be a whole number in [{lo}, {hi}]" + (f" ({why})" if why else ""))
    return value


def check_output(path: str | os.PathLike | None, option: str, suffixes: Iterable[str] | None = None) -> None:
    """Refuse an output file before any work: its folder must exist and be writable, the path must not be
    a folder, and its suffix (when ``suffixes`` is given) must be one that can be written. None passes."""
    if path is None or str(path) == "":
        return
    p = Path(path)
    folder = p.parent
    if p.is_dir():
        raise ConfigError(f"{option} {str(path)!r}: is a folder; give a file name")
    if not folder.is_dir():
        what = "is a file, not a folder" if folder.exists() else "does not exist"
        raise ConfigError(f"{option} {str(path)!r}: folder {str(folder)!r} {what}; create it first or give "
                          f"another path")
    if not os.access(folder, os.W_OK):
        raise ConfigError(f"{option} {str(path)!r}: folder {str(folder)!r} is not writable")
    if suffixes is not None:
        suffixes = tuple(suffixes)
        if p.suffix.lower() not in suffixes:
            raise ConfigError(f"{option} {str(path)!r}: suffix {p.suffix or '(none)'!r} cannot be written, "
                              f"allowed {', '.join(suffixes)}")


def check_not_the_config(path: str | os.PathLike | None, option: str, config: str | os.PathLike) -> None:
    """Refuse to write a command's output config over the config it reads (``tune X.yaml --out X.yaml``): the
    output is a complete config in bare SI, so a hand-written file would lose its comments and units."""
    if path is None or not Path(path).is_file() or not Path(config).is_file():
        return
    if os.path.samefile(path, config):
        raise ConfigError(f"{option} {str(path)!r}: is the config this command reads; it would be written over as bare "
                          f"SI values, its comments and units lost: give another file")


def check_output_dir(path: str | os.PathLike, option: str, overwrite: bool = False,
                     how: str = "--overwrite to replace what is in it") -> None:
    """Refuse a run's output folder before any work: not a file, and empty unless ``overwrite`` (a used
    folder would mix two runs). A missing folder is fine: the run makes it, with its parents."""
    p = Path(path)
    if p.exists() and not p.is_dir():
        raise ConfigError(f"{option} {str(path)!r}: is a file; give a folder")
    if p.is_dir():
        if not os.access(p, os.W_OK):
            raise ConfigError(f"{option} {str(path)!r}: folder is not writable")
        entries = sorted(e.name for e in p.iterdir())
        if entries and not overwrite:
            shown = ", ".join(entries[:3]) + (f" and {len(entries) - 3} more" if len(entries) > 3 else "")
            raise ConfigError(f"{option} {str(path)!r}: folder is not empty ({shown}); give a new folder, or "
                              f"{how}")
    else:
        ancestor = next((a for a in p.absolute().parents if a.exists()), None)
        if ancestor is not None and (not ancestor.is_dir() or not os.access(ancestor, os.W_OK)):
            raise ConfigError(f"{option} {str(path)!r}: cannot be made in {str(ancestor)!r} (not a writable "
                              f"folder)")
