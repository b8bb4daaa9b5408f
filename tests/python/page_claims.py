"""What the pages say about what the checks measure, held to the measurements.

Numbers. A page marks a measured number `<!-- number NAME -->0.4241<!-- /number -->`;
the check that measures it calls `record(NAME, "0.4241")`, which writes the file
`./course test --update-book` copies into the page (tools/course_tools/cli/measured_pages.py), and
test_book checks that every marked number is recorded by a check.

Directions. A page that says which way a planted bug moves the picture ("too dark", "brighter")
marks the sentence with a comment at the end of its line, invisible in the book:

    ... the rough metals come out too **dark** ... <!-- claim 15-missing-jacobian: darker -->

The test that plants the bug measures the picture with and without it and calls
`check("15-missing-jacobian", ratio)`: the ratio of the two brightnesses must go the
way the page says, or the test fails and names the page and line. test_book checks the
other half: every claim in the pages is checked by a test, so a new sentence cannot
slip in unheld."""

from __future__ import annotations

import functools
import math
import re
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
from course_tools.cli import measured_pages

PAGES = ROOT / "book" / "docs"
ARTIFACTS = ROOT / "build" / "test-artifacts"

# Each direction a page may state, and what it means for the ratio
# (the picture with the bug / the picture without it, in brightness).
DIRECTIONS = {
    "darker": lambda ratio: ratio < 1.0,
    "brighter": lambda ratio: ratio > 1.0,
}

CLAIM = re.compile(r"<!-- claim ([A-Za-z0-9_-]+): ([a-z]+) -->")


@dataclass(frozen=True)
class Claim:
    name: str
    direction: str
    page: Path
    line: int

    def where(self) -> str:
        return f"{self.page.relative_to(PAGES.parents[1])}:{self.line}"


def all_claims() -> list[Claim]:
    """Every claim in the book's pages, in page order."""
    claims = []
    for page in sorted(PAGES.rglob("*.md")):
        for number, text in enumerate(page.read_text(encoding="utf-8").splitlines(), 1):
            for match in CLAIM.finditer(text):
                claims.append(Claim(match[1], match[2], page, number))
    return claims


def stated(name: str) -> Claim:
    """The one claim of that name; an unknown name, a repeated one or an unknown
    direction is an error in the page."""
    found = [c for c in all_claims() if c.name == name]
    assert len(found) == 1, f"claim {name!r} is in {len(found)} places in the pages, not 1"
    claim = found[0]
    assert claim.direction in DIRECTIONS, \
        f"{claim.where()}: claim {name!r} says {claim.direction!r}; known: {sorted(DIRECTIONS)}"
    return claim


def check(name: str, ratio: float) -> None:
    """Fails unless the measured brightness ratio (with the bug / without) goes the way
    the page's claim says."""
    claim = stated(name)
    assert DIRECTIONS[claim.direction](ratio), (
        f"{claim.where()} says the picture comes out {claim.direction}, but the measured "
        f"ratio with the bug to without is {ratio:.3f}")


def plus_minus(mean: float, error: float) -> str:
    """"2.0010 ± 0.0050": a measured mean to the digits its standard error allows (two
    significant digits of the error)."""
    decimals = max(0, 1 - math.floor(math.log10(error))) if error > 0 else 4
    return f"{mean:.{decimals}f} ± {error:.{decimals}f}"


@functools.cache
def marked_numbers() -> frozenset[str]:
    """The names of the numbers the pages mark (measured_pages.NUMBER), read once."""
    return frozenset(name for page in PAGES.rglob("*.md")
                     for name, _ in measured_pages.NUMBER.findall(page.read_text(encoding="utf-8")))


def record(name: str, text: str) -> None:
    """Writes a measured number, as the page should show it, for --update-book. The name
    must be marked in a page (test_book checks the other way round)."""
    assert name in marked_numbers(), f"no page marks the number {name!r}"
    folder = measured_pages.numbers_folder(ARTIFACTS)
    folder.mkdir(parents=True, exist_ok=True)
    (folder / f"{name}.txt").write_text(text + "\n")
