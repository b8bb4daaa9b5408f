"""What the autograder runs for each chapter: named tests with points, the chapter's
command-line arguments, and whether students see the result before the deadline
('visible') or only after it ('after_due_date', Gradescope's hidden tests).

kind 'image': the submission's PNG is compared with the solution's for the same args.
kind 'check': the program checks itself; it must exit 0 and print `expect`."""

from __future__ import annotations

import re
from dataclasses import dataclass, field


@dataclass
class GradeTest:
    name: str
    max_score: float
    args: list[str] = field(default_factory=list)
    kind: str = "image"
    visibility: str = "visible"
    expect: str = ""

    @property
    def slug(self) -> str:
        return re.sub(r"[^a-z0-9]+", "_", self.name.lower()).strip("_")


SPECS: dict[str, list[GradeTest]] = {
    "01": [
        GradeTest("sums of 1000 floats", 3, ["--count", "1000"], "check", expect="all correct"),
        GradeTest("one element", 2, ["--count", "1"], "check", expect="all correct"),
        GradeTest("33 elements: a partial work group", 3, ["--count", "33"], "check",
                  expect="all correct"),
        GradeTest("a million elements", 2, ["--count", "1000000"], "check",
                  "after_due_date", expect="all correct"),
    ],
    "02": [
        GradeTest("pattern, 1D dispatch", 4, ["--width", "96", "--height", "64",
                                               "--dispatch", "1d"]),
        GradeTest("pattern, 2D dispatch", 3, ["--width", "96", "--height", "64",
                                               "--dispatch", "2d"]),
        GradeTest("odd size, 1D dispatch", 3, ["--width", "203", "--height", "157",
                                                "--dispatch", "1d"], visibility="after_due_date"),
    ],
}
