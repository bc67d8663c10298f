"""A measured swing, as a video tool (Kinovea) exports it: read and checked.

The CSV has a header row and one row per video frame from the catch to the slip-off:

=============  ==========================================================
``t``          s, 0 at the catch (the arm hooking the handrail), rising
``theta1_deg`` frame angle from the horizontal, deg (the paper's theta1)
``theta2_deg`` optional: robot line angle from the horizontal, deg
=============  ==========================================================

Other columns are ignored; the separator may be a comma, a semicolon or a tab. Bad input raises
``ConfigError`` naming the file, the row, the column and the value.
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..config import ConfigError

TIME, THETA1, THETA2 = "t", "theta1_deg", "theta2_deg"
MIN_ROWS = 3  # fewer samples cannot tell a swing's shape
ANGLE_LIMIT_DEG = 360.0  # |angle| beyond a full turn is not an angle in degrees
SEPARATORS = ",;\t"


@dataclass(frozen=True)
class MeasuredSwing:
    """Measured times (s from the catch) and angles (deg); ``theta2`` is None when not measured."""

    t: np.ndarray
    theta1: np.ndarray
    theta2: np.ndarray | None
    path: str = ""


def load_measured(path: str | Path) -> MeasuredSwing:
    """Read and check a measured swing CSV."""
    p = Path(path)
    if not p.is_file():
        raise ConfigError(f"--trace {str(p)!r}: not found")
    lines = [ln for ln in p.read_text().splitlines() if ln.strip()]
    if not lines:
        raise ConfigError(f"--trace {str(p)!r}: empty; expected a header row with columns {TIME}, {THETA1}")
    reader = csv.DictReader(lines, dialect=_dialect(lines[0]))
    header = [h.strip() for h in reader.fieldnames or []]
    reader.fieldnames = header
    for column in (TIME, THETA1):
        if column not in header:
            raise ConfigError(f"--trace {str(p)!r}: missing column {column!r}; columns found: {header}; required: "
                              f"{TIME} (s from the catch), {THETA1} (deg), optional {THETA2} (deg)")
    rows = list(reader)
    if len(rows) < MIN_ROWS:
        raise ConfigError(f"--trace {str(p)!r}: {len(rows)} data rows; at least {MIN_ROWS} are needed")
    t = _column(rows, TIME, p)
    theta1 = _column(rows, THETA1, p)
    theta2 = _column(rows, THETA2, p) if THETA2 in header else None
    _check_times(t, p)
    for column, values in ((THETA1, theta1), (THETA2, theta2)):
        if values is not None:
            _check_angles(values, column, p)
    return MeasuredSwing(t=t, theta1=theta1, theta2=theta2, path=str(p))


def _dialect(header: str):
    try:
        return csv.Sniffer().sniff(header, delimiters=SEPARATORS)
    except csv.Error:
        return csv.excel


def _column(rows: list[dict], column: str, p: Path) -> np.ndarray:
    out = []
    for i, row in enumerate(rows):
        raw = (row.get(column) or "").strip()
        try:
            v = float(raw)
        except ValueError:
            v = math.nan
        if not math.isfinite(v):
            raise ConfigError(f"--trace {str(p)!r}: data row {i + 1}, column {column} = {raw!r}: must be a finite "
                              f"number")
        out.append(v)
    return np.array(out)


def _check_times(t: np.ndarray, p: Path) -> None:
    if t[0] < 0:
        raise ConfigError(f"--trace {str(p)!r}: data row 1, column {TIME} = {float(t[0])!r}: must be >= 0 (s from the "
                          f"catch)")
    back = np.flatnonzero(np.diff(t) <= 0)
    if back.size:
        i = back[0] + 1
        raise ConfigError(f"--trace {str(p)!r}: data row {i + 1}, column {TIME} = {float(t[i])!r}: must exceed the row "
                          f"before ({float(t[i - 1])!r}); times rise")


def _check_angles(values: np.ndarray, column: str, p: Path) -> None:
    bad = np.flatnonzero(np.abs(values) > ANGLE_LIMIT_DEG)
    if bad.size:
        i = bad[0]
        raise ConfigError(f"--trace {str(p)!r}: data row {i + 1}, column {column} = {float(values[i])!r}: out of "
                          f"range, allowed [-{ANGLE_LIMIT_DEG:g}, {ANGLE_LIMIT_DEG:g}] deg")
