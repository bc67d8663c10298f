"""Write the golden record of the prototype's run (tests/golden/paper_run.json).

    python tests/golden/regenerate.py

Run it only on purpose, when a change is meant to alter the physics; commit the new file with
the change and say why in the commit message. tests/test_hard_cases.py checks that the code
reproduces the record bit for bit on this platform: every event (catch, detach, angles, energies,
health) at full precision, and a SHA-256 of every trace row; and, for any platform (another libm),
that it agrees within the tolerances measured in tests/golden/tolerances.py.
"""

from __future__ import annotations

import hashlib
import json
from pathlib import Path

import numpy as np

from aero_env.config import load_config
from aero_env.physics import simulate
from aero_env.physics.run import TRACE_COLUMNS

ROOT = Path(__file__).resolve().parents[2]
GOLDEN = Path(__file__).with_name("paper_run.json")


def golden_record() -> dict:
    """The prototype's run as JSON-ready data (floats round-trip exactly through JSON)."""
    result = simulate(load_config(ROOT / "configs" / "paper.yaml"), trace=True)
    record = result.to_json_dict()
    del record["wall_time"]
    digest = hashlib.sha256()
    for column in TRACE_COLUMNS:
        digest.update(np.ascontiguousarray(result.trace[column], dtype=np.float64).tobytes())
    record["trace_rows"] = len(result.trace["t"])
    record["trace_sha256"] = digest.hexdigest()
    return record


if __name__ == "__main__":
    GOLDEN.write_text(json.dumps(golden_record(), indent=1) + "\n")
    print(f"wrote {GOLDEN.relative_to(ROOT)}")
