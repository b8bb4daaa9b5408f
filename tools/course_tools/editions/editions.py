"""The book's two editions, and the page a released starter carries.

The instructors' edition (./course book) shows the code as it is, solutions included,
with short answer notes after each chapter's exercises. The student edition
(./course book --student) is the one to publish: its listings come from a copy of the
sources in which every SOLUTION block is what the starter has instead (the TODO with its
hint, and the stub), and the answer notes are left out.

A block's code does not stay inside its own chapter: once chapter 04 is done, its
sphere test is given code in chapter 05's folder, unmarked, and so on forward. In the
student edition such a copy is taken out too, and shown as
`// TODO (chapter 04): <hint>` with the stub: a student reading ahead is not handed
chapter 04's answer by chapter 06's listing or diff. Copies are found word for word
(censor_copies) or, where a later chapter changed them a little, by aligning the
block's lines with the file's (changed_copy).

A starter's page (classroom.release) is the chapter's page with every snippet resolved
against the starter's own files, its formulas typeset and its figures beside it: one
HTML page that opens offline, and the same page as Markdown with the code inlined.
"""

from __future__ import annotations

import difflib
import html
import os
import re
import shutil
import textwrap
from dataclasses import dataclass, field
from pathlib import Path

from course_tools import chapters as chapter_list
from course_tools.editions import solution_markers

from course_tools.paths import ROOT

STUDENT_SITE = ROOT / "book" / "site-student"
# The copy of the sources the student edition's listings come from (snippets' base path).
STUDENT_SOURCES = ROOT / "build" / "book-student" / "sources"
EDITION_VARIABLE = "COURSE_BOOK_EDITION"  # "student", or unset: the instructors' edition


def edition() -> str:
    return "student" if os.environ.get(EDITION_VARIABLE) == "student" else "instructors"


# ---------------------------------------------------------------- solution blocks

@dataclass
class SolutionBlock:
    chapter: str          # "04_spheres"
    path: str             # "shaders/04_spheres/sphere.glsl"
    begin_line: int       # 1-based, the BEGIN SOLUTION line
    hint: str
    body: list[str] = field(default_factory=list)   # the solution's lines, as written
    stubs: list[str] = field(default_factory=list)  # the STUB lines' code


def checkpoint_sources(root: Path, chapter: str) -> list[Path]:
    return [path for top in ("chapters", "shaders")
            for path in sorted((root / top / chapter).rglob("*")) if path.is_file()]


def solution_blocks(root: Path, chapter: str | None = None) -> list[SolutionBlock]:
    """Every SOLUTION block of the checkpoints (or of one), in course order."""
    found = []
    for name in [chapter] if chapter else chapter_list.names(root):
        for path in checkpoint_sources(root, name):
            if path.suffix not in solution_markers.MARKED_SUFFIXES:
                continue
            relative = str(path.relative_to(root))
            text = path.read_text()
            lines = text.splitlines()
            for block in solution_markers.find_blocks(text, relative):
                inside = lines[block.begin_line:block.end_line - 1]
                found.append(SolutionBlock(
                    name, relative, block.begin_line, block.hint or "write this part",
                    [line for line in inside if not solution_markers.STUB.match(line)],
                    [solution_markers.STUB.match(line)["code"] for line in inside
                     if solution_markers.STUB.match(line)]))
    return found


def code_of(line: str) -> str:
    """A line's code, without its indentation, a trailing // comment or spaces inside
    (`x  = a;` and `x = a;` are the same line); empty for a blank or comment line."""
    code = line.split("//", 1)[0]
    return " ".join(code.split())


# ---------------------------------------------------------------- the student's sources

def taken_out(block: SolutionBlock, indent: str, own: bool) -> list[str]:
    """What a student sees where `block` was: the starter's TODO and stubs. In a later
    chapter's copy, the TODO names the chapter whose exercise it was."""
    label = "TODO" if own else f"TODO (chapter {block.chapter[:2]})"
    return [f"{indent}// {label}: {block.hint}"] + [f"{indent}{stub}" for stub in block.stubs]


def censor_copies(text: str, block: SolutionBlock) -> str:
    """Every word-for-word copy of the block's lines (indentation aside) in a later
    chapter's file becomes the TODO and stubs."""
    wanted = [line.strip() for line in block.body]
    if not any(wanted):
        return text
    lines = text.splitlines()
    stripped = [line.strip() for line in lines]
    out, i = [], 0
    while i < len(lines):
        if stripped[i:i + len(wanted)] == wanted:
            indent = lines[i][:len(lines[i]) - len(lines[i].lstrip())]
            out += taken_out(block, indent, own=False)
            i += len(wanted)
        else:
            out.append(lines[i])
            i += 1
    return "\n".join(out) + ("\n" if text.endswith("\n") else "")


# A later chapter may change a block's code a little (chapter 07's triangle test reads
# corners without `.xyz`). Such a copy is found by aligning the block's lines with the
# file's (difflib): at least half of the block's code lines, all within a stretch not
# much longer than the block. The copy then runs from where the block's first line
# would be to where its last would be, but never out of the block's indentation.
NEARBY = 8  # lines a changed copy may have grown by


def changed_copy(lines: list[str], block: SolutionBlock) -> tuple[int, int] | None:
    """(first, last) line index of a changed copy of the block in `lines`, or None."""
    body = [line.strip() for line in block.body]
    code = [code_of(line) for line in block.body]
    wanted = sum(1 for c in code if c)
    if wanted == 0:
        return None
    # Lines compare by their code, so that a copy with a comment added after it is one.
    matcher = difflib.SequenceMatcher(None, [c or line for c, line in zip(code, body)],
                                      [code_of(line) or line.strip() for line in lines],
                                      autojunk=False)
    pairs = [(i + k, j + k) for i, j, size in matcher.get_matching_blocks()
             for k in range(size) if code[i + k]]
    best: list[tuple[int, int]] = []
    for start in range(len(pairs)):  # the most matches within one short stretch
        near = [p for p in pairs[start:] if p[1] - pairs[start][1] <= len(body) + NEARBY]
        if len(near) > len(best):
            best = near
    if len(best) * 2 < wanted:
        return None
    (first_i, first), (last_i, last) = best[0], best[-1]
    indent = len(lines[first]) - len(lines[first].lstrip())

    def inside(j: int) -> bool:
        line = lines[j]
        return (not line.strip() or len(line) - len(line.lstrip()) >= indent) \
            and "--8<--" not in line
    for _ in range(first_i):
        if first > 0 and inside(first - 1):
            first -= 1
    for _ in range(len(body) - 1 - last_i):
        if last + 1 < len(lines) and inside(last + 1) and lines[last + 1].strip():
            last += 1
    # The block's own comments, where they still stand just before the copy.
    while first > 0 and lines[first - 1].strip() in body and not code_of(lines[first - 1]) \
            and lines[first - 1].strip():
        first -= 1
    return first, last


def censor_changed_copy(text: str, block: SolutionBlock) -> str:
    lines = text.splitlines()
    span = changed_copy(lines, block)
    if span is None:
        return text
    first, last = span
    indent = lines[first][:len(lines[first]) - len(lines[first].lstrip())]
    lines[first:last + 1] = taken_out(block, indent, own=False)
    return "\n".join(lines) + ("\n" if text.endswith("\n") else "")


def student_text(text: str, path: str, earlier: list[SolutionBlock]) -> str:
    """The student edition of one checkpoint file: its own blocks as in the starter,
    copies of earlier chapters' blocks taken out, word for word or changed."""
    if Path(path).suffix not in solution_markers.MARKED_SUFFIXES:
        return text
    text = solution_markers.strip_solutions(text, path)
    for block in earlier:
        text = censor_changed_copy(censor_copies(text, block), block)
    return text


def student_checkpoint(root: Path, chapter: str,
                       blocks: list[SolutionBlock] | None = None) -> dict[str, str]:
    """'chapters/NN_name/x.cpp' -> the student edition's text, for one checkpoint."""
    blocks = solution_blocks(root) if blocks is None else blocks
    order = chapter_list.names(root)
    earlier = [b for b in blocks if order.index(b.chapter) < order.index(chapter)]
    files = {}
    for path in checkpoint_sources(root, chapter):
        relative = str(path.relative_to(root))
        try:
            files[relative] = student_text(path.read_text(), relative, earlier)
        except UnicodeDecodeError:
            continue  # a binary file: no listing shows it
    return files


# A file gone from checkpoint a and a file new in b count as one file renamed when at
# least this share of their lines agree (git's rename detection uses 50% too): chapter
# 12's path.comp and the appendix's path.frag are one shader, changed, not two.
RENAME_SIMILARITY = 0.5


def renamed_files(before: dict[str, str], after: dict[str, str]) -> dict[str, str]:
    """{key in before only: key in after only} for the pairs that are one file renamed:
    same top folder (chapters/ or shaders/), the most similar pairs first."""
    gone = [k for k in before if k not in after]
    new = [k for k in after if k not in before]
    scored = []
    for old_key in gone:
        for new_key in new:
            if old_key.split("/")[0] != new_key.split("/")[0]:
                continue
            matcher = difflib.SequenceMatcher(None, before[old_key].splitlines(),
                                              after[new_key].splitlines(), autojunk=False)
            if matcher.ratio() >= RENAME_SIMILARITY:
                scored.append((-matcher.ratio(), old_key, new_key))
    pairs: dict[str, str] = {}
    for _, old_key, new_key in sorted(scored):
        if old_key not in pairs and new_key not in pairs.values():
            pairs[old_key] = new_key
    return pairs


def checkpoint_diff(old: dict[str, str], new: dict[str, str], a: str,
                    b: str) -> list[tuple[str, list[str]]]:
    """Per file, the unified diff from checkpoint a to checkpoint b, given their texts
    keyed 'chapters/NN_name/...' (the files as they are, or an edition of them). A file
    renamed on the way (renamed_files) is one diff, keyed by its new name."""
    def by_file(texts: dict[str, str]) -> dict[str, str]:
        keyed = {}
        for path, text in texts.items():
            top, _, rest = path.split("/", 2)
            keyed[f"{top}/{rest}"] = text
        return keyed
    before, after = by_file(old), by_file(new)
    renamed = renamed_files(before, after)
    old_name = {new_key: old_key for old_key, new_key in renamed.items()}
    result = []
    for key in sorted((set(before) - set(renamed)) | set(after)):
        source = old_name.get(key, key)
        top, rest = key.split("/", 1)
        old_rest = source.split("/", 1)[1]
        lines = list(difflib.unified_diff(
            before[source].splitlines() if source in before else [],
            after[key].splitlines() if key in after else [],
            f"{top}/{a}/{old_rest}" if source in before else "/dev/null",
            f"{top}/{b}/{rest}" if key in after else "/dev/null", lineterm=""))
        if lines:
            result.append((key, lines))
    return result


# What one checkpoint should add to the one before it, at most: a lesson, no more.
DIFF_TARGET = 600


def changed_lines(diffs: list[tuple[str, list[str]]]) -> tuple[int, int]:
    """(added, removed) lines of a checkpoint_diff, headers not counted."""
    added = sum(1 for _, lines in diffs for l in lines
                if l.startswith("+") and not l.startswith("+++"))
    removed = sum(1 for _, lines in diffs for l in lines
                  if l.startswith("-") and not l.startswith("---"))
    return added, removed


def diff_size_table(diffs: dict[tuple[str, str], list[tuple[str, list[str]]]]) -> str:
    """The book index's table: each checkpoint diff's files and changed lines, from the
    diffs the book shows ((from, to) -> checkpoint_diff)."""
    lines = ["| checkpoint | files | added | removed | changed |",
             "| --- | ---: | ---: | ---: | ---: |"]
    for (a, b), files in diffs.items():
        added, removed = changed_lines(files)
        total = added + removed
        mark = "" if total <= DIFF_TARGET else " (over)"
        lines.append(f"| `./course diff {a[:2]} {b[:2]}` | {len(files)} | {added} | "
                     f"{removed} | {total}{mark} |")
    return "\n".join(lines) + "\n"


def diff_text(old: dict[str, str], new: dict[str, str], a: str, b: str) -> str:
    """The whole diff, as the book includes it (book/docs/generated/diff_NN_MM.diff)."""
    return "\n".join(line for _, lines in checkpoint_diff(old, new, a, b)
                     for line in lines) + "\n"


def checkpoint_texts(root: Path, chapter: str) -> dict[str, str]:
    """'chapters/NN_name/x.cpp' -> text, for every file of a checkpoint under root."""
    return {str(path.relative_to(root)): path.read_text()
            for path in checkpoint_sources(root, chapter)}


def write_student_sources(root: Path, out: Path, diff_pairs: list[tuple[str, str]]) -> Path:
    """The folder the student edition's snippets read: chapters/ and shaders/ in their
    student edition, common/ as it is, and book/docs/generated/ with the checkpoint
    diffs made from the student edition and the setup page's generated tables."""
    if out.exists():
        shutil.rmtree(out)
    blocks = solution_blocks(root)
    editions = {name: student_checkpoint(root, name, blocks) for name in chapter_list.names(root)}
    for files in editions.values():
        for relative, text in files.items():
            (out / relative).parent.mkdir(parents=True, exist_ok=True)
            (out / relative).write_text(text)
    shutil.copytree(root / "common", out / "common")
    shutil.copytree(root / "assets", out / "assets")  # the scene files pages show
    # Prototypes whose code a page shows (the numpy Monte Carlo of chapter 11): they
    # teach, they are not exercises; the reference renderers are not copied.
    for page in sorted((root / "book" / "docs" / "chapters").glob("*.md")):
        for shown in re.findall(r'--8<-- "(python_prototypes/[\w/]+\.py)', page.read_text()):
            (out / shown).parent.mkdir(parents=True, exist_ok=True)
            shutil.copyfile(root / shown, out / shown)
    generated = out / "book" / "docs" / "generated"
    generated.mkdir(parents=True)
    for table in (root / "book" / "docs" / "generated").glob("*.md"):
        shutil.copyfile(table, generated / table.name)
    for a, b in diff_pairs:
        (generated / f"diff_{a[:2]}_{b[:2]}.diff").write_text(
            diff_text(editions[a], editions[b], a, b))
    return out


# ---------------------------------------------------------------- answer notes

# An instructors' note: `??? answers "Answers"` (a collapsed pymdownx.details block;
# `!!! answers` and `???+ answers` too) and every indented or blank line after it.
ANSWERS = re.compile(r"^(?:\?\?\?\+?|!!!)\s+answers\b")


def drop_answers(markdown: str) -> str:
    """The page without its answer notes (the student edition, a starter's page)."""
    out, inside = [], False
    for line in markdown.splitlines(keepends=True):
        if ANSWERS.match(line):
            inside = True
            continue
        if inside and (not line.strip() or line.startswith(("    ", "\t"))):
            continue
        inside = False
        out.append(line)
    return "".join(out)


# ---------------------------------------------------------------- snippets, resolved

SNIPPET = re.compile(r"""^(?P<indent>[ \t]*)--8<-- (?P<quote>["'])(?P<target>[^"']+)(?P=quote)\s*$""")
SECTION = re.compile(r"--8<-- \[(?P<kind>start|end):(?P<name>\w+)\]")


class SnippetError(Exception):
    """A starter's page that cannot be made: a listing or a formula, named."""


def snippet(base: Path, target: str, where: str) -> list[str]:
    """The lines `--8<-- "target"` includes, as pymdownx.snippets includes them with the
    book's settings: a whole file, or a `file:section` between its [start:section] and
    [end:section] markers, dedented, other sections' markers left out."""
    path, _, section = target.partition(":")
    file = base / path
    if not file.is_file():
        raise SnippetError(f"{where}: {target}: no {path} in {base}")
    lines = file.read_text().splitlines()
    if section:
        starts = [i for i, l in enumerate(lines) if (m := SECTION.search(l))
                  and m["kind"] == "start" and m["name"] == section]
        ends = [i for i, l in enumerate(lines) if (m := SECTION.search(l))
                and m["kind"] == "end" and m["name"] == section]
        if not starts or not ends or ends[0] < starts[0]:
            raise SnippetError(f"{where}: {target}: no section '{section}' in {path}")
        lines = lines[starts[0] + 1:ends[0]]
        lines = textwrap.dedent("\n".join(lines)).splitlines()
    return [line for line in lines if not SECTION.search(line)]


def resolve_snippets(markdown: str, base: Path, where: str) -> str:
    out = []
    for line in markdown.splitlines():
        if match := SNIPPET.match(line):
            out += [match["indent"] + included if included else ""
                    for included in snippet(base, match["target"], where)]
        else:
            out.append(line)
    return "\n".join(out) + "\n"


# ---------------------------------------------------------------- a starter's page

FIGURE = re.compile(r"\]\(\.\./generated/(?P<name>[\w.-]+\.png)\)")


def page_figures(markdown: str) -> list[str]:
    """The figures a book page shows (../generated/NAME.png)."""
    return sorted(set(m["name"] for m in FIGURE.finditer(markdown)))


def page_figures_inlined(markdown: str) -> list[str]:
    """The figures a starter's page shows (figures/NAME.png)."""
    return sorted(set(re.findall(r"\]\(figures/([\w.-]+\.png)\)", markdown)))


def starter_markdown(root: Path, chapter: str, starter: Path) -> str:
    """The chapter's page with the starter's code in it: snippets from the starter's own
    files, the diff from the previous checkpoint, solved, to this starter (what the
    chapter adds, with its TODOs), figures from figures/ beside the page, no answer
    notes."""
    page = root / "book" / "docs" / "chapters" / f"{chapter}.md"
    markdown = drop_answers(page.read_text())
    order = chapter_list.names(root)
    generated = starter / "book" / "generated"  # the page's diff, kept while resolving
    generated.mkdir(parents=True, exist_ok=True)
    try:
        for target in re.findall(r"book/docs/generated/(diff_\w+\.diff)", markdown):
            a, b = [find(order, n) for n in target[5:-5].split("_")]
            solved = {path: solved_text(text)
                      for path, text in checkpoint_texts(root, a).items()}
            (generated / target).write_text(diff_text(
                solved, checkpoint_texts(starter, b), a, b))
        markdown = markdown.replace("book/docs/generated/", "book/generated/")
        markdown = resolve_snippets(markdown, starter, f"book/docs/chapters/{chapter}.md")
    finally:
        shutil.rmtree(generated)
    return FIGURE.sub(lambda m: f"](figures/{m['name']})", markdown)


def solved_text(text: str) -> str:
    """A checkpoint file as its student has it once the chapter is done: the solutions
    in, the markers and stubs out."""
    return "".join(line for line in text.splitlines(keepends=True)
                   if not (solution_markers.BEGIN.match(line) or solution_markers.END.match(line)
                           or solution_markers.STUB.match(line)))


def find(order: list[str], number: str) -> str:
    return next(name for name in order if name[:2] == number)

PAGE = """<!doctype html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<title>{title}</title>
<style>
body {{ font: 16px/1.6 system-ui, -apple-system, "Segoe UI", Roboto, sans-serif;
       color: #222; max-width: 52rem; margin: 2rem auto; padding: 0 1rem; }}
h1, h2, h3 {{ line-height: 1.25; }} h2 {{ border-bottom: 1px solid #ddd; }}
a.headerlink {{ display: none; }}
code {{ font-family: ui-monospace, "SFMono-Regular", Menlo, Consolas, monospace;
        font-size: 0.9em; background: #f3f3f6; padding: 0.1em 0.25em; border-radius: 3px; }}
pre code {{ background: none; padding: 0; }}
.highlight pre {{ background: #f7f7fa; padding: 0.8em 1em; overflow-x: auto;
                  border: 1px solid #e4e4ec; border-radius: 4px; line-height: 1.4; }}
img {{ max-width: 100%; }}
.grid {{ display: grid; grid-template-columns: repeat(auto-fit, minmax(16rem, 1fr));
         gap: 1rem; }}
.admonition, details {{ border-left: 4px solid #3f51b5; background: #f5f6fb;
                        padding: 0.3em 1em; margin: 1em 0; }}
.admonition-title, summary {{ font-weight: 600; }}
table {{ border-collapse: collapse; }} td, th {{ border: 1px solid #ddd; padding: 0.3em 0.6em; }}
math {{ font-family: "STIX Two Math", "Latin Modern Math", "Cambria Math", math;
        font-size: 1.1em; }}
math[display="block"] {{ margin: 1em 0; overflow-x: auto; }}
.starter-note {{ color: #555; font-size: 0.9em; border-bottom: 1px solid #ddd;
                 padding-bottom: 0.5em; }}
{pygments}
</style>
</head>
<body>
<p class="starter-note">The page of chapter {name} for this starter: the code shown is
this folder's, with the parts you write marked <code>TODO</code>. The whole book:
<code>./course book</code> in the course's repository.</p>
{body}
</body>
</html>
"""


def render_page(markdown: str, title: str, name: str) -> str:
    """The page as one HTML file that needs nothing else but its figures: the book's
    Markdown extensions, code highlighted with inline colours, formulas typeset as
    MathML as the book's own hook does (formulas.py)."""

    import markdown as markdown_module
    from pygments.formatters import HtmlFormatter
    from course_tools.editions import formulas as mathml

    converter = markdown_module.Markdown(extensions=[
        "admonition", "attr_list", "md_in_html", "tables", "toc", "pymdownx.details",
        "pymdownx.superfences", "pymdownx.highlight", "pymdownx.arithmatex"],
        extension_configs={"pymdownx.highlight": {"anchor_linenums": False},
                           "pymdownx.arithmatex": {"generic": True}})
    body = converter.convert(markdown)
    problems = []

    def typeset(match: re.Match) -> str:
        display = match["block"] is not None
        tex = html.unescape(match["block"] if display else match["inline"])
        try:
            return match["open"] + mathml.to_mathml(tex, display) + match["close"]
        except mathml.FormulaError as error:
            problems.append(f"{tex}: {error}")
            return match[0]

    body = mathml.FORMULA.sub(typeset, body)
    if problems:
        raise SnippetError(f"{name}: formulas that cannot be typeset: {problems}")
    pygments = HtmlFormatter(style="friendly").get_style_defs(".highlight")
    return PAGE.format(title=html.escape(title), name=name, body=body, pygments=pygments)
