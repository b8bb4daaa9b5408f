"""The built book in a real browser (Debian's Chromium, driven by Playwright): every
page loads without console errors, every image has loaded with a real size, every
internal link resolves, and the search finds a chapter by a word from its text."""

from __future__ import annotations

import functools
import http.server
import shutil
import threading
import urllib.error
import urllib.parse
import urllib.request
from pathlib import Path

import pytest

from conftest import ROOT

SITE = ROOT / "book" / "site"
ARTIFACTS = ROOT / "build" / "test-artifacts"
CHROMIUM = shutil.which("chromium") or "/usr/bin/chromium"
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
    from playwright.sync_api import sync_playwright
    with sync_playwright() as playwright:
        chromium = playwright.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        yield chromium
        chromium.close()


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
    for relative, name in [(".", "book_home.png"),
                           ("chapters/02_first_pixels", "book_chapter02.png")]:
        page.goto(urllib.parse.urljoin(site_url, "" if relative == "." else relative + "/"),
                  wait_until="load")
        page.screenshot(path=str(ARTIFACTS / name), full_page=False)
        assert (ARTIFACTS / name).stat().st_size > 10_000
