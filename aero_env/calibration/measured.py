"""A measured swing, as a video tool (Kinovea) exports it: read and checked.

The CSV has a header row and one row per video frame from the catch to the slip-off:

=============  ==========================================================
``t``          s, 0 at the catch (the arm hooking the handrail), rising
               (or ``t_s``)
``theta1_deg`` frame angle from the horizontal, deg (the paper's theta1)
``theta2_deg`` optional: robot line angle from the horizontal, deg
=============  ==========================================================

Other columns are ignored; the separator may be a comma, a semicolon or a tab. Bad input raises
``ConfigError`` naming the file, the row, the column and the value.

``aero-env simulate --trace`` writes a whole run in these units (``t_s`` from the run's start, and a
``contact`` column: the frame the hook is on, -1 in flight); such a file is read too, and
:meth:`MeasuredSwing.swing_of` keeps the rows of the swing fitted, timed from its catch.
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..config import ConfigError
from ..files import read_text

TIME, THETA1, THETA2 = "t", "theta1_deg", "theta2_deg"
TIME_S = "t_s"  # simulate --trace's time column (s from the run's start)
CONTACT = "contact"  # simulate --trace's: the frame whose handrail the hook is on, -1 in flight
FRAME = "frame"  # simulate --trace's: the frame whose theta1 the row holds
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
    # a whole run (simulate --trace): at each row the frame the hook is on (-1 in flight) and the frame whose theta1
    # the row holds (it turns to the catching frame a few rows after the catch)
    contact: np.ndarray | None = None
    frame: np.ndarray | None = None

    def swing_of(self, swing: int) -> "MeasuredSwing":
        """Swing ``swing`` of a whole run: the rows hooked on its frame that hold its frame's theta1, timed from the
        first row hooked on it (the catch); a measured swing (no ``contact`` column) as it is."""
        if self.contact is None:
            return self
        hooked = np.flatnonzero(self.contact == swing)
        rows = hooked[self.frame[hooked] == swing] if self.frame is not None else hooked
        if rows.size < MIN_ROWS:
            raise ConfigError(f"--trace {self.path!r}: a whole run (column {CONTACT}) with {rows.size} rows on frame "
                              f"{swing}; at least {MIN_ROWS} are needed to fit swing {swing} (give another --swing, or "
                              f"simulate more frames)")
        return MeasuredSwing(t=self.t[rows] - self.t[hooked[0]], theta1=self.theta1[rows],
                             theta2=None if self.theta2 is None else self.theta2[rows], path=self.path)


def load_measured(path: str | Path) -> MeasuredSwing:
    """Read and check a measured swing CSV."""
    p = Path(path)
    lines = [ln for ln in read_text(p, "--trace", f"a CSV with columns {TIME}, {THETA1}").splitlines() if ln.strip()]
    if not lines:
        raise ConfigError(f"--trace {str(p)!r}: empty; expected a header row with columns {TIME}, {THETA1}")
    reader = csv.DictReader(lines, dialect=_dialect(lines[0]))
    header = [h.strip() for h in reader.fieldnames or []]
    reader.fieldnames = header
    time = TIME if TIME in header or TIME_S not in header else TIME_S
    for column in (time, THETA1):
        if column not in header:
            raise ConfigError(f"--trace {str(p)!r}: missing column {column!r}; columns found: {header}; required: "
                              f"{TIME} (s from the catch; or {TIME_S}), {THETA1} (deg), optional {THETA2} (deg)")
    rows = list(reader)
    if len(rows) < MIN_ROWS:
        raise ConfigError(f"--trace {str(p)!r}: {len(rows)} data rows; at least {MIN_ROWS} are needed")
    t = _column(rows, time, p)
    theta1 = _column(rows, THETA1, p)
    theta2 = _column(rows, THETA2, p) if THETA2 in header else None
    contact = _column(rows, CONTACT, p) if CONTACT in header else None
    frame = _column(rows, FRAME, p) if contact is not None and FRAME in header else None
    _check_times(t, p, time)
    for column, values in ((THETA1, theta1), (THETA2, theta2)):
        if values is not None:
            _check_angles(values, column, p)
    return MeasuredSwing(t=t, theta1=theta1, theta2=theta2, path=str(p), contact=contact, frame=frame)


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


def _check_times(t: np.ndarray, p: Path, column: str = TIME) -> None:
    if t[0] < 0:
        raise ConfigError(f"--trace {str(p)!r}: data row 1, column {column} = {float(t[0])!r}: must be >= 0 (s from the "
                          f"catch)")
    back = np.flatnonzero(np.diff(t) <= 0)
    if back.size:
        i = back[0] + 1
        raise ConfigError(f"--trace {str(p)!r}: data row {i + 1}, column {column} = {float(t[i])!r}: must exceed the "
                          f"row before ({float(t[i - 1])!r}); times rise")


def _check_angles(values: np.ndarray, column: str, p: Path) -> None:
    bad = np.flatnonzero(np.abs(values) > ANGLE_LIMIT_DEG)
    if bad.size:
        i = bad[0]
        raise ConfigError(f"--trace {str(p)!r}: data row {i + 1}, column {column} = {float(values[i])!r}: out of "
                          f"range, allowed [-{ANGLE_LIMIT_DEG:g}, {ANGLE_LIMIT_DEG:g}] deg")
