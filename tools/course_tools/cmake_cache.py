"""What a CMake build folder was configured with."""

from __future__ import annotations

import re
from pathlib import Path

ENTRY = re.compile(r"^(\w+):\w+=(.*)$", flags=re.M)  # NAME:TYPE=value


def options(build_dir: Path) -> dict[str, str]:
    """NAME -> value of the CMake cache in build_dir (empty before the first configure)."""
    cache = build_dir / "CMakeCache.txt"
    return dict(ENTRY.findall(cache.read_text())) if cache.exists() else {}
