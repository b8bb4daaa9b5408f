"""The setup page's tables, written before every build from what ./course itself reads,
so the page cannot drift from it: the layers (which verbs set each up, and the Python
packages of requirements/<layer>.txt) and the platforms (tools/platforms.ini).

They go to docs/generated/layers.md and platforms.md (git-ignored, like the figures),
which setup.md pulls in with snippets; mkdocs.yml keeps docs/generated/*.md from
becoming pages."""

from __future__ import annotations

import html
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
from course_tools.cli.verbs import VERB_LAYERS  # which verb needs which layer
from course_tools.setup import platforms  # tools/course_tools/setup/platforms.py: standard library only

GENERATED = ROOT / "book" / "docs" / "generated"
REQUIREMENTS = ROOT / "requirements"


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


def pinned(layer: str) -> list[tuple[str, str]]:
    """(name, version) of each package requirements/<layer>.txt pins itself; a package
    pinned only for some platforms (an environment marker after ';') names them after
    its version."""
    found = []
    for line in (REQUIREMENTS / f"{layer}.txt").read_text().splitlines():
        match = re.match(r"\s*([A-Za-z0-9_.\-]+)==([^\s;]+)\s*(?:;(.*))?", line.split("#")[0])
        if match:
            where = [f"{system} {machine}" for system, machine in re.findall(
                r'sys_platform == "(\w+)" and platform_machine == "(\w+)"', match[3] or "")]
            only = f" (only {', '.join(where)})" if where else ""
            found.append((match[1], match[2] + only))
    return found


def layers_table() -> str:
    verbs = {layer: [f"`{verb}`" for verb, needs in VERB_LAYERS.items()
                     if needs == layer and verb != "setup"] for layer in platforms.LAYERS}
    lines = [
        "<!-- Written by book/hooks/setup_tables.py from tools/course_tools/cli/verbs.py, "
        "tools/course_tools/setup/platforms.py and requirements/: edit those. -->",
        "",
        "| layer | set up by `./course` | builds on | Python packages it adds |",
        "|---|---|---|---|",
    ]
    for layer in platforms.LAYERS:
        below = [f"`{part}`" for part in platforms.INCLUDES[layer] if part != layer]
        python = ", ".join(f"`{name}` {version}" for name, version in pinned(layer))
        lines.append(f"| `{layer}` | {', '.join(verbs[layer])} | {', '.join(below) or '—'} "
                     f"| {python or 'none'} |")
    return "\n".join(lines) + "\n"


def write(name: str, text: str):
    out = GENERATED / name
    out.parent.mkdir(parents=True, exist_ok=True)
    if not out.exists() or out.read_text() != text:  # `mkdocs serve` watches this folder
        out.write_text(text)


def on_pre_build(config):
    write("layers.md", layers_table())
    write("platforms.md", table(platforms.read_table()))
