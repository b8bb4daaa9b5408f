"""Classroom: solution markers are well formed everywhere, and a starter release builds,
runs, and draws a wrong picture instead of crashing."""

import re
import shutil
import subprocess
import sys

import pytest

from conftest import ROOT, assert_images_agree, read_image

from course_tools.editions import classroom, solution_markers
from course_tools.grading import grader
from course_tools.grading import sandbox

BUILD = ROOT / "build"


def test_every_marker_in_the_repository_is_balanced():
    assert solution_markers.check_all_markers(ROOT) > 0


@pytest.mark.parametrize("text,line,message", [
    ("a\n// BEGIN SOLUTION x\nb\n", 2, "never closed"),
    ("// END SOLUTION\n", 1, "without BEGIN"),
    ("// BEGIN SOLUTION\n// BEGIN SOLUTION\n// END SOLUTION\n", 2, "cannot nest"),
    ("x\n// STUB: y\n", 2, "STUB outside"),
])
def test_bad_markers_name_file_and_line(text, line, message):
    with pytest.raises(solution_markers.MarkerError, match=f"shader.comp:{line}: .*{message}"):
        solution_markers.find_blocks(text, "shader.comp")


def test_strip_keeps_hint_and_stub():
    text = ("void f() {\n    // BEGIN SOLUTION add them\n    x = a + b;\n"
            "    // STUB: x = 0;\n    // END SOLUTION\n}\n")
    assert solution_markers.strip_solutions(text, "f.glsl") == (
        "void f() {\n    // TODO: add them\n    x = 0;\n}\n")


def test_a_check_that_plants_a_solution_line_is_left_out_of_the_starter():
    """Both ways of planting a mistake: str.replace and path_checks.shaders_with_bug,
    also through the test file's own helpers, however deep."""
    solution, starter = "hit = a >= 0.0;\nreturn hit;", "return false;"
    test = ('import path_checks\nRIGHT = "hit = a >= 0.0;"\n\n'
            'def test_replaced():\n    text = "".replace(RIGHT, "hit = true;")\n\n'
            'def test_planted():\n'
            '    path_checks.shaders_with_bug("10", None, ("s.glsl", RIGHT, "x"))\n\n'
            'def shaders_with(bug=None):\n'
            '    return path_checks.shaders_with_bug("10", None, bug)\n\n'
            'def render(bug=None):\n    return shaders_with(bug)\n\n'
            'def test_planted_through_helpers():\n    render(("s.glsl", RIGHT, "x"))\n\n'
            'def test_helpers_without_a_plant():\n    render()\n\n'
            'def test_kept():\n    assert "return false;"\n')
    kept = classroom.without_planted_mistakes(test, solution, starter)
    assert "def test_kept" in kept and "a >= 0.0" not in kept
    assert "test_replaced" not in kept and "test_planted" not in kept
    assert "test_helpers_without_a_plant" in kept and "def render" in kept


def released_chapters():
    chapters = sorted(p.name for p in (ROOT / "chapters").iterdir() if p.is_dir())
    return [c for c in chapters if classroom.has_exercises(ROOT, c)]


def compile_starter(starter, chapter):
    """Compiles the starter's host code as the grader compiles a submission: in its
    sandbox, with the flags CMake used for the solution, linked with the instructor's
    common layer (so it shares compiled objects with the grading tests). The program's
    own shader folder is the sandbox's, gone afterwards: run it with --shader-dir."""
    with sandbox.Sandbox(hide=[], close=[]) as box:
        source = box.folder("submission", writable=False)
        grader.copy_submission(starter, chapter, source)
        box.seal(source)
        workdir = box.folder("run", writable=True)
        program, log = grader.compile_submission(ROOT, BUILD, chapter, source, workdir)
        assert program is not None, log
        kept = starter / "build-starter" / chapter
        kept.parent.mkdir()
        shutil.copyfile(program, kept)
        kept.chmod(0o755)
    return kept


# What shows a starter's mistake, where the default picture cannot: chapter 14's exercise
# is the SAH, and any tree, good or bad, finds the same hits; its traversal work shows.
# Chapter 19's is a quad written out as constants, and the default showcase (51 shapes)
# is read from storage buffers; chapter 21's is the tree's walk, and the showcase has
# no triangles; chapter 23's is the wavefront's queue, which the default megakernel
# does not use; chapter 29's is the blend of frames, and the default draws one.
SHOWN_BY = {"14_bvh_sah": ["--view", "cost"], "19_specialisation": ["--scene", "cornell_box"],
            "21_tree_price": ["--scene", "cornell_teapot"],
            "23_wavefront": ["--kernel", "wavefront"],
            "29_temporal": ["--move-frames", "4", "--move", "0.2,0.1,-0.3", "--blend", "0.05"]}


@pytest.mark.parametrize("chapter", released_chapters())
def test_starter_builds_runs_and_is_wrong(tmp_path, chapter):
    starter = classroom.release(ROOT, chapter, tmp_path / "starter")
    text = "".join(p.read_text() for p in starter.rglob("*")
                   if p.is_file() and p.suffix in solution_markers.MARKED_SUFFIXES)
    assert "BEGIN SOLUTION" not in text and "END SOLUTION" not in text
    assert "TODO:" in text
    later = [c.name for c in (ROOT / "chapters").iterdir() if c.name > chapter]
    for name in later:
        assert not list(starter.rglob(f"*{name}*")), f"{name} leaked into the starter"
    assert (starter / "README.md").exists()

    program = compile_starter(starter, chapter)
    shaders = ["--shader-dir", str(starter / "shaders" / chapter)]
    if chapter.startswith("01"):
        result = subprocess.run([str(program), "--count", "100", *shaders],
                                capture_output=True, text=True, timeout=120)
        assert result.returncode == 1 and "sums are wrong" in result.stderr  # no crash
        return
    out = tmp_path / "starter.png"
    view = SHOWN_BY.get(chapter, [])
    result = subprocess.run([str(program), "--headless", "--width", "64", "--height", "48",
                             *view, *shaders, "--out", str(out)], capture_output=True,
                            text=True, timeout=300)
    assert result.returncode == 0, result.stderr
    solution = tmp_path / "solution.png"
    subprocess.run([str(BUILD / "bin" / chapter), "--headless", "--width", "64", "--height",
                    "48", *view, "--out", str(solution)], check=True, capture_output=True)
    # The starter's picture must fail the course's image check against the solution.
    with pytest.raises(AssertionError):
        assert_images_agree(read_image(out), read_image(solution), label=chapter)


def test_release_verb_writes_a_starter(tmp_path):
    result = subprocess.run([sys.executable, str(ROOT / "tools" / "course.py"), "release", "02",
                             "--out", str(tmp_path / "s")], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    assert (tmp_path / "s" / "chapters" / "02_first_pixels" / "main.cpp").exists()


def test_release_refuses_a_chapter_without_exercises(tmp_path):
    # Every chapter has SOLUTION blocks now (the appendix's: reading shapes out of its
    # buffer texture); a folder without any would give a starter that is the solution.
    assert classroom.has_exercises(ROOT, "A2_gl33_fragment")
    for top in ("chapters", "shaders"):
        (tmp_path / top / "99_plain").mkdir(parents=True)
    (tmp_path / "chapters" / "99_plain" / "main.cpp").write_text("int main() {}\n")
    assert not classroom.has_exercises(tmp_path, "99_plain")
    result = subprocess.run([sys.executable, str(ROOT / "tools" / "course.py"), "release", "99",
                             "--out", str(tmp_path / "s")], capture_output=True, text=True)
    assert result.returncode == 2 and "no chapter '99'" in result.stderr
    assert not (tmp_path / "s").exists()


def test_autograder_zip_has_gradescope_entry_points(tmp_path):
    import stat
    import zipfile
    out = tmp_path / "ag.zip"
    result = subprocess.run([sys.executable, str(ROOT / "tools" / "course.py"), "autograder",
                             "02", "--out", str(out)], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    with zipfile.ZipFile(out) as archive:
        names = archive.namelist()
        for entry in ("setup.sh", "run_autograder", "course/course", "course/tools/course_tools/grading/grader.py",
                      "course/chapters/02_first_pixels/main.cpp"):
            assert entry in names
        for entry in ("setup.sh", "run_autograder", "course/course"):
            mode = archive.getinfo(entry).external_attr >> 16
            assert mode & stat.S_IXUSR, f"{entry} must be executable"
        setup = archive.read("setup.sh").decode()
        # The references are rendered, then every chapter's solution leaves the image.
        prepare = setup.index("./course grade 02 --prepare")
        assert prepare < setup.index("rm -rf chapters shaders build/bin")
        run = archive.read("run_autograder").decode()
        assert "./course grade 02 --submission /autograder/submission" in run
        assert "--out /autograder/results" in run
        assert not any(n.startswith("course/build/") or "/.venv/" in n for n in names)


def test_a_starter_builds_the_earlier_chapters_its_checks_compare_with(tmp_path):
    # Chapter 23's checks draw chapter 22's pictures to compare with, and chapter 14's
    # run chapter 12's and count chapter 13's steps: their starters hold those chapters,
    # finished (no markers, nothing to write), and build them; chapter 02's holds none.
    for chapter, references in [("23_wavefront", ["22_path_regeneration"]),
                                ("14_bvh_sah", ["12_light_sampling", "13_bvh"]),
                                ("02_first_pixels", [])]:
        starter = classroom.release(ROOT, chapter, tmp_path / chapter)
        built = re.findall(r"^add_chapter\((\w+)\)", (starter / "CMakeLists.txt").read_text(),
                           flags=re.M)
        assert sorted(built) == sorted([chapter, *references])
        assert sorted(p.name for p in (starter / "chapters").iterdir()) == built
        readme = (starter / "README.md").read_text()
        for reference in references:
            assert (starter / "manifests" / f"{reference}.ini").exists()
            assert f"`chapters/{reference}/`" in readme
            for top in ("chapters", "shaders"):
                for path in (starter / top / reference).rglob("*"):
                    if path.suffix in solution_markers.MARKED_SUFFIXES:
                        text = path.read_text()
                        assert "SOLUTION" not in text and "TODO" not in text, path
        # The reference is the solution: its files equal the course's, markers aside.
        for reference in references:
            original = ROOT / "shaders" / reference
            for path in original.rglob("*"):
                copied = starter / "shaders" / reference / path.relative_to(original)
                assert copied.read_text() == solution_markers.keep_solutions(path.read_text(),
                                                                      str(path))
        if not references:
            assert "is finished" not in readme and "are finished" not in readme


def test_starter_has_a_classroom_workflow(tmp_path):
    starter = classroom.release(ROOT, "02_first_pixels", tmp_path / "s")
    workflow = (starter / ".github" / "workflows" / "classroom.yml").read_text()
    assert "./course test 02" in workflow


def test_a_starter_carries_no_catalogue_of_mistakes_and_says_how_to_check(tmp_path):
    """The catalogue of mistakes is edits of solution code: no starter carries it (nor
    its tools: they import it only to measure the mistakes, which a starter cannot).
    Its README tells a learner without a class how to be graded with a diagnosis."""
    starter = classroom.release(ROOT, "12_light_sampling", tmp_path / "s")
    assert not (starter / "grading_catalogue").exists()
    carried = {p.name for p in starter.rglob("*.py")}
    assert not carried & {p.name for p in (ROOT / "grading_catalogue").glob("*.py")
                          if p.name != "__init__.py"}
    readme = (starter / "README.md").read_text()
    assert "./course check 12 /path/to/this/folder" in readme


def test_a_starter_runs_the_prototype_its_page_shows(tmp_path):
    """Chapter 11's page shows code of python_prototypes/monte_carlo.py: the starter has
    it, with what it imports, and it runs there."""
    starter = classroom.release(ROOT, "11_path_tracing", tmp_path / "s")
    script = starter / "python_prototypes" / "monte_carlo.py"
    assert script.exists() and (starter / "python_prototypes" / "figure_file.py").exists()
    result = subprocess.run([sys.executable, str(script), "--figure", str(tmp_path / "mc.png"),
                             "--which", "light"], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    assert (tmp_path / "mc.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_a_starter_runs_its_own_checks(tmp_path):
    """What a student does first: `./course test 23` in a fresh starter. It builds (the
    asset generators came along), builds chapter 22 to compare with, and runs chapter
    23's checks: the megakernel's pass, since the student's exercise is the wavefront's
    queue, and the wavefront's fail until it is written. None fails for want of a
    program."""
    starter = classroom.release(ROOT, "23_wavefront", tmp_path / "s")
    (starter / ".venv").symlink_to(sys.prefix)  # this interpreter's packages: no pip
    result = subprocess.run([str(starter / "course"), "test", "23"], cwd=starter,
                            capture_output=True, text=True, timeout=1800)
    report = result.stdout + result.stderr
    assert result.returncode == 1, report[-3000:]
    assert "is not built" not in report and "ninja: error" not in report
    failed = set(re.findall(r"^FAILED \S+::(\w+)", result.stdout, flags=re.M))
    assert "test_a_pool_smaller_than_the_image_runs_it_in_waves" in failed
    assert "test_the_wavefront_agrees_with_mitsuba" in failed
    passed = {"test_other_views_need_the_megakernel"}
    assert not passed & failed, failed
    assert re.search(r"^\d+ passed, \d+ failed", result.stdout, flags=re.M), report[-3000:]
