"""The book's two editions and the starters' pages: no line of a solution reaches a
starter (any of its files, its page included) or the student edition of the book, and
the instructors' edition has them, with the answer notes.

Which lines count as "a line of a solution" (solution_lines below):

- the lines inside a chapter's SOLUTION blocks, in chapters/NN_name/ and
  shaders/NN_name/, without the BEGIN, END and STUB lines;
- as code: indentation, a trailing `// comment` and repeated spaces removed; blank
  and comment-only lines do not count (a comment is prose, and hints are allowed to
  say what the code does);
- not given code: a line that also stands outside the chapter's SOLUTION blocks, in
  an earlier chapter (whose solutions a later starter hands down as given code), or in
  common/, or stands inside such a line, is in the starter legitimately (`}`; chapter 05's
  `return t > tMin && t < tMax;`, from chapter 04's sphere test; chapter 03's pixel
  centre, computed as in chapter 02's pattern), so it proves nothing.

The student edition holds every chapter at once, where a later chapter's own new code
may share a short idiom with an earlier exercise (chapter 05's plane loop says
`found = true;` like chapter 04's sphere loop; chapter 11's new sphere test ends in
`return t > tMin && t < tMax;` like chapter 04's). So for the book, a line shorter
than IDIOM_LENGTH characters that also stands outside SOLUTION blocks in any chapter
counts as an idiom, not as evidence. Every exercise keeps at least one line that
counts (checked below), so no block escapes the check.

A line is found when it appears, spaces collapsed, anywhere in a file's text: code
listings in HTML are split into highlighting spans, so tags are removed and entities
decoded first, and in the search index every string is searched."""

from __future__ import annotations

import html
import json
import re
import subprocess
import sys
from functools import lru_cache
from pathlib import Path

import pytest

from conftest import ROOT

from course_tools import chapters
from course_tools.editions import classroom, solution_markers
from course_tools.editions import editions

COURSE = [sys.executable, str(ROOT / "tools" / "course.py")]
IDIOM_LENGTH = 30
ORDER = chapters.names(ROOT)
EXERCISES = [name for name in ORDER if classroom.has_exercises(ROOT, name)]


def code_lines(text: str) -> set[str]:
    return {code for code in map(editions.code_of, text.splitlines()) if code}


@lru_cache(maxsize=None)
def given_code(chapter: str) -> frozenset[str]:
    """The code a student of `chapter` has been given or has written: the earlier
    checkpoints whole, this one outside its SOLUTION blocks, and common/."""
    given = set()
    for name in ORDER[:ORDER.index(chapter) + 1]:
        for path in editions.checkpoint_sources(ROOT, name):
            text = path.read_text()
            if name == chapter and path.suffix in solution_markers.MARKED_SUFFIXES:
                text = solution_markers.strip_solutions(text, str(path.relative_to(ROOT)))
            given |= code_lines(text)
    for path in (ROOT / "common").rglob("*"):
        if path.is_file() and path.suffix in solution_markers.MARKED_SUFFIXES:
            given |= code_lines(path.read_text())
    return frozenset(given)


@lru_cache(maxsize=None)
def code_outside_blocks_anywhere() -> frozenset[str]:
    code = set()
    for name in ORDER:
        for path in editions.checkpoint_sources(ROOT, name):
            text = path.read_text()
            if path.suffix in solution_markers.MARKED_SUFFIXES:
                text = solution_markers.strip_solutions(text, str(path.relative_to(ROOT)))
            code |= code_lines(text)
    return frozenset(code)


@lru_cache(maxsize=None)
def given_text(chapter: str) -> str:
    """The given code's lines, one a line: a solution line found inside one of them (the
    restart `path = startPath(...)` inside the given `PathState path = startPath(...)`)
    is in the starter legitimately, as a whole given line is."""
    return "\n".join(sorted(given_code(chapter)))


def solution_lines(chapter: str, for_the_book: bool = False) -> dict[str, str]:
    """The lines that count (see the module's docstring): code -> 'file:line'."""
    counted = {}
    for block in editions.solution_blocks(ROOT, chapter):
        for offset, line in enumerate(block.body):
            code = editions.code_of(line)
            if not code or code in given_code(chapter) or code in given_text(chapter):
                continue
            if for_the_book and len(code) < IDIOM_LENGTH \
                    and code in code_outside_blocks_anywhere():
                continue
            counted.setdefault(code, f"{block.path}:{block.begin_line + 1 + offset}")
    return counted


def readable(text: str) -> str:
    """A page's text as a reader sees it, spaces collapsed: no tags, no entities."""
    return " ".join(html.unescape(re.sub(r"<[^>]+>", "", text)).split())


def leaks(text: str, lines: dict[str, str]) -> list[str]:
    return [f"{where}: {code}" for code, where in lines.items() if code in text]


def site_texts(site: Path) -> dict[str, str]:
    """Every page's readable text, and every string of the search index."""
    texts = {}
    for page in site.rglob("*.html"):
        texts[str(page.relative_to(site))] = readable(page.read_text())
    index = site / "search" / "search_index.json"
    strings = []

    def walk(value):
        if isinstance(value, str):
            strings.append(readable(value))
        elif isinstance(value, dict):
            for item in value.values():
                walk(item)
        elif isinstance(value, list):
            for item in value:
                walk(item)
    walk(json.loads(index.read_text()))
    texts["search/search_index.json"] = " | ".join(strings)
    return texts


# ---------------------------------------------------------------- the definition itself

@pytest.mark.parametrize("chapter", EXERCISES)
def test_every_solution_block_has_lines_that_count(chapter):
    """No exercise escapes the checks: each block keeps a line that counts, in the
    starter's sense and in the book's."""
    for block in editions.solution_blocks(ROOT, chapter):
        codes = {editions.code_of(line) for line in block.body}
        assert codes & set(solution_lines(chapter)), f"{block.path}:{block.begin_line}"
        assert codes & set(solution_lines(chapter, for_the_book=True)), \
            f"{block.path}:{block.begin_line}"


def test_given_code_and_idioms_do_not_count():
    assert "}" not in solution_lines("04_spheres")
    # Chapter 04's sphere test is given code in chapter 05's folder.
    assert "return t > tMin && t < tMax;" in solution_lines("04_spheres")
    assert "return t > tMin && t < tMax;" not in solution_lines("05_shading_shadows")
    assert "return t > tMin && t < tMax;" not in solution_lines("04_spheres", True)
    assert "float halfChord = sqrt(radiusSquared - missBySquared);" in \
        solution_lines("04_spheres", True)


def test_a_leak_is_found_through_highlighting_spans():
    lines = {"t = tClosest - halfChord;": "sphere.glsl:20"}
    page = ('<span class="n">t</span><span class="w"> </span><span class="o">=</span>'
            '<span class="w"> </span><span class="n">tClosest</span><span class="w"> '
            '</span><span class="o">-</span><span class="w"> </span>'
            '<span class="n">halfChord</span><span class="p">;</span>')
    assert leaks(readable(page), lines) == ["sphere.glsl:20: t = tClosest - halfChord;"]


# ---------------------------------------------------------------- the student's sources

def test_a_later_chapters_copy_of_a_solution_is_taken_out():
    """Chapter 05 carries chapter 04's sphere test word for word, chapter 07 carries
    chapter 06's triangle test changed (no `.xyz`): both become the TODO and stub."""
    blocks = editions.solution_blocks(ROOT)
    sphere = editions.student_checkpoint(ROOT, "05_shading_shadows", blocks)[
        "shaders/05_shading_shadows/sphere.glsl"]
    assert "// TODO (chapter 04): intersect the ray with the sphere" in sphere
    assert "halfChord" not in sphere
    triangle = editions.student_checkpoint(ROOT, "07_obj_teapot", blocks)[
        "shaders/07_obj_teapot/triangle.glsl"]
    assert "// TODO (chapter 06): Moller-Trumbore" in triangle
    assert "determinant" not in triangle
    assert "struct Corners" in triangle  # chapter 07's own code stays


def test_a_copy_with_a_comment_added_after_it_is_taken_out():
    """Chapter 29 carries chapter 28's one-line block with a comment after it."""
    code = "dispatch(STAGE_FILTER, samples, 1u << pass);"
    block = editions.SolutionBlock("28_denoising", "chapters/28_denoising/denoiser.cpp", 80,
                                   "the pass's taps", [f"        {code}"],
                                   ["dispatch(STAGE_FILTER, samples, 1u);"])
    later = f"for (;;) {{\n    {code}  // taps 1, 2, 4, ... pixels apart\n    swap();\n}}\n"
    censored = editions.student_text(later, "chapters/29_temporal/denoiser.cpp", [block])
    assert code not in censored
    assert ("    // TODO (chapter 28): the pass's taps\n"
            "    dispatch(STAGE_FILTER, samples, 1u);\n    swap();") in censored


def test_answer_notes_are_dropped_with_everything_indented_under_them():
    page = ("## Exercises\n\n1. Why?\n\n??? answers \"Answers\"\n\n    1. Because.\n"
            "       More.\n\n    2. Also.\n\nAfter.\n")
    assert editions.drop_answers(page) == "## Exercises\n\n1. Why?\n\nAfter.\n"


# ---------------------------------------------------------------- starters

@pytest.mark.parametrize("chapter", EXERCISES)
def test_no_solution_line_reaches_a_starter(tmp_path, chapter):
    """Every file of the starter, its page (Markdown and HTML) included."""
    starter = classroom.release(ROOT, chapter, tmp_path / "starter")
    lines = solution_lines(chapter)
    assert lines
    found = []
    for path in sorted(p for p in starter.rglob("*") if p.is_file()):
        try:
            text = path.read_text()
        except UnicodeDecodeError:
            continue  # images
        if path.suffix == ".html":
            text = readable(text)
        found += [f"{path.relative_to(starter)} has {leak}"
                  for leak in leaks(" ".join(text.split()), lines)]
    assert not found, "\n".join(found)
    page = starter / "book" / f"{chapter}.md"
    assert "--8<--" not in page.read_text() and "--8<--" not in \
        (starter / "book" / f"{chapter}.html").read_text()
    assert "TODO:" in page.read_text()  # the listings are the starter's
    assert "??? answers" not in page.read_text()


def test_a_starters_page_shows_its_own_code_formulas_and_figures(tmp_path):
    """./course release 04 --draft: the page's listings come from the starter's files
    (edit one and release again to see it), formulas are MathML, figures are there."""
    out = tmp_path / "s"
    result = subprocess.run([*COURSE, "release", "04", "--draft", "--out", str(out)],
                            capture_output=True, text=True, timeout=900)
    assert result.returncode == 0, result.stderr[-3000:]
    page = (out / "book" / "04_spheres.html").read_text()
    starter_code = (out / "shaders" / "04_spheres" / "sphere.glsl").read_text()
    assert "// TODO: intersect the ray with the sphere, geometrically" in starter_code
    assert "TODO: intersect the ray with the sphere, geometrically" in readable(page)
    assert "<math" in page and "class=\"arithmatex\">\\(" not in page
    for figure in re.findall(r'<img[^>]+src="([^"]+)"', page):
        assert (out / "book" / figure).is_file(), figure
    assert len(re.findall(r"<img", page)) >= 4
    markdown = (out / "book" / "04_spheres.md").read_text()
    assert "](figures/04_spheres.png)" in markdown and "## Exercises" in markdown
    assert "+++ shaders/04_spheres/sphere.glsl" in markdown  # the diff, to the starter
    # Rendered against the starter's files, whatever they hold.
    section = (out / "shaders" / "04_spheres" / "trace.comp")
    section.write_text(section.read_text().replace("vec3 sky(", "vec3 skyColour(", 1))
    again = editions.starter_markdown(ROOT, "04_spheres", out)
    assert "vec3 skyColour(" in again


# ---------------------------------------------------------------- the two editions

@pytest.fixture(scope="module")
def student_book(built_book):
    """./course book --student --draft, after the instructors' edition (built_book), with
    the figures and diffs that build just rendered from the same tree (rendering them
    again took three minutes of the suite)."""
    result = subprocess.run([*COURSE, "book", "--student", "--draft", "--figures-as-they-are"],
                            capture_output=True, text=True, timeout=900, cwd=ROOT)
    assert result.returncode == 0, result.stderr[-3000:]
    assert result.stdout.strip().endswith("book/site-student/index.html")
    return editions.STUDENT_SITE


def test_no_solution_line_reaches_the_student_edition(student_book):
    texts = site_texts(student_book)
    found = []
    for chapter in EXERCISES:
        lines = solution_lines(chapter, for_the_book=True)
        for name, text in texts.items():
            found += [f"{name} has {leak}" for leak in leaks(text, lines)]
    assert not found, "\n".join(found)


def test_the_student_edition_shows_the_starters_code_and_no_answers(student_book):
    texts = site_texts(student_book)
    page = texts["chapters/04_spheres/index.html"]
    assert "// TODO: intersect the ray with the sphere, geometrically return false;" in page
    assert "// TODO (chapter 04): keep the nearest hit" in \
        texts["chapters/05_shading_shadows/index.html"]
    for chapter in EXERCISES:
        source = (student_book / "chapters" / chapter / "index.html").read_text()
        assert 'class="answers' not in source and "Answers (instructors" not in source
    assert "Answers (instructors" not in texts["search/search_index.json"]
    assert "student edition" in texts["index.html"]


def test_the_instructors_edition_has_the_solutions_and_the_answers(built_book,
                                                                  student_book):
    """The check above would pass on an empty book: the same lines are found in the
    instructors' edition, every exercise's answer note is there, and the student
    edition did not overwrite it."""
    texts = site_texts(built_book)
    book_text = " ".join(texts.values())
    for chapter in EXERCISES:
        shown = [code for code in solution_lines(chapter, for_the_book=True)
                 if code in book_text]
        assert shown, f"no line of {chapter}'s solution is in the instructors' edition"
    shown = sum(code in book_text for chapter in EXERCISES
                for code in solution_lines(chapter, for_the_book=True))
    assert shown >= 40
    for chapter in EXERCISES:  # an answer for every exercise
        source = (built_book / "chapters" / chapter / "index.html").read_text()
        exercises = source[source.index('id="exercises"'):]
        questions = exercises[:exercises.index("</ol>")].count("<li>")
        assert '<details class="answers">' in exercises, chapter
        note = exercises[exercises.index('<details class="answers">'):]
        assert note[:note.index("</details>")].count("<li>") == questions >= 3, chapter
    assert "student edition" not in texts["index.html"]
