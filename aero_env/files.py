"""Every file the project writes, written whole or not at all; a failed write, and a file that cannot be read back,
said in one line.

:func:`write_atomically` writes a temporary file beside the target, ``fsync``\\ s it and renames it over the target:
a reader, or a run stopped half-way (Ctrl-C, SIGTERM, a full disk, a crash), finds the old file or the whole new
one, never part of one. A write that fails (the disk full, the folder gone or read-only) raises
:class:`WriteFailed`, a :class:`~aero_env.config.ConfigError` whose one line names the file, the system's reason
and that the old file is as it was; the command line prints it as a ``file error`` (exit status 2). Nothing is
left behind: no temporary file, no 0-byte plot.

The command line and the agents' commands write through here (plots, animations, traces, the kit, tuned and
fitted configs, a training run's files), so a new writer should too. :func:`read_text` reads a text file a user
names (a config, a measured trace) with the same one-line refusals: missing, a folder, unreadable, not text.
"""

from __future__ import annotations

import io
import os
from pathlib import Path
from typing import Callable

from .config.validation import ConfigError


class WriteFailed(ConfigError):
    """A file could not be written whole (its old content, if any, is kept): one line naming it and why."""


WriteFailed.__module__ = "aero_env.files"


def temporary_path(path: Path) -> Path:
    """Where :func:`write_atomically` writes ``path`` first: a hidden file beside it (same folder, so the rename
    stays on one file system and is atomic)."""
    return path.with_name(f".{path.name}.part")


def write_atomically(path: str | os.PathLike, write: Callable, what: str = "output file") -> None:
    """Write ``path`` through ``write(f)`` (``f`` a binary file open for writing) into a temporary file beside it,
    flush it to the disk, then rename it over ``path``. An ``OSError`` on the way (ENOSPC, EACCES, EROFS ...)
    raises :class:`WriteFailed` naming ``what`` and the file; every other exception (KeyboardInterrupt included)
    passes through unchanged. Either way the temporary file is removed and ``path`` holds what it held."""
    path = Path(path)
    tmp = temporary_path(path)
    try:
        with open(tmp, "wb") as f:
            write(f)
            f.flush()
            os.fsync(f.fileno())  # the data on the disk before the rename makes it the file (a crash keeps one whole)
        os.replace(tmp, path)
    except OSError as exc:
        kept = "it was left as it was" if path.exists() else "nothing was written"
        reason = exc.strerror or type(exc).__name__
        raise WriteFailed(f"{what} {str(path)!r}: cannot be written ({reason}); {kept}") from None
    finally:
        try:
            tmp.unlink(missing_ok=True)
        except OSError:  # the folder itself is gone or read-only: there is nothing of ours left in it
            pass


def write_text_atomically(path: str | os.PathLike, text: str, what: str = "output file") -> None:
    """:func:`write_atomically` for a text (UTF-8)."""
    write_atomically(path, lambda f: f.write(text.encode("utf-8")), what)


def text_writer(write_text: Callable[[io.TextIOBase], None]) -> Callable:
    """A ``write(f)`` for :func:`write_atomically` from one that writes text (``csv.writer`` and the like)."""
    def write(f) -> None:
        wrapper = io.TextIOWrapper(f, encoding="utf-8", newline="")
        write_text(wrapper)
        wrapper.flush()
        wrapper.detach()  # leave ``f`` open: write_atomically flushes and syncs it

    return write


def save_figure(fig, path: str | os.PathLike, what: str = "plot file", **savefig_kwargs) -> None:
    """matplotlib's ``fig.savefig`` through :func:`write_atomically` (the format from ``path``'s suffix)."""
    fmt = Path(path).suffix.lstrip(".").lower() or None
    write_atomically(path, lambda f: fig.savefig(f, format=fmt, **savefig_kwargs), what)


def read_text(path: str | os.PathLike, what: str, expected: str) -> str:
    """The UTF-8 text of ``path``, or a ConfigError naming ``what`` (e.g. "config file", "--trace") and the file
    when it is missing, a folder, unreadable or not text (a binary file, say), and ``expected`` what it should be
    ("YAML (e.g. configs/paper.yaml)")."""
    p = Path(path)
    if p.is_dir():
        raise ConfigError(f"{what} {str(p)!r}: is a folder; give {expected}")
    if not p.is_file():
        raise ConfigError(f"{what} {str(p)!r}: not found")
    try:
        return p.read_text(encoding="utf-8")
    except UnicodeDecodeError:
        raise ConfigError(f"{what} {str(p)!r}: not a text file; expected {expected}") from None
    except OSError as exc:
        raise ConfigError(f"{what} {str(p)!r}: cannot be read ({exc.strerror or exc})") from None
