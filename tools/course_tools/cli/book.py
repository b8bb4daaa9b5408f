"""./course diff and ./course book: checkpoint diffs, the book's figures rendered by the
real programs (kept while nothing that makes them changes), and the MkDocs build."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

from course_tools.cli.build import (
    BOOK,
    BUILD,
    GENERATED,
    binary,
    build,
    chapter_manifests,
    find_chapter,
    run_checked,
    say,
)
from course_tools.paths import ROOT


def checkpoint_diff(a: str, b: str) -> list[tuple[str, list[str]]]:
    """Per file, the unified diff from checkpoint a to checkpoint b."""
    from course_tools.editions import editions
    return editions.checkpoint_diff(editions.checkpoint_texts(ROOT, a),
                                    editions.checkpoint_texts(ROOT, b), a, b)


def cmd_diff(args):
    a, b = find_chapter(args.a), find_chapter(args.b)
    diffs = checkpoint_diff(a, b)
    color = sys.stdout.isatty() and not args.no_color
    if args.stat:
        for key, lines in diffs:
            plus = sum(1 for l in lines if l.startswith("+") and not l.startswith("+++"))
            minus = sum(1 for l in lines if l.startswith("-") and not l.startswith("---"))
            print(f" {key:44} | +{plus} -{minus}")
        print(f" {len(diffs)} files changed from {a} to {b}")
        return
    paint = {"+": "\033[32m", "-": "\033[31m", "@": "\033[36m"}
    for _, lines in diffs:
        for line in lines:
            if color and line[:1] in paint and not line.startswith(("+++", "---")):
                print(f"{paint[line[0]]}{line}\033[0m")
            elif color and line.startswith(("+++", "---")):
                print(f"\033[1m{line}\033[0m")
            else:
                print(line)


def draft_arguments(arguments: list[str]) -> list[str]:
    """A quick version of a figure for checking the book builds: a quarter of the size
    and at most 4 samples per pixel, from the same program and options."""
    quick = list(arguments)
    for i, argument in enumerate(quick[:-1]):
        if argument in ("--width", "--height"):
            quick[i + 1] = str(max(16, int(quick[i + 1]) // 4))
        elif argument == "--spp":
            quick[i + 1] = str(min(4, int(quick[i + 1])))
    return quick


def figure_rows() -> list[tuple[str, str, str]]:
    """(figure, program, arguments) of every picture in the book: the [figures] of each
    chapter's manifest, in the chapters' order."""
    return [(f.name, f.program, f.arguments) for manifest in chapter_manifests().values()
            for f in manifest.figures]


def figure_programs(rows) -> list[str]:
    """The chapter programs that render these figures (the build targets they need)."""
    return sorted({find_chapter(program) for _, program, _ in rows
                   if not program.startswith("python_prototypes/")})


def figure_key(program: str, arguments: list[str]) -> str:
    """What makes a figure, as a reference cache key (course_tools/reference_cache.py):
    for a chapter, what makes its grading references (grader.reference_maker: its
    sources, the common layer, build files, assets, compiler, GL and Mesa's settings);
    for a prototype, its script and the prototypes it imports (so a new prototype beside
    them keeps every kept figure), the built assets and the Python, numpy and matplotlib
    that draw it; for both, the test data figures may name, and the arguments."""
    from course_tools import reference_cache
    if program.startswith("python_prototypes/"):
        import importlib.metadata
        from course_tools.python_imports import imported_modules
        versions = [importlib.metadata.version(p) for p in ("numpy", "matplotlib")]
        script = ROOT / program  # with the prototypes it imports, and only those
        sources = sorted({script, *imported_modules(script, [ROOT])})
        maker = reference_cache.key("prototype figure", reference_cache.tree_digest(
            *sources, BUILD / "assets"), sys.version, *versions)
    else:
        from course_tools.grading import grader
        maker = grader.reference_maker(ROOT, BUILD, find_chapter(program))
    return reference_cache.key("book figure", maker, reference_cache.tree_digest(
        ROOT / "tests" / "data", scenes_as_read=True), program, *arguments)


def render_figures(rows, out: Path, draft: bool = False):
    """Renders figures (rows of figure_rows()) into `out`, with the real programs. A
    figure whose program and inputs are unchanged since it was rendered on this machine
    comes from the reference cache (figure_key)."""
    from course_tools import reference_cache
    out.mkdir(parents=True, exist_ok=True)
    for figure, program, arguments in rows:
        if program.startswith("python_prototypes/"):
            options = arguments.split()
            command = [sys.executable, str(ROOT / program), *options, "--figure",
                       str(out / figure)]
        else:
            options = arguments.split()
            options = draft_arguments(options) if draft else options
            command = [str(binary(find_chapter(program))), "--headless", "--out",
                       str(out / figure), *options]
        name = figure_key(program, options) + Path(figure).suffix
        kept = reference_cache.fetch(name)
        if kept is not None:
            (out / figure).write_bytes(kept)
            continue
        say(f"figure {figure}")
        run_checked(command, cwd=ROOT, stdout=subprocess.DEVNULL)
        reference_cache.store(name, (out / figure).read_bytes())


def render_book_figures(draft: bool = False):
    """Every picture in the book comes from the real programs, listed in the manifests."""
    render_figures(figure_rows(), GENERATED, draft)
    diffs = {(a, b): checkpoint_diff(a, b) for a, b in book_diff_pairs()}
    for (a, b), files in diffs.items():
        lines = [l for _, d in files for l in d]
        (GENERATED / f"diff_{a[:2]}_{b[:2]}.diff").write_text("\n".join(lines) + "\n")
    from course_tools.editions import editions
    (GENERATED / "diff_sizes.md").write_text(editions.diff_size_table(diffs))


def book_diff_pairs() -> list[tuple[str, str]]:
    """(from, to) of every diff the book includes: each numbered chapter against the
    one before it, or against the one it branches from (its manifest's `base`), and
    each appendix against the chapter it was copied from (its `base`, not whatever
    comes before it in CMakeLists.txt)."""
    manifests = chapter_manifests()
    numbered = [name for name in manifests if name[:2].isdigit()]
    # A numbered chapter with a base branches from it (chapter 24 from 18).
    pairs = [(manifests[name].base or before, name)
             for before, name in zip(numbered, numbered[1:])]
    return pairs + [(m.base, name) for name, m in manifests.items()
                    if m.base and not name[:2].isdigit()]


def cmd_book(args):
    from course_tools.editions import editions
    build()
    if not args.figures_as_they_are:
        render_book_figures(draft=args.draft)
    os.environ["NO_MKDOCS_2_WARNING"] = "1"  # Material 9.7+ advertises its successor
    # book/hooks/edition.py reads this: the student edition's listings come from the
    # starters' code, without the answer notes, into book/site-student.
    os.environ[editions.EDITION_VARIABLE] = "student" if args.student else "instructors"
    mkdocs = [sys.executable, "-m", "mkdocs"]
    config = str(BOOK / "mkdocs.yml")
    if args.serve:
        run_checked([*mkdocs, "serve", "-f", config], cwd=ROOT)
    else:
        # cwd: snippet paths in the pages are relative to the repository root.
        run_checked([*mkdocs, "build", "--strict", "-q", "-f", config], cwd=ROOT)
        site = editions.STUDENT_SITE if args.student else BOOK / "site"
        print(site / "index.html")


