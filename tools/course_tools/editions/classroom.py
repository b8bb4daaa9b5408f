"""Classroom tooling: starter releases (a chapter with its solution blocks taken out,
solution_markers.py), Gradescope autograder zips and the classroom workflow."""

from __future__ import annotations

import re
import shutil
from pathlib import Path

from course_tools import chapters as chapter_list
from course_tools.python_imports import imported_modules
from course_tools.editions import editions
from course_tools.editions.solution_markers import (MARKED_SUFFIXES, find_blocks,
                                                    keep_solutions, strip_solutions)


# ---------------------------------------------------------------- release

STUDENT_README = """# Chapter {number}: {title}

This is the starter code for chapter {name} of the GPU ray tracing course. The parts
you write are marked `TODO` in `chapters/{name}/` and `shaders/{name}/`.

The chapter's page, with this folder's code in its listings: open
`book/{name}.html` in a browser (it needs no network), or read `book/{name}.md`
(GitHub shows it, formulas too).

```bash
./course run {number}     # build and render; prints the PNG's path
./course test {number}    # the chapter's own checks (not your grader's)
```

Until you fill in the TODOs, the program builds and runs but draws the wrong picture
(or, for chapter 01, reports wrong sums). Hand in this whole folder.
{references}
`./course test` runs the book's checks of this chapter: your pictures against references
computed another way (numpy, Mitsuba 3) and properties a right program has. Your grader
runs other tests, with arguments you do not see, and compares your program's output with
the solution's for the same arguments: exactly where there is one right picture, and by
statistics where the picture is random (region by region, with your program's own noise,
at its own seeds), so any correct way of drawing random numbers passes. Passing
`./course test` is a good sign, not a promise of full marks.

Learning on your own, without a class? In the course's full repository,
`./course check {number} /path/to/this/folder` grades this folder as a class's grader
would (hidden tests shown) and, where a test fails, says which known mistake your
pictures look like and which section of the page explains it.
"""


def has_exercises(root: Path, chapter: str) -> bool:
    """Does the chapter have SOLUTION blocks to take out? (The appendix has none.)"""
    return any(find_blocks(path.read_text(), str(path))
               for top in ("chapters", "shaders") for path in (root / top / chapter).rglob("*")
               if path.suffix in MARKED_SUFFIXES)


def page_prototypes(root: Path, chapter: str) -> list[str]:
    """The python_prototypes files the chapter's page shows code of: the starter's page
    resolves those snippets, and the student runs the prototype."""
    page = root / "book" / "docs" / "chapters" / f"{chapter}.md"
    if not page.exists():
        return []
    return sorted(set(re.findall(r'--8<-- "(python_prototypes/[\w/]+\.py)', page.read_text())))


# A check that runs another chapter's program names it as the first argument, or the
# second after tmp_path: render(tmp_path, "12", ...), path_trace("21", tmp_path, ...).
CHAPTER_ARGUMENT = re.compile(r'\(\s*(?:tmp_path\s*,\s*)?"(\d\d)"')


def reference_chapters(root: Path, chapter: str, test_files: list[Path]) -> list[str]:
    """The earlier chapters whose programs the chapter's checks run to compare with
    (chapter 23's pictures against chapter 22's, ...). Its starter builds them, whole:
    they are the student's earlier hand-ins, and this chapter's own code holds them."""
    folders = {p.name[:2]: p.name for p in (root / "chapters").iterdir() if p.is_dir()}
    numbers = {n for path in test_files for n in CHAPTER_ARGUMENT.findall(path.read_text())}
    return sorted(folders[n] for n in numbers if n in folders and n < chapter[:2])


def chapter_code(root: Path, chapter: str) -> tuple[str, str]:
    """All of a chapter's marked code, as the solution has it and as its starter does."""
    solution, starter = [], []
    for top in ("chapters", "shaders"):
        for path in sorted((root / top / chapter).rglob("*")):
            if path.is_file() and path.suffix in MARKED_SUFFIXES:
                text = path.read_text()
                solution.append(text)
                starter.append(strip_solutions(text, str(path.relative_to(root))))
    return "\n".join(solution), "\n".join(starter)


# What a test calls to plant a mistake: str.replace, and tests/python/path_checks.py's
# helper that copies a shader folder with one line replaced.
PLANTING_CALLS = {"replace", "shaders_with_bug"}


def without_planted_mistakes(test: str, solution: str, starter: str) -> str:
    """A chapter's test file for its starter. The checks that prove they can fail plant
    a mistake in a copy of the solution (`replace("<a line of the solution>", ...)`, or
    path_checks.shaders_with_bug): they can only run on the solution, and their strings
    are pieces of it. A test function that makes one of the PLANTING_CALLS with a string
    found in the solution but not in the starter is left out, with the module-level
    constants only such tests use."""
    import ast
    tree = ast.parse(test)

    def strings(node) -> set[str]:
        return {n.value for n in ast.walk(node)
                if isinstance(n, ast.Constant) and isinstance(n.value, str)}

    def solution_only(text: str) -> bool:
        return bool(text.strip()) and text in solution and text not in starter

    constants = {}  # module-level NAME = ... -> its node
    for node in tree.body:
        if isinstance(node, ast.Assign) and len(node.targets) == 1 \
                and isinstance(node.targets[0], ast.Name):
            constants[node.targets[0].id] = node
    def called(node) -> set[str]:
        return {getattr(n.func, "attr", getattr(n.func, "id", None))
                for n in ast.walk(node) if isinstance(n, ast.Call)}

    # The file's own helpers that plant (a shaders_with(tmp_path, bug) around
    # shaders_with_bug), however deep, plant too.
    functions = {node.name: node for node in tree.body if isinstance(node, ast.FunctionDef)}
    planting = set(PLANTING_CALLS)
    while grown := {name for name, node in functions.items()
                    if name not in planting and called(node) & planting}:
        planting |= grown

    def plants(node) -> bool:  # calls something.replace(...), shaders_with_bug(...) or a helper
        return bool(called(node) & planting)

    cut = []
    for node in tree.body:
        if isinstance(node, ast.FunctionDef) and node.name.startswith("test_") \
                and plants(node):
            used = {n.id for n in ast.walk(node) if isinstance(n, ast.Name)}
            texts = strings(node).union(*(strings(constants[name]) for name in used
                                          if name in constants))
            if any(map(solution_only, texts)):
                cut.append(node)
    if not cut:
        return test
    kept_names = set()
    for node in tree.body:
        if node not in cut:
            kept_names |= {n.id for n in ast.walk(node) if isinstance(n, ast.Name)
                           and isinstance(n.ctx, ast.Load)}
    for name, node in constants.items():
        if name not in kept_names and any(map(solution_only, strings(node))):
            cut.append(node)
    lines = test.splitlines(keepends=True)
    for node in sorted(cut, key=lambda n: n.lineno, reverse=True):
        first = min([node.lineno] + [d.lineno for d in getattr(node, "decorator_list", [])])
        while first > 1 and lines[first - 2].startswith("#"):
            first -= 1  # the comment that introduces it
        lines[first - 1:node.end_lineno] = []
    note = ("\n# (The course's checks that plant mistakes in a copy of the solution are not\n"
            "# part of the starter: they run on the solution only.)\n")
    return "".join(lines).rstrip("\n") + "\n" + note


def release(root: Path, chapter: str, out: Path, figures: Path | None = None) -> Path:
    """Writes the starter of `chapter` (e.g. '04_spheres') into `out`, with the chapter's
    page rendered against the starter's code (tools/course_tools/editions/editions.py) in book/, and the
    page's figures from the folder `figures` (./course release renders them) if given."""
    number = chapter[:2]
    if out.exists():
        shutil.rmtree(out)
    out.mkdir(parents=True)

    def copy(relative: str):
        source, target = root / relative, out / relative
        target.parent.mkdir(parents=True, exist_ok=True)
        if source.is_dir():
            shutil.copytree(source, target, ignore=shutil.ignore_patterns("__pycache__"))
        else:
            shutil.copy2(source, target)

    # third_party: the pinned stb header, which a Mac (no libstb-dev) builds with.
    # The tools whole (./course's verbs and what they import; pyproject.toml installs
    # them into the starter's .venv as here).
    for relative in ("course", "requirements", "pyproject.toml", "tools/course.py",
                     "tools/course_tools", f"manifests/{chapter}.ini", "tools/platforms.ini",
                     "cmake", "common", "third_party", "tests/python/conftest.py",
                     "tests/python/suite_clock.py", "tests/python/chapters/test_command_line.py",
                     ".gitignore"):
        copy(relative)
    if (root / "assets").exists():
        copy("assets")  # the scene files, and the small source data the build uses
    # cmake/Assets.cmake runs these at build time (teapots, gems, textures, skies), with
    # what they import.
    def copy_script(relative: str):  # a python_prototypes script, with what it imports
        copy(relative)
        for module in imported_modules(root / relative, [root]):
            copy(str(module.relative_to(root)))

    assets_cmake = (root / "cmake" / "Assets.cmake").read_text()
    for generator in sorted(set(re.findall(r"python_prototypes/\w+\.py", assets_cmake))):
        if (root / generator).exists():
            copy_script(generator)
    if not number.isdigit() or int(number) >= 7:
        copy("tests/data/obj")  # the OBJ files the mesh chapters' checks load
    tests = sorted((root / "tests" / "python" / "chapters").glob(f"test_{number}_*.py"))
    solution, starter = chapter_code(root, chapter)
    imported = set()
    for test in tests:
        target = out / test.relative_to(root)
        target.parent.mkdir(parents=True, exist_ok=True)
        target.write_text(without_planted_mistakes(test.read_text(), solution, starter))
        imported |= imported_modules(test, [root, root / "tests" / "python",
                                            root / "tests" / "python" / "chapters"])
    for module in sorted(imported):
        copy(str(module.relative_to(root)))
    references = reference_chapters(root, chapter, tests + sorted(imported))
    for prototype in page_prototypes(root, chapter):
        copy_script(prototype)  # so that the student can run it

    def copy_checkpoint(name: str, edit):
        """A chapter's folders, each marked file passed through `edit`."""
        for top in ("chapters", "shaders"):
            for source in sorted((root / top / name).rglob("*")):
                if not source.is_file():
                    continue
                target = out / source.relative_to(root)
                target.parent.mkdir(parents=True, exist_ok=True)
                if source.suffix in MARKED_SUFFIXES:
                    relative = str(source.relative_to(root))
                    target.write_text(edit(source.read_text(), relative))
                else:
                    shutil.copy2(source, target)

    copy_checkpoint(chapter, strip_solutions)  # the chapter itself, solutions taken out
    for reference in references:  # the earlier ones the checks compare with, finished
        copy(f"manifests/{reference}.ini")
        copy_checkpoint(reference, keep_solutions)

    # A build of this chapter and its references: no unit tests, no other chapters.
    cmake = (root / "CMakeLists.txt").read_text()
    kept = {chapter, *references}
    cmake = "".join(line for line in cmake.splitlines(keepends=True)
                    if not (chapter_list.ADD_CHAPTER.match(line)
                            and chapter_list.ADD_CHAPTER.match(line)[1] not in kept))
    cmake = re.sub(r"^enable_testing\(\)\n|^add_subdirectory\(tests/cpp\)\n", "", cmake,
                   flags=re.M)
    (out / "CMakeLists.txt").write_text(cmake)

    page = root / "book" / "docs" / "chapters" / f"{chapter}.md"
    title = chapter[3:].replace("_", " ")
    if page.exists():
        heading = page.read_text().splitlines()[0]
        title = heading.split("·", 1)[-1].strip() if "·" in heading else title
        write_page(root, chapter, out, figures, f"{number} · {title}")
    named = ", ".join(f"`chapters/{name}/`" for name in references)
    note = (f"\n{named} {'is' if len(references) == 1 else 'are'} finished: some of "
            "`./course test`'s checks compare your\npictures with "
            f"{'its' if len(references) == 1 else 'theirs'}. Nothing there is yours "
            "to write.\n") if references else ""
    (out / "README.md").write_text(STUDENT_README.format(number=number, name=chapter,
                                                         title=title, references=note))
    workflow = out / ".github" / "workflows" / "classroom.yml"
    workflow.parent.mkdir(parents=True)
    workflow.write_text(classroom_workflow(number))
    return out


def write_page(root: Path, chapter: str, out: Path, figures: Path | None, title: str):
    """book/NN_name.md (the page with the starter's code inlined), book/NN_name.html
    (the same page, standing alone: formulas typeset, figures beside it) and
    book/figures/."""
    book = out / "book"
    book.mkdir(exist_ok=True)
    markdown = editions.starter_markdown(root, chapter, out)
    (book / f"{chapter}.md").write_text(markdown)
    (book / f"{chapter}.html").write_text(editions.render_page(markdown, title, chapter))
    for name in editions.page_figures_inlined(markdown):
        if figures is not None and (figures / name).exists():
            (book / "figures").mkdir(exist_ok=True)
            shutil.copyfile(figures / name, book / "figures" / name)


# ---------------------------------------------------------------- autograder packages

GRADESCOPE_SETUP = """#!/usr/bin/env bash
# Gradescope runs this once, as root, when the autograder image is built: the grading
# layer only (the build's packages, numpy and matplotlib; no browser, no Mitsuba), the
# chapter's build, the reference images its solution renders and the signatures of its
# catalogued mistakes (what a failing report names). Then the solutions leave the
# image: every chapter carries the code of the chapters before it, so all of chapters/
# and shaders/ go, with the programs and objects built from them, the numpy reference
# renderers and the mistakes' catalogue (edits of solution code). Grading needs only
# common/, tools/, the build's flags, libraries and generated headers, and
# build/grading/ (the references and signatures).
set -euo pipefail
cd /autograder/source/course
./course setup grade
./course build
./course grade {number} --prepare
for chapter in chapters/*/; do rm -rf "build/CMakeFiles/$(basename "$chapter").dir"; done
rm -rf chapters shaders build/bin grading_catalogue
# The prototypes are the numpy solutions; the grader reads images with two of them.
find python_prototypes -name '*.py' ! -name __init__.py ! -name pfm.py ! -name srgb.py -delete
chmod o-rwx /autograder/source /autograder/source/course
"""

GRADESCOPE_RUN = """#!/usr/bin/env bash
# Gradescope runs this for every submission; results.json must land in /autograder/results.
set -uo pipefail
cd /autograder/source/course
./course grade {number} --submission /autograder/submission --out /autograder/results
"""

# A plain GitHub Actions workflow (GitHub Classroom's own autograding actions are
# deprecated): the chapter's checks pass or fail on every push, with the course's
# layered set-up. "{number}" is the chapter; GitHub's own ${{ }} stays as written.
CLASSROOM_WORKFLOW = """# Chapter {number}'s checks on every push: the same ones ./course test {number} runs.
name: chapter {number} checks
on: [push, workflow_dispatch]
permissions:
  contents: read
jobs:
  checks:
    runs-on: ubuntu-24.04
    timeout-minutes: 45
    steps:
      - uses: actions/checkout@v6
      - name: the test layer's Ubuntu packages
        run: >-
          sudo apt-get update &&
          sudo apt-get install -y --no-install-recommends $(./course packages test)
      - name: the Python layers, from the cache when the requirements have not changed
        uses: actions/cache@v5
        with:
          path: |
            .venv
            ~/.cache/ms-playwright
          key: venv-ubuntu-24.04-${{ hashFiles('requirements/*.txt') }}
      - name: chapter {number} checks
        run: ./course test {number}
"""


def classroom_workflow(number: str) -> str:
    return CLASSROOM_WORKFLOW.replace("{number}", number)


def tracked_files(root: Path) -> list[Path]:
    import subprocess
    listed = subprocess.run(["git", "ls-files"], cwd=root, capture_output=True, text=True)
    if listed.returncode == 0 and listed.stdout.strip():
        return [root / line for line in listed.stdout.splitlines()]
    return [p for p in root.rglob("*") if p.is_file() and "build" not in p.parts
            and ".venv" not in p.parts]


def autograder_zip(root: Path, chapter: str, out: Path) -> Path:
    """A Gradescope autograder: setup.sh, run_autograder and the instructor's course."""
    import stat
    import zipfile
    number = chapter[:2]
    out.parent.mkdir(parents=True, exist_ok=True)
    with zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as archive:
        def add_text(name, text, executable=False):
            info = zipfile.ZipInfo(name)
            mode = 0o755 if executable else 0o644
            info.external_attr = (stat.S_IFREG | mode) << 16
            archive.writestr(info, text)
        add_text("setup.sh", GRADESCOPE_SETUP.format(number=number), executable=True)
        add_text("run_autograder", GRADESCOPE_RUN.format(number=number), executable=True)
        for path in tracked_files(root):
            if path.is_file():
                mode = path.stat().st_mode
                info = zipfile.ZipInfo(f"course/{path.relative_to(root)}")
                info.external_attr = (stat.S_IFREG | (mode & 0o777)) << 16
                info.compress_type = zipfile.ZIP_DEFLATED
                archive.writestr(info, path.read_bytes())
    return out
