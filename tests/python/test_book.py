"""The book builds strictly, with every figure rendered by the real programs, and the
front door's read-only verbs work."""

import subprocess
import sys

from conftest import ROOT, read_image

COURSE = [sys.executable, str(ROOT / "tools" / "course.py")]


def test_book_builds_strictly_with_real_figures(built_book):
    site = built_book
    assert (site / "index.html").exists()
    figures = [line.split("\t")[0] for line in (ROOT / "book" / "figures.tsv").read_text()
               .splitlines() if line.strip() and not line.startswith("#")]
    for figure in figures:
        rendered = ROOT / "book" / "docs" / "generated" / figure
        image = read_image(rendered)
        assert image.shape[0] >= 16 and image.shape[1] >= 16, figure
        assert image.std() > 0, f"{figure} is blank"
        assert (site / "generated" / figure).exists(), figure
    page = (site / "chapters" / "02_first_pixels" / "index.html").read_text()
    assert "patternColor" in page  # code pulled from the real shader
    assert "--8&lt;--" not in page and "--8<--" not in page


def test_diff_shows_only_what_the_chapter_adds():
    result = subprocess.run([*COURSE, "diff", "01", "02"], capture_output=True, text=True)
    assert result.returncode == 0
    assert "+++ chapters/02_first_pixels/main.cpp" in result.stdout
    assert "--- chapters/01_buffer_add/main.cpp" in result.stdout
    assert "\033[" not in result.stdout  # no colour when piped
    stat = subprocess.run([*COURSE, "diff", "01", "02", "--stat"], capture_output=True,
                          text=True)
    assert "files changed from 01_buffer_add to 02_first_pixels" in stat.stdout


def test_list_names_every_chapter():
    result = subprocess.run([*COURSE, "list"], capture_output=True, text=True)
    assert result.returncode == 0
    for folder in sorted((ROOT / "chapters").iterdir()):
        assert folder.name in result.stdout
