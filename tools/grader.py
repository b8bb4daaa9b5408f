"""The autograder: ./course grade NN --submission DIR.

A submission is a folder shaped like a starter (chapters/NN_name/, shaders/NN_name/).
Only those two folders are taken from it; everything else — the common layer, the
build flags, the tests, the reference images — is the instructor's, so a submission
cannot change how it is graded. The student's host code is compiled with the flags
CMake used for the solution and linked with the instructor's common layer; the program
runs headless in a scratch folder under CPU, wall-clock, file-size and output limits.
Images are compared with references rendered by the instructor's solution, kept in
build/grading/, outside any student's reach.

Writes Gradescope's results.json, a Markdown report with images (submission,
reference, error heatmap) and prints a table.
"""

from __future__ import annotations

import hashlib
import json
import os
import resource
import shlex
import shutil
import signal
import subprocess
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from grading_specs import SPECS, GradeTest

OUTPUT_LIMIT = 20_000          # characters of a program's output kept in a report
FILE_SIZE_LIMIT = 256 << 20    # bytes any one file the program writes may reach
# Per run. A hung GPU or driver is killed at WALL_SECONDS; the environment may lower
# both (the course's own tests of the grader do, to keep them short).
CPU_SECONDS = int(os.environ.get("COURSE_GRADE_CPU_SECONDS", 120))
WALL_SECONDS = int(os.environ.get("COURSE_GRADE_WALL_SECONDS", 180))
COMPILE_SECONDS = 300


@dataclass
class Outcome:
    test: GradeTest
    score: float = 0.0
    output: str = ""
    images: dict[str, str] = field(default_factory=dict)


# ---------------------------------------------------------------- running things

def _limit_resources():
    resource.setrlimit(resource.RLIMIT_CPU, (CPU_SECONDS, CPU_SECONDS + 5))
    resource.setrlimit(resource.RLIMIT_FSIZE, (FILE_SIZE_LIMIT, FILE_SIZE_LIMIT))
    resource.setrlimit(resource.RLIMIT_CORE, (0, 0))
    os.setsid()  # its own process group, so a timeout kills every child too


def run_limited(command: list[str], cwd: Path, timeout: float = WALL_SECONDS):
    """Runs a student's program; returns (exit code or None on timeout, output)."""
    log = cwd / ".output.log"
    env = {"PATH": os.environ.get("PATH", "/usr/bin:/bin"), "HOME": str(cwd),
           "TMPDIR": str(cwd), "LANG": "C.UTF-8"}
    for key in ("MESA_GL_VERSION_OVERRIDE", "LIBGL_ALWAYS_SOFTWARE", "GALLIUM_DRIVER"):
        if key in os.environ:
            env[key] = os.environ[key]
    with open(log, "wb") as sink:
        process = subprocess.Popen(command, cwd=cwd, stdout=sink, stderr=subprocess.STDOUT,
                                   stdin=subprocess.DEVNULL, env=env,
                                   preexec_fn=_limit_resources)
        try:
            code = process.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            os.killpg(process.pid, signal.SIGKILL)
            process.wait()
            code = None
    with open(log, "rb") as source:
        text = source.read(OUTPUT_LIMIT + 1).decode("utf-8", "replace")
    if len(text) > OUTPUT_LIMIT:
        text = text[:OUTPUT_LIMIT] + "\n[output cut at 20 000 characters]"
    log.unlink()
    return code, text


def describe_exit(code) -> str:
    if code is None:
        return f"did not finish within {WALL_SECONDS} s (killed)"
    if code == -signal.SIGXCPU:
        return f"used more than {CPU_SECONDS} s of CPU time (killed)"
    if code < 0:
        return f"crashed with signal {signal.Signals(-code).name}"
    return f"exit code {code}"


# ---------------------------------------------------------------- building

def object_key(root: Path, chapter: str, source_dir: Path, source: Path,
               arguments: list[str]) -> str:
    """What a compiled object depends on, hashed: the compiler's arguments (with the
    submission's folder and the output left out), the source, every header of the
    submission's chapter and shader folders, and the common layer's headers. Two
    submissions that share a file (a starter and its solution share all but a few)
    then share its object."""
    digest = hashlib.sha256()
    for argument in arguments:
        digest.update(argument.replace(str(source_dir), "<submission>").encode() + b"\0")
    headers = [*sorted((source_dir / "chapters" / chapter).glob("*.h")),
               *sorted((source_dir / "shaders" / chapter).glob("*.h")),
               *sorted((root / "common" / "course").glob("*.h"))]
    for path in [source, *headers]:
        digest.update(str(path.relative_to(source_dir if source_dir in path.parents
                                           else root)).encode() + b"\0")
        digest.update(path.read_bytes() + b"\0")
    return digest.hexdigest()


def compile_submission(root: Path, build: Path, chapter: str, source_dir: Path,
                       workdir: Path) -> tuple[Path | None, str]:
    """Compiles the submission's chapter sources like CMake compiled the solution.
    Objects are kept in build/grading/objects by what they depend on (object_key), so a
    file that many submissions leave as it was is compiled once."""
    commands = json.loads((build / "compile_commands.json").read_text())
    objects, log = [], ""
    cache = build / "grading" / "objects"
    cache.mkdir(parents=True, exist_ok=True)
    sources = sorted((source_dir / "chapters" / chapter).glob("*.cpp"))
    if not sources:
        return None, f"no .cpp files in chapters/{chapter}/ of the submission"
    for source in sources:
        original = root / "chapters" / chapter / source.name
        entry = next((c for c in commands if c["file"] == str(original)), None)
        if entry is None:  # a file the solution does not have: use main.cpp's flags
            entry = next(c for c in commands
                         if c["file"] == str(root / "chapters" / chapter / "main.cpp"))
        arguments = [a.replace(str(root / "chapters" / chapter),
                               str(source_dir / "chapters" / chapter))
                     .replace(str(root / "shaders" / chapter),
                              str(source_dir / "shaders" / chapter))
                     for a in shlex.split(entry["command"])]
        target = workdir / (source.stem + ".o")
        arguments[arguments.index("-c") + 1] = str(source)
        output_index = arguments.index("-o") + 1
        cached = cache / (object_key(root, chapter, source_dir, source,
                                     arguments[:output_index - 1] +
                                     arguments[output_index + 1:]) + ".o")
        arguments[output_index] = str(target)
        if cached.exists():
            shutil.copyfile(cached, target)
        else:
            code, output = run_limited(arguments, workdir, timeout=COMPILE_SECONDS)
            log += output
            if code != 0:
                return None, f"compiling {source.name} failed ({describe_exit(code)}):\n{log}"
            partial = cached.with_suffix(f".{os.getpid()}.partial")
            shutil.copyfile(target, partial)
            partial.replace(cached)  # whole or not at all, even with two graders at once
        objects.append(str(target))
    program = workdir / chapter
    link = ["g++", *objects, "-o", str(program), str(build / "common" / "libcourse_common.a"),
            str(build / "libglad.a"), "-lEGL", "-lglfw", "-ldl", "-lpthread"]
    code, output = run_limited(link, workdir, timeout=COMPILE_SECONDS)
    if code != 0:
        return None, f"linking failed ({describe_exit(code)}):\n{output}"
    return program, log


def copy_submission(submission: Path, chapter: str, destination: Path) -> str:
    """Copies only chapters/NN and shaders/NN, refusing links and oversized files."""
    notes = []
    for top in ("chapters", "shaders"):
        source = submission / top / chapter
        if not source.is_dir():
            notes.append(f"the submission has no {top}/{chapter}/ folder")
            continue
        for path in sorted(source.rglob("*")):
            relative = path.relative_to(submission)
            if path.is_symlink():
                notes.append(f"ignored the link {relative}")
                continue
            if path.is_file():
                if path.stat().st_size > 1 << 20:
                    notes.append(f"ignored {relative}: larger than 1 MiB")
                    continue
                target = destination / relative
                target.parent.mkdir(parents=True, exist_ok=True)
                shutil.copyfile(path, target)
    return "\n".join(notes)


# ---------------------------------------------------------------- images

def read_png(path: Path) -> np.ndarray:
    from PIL import Image
    return np.asarray(Image.open(path).convert("RGB"), dtype=np.float64)


def agreement(image: np.ndarray, reference: np.ndarray) -> tuple[float, float]:
    """(fraction of pixels within 2/255 in every channel, mean absolute error /255)."""
    error = np.abs(image - reference)
    return float(np.mean(np.all(error <= 2.0, axis=-1))), float(np.mean(error))


def image_score(fraction: float, mean_error: float) -> float:
    """Full marks at the course's bar (99.5% of pixels within 2/255, mean < 0.5/255);
    half marks for a near miss (98% of pixels right: an edge or a small region wrong);
    nothing below. Tiers, not a slope: most of a picture is easy (a starter that draws
    only the sky already has most pixels right), so a slope would pay for the sky."""
    if fraction >= 0.995 and mean_error < 0.5:
        return 1.0
    if fraction >= 0.98:
        return 0.5
    return 0.0


def write_heatmap(image: np.ndarray, reference: np.ndarray, path: Path):
    from matplotlib import colormaps
    from PIL import Image
    error = np.max(np.abs(image - reference), axis=-1) / 255.0
    colored = colormaps["inferno"](np.clip(error * 4.0, 0.0, 1.0))[..., :3]
    Image.fromarray((colored * 255).astype(np.uint8)).save(path)


# ---------------------------------------------------------------- grading

def reference_image(root: Path, build: Path, chapter: str, test: GradeTest) -> Path:
    """The solution's image for the test's arguments (the instructor's build, its own
    shaders), made once and kept; the file name carries a hash of the arguments, so a
    changed spec makes a new one."""
    folder = build / "grading" / chapter
    folder.mkdir(parents=True, exist_ok=True)
    digest = hashlib.sha256("\0".join(test.args).encode()).hexdigest()[:10]
    path = folder / f"{test.slug}-{digest}.png"
    if not path.exists():
        subprocess.run([str(build / "bin" / chapter), "--headless", *test.args,
                        "--out", str(path)], check=True, capture_output=True, timeout=600)
    return path


def statistical_references(root: Path, build: Path, chapter: str,
                           test: GradeTest) -> list[Path]:
    """The solution's PFMs a 'statistical' or 'traversal' test compares with
    (tools/grading_statistics.py: many samples at a few seeds, or chapter 11's distance
    and cost views), rendered once by the instructor's build and kept beside the
    reference images, each named by a hash of its arguments."""
    import grading_statistics
    for folder in (build / "grading", build / "grading" / chapter):
        folder.mkdir(exist_ok=True)
        os.chmod(folder, 0o700)  # only the grader's own user opens the references
    paths = []
    for arguments in grading_statistics.reference_arguments(test):
        digest = hashlib.sha256("\0".join(arguments).encode()).hexdigest()[:16]
        path = build / "grading" / chapter / f"{test.slug}-{digest}.pfm"
        if not path.exists():
            # A name of its own, then a rename: two graders may render the same one.
            partial = path.with_name(f".{path.stem}.{os.getpid()}.{id(arguments)}.pfm")
            subprocess.run([str(build / "bin" / chapter), "--headless", *arguments,
                            "--out", str(partial)], check=True, capture_output=True,
                           timeout=1800)
            partial.replace(path)
        paths.append(path)
    return paths


def grade_test(root: Path, build: Path, chapter: str, program: Path, test: GradeTest,
               workdir: Path, report_dir: Path, extra_args: list[str]) -> Outcome:
    """Runs the submission with the test's arguments plus extra_args (its shader folder);
    the reference is the solution's, with the test's arguments alone."""
    outcome = Outcome(test)
    if test.kind == "check":
        code, output = run_limited([str(program), *test.args, *extra_args], workdir)
        passed = code == 0 and test.expect in output
        outcome.score = test.max_score if passed else 0.0
        outcome.output = (("passed" if passed else f"failed: {describe_exit(code)}") +
                          f"\n{output.strip()}")
        return outcome

    if test.kind in ("statistical", "traversal"):
        # Random pictures by statistics, chapter 11's tree by its work within a band:
        # tools/grading_statistics.py, with this grader's runner and references.
        import grading_statistics
        return grading_statistics.grade_test(
            test, outcome, workdir, report_dir,
            run=lambda arguments, out: run_limited(
                [str(program), "--headless", *arguments, *extra_args, "--out", str(out)],
                workdir),
            references=lambda: statistical_references(root, build, chapter, test),
            describe=describe_exit)

    out = workdir / f"{test.slug}.png"
    code, output = run_limited([str(program), "--headless", *test.args, *extra_args,
                                "--out", str(out)], workdir)
    if code != 0 or not out.exists():
        outcome.output = f"the program {describe_exit(code)}, no image:\n{output.strip()}"
        return outcome
    reference_path = reference_image(root, build, chapter, test)
    image, reference = read_png(out), read_png(reference_path)
    if image.shape != reference.shape:
        outcome.output = f"image is {image.shape[1]}x{image.shape[0]}, expected " \
                         f"{reference.shape[1]}x{reference.shape[0]}"
        return outcome
    fraction, mean_error = agreement(image, reference)
    outcome.score = round(test.max_score * image_score(fraction, mean_error), 2)
    outcome.output = (f"{fraction:.2%} of pixels within 2/255 of the reference "
                      f"(full marks from 99.5%), mean error {mean_error:.2f}/255")
    shutil.copyfile(out, report_dir / f"{test.slug}_submission.png")
    shutil.copyfile(reference_path, report_dir / f"{test.slug}_reference.png")
    write_heatmap(image, reference, report_dir / f"{test.slug}_error.png")
    outcome.images = {kind: f"{test.slug}_{kind}.png"
                      for kind in ("submission", "reference", "error")}
    return outcome


def grade(root: Path, build: Path, chapter: str, submission: Path, out: Path,
          show_hidden: bool = False) -> dict:
    tests = SPECS[chapter[:2]]
    out.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(prefix="course-grade-") as scratch:
        scratch = Path(scratch)
        notes = copy_submission(submission, chapter, scratch / "submission")
        workdir = scratch / "run"
        workdir.mkdir()
        program, build_log = compile_submission(root, build, chapter,
                                                scratch / "submission", workdir)
        outcomes = []
        for test in tests:
            if program is None:
                outcomes.append(Outcome(test, 0.0, "the submission does not build:\n" +
                                        build_log[-OUTPUT_LIMIT:]))
                continue
            # The submission's shaders, not the solution's (but not for the reference):
            shader_args = ["--shader-dir", str(scratch / "submission" / "shaders" / chapter)]
            outcomes.append(grade_test(root, build, chapter, program, test, workdir, out,
                                       shader_args))
    results = {
        "score": round(sum(o.score for o in outcomes), 2),
        "output": f"chapter {chapter}" + (f"\n{notes}" if notes else ""),
        "tests": [{"name": o.test.name, "score": o.score, "max_score": o.test.max_score,
                   "output": o.output, "visibility": o.test.visibility} for o in outcomes],
    }
    (out / "results.json").write_text(json.dumps(results, indent=2))
    write_report(out, chapter, outcomes, results, notes, show_hidden)
    return results


def write_report(out: Path, chapter: str, outcomes: list[Outcome], results: dict,
                 notes: str, show_hidden: bool):
    total = sum(o.test.max_score for o in outcomes)
    lines = [f"# Grading report: chapter {chapter}", "",
             f"**Score: {results['score']} / {total}**", ""]
    if notes:
        lines += ["Notes on the submission:", "", *[f"- {n}" for n in notes.splitlines()], ""]
    lines += ["| test | score | visibility |", "|---|---|---|"]
    lines += [f"| {o.test.name} | {o.score} / {o.test.max_score} | {o.test.visibility} |"
              for o in outcomes]
    for o in outcomes:
        if o.test.visibility != "visible" and not show_hidden:
            continue
        lines += ["", f"## {o.test.name}", "", "```text", o.output.strip(), "```"]
        if o.images:
            lines += ["", "| submission | reference | error (brighter = worse) |",
                      "|---|---|---|",
                      "| " + " | ".join(f"![{k}]({v})" for k, v in o.images.items()) + " |"]
    (out / "report.md").write_text("\n".join(lines) + "\n")


def print_table(results: dict):
    width = max(len(t["name"]) for t in results["tests"]) + 2
    for t in results["tests"]:
        print(f"{t['name']:{width}} {t['score']:>6} / {t['max_score']:<4} {t['visibility']}")
    total = sum(t["max_score"] for t in results["tests"])
    print(f"{'total':{width}} {results['score']:>6} / {total}")
