"""Which of the course's own Python files a file imports, read from its text (nothing
is imported to find out): what a starter must ship with a chapter's tests, and what a
kept Mitsuba render or book figure depends on."""

from __future__ import annotations

import re
from pathlib import Path


def imported_modules(test_file: Path, folders: list[Path]) -> set[Path]:
    """The modules under `folders` that a Python file imports (a chapter's tests, a
    figure script), and what those import in turn: `import a.b`, `from a.b import c` (a.b, or the module a/b/c.py) resolved
    against each folder (the repository's root for python_prototypes' modules, the
    tests' own folder for their helpers), with the packages' __init__.py."""
    wanted, queue = set(), [test_file]
    while queue:
        text = queue.pop().read_text()
        names = []
        for module, what in re.findall(r"^[ \t]*from[ \t]+([\w.]+)[ \t]+import[ \t]+"
                                       r"(\([^)]*\)|[^\n#]*)", text, flags=re.M):
            names += [module] + [f"{module}.{word}" for word in re.findall(r"\w+", what)]
        names += re.findall(r"^[ \t]*import[ \t]+([\w.]+)", text, flags=re.M)
        for module in names:
            for folder in folders:
                candidate = folder / (module.replace(".", "/") + ".py")
                if candidate.exists() and candidate not in wanted:
                    wanted.add(candidate)
                    queue.append(candidate)
                    package_init = candidate.parent / "__init__.py"
                    if package_init.exists():
                        wanted.add(package_init)
    return wanted
