"""The setup page's table of platforms and packages, written from tools/platforms.ini (the
table ./course installs from) before every build, so the page cannot drift from it.

It goes to docs/generated/platforms.md (git-ignored, like the figures), which setup.md
pulls in with a snippet; mkdocs.yml keeps docs/generated/*.md from becoming pages."""

from __future__ import annotations

import html
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools"))
import platforms  # noqa: E402  (tools/platforms.py: standard library only)

OUT = ROOT / "book" / "docs" / "generated" / "platforms.md"


def cell(text: str) -> str:
    return html.escape(text, quote=False).replace("|", "&#124;")


def packages(names: list[str]) -> str:
    return " ".join(f"`{name}`" for name in names) or "nothing"


def browser(platform: platforms.Platform) -> str:
    if platform.browser == "playwright":
        return "Playwright's own"
    return f"`{platform.browser}`" if platform.browser else "none named"


def table(rows: dict[str, platforms.Platform]) -> str:
    """One row per platform and layer that installs something; a sentence for the layers
    that install nothing anywhere (their additions are Python packages only)."""
    used = [layer for layer in platforms.LAYERS
            if any(platform.packages[layer] for platform in rows.values())]
    unused = [f"`{layer}`" for layer in platforms.LAYERS if layer not in used]
    lines = [
        "<!-- Written by book/hooks/setup_tables.py from tools/platforms.ini: edit that. -->",
        "",
        "| platform | layer | adds these packages |",
        "|---|---|---|",
    ]
    for platform in rows.values():
        first = True
        for layer in used:
            if platform.packages[layer]:
                name = cell(platform.name) if first else ""
                lines.append(f"| {name} | `{layer}` | {packages(platform.packages[layer])} |")
                first = False
    if unused:
        lines += ["", f"The {' and '.join(unused)} layers add no distribution packages on any "
                  "platform: what they add is Python packages."]
    lines += [
        "",
        "For the checks, each platform also names the Chromium that drives the book's "
        "browser test (Playwright's own where the distribution's is a snap or there is "
        "none) and the libLLVM that Mitsuba's `llvm_*` variants load (without one, its "
        "scalar variant runs), and says how the row was last checked:",
        "",
        "| platform | browser | libLLVM for Mitsuba | tested |",
        "|---|---|---|---|",
    ]
    for platform in rows.values():
        libllvm = f"`{platform.libllvm}`" if platform.libllvm else "none: scalar only"
        lines.append(f"| {cell(platform.name)} | {browser(platform)} | {libllvm} | "
                     f"{cell(platform.tested)} |")
    return "\n".join(lines) + "\n"


def on_pre_build(config):
    text = table(platforms.read_table())
    OUT.parent.mkdir(parents=True, exist_ok=True)
    if not OUT.exists() or OUT.read_text() != text:  # `mkdocs serve` watches this folder
        OUT.write_text(text)
