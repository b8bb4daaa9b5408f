"""The autograder: the solution scores full marks, the starter nearly nothing, a planted
bug loses exactly the tests it should, and broken submissions (not compiling, crashing,
hanging, flooding the output) fail cleanly while the grader stays healthy."""

import csv
import json
import os
import shutil
import subprocess
import sys

import pytest

from conftest import ROOT

from course_tools.editions import classroom
from course_tools.grading import grader, grading_specs
import grading_catalogue

COURSE = [sys.executable, str(ROOT / "tools" / "course.py")]
# Tight limits for the submissions that are meant to hang: the grader must kill them.
FAST_LIMITS = {"COURSE_GRADE_WALL_SECONDS": "5", "COURSE_GRADE_CPU_SECONDS": "3"}


def solution_copy(chapter, destination):
    for top in ("chapters", "shaders"):
        shutil.copytree(ROOT / top / chapter, destination / top / chapter)
    return destination


def grade(chapter, submission, out, limits=None, keep_runs=False):
    """Grades with the real limits, or tighter ones (for submissions meant to time out).
    keep_runs: replay the runs of an earlier grading of the same files (the starters and
    solutions, graded on every run of the suite: grader.KeptRuns)."""
    env = dict(os.environ, **(limits or {}))
    result = subprocess.run([*COURSE, "grade", chapter[:2], "--submission", str(submission),
                             "--out", str(out), *(["--keep-runs"] if keep_runs else [])],
                            capture_output=True, text=True, env=env, timeout=600)
    assert result.returncode == 0, result.stderr[-2000:]
    results = json.loads((out / "results.json").read_text())
    return results, {t["name"]: t for t in results["tests"]}


def total(results):
    return sum(t["max_score"] for t in results["tests"])


GRADED = sorted(p.name for p in (ROOT / "chapters").iterdir() if p.name[:2] in
                grading_specs.SPECS)


# The chapters graded by statistics grade their solution, unchanged, with their
# catalogue of variants (test_grading_statistics.py: "the solution as it is" must score
# full marks there): the same grading, done once.
WITH_CATALOGUE = set(grading_catalogue.CATALOGUE)


def test_references_a_changed_solution_made_are_made_again():
    # build/grading/NN's files name only their arguments. After a scene file or the
    # solution changes (reference_maker), the old references must not stand: a correct
    # submission, run on the new scene, would fail against them.
    chapter, build = "02_first_pixels", ROOT / "build"
    grader.prepare_references(ROOT, build, chapter)
    folder = build / "grading" / chapter
    references = sorted(folder.glob("*.png")) + sorted(folder.glob("*.pfm"))
    assert references, "chapter 02 has reference images"
    made = references[0].read_bytes()
    (folder / "made-by").write_text("a solution that has changed since")
    references[0].write_bytes(b"a picture of the old solution's")
    grader.prepare_references(ROOT, build, chapter)
    assert references[0].read_bytes() == made
    assert (folder / "made-by").read_text() == grader.reference_maker(ROOT, build, chapter)


@pytest.mark.parametrize("chapter", GRADED)
def test_solution_full_marks_and_starter_near_zero(tmp_path, chapter):
    # The starter first, with no reference images kept yet: the references must come
    # from the solution's shaders, never from the submission being graded.
    shutil.rmtree(ROOT / "build" / "grading" / chapter, ignore_errors=True)
    starter = classroom.release(ROOT, chapter, tmp_path / "starter")
    results, tests = grade(chapter, starter, tmp_path / "g2", keep_runs=True)
    assert results["score"] <= 0.1 * total(results), tests
    if chapter[:2] in WITH_CATALOGUE:
        return  # the solution's full marks: test_grading_statistics.py
    results, tests = grade(chapter, solution_copy(chapter, tmp_path / "solution"),
                           tmp_path / "g1", keep_runs=True)
    assert results["score"] == total(results), tests


def test_results_json_is_gradescope_shaped_and_report_has_images(tmp_path):
    results, _ = grade("02", solution_copy("02_first_pixels", tmp_path / "s"), tmp_path / "g")
    assert set(results) >= {"score", "tests", "output"}
    for test in results["tests"]:
        assert set(test) >= {"name", "score", "max_score", "output", "visibility"}
        assert test["visibility"] in ("visible", "hidden", "after_due_date", "after_published")
    assert any(t["visibility"] == "after_due_date" for t in results["tests"])
    report = (tmp_path / "g" / "report.md").read_text()
    assert "pattern_1d_dispatch_error.png" in report
    assert (tmp_path / "g" / "pattern_1d_dispatch_error.png").stat().st_size > 100


def test_planted_bug_loses_exactly_the_1d_tests(tmp_path):
    submission = solution_copy("02_first_pixels", tmp_path / "buggy")
    shader = submission / "shaders" / "02_first_pixels" / "pattern_1d.comp"
    text = shader.read_text()
    shader.write_text(text.replace("uvec2(index % imageSize.x, index / imageSize.x)",
                                   "uvec2(index / imageSize.x, index % imageSize.x)"))
    results, tests = grade("02", submission, tmp_path / "g")
    assert tests["pattern, 2D dispatch"]["score"] == tests["pattern, 2D dispatch"]["max_score"]
    assert tests["pattern, 1D dispatch"]["score"] == 0
    assert tests["odd size, 1D dispatch"]["score"] == 0


def test_nearest_hit_bug_loses_exactly_the_overlap_tests(tmp_path):
    """Chapter 04 with the classic bug (the first sphere hit wins): a single sphere and
    the distant view are still (almost) right; the close-up of the overlap is not."""
    submission = solution_copy("04_spheres", tmp_path / "buggy")
    scene = submission / "shaders" / "04_spheres" / "scene.glsl"
    text = scene.read_text()
    assert "if (firstHitOnly) break;" in text
    scene.write_text(text.replace("if (firstHitOnly) break;", "break;"))
    results, tests = grade("04", submission, tmp_path / "g")
    assert tests["one sphere"]["score"] == tests["one sphere"]["max_score"]
    assert tests["overlapping spheres, close up"]["score"] == 0
    # From afar the overlap covers about 1.4% of the picture: a near miss, half marks.
    assert tests["four spheres"]["score"] == tests["four spheres"]["max_score"] / 2


def break_main(submission, chapter, code):
    main = submission / "chapters" / chapter / "main.cpp"
    text = main.read_text()
    main.write_text(text.replace("return course::run(", code + "\n    return course::run(", 1))


@pytest.mark.parametrize("kind,code,message", [
    ("not compiling", "this is not C++;", "does not build"),
    ("crashing", "std::abort();", "crashed with signal SIGABRT"),
    # Killed by its CPU limit, or by the wall clock first on a busy machine.
    ("hanging", "for (volatile int spin = 0;; ) {}", "(killed)"),
    ("sleeping", "for (;;) sleep(1);", "did not finish within 5 s (killed)"),
    ("flooding", "for (int i = 0; i < 2000000; ++i) std::puts(\"spam spam spam\");",
     "output cut"),
])
def test_broken_submissions_fail_cleanly(tmp_path, kind, code, message):
    submission = solution_copy("01_buffer_add", tmp_path / kind)
    break_main(submission, "01_buffer_add", code)
    main = submission / "chapters" / "01_buffer_add" / "main.cpp"
    main.write_text("#include <unistd.h>\n#include <cstdlib>\n#include <cstdio>\n" +
                    main.read_text())
    results, tests = grade("01", submission, tmp_path / "g", FAST_LIMITS)
    assert results["score"] == 0
    assert any(message in t["output"] for t in tests.values()), tests
    assert all(len(t["output"]) < 25_000 for t in tests.values())


def test_missing_folders_are_reported(tmp_path):
    (tmp_path / "empty").mkdir()
    results, tests = grade("02", tmp_path / "empty", tmp_path / "g")
    assert results["score"] == 0
    assert "no chapters/02_first_pixels/" in results["output"]


def test_check_grades_a_learners_folder_and_names_its_mistake(tmp_path):
    """./course check NN FOLDER, for a learner outside a class: a folder with one of
    chapter 04's catalogued mistakes fails (exit 1) and its mistake is named with the
    book's section; the solution's own code passes (exit 0) with no diagnosis; the
    course's own tree and a folder without the chapter are refused (exit 2)."""
    variant = next(v for v in grading_catalogue.CATALOGUE["04"]
                   if not v.correct and not v.held_out)
    work = grading_catalogue.apply(variant, ROOT, tmp_path / "work")
    check = [*COURSE, "check", "04"]
    result = subprocess.run([*check, str(work), "--out", str(tmp_path / "out")],
                            capture_output=True, text=True, timeout=900)
    assert result.returncode == 1, result.stderr[-2000:]
    assert "These pictures look like a known mistake" in result.stdout, result.stdout
    assert f"- {variant.name}. {variant.explanation}" in result.stdout
    assert f"chapters/04_spheres/#{variant.anchor}" in result.stdout
    report = (tmp_path / "out" / "report.md").read_text()
    assert "## What this looks like" in report and variant.name in report
    right = solution_copy("04_spheres", tmp_path / "right")
    result = subprocess.run([*check, str(right), "--out", str(tmp_path / "out2")],
                            capture_output=True, text=True, timeout=900)
    assert result.returncode == 0, result.stdout + result.stderr[-2000:]
    assert "look like" not in result.stdout
    for folder, message in ((ROOT, "the course's own tree"),
                            (tmp_path, "no chapters/04_spheres or shaders/04_spheres")):
        result = subprocess.run([*check, str(folder)], capture_output=True, text=True,
                                timeout=900)
        assert result.returncode == 2 and message in result.stderr, result.stderr


def test_check_in_a_starter_says_where_to_run_it(tmp_path, monkeypatch, capsys):
    """A starter has no solution to compare with (nor the catalogue): ./course check
    there says to run it from the course's full repository, with this folder."""
    import argparse
    from course_tools.cli import commands
    monkeypatch.setattr(commands, "ROOT", tmp_path)
    with pytest.raises(SystemExit) as stop:
        commands.cmd_check(argparse.Namespace(chapter="04", folder=str(tmp_path), out=None))
    assert stop.value.code == 2
    assert f"there, run ./course check 04 {tmp_path}" in capsys.readouterr().err


def test_a_whole_class_at_once(tmp_path):
    """--submissions grades every folder (here the solution, the starter and one that
    does not compile) into its own results, and sums them up in one CSV."""
    submissions = tmp_path / "class"
    solution_copy("04_spheres", submissions / "alice")
    classroom.release(ROOT, "04_spheres", submissions / "bob")
    break_main(solution_copy("04_spheres", submissions / "carol"), "04_spheres",
               "this is not C++;")
    out = tmp_path / "graded"
    result = subprocess.run([*COURSE, "grade", "04", "--submissions", str(submissions),
                             "--out", str(out)], capture_output=True, text=True, timeout=900)
    assert result.returncode == 0, result.stderr[-2000:]
    assert result.stdout.strip() == str(out / "summary.csv")
    with open(out / "summary.csv", newline="") as source:
        rows = {row["student"]: row for row in csv.DictReader(source)}
    assert set(rows) == {"alice", "bob", "carol"}
    assert float(rows["alice"]["score"]) == float(rows["alice"]["max_score"]) == 10
    assert float(rows["alice"]["overlapping spheres, close up"]) == 2
    assert float(rows["bob"]["score"]) <= 1
    assert float(rows["carol"]["score"]) == 0
    assert "does not build" in rows["carol"]["notes"]
    assert "compiling main.cpp failed" in rows["carol"]["notes"]
    assert rows["alice"]["looks like"] == rows["carol"]["looks like"] == ""
    for student in rows:
        results = json.loads((out / student / "results.json").read_text())
        assert results["score"] == float(rows[student]["score"])
        assert (out / student / "report.md").exists()
