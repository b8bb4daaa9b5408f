"""Reading what a course program printed. Standard library only.

A chapter run with --json (and the grader) prints its statistics as one JSON object on
its last line of standard output, after whatever it logged before."""

from __future__ import annotations

import json


def last_json_line(stdout: str, program: str = "the program") -> dict:
    """The JSON object on the last non-empty line of `stdout`. A program that printed
    none is a ValueError naming it and showing the end of what it did print."""
    lines = stdout.strip().splitlines()
    try:
        printed = json.loads(lines[-1]) if lines else None
    except json.JSONDecodeError:
        printed = None
    if not isinstance(printed, dict):
        raise ValueError(f"{program} printed no JSON statistics on its last line; its "
                         f"output ended with: {stdout[-300:]!r}")
    return printed
