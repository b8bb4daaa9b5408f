"""The built book in a real browser (the Chromium tools/platforms.ini names for this
platform, or Playwright's own, driven by Playwright): every page loads without console
errors, every image has loaded with a real size, every internal link resolves, no page
shows a formula as TeX, formulas are drawn as MathML, and the search finds a chapter by
a word from its text."""

from __future__ import annotations

import functools
import http.server
import threading
import urllib.error
import urllib.parse
import urllib.request

import pytest

from conftest import ROOT

from course_tools.setup import machine_setup

SITE = ROOT / "book" / "site"
ARTIFACTS = ROOT / "build" / "test-artifacts"
# Chromium on a closed network: no background services that would call home.
CHROMIUM_ARGS = ["--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                 "--disable-background-networking", "--disable-component-update",
                 "--disable-sync"]


class QuietHandler(http.server.SimpleHTTPRequestHandler):
    def log_message(self, *args):
        pass


@pytest.fixture(scope="module")
def site_url(built_book):
    handler = functools.partial(QuietHandler, directory=str(SITE))
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    yield f"http://127.0.0.1:{server.server_address[1]}/"
    server.shutdown()


@pytest.fixture(scope="module")
def browser():
    """The platform's Chromium (a path), or Playwright's own where the table says so
    (None: Ubuntu, whose Chromium is a snap). No browser is a failure, never a skip."""
    from playwright.sync_api import sync_playwright
    executable = machine_setup.browser_executable()
    which = executable or "Playwright's own Chromium (python -m playwright install chromium)"
    with sync_playwright() as playwright:
        try:
            chromium = playwright.chromium.launch(executable_path=executable,
                                                  args=CHROMIUM_ARGS)
        except Exception as error:  # Playwright's Error: no such file, no browser, ...
            pytest.fail(f"cannot launch {which} for the book's browser check "
                        f"(./course setup test installs it): {error}", pytrace=False)
        yield chromium
        chromium.close()


# What a formula looks like when nothing typeset it (arithmatex's output, or the source).
TEX_DELIMITERS = ["\\(", "\\[", "$$"]


def pages() -> list[str]:
    return sorted(str(p.relative_to(SITE).parent) for p in SITE.rglob("index.html")
                  if "assets" not in p.parts and "search" not in p.parts)


def test_every_page_loads_cleanly_with_its_images_and_links(site_url, browser):
    page = browser.new_page()
    problems, checked_links = [], set()
    page.on("console", lambda m: problems.append(f"console {m.type}: {m.text}")
            if m.type == "error" else None)
    page.on("pageerror", lambda e: problems.append(f"page error: {e}"))
    for relative in pages():
        url = urllib.parse.urljoin(site_url, "" if relative == "." else relative + "/")
        response = page.goto(url, wait_until="load")
        assert response and response.ok, url
        images = page.eval_on_selector_all(
            "article img", "els => els.map(e => [e.src, e.complete, e.naturalWidth])")
        for source, complete, width in images:
            assert complete and width > 0, f"{url}: image {source} did not load"
        text = page.inner_text("body")  # what a reader sees, code listings included
        for tex in TEX_DELIMITERS:
            if tex in text:
                at = text.index(tex)
                problems.append(f"{url}: a formula shown as TeX: ...{text[at - 40:at + 60]}...")
        links = page.eval_on_selector_all("a[href]", "els => els.map(e => e.href)")
        for link in links:
            target = link.split("#")[0]
            if not target.startswith(site_url) or target in checked_links:
                continue
            checked_links.add(target)
            try:
                urllib.request.urlopen(target).close()
            except urllib.error.HTTPError as error:
                problems.append(f"{url}: broken link {link} ({error.code})")
    assert not problems, "\n".join(problems)
    assert len(pages()) >= 5


def test_formulas_are_drawn_as_mathml(site_url, browser):
    """Chapter 11's rendering equation is a display formula that Chromium lays out
    itself: a <math display="block"> with an integral and subscripts, as tall as a
    formula and not a line of TeX; chapter 06's fractions have two parts, one above
    the other."""
    page = browser.new_page()
    page.goto(urllib.parse.urljoin(site_url, "chapters/11_path_tracing/"), wait_until="load")
    formulas = page.eval_on_selector_all(
        "article math", "els => els.map(e => [e.getAttribute('display'), "
        "e.getBoundingClientRect().width, e.getBoundingClientRect().height, e.textContent])")
    assert len(formulas) >= 5, formulas
    display = [f for f in formulas if f[0] == "block"]
    assert display, "no display formula on chapter 11's page"
    _, width, height, text = display[0]
    assert "∫" in text and "ω" in text and "\\" not in text, text
    assert width > 200 and height > 10, (width, height)
    assert page.locator("article math msub").count() >= 5  # L_o, ω_i, ...

    page.goto(urllib.parse.urljoin(site_url, "chapters/06_triangles/"), wait_until="load")
    fractions = page.eval_on_selector_all(
        "article mfrac", "els => els.map(e => [...e.children].map("
        "c => c.getBoundingClientRect().top))")
    assert len(fractions) == 3, fractions
    for numerator_top, denominator_top in fractions:
        assert denominator_top > numerator_top + 5, "a fraction not drawn as one"


def test_search_finds_a_chapter_by_a_word_from_its_text(site_url, browser):
    page = browser.new_page()
    page.goto(site_url, wait_until="load")
    page.keyboard.press("/")  # Material's shortcut: focus the search box
    page.keyboard.type("bounds check", delay=20)
    page.wait_for_selector(".md-search-result__item", timeout=15000)
    results = page.inner_text(".md-search-result")
    assert "matching document" in results
    assert "Buffer add" in results  # chapter 01 explains the bounds check


def test_screenshots_for_the_record(site_url, browser):
    ARTIFACTS.mkdir(parents=True, exist_ok=True)
    page = browser.new_page(viewport={"width": 1280, "height": 900})
    for relative, name, anchor in [
            (".", "book_home.png", None),
            ("chapters/02_first_pixels", "book_chapter02.png", None),
            ("chapters/11_path_tracing", "book_chapter10_formula.png",
             "the-rendering-equation-and-how-to-estimate-it"),
            ("setup", "book_setup_platforms.png", "what-each-platform-installs")]:
        page.goto(urllib.parse.urljoin(site_url, "" if relative == "." else relative + "/")
                  + (f"#{anchor}" if anchor else ""), wait_until="load")
        page.screenshot(path=str(ARTIFACTS / name), full_page=False)
        assert (ARTIFACTS / name).stat().st_size > 10_000
