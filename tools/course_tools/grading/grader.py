"""The autograder: ./course grade NN --submission DIR (one) or --submissions DIR (a class).

A submission is a folder shaped like a starter (chapters/NN_name/, shaders/NN_name/).
Only those two folders are taken from it; everything else — the common layer, the
build flags, the tests, the reference images — is the instructor's, so a submission
cannot change how it is graded. The student's host code is compiled with the flags
CMake used for the solution and linked with the instructor's common layer, both taken
from a read-only staging copy; it is compiled and run in a sandbox (tools/course_tools/grading/sandbox.py):
as another user, without network, with limits, with none of the instructor's files
readable. Images are compared with references rendered beforehand by the instructor's
solution, kept in build/grading/, outside the submission's reach.

Writes Gradescope's results.json, a Markdown report with images (submission,
reference, error heatmap) and prints a table; for a class, one folder of those per
student and a CSV summary.
"""

from __future__ import annotations

import csv
import hashlib
import io
import json
import os
import re
import shlex
import shutil
import signal
import stat
import subprocess
import tempfile
import threading
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from course_tools import chapters, cmake_cache, reference_cache
from course_tools.grading import denoised_grading, diagnosis, grading_statistics, sandbox
from course_tools.grading.sandbox import run_limited
from course_tools.grading.submission_files import (private_folder, read_regular, submitted_file,
                                                    write_atomically, write_new)
from course_tools.grading.grading_specs import SPECS, GradeTest

OUTPUT_LIMIT = sandbox.OUTPUT_KEPT  # characters of a program's output kept in a report
HEADER_SUFFIXES = {".h", ".hpp", ".hh", ".inl", ".ipp"}
STAGED_FILE_LIMIT = 32 << 20  # the benchmark's million-triangle teapot is not staged


@dataclass
class Outcome:
    test: GradeTest
    score: float = 0.0
    output: str = ""
    images: dict[str, str] = field(default_factory=dict)
    measurement: dict | None = None  # what the diagnosis compares (diagnosis.py)


# ---------------------------------------------------------------- running things

def describe_exit(code, output: str = "", timeout: float | None = None) -> str:
    limits = sandbox.current_limits()
    if code is None:
        return f"did not finish within {timeout or limits.wall_seconds} s (killed)"
    if code == "total":
        return (f"was stopped: the whole grading may take {limits.total_seconds} s, and "
                "they were spent")
    if code == "output":
        return f"printed more than {limits.output_mb} MiB (killed)"
    if code == "disk":
        return f"left more than {limits.disk_mb} MiB in its folder (killed)"
    if code == -signal.SIGXCPU:
        return f"used more than {limits.cpu_seconds} s of CPU time (killed)"
    if code == -signal.SIGXFSZ:
        return f"wrote a file larger than {limits.file_mb} MiB (killed)"
    if code < 0:
        text = f"crashed with signal {signal.Signals(-code).name}"
        if re.search(r"bad_alloc|Cannot allocate memory|out of memory", output, re.I):
            text += f" (out of memory: the limit is {limits.memory_mb} MiB)"
        return text
    text = f"exit code {code}"
    if "Resource temporarily unavailable" in output:
        text += f" (at most {limits.processes} processes and threads)"
    return text


# ---------------------------------------------------------------- staging

class Staging:
    """What compiling and linking a submission need from the instructor's tree — the
    include folders and the folders named by -D macros in the chapter's compile flags,
    the common layer's libraries — copied into a read-only folder outside the tree
    (sandbox base/staging/NN_name-HASH, made once per content). rewrite() points a
    compiler argument at the copies."""

    def __init__(self, root: Path, build: Path, chapter: str, arguments: list[str],
                 libraries: list[Path], base: Path):
        # Never staged, whatever the flags say: any chapter's solution (later chapters
        # carry earlier ones' code) and the references.
        secret = [root / "chapters", root / "shaders", build / "grading", build / "bin"]
        prefixes = sorted({str(build): "build", str(root): "source"}.items(),
                          key=lambda item: -len(item[0]))
        self.prefixes = prefixes
        self.pattern = re.compile("(?:" + "|".join(re.escape(p) for p, _ in prefixes) +
                                  r")(?:/[^\s\"']*)?(?=[\s\"']|$)")
        wanted: dict[Path, str] = {}  # instructor's path -> "headers" | "all"
        previous = ""
        for argument in arguments:
            include = argument.startswith(("-I", "-isystem", "-iquote")) or \
                previous in ("-I", "-isystem", "-iquote")
            for match in self.pattern.finditer(argument):
                path = Path(match.group(0))
                if any(path == s or s in path.parents or path in s.parents for s in secret):
                    continue
                if path.exists() and wanted.get(path) != "all":
                    wanted[path] = "headers" if include and path.is_dir() else "all"
            previous = argument
        for library in libraries:
            wanted[library] = "all"
        files: list[tuple[Path, Path]] = []  # (instructor's file, staged relative path)
        for path, kind in sorted(wanted.items()):
            candidates = sorted(p for p in path.rglob("*") if p.is_file()) \
                if path.is_dir() else [path]
            for file in candidates:
                if file.is_symlink() and not file.resolve().is_file():
                    continue
                if kind == "headers" and file.suffix not in HEADER_SUFFIXES:
                    continue
                # Big data files stay out; the libraries, which linking needs, never do
                # (with debug information they pass 32 MiB on some compilers).
                if file.stat().st_size > STAGED_FILE_LIMIT and path not in libraries:
                    continue
                files.append((file, self.relative(file)))
        # Named by the files' contents, not their times: a clean clone of the same tree
        # stages to the same folder, so its compiler arguments, and the objects kept
        # under them (object_cache), are the same as the last clone's.
        digest = hashlib.sha256()
        for file, relative in files:
            digest.update(f"{relative}\0{reference_cache.file_digest(file)}\0".encode())
        folder = sandbox.prepare_base(base) / "staging"
        folder.mkdir(exist_ok=True)
        os.chmod(folder, 0o711)
        self.path = folder / f"{chapter}-{digest.hexdigest()[:16]}"
        if not self.path.is_dir():
            self._make(files)
        os.utime(self.path)
        self._prune(folder, chapter)

    def relative(self, path: Path) -> Path:
        text = str(path)
        for prefix, name in self.prefixes:
            if text == prefix or text.startswith(prefix + "/"):
                return Path(name) / text[len(prefix):].lstrip("/")
        raise ValueError(f"{path} is not in the instructor's tree")

    def staged(self, path: Path) -> Path:
        return self.path / self.relative(path)

    def rewrite(self, argument: str) -> str:
        return self.pattern.sub(lambda m: str(self.staged(Path(m.group(0)))), argument)

    def _make(self, files):
        partial = self.path.with_name(f".{self.path.name}.{os.getpid()}."
                                      f"{threading.get_ident()}")
        for file, relative in files:
            target = partial / relative
            target.parent.mkdir(parents=True, exist_ok=True)
            shutil.copyfile(file, target)
            os.chmod(target, 0o644)
        for directory, _, _ in os.walk(partial):
            os.chmod(directory, 0o755)
        try:
            partial.rename(self.path)
        except OSError:  # another grader made the same one meanwhile
            shutil.rmtree(partial, ignore_errors=True)

    @staticmethod
    def _prune(folder: Path, chapter: str, age_seconds: float = 86400):
        """Copies of an older build of the chapter, unused for a day, go."""
        for old in folder.glob(f"{chapter}-*"):
            try:
                if time.time() - old.stat().st_mtime > age_seconds:
                    shutil.rmtree(old, ignore_errors=True)
            except FileNotFoundError:
                pass


# ---------------------------------------------------------------- building

def object_key(arguments: list[str], source: Path, source_dir: Path, chapter: str) -> str:
    """What the compiler is told, hashed: its arguments as they are (the output left
    out; paths in -D macros end up in the object, so they must be the same: a grading's
    folders are the same for each grading in a sandbox slot), the source, and the names
    of every file in the submission's chapter and shader folders (a file that is only
    tested for, with __has_include, changes nothing else). What it then reads is the
    second half of the key (dependency_digest): objects kept by object_key alone would
    let a submission that shadows a header poison the next one's object."""
    digest = hashlib.sha256()
    for argument in [*arguments, str(source)]:
        digest.update(argument.encode() + b"\0")
    digest.update(source.read_bytes() + b"\0")
    for top in ("chapters", "shaders"):
        folder = source_dir / top / chapter
        for path in sorted(folder.rglob("*")):
            digest.update(str(path.relative_to(source_dir)).encode() + b"\0")
    return digest.hexdigest()


def placeholder(text: str, places: list[tuple[str, str]]) -> str:
    for real, name in places:
        text = text.replace(real, name)
    return text


def real_path(name: str, places: list[tuple[str, str]]) -> str:
    for real, placeholder_name in places:
        if name.startswith(placeholder_name):
            return real + name[len(placeholder_name):]
    return name


def dependency_digest(names: list[str], places: list[tuple[str, str]]) -> str | None:
    """The contents of every file the compiler read, hashed; None when one is gone or
    is not a regular file (then nothing is kept)."""
    digest = hashlib.sha256()
    for name in names:
        path = real_path(name, places)
        if not os.path.isabs(path):
            return None
        try:
            status = os.stat(path)
            if not stat.S_ISREG(status.st_mode) or status.st_size > 64 << 20:
                return None
            with open(path, "rb") as source:
                digest.update(name.encode() + b"\0" + source.read() + b"\0")
        except OSError:
            return None
    return digest.hexdigest()


def parse_dependencies(text: str) -> list[str]:
    """The prerequisites of a make rule as gcc -MD writes it."""
    text = text.replace("\\\n", " ")
    _, _, prerequisites = text.partition(": ")
    words = re.split(r"(?<!\\)\s+", prerequisites.strip())
    return [w.replace("\\ ", " ") for w in words if w]


def cached_object(folder: Path, places) -> Path | None:
    for dependencies in sorted(folder.glob("*.deps")):
        digest = dependency_digest(json.loads(dependencies.read_text()), places)
        if digest and (folder / f"{digest}.o").exists():
            return folder / f"{digest}.o"
    return None


def keep_object(folder: Path, target: Path, depfile: Path, places):
    """Keeps a freshly compiled object under what it was compiled from. The object and
    the dependency list are read safely: they sit in the submission's folder."""
    try:
        data = read_regular(target, 1 << 30)
        names = [placeholder(p, places)
                 for p in parse_dependencies(read_regular(depfile, 16 << 20).decode())]
    except (OSError, ValueError, UnicodeDecodeError):
        return
    digest = dependency_digest(names, places)
    if digest is None:
        return
    folder.mkdir(parents=True, exist_ok=True)
    listing = json.dumps(names).encode()
    write_atomically(folder / f"{hashlib.sha256(listing).hexdigest()[:16]}.deps", listing)
    write_atomically(folder / f"{digest}.o", data)


def object_cache(build: Path) -> Path:
    """Where compiled objects are kept: in the per-user reference cache when there is one,
    hidden from submissions as it is, so that a clean clone of the same tree finds the
    objects of the last (their keys name every argument and every file read); else in
    the build."""
    kept = reference_cache.folder()
    if kept is not None:
        return private_folder(private_folder(kept) / "objects")
    return private_folder(build / "grading" / "objects")


def compile_submission(root: Path, build: Path, chapter: str, source_dir: Path,
                       workdir: Path) -> tuple[Path | None, str]:
    """Compiles the submission's chapter sources like CMake compiled the solution. In a
    grading (an active sandbox) the flags point at the staging copy instead of the
    instructor's tree, and the compiler runs in the sandbox. Objects are kept
    (object_cache) by what they depend on (object_key, dependency_digest), so a file
    that many submissions leave as it was is compiled once, in this clone or the last."""
    box = sandbox.active()
    limits = sandbox.current_limits()
    commands = json.loads((build / "compile_commands.json").read_text())
    chapter_commands = [c for c in commands
                        if c["file"].startswith(str(root / "chapters" / chapter) + "/")]
    objects, log = [], ""
    cache = object_cache(build)
    for old in cache.glob("*.o"):  # kept by an older grader, by object_key alone
        old.unlink(missing_ok=True)
    sources = sorted((source_dir / "chapters" / chapter).glob("*.cpp"))
    if not sources:
        return None, f"no .cpp files in chapters/{chapter}/ of the submission"
    libraries = [build / "common" / "libcourse_common.a", build / "libglad.a"]

    def submission_arguments(entry) -> list[str]:
        """The flags with the chapter's folders replaced by the submission's."""
        return [a.replace(str(root / "chapters" / chapter),
                          str(source_dir / "chapters" / chapter))
                .replace(str(root / "shaders" / chapter), str(source_dir / "shaders" / chapter))
                for a in shlex.split(entry["command"])]

    staging = None
    if box is not None:
        staging = Staging(root, build, chapter,
                          [a for c in chapter_commands for a in submission_arguments(c)],
                          libraries, box.base)
        libraries = [staging.staged(library) for library in libraries]
    places = [(str(source_dir), "<submission>")]
    if staging is not None:
        places.insert(0, (str(staging.path), "<staging>"))
    for source in sources:
        original = root / "chapters" / chapter / source.name
        entry = next((c for c in chapter_commands if c["file"] == str(original)), None)
        if entry is None:  # a file the solution does not have: use main.cpp's flags
            entry = next(c for c in chapter_commands
                         if c["file"] == str(root / "chapters" / chapter / "main.cpp"))
        arguments = submission_arguments(entry)
        if staging is not None:
            arguments = [staging.rewrite(a) for a in arguments]
        target = workdir / (source.stem + ".o")
        arguments[arguments.index("-c") + 1] = str(source)
        output_index = arguments.index("-o") + 1
        key = object_key(arguments[:output_index - 1] + arguments[output_index + 1:],
                         source, source_dir, chapter)
        arguments[output_index] = str(target)
        cached = cached_object(cache / key, places)
        if cached is not None:
            write_new(target, cached.read_bytes())
        else:
            depfile = workdir / (source.stem + ".d")
            code, output = run_limited([*arguments, "-MD", "-MF", str(depfile)], workdir,
                                       timeout=limits.compile_seconds)
            log += output
            if code != 0:
                return None, (f"compiling {source.name} failed "
                              f"({describe_exit(code, output, limits.compile_seconds)}):\n{log}")
            keep_object(cache / key, target, depfile, places)
        objects.append(str(target))
    program = workdir / chapter
    link = ["g++", *objects, "-o", str(program), *map(str, libraries),
            *system_libraries(build, chapter), "-lpthread"]
    code, output = run_limited(link, workdir, timeout=limits.compile_seconds)
    if code != 0:
        return None, (f"linking failed ({describe_exit(code, output, limits.compile_seconds)})"
                      f":\n{output}")
    return program, log


def system_libraries(build: Path, chapter: str) -> list[str]:
    """What the solution's program links besides the course's own two libraries, as
    CMake wrote it into build.ninja (GLFW, EGL, OpenGL, OpenEXR and what those need):
    the same link line, whichever packages and versions this machine has. Kept in
    build/grading/NN/link-libraries.txt, so that a prepared autograder needs no
    build.ninja."""
    kept = private_folder(build / "grading" / chapter) / "link-libraries.txt"
    ninja = build / "build.ninja"
    if not ninja.exists():
        if not kept.exists():
            raise FileNotFoundError(f"neither {ninja} nor {kept}: was this autograder "
                                    "prepared (./course grade NN --prepare)?")
        return kept.read_text().split("\n")[:-1]
    block = re.search(rf"^build bin/{re.escape(chapter)}: .*?\n((?:  .*\n)*)",
                      ninja.read_text(), re.M)
    line = re.search(r"^  LINK_LIBRARIES = (.*)$", block.group(1), re.M) if block else None
    if line is None:
        raise FileNotFoundError(f"no link line for bin/{chapter} in {ninja}")
    own = {"common/libcourse_common.a", "libglad.a"}
    libraries = [word for word in shlex.split(line.group(1)) if word not in own]
    text = "".join(f"{word}\n" for word in libraries)
    if not kept.exists() or kept.read_text() != text:
        kept.write_text(text)
    return libraries


def copy_submission(submission: Path, chapter: str, destination: Path) -> str:
    """Copies only chapters/NN and shaders/NN, refusing links (anywhere on the way, so
    that a submission cannot hand in the instructor's folder by pointing at it),
    special files and oversized files."""
    notes = []
    base = submission.resolve()
    for top in ("chapters", "shaders"):
        source = submission / top / chapter
        for step in (submission / top, source):
            if step.is_symlink():
                notes.append(f"ignored the link {step.relative_to(submission)}")
                break
        else:
            if not source.is_dir():
                notes.append(f"the submission has no {top}/{chapter}/ folder")
                continue
            for path in sorted(source.rglob("*")):
                relative = path.relative_to(submission)
                if path.is_symlink() or base not in path.resolve().parents:
                    notes.append(f"ignored the link {relative}")
                    continue
                if path.is_dir():
                    continue
                if not path.is_file():
                    notes.append(f"ignored {relative}: not a regular file")
                    continue
                if path.stat().st_size > 1 << 20:
                    notes.append(f"ignored {relative}: larger than 1 MiB")
                    continue
                target = destination / relative
                target.parent.mkdir(parents=True, exist_ok=True)
                shutil.copyfile(path, target, follow_symlinks=False)
    return "\n".join(notes)


# ---------------------------------------------------------------- images

def read_png(source: Path | bytes) -> np.ndarray:
    """A PNG file, or a submission's PNG already read (read_regular): never more than
    16 million pixels, so that a crafted file cannot take the grader's memory."""
    from PIL import Image
    image = Image.open(io.BytesIO(source) if isinstance(source, bytes) else source)
    if image.width * image.height > 1 << 24:
        raise ValueError(f"{image.width}x{image.height} pixels is too large")
    return np.asarray(image.convert("RGB"), dtype=np.float64)


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
    shaders, run by the grader's own user, never in a submission's sandbox), made once
    and kept in build/grading, which only that user can open; the file name carries a
    hash of the arguments, so a changed spec makes a new one."""
    private_folder(build / "grading")
    folder = private_folder(build / "grading" / chapter)
    digest = hashlib.sha256("\0".join(test.args).encode()).hexdigest()[:10]
    path = folder / f"{test.slug}-{digest}.png"
    if not path.exists():
        render_reference(root, build, chapter, test.args, path, timeout=600,
                         inputs=test.inputs)
    return path


# What makes a reference besides its arguments, per (root, build, chapter): worked out
# once per process (hashing the sources and assets takes a moment).
_MAKERS: dict[tuple[str, str, str], str] = {}
_MAKERS_LOCK = threading.Lock()
# Settings of Mesa's that could change its pictures: they are part of a reference's key.
RENDERER_VARIABLES = ("LP_", "GALLIUM_", "MESA_", "LIBGL_", "DRI_", "__GLX_", "EGL_")


def build_file_for(root: Path, chapter: str) -> str:
    """The top CMakeLists.txt as it bears on one chapter: without the other chapters'
    add_chapter lines, which build other programs, so that a new chapter leaves every
    other chapter's references (and the renders and figures keyed by them) as they
    were. Every other line counts."""
    lines = (root / "CMakeLists.txt").read_text().splitlines()
    return "\n".join(line for line in lines
                     if not (found := chapters.ADD_CHAPTER.match(line))
                     or found.group(1) == chapter)


def reference_maker(root: Path, build: Path, chapter: str) -> str:
    """A digest of everything besides the arguments that decides the solution's
    pictures: the checkpoint's sources and shaders, the common layer, the build files
    (the top CMakeLists.txt without the other chapters' lines: build_file_for),
    the assets (committed and generated; a scene as its reader reads it, without its
    comments: reference_cache.scene_as_read), the compiler and its flags, the GL that
    renders (its renderer and version strings name Mesa and LLVM) and Mesa's settings
    in the environment. None of it is the submission's."""
    remembered = (str(root), str(build), chapter)
    with _MAKERS_LOCK:
        if remembered in _MAKERS:
            return _MAKERS[remembered]
    cache = cmake_cache.options(build)
    compiler = cache.get("CMAKE_CXX_COMPILER", "c++")
    version = subprocess.run([compiler, "--version"], capture_output=True, text=True,
                             timeout=60).stdout
    probe = subprocess.run([str(build / "bin" / chapter), "--headless",
                            "--probe-loop-limit", "--json"], capture_output=True, text=True,
                           timeout=120)
    gl = json.loads(probe.stdout) if probe.returncode == 0 else {}
    settings = sorted((k, v) for k, v in os.environ.items() if k.startswith(RENDERER_VARIABLES)
                      and not k.startswith("MESA_SHADER_CACHE"))
    maker = reference_cache.key(
        "grading reference", chapter,
        reference_cache.tree_digest(root / "chapters" / chapter, root / "shaders" / chapter,
                                    root / "common", root / "cmake", root / "third_party",
                                    root / "assets", build / "assets", scenes_as_read=True),
        build_file_for(root, chapter),
        version, *(f"{k}={cache.get(k, '')}" for k in sorted(cache)
                   if k.startswith(("CMAKE_BUILD_TYPE", "CMAKE_CXX_FLAGS", "COURSE_"))),
        gl.get("renderer", "unknown renderer"), gl.get("gl_version", "unknown version"),
        gl.get("backend", ""), *(f"{k}={v}" for k, v in settings))
    with _MAKERS_LOCK:
        _MAKERS[remembered] = maker
    return maker


def render_reference(root: Path, build: Path, chapter: str, arguments: list[str],
                     path: Path, timeout: float, inputs: tuple[str, ...] = ()):
    """Renders the solution's picture for `arguments` into path, or copies it from the
    per-user reference cache (tools/course_tools/reference_cache.py) when the same sources, assets,
    compiler and GL made it before. The program runs in a folder of its own holding
    the test's input files. A name of its own, then a rename: two graders may render
    the same one at once."""
    program = build / "bin" / chapter
    if not program.exists():
        raise FileNotFoundError(f"no reference {path.name} and no {program} to render "
                                "it (was this autograder prepared for other tests?)")
    partial = path.with_name(f".{path.stem}.{os.getpid()}.{threading.get_ident()}"
                             f"{path.suffix}")
    name = None
    if (root / "chapters" / chapter).is_dir() and reference_cache.folder() is not None:
        name = reference_cache.key(reference_maker(root, build, chapter),
                                   *arguments) + path.suffix
        kept = reference_cache.fetch(name)
        if kept is not None:
            write_new(partial, kept, 0o600)
            partial.replace(path)
            return
    with tempfile.TemporaryDirectory(prefix="course-reference-") as folder:
        for input_name in inputs:
            shutil.copyfile(build / "assets" / input_name, Path(folder) / Path(input_name).name)
        # A step's allowance as in the submissions' runs (sandbox.GRADING_GPU_STEP_SECONDS).
        environment = dict(os.environ)
        environment.setdefault("COURSE_GPU_TIMEOUT_SECONDS",
                               str(sandbox.GRADING_GPU_STEP_SECONDS))
        subprocess.run([str(program), "--headless", *arguments, "--out", str(partial)],
                       check=True, capture_output=True, timeout=timeout, cwd=folder,
                       env=environment)
    if name is not None:
        reference_cache.store(name, partial.read_bytes())
    partial.replace(path)


def statistical_references(root: Path, build: Path, chapter: str,
                           test: GradeTest) -> list[Path]:
    """The solution's PFMs a 'statistical' or 'traversal' test compares with
    (tools/course_tools/grading/grading_statistics.py: many samples at a few seeds, or chapter 13's distance
    and cost views), rendered once by the instructor's build and kept beside the
    reference images, each named by a hash of its arguments."""
    for folder in (build / "grading", build / "grading" / chapter):
        folder.mkdir(exist_ok=True)
        os.chmod(folder, 0o700)  # only the grader's own user opens the references
    paths = []
    for arguments in grading_statistics.reference_arguments(test):
        digest = hashlib.sha256("\0".join(arguments).encode()).hexdigest()[:16]
        path = build / "grading" / chapter / f"{test.slug}-{digest}.pfm"
        if not path.exists():
            render_reference(root, build, chapter, arguments, path, timeout=1800,
                             inputs=test.inputs)
        paths.append(path)
    return paths


def drop_stale_references(root: Path, build: Path, chapter: str):
    """build/grading/NN's references name only their arguments: those a changed solution
    made (its sources, a scene file, the compiler or the GL: reference_maker) are
    removed, so that they are made again. The folder's `made-by` says which made them.
    An autograder image, whose sources are gone after --prepare, keeps its own."""
    if not (root / "chapters" / chapter).is_dir():
        return
    private_folder(build / "grading")
    folder = private_folder(build / "grading" / chapter)
    maker, mark = reference_maker(root, build, chapter), folder / "made-by"
    if not mark.exists() or mark.read_text() != maker:
        for stale in [*folder.glob("*.png"), *folder.glob("*.pfm"),
                      *folder.glob(SIGNATURES)]:
            stale.unlink()
        mark.write_text(maker)


def prepare_references(root: Path, build: Path, chapter: str) -> list[Path]:
    """Every reference image of the chapter's tests, rendered before any submission's
    code runs (and before an autograder image loses the solution's sources); those a
    changed solution made before are made again (drop_stale_references)."""
    drop_stale_references(root, build, chapter)
    paths = []
    for test in SPECS[chapter[:2]]:
        if test.kind == "image":
            paths.append(reference_image(root, build, chapter, test))
        elif test.kind in grading_statistics.KINDS:
            paths += statistical_references(root, build, chapter, test)
    return paths


def prepare(root: Path, build: Path, chapter: str) -> list[Path]:
    """./course grade NN --prepare: the references, the catalogued mistakes' signatures,
    and a mark saying that grading may go on without the solution's sources (an
    autograder image removes them after this)."""
    references = prepare_references(root, build, chapter)
    signatures = prepare_signatures(root, build, chapter)
    if signatures is not None:
        references.append(signatures)
    system_libraries(build, chapter)  # the link line, kept beside the references
    (build / "grading" / chapter / "prepared").write_text(
        "".join(f"{p.name}\n" for p in references))
    return references


def is_prepared(build: Path, chapter: str) -> bool:
    return (build / "grading" / chapter / "prepared").exists()


def copy_inputs(build: Path, test: GradeTest, folder: Path):
    """The test's input files (GradeTest.inputs), copied into the folder a program runs
    in, readable by the submission's user."""
    for name in test.inputs:
        target = folder / Path(name).name
        if not target.exists():
            shutil.copyfile(build / "assets" / name, target)
            os.chmod(target, 0o644)


class KeptRuns:
    """A submission's successful runs, kept and replayed when nothing that makes them
    has changed: for the course's own suite, which grades the same catalogue variants
    and starters on every run (tests/python/tools/test_grading_statistics.py), and for an
    instructor regrading a class after changing the points (--keep-runs).

    A run's file and printed text are kept in the per-user reference cache
    (tools/course_tools/reference_cache.py) under a key made of reference_maker's (the solution's
    tree, the common layer, the build files, assets, compiler and flags, the GL that
    renders and Mesa's settings), the submission's own files as graded and the run's
    arguments: a program with the same sources run the same way on the same GL writes
    the same file (the grader's references rest on the same fact). A run that failed
    is never kept, so it is run again; the grading's statistics always run anew."""

    def __init__(self, root: Path, build: Path, chapter: str, source: Path):
        self.prefix = reference_cache.key(
            "submission run", reference_maker(root, build, chapter),
            reference_cache.tree_digest(source / "chapters" / chapter,
                                        source / "shaders" / chapter))
        self.replayed = 0
        self.made = 0

    def run(self, arguments: list[str], out: Path | None, runner):
        """runner() runs the program for real (writing out, if any); returns (exit
        code, output) as sandbox.run_limited does, from the cache when this run was kept."""
        name = reference_cache.key(self.prefix, *arguments,
                                   out.suffix if out is not None else "") + ".run"
        kept = reference_cache.fetch(name)
        if kept is not None:
            length = int.from_bytes(kept[:8], "little")
            output, data = kept[8:8 + length].decode(), kept[8 + length:]
            if out is not None:
                if out.exists() or out.is_symlink():
                    out.unlink()
                write_new(out, data)
            self.replayed += 1
            return 0, output
        code, output = runner()
        data = b""
        if code == 0 and out is not None:
            data, _ = submitted_file(out)
        if code == 0 and data is not None:
            text = output.encode()
            reference_cache.store(name, len(text).to_bytes(8, "little") + text + data)
            self.made += 1
        return code, output


def grade_test(root: Path, build: Path, chapter: str, program: Path, test: GradeTest,
               workdir: Path, report_dir: Path, extra_args: list[str],
               kept: KeptRuns | None = None,
               first_seed: int = grading_statistics.SUBMISSION_SEED) -> Outcome:
    """Runs the submission with the test's arguments plus extra_args (its shader folder);
    the reference is the solution's, with the test's arguments alone. With kept, runs
    whose inputs have not changed since they were kept are replayed. A random picture's
    runs start at first_seed (the catalogued mistakes' signatures use other seeds)."""
    outcome = Outcome(test)
    copy_inputs(build, test, workdir)

    def run(arguments: list[str], out: Path | None = None):
        command = [str(program), *arguments, *extra_args,
                   *(["--out", str(out)] if out is not None else [])]
        if kept is None:
            return run_limited(command, workdir)
        return kept.run(arguments, out, lambda: run_limited(command, workdir))

    if test.kind == "check":
        code, output = run(test.args)
        passed = code == 0 and test.expect in output
        outcome.score = test.max_score if passed else 0.0
        outcome.output = (("passed" if passed else f"failed: {describe_exit(code, output)}") +
                          f"\n{output.strip()}")
        return outcome

    if test.kind in grading_statistics.KINDS:
        # Random pictures by statistics, chapter 13's tree by its work within a band
        # (grading_statistics.py), a denoiser against the solution's filter
        # (denoised_grading.py), with this grader's runner and references.
        judge = (denoised_grading.grade_test if test.kind == "denoised"
                 else grading_statistics.grade_test)
        return judge(
            test, outcome, workdir, report_dir,
            run=lambda arguments, out: run(["--headless", *arguments], out),
            references=lambda: statistical_references(root, build, chapter, test),
            describe=describe_exit, first_seed=first_seed)

    out = workdir / f"{test.slug}.png"
    outcome.measurement = diagnosis.stopped("image", "failed")
    code, output = run(["--headless", *test.args], out)
    # Read once, safely (no link followed), after every process of the run is gone.
    png, problem = submitted_file(out) if code == 0 else (None, "")
    if png is None:
        why = describe_exit(code, output) if code != 0 else f"exited 0 but {problem}"
        outcome.output = f"the program {why}, no image:\n{output.strip()}"
        return outcome
    reference_path = reference_image(root, build, chapter, test)
    try:
        image = read_png(png)
    except Exception as error:  # noqa: BLE001 - whatever the file is, it is not an image
        outcome.output = f"the program's {out.name} is not a readable PNG: {error}"
        return outcome
    reference = read_png(reference_path)
    if image.shape != reference.shape:
        outcome.output = f"image is {image.shape[1]}x{image.shape[0]}, expected " \
                         f"{reference.shape[1]}x{reference.shape[0]}"
        return outcome
    fraction, mean_error = agreement(image, reference)
    outcome.measurement = diagnosis.image_measurement(image, reference)
    outcome.score = round(test.max_score * image_score(fraction, mean_error), 2)
    outcome.output = (f"{fraction:.2%} of pixels within 2/255 of the reference "
                      f"(full marks from 99.5%), mean error {mean_error:.2f}/255")
    (report_dir / f"{test.slug}_submission.png").write_bytes(png)
    shutil.copyfile(reference_path, report_dir / f"{test.slug}_reference.png")
    write_heatmap(image, reference, report_dir / f"{test.slug}_error.png")
    outcome.images = {kind: f"{test.slug}_{kind}.png"
                      for kind in ("submission", "reference", "error")}
    return outcome


def sensitive_paths(root: Path, build: Path, chapter: str) -> list[Path]:
    """What a submission must not be able to read: a sample of the instructor's tree
    (the solution, the specs, the tests), the build (its programs and flags), the
    references, the object cache and the per-user reference cache."""
    grading = build / "grading"
    paths = [root / "CMakeLists.txt", root / "tools" / "grading_specs.py",
             root / "chapters" / chapter / "main.cpp", root / "shaders" / chapter,
             root / "tests" / "python" / "tools" / "test_grading.py", build / "compile_commands.json",
             build / "bin" / chapter, grading / chapter, object_cache(build)]
    paths += sorted((grading / chapter).glob("*.p[nf]m"))[:1]  # a PNG or PFM reference
    kept = reference_cache.folder()
    if kept is not None:
        paths.append(kept)
    return paths


def grade(root: Path, build: Path, chapter: str, submission: Path, out: Path,
          show_hidden: bool = False, hide=(), close=(), keep_runs: bool = False,
          kept_counts: dict | None = None,
          first_seed: int = grading_statistics.SUBMISSION_SEED,
          measured: dict | None = None, diagnose: bool = True) -> dict:
    """Grades one submission into out (results.json, report.md, images). hide, close:
    more folders the submission must not see (a class's other submissions and
    results), covered in its mount namespace and closed to other users. keep_runs:
    replay the submission's runs kept from an earlier grading of the same files
    (KeptRuns); kept_counts, if given, gets how many were replayed and made.
    When a test fails and the chapter's mistake signatures were prepared, the results
    say which catalogued mistake the pictures look like (diagnosis.py); measured, if
    given, gets each test's measurement; first_seed moves a random picture's runs to
    other seeds (the signatures' own runs)."""
    tests = SPECS[chapter[:2]]
    out.mkdir(parents=True, exist_ok=True)
    prepare_references(root, build, chapter)  # as this user, before any student code
    # The handed-in folder is closed too: where the kernel refuses a mount namespace (a
    # chroot, some containers), permissions are all that keep it from the running copy.
    kept = reference_cache.folder()  # the reference cache: 0700, and covered too
    kept = [kept] if kept is not None and kept.is_dir() else []
    with sandbox.Sandbox(hide=[root, build, submission, out, *kept, *hide],
                         close=[root, build, submission, *close]) as box:
        source = box.folder("submission", writable=False)
        notes = copy_submission(submission, chapter, source)
        box.seal(source)
        workdir = box.folder("run", writable=True)
        problems = box.check_access(
            sensitive_paths(root, build, chapter) + [submission],
            [root, build, build / "grading", out, box.base, source])
        if problems and box.root:
            raise sandbox.SandboxError("refusing to grade: the submission's user could "
                                       "reach what it must not:\n  " + "\n  ".join(problems))
        program, build_log = compile_submission(root, build, chapter, source, workdir)
        kept = KeptRuns(root, build, chapter, source) if keep_runs else None
        outcomes = []
        for test in tests:
            if program is None:
                outcomes.append(Outcome(test, 0.0, "the submission does not build:\n" +
                                        build_log[-OUTPUT_LIMIT:]))
                continue
            # The submission's shaders, not the solution's (but not for the reference):
            shader_args = ["--shader-dir", str(source / "shaders" / chapter)]
            outcomes.append(grade_test(root, build, chapter, program, test, workdir, out,
                                       shader_args, kept, first_seed))
        protections = box.protections() + [f"NOT kept from the submission: {p}"
                                           for p in problems]
    if kept is not None and kept_counts is not None:
        kept_counts.update(replayed=kept.replayed, made=kept.made)
    measurements = {o.test.slug: o.measurement for o in outcomes
                    if o.measurement is not None}
    if measured is not None:
        measured.update(measurements)
    found = None
    if diagnose and any(o.score < o.test.max_score for o in outcomes):
        found = diagnosis.diagnose(measurements, load_signatures(build, chapter))
    looks_like = diagnosis.describe(found)
    results = {
        "score": round(sum(o.score for o in outcomes), 2),
        "output": f"chapter {chapter}" + (f"\n{notes}" if notes else "") +
                  (f"\n\n{looks_like}" if looks_like else ""),
        "tests": [{"name": o.test.name, "score": o.score, "max_score": o.test.max_score,
                   "output": o.output + (f"\n\n{looks_like}" if looks_like and
                                         o.score < o.test.max_score else ""),
                   "visibility": o.test.visibility} for o in outcomes],
    }
    if found is not None:
        results["extra_data"] = {"diagnosis": found}
    (out / "results.json").write_text(json.dumps(results, indent=2))
    write_report(out, chapter, outcomes, results, notes, show_hidden, protections,
                 looks_like)
    return results


# ---------------------------------------------------------------- the mistakes' signatures

SIGNATURES = "signatures.json"


def load_signatures(build: Path, chapter: str) -> dict | None:
    """What prepare_signatures measured of the chapter's catalogued mistakes, if it ran."""
    try:
        return json.loads((build / "grading" / chapter / SIGNATURES).read_text())
    except (OSError, ValueError):
        return None


def prepare_signatures(root: Path, build: Path, chapter: str, progress=None,
                       jobs: int = 2) -> Path | None:
    """build/grading/NN/signatures.json: each catalogued mistake of the chapter
    (grading_catalogue, the instructor's; the held-out ones left out) graded like a
    submission, its random pictures at diagnosis.FOLDS sets of seeds no submission
    uses, with the threshold calibrated on them (diagnosis.calibrate). Made with the
    references and dropped with them (drop_stale_references); None where the chapter
    has no catalogue or its solution's sources are gone (an autograder image keeps what
    --prepare made). Kept in the per-user reference cache too, as the references are,
    under the solution's, build's and GL's key (reference_maker), the catalogue's and the
    grader's measuring code's."""
    drop_stale_references(root, build, chapter)
    path = build / "grading" / chapter / SIGNATURES
    try:
        import grading_catalogue
    except ImportError:  # a starter: the catalogue holds solution code and stays home
        return path if path.exists() else None
    variants = [v for v in grading_catalogue.CATALOGUE.get(chapter[:2], ())
                if v.chapter == chapter and not v.correct and not v.held_out]
    if not variants or not (root / "chapters" / chapter).is_dir():
        return path if path.exists() else None
    # The catalogue's own words and edits, and how the grader measures, are part of
    # what made them (beside the solution, build and GL: reference_maker).
    catalogue = reference_cache.key(
        repr(variants), *(reference_cache.file_digest(Path(module.__file__))
                          for module in (diagnosis, grading_statistics,
                                         denoised_grading)))
    kept = load_signatures(build, chapter)
    if kept is not None and kept.get("catalogue") == catalogue:
        return path
    private_folder(build / "grading" / chapter)
    name = reference_cache.key("mistake signatures", reference_maker(root, build, chapter),
                               catalogue) + ".json"
    stored = reference_cache.fetch(name) if reference_cache.folder() is not None else None
    if stored is not None and signatures_measured(stored):
        write_atomically(path, stored)
        return path
    prepare_references(root, build, chapter)
    random = any(t.kind in grading_statistics.RANDOM_KINDS for t in SPECS[chapter[:2]])
    seeds = diagnosis.FOLD_SEEDS[:diagnosis.FOLDS if random else 1]
    if progress is not None:
        progress(f"measuring chapter {chapter}'s {len(variants)} catalogued mistakes "
                 f"({len(seeds)} set{'s' if len(seeds) > 1 else ''} of runs each), once")

    with tempfile.TemporaryDirectory(prefix="course-signatures-") as scratch:
        def measure(job):
            variant, seed = job
            folder = Path(scratch) / f"{variant.slug}-{seed}"
            submission = grading_catalogue.apply(variant, root, folder / "submission")
            measured = {}
            grade(root, build, chapter, submission, folder / "graded", keep_runs=True,
                  first_seed=seed, measured=measured, diagnose=False)
            return variant.name, measured

        right = grading_catalogue.solution(chapter)
        with ThreadPoolExecutor(max_workers=max(1, jobs)) as pool:
            graded = list(pool.map(measure, [(v, s) for v in [right, *variants]
                                             for s in seeds]))
    folds = {v.name: [m for name, m in graded if name == v.name] for v in variants}
    calibration = diagnosis.calibrate(
        folds, {v.name: v.same_effect for v in variants if v.same_effect},
        remeasure=grading_statistics.diagnosis_measurement,
        solution=[m for name, m in graded if name == right.name])
    known = calibration["signatures"]
    data = {"chapter": chapter, "catalogue": catalogue, "seeds": list(seeds),
            "threshold": calibration["threshold"], "theory": calibration["theory"],
            "held_out": calibration["held_out"],
            "noise_held_out": calibration["noise_held_out"],
            "confusable": calibration["confusable"],
            "solution": {"tests": known[diagnosis.SOLUTION],
                         "threshold": calibration["thresholds"][diagnosis.SOLUTION],
                         "noise_tolerance": calibration["noise_tolerances"][diagnosis.SOLUTION]},
            "mistakes": [{"name": v.name, "explanation": v.explanation,
                          "section": v.section, "anchor": v.anchor,
                          "same_effect": v.same_effect,
                          "threshold": calibration["thresholds"][v.name],
                          "noise_tolerance": calibration["noise_tolerances"][v.name],
                          "tests": known[v.name]} for v in variants]}
    payload = json.dumps(data, indent=1).encode()
    # Kept only when every grading ran: signatures of gradings that did not build would
    # be used by every later grading of the same code (signatures_measured on reading).
    if reference_cache.folder() is not None and signatures_measured(payload):
        reference_cache.store(name, payload)
    write_atomically(path, payload)
    return path


def signatures_measured(payload: bytes) -> bool:
    """Whether kept signatures hold a measurement of every test of the solution and of
    each mistake: signatures kept from gradings that never ran (an earlier grader kept
    them when a submission could not link) are made again."""
    try:
        data = json.loads(payload)
        return bool(data["solution"]["tests"]) and all(m["tests"] for m in data["mistakes"])
    except (ValueError, KeyError, TypeError):
        return False


def failed_results(chapter: str, reason: str) -> dict:
    """Zero on every test, with the reason: what a class gets for a submission the
    grader could not grade at all."""
    return {"score": 0.0, "output": f"chapter {chapter}\n{reason}",
            "tests": [{"name": t.name, "score": 0.0, "max_score": t.max_score,
                       "output": reason, "visibility": t.visibility}
                      for t in SPECS[chapter[:2]]]}


def summary_notes(results: dict) -> str:
    """Why points were lost, in one line: the first line of each such test's output."""
    reasons = []
    for test in results["tests"]:
        if test["score"] >= test["max_score"]:
            continue
        lines = [line.strip() for line in test["output"].splitlines() if line.strip()]
        reason = lines[0] if lines else "no output"
        if reason.endswith(":") and len(lines) > 1:
            reason += " " + lines[1]
        if reason.startswith("the submission does not build"):
            reasons = [reason]  # the same for every test
            break
        reasons.append(f"{test['name']}: {reason}")
    text = "; ".join(reasons)
    return text if len(text) <= 300 else text[:297] + "..."


def grade_class(root: Path, build: Path, chapter: str, submissions: Path, out: Path,
                jobs: int | None = None, show_hidden: bool = False, progress=print,
                keep_runs: bool = False) -> Path:
    """./course grade NN --submissions DIR: every folder in DIR is one student's
    submission, graded as many at once as there are cores (each in a sandbox of its
    own, with a user of its own). Writes OUT/<student>/results.json and report.md, and
    OUT/summary.csv (student, score, max, one column per test, notes). A submission
    that does not build, crashes, or cannot be graded at all gets 0 with the reason,
    and the others go on."""
    folders = sorted(p for p in submissions.iterdir()
                     if p.is_dir() and not p.is_symlink() and not p.name.startswith("."))
    out.mkdir(parents=True, exist_ok=True)
    prepare_references(root, build, chapter)  # once, before the workers start
    prepare_signatures(root, build, chapter, progress)
    tests = SPECS[chapter[:2]]

    def one(folder: Path) -> tuple[str, dict]:
        target = out / folder.name
        started = time.monotonic()
        try:
            results = grade(root, build, chapter, folder, target, show_hidden,
                            hide=[submissions, out], close=[submissions, out],
                            keep_runs=keep_runs)
        except Exception as error:  # noqa: BLE001 - one student's problem, not the class's
            results = failed_results(chapter, f"the grader could not grade this "
                                              f"submission: {error}")
            target.mkdir(parents=True, exist_ok=True)
            (target / "results.json").write_text(json.dumps(results, indent=2))
            (target / "report.md").write_text(f"# Grading report: chapter {chapter}\n\n"
                                              f"**Score: 0**\n\n{results['output']}\n")
        progress(f"{folder.name}: {results['score']} / "
                 f"{sum(t.max_score for t in tests)} "
                 f"({time.monotonic() - started:.1f} s)")
        return folder.name, results

    with ThreadPoolExecutor(max_workers=max(1, jobs or os.cpu_count() or 1)) as pool:
        graded = list(pool.map(one, folders))
    summary = out / "summary.csv"
    with open(summary, "w", newline="") as sink:
        writer = csv.writer(sink)
        writer.writerow(["student", "score", "max_score", *(t.name for t in tests), "notes",
                         "looks like"])
        for name, results in graded:
            by_name = {t["name"]: t["score"] for t in results["tests"]}
            found = results.get("extra_data", {}).get("diagnosis") or {"matches": []}
            writer.writerow([name, results["score"], sum(t.max_score for t in tests),
                             *(by_name.get(t.name, 0.0) for t in tests),
                             summary_notes(results),
                             "; ".join(m["name"] for m in found["matches"])])
    return summary


def write_report(out: Path, chapter: str, outcomes: list[Outcome], results: dict,
                 notes: str, show_hidden: bool, protections: list[str] = (),
                 looks_like: str = ""):
    total = sum(o.test.max_score for o in outcomes)
    lines = [f"# Grading report: chapter {chapter}", "",
             f"**Score: {results['score']} / {total}**", ""]
    if notes:
        lines += ["Notes on the submission:", "", *[f"- {n}" for n in notes.splitlines()], ""]
    lines += ["| test | score | visibility |", "|---|---|---|"]
    lines += [f"| {o.test.name} | {o.score} / {o.test.max_score} | {o.test.visibility} |"
              for o in outcomes]
    if looks_like:
        lines += ["", "## What this looks like", "", looks_like]
    for o in outcomes:
        if o.test.visibility != "visible" and not show_hidden:
            continue
        lines += ["", f"## {o.test.name}", "", "```text", o.output.strip(), "```"]
        if o.images:
            lines += ["", "| submission | reference | error (brighter = worse) |",
                      "|---|---|---|",
                      "| " + " | ".join(f"![{k}]({v})" for k, v in o.images.items()) + " |"]
    if protections:
        lines += ["", "## How the submission was run", "",
                  *[f"- {line}" for line in protections]]
    (out / "report.md").write_text("\n".join(lines) + "\n")


def print_table(results: dict):
    width = max(len(t["name"]) for t in results["tests"]) + 2
    for t in results["tests"]:
        print(f"{t['name']:{width}} {t['score']:>6} / {t['max_score']:<4} {t['visibility']}")
    total = sum(t["max_score"] for t in results["tests"])
    print(f"{'total':{width}} {results['score']:>6} / {total}")
