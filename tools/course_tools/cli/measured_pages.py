"""What the suite measured, written into the pages, never typed: `./course test
--update-book`, once a whole suite has passed, writes

- the instructors page's table of the grading catalogues, from the files each catalogue
  run writes (tests/python/tools/test_grading_statistics.py:
  build/test-artifacts/grading-catalogue-NN.json), between its catalogue markers;
- every number a page marks `<!-- number NAME -->0.4241<!-- /number -->`, from the file
  the check that measures it writes (tests/python/page_claims.record:
  build/test-artifacts/page-numbers/NAME.txt).

Only files this run wrote count, so an earlier run's figures are never mixed in.
test_book checks that the table names exactly the catalogued variants, and that every
marked number is recorded by a check."""

from __future__ import annotations

import json
import re
import sys
from pathlib import Path

from course_tools.bench import common as bench_common

from course_tools.paths import ROOT

PAGES = ROOT / "book" / "docs"
PAGE = PAGES / "instructors.md"
START = "<!-- catalogue:start -->"
END = "<!-- catalogue:end -->"
NUMBER = re.compile(r"<!-- number ([A-Za-z0-9_.-]+) -->(.*?)<!-- /number -->")


def numbers_folder(artifacts: Path) -> Path:
    """Where the checks write the numbers the pages mark, one file per name."""
    return artifacts / "page-numbers"


def chapter_order(name: str) -> tuple:
    """Numbered chapters first, in order, then the appendices."""
    return (not name[:2].isdigit(), name)


def catalogue_table(artifacts: Path, since: float = 0.0) -> str | None:
    """The markdown table from the catalogue files written after `since` (a time stamp);
    None when there are none."""
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


def write_numbers(artifacts: Path, since: float = 0.0, pages: Path = PAGES) -> list[str]:
    """Replaces each marked number whose file this run wrote; returns the names written."""
    folder = numbers_folder(artifacts)
    measured = {p.stem: p.read_text().strip() for p in folder.glob("*.txt")
                if p.stat().st_mtime >= since} if folder.is_dir() else {}
    written = []
    for page in sorted(pages.rglob("*.md")):
        text = page.read_text(encoding="utf-8")

        def measured_or_kept(match):
            if match[1] not in measured:
                return match[0]
            written.append(match[1])
            return f"<!-- number {match[1]} -->{measured[match[1]]}<!-- /number -->"
        new = NUMBER.sub(measured_or_kept, text)
        if new != text:
            page.write_text(new, encoding="utf-8")
    return written


def write(artifacts: Path, since: float, page: Path = PAGE) -> int:
    """Writes what this run measured into the pages; says what it wrote."""
    table = catalogue_table(artifacts, since)
    if table is None:
        print(f"measured pages: no catalogue of this run in {artifacts}", file=sys.stderr)
        return 1
    if bench_common.write_table(page, START, END, table):
        print(f"measured pages: wrote the catalogue table into {page}")
    written = write_numbers(artifacts, since)
    print(f"measured pages: {len(written)} marked numbers written from this run")
    return 0
