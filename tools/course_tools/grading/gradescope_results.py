"""Checks a results.json against Gradescope's autograder format, as its documentation
("Autograder Specifications: Output format") describes it: a top-level score or
per-test scores, and per test a name, score, max_score, output and visibility from
Gradescope's four values. Standard library only (the fresh-machine check runs it).

    python3 tools/course_tools/grading/gradescope_results.py results.json [--expect-fraction-at-least F]
                                                     [--expect-fraction-at-most F]
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path

VISIBILITIES = {"hidden", "after_due_date", "after_published", "visible"}
OUTPUT_FORMATS = {"text", "html", "simple_format", "md", "ansi"}
TOP_LEVEL = {"score", "execution_time", "output", "output_format", "test_output_format",
             "test_name_format", "visibility", "stdout_visibility", "extra_data", "tests",
             "leaderboard"}
PER_TEST = {"score", "max_score", "status", "name", "name_format", "number", "output",
            "output_format", "tags", "visibility", "extra_data"}


def is_number(value) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool) and \
        math.isfinite(value)


def problems(results) -> list[str]:
    """Everything in `results` that Gradescope would reject or misread; empty if none."""
    found = []
    if not isinstance(results, dict):
        return ["the top level is not an object"]
    found += [f"unknown top-level key '{k}'" for k in results if k not in TOP_LEVEL]
    tests = results.get("tests")
    if "score" not in results and not tests:
        found.append("neither a top-level score nor tests")
    if "score" in results and not is_number(results["score"]):
        found.append("score is not a finite number")
    for key in ("visibility", "stdout_visibility"):
        if key in results and results[key] not in VISIBILITIES:
            found.append(f"{key} '{results[key]}' is not one of {sorted(VISIBILITIES)}")
    for key in ("output_format", "test_output_format", "test_name_format"):
        if key in results and results[key] not in OUTPUT_FORMATS:
            found.append(f"{key} '{results[key]}' is not one of {sorted(OUTPUT_FORMATS)}")
    if tests is None:
        return found
    if not isinstance(tests, list):
        return found + ["tests is not a list"]
    for index, test in enumerate(tests):
        where = f"tests[{index}]"
        if not isinstance(test, dict):
            found.append(f"{where} is not an object")
            continue
        found += [f"{where}: unknown key '{k}'" for k in test if k not in PER_TEST]
        for key in ("name", "output"):
            if not isinstance(test.get(key), str):
                found.append(f"{where}: {key} is missing or not text")
        for key in ("score", "max_score"):
            if not is_number(test.get(key)):
                found.append(f"{where}: {key} is missing or not a finite number")
        if is_number(test.get("score")) and is_number(test.get("max_score")) and \
                not 0 <= test["score"] <= test["max_score"]:
            found.append(f"{where}: score {test['score']} outside 0..{test['max_score']}")
        if test.get("visibility", "visible") not in VISIBILITIES:
            found.append(f"{where}: visibility '{test['visibility']}' is not one of "
                         f"{sorted(VISIBILITIES)}")
        if "status" in test and test["status"] not in ("passed", "failed"):
            found.append(f"{where}: status '{test['status']}' is not passed or failed")
    if is_number(results.get("score")) and all(
            isinstance(t, dict) and is_number(t.get("score")) for t in tests):
        total = sum(t["score"] for t in tests)
        if abs(total - results["score"]) > 0.011:
            found.append(f"score {results['score']} is not the sum of the tests' {total}")
    return found


def fraction(results: dict) -> float:
    """The score as a fraction of the maximum."""
    most = sum(t["max_score"] for t in results["tests"])
    return results["score"] / most if most else 0.0


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("results", type=Path)
    parser.add_argument("--expect-fraction-at-least", type=float)
    parser.add_argument("--expect-fraction-at-most", type=float)
    args = parser.parse_args()
    try:
        results = json.loads(args.results.read_text())
    except (OSError, ValueError) as error:
        print(f"{args.results}: {error}", file=sys.stderr)
        return 3
    found = problems(results)
    for problem in found:
        print(f"{args.results}: {problem}", file=sys.stderr)
    if found:
        return 1
    share = fraction(results)
    print(f"{args.results}: valid; score {results['score']} ({share:.0%})")
    if args.expect_fraction_at_least is not None and share < args.expect_fraction_at_least:
        print(f"{args.results}: expected at least {args.expect_fraction_at_least:.0%}",
              file=sys.stderr)
        return 1
    if args.expect_fraction_at_most is not None and share > args.expect_fraction_at_most:
        print(f"{args.results}: expected at most {args.expect_fraction_at_most:.0%}",
              file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
