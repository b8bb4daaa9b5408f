"""The suite's closing table (tools/course_tools/cli/suite_parts.py): parts and their shares, and each
chapter's share of the checks' time against the 60 s its own checks may take."""

from __future__ import annotations


from conftest import ROOT

from course_tools.cli import suite_parts


def test_each_check_is_given_to_the_chapter_it_names():
    cases = {
        "tests/python/chapters/test_13_bvh.py::test_smooth_teapot_agrees_with_mitsuba": ("13", "own"),
        "tests/python/chapters/test_A2_gl33_fragment.py::test_x[egl]": ("A2", "own"),
        "tests/python/tools/test_grading_statistics.py::test_catalogue_variant[16-wrong-no_tir]":
            ("16", "grading"),
        "tests/python/tools/test_grading.py::test_solution_full_marks_and_starter_near_zero"
        "[23_wavefront]": ("23", "grading"),
        "tests/python/tools/test_classroom.py::test_starter_builds_runs_and_is_wrong"
        "[A2_gl33_fragment]": ("A2", "grading"),
        "tests/python/tools/test_book.py::test_book_builds_strictly_with_real_figures": None,
        "tests/python/chapters/test_command_line.py::test_too_old_gl_is_exit_4_with_the_way_out"
        "[egl-03]": None,
    }
    for check, expected in cases.items():
        assert suite_parts.chapter_of(check) == expected, check


def test_the_shares_name_a_chapter_over_its_minute():
    table = suite_parts.chapter_shares({
        "tests/python/chapters/test_16_glass.py::a": 50.0, "tests/python/chapters/test_16_glass.py::b": 20.0,
        "tests/python/tools/test_grading.py::t[16_glass]": 30.0,
        "tests/python/chapters/test_12_light_sampling.py::a": 59.0,
        "tests/python/tools/test_book.py::a": 7.0})
    rows = {line.split()[0]: line for line in table.splitlines()[3:]}
    assert rows["16"].split()[1:] == ["1:10", "0:30", "over", "its", "60", "s"]
    assert rows["12"].split()[1:] == ["0:59", "0:00"]
    assert rows["no"].split()[-1] == "0:07"
    assert suite_parts.chapter_shares({}) == ""
