"""The instructors page's table of the grading catalogues, written from what the suite
measured, never typed: each catalogue run (tests/python/test_grading_statistics.py)
writes build/test-artifacts/grading-catalogue-NN.json, and `./course test
--update-book`, once a whole suite has passed, writes the table of every variant's
score between the markers in book/docs/instructors.md. test_book checks that the table
names exactly the catalogued variants, chapter by chapter."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import bench_common

ROOT = Path(__file__).resolve().parents[1]
PAGE = ROOT / "book" / "docs" / "instructors.md"
START = "<!-- catalogue:start -->"
END = "<!-- catalogue:end -->"


def chapter_order(name: str) -> tuple:
    """Numbered chapters first, in order, then the appendices."""
    return (not name[:2].isdigit(), name)


def table(artifacts: Path, since: float = 0.0) -> str | None:
    """The markdown table from the catalogue files written after `since` (a time stamp:
    files of an earlier run are not mixed in); None when there are none."""
    files = sorted((p for p in artifacts.glob("grading-catalogue-*.json")
                    if p.stat().st_mtime >= since),
                   key=lambda p: chapter_order(p.stem.rsplit("-", 1)[1]))
    if not files:
        return None
    rows = ["| chapter | variant | score |", "|---|---|---|"]
    for path in files:
        catalogue = json.loads(path.read_text())
        for variant in catalogue["variants"]:
            kind = "correct" if variant["correct"] else "wrong"
            rows.append(f"| {catalogue['chapter'][:2]} | {kind}: {variant['name']} | "
                        f"{variant['score']:.0%} |")
    return "\n".join(rows)


def write(artifacts: Path, since: float, update_book: bool, page: Path = PAGE) -> int:
    """Prints where the table goes; writes it into the page when asked."""
    text = table(artifacts, since)
    if text is None:
        print(f"catalogue table: no catalogue of this run in {artifacts}", file=sys.stderr)
        return 1
    bench_common.book_or_not(update_book, page, START, END, text)
    return 0
