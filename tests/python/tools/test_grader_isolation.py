"""Hostile submissions: chapter 04's starter (or solution) with a few malicious lines in
main.cpp. Each attack must earn nothing, leave the grader and the machine as they were,
and the report must say why. The attacks know the instructor's paths (a student can
guess /autograder/source/course), and most give up loudly when the attack fails, so
the report shows what the sandbox refused. See tools/course_tools/grading/sandbox.py for the protections."""

import argparse
import hashlib
import json
import os
import re
import shutil
import socket
import threading
import uuid

import pytest

from conftest import ROOT

from course_tools.editions import classroom
from course_tools.grading import grader
from course_tools.grading import sandbox

BUILD = ROOT / "build"
CHAPTER = "04_spheres"
ALL_TESTS = list(grader.SPECS["04"])
# Short runs: hostile programs are meant to hang, fork, allocate or print until killed.
FAST = {"COURSE_GRADE_WALL_SECONDS": "4", "COURSE_GRADE_CPU_SECONDS": "3",
        "COURSE_GRADE_PROCESSES": "48", "COURSE_GRADE_MEMORY_MB": "1536",
        "COURSE_GRADE_OUTPUT_MB": "4"}

ALL_OF_04 = list(grader.SPECS["04"])  # before short_grading keeps only the first
# What the sandbox adds to a run's output when it waited on a pipe that something outside
# the run still held: the grader was kept waiting (sandbox.Sandbox.run).
PIPE_HELD = "the output pipe stayed open"

pytestmark = pytest.mark.skipif(os.geteuid() != 0, reason="the grader separates users only "
                                "when it runs as root (as on Gradescope)")

INCLUDES = """#include <arpa/inet.h>
#include <dirent.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <unistd.h>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>
static bool copyFile(const std::string& from, const std::string& to) {
    FILE* in = std::fopen(from.c_str(), "rb");
    if (!in) {
        std::fprintf(stderr, "cannot read %s: %s\\n", from.c_str(), std::strerror(errno));
        return false;
    }
    FILE* out = std::fopen(to.c_str(), "wb");
    char buffer[4096];
    for (size_t n; (n = std::fread(buffer, 1, sizeof buffer, in)) > 0;)
        std::fwrite(buffer, 1, n, out);
    std::fclose(in); std::fclose(out);
    return true;
}
static char** optionValue(int argc, char** argv, const char* name) {
    for (int i = 1; i + 1 < argc; ++i) if (std::strcmp(argv[i], name) == 0) return &argv[i + 1];
    return nullptr;
}
"""


@pytest.fixture(autouse=True)
def short_grading(monkeypatch):
    """Lowered limits, and only the first of chapter 04's tests (one sphere, 3 points)."""
    for name, value in FAST.items():
        monkeypatch.setenv(name, value)
    monkeypatch.setitem(grader.SPECS, "04", grader.SPECS["04"][:1])


@pytest.fixture(scope="module")
def starter(tmp_path_factory):
    return classroom.release(ROOT, CHAPTER, tmp_path_factory.mktemp("starter") / "s")


@pytest.fixture(scope="module")
def solution(tmp_path_factory):
    folder = tmp_path_factory.mktemp("solution")
    for top in ("chapters", "shaders"):
        shutil.copytree(ROOT / top / CHAPTER, folder / top / CHAPTER)
    return folder


def hostile(base, destination, code):
    """base (a starter or the solution) with `code` run first thing in main()."""
    shutil.copytree(base, destination, ignore=shutil.ignore_patterns("build*"))
    main = destination / "chapters" / CHAPTER / "main.cpp"
    text = main.read_text()
    assert "    return course::run(" in text
    text = text.replace("    return course::run(", "    {\n" + code + "\n    }\n"
                        "    return course::run(", 1)
    main.write_text(INCLUDES + text)
    return destination


def grade(submission, tmp_path):
    out = tmp_path / "graded"
    results = grader.grade(ROOT, BUILD, CHAPTER, submission, out)
    report = (out / "report.md").read_text()
    assert_healthy(report)
    return results, results["tests"][0]["output"], report


def assert_healthy(report):
    """No process of the submission's user survives the grading; it ran as that user,
    without network, with the instructor's folders covered."""
    match = re.search(r"unprivileged user (\S+) \(uid (\d+)\)", report)
    assert match, report
    assert sandbox._live_processes(int(match.group(2))) == []
    assert "no network at all" in report


def c_string(path):
    return '"' + str(path).replace("\\", "\\\\").replace('"', '\\"') + '"'


# ---------------------------------------------------------------- reaching the solution

def test_reading_the_solution_at_run_time(starter, tmp_path):
    """Copies the instructor's shaders into its folder and points --shader-dir there."""
    code = f"""
    const std::string theirs = {c_string(ROOT / "shaders" / CHAPTER)};
    ::mkdir("stolen", 0700);
    for (const char* name : {{"trace.comp", "camera.glsl", "hit.glsl", "scene.glsl",
                             "sphere.glsl", "shared.h"}})
        if (!copyFile(theirs + "/" + name, std::string("stolen/") + name)) return 1;
    if (!copyFile({c_string(ROOT / "chapters" / CHAPTER / "main.cpp")}, "stolen/main.cpp"))
        return 1;
    static std::string mine = "stolen";
    if (char** dir = optionValue(argc, argv, "--shader-dir")) *dir = mine.data();"""
    results, output, _ = grade(hostile(starter, tmp_path / "s", code), tmp_path)
    assert results["score"] == 0
    assert f"cannot read {ROOT}/shaders/{CHAPTER}/trace.comp" in output
    assert "No such file or directory" in output or "Permission denied" in output


def test_including_a_solution_file_does_not_compile(starter, tmp_path):
    code = "    // nothing at run time: the attack is the #include at the top"
    submission = hostile(starter, tmp_path / "s", code)
    main = submission / "chapters" / CHAPTER / "main.cpp"
    text = main.read_text()
    assert '#include "camera.h"' in text  # the solution's instead: it compiles, if readable
    main.write_text(text.replace('#include "camera.h"',
                                 f"#include {c_string(ROOT / 'chapters' / CHAPTER / 'camera.h')}"))
    results, output, _ = grade(submission, tmp_path)
    assert results["score"] == 0
    assert "does not build" in output and "compiling main.cpp failed" in output
    assert f"{ROOT}/chapters/{CHAPTER}/camera.h" in output


def test_running_the_instructors_program(starter, tmp_path):
    """execs build/bin/04_spheres (the solution) without the --shader-dir option."""
    code = f"""
    std::vector<char*> args;
    for (int i = 0; i < argc; ++i) {{
        if (std::strcmp(argv[i], "--shader-dir") == 0) {{ ++i; continue; }}
        args.push_back(argv[i]);
    }}
    args.push_back(nullptr);
    ::execv({c_string(BUILD / "bin" / CHAPTER)}, args.data());
    std::perror("execv {BUILD}/bin/{CHAPTER}");
    return 1;"""
    results, output, _ = grade(hostile(starter, tmp_path / "s", code), tmp_path)
    assert results["score"] == 0
    assert f"execv {BUILD}/bin/{CHAPTER}:" in output


def test_pointing_shader_dir_at_the_instructors_shaders(starter, tmp_path):
    """The attack that once scored 10/10: the instructor's shader folder, found from a
    path macro of the compile flags (or guessed), replaces --shader-dir's value."""
    code = f"""
    static std::vector<std::string> candidates = {{
        std::string(COURSE_ASSET_DIR) + "/../shaders/{CHAPTER}",
        {c_string(ROOT / "shaders" / CHAPTER)}}};
    char** dir = optionValue(argc, argv, "--shader-dir");
    bool found = false;
    for (std::string& candidate : candidates) {{
        struct stat status;
        if (::stat((candidate + "/trace.comp").c_str(), &status) == 0) {{
            *dir = candidate.data(); found = true; break;
        }}
        std::fprintf(stderr, "no %s/trace.comp: %s\\n", candidate.c_str(), std::strerror(errno));
    }}
    std::fprintf(stderr, "COURSE_ASSET_DIR is %s, COURSE_SHADER_DIR is %s\\n",
                 COURSE_ASSET_DIR, COURSE_SHADER_DIR);
    if (!found) return 1;"""
    results, output, _ = grade(hostile(starter, tmp_path / "s", code), tmp_path)
    assert results["score"] == 0
    assert f"no {ROOT}/shaders/{CHAPTER}/trace.comp" in output
    # The macros point at the staging copy and at the submission's own shaders.
    assert f"COURSE_ASSET_DIR is {ROOT}" not in output
    assert f"COURSE_SHADER_DIR is {ROOT}" not in output


def test_overwriting_the_references_and_results_json(starter, tmp_path):
    reference = grader.reference_image(ROOT, BUILD, CHAPTER, grader.SPECS["04"][0])
    before = hashlib.sha256(reference.read_bytes()).hexdigest()
    results_json = tmp_path / "graded" / "results.json"
    code = f"""
    bool any = false;
    for (const char* path : {{{c_string(reference)}, {c_string(results_json)}}}) {{
        FILE* file = std::fopen(path, "wb");
        if (!file) {{
            std::fprintf(stderr, "cannot write %s: %s\\n", path, std::strerror(errno));
            continue;
        }}
        std::fputs("{{\\"score\\": 100}}", file); std::fclose(file); any = true;
    }}
    if (!any) return 1;"""
    results, output, _ = grade(hostile(starter, tmp_path / "s", code), tmp_path)
    assert results["score"] == 0
    assert f"cannot write {reference}" in output and f"cannot write {results_json}" in output
    assert hashlib.sha256(reference.read_bytes()).hexdigest() == before
    assert '"score": 0' in results_json.read_text()


def test_reading_or_poisoning_the_kept_objects(starter, tmp_path):
    """The compiled objects later gradings reuse, in the per-user cache so that a clean
    clone finds them (grader.object_cache): a submission can neither list them nor
    leave one of its own there for the next submission to link."""
    cache = grader.object_cache(BUILD)
    planted = cache / "planted.o"
    code = f"""
    bool any = false;
    if (DIR* dir = opendir({c_string(cache)})) {{ closedir(dir); any = true; }}
    else std::fprintf(stderr, "cannot list %s: %s\\n", {c_string(cache)}, std::strerror(errno));
    if (FILE* file = std::fopen({c_string(planted)}, "wb")) {{ std::fclose(file); any = true; }}
    else std::fprintf(stderr, "cannot write %s: %s\\n", {c_string(planted)},
                      std::strerror(errno));
    std::fprintf(stderr, any ? "reached the kept objects\\n" : "kept out\\n");
    return 1;  // its messages in the report"""
    results, output, _ = grade(hostile(starter, tmp_path / "s", code), tmp_path)
    assert results["score"] == 0 and "kept out" in output, output
    assert f"cannot list {cache}" in output and f"cannot write {planted}" in output
    assert not planted.exists()


def test_the_staging_copy_is_named_by_its_files_contents(tmp_path):
    """Two clones of the same tree, built at different times, stage the compiler's
    folders to the same place: the arguments, and so the kept objects' keys, match."""
    places = []
    for clone, when in (("a", 1_000_000_000), ("b", 1_700_000_000)):
        root, build = tmp_path / clone, tmp_path / clone / "build"
        (root / "common").mkdir(parents=True)
        (build / "generated").mkdir(parents=True)
        for path, text in ((root / "common" / "a.h", "int a;\n"),
                           (build / "generated" / "b.h", "int b;\n")):
            path.write_text(text)
            os.utime(path, (when, when))
        arguments = [f"-I{root / 'common'}", f"-I{build / 'generated'}"]
        staging = grader.Staging(root, build, "04_spheres", arguments, [], tmp_path / "base")
        places.append(staging.path.name)
        assert (staging.path / "source" / "common" / "a.h").read_text() == "int a;\n"
    assert places[0] == places[1]


def test_the_libraries_are_staged_whatever_their_size(tmp_path, monkeypatch):
    """A file bigger than STAGED_FILE_LIMIT in a folder the flags name (the benchmark's
    teapot) is left out; a library the link needs is staged however big it grows (the
    common layer's, with GCC 14's debug information, passed 32 MiB)."""
    monkeypatch.setattr(grader, "STAGED_FILE_LIMIT", 64)
    root, build = tmp_path / "tree", tmp_path / "tree" / "build"
    (build / "assets").mkdir(parents=True)
    (build / "common").mkdir()
    (build / "assets" / "teapot.obj").write_bytes(b"v 0 0 0\n" * 100)
    (build / "assets" / "small.obj").write_bytes(b"v 0 0 0\n")
    library = build / "common" / "libcourse_common.a"
    library.write_bytes(b"!<arch>\n" + b"x" * 1000)
    arguments = [f'-DCOURSE_GENERATED_ASSET_DIR="{build / "assets"}"']
    staging = grader.Staging(root, build, "04_spheres", arguments, [library],
                             tmp_path / "base")
    assert staging.staged(library).read_bytes() == library.read_bytes()
    assert staging.staged(build / "assets" / "small.obj").exists()
    assert not staging.staged(build / "assets" / "teapot.obj").exists()


def test_a_link_to_the_reference_instead_of_an_image(starter, tmp_path):
    """Leaves --out as a link to the reference: the grader must not follow it."""
    reference = grader.reference_image(ROOT, BUILD, CHAPTER, grader.SPECS["04"][0])
    code = f"""
    char** out = optionValue(argc, argv, "--out");
    if (::symlink({c_string(reference)}, *out) != 0) std::perror("symlink");
    return 0;"""
    results, output, _ = grade(hostile(starter, tmp_path / "s", code), tmp_path)
    assert results["score"] == 0
    assert "left a link where the file should be (not followed)" in output


def test_a_linked_shader_folder_is_not_copied(starter, tmp_path):
    submission = tmp_path / "s"
    shutil.copytree(starter / "chapters", submission / "chapters")
    (submission / "shaders").mkdir()
    (submission / "shaders" / CHAPTER).symlink_to(ROOT / "shaders" / CHAPTER)
    results, output, _ = grade(submission, tmp_path)
    assert results["score"] == 0
    assert f"ignored the link shaders/{CHAPTER}" in results["output"]


# ---------------------------------------------------------------- harming the machine

def test_a_fork_bomb(solution, tmp_path):
    results, output, _ = grade(hostile(solution, tmp_path / "s", "for (;;) ::fork();"),
                               tmp_path)
    assert results["score"] == 0
    assert "did not finish within 4 s (killed)" in output or "s of CPU time" in output
    assert PIPE_HELD not in output
    # The machine still forks, and the next grading is not hurt.
    results, _, _ = grade(solution, tmp_path / "after")
    assert results["score"] == results["tests"][0]["max_score"]


def test_a_memory_bomb(solution, tmp_path, monkeypatch):
    # A lower memory limit and room in time, so that the memory limit is what stops the
    # bomb even on a loaded machine (faulting in 1.5 GiB once took more than 3 s of CPU).
    monkeypatch.setenv("COURSE_GRADE_MEMORY_MB", "512")
    monkeypatch.setenv("COURSE_GRADE_CPU_SECONDS", "30")
    monkeypatch.setenv("COURSE_GRADE_WALL_SECONDS", "60")
    code = """
    std::vector<char*> hog;
    for (;;) { hog.push_back(new char[64 << 20]); std::memset(hog.back(), 1, 64 << 20); }"""
    results, output, _ = grade(hostile(solution, tmp_path / "s", code), tmp_path)
    assert results["score"] == 0
    assert "crashed with signal SIGABRT (out of memory: the limit is 512 MiB)" in output


def test_no_network(solution, tmp_path):
    listener = socket.socket()
    listener.bind(("127.0.0.1", 0))
    listener.listen()
    listener.settimeout(0.2)
    port = listener.getsockname()[1]
    visitors, done = [], threading.Event()

    def accept():
        while not done.is_set():
            try:
                visitors.append(listener.accept())
            except OSError:
                pass
    thread = threading.Thread(target=accept)
    thread.start()
    code = f"""
    int s = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in address{{}};
    address.sin_family = AF_INET;
    address.sin_port = htons({port});
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (::connect(s, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0) {{
        std::perror("connect to 127.0.0.1:{port}");
        return 1;
    }}
    ::send(s, "the solution", 12, 0);"""
    try:
        results, output, _ = grade(hostile(solution, tmp_path / "s", code), tmp_path)
    finally:
        done.set()
        thread.join()
        listener.close()
    assert visitors == []
    assert results["score"] == 0
    assert f"connect to 127.0.0.1:{port}: Network is unreachable" in output


def test_writing_outside_its_folder(starter, tmp_path):
    marker = f"pwned-{uuid.uuid4().hex[:8]}"
    targets = [f"/tmp/{marker}", f"/var/tmp/{marker}", str(ROOT / marker),
               str(BUILD / "grading" / marker), f"/var/lib/course-grader/{marker}"]
    code = f"""
    int written = 0;
    for (const char* path : {{{", ".join(c_string(t) for t in targets)}}}) {{
        FILE* file = std::fopen(path, "w");
        if (!file) {{
            std::fprintf(stderr, "cannot write %s: %s\\n", path, std::strerror(errno));
            continue;
        }}
        std::fputs("pwned", file); std::fclose(file); ++written;
        std::fprintf(stderr, "wrote %s\\n", path);
    }}
    if (written < 5) return 1;"""
    results, output, _ = grade(hostile(starter, tmp_path / "s", code), tmp_path)
    assert results["score"] == 0
    for target in targets:
        assert not os.path.exists(target), target
    for target in targets[2:]:
        assert f"cannot write {target}" in output
    # /tmp and /var/tmp were private to the run: what it wrote there is gone with it.


def test_gigabytes_of_output(solution, tmp_path):
    code = """
    static char line[1 << 16];
    std::memset(line, 'x', sizeof line);
    for (;;) std::fwrite(line, 1, sizeof line, stdout);"""
    results, output, report = grade(hostile(solution, tmp_path / "s", code), tmp_path)
    assert results["score"] == 0
    assert "printed more than 4 MiB (killed)" in output
    assert len(output) < 25_000 and len(report) < 60_000
    assert PIPE_HELD not in output


def test_a_program_that_never_exits(solution, tmp_path):
    code = """
    if (::fork() == 0) { ::setsid(); for (;;) ::sleep(1); }  // and a child that hides
    for (;;) ::sleep(1);"""
    results, output, _ = grade(hostile(solution, tmp_path / "s", code), tmp_path)
    assert results["score"] == 0
    assert "did not finish within 4 s (killed)" in output
    assert PIPE_HELD not in output


def test_a_crawling_submission_still_gets_its_results(solution, tmp_path, monkeypatch):
    """Gradescope ends an autograder that runs past its time-out with no results at all,
    so the grading as a whole has a budget (COURSE_GRADE_TOTAL_SECONDS): runs that
    would pass it are stopped or never started, and every test still gets its 0 and
    its reason."""
    monkeypatch.setitem(grader.SPECS, "04", ALL_OF_04)
    monkeypatch.setenv("COURSE_GRADE_TOTAL_SECONDS", "10")
    code = "for (;;) ::sleep(1);"
    results, _, report = grade(hostile(solution, tmp_path / "s", code), tmp_path)
    outputs = [test["output"] for test in results["tests"]]
    assert results["score"] == 0 and len(outputs) == 4
    budget = "was stopped: the whole grading may take 10 s, and they were spent"
    assert "did not finish within 4 s" in outputs[0] or budget in outputs[0]
    assert all(budget in output for output in outputs[2:]), outputs
    assert "10 s for the whole grading" in report


def test_a_child_left_behind_is_killed_before_the_images_are_read(solution, tmp_path):
    """A correct program that leaves a daemon behind (holding its output open) scores
    what its image is worth, without the grader waiting for the daemon, which is gone
    when the grading ends (assert_healthy)."""
    code = """
    if (::fork() == 0) { ::setsid(); if (::fork() == 0) for (;;) ::sleep(1); ::_exit(0); }"""
    results, _, _ = grade(hostile(solution, tmp_path / "s", code), tmp_path)
    assert results["score"] == results["tests"][0]["max_score"]


def test_a_run_ends_with_its_program_though_a_child_holds_its_output(monkeypatch):
    """What the grading above shows only by its score, seen in the sandbox's own words: a
    run whose program exits is over then, its leftovers killed, so the grader neither
    waits out the time limit (the code would be None, killed) nor waits on the pipe a
    leftover holds (the output would say so)."""
    for name, value in FAST.items():
        monkeypatch.setenv(name, value)
    with sandbox.Sandbox() as box:
        work = box.folder("work", writable=True)
        run = box.run(["/bin/sh", "-c", "setsid sleep 1000 & echo started"], work)
        assert sandbox._live_processes(box.uid) == []
    assert run == (0, "started\n")


# ---------------------------------------------------------------- the autograder image

def test_grading_needs_none_of_the_solutions_sources(solution, tmp_path, monkeypatch):
    """What an autograder image keeps after ./course grade NN --prepare: no chapters/,
    no shaders/, no build/bin; the references, the common layer and the flags."""
    monkeypatch.setitem(grader.SPECS, "04", ALL_TESTS)
    grader.prepare(ROOT, BUILD, CHAPTER)
    fake = tmp_path / "course"
    build = fake / "build"
    shutil.copytree(ROOT / "common", fake / "common")
    shutil.copytree(ROOT / "assets", fake / "assets")
    shutil.copytree(BUILD / "glad" / "include", build / "glad" / "include")
    (build / "common").mkdir()
    shutil.copy2(BUILD / "common" / "libcourse_common.a", build / "common")
    shutil.copy2(BUILD / "libglad.a", build)
    shutil.copytree(BUILD / "grading" / CHAPTER, build / "grading" / CHAPTER)
    commands = (BUILD / "compile_commands.json").read_text()
    (build / "compile_commands.json").write_text(
        commands.replace(str(BUILD), str(build)).replace(str(ROOT), str(fake)))
    assert grader.is_prepared(build, CHAPTER)
    results = grader.grade(fake, build, CHAPTER, solution, tmp_path / "graded")
    assert results["score"] == sum(t.max_score for t in ALL_TESTS), results
    assert not (fake / "chapters").exists() and not (build / "bin").exists()
    # ./course grade there skips the build (which would fail) and grades the same.
    from course_tools.cli import commands as course
    monkeypatch.setattr(course, "ROOT", fake)
    monkeypatch.setattr(course, "BUILD", build)
    shutil.copy2(ROOT / "CMakeLists.txt", fake)
    arguments = dict(chapter="04", submission=str(solution), submissions=None,
                     prepare=False, out=str(tmp_path / "graded-by-course"), jobs=None,
                     show_hidden=False, keep_runs=False)
    course.cmd_grade(argparse.Namespace(**arguments))
    again = json.loads((tmp_path / "graded-by-course" / "results.json").read_text())
    assert again["score"] == results["score"]
    # Kept runs are keyed by the solution's sources, which are gone: a clear refusal.
    with pytest.raises(SystemExit) as refused:
        course.cmd_grade(argparse.Namespace(**{**arguments, "keep_runs": True}))
    assert refused.value.code == 2


def test_signatures_kept_from_gradings_that_never_ran_are_made_again():
    """An earlier grader kept a chapter's mistake signatures even when no variant could
    be built (a library left out of the staging copy): every test's measurement empty.
    Such kept signatures are not used; whole ones are."""
    whole = {"solution": {"tests": {"one_sphere": [0.1]}},
             "mistakes": [{"name": "m", "tests": {"one_sphere": [0.4]}}]}
    never_ran = {"solution": {"tests": {}}, "mistakes": [{"name": "m", "tests": {}}]}
    assert grader.signatures_measured(json.dumps(whole).encode())
    assert not grader.signatures_measured(json.dumps(never_ran).encode())
    assert not grader.signatures_measured(b"torn")
