"""Every shader the chapters compile, checked by the Khronos reference compiler.

llvmpipe accepts some GLSL a stricter driver refuses; glslangValidator (Debian's
glslang-tools, in the test layer) follows the specification. Each chapter runs once per
variant of its shaders (the scene code chapters 19-23 write for a scene, --generic,
each memory path, the wavefront kernels) with COURSE_SHADER_DUMP set, which makes the
program write each stage's text as the GL gets it (#includes expanded, generated
files in: common/shader_program.cpp); the starters' shaders (with their stubs, as
./course release makes them) are checked the same way. glslang then validates every text."""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

import pytest
from conftest import ROOT, run_chapter

from course_tools import chapters
from course_tools.editions.solution_markers import strip_solutions

SMALL = ("--width", "16", "--height", "12", "--spp", "1")
MEMORY_PATHS = [(), ("--generic",), ("--scene", "cornell_teapot", "--bvh-memory", "storage"),
                ("--scene-memory", "uniform"), ("--scene-memory", "constants"),
                ("--scene", "sky_showcase"), ("--scene", "lens_textures")]
VARIANTS = {
    "19": [(), ("--generic",), ("--scene", "cornell_teapot"), ("--scene", "sky_showcase"),
           ("--scene-memory", "storage")],
    "20": MEMORY_PATHS, "21": MEMORY_PATHS, "22": MEMORY_PATHS,
    "23": MEMORY_PATHS + [("--kernel", "wavefront"),
                          ("--kernel", "wavefront", "--scene", "sky_showcase", "--generic")],
}


def glslang() -> str:
    found = shutil.which("glslangValidator")
    if not found:
        pytest.skip("glslangValidator is not installed (./course setup test installs "
                    "glslang-tools); ./course test counts this as a failure")
    return found


def dumped_shaders(chapter: str, folder: Path, *args: str, shader_dir: Path | None = None,
                   must_run: bool = True) -> list[Path]:
    """The stage texts one run of the chapter compiles."""
    folder.mkdir(parents=True)
    image = () if chapter.startswith("01") else (*SMALL, "--out", folder / "image.pfm")
    where = ("--shader-dir", shader_dir) if shader_dir else ()
    result = run_chapter(chapter[:2], *image, *where, *args,
                         env={"COURSE_SHADER_DUMP": str(folder)})
    if must_run:
        assert result.returncode == 0, result.stderr
    shaders = sorted(p for p in folder.iterdir() if p.suffix in {".comp", ".frag", ".vert"})
    assert shaders, f"{chapter} {args}: no shader was dumped ({result.stderr})"
    return shaders


def refused(validator: str, shaders: list[Path]) -> list[str]:
    problems = []
    for shader in shaders:
        result = subprocess.run([validator, str(shader)], capture_output=True, text=True,
                                timeout=60)
        if result.returncode != 0:
            problems.append(f"{shader.name}:\n{result.stdout}{result.stderr}")
    return problems


@pytest.mark.parametrize("chapter", chapters.names(ROOT))
def test_every_shader_of_a_chapter_passes_the_reference_compiler(chapter, tmp_path):
    validator = glslang()
    problems = []
    for number, args in enumerate(VARIANTS.get(chapter[:2], [()])):
        shaders = dumped_shaders(chapter, tmp_path / f"variant{number}", *args)
        problems += [f"{' '.join(args) or 'default'}: {p}" for p in refused(validator, shaders)]
    assert not problems, "\n".join(problems)


def starter_shaders(chapter: str, destination: Path) -> Path | None:
    """The starter's shader folder (./course release's: the chapter's own solutions
    taken out, its stubs in), or None when the chapter's exercises are all in C++."""
    source = ROOT / "shaders" / chapter
    texts = {path.name: path.read_text() for path in sorted(source.iterdir())}
    stubbed = {name: strip_solutions(text, f"shaders/{chapter}/{name}")
               for name, text in texts.items()}
    if stubbed == texts:
        return None
    folder = destination / "shaders" / chapter
    folder.mkdir(parents=True)
    for name, text in stubbed.items():
        (folder / name).write_text(text)
    return folder


@pytest.mark.parametrize("chapter", chapters.names(ROOT))
def test_the_starters_shaders_pass_the_reference_compiler(chapter, tmp_path):
    validator = glslang()
    folder = starter_shaders(chapter, tmp_path / "starter")
    if folder is None:
        return  # its exercises are in C++ only
    # A starter's picture is wrong until the exercise is done; its shaders must compile.
    shaders = dumped_shaders(chapter, tmp_path / "dump", shader_dir=folder, must_run=False)
    problems = refused(validator, shaders)
    assert not problems, "\n".join(problems)


def test_the_check_refuses_what_the_specification_refuses(tmp_path):
    """It can fail: a shader that assigns a float to an int is refused, with the line."""
    shader = tmp_path / "001-wrong.comp"
    shader.write_text("#version 430\nlayout(local_size_x = 1) in;\n"
                      "void main() {\n    int count = 1.5;\n}\n")
    problems = refused(glslang(), [shader])
    assert problems and "4:" in problems[0], problems
