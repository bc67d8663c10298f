"""The progress of a batch of hand-made builds, on stderr (``aero-env robustness`` and ``aero-env sheet``)."""

from __future__ import annotations

import sys


class RunProgress:
    """The finished runs on stderr, as ``aero-env tune`` shows its trials: a tqdm bar (where the ``tune`` or ``rl``
    extra installed tqdm; else '<label>: 37/135 runs' rewritten in place); stdout, and so ``--json``, stays
    clean; nothing when not ``enabled`` (``--no-progress``). The bar starts at the first finished run, when the
    total is known. A callable for :func:`aero_env.robustness.study.assess`'s ``progress``."""

    def __init__(self, label: str, enabled: bool = True, stream=None):
        self.label, self.enabled, self.stream, self.bar = label, enabled, stream or sys.stderr, None

    def __call__(self, done: int, total: int) -> None:
        if not self.enabled:
            return
        if self.bar is None:
            try:
                from tqdm import tqdm
            except ImportError:  # the core install has no tqdm
                end = "\n" if done == total else ""
                print(f"\r{self.label}: {done}/{total} runs", end=end, file=self.stream, flush=True)
                return
            self.bar = tqdm(total=total, desc=self.label, unit="run", dynamic_ncols=True, file=self.stream)
        self.bar.update(done - self.bar.n)
        if done == total:
            self.close()

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()
            self.bar = None
