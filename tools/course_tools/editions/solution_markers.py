"""Solution markers. Lesson code marks what a student writes:

    // BEGIN SOLUTION the colour of the pixel
    vec3 colour = shade(hit);
    // STUB: vec3 colour = vec3(0.0);
    // END SOLUTION

A starter release replaces each block by a TODO carrying the hint from the BEGIN line,
followed by the block's STUB lines uncommented, so the starter still compiles and runs
(and draws a wrong picture). The same markers work in C++ and GLSL.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

BEGIN = re.compile(r"^(?P<indent>\s*)//\s*BEGIN SOLUTION\b\s*(?P<hint>.*)$")
END = re.compile(r"^\s*//\s*END SOLUTION\b")
STUB = re.compile(r"^\s*//\s*STUB:\s?(?P<code>.*)$")
MARKED_SUFFIXES = {".cpp", ".h", ".hpp", ".comp", ".glsl", ".vert", ".frag"}


class MarkerError(Exception):
    """An unbalanced or nested marker, with file:line."""


@dataclass
class Block:
    begin_line: int  # 1-based
    end_line: int
    hint: str


def find_blocks(text: str, path: str) -> list[Block]:
    """The solution blocks of a file; raises MarkerError naming file:line when the
    markers are unbalanced or nested, or a STUB stands outside a block."""
    blocks, open_line, hint = [], None, ""
    for number, line in enumerate(text.splitlines(), start=1):
        if begin := BEGIN.match(line):
            if open_line is not None:
                raise MarkerError(f"{path}:{number}: BEGIN SOLUTION inside the block opened "
                                  f"at line {open_line} (blocks cannot nest)")
            open_line, hint = number, begin.group("hint").strip()
        elif END.match(line):
            if open_line is None:
                raise MarkerError(f"{path}:{number}: END SOLUTION without BEGIN SOLUTION")
            blocks.append(Block(open_line, number, hint))
            open_line = None
        elif STUB.match(line) and open_line is None:
            raise MarkerError(f"{path}:{number}: STUB outside a solution block")
    if open_line is not None:
        raise MarkerError(f"{path}:{open_line}: BEGIN SOLUTION is never closed")
    return blocks


def strip_solutions(text: str, path: str) -> str:
    """The starter version of a file: every block becomes its TODO and stubs."""
    find_blocks(text, path)  # validate first
    out, inside = [], False
    for line in text.splitlines(keepends=True):
        if begin := BEGIN.match(line):
            inside = True
            hint = begin.group("hint").strip() or "write this part"
            out.append(f"{begin.group('indent')}// TODO: {hint}\n")
        elif END.match(line):
            inside = False
        elif inside:
            if stub := STUB.match(line):
                indent = line[: len(line) - len(line.lstrip())]
                out.append(f"{indent}{stub.group('code')}\n")
        else:
            out.append(line)
    return "".join(out)


def keep_solutions(text: str, path: str) -> str:
    """A file as a finished chapter has it: the solutions kept, the markers and stubs
    gone (as each chapter's copy of the one before it has them)."""
    find_blocks(text, path)  # validate first
    return "".join(line for line in text.splitlines(keepends=True)
                   if not (BEGIN.match(line) or END.match(line) or STUB.match(line)))


def marked_files(root: Path) -> list[Path]:
    files = []
    for top in ("chapters", "shaders", "common"):
        for path in sorted((root / top).rglob("*")):
            if path.is_file() and path.suffix in MARKED_SUFFIXES:
                files.append(path)
    return files


def check_all_markers(root: Path) -> int:
    """Validates every marked file in the repository; returns the number of blocks."""
    count = 0
    for path in marked_files(root):
        count += len(find_blocks(path.read_text(), str(path.relative_to(root))))
    return count
