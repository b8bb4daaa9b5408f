"""What a catalogued submission is: a few find-and-replace edits on a copy of the
solution's chapters/NN and shaders/NN, named, said to be correct or wrong, and (wrong
ones) explained for the grader's diagnosis.

An edit names its file (relative to the chapter's shader or host folder), the exact
text it replaces and what replaces it; applying one that finds nothing, or finds the
text more than `count` times, fails (so a catalogue that drifts from the solution
says so instead of grading the solution again).

This package holds solution code (the lines the edits replace), so it is the
instructor's only: a starter (./course release) does not carry it, and the autograder
keeps only what was measured from it (build/grading/NN/signatures.json)."""

from __future__ import annotations

import re
import shutil
import unicodedata
from dataclasses import dataclass, field
from pathlib import Path


@dataclass(frozen=True)
class Edit:
    file: str   # "shaders/sampling.glsl" or "chapters/bvh.cpp": the chapter's folder
    old: str
    new: str
    count: int = 1


@dataclass(frozen=True)
class Variant:
    chapter: str
    name: str
    correct: bool
    edits: tuple[Edit, ...] = field(default_factory=tuple)
    # A wrong variant's one line for a student: what the code gets wrong, in the
    # picture's terms, and the heading of the chapter's page that teaches it.
    explanation: str = ""
    section: str = ""
    # Another catalogued mistake whose pictures are this one's (the same estimator
    # written another way): the diagnosis may name either.
    same_effect: str = ""
    # Kept out of the signatures: the name of the catalogued mistake this variant makes,
    # written differently, which the diagnosis must recognise.
    held_out: str = ""
    # False for a mistake whose pictures change from run to run beyond what a signature
    # can hold (a data race): the diagnosis may name it, but must never name another.
    recognisable: bool = True

    @property
    def slug(self) -> str:
        return "".join(c if c.isalnum() else "_" for c in self.name.lower())[:60]

    @property
    def anchor(self) -> str:
        return heading_anchor(self.section) if self.section else ""


def heading_anchor(heading: str) -> str:
    """The id MkDocs gives a heading (Python-Markdown's toc slugify, which the book's
    mkdocs.yml uses): ASCII, lower case, punctuation dropped, spaces to hyphens."""
    text = unicodedata.normalize("NFKD", heading).encode("ascii", "ignore").decode()
    text = re.sub(r"[^\w\s-]", "", text).strip().lower()
    return re.sub(r"[-\s]+", "-", text)


def solution(chapter: str) -> Variant:
    """The solution itself, unchanged: graded with its catalogue, it must score full
    marks (test_grading.py's check of the solution, for these chapters)."""
    return Variant(chapter, "the solution as it is", True, ())


def apply(variant: Variant, root: Path, destination: Path) -> Path:
    """Copies the solution's chapter folders into destination and applies the edits."""
    for top in ("chapters", "shaders"):
        shutil.copytree(root / top / variant.chapter, destination / top / variant.chapter)
    for edit in variant.edits:
        top, name = edit.file.split("/", 1)
        path = destination / top / variant.chapter / name
        text = path.read_text()
        found = text.count(edit.old)
        assert found == edit.count, \
            f"{variant.name}: {edit.file} has {found} of {edit.old!r}, expected {edit.count}"
        changed = text.replace(edit.old, edit.new)
        assert changed != text, f"{variant.name}: the edit of {edit.file} changed nothing"
        path.write_text(changed)
    return destination
