"""The OpenGL functions each version's core profile has, from the Khronos registry
(gl.xml) that glad2 ships and the build generates the loader from, and the GL functions a
source file calls: for the checks that a chapter calls nothing newer than the context it
asks for (test_gl_versions.py, test_A2_gl33_fragment.py)."""

from __future__ import annotations

import re
import xml.etree.ElementTree as ET
from functools import cache
from pathlib import Path


@cache
def _registry():
    import glad
    return ET.parse(Path(glad.__file__).parent / "files" / "gl.xml").getroot()


@cache
def every_command() -> frozenset[str]:
    """Every GL command the registry names, of any version or extension."""
    return frozenset(c.findtext("proto/name") for c in _registry().iter("command"))


@cache
def core_commands(version: tuple[int, int]) -> frozenset[str]:
    """The commands of the core profile of OpenGL `version` (required up to it, minus
    what the core profile removed)."""
    core, removed = set(), set()
    for feature in _registry().iter("feature"):
        number = tuple(map(int, feature.get("number").split(".")))
        if feature.get("api") != "gl" or number > version:
            continue
        for part, names in (("require", core), ("remove", removed)):
            for block in feature.iter(part):
                if block.get("profile") in (None, "core"):
                    names.update(c.get("name") for c in block.iter("command"))
    return frozenset(core - removed)


def gl_calls(path: Path) -> list[tuple[str, int]]:
    """(GL function, line number) of every GL function named in a source file's code
    (comments left out)."""
    everything = every_command()
    calls = []
    for number, line in enumerate(path.read_text().splitlines(), start=1):
        code = line.split("//")[0]
        calls += [(name, number) for name in re.findall(r"\bgl[A-Z]\w*", code)
                  if name in everything]
    return calls


def enclosing_function(path: Path, line_number: int) -> str:
    """The text of the top-level definition around a line: from the last line that
    starts in column 0 with code (functions are not indented in the course's style)."""
    lines = path.read_text().splitlines()[:line_number]
    start = max(i for i, line in enumerate(lines)
                if re.match(r"[A-Za-z]", line) and not line.startswith("namespace"))
    return "\n".join(lines[start:])
