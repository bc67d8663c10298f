"""The README quotes the benchmark's numbers as the benchmark printed them.

docs/agents.md holds the output of ``python benchmarks/rl_vs_tuning.py`` in a block that
``scripts/regenerate_docs.py`` rewrites; the README's table of whole-row shares must be those cells, method by
method, so a regeneration that moves a number makes this test fail until the README follows.
"""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
BENCHMARK = "<!-- run: python benchmarks/rl_vs_tuning.py --plot docs/rl_learning_curve.png -->"


def _table_rows(text: str, header_starts: str) -> dict[str, list[str]]:
    """The rows (first cell -> cells) of the first markdown table in ``text`` whose header starts so."""
    lines = text.splitlines()
    start = next(i for i, ln in enumerate(lines) if ln.startswith(header_starts))
    head = [c.strip() for c in lines[start].strip("|").split("|")]
    rows = {}
    for ln in lines[start + 2:]:
        if not ln.startswith("|"):
            break
        cells = [c.strip() for c in ln.strip("|").split("|")]
        rows[cells[0]] = dict(zip(head, cells))
    return rows


def benchmark_block() -> str:
    page = (ROOT / "docs" / "agents.md").read_text()
    body = page.split(BENCHMARK, 1)[1]
    return re.match(r"\n```text\n(.*?)^```$", body, re.S | re.M).group(1)


def test_the_readmes_shares_are_the_benchmarks_cells():
    printed = _table_rows(benchmark_block(), "| method | seeds |")
    quoted = _table_rows((ROOT / "README.md").read_text(), "| method (hold-out contexts) |")
    assert len(quoted) >= 4
    for method, row in quoted.items():
        assert method in printed, method
        assert row["seeds"] == printed[method]["seeds"], method
        assert row["whole row: mean [95 % CI]"] == printed[method]["whole row: mean [95 % CI]"], method


def test_the_check_reads_a_table_as_printed():
    # the parser on a table written here: a number changed in one place is seen
    text = "x\n| method (hold-out contexts) | seeds | whole row: mean [95 % CI] |\n|---|---|---|\n| ppo | 10 | 93.9 % " \
           "[88.2, 98.8] |\n\nafter"
    rows = _table_rows(text, "| method (hold-out contexts) |")
    assert rows == {"ppo": {"method (hold-out contexts)": "ppo", "seeds": "10",
                            "whole row: mean [95 % CI]": "93.9 % [88.2, 98.8]"}}
