"""The rules of the repository's layout (book/docs/maintainers.md): every chapter folder is
built and tested, chapters contain no GL plumbing, and checkpoints come in pairs; the
Python tools are one package whose modules import one way, and nothing edits sys.path."""

import ast
import re
from pathlib import Path

import pytest
from conftest import ROOT

from course_tools import chapters

CHAPTER_DIRS = sorted(p.name for p in (ROOT / "chapters").iterdir() if p.is_dir())


def test_every_chapter_folder_is_built():
    assert CHAPTER_DIRS == chapters.names(ROOT)


def test_every_chapter_has_shaders_tests_and_a_book_page():
    shader_dirs = sorted(p.name for p in (ROOT / "shaders").iterdir() if p.is_dir())
    assert shader_dirs == CHAPTER_DIRS
    for name in CHAPTER_DIRS:
        number = name[:2]
        assert list((ROOT / "tests" / "python" / "chapters").glob(f"test_{number}_*.py")), name
        assert (ROOT / "book" / "docs" / "chapters" / f"{name}.md").exists(), name


def chapter_numbers_named(text: str) -> list[str]:
    """Where a text names a chapter by its number or its folder ("chapter 16", "Chapter
    18's", "chapters 03-06", "02_first_pixels")."""
    return re.findall(r"\b[Cc]hapters? \d+|\b(?:\d\d|A\d)_[a-z]\w*", text)


def test_the_common_layer_names_no_chapter():
    """common/ is what no chapter teaches, whatever the chapters' order: a message that
    names a chapter comes from the chapters' manifests (cmake/SceneSupport.cmake)."""
    named = [f"{path.relative_to(ROOT)}: {', '.join(found)}"
             for path in sorted((ROOT / "common").rglob("*")) if path.is_file()
             for found in [chapter_numbers_named(path.read_text(errors="replace"))] if found]
    assert named == [], "\n".join(named)
    assert chapter_numbers_named("glass comes in chapter 16; see 02_first_pixels") == \
        ["chapter 16", "02_first_pixels"]
    assert chapter_numbers_named("the chapter NN_name; a chapter's manifest") == []


def test_chapters_contain_no_context_plumbing():
    pattern = re.compile(r"eglInitialize|glfwInit|OSMesaCreateContext|gladLoad")
    for path in (ROOT / "chapters").rglob("*.cpp"):
        assert not pattern.search(path.read_text()), f"{path}: GL plumbing belongs in common/"


def test_chapter_mains_read_as_lessons():
    for path in (ROOT / "chapters").glob("*/main.cpp"):
        lines = path.read_text().splitlines()
        assert lines[0].startswith(("// Chapter", "// Appendix")), \
            f"{path}: start with what the chapter teaches"
        assert len(lines) <= 200, f"{path}: {len(lines)} lines; move helpers to their own file"
        assert max(map(len, lines)) <= 96, f"{path}: keep lines within 96 columns"


def test_nothing_cites_a_file_outside_the_repository():
    """The project explains itself: its design is book/docs/maintainers.md, and no code,
    test or page sends a reader to documents that are not in the repository."""
    outside = re.compile(r"COURSE\.md|STYLE\.md|\.\./shared\b")
    suffixes = {".py", ".cpp", ".h", ".glsl", ".comp", ".frag", ".vert", ".cmake", ".txt",
                ".md", ".sh", ".yml", ".ini", ".scene"}
    offenders = []
    for path in ROOT.rglob("*"):
        parts = path.relative_to(ROOT).parts
        if parts[0] in (".git", ".venv", "build") or "site" in parts[:2] or \
                not path.is_file():
            continue
        if path.suffix in suffixes or path.name in ("course", "run"):
            for number, line in enumerate(path.read_text(errors="replace").splitlines(), 1):
                if outside.search(line):
                    offenders.append(f"{path.relative_to(ROOT)}:{number}: {line.strip()}")
    assert offenders == [], "\n".join(offenders)


# ---------------------------------------------------------------- the Python side

PYTHON_FOLDERS = ("tools", "tests/python", "book/hooks", "python_prototypes", "grading_catalogue")
PACKAGE = ROOT / "tools" / "course_tools"
# The tools' jobs, each importing only from its own rank or below: set-up runs before
# .venv exists and needs nothing else; the grader needs only the shared pieces; editions
# and starters may grade; benches may grade and read editions; the command line, all.
RANKS = {"setup": 1, "grading": 2, "editions": 3, "bench": 4, "windows": 4, "cli": 5}  # shared: 0


def python_files() -> list[Path]:
    return sorted(p for folder in PYTHON_FOLDERS for p in (ROOT / folder).rglob("*.py")
                  if "__pycache__" not in p.parts)


def module_name(path: Path) -> str:
    relative = path.relative_to(PACKAGE.parent).with_suffix("")
    parts = relative.parts[:-1] if relative.name == "__init__" else relative.parts
    return ".".join(parts)


def imported_names(tree: ast.AST) -> set[str]:
    """Every module an import statement names, at the top or inside a function:
    `import a.b` gives a.b; `from a import b, c` gives a, a.b and a.c."""
    names = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            names |= {alias.name for alias in node.names}
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            names.add(node.module)
            names |= {f"{node.module}.{alias.name}" for alias in node.names}
    return names


def tools_graph() -> dict[str, set[str]]:
    modules = {module_name(p): p for p in PACKAGE.rglob("*.py")}
    return {name: {other for other in imported_names(ast.parse(path.read_text()))
                   if other in modules and other != name}
            for name, path in modules.items()}


def rank(module: str) -> int:
    parts = module.split(".")
    return RANKS.get(parts[1], 0) if len(parts) > 2 or parts[-1] in RANKS else 0


def cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The import cycles of a graph, each as the path that closes it."""
    found, state = [], {}

    def visit(module: str, path: list[str]):
        state[module] = "open"
        for other in sorted(graph.get(module, ())):
            if state.get(other) == "open":
                found.append(path[path.index(other):] + [other])
            elif other not in state:
                visit(other, path + [other])
        state[module] = "done"

    for module in sorted(graph):
        if module not in state:
            visit(module, [module])
    return found


def test_the_tools_import_one_way():
    graph = tools_graph()
    assert "course_tools.grading.grader" in graph and "course_tools.cli.verbs" in graph
    assert cycles(graph) == []
    upward = [f"{module} imports {other}" for module, others in graph.items()
              for other in others if rank(other) > rank(module)]
    assert upward == [], "\n".join(upward)


def test_the_import_checks_can_fail():
    assert cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}}) == [["a", "b", "c", "a"]]
    assert cycles({"a": {"b"}, "b": set()}) == []
    assert rank("course_tools.cli.verbs") > rank("course_tools.grading.grader") > \
        rank("course_tools.chapters")
    inside = ast.parse("def f():\n    from course_tools.grading import grader\n")
    assert "course_tools.grading.grader" in imported_names(inside)


def path_edits(source: str) -> list[int]:
    """Lines that change sys.path (insert, append, an assignment...) or write code that
    would, as text for another interpreter."""
    lines = [number for number, line in enumerate(source.splitlines(), 1)
             if re.search(r"sys\.path\s*(\.\s*(insert|append|extend|remove)\b|\[.*\]\s*=|[+]?=)",
                          line) or "site.addsitedir" in line]
    return lines


def test_nothing_edits_sys_path():
    """The package is installed into .venv (pyproject.toml) and pytest finds the checks'
    helpers through its configuration: no script, check or hook edits sys.path."""
    offenders = [f"{path.relative_to(ROOT)}:{line}" for path in python_files()
                 if path.name != "test_layout.py"
                 for line in path_edits(path.read_text())]
    assert offenders == []
    assert path_edits("import sys\nsys.path.insert(0, 'x')\n") == [2]
    assert path_edits("sys.path = ['x']\n") == [1]
    assert path_edits("code = 'sys.path.append(here)'\n") == [1]


@pytest.mark.parametrize("definition, home", [
    (r"^def read_pfm\(|^def parse_pfm\(|^def decode_pfm\(", "python_prototypes/pfm.py"),
    (r"0\.0031308|<= 0\.04045", "python_prototypes/srgb.py"),
    (r"add_chapter\\\(", "tools/course_tools/chapters.py"),
    (r"^def run_limited\(", "tools/course_tools/grading/sandbox.py"),
    (r"^def minutes\(", "tools/course_tools/cli/suite_parts.py"),
    (r"CMakeCache\.txt", "tools/course_tools/cmake_cache.py"),
])
def test_one_copy_of_each_helper(definition, home):
    """Each of these helpers is written once, where `home` says; the checks may restate
    a constant to test it (tests/python/chapters, prototypes, tools are not searched,
    nor the C++ the planted mistakes are made of)."""
    pattern = re.compile(definition, flags=re.M)
    helpers = [p for p in python_files() if p.parent.name not in ("chapters", "prototypes")
               and not (p.parent.name == "tools" and p.parent.parent.name == "python")
               and p.parent.name != "grading_catalogue"]
    found = [str(p.relative_to(ROOT)) for p in helpers if pattern.search(p.read_text())]
    assert found == [home]
