"""What the suite measured, written into the pages, never typed: `./course test
--update-book`, once a whole suite has passed, writes

- the instructors page's tables of the grading catalogues (each variant's score and
  diagnosis; each chapter's diagnoses counted), from the files each catalogue run
  writes (tests/python/tools/test_grading_statistics.py:
  build/test-artifacts/grading-catalogue-NN.json), between their markers;
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
DIAGNOSIS_START = "<!-- diagnosis:start -->"
DIAGNOSIS_END = "<!-- diagnosis:end -->"
NUMBER = re.compile(r"<!-- number ([A-Za-z0-9_.-]+) -->(.*?)<!-- /number -->")


def numbers_folder(artifacts: Path) -> Path:
    """Where the checks write the numbers the pages mark, one file per name."""
    return artifacts / "page-numbers"


def chapter_order(name: str) -> tuple:
    """Numbered chapters first, in order, then the appendices."""
    return (not name[:2].isdigit(), name)


def catalogues(artifacts: Path, since: float = 0.0) -> list[dict]:
    """The catalogue files written after `since` (a time stamp), in chapter order."""
    files = sorted((p for p in artifacts.glob("grading-catalogue-*.json")
                    if p.stat().st_mtime >= since),
                   key=lambda p: chapter_order(p.stem.rsplit("-", 1)[1]))
    return [json.loads(path.read_text()) for path in files]


def variant_kind(variant: dict) -> str:
    return "held-out" if variant.get("held_out") else \
        "correct" if variant["correct"] else "wrong"


def diagnosed_as(variant: dict) -> str:
    """What the diagnosis named, in the table's words."""
    names = variant.get("diagnosed", [])
    if not names:
        return "nothing" if variant.get("recognisable", True) else \
            "nothing (a data race: not recognisable)"
    meant = variant.get("held_out") or variant["name"]
    said = "itself" if not variant.get("held_out") else "the mistake it makes"
    if names == [meant]:
        return said
    if variant.get("as_meant"):  # with mistakes the catalogue says have the same effect
        return f"{said}, with {'; '.join(n for n in names if n != meant)} (the same effect)"
    return "; ".join(names)


def catalogue_table(artifacts: Path, since: float = 0.0) -> str | None:
    """The markdown table of every catalogued variant: its score and what the diagnosis
    named; None when no catalogue file is this run's."""
    found = catalogues(artifacts, since)
    if not found:
        return None
    rows = ["| chapter | variant | score | diagnosed as |", "|---|---|---|---|"]
    for catalogue in found:
        for variant in catalogue["variants"]:
            rows.append(f"| {catalogue['chapter'][:2]} | {variant_kind(variant)}: "
                        f"{variant['name']} | {variant['score']:.0%} | "
                        f"{diagnosed_as(variant)} |")
    return "\n".join(rows)


def diagnosis_table(artifacts: Path, since: float = 0.0) -> str | None:
    """Per chapter: catalogued mistakes recognised from seeds their signatures were not
    made from, held-out ones recognised, and diagnoses given to correct variants."""
    found = catalogues(artifacts, since)
    if not found:
        return None
    rows = ["| chapter | mistakes recognised | held-out recognised | "
            "correct variants diagnosed | cannot be told apart |", "|---|---:|---:|---:|---|"]
    for catalogue in found:
        variants = catalogue["variants"]
        wrong = [v for v in variants if not v["correct"] and not v.get("held_out")]
        held = [v for v in variants if v.get("held_out")]
        correct = [v for v in variants if v["correct"]]
        recognised = sum((v.get("held_out") or v["name"]) in v.get("diagnosed", [])
                         for v in wrong + held)
        mine = sum(v["name"] in v.get("diagnosed", []) for v in wrong)
        pairs = "; ".join(" / ".join(pair) for pair in catalogue.get("confusable", []))
        rows.append(f"| {catalogue['chapter'][:2]} | {mine} / {len(wrong)} | "
                    f"{recognised - mine} / {len(held)} | "
                    f"{sum(bool(v.get('diagnosed')) for v in correct)} / {len(correct)} | "
                    f"{pairs or 'none'} |")
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
    if bench_common.write_table(page, DIAGNOSIS_START, DIAGNOSIS_END,
                                diagnosis_table(artifacts, since)):
        print(f"measured pages: wrote the diagnosis table into {page}")
    written = write_numbers(artifacts, since)
    print(f"measured pages: {len(written)} marked numbers written from this run")
    return 0
