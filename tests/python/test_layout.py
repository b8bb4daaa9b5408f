"""The rules of the repository's layout (book/docs/maintainers.md): every chapter folder is
built and tested, chapters contain no GL plumbing, and checkpoints come in pairs."""

import re

from conftest import ROOT

CHAPTER_DIRS = sorted(p.name for p in (ROOT / "chapters").iterdir() if p.is_dir())


def built_chapters():
    text = (ROOT / "CMakeLists.txt").read_text()
    return re.findall(r"^add_chapter\((\w+)\)", text, flags=re.M)


def test_every_chapter_folder_is_built():
    assert CHAPTER_DIRS == built_chapters()


def test_every_chapter_has_shaders_tests_and_a_book_page():
    shader_dirs = sorted(p.name for p in (ROOT / "shaders").iterdir() if p.is_dir())
    assert shader_dirs == CHAPTER_DIRS
    for name in CHAPTER_DIRS:
        number = name[:2]
        assert list((ROOT / "tests" / "python").glob(f"test_{number}_*.py")), name
        assert (ROOT / "book" / "docs" / "chapters" / f"{name}.md").exists(), name


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
