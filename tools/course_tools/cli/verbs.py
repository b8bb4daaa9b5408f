"""The command line of ./course: one table of verbs, each with its options, what it
does (a function of commands.py, suite.py or book.py, which import only the standard
library at first) and the set-up layer it needs (setup/machine_setup.py). A verb with
a layer first sets that layer up with the system's Python, then runs again in .venv;
verbs without one only read files and run with whatever Python started ./course."""

from __future__ import annotations

import argparse
import os
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

from course_tools.cli import book, commands, suite
from course_tools.paths import ROOT
from course_tools.setup.platforms import LAYERS  # run, book, grade, test


@dataclass(frozen=True)
class Verb:
    name: str
    help: str
    options: Callable[[argparse.ArgumentParser], None]  # adds the verb's options
    command: Callable[[argparse.Namespace], None]  # carries it out
    layer: str | None       # the set-up layer it needs (None: files only)
    description: str = ""


def no_options(parser: argparse.ArgumentParser):
    pass


def layer_option(parser: argparse.ArgumentParser):
    parser.add_argument("layer", nargs="?", default="run", choices=LAYERS)


def run_options(parser: argparse.ArgumentParser):
    parser.add_argument("chapter", nargs="?", help="chapter number, e.g. 02")
    parser.add_argument("options", nargs=argparse.REMAINDER, help="chapter options")


def test_options(parser: argparse.ArgumentParser):
    parser.add_argument("chapter", nargs="?", help="only this chapter's checks")
    parser.add_argument("-k", help="only pytest checks matching this expression")
    parser.add_argument("--sanitize", action="store_true",
                        help="build with ASan + UBSan and run the units and chapter checks")
    parser.add_argument("--update-book", action="store_true",
                        help="once the whole suite has passed, write what it measured into "
                        "the pages (the catalogues' scores, the numbers pages mark)")


def gpu_check_command(args):
    from course_tools.cli import gpu_check  # the bench helpers only when asked for
    gpu_check.cmd_gpu_check(args)


def gpu_check_options(parser: argparse.ArgumentParser):
    parser.add_argument("--gpu", type=int, help="the EGL device to check (default: the "
                        "first that works, GPUs first; the report lists them)")
    parser.add_argument("--repeat", type=int, default=3,
                        help="timed runs of each figure; the median is reported (3)")
    parser.add_argument("--update-book", action="store_true",
                        help="write this device's row into book/docs/benchmarks.md")


def fuzz_options(parser: argparse.ArgumentParser):
    parser.add_argument("target", nargs="?", help="only targets whose name contains this")
    parser.add_argument("--seconds", type=int, default=60, help="per target (default 60)")


def diff_options(parser: argparse.ArgumentParser):
    parser.add_argument("a")
    parser.add_argument("b")
    parser.add_argument("--stat", action="store_true", help="a summary per file")
    parser.add_argument("--no-color", action="store_true")


def book_options(parser: argparse.ArgumentParser):
    parser.add_argument("--serve", action="store_true", help="preview on localhost:8000")
    parser.add_argument("--draft", action="store_true",
                        help="quick small figures (how ./course test checks the book builds)")
    parser.add_argument("--student", action="store_true",
                        help="the student edition, to publish: the starters' code instead "
                        "of the solutions, no answer notes (into book/site-student)")
    parser.add_argument("--figures-as-they-are", action="store_true",
                        help="use the figures and diffs the last ./course book made, "
                        "without rendering them again (both editions in one test run)")


def bench_options(parser: argparse.ArgumentParser):
    parser.add_argument(
        "which", nargs="?", choices=["all", "mitsuba", "bvh", "speed", "wavefront", "instances",
                            "denoise", "grading", "cost"],
        default="all", help="which benchmark (default: mitsuba, bvh, speed, wavefront, "
        "instances and denoise; "
        "mitsuba: the Cornell box through chapter 12 and the newest chapter, the teapot "
        "through the newest chapter with a BVH, ours and Mitsuba's runs taking turns; "
        "speed: chapters 19 to 21 (specialisation, memory paths, the tree's price) against "
        "chapter 18; wavefront: chapter 22's megakernel, one sample a dispatch and "
        "regenerating, against chapter 23's wavefront; instances: chapter 26's field of "
        "10 000 teapots against one, and chapter 27's twisting teapot, refitted against "
        "rebuilt; denoise: chapter 28's filter against the raw picture and Open Image Denoise "
        "on four scenes, and its cost in samples a pixel; grading: one submission of each "
        "chapter on one core; cost: instructions a sample, counted by valgrind through the "
        "newest chapter with a BVH, with --shader-dirs to compare changed shaders)")
    parser.add_argument("--chapters", nargs="*", help="grading: only these chapters")
    parser.add_argument("--shader-dirs", nargs="*", default=[],
                        help="cost: folders of changed copies of the chapter's shaders, "
                        "each counted against the chapter's own")
    parser.add_argument("--repeat", type=int, default=3,
                        help="runs of each figure (gradings per chapter): the median and "
                        "the range are reported (3)")
    parser.add_argument("--update-book", action="store_true",
                        help="write the tables (and the BVH figure) into the book's pages, "
                        "book/docs/benchmarks.md, the chapters' and instructors.md; only "
                        "from a quiet machine")
    parser.add_argument("--size", type=int, default=256,
                        help="mitsuba: image side (default 256)")
    parser.add_argument("--spp", type=int, default=128,
                        help="mitsuba: samples per pixel (128)")
    parser.add_argument("--depth", type=int, default=6, help="mitsuba: bounces (default 6)")
    parser.add_argument("--speed-spp", type=int, default=32,
                        help="speed: samples per pixel (32)")


def release_options(parser: argparse.ArgumentParser):
    parser.add_argument("chapter")
    parser.add_argument("--out",
                        help="folder to write (default build/release/NN_name-starter)")
    parser.add_argument("--draft", action="store_true",
                        help="quick small figures on the starter's page")


def grade_options(parser: argparse.ArgumentParser):
    parser.add_argument("chapter")
    which = parser.add_mutually_exclusive_group(required=True)
    which.add_argument("--submission", help="the student's folder")
    which.add_argument("--submissions", help="a folder with one folder per student: grade "
                       "them all, as many at once as there are cores; writes "
                       "OUT/summary.csv")
    which.add_argument("--prepare", action="store_true",
                       help="only render the reference images (an autograder image does "
                       "this before it removes the solution's sources)")
    parser.add_argument("--out", help="where results.json and report.md go (--submissions: "
                        "one folder per student in it)")
    parser.add_argument("--jobs", type=int, help="--submissions: how many at once "
                        "(default: the number of cores)")
    parser.add_argument("--show-hidden", action="store_true",
                        help="include hidden tests' details in the report")
    parser.add_argument("--keep-runs", action="store_true",
                        help="replay the runs of a submission graded before with the same "
                        "files, solution, build and GL (kept in the reference cache) "
                        "instead of running them again: for regrading after the points "
                        "change, and for the course's own suite")


def check_options(parser: argparse.ArgumentParser):
    parser.add_argument("chapter")
    parser.add_argument("folder", help="your work: a folder with chapters/NN_name/ and "
                        "shaders/NN_name/ (a starter from ./course release)")
    parser.add_argument("--out", help="where results.json and report.md go "
                        "(default: build/checks/NN_name)")


def windows_check_options(parser: argparse.ArgumentParser):
    parser.add_argument("chapter", nargs="?", help="only this chapter's checks")


def windows_check_command(args):
    from course_tools.windows import check  # only when asked for
    check.cmd_windows_check(args)


def autograder_options(parser: argparse.ArgumentParser):
    parser.add_argument("chapter")
    parser.add_argument("--out", help="zip to write")


VERBS = [
    Verb("setup", "install what a layer of the course needs and configure the build (run: "
         "the chapters; book; grade; test: all)", layer_option, commands.cmd_setup, "run"),
    Verb("packages", "the distribution packages of a layer on this platform "
         "(tools/platforms.ini), on one line", layer_option, commands.cmd_packages, None),
    Verb("build", "build every chapter", no_options, commands.cmd_build, "run"),
    Verb("list", "the chapters, one line each", no_options, commands.cmd_list, None),
    Verb("run", "build and run a chapter headless (default: the last)", run_options,
         commands.cmd_run, "run", "Runs a chapter; options after the chapter number go to the "
         "chapter program (see its --help)."),
    Verb("test", "build everything and run every check", test_options, suite.cmd_test, "test"),
    Verb("fuzz", "run the libFuzzer targets (OBJ, scene, #include)", fuzz_options,
         suite.cmd_fuzz, "test"),
    Verb("diff", "what checkpoint B adds to checkpoint A", diff_options, book.cmd_diff, None),
    Verb("book", "render the figures and build the book", book_options, book.cmd_book, "book"),
    Verb("bench", "our path tracer against Mitsuba 3 (Cornell box, teapot); chapter 14's "
         "BVH against brute force, 552 to 1M triangles", bench_options, commands.cmd_bench, "test",
         "Measures each figure --repeat times and reports the median with the range of the "
         "runs, names the machine (CPU, cores, Mesa, LLVM, Mitsuba) and warns when it was "
         "busy (1-minute load above 0.3 per core). Prints the tables and writes "
         "build/bench/*.json; the book's pages change only with --update-book."),
    Verb("gpu-check", "on a machine with a GPU: build, every chapter's image checks and the "
         "speed figures on its EGL device, one report, in 10 minutes", gpu_check_options,
         lambda args: gpu_check_command(args), "test",
         "Builds, lists the EGL devices and what the chosen one allows, runs every "
         "chapter's image checks with COURSE_GPU set, measures every chapter's samples per "
         "second, the BVH at a million triangles and the megakernel against the wavefront, "
         "and writes build/gpu-check/report.md (tools/gpu_check.sh runs it)."),
    Verb("windows-check", "build every chapter for Windows with MinGW-w64 and run their "
         "image checks under Wine (Debian)", windows_check_options, windows_check_command,
         "test", "Cross-builds the chapters as Windows programs (cmake --preset "
         "linux-mingw-cross, GLFW's Windows DLL from a pinned wheel), runs them under Wine "
         "on a virtual X server, where Wine's OpenGL is Mesa's llvmpipe, and runs the "
         "chapters' image checks marked 'windows' on their pictures. Installs MinGW-w64, "
         "Wine and Xvfb from Debian's packages when run as root."),
    Verb("release", "write a student starter for a chapter", release_options, commands.cmd_release,
         "book", "Copies the checkpoint with every BEGIN/END SOLUTION block replaced by its "
         "TODO hint and STUB lines, with the chapter's page rendered against that code "
         "(book/)."),
    Verb("grade", "grade a student submission of a chapter", grade_options, commands.cmd_grade,
         "grade", "Builds and runs the submission headless in a sandbox (another user, no "
         "network, limits; nothing of the instructor's readable) and compares its images "
         "with the solution's."),
    Verb("check", "grade your own work on a chapter as a grader would, and name the "
         "known mistake it looks like", check_options, commands.cmd_check, "grade",
         "For learners outside a class: your folder (a starter you filled in) is graded "
         "against this repository's solution, hidden tests shown; where a test fails, the "
         "report says which of the chapter's catalogued mistakes the pictures look like "
         "and where the book explains it."),
    Verb("autograder", "build a Gradescope autograder zip", autograder_options,
         commands.cmd_autograder, "grade"),
]

# The set-up layer each verb needs (the book's set-up page shows this table).
VERB_LAYERS = {verb.name: verb.layer for verb in VERBS if verb.layer}


def parser() -> argparse.ArgumentParser:
    top = argparse.ArgumentParser(
        prog="./course", description="The GPU ray tracing course. Start with: ./course run")
    verbs = top.add_subparsers(dest="verb", metavar="VERB")
    for verb in VERBS:
        verb.options(verbs.add_parser(verb.name, help=verb.help,
                                      description=verb.description or None))
    return top


def set_up_and_enter_venv(layer: str):
    """Sets up `layer`, then runs this command again in .venv (unless already there)."""
    from course_tools.setup import machine_setup
    if os.environ.get("COURSE_LAYER_READY") != layer:
        try:
            machine_setup.ensure(layer)
        except machine_setup.SetupError as error:
            print(f"course: {error}", file=sys.stderr)
            sys.exit(error.code)
    python = machine_setup.venv_python()
    if Path(sys.prefix).resolve() != machine_setup.VENV.resolve():
        os.environ["COURSE_LAYER_READY"] = layer
        os.execv(str(python), [str(python), str(ROOT / "tools" / "course.py"), *sys.argv[1:]])


def main():
    top = parser()
    args, unknown = top.parse_known_args()
    if args.verb is None or args.verb == "help":
        top.print_help()
        return
    if unknown and args.verb != "run":
        top.error(f"unrecognised arguments: {' '.join(unknown)}")
    verb = next(verb for verb in VERBS if verb.name == args.verb)
    layer = args.layer if verb.name == "setup" else verb.layer
    if layer:
        set_up_and_enter_venv(layer)
    if verb.name == "run":
        args.options = list(args.options) + unknown
        if args.chapter and args.chapter.startswith("-"):
            args.options.insert(0, args.chapter)
            args.chapter = None
    verb.command(args)
