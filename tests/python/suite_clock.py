"""The suite's clock, a pytest plugin (conftest.py loads it).

As the checks run it says on stderr where they are: checks done of how many, the file
at hand, the time so far and the time left, expected from the last run's durations
(build/test-artifacts/check-durations.json, updated at the end of each run that ran more
than a handful of checks). ./course test prints this run's slowest checks
(check-durations-this-run.json), so that drift shows in every log. Quiet when pytest
runs a single check."""

from __future__ import annotations

import json
import os
import sys
import time
from pathlib import Path

import pytest

from course_tools.cli.suite_parts import minutes

# COURSE_TEST_ARTIFACTS: another folder, for runs whose times are not the suite's
# (./course windows-check runs the Windows build's programs under Wine).
ARTIFACTS = Path(os.environ.get("COURSE_TEST_ARTIFACTS") or
                 Path(__file__).resolve().parents[2] / "build" / "test-artifacts")
DURATIONS = ARTIFACTS / "check-durations.json"  # every check's last time: the estimate
THIS_RUN = ARTIFACTS / "check-durations-this-run.json"  # this run's checks alone
EVERY_SECONDS = 30.0  # at most one progress line this often
SMALLEST_RUN_KEPT = 20  # a run of fewer checks leaves the last estimate as it was


def read_durations(path: Path = DURATIONS) -> dict[str, float]:
    try:
        return {k: float(v) for k, v in json.loads(path.read_text()).items()}
    except (OSError, ValueError, AttributeError):
        return {}


class SuiteClock:
    def __init__(self, workers: int = 1):
        self.workers = max(1, workers)  # pytest-xdist's: the checks left share them
        self.started = time.monotonic()
        self.last_said = self.started
        self.expected = read_durations()
        self.seconds: dict[str, float] = {}
        self.items: list[str] = []
        self.done: set[str] = set()

    def pytest_collection_finish(self, session):
        self.items = [item.nodeid for item in session.items]

    @pytest.hookimpl(optionalhook=True)
    def pytest_xdist_node_collection_finished(self, node, ids):
        """Spread over workers (pytest-xdist), the controller collects nothing itself:
        each worker says what it collected (all the same checks)."""
        self.items = list(ids)

    def pytest_runtest_logreport(self, report):
        name = report.nodeid
        self.seconds[name] = self.seconds.get(name, 0.0) + report.duration
        if report.when != "teardown":
            return
        self.done.add(name)
        now = time.monotonic()
        if len(self.items) > 1 and now - self.last_said >= EVERY_SECONDS:
            self.last_said = now
            self.say(report.nodeid.split("::")[0].rsplit("/", 1)[-1], now)

    def time_left(self) -> float | None:
        if not self.expected:
            return None
        known = [self.expected[n] for n in self.items if n in self.expected]
        typical = sorted(known)[len(known) // 2] if known else 0.0
        left = sum(self.expected.get(n, typical) for n in self.items if n not in self.done)
        return left / self.workers

    def say(self, where: str, now: float):
        left = self.time_left()
        estimate = f", about {minutes(left)} left" if left is not None else ""
        print(f"course: pytest {len(self.done)}/{len(self.items)} checks ({where}), "
              f"{minutes(now - self.started)} elapsed{estimate}", file=sys.__stderr__,
              flush=True)

    def pytest_sessionfinish(self, session):
        ARTIFACTS.mkdir(parents=True, exist_ok=True)
        this_run = {k: round(v, 3) for k, v in self.seconds.items()}
        write_json(THIS_RUN, this_run)
        if len(this_run) >= SMALLEST_RUN_KEPT:
            write_json(DURATIONS, {**self.expected, **this_run})


def write_json(path: Path, value: dict):
    partial = path.with_name(f".{path.name}.{os.getpid()}")
    partial.write_text(json.dumps(value, indent=0, sort_keys=True))
    partial.replace(path)


def pytest_configure(config):
    if hasattr(config, "workerinput"):
        return  # a pytest-xdist worker: the controller keeps the clock
    workers = config.getoption("numprocesses", None) if config.pluginmanager.hasplugin(
        "xdist") else None
    config.pluginmanager.register(SuiteClock(workers if isinstance(workers, int) else 1),
                                  "suite_clock_instance")
