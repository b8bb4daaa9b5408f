"""The chapters, in course order: the add_chapter() lines of CMakeLists.txt are the one
list every tool reads (the build's own), for this repository or any other root (a
starter, an autograder's copy)."""

from __future__ import annotations

import re
from pathlib import Path

from course_tools.paths import ROOT

# One add_chapter(NN_name) line of a CMakeLists.txt; group 1 is the checkpoint's name.
ADD_CHAPTER = re.compile(r"^add_chapter\((\w+)\)", flags=re.M)


def names(root: Path = ROOT) -> list[str]:
    """Checkpoint names in order, e.g. ['01_buffer_add', ..., 'A2_gl33_fragment']."""
    return ADD_CHAPTER.findall((root / "CMakeLists.txt").read_text())


def numbered(root: Path = ROOT) -> list[str]:
    """The numbered chapters, without the appendices (A1_...)."""
    return [name for name in names(root) if name[:2].isdigit()]


def matching(prefix: str, root: Path = ROOT) -> str | None:
    """The chapter a user means by '7', '07' or '07_obj_teapot'; None if there is none."""
    for name in names(root):
        if name == prefix or name.split("_")[0] == prefix.zfill(2):
            return name
    return None


def summary(name: str, root: Path = ROOT) -> str:
    """The first sentence of the comment that opens the chapter's main.cpp
    ('// Chapter 02: the GPU paints an image. ...' gives 'the GPU paints an image.')."""
    words = []
    for line in (root / "chapters" / name / "main.cpp").read_text().splitlines():
        if not line.startswith("//"):
            break
        words.append(line[2:].strip())
    text = " ".join(words).split(": ", 1)[-1]
    return text.split(". ")[0].rstrip(".") + "."
