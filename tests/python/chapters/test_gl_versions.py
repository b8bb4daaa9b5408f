"""Every chapter calls only what the OpenGL context it asks for has (issue: a GL 4.5 call
in a 4.3 context works on Mesa, which gives 4.5 anyway, and fails on a driver that gives
exactly what was asked). The GL functions named in a chapter's sources must be in the
core profile of the version its main.cpp asks for (4.3 unless it names another, as the
OpenGL 3.3 appendix does); in common/, a function newer than 4.3 must sit behind a
version check. The functions each version has come from the Khronos registry that the
build generates the loader from (gl_registry.py)."""

from __future__ import annotations

import re

import gl_registry
import pytest
from conftest import ROOT

from course_tools import chapters

COMPUTE_FLOOR = (4, 3)  # what course::run asks for unless told otherwise
NEWER_GUARDS = ["GLAD_GL_VERSION_4_4", "GLAD_GL_VERSION_4_5", "GLAD_GL_VERSION_4_6"]


def requested_version(chapter: str) -> tuple[int, int]:
    """The version a chapter's main.cpp passes to course::run, as course::GlVersion."""
    main = (ROOT / "chapters" / chapter / "main.cpp").read_text()
    asked = re.search(r"course::GlVersion \w+\{(\d), (\d)\}", main)
    return (int(asked[1]), int(asked[2])) if asked else COMPUTE_FLOOR


@pytest.mark.parametrize("chapter", chapters.names(ROOT))
def test_a_chapter_calls_only_what_its_context_has(chapter):
    version = requested_version(chapter)
    allowed = gl_registry.core_commands(version)
    newer = [f"chapters/{chapter}/{path.name}:{line}: {name} is newer than OpenGL "
             f"{version[0]}.{version[1]}"
             for path in sorted((ROOT / "chapters" / chapter).glob("*.[ch]*"))
             for name, line in gl_registry.gl_calls(path) if name not in allowed]
    assert not newer, "\n".join(newer)


def test_common_guards_what_is_newer_than_4_3():
    allowed = gl_registry.core_commands(COMPUTE_FLOOR)
    for path in sorted((ROOT / "common").rglob("*.[ch]*")):
        for name, line in gl_registry.gl_calls(path):
            if name in allowed:
                continue
            function = gl_registry.enclosing_function(path, line)
            assert any(guard in function for guard in NEWER_GUARDS), \
                f"common/{path.relative_to(ROOT / 'common')}:{line}: {name} is newer " \
                f"than OpenGL 4.3 and not behind a version check"


def test_the_check_finds_a_newer_call(tmp_path):
    # A check that cannot fail is not a check: the call chapter 23 made before, in a
    # chapter that asks for 4.3.
    source = tmp_path / "wavefront.cpp"
    source.write_text("void f() {\n    glClearNamedBufferSubData(id, GL_R32UI, 0, 4, "
                      "GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);  // 4.5\n}\n")
    calls = gl_registry.gl_calls(source)
    assert calls == [("glClearNamedBufferSubData", 2)]
    assert "glClearNamedBufferSubData" not in gl_registry.core_commands(COMPUTE_FLOOR)
    assert "glClearNamedBufferSubData" in gl_registry.core_commands((4, 5))
    assert "glClearBufferSubData" in gl_registry.core_commands(COMPUTE_FLOOR)
    assert requested_version("A2_gl33_fragment") == (3, 3)
    assert requested_version("12_light_sampling") == COMPUTE_FLOOR
