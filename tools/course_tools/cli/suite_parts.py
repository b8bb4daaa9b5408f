"""Where ./course test spends its time: each part (build, ctest, pytest, fuzzing, the
sanitizers) timed as it runs, said as it starts (with the time expected from the last
whole run), and a table at the end with the slowest checks, so that drift shows in
every log. The last whole run's parts are kept in build/test-artifacts/suite-parts.json;
the slowest checks come from the pytest plugin's check-durations.json
(tests/python/suite_clock.py)."""

from __future__ import annotations

import json
import os
import re
import sys
import time
from contextlib import contextmanager
from pathlib import Path

BUDGET_SECONDS = 15 * 60  # the whole suite on 2 cores (book/docs/maintainers.md)


def minutes(seconds: float) -> str:
    seconds = max(0, int(round(seconds)))
    return f"{seconds // 60}:{seconds % 60:02d}"


def this_run_durations(artifacts: Path) -> dict[str, float]:
    """Each check of the last pytest run and its seconds (written by the plugin)."""
    try:
        return json.loads((artifacts / "check-durations-this-run.json").read_text())
    except (OSError, ValueError):
        return {}


CHAPTER_SHARE_SECONDS = 60  # a chapter's own checks, ./course test NN once built

# Where a check id names a chapter: its file (test_13_bvh.py), a catalogue variant
# ([13-correct-...]) or a chapter parameter ([16_glass], [A2_gl33_fragment]).
CHAPTER_PATTERNS = (re.compile(r"(?:^|/)test_(\d\d|A\d)_"),
                    re.compile(r"\[(\d\d|A\d)-(?:correct|wrong)-"),
                    re.compile(r"\[(\d\d|A\d)_[a-z]"))


def chapter_of(check: str) -> tuple[str, str] | None:
    """(chapter, "own" for its test file or "grading" for its gradings, starter and
    catalogue elsewhere), or None for a check that is no one chapter's."""
    for number, pattern in enumerate(CHAPTER_PATTERNS):
        match = pattern.search(check)
        if match:
            return match.group(1), "own" if number == 0 else "grading"
    return None


def chapter_shares(durations: dict[str, float]) -> str:
    """Each chapter's share of the checks' time (summed over the workers): its own
    checks (test_NN_*.py, what ./course test NN runs) and the rest that names it
    (gradings, catalogue, starter), against the 60 s a chapter's own checks may take."""
    shares: dict[str, dict[str, float]] = {}
    shared = 0.0
    for check, seconds in durations.items():
        found = chapter_of(check)
        if found is None:
            shared += seconds
            continue
        chapter, kind = found
        shares.setdefault(chapter, {"own": 0.0, "grading": 0.0})[kind] += seconds
    if not shares:
        return ""
    lines = ["", "each chapter's share of the checks' time (over all workers):",
             f"  {'chapter':8} {'own checks':>10} {'gradings etc.':>14}"]
    for chapter in sorted(shares):
        own, grading = shares[chapter]["own"], shares[chapter]["grading"]
        over = "  over its 60 s" if own > CHAPTER_SHARE_SECONDS else ""
        lines.append(f"  {chapter:8} {minutes(own):>10} {minutes(grading):>14}{over}")
    lines.append(f"  {'no one chapter':23} {minutes(shared):>10}")
    return "\n".join(lines)


class SuiteParts:
    def __init__(self, artifacts: Path, names: list[str]):
        self.artifacts = artifacts
        self.names = names  # every part this run will go through, in order
        self.started = time.monotonic()
        self.seconds: dict[str, float] = {}
        try:
            self.last = json.loads((artifacts / "suite-parts.json").read_text())["parts"]
        except (OSError, ValueError, KeyError, TypeError):
            self.last = {}

    @contextmanager
    def part(self, name: str):
        index = self.names.index(name) + 1 if name in self.names else len(self.seconds) + 1
        expected = ""
        if self.last and all(n in self.last for n in self.names):
            total = sum(self.last[n] for n in self.names)
            expected = f"; the last whole run took {minutes(total)}"
        print(f"course: part {index} of {len(self.names)}: {name} "
              f"({minutes(time.monotonic() - self.started)} elapsed{expected})",
              file=sys.stderr, flush=True)
        began = time.monotonic()
        try:
            yield
        finally:
            self.seconds[name] = self.seconds.get(name, 0.0) + time.monotonic() - began

    def report(self, slowest_checks: dict[str, float], count: int = 15,
               whole: bool = True) -> str:
        """The table: each part's time and share, the total against the budget, then the
        `count` slowest checks. A whole run's parts are kept for the next estimate."""
        total = time.monotonic() - self.started
        lines = ["", "where the time went:", f"  {'part':42} {'time':>7} {'share':>6}"]
        for name, seconds in self.seconds.items():
            lines.append(f"  {name:42} {minutes(seconds):>7} {seconds / total:6.0%}")
        lines.append(f"  {'in all':42} {minutes(total):>7}"
                     + (f"   (budget {minutes(BUDGET_SECONDS)} on 2 cores)" if whole else ""))
        if slowest_checks:
            lines += ["", f"the {count} slowest checks (setup, call and teardown):"]
            ranked = sorted(slowest_checks.items(), key=lambda item: -item[1])[:count]
            lines += [f"  {minutes(seconds):>6}  {name}" for name, seconds in ranked]
            if whole:
                lines.append(chapter_shares(slowest_checks))
        if whole:
            self.artifacts.mkdir(parents=True, exist_ok=True)
            kept = {"parts": {n: round(s, 1) for n, s in self.seconds.items()},
                    "total": round(total, 1), "cores": os.cpu_count()}
            partial = self.artifacts / f".suite-parts.json.{os.getpid()}"
            partial.write_text(json.dumps(kept, indent=2))
            partial.replace(self.artifacts / "suite-parts.json")
        return "\n".join(lines)
