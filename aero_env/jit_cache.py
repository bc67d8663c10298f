"""Where numba caches the project's compiled code: one folder per version of the source, numba and Python.

numba's own cache checks only the file that holds a function, not the files its callees live in; a folder
keyed on the text of every file a compiled function reads means an edited callee can never run under a stale
caller. The root is ``~/.cache/aero-env`` (``$XDG_CACHE_HOME/aero-env``; ``AERO_ENV_CACHE`` moves it). Both
compiled parts use it: the reduced model's kernels (:mod:`aero_env.models.reduced`) and the pymunk world's
friction switch (:mod:`aero_env.physics.slip_kernel`).
"""

from __future__ import annotations

import contextlib
import hashlib
import os
import sys
from pathlib import Path
from typing import Iterable, Iterator


def cache_dir(folder: Path, files: Iterable[str]) -> Path:
    """The cache folder for compiled functions whose source is ``files`` (names inside ``folder``)."""
    import numba

    digest = hashlib.sha256()
    for name in files:
        digest.update((Path(folder) / name).read_bytes())
    digest.update(f"{numba.__version__} {sys.version}".encode())
    root = os.environ.get("AERO_ENV_CACHE") or os.path.join(
        os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache"), "aero-env")
    return Path(root) / "numba" / digest.hexdigest()[:16]


@contextlib.contextmanager
def caching_in(path: Path) -> Iterator[None]:
    """Decorate (import) compiled functions inside this block to cache them in ``path``: numba reads its
    cache folder when a function is decorated, so this points it at ours for our modules only."""
    import numba

    previous = numba.config.CACHE_DIR
    numba.config.CACHE_DIR = str(path)
    try:
        yield
    finally:
        numba.config.CACHE_DIR = previous
