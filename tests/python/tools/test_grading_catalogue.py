"""The grading catalogue (grading_catalogue/) against the solution and the book: every
catalogued submission's edits still apply to the solution's code, every catalogued
mistake is explained with a heading its chapter's page really has (and links to it by
the id MkDocs gives that heading), and every held-out variant names a catalogued
mistake of its chapter. Fast: no build, no render."""

import re

import pytest
from conftest import ROOT
from markdown.extensions.toc import slugify

import grading_catalogue

CHAPTERS = sorted(grading_catalogue.CATALOGUE)
LONGEST_EXPLANATION = 110  # characters: one line of the grader's report


def page_of(chapter: str):
    pages = sorted((ROOT / "book" / "docs" / "chapters").glob(f"{chapter}_*.md"))
    assert len(pages) == 1, f"chapter {chapter}: book pages {pages}"
    return pages[0]


def headings(chapter: str) -> list[str]:
    """The text of every heading of the chapter's page (outside fenced code), without
    its #'s, a closing run of #'s or an attribute list ({: #id })."""
    found, fence = [], None
    for line in page_of(chapter).read_text().splitlines():
        stripped = line.lstrip()
        marker = re.match(r"(`{3,}|~{3,})", stripped)
        if marker:
            if fence is None:
                fence = marker.group(1)[0]
            elif stripped.startswith(fence * 3):
                fence = None
            continue
        if fence is None and line.startswith("#"):
            text = re.sub(r"^#+\s*", "", line)
            text = re.sub(r"\s*\{[^}]*\}\s*$", "", text)
            found.append(re.sub(r"\s+#+\s*$", "", text).strip())
    return found


def mistakes(chapter: str) -> list:
    return [v for v in grading_catalogue.CATALOGUE[chapter] if not v.correct]


@pytest.mark.parametrize("chapter", CHAPTERS)
def test_every_variant_applies_to_the_solution(chapter, tmp_path):
    """apply() asserts that each edit finds its text exactly `count` times and changes
    the file: a catalogue that drifted from the solution fails here, not by grading the
    solution again under a wrong name."""
    variants = grading_catalogue.CATALOGUE[chapter]
    names = [v.name for v in variants]
    assert len(names) == len(set(names)), f"chapter {chapter}: a name used twice"
    for index, variant in enumerate(variants):
        assert variant.chapter.split("_")[0] == chapter, variant.name
        assert variant.correct or variant.edits, f"{variant.name}: the solution itself"
        submission = grading_catalogue.apply(variant, ROOT, tmp_path / str(index))
        for top in ("chapters", "shaders"):
            assert (submission / top / variant.chapter).is_dir(), variant.name


@pytest.mark.parametrize("chapter", CHAPTERS)
def test_every_mistake_is_explained_with_a_heading_of_its_page(chapter):
    anchors = {grading_catalogue.heading_anchor(text): text for text in headings(chapter)}
    for variant in grading_catalogue.CATALOGUE[chapter]:
        if variant.correct:
            assert not (variant.explanation or variant.section or variant.held_out
                        or variant.same_effect), f"{variant.name}: correct, yet explained"
            continue
        explanation = variant.explanation
        assert explanation.strip(), f"{variant.name}: no explanation"
        assert "\n" not in explanation, f"{variant.name}: more than one line"
        assert len(explanation) <= LONGEST_EXPLANATION, \
            f"{variant.name}: {len(explanation)} characters"
        assert variant.section, f"{variant.name}: no section"
        assert variant.anchor in anchors, \
            f"{variant.name}: {page_of(chapter).name} has no heading {variant.section!r}"
        assert variant.section == anchors[variant.anchor], \
            f"{variant.name}: the heading reads {anchors[variant.anchor]!r}"


# Headings of the book with non-ASCII text and punctuation, besides those the catalogue
# names today.
AWKWARD_HEADINGS = {
    "Radiance, and why a white wall is albedo/π",
    "Beer–Lambert",
    "Why refracted radiance is scaled by 1/η²",
    "A2 · The path tracer on OpenGL 3.3 (macOS)",
}


@pytest.mark.parametrize("section", sorted(
    {v.section for vs in grading_catalogue.CATALOGUE.values() for v in vs if v.section}
    | AWKWARD_HEADINGS))
def test_heading_anchor_is_python_markdowns_slugify(section):
    """The link's fragment must be the id the book's MkDocs gives the heading: the toc
    extension's slugify, which mkdocs.yml uses."""
    assert grading_catalogue.heading_anchor(section) == slugify(section, "-")


@pytest.mark.parametrize("chapter", CHAPTERS)
def test_held_out_variants_name_a_catalogued_mistake_of_their_chapter(chapter):
    catalogued = {v.name for v in mistakes(chapter) if not v.held_out}
    for variant in grading_catalogue.CATALOGUE[chapter]:
        if variant.held_out:
            assert not variant.correct, f"{variant.name}: held out, yet correct"
            assert variant.held_out in catalogued, \
                f"{variant.name}: {variant.held_out!r} is no catalogued mistake of {chapter}"
            assert variant.held_out != variant.name
            original = next(v for v in mistakes(chapter) if v.name == variant.held_out)
            assert variant.edits != original.edits, \
                f"{variant.name}: the same edits as {original.name!r}, not written differently"
        if variant.same_effect:
            assert variant.same_effect in catalogued and variant.same_effect != variant.name, \
                f"{variant.name}: same_effect {variant.same_effect!r}"
