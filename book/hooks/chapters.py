"""The book's list of chapters, from the chapters' manifests (manifests/NN_name.ini,
tools/course_tools/manifests.py): the navigation's Chapters and Appendices sections, and the list
on the front page where index.md says <!-- chapters -->. Adding a chapter is its
folders, its manifest and its add_chapter() line; nothing here or in mkdocs.yml."""

from __future__ import annotations

from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
from course_tools import chapters  # the add_chapter() lines of CMakeLists.txt
from course_tools import manifests

MARKER = "<!-- chapters -->"


def chapter_manifests() -> dict[str, manifests.Manifest]:
    return manifests.load(ROOT, chapters.names())


def on_config(config, **kwargs):
    found = chapter_manifests()
    sections = {
        "Chapters": [{f"{m.number} {m.title}": f"chapters/{name}.md"}
                     for name, m in found.items() if m.number.isdigit()],
        "Appendices": [{f"{m.number} {m.title}": f"chapters/{name}.md"}
                       for name, m in found.items() if not m.number.isdigit()],
    }
    for entry in config["nav"]:
        if isinstance(entry, dict):
            for title in entry:
                if title in sections:
                    entry[title] = sections[title]
    return config


def chapter_list() -> str:
    found = chapter_manifests().items()
    lines = [f"{int(m.number)}. [{m.title}](chapters/{name}.md): {m.summary}"
             for name, m in found if m.number.isdigit()]
    lines.append("")
    lines += [f"Appendix {m.number}, [{m.title}](chapters/{name}.md): {m.summary}"
              for name, m in found if not m.number.isdigit()]
    return "\n".join(lines)


def on_page_markdown(markdown, page, **kwargs):
    if MARKER in markdown:
        markdown = markdown.replace(MARKER, chapter_list())
    return markdown
