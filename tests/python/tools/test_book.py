"""The book builds strictly, with every figure rendered by the real programs and every
formula typeset as MathML, its setup page shows the platform table it is generated
from, and the front door's read-only verbs work."""

import html as html_module
import re
import subprocess
import sys

import pytest

from conftest import ROOT, read_image

from course_tools import chapters, manifests
from course_tools.cli.book import figure_rows  # every chapter manifest's pictures
from course_tools.editions import formulas as mathml  # as book/hooks/mathml.py typesets
from course_tools.setup import machine_setup, platforms

COURSE = [sys.executable, str(ROOT / "tools" / "course.py")]


def test_book_builds_strictly_with_real_figures(built_book):
    site = built_book
    assert (site / "index.html").exists()
    figures = [figure for figure, _, _ in figure_rows()]
    assert len(figures) >= 40
    for figure in figures:
        rendered = ROOT / "book" / "docs" / "generated" / figure
        image = read_image(rendered)
        assert image.shape[0] >= 16 and image.shape[1] >= 16, figure
        assert image.std() > 0, f"{figure} is blank"
        assert (site / "generated" / figure).exists(), figure
    page = (site / "chapters" / "02_first_pixels" / "index.html").read_text()
    assert "patternColor" in page  # code pulled from the real shader
    assert "--8&lt;--" not in page and "--8<--" not in page


def test_every_chapter_has_a_manifest_and_every_picture_is_listed(built_book):
    """The manifests name every chapter's title, summary and pictures: the navigation
    and the front page's list come from them, and each picture a page shows is one a
    manifest renders (and none is rendered for no page)."""
    found = manifests.load(ROOT, chapters.names())
    assert list(found) == chapters.names()
    index = (built_book / "index.html").read_text()
    shown = set()
    for name, manifest in found.items():
        assert f'href="chapters/{name}/"' in index and manifest.title in index, name
        page = (ROOT / "book" / "docs" / "chapters" / f"{name}.md").read_text()
        shown |= set(re.findall(r"\.\./generated/([\w.-]+\.png)", page))
    assert shown == {figure for figure, _, _ in figure_rows()}


def test_a_broken_manifest_is_a_clear_error(tmp_path):
    bad = tmp_path / "manifests" / "01_buffer_add.ini"
    bad.parent.mkdir()
    bad.write_text("[chapter]\ntitle = Buffer add\n")
    with pytest.raises(manifests.ManifestError, match="01_buffer_add.ini: \\[chapter\\] needs a summary"):
        manifests.load(tmp_path, ["01_buffer_add"])
    bad.write_text("[chapter]\ntitle = x\nsummary = y\n[figures]\nnot_a_png = 01\n")
    with pytest.raises(manifests.ManifestError, match="expected NAME.png = PROGRAM"):
        manifests.load(tmp_path, ["01_buffer_add"])
    with pytest.raises(manifests.ManifestError, match="missing"):
        manifests.load(tmp_path, ["02_first_pixels"])


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


# ---------------------------------------------------------------- formulas

def built_pages(site) -> list:
    return sorted(p for p in site.rglob("*.html") if "assets" not in p.parts)


def test_every_formula_is_mathml_in_the_built_book(built_book):
    """No page keeps a formula as TeX: every arithmatex wrapper holds a <math> element
    (the browser test checks the same of the text a reader sees)."""
    typeset = 0
    for page in built_pages(built_book):
        html = page.read_text()
        for wrapper in re.finditer(r'class="arithmatex">(.{0,6})', html):
            assert wrapper.group(1).startswith("<math"), \
                f"{page.relative_to(built_book)}: a formula left as TeX: {wrapper.group(0)}"
            typeset += 1
    assert typeset >= 20  # chapters 04, 05, 06, 08, 09, 11, 12 and 13 have formulas
    page = (built_book / "chapters" / "11_path_tracing" / "index.html").read_text()
    assert '<math alttext="L_o(x, \\omega_o)' in page and 'display="block"' in page


@pytest.mark.parametrize("tex, element", [
    (r"\frac{a}{b}", "<mfrac>"),
    (r"\sum_{i=1}^{N} x_i", "&#x02211;"),
    (r"\int_{H^2} f \, d\omega", "&#x0222B;"),
    (r"L_o(x, \omega_o)", "<msub>"),
    (r"\omega \theta \pi", "&#x003C9;"),
    (r"\mathbf{v} \cdot \mathbf{n}", "&#x1D42F;"),  # bold v
    (r"\sqrt{b^2 - c}", "<msqrt>"),
    (r"\text{albedo} \cdot \max(0, N \cdot L)", "<mtext>albedo</mtext>"),
])
def test_formulas_become_mathml(tex, element):
    for display in (False, True):
        result = mathml.to_mathml(tex, display)
        assert result.startswith("<math ") and element in result, result
        assert f'display="{"block" if display else "inline"}"' in result


def test_a_function_name_is_set_apart_from_its_argument():
    assert '<mi>cos</mi><mspace width="0.167em" />' in mathml.to_mathml(r"\cos\theta", False)
    assert "<mi>cos</mi><mo" in mathml.to_mathml(r"\cos(x)", False)


@pytest.mark.parametrize("tex, reason", [
    (r"\foo x", "does not know \\foo"),         # latex2mathml would print "\foo"
    (r"\frac{a}{b", "never closed"),
    (r"a}", "closes nothing"),
    (r"\frac{a}", "<mfrac> has 1 parts"),       # latex2mathml: a fraction of one part
    (r"a &= b", "not well-formed"),             # latex2mathml: a bare '&' in the XML
    (r"x_", "latex2mathml"),
    (r"\left( a \right", "latex2mathml"),
])
def test_formulas_latex2mathml_gets_wrong_are_refused(tex, reason):
    with pytest.raises(mathml.FormulaError, match=re.escape(reason)):
        mathml.to_mathml(tex, True)


def test_a_formula_that_cannot_be_typeset_fails_the_strict_build(tmp_path):
    """The hook's error names the page and the formula, and --strict turns it into a
    failed build (a book with raw TeX in it must not pass)."""
    (tmp_path / "docs").mkdir()
    (tmp_path / "docs" / "index.md").write_text("Fine: $a_1$.\n")
    (tmp_path / "docs" / "broken.md").write_text("Broken:\n\n$$ x = \\frobnicate{y} $$\n")
    (tmp_path / "mkdocs.yml").write_text(
        "site_name: t\nmarkdown_extensions:\n  - pymdownx.arithmatex:\n      generic: true\n"
        f"hooks:\n  - {ROOT / 'book' / 'hooks' / 'mathml.py'}\n")
    result = subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "-q"],
                            cwd=tmp_path, capture_output=True, text=True, timeout=120)
    assert result.returncode != 0
    assert "broken.md" in result.stderr and "\\frobnicate" in result.stderr, result.stderr
    assert "index.md" not in result.stderr


# ---------------------------------------------------------------- the setup page

def page_text(path) -> str:
    return html_module.unescape(re.sub(r"<[^>]+>", " ", path.read_text()))


def test_setup_page_shows_every_platform_and_package_of_the_table(built_book):
    """The table is generated from tools/platforms.ini: every row, every layer's
    packages, the browser, the libLLVM and how the row was tested are on the page."""
    page = built_book / "setup" / "index.html"
    source = page.read_text()
    text = " ".join(page_text(page).split())
    for platform in platforms.read_table().values():
        assert " ".join(platform.name.split()) in text, platform.key
        for layer in platforms.LAYERS:
            for package in platform.packages[layer]:
                assert f"<code>{html_module.escape(package)}</code>" in source, \
                    f"{platform.key}: {layer} package {package}"
        if platform.browser == "playwright":
            assert "Playwright" in text
        else:
            assert f"<code>{platform.browser}</code>" in source, platform.key
        if platform.libllvm:
            assert f"<code>{platform.libllvm}</code>" in source, platform.key
        assert " ".join(platform.tested.split()) in text, platform.key
    assert "requirements.txt" not in text  # the single file of before the layers


def test_setup_page_shows_each_layers_verbs_and_python_packages(built_book):
    """The layers table is generated from the verbs table's VERB_LAYERS and the
    requirements files: every verb that sets up a layer, every pinned package."""
    from course_tools.cli.verbs import VERB_LAYERS
    source = (built_book / "setup" / "index.html").read_text()
    rows = {row.group(1): row.group(0) for row in re.finditer(
        r"<tr>\s*<td><code>(\w+)</code></td>.*?</tr>", source, flags=re.S)}
    for layer in platforms.LAYERS:
        assert layer in rows, f"no row for the {layer} layer"
        for verb, needs in VERB_LAYERS.items():
            if needs == layer and verb != "setup":
                assert f"<code>{verb}</code>" in rows[layer], f"{layer}: ./course {verb}"
        requirements = ROOT / "requirements" / f"{layer}.txt"
        for line in requirements.read_text().splitlines():
            name, pin, version = line.split("#")[0].strip().partition("==")
            version = version.split(";")[0].strip()  # without a platform marker
            if pin:
                assert f"<code>{name}</code> {version}" in rows[layer], f"{layer}: {name}"


def test_setup_page_gives_every_exit_code_of_set_up(built_book):
    source = (built_book / "setup" / "index.html").read_text()
    codes = {name: value for name, value in vars(machine_setup).items()
             if name.isupper() and isinstance(value, int) and not isinstance(value, bool)}
    assert set(codes) >= {"UNKNOWN_PLATFORM", "MISSING_PACKAGES", "NO_PACKAGE_MANAGER",
                          "PYTHON_TOO_OLD", "PIP_FAILED"}
    for name, code in codes.items():
        assert f"<td>{code}</td>" in source, f"exit code {code} ({name}) is not explained"


# --- What the pages say a planted bug does ---------------------------------------------------

def test_every_claim_in_the_pages_is_held_by_the_test_that_plants_its_bug():
    """Each sentence marked `<!-- claim NAME: DIRECTION -->` (page_claims) is checked by
    a test that measures the picture with the bug: its name appears in exactly one
    page_claims.check call, so no claim stands unheld and no check names a claim that
    is gone."""
    import page_claims
    claims = page_claims.all_claims()
    assert len(claims) >= 4
    names = [claim.name for claim in claims]
    assert len(names) == len(set(names)), names
    tests = {path.name: path.read_text()
             for path in (ROOT / "tests" / "python").rglob("test_*.py")
             if path.name != "test_book.py"}  # whose own claims below are made up
    checked = {name for text in tests.values()
               for name in re.findall(r'page_claims\.check\(\s*"([^"]+)"', text)}
    for claim in claims:
        assert claim.direction in page_claims.DIRECTIONS, claim.where()
        assert claim.name in checked, f"{claim.where()}: no test checks claim {claim.name}"
    assert checked <= set(names), f"checks of claims no page makes: {checked - set(names)}"


def test_a_claim_the_measurement_contradicts_fails_naming_its_page(tmp_path, monkeypatch):
    import page_claims
    page = tmp_path / "chapters" / "99_test.md"
    page.parent.mkdir(parents=True)
    page.write_text("Intro.\nForget it and the picture is too dark. "
                    "<!-- claim 99-forgotten: darker -->\n")
    monkeypatch.setattr(page_claims, "PAGES", tmp_path)
    page_claims.check("99-forgotten", 0.7)  # darker, as the page says
    with pytest.raises(AssertionError, match=r"99_test\.md:2 says the picture comes out "
                                             r"darker.*1\.300"):
        page_claims.check("99-forgotten", 1.3)
    page.write_text("<!-- claim 99-forgotten: greener -->\n")
    with pytest.raises(AssertionError, match="greener"):
        page_claims.check("99-forgotten", 0.7)
    with pytest.raises(AssertionError, match="in 0 places"):
        page_claims.check("99-unknown", 0.7)


def test_the_instructors_catalogue_table_names_every_catalogued_variant():
    """The tables between the catalogue and diagnosis markers are written by ./course
    test --update-book from what the suite measured (tools/course_tools/cli/measured_pages.py);
    here the first must name exactly the variants of grading_catalogue, each in its
    chapter and kind, with a score a wrong variant may have (at most half) or a correct
    one (at least 90%) and the diagnosis the suite asks of it (nothing for a correct
    one, a wrong one itself, a held-out one the mistake it makes); the second, one row
    per catalogued chapter."""
    from course_tools.cli import measured_pages
    import grading_catalogue
    page = (ROOT / "book" / "docs" / "instructors.md").read_text()
    table = page.split(measured_pages.START, 1)[1].split(measured_pages.END, 1)[0]
    rows = re.findall(r"^\| (\w\w) \| (correct|wrong|held-out): (.+?) \| (\d+)% \| (.+?) \|$",
                      table, re.M)
    listed = {(chapter, kind, name) for chapter, kind, name, _, _ in rows}
    expected = {(number, "held-out" if v.held_out else "correct" if v.correct else "wrong",
                 v.name)
                for number, variants in grading_catalogue.CATALOGUE.items() for v in variants}
    assert len(rows) == len(listed)
    assert listed == expected, (sorted(expected - listed), sorted(listed - expected))
    unrecognisable = {v.name: number for number, variants in grading_catalogue.CATALOGUE.items()
                      for v in variants if not v.recognisable}
    for _, kind, name, score, diagnosed in rows:
        assert (int(score) >= 90) if kind == "correct" else (int(score) <= 50), name
        expected_diagnosis = {"correct": "nothing", "wrong": "itself",
                              "held-out": "the mistake it makes"}[kind]
        same_effect = f"{expected_diagnosis}, with "  # and mistakes of the same effect
        assert diagnosed == expected_diagnosis or kind != "correct" and \
            diagnosed.startswith(same_effect) and diagnosed.endswith("(the same effect)") or \
            name in unrecognisable and \
            diagnosed in ("itself", "nothing (a data race: not recognisable)"), (name, diagnosed)
    counts = page.split(measured_pages.DIAGNOSIS_START, 1)[1].split(
        measured_pages.DIAGNOSIS_END, 1)[0]
    chapters = re.findall(r"^\| (\w\w) \| (\d+) / (\d+) \| (\d+) / (\d+) \| 0 / \d+ \|",
                          counts, re.M)
    assert {c for c, *_ in chapters} == set(grading_catalogue.CATALOGUE)
    races = list(unrecognisable.values())
    assert all(int(b) - races.count(c) <= int(a) <= int(b) for c, a, b, _, _ in chapters)
    assert all(a == b for _, _, _, a, b in chapters)


def test_every_number_a_page_marks_is_recorded_by_a_check():
    """`<!-- number NAME -->` in a page (page_claims, tools/course_tools/cli/measured_pages.py) must be
    written by a check's page_claims.record call, its name literal or an f-string whose
    fields stand for any text; so ./course test --update-book can rewrite every one."""
    from course_tools.cli import measured_pages
    marked = {(name, page.name) for page in (ROOT / "book" / "docs").rglob("*.md")
              for name, _ in measured_pages.NUMBER.findall(page.read_text())}
    assert len(marked) >= 10
    # A line that starts with a marker would begin a raw HTML block, cutting its
    # paragraph or list item in two: markers stand inside or at the end of a line.
    for page in (ROOT / "book" / "docs").rglob("*.md"):
        for number, line in enumerate(page.read_text().splitlines(), 1):
            assert not re.match(r"\s*<!-- (number|claim) ", line), f"{page.name}:{number}"
    sources = "\n".join(p.read_text() for p in (ROOT / "tests" / "python").rglob("test_*.py"))
    patterns = [re.escape(re.sub(r"\{[^}]*\}", "\0", text)).replace("\0", ".+")
                for text in re.findall(r'page_claims\.record\(\s*f?"([^"]+)"', sources)]
    for name, page in sorted(marked):
        assert any(re.fullmatch(p, name) for p in patterns), \
            f"{page}: the number {name} is recorded by no check"


def test_update_book_writes_only_this_runs_numbers(tmp_path):
    from course_tools.cli import measured_pages
    pages, artifacts = tmp_path / "docs", tmp_path / "artifacts"
    pages.mkdir()
    page = pages / "page.md"
    page.write_text("Measured <!-- number a -->1.0<!-- /number --> and "
                    "<!-- number b -->2.0<!-- /number -->.\n")
    folder = measured_pages.numbers_folder(artifacts)
    folder.mkdir(parents=True)
    (folder / "a.txt").write_text("1.5\n")
    old = folder / "b.txt"
    old.write_text("9.9\n")
    import os
    os.utime(old, (1, 1))  # an earlier run's
    assert measured_pages.write_numbers(artifacts, since=100, pages=pages) == ["a"]
    assert page.read_text() == ("Measured <!-- number a -->1.5<!-- /number --> and "
                                "<!-- number b -->2.0<!-- /number -->.\n")
