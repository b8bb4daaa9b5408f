"""What the path tracers' checks (chapters 11 and 12) share: rendering to linear PFM,
the standard error of a mean over pixels, a closed-form form factor, and the region by
region comparison with Mitsuba 3; and for the materials (chapters 15 and 16): the
close-up of one object, which measures its brightness against Mitsuba's closely enough
to tell 2% from 0, a named region's pixels, shaders with one planted bug, and the GPU
probe of a chapter's BSDF functions (tests/cpp/bsdf_probe.cpp).

Every expected value is compared with the statistical error of the estimate: the
standard error of a mean of N independent pixels is the spread of the pixels over
sqrt(N). Limits of 4.5 standard errors fail a correct renderer about once in 150,000
comparisons; the seeds are fixed, so the results do not change from run to run."""

from __future__ import annotations

import json
import math
import re
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

from conftest import (RUNNER, ROOT, chapter_name, copy_shaders, program_path, read_pfm,
                      regions_agreeing, run_chapter)

from course_tools.grading import grader
from course_tools import mitsuba_cache, reference_cache

SCENES = ROOT / "tests" / "data" / "scenes"
SIGMAS = 4.5
BSDF_PROBE = ROOT / "build" / "tests" / "bsdf_probe"


def path_trace(chapter: str, tmp_path, name: str, *args) -> np.ndarray:
    """Renders with the chapter to a PFM (linear) and returns it (height, width, 3). A
    render whose program and inputs are those of one made before on this machine comes
    from the reference cache (kept_render_key)."""
    out = tmp_path / f"{name}.pfm"
    arguments = [str(a) for a in args]
    name = kept_render_key(chapter, arguments, out)
    kept = reference_cache.fetch(name)
    if kept is not None:
        out.write_bytes(kept)
    else:
        result = run_chapter(chapter, "--headless", "--out", out, *arguments)
        assert result.returncode == 0, result.stderr
        reference_cache.store(name, out.read_bytes())
    return read_pfm(out)[..., :3]


def kept_render_key(chapter: str, arguments: list[str], out: Path) -> str:
    """Everything that makes a chapter's render: what makes its grading references
    (grader.reference_maker: its sources and shaders, the common layer, the build files,
    the assets, the compiler, the GL and Mesa's settings), the test data, and the
    arguments, where a file or folder an argument names counts by its contents (a
    --shader-dir with a planted bug, a scene written by the test), a file with the
    other files beside it (the meshes and textures a scene names), but never the
    output."""
    parts = [grader.reference_maker(ROOT, ROOT / "build", chapter_name(chapter)),
             reference_cache.tree_digest(ROOT / "tests" / "data", scenes_as_read=True)]
    if RUNNER:
        # Another system's program (the Windows build under Wine): its own renders, never
        # the Linux program's kept ones, since the check is of that program.
        parts += ["program", reference_cache.file_digest(program_path(chapter_name(chapter)))]
    for argument in arguments:
        path = Path(argument)
        if path.is_dir():
            parts += ["folder", reference_cache.tree_digest(path)]
        elif path.is_file() and path.suffix == ".scene":
            parts += ["scene", scene_contents(path)]
            parts += [f"beside {p.name} " + (scene_contents(p) if p.suffix == ".scene"
                                              else reference_cache.file_digest(p))
                      for p in sorted(path.parent.iterdir())
                      if p.is_file() and p != path and p != out]
        elif path.is_file():
            parts += ["file", path.suffix, reference_cache.file_digest(path)]
        else:
            parts.append(argument)
    return reference_cache.key("chapter render", *parts) + ".pfm"


def scene_contents(path: Path) -> str:
    """A scene file's text as its reader reads it (without its comments:
    reference_cache.scene_as_read), with each absolute path in it (close_up writes its
    meshes' so) replaced by the digest of the file it names: the same scene in another
    clone reads the same."""
    text = reference_cache.scene_as_read(path.read_bytes()).decode("utf-8", "replace")
    for name in sorted(set(re.findall(r"/[^\s\"']+", text)), key=len, reverse=True):
        if Path(name).is_file():
            text = text.replace(name, f"<file {reference_cache.file_digest(Path(name))}>")
    return text


def mean_and_error(values: np.ndarray):
    """Mean and standard error of the mean over the first axis (pixels)."""
    values = values.reshape(-1, values.shape[-1])
    return values.mean(axis=0), values.std(axis=0, ddof=1) / math.sqrt(len(values))


def assert_mean_everywhere(image: np.ndarray, expected: float, block: int = 8,
                           margin: float = 1e-4):
    """The image's mean is `expected` within SIGMAS standard errors (plus `margin`: 1e-4
    for float rounding), and so is each block x block square's: everywhere, not just on
    average.
    (Single pixels are no test at a few dozen samples: Russian roulette makes their
    distribution heavy-tailed.)"""
    mean, error = mean_and_error(image)
    assert np.all(np.abs(mean - expected) < SIGMAS * error + margin), (mean, error)
    rows, columns = image.shape[0] // block, image.shape[1] // block
    squares = image[:rows * block, :columns * block].reshape(rows, block, columns, block, 3)
    for square in squares.swapaxes(1, 2).reshape(rows * columns, block * block, 3):
        square_mean, square_error = mean_and_error(square)
        assert np.all(np.abs(square_mean - expected) < SIGMAS * square_error + margin), \
            square_mean


def rectangle_form_factor(a: float, b: float, h: float) -> float:
    """Form factor from a small patch to a parallel a x b rectangle h above it, one
    corner straight above the patch (the standard closed form)."""
    x, y = a / h, b / h
    return (x / math.sqrt(1 + x * x) * math.atan(y / math.sqrt(1 + x * x))
            + y / math.sqrt(1 + y * y) * math.atan(x / math.sqrt(1 + y * y))) / (2 * math.pi)


def square_light_expected() -> float:
    """tests/data/scenes/square_light.scene: the floor (albedo 0.5) under the centre of a
    0.5 m square light (radiance 10) 1 m up, made of four 0.25 m squares each with a
    corner above the point. Radiance = albedo / pi * irradiance = albedo * L_e * F."""
    return 0.5 * 10.0 * 4 * rectangle_form_factor(0.25, 0.25, 1.0)


def assert_agrees_with_mitsuba(ours: np.ndarray, spp: int = 512,
                               scene_file: Path = ROOT / "assets" / "scenes" /
                               "cornell_spheres.scene", mesh_folders=(),
                               most_relative: float | None = None) -> list[str]:
    """Every region of the scene (the pixels that see one wall, sphere, mesh or the
    light, at least 20) within SIGMAS standard errors of Mitsuba 3's render at `spp`,
    and within most_relative of its brightness if given. Returns the regions compared."""
    pytest.importorskip("mitsuba")
    from python_prototypes import scene_io
    scene = scene_io.load_scene(str(scene_file), [str(f) for f in mesh_folders])
    height, width = ours.shape[:2]
    theirs = kept_mitsuba(scene, width, height, spp, 6, seed=0, variant="scalar_rgb")
    return regions_agreeing(ours, theirs, scene_file, SIGMAS,
                            mesh_folders, most_relative)


def kept_mitsuba(scene, width: int, height: int, spp: int, bounces: int, seed: int = 0,
                 variant: str = "scalar_rgb") -> np.ndarray:
    """Mitsuba 3's render, kept once made (course_tools/mitsuba_cache.py); the check is
    skipped where Mitsuba is not installed."""
    pytest.importorskip("mitsuba")
    return mitsuba_cache.kept_render(scene, width, height, spp, bounces, seed, variant)


def close_up(scene_file: Path, name: str, folder: Path, size: int, mesh_folders=(),
             margin: float = 1.08):
    """scene_file seen from the same eye, zoomed onto one object (a sphere or a mesh,
    by name) so that it fills the picture: the same rays hit it, many times as many
    pixels. The picture is `size` pixels across its longer side, shaped like the object
    (square for a sphere). Returns the new scene file, written into `folder` (mesh paths
    made absolute, so that it loads from there), and the picture's width and height."""
    from python_prototypes import obj_io
    from python_prototypes import scene_io
    scene = scene_io.load_scene(str(scene_file), [str(f) for f in mesh_folders])
    eye = np.asarray(scene.camera.eye, dtype=np.float64)
    sphere = next((s for s in scene.spheres if s.name == name), None)
    if sphere is not None:
        offset = np.asarray(sphere.center) - eye
        distance = np.linalg.norm(offset)
        look = offset / distance
        half_tangent = math.tan(margin * math.asin(sphere.radius / distance))
        width = height = size
    else:
        mesh = next(m for m in scene.meshes if m.name == name)
        positions = obj_io.read_obj(str(mesh.path))[0]
        world = positions @ mesh.world_from_mesh()[:3, :3].T + mesh.world_from_mesh()[:3, 3]
        look = None
        for _ in range(3):  # aim at the middle of the object's extent in the picture
            if look is None:
                look = world.mean(axis=0) - eye
                look /= np.linalg.norm(look)
            right = np.cross(look, [0.0, 1.0, 0.0])
            right /= np.linalg.norm(right)
            up = np.cross(right, look)
            relative = world - eye
            depth = relative @ look
            x, y = relative @ right / depth, relative @ up / depth
            centre = (x.max() + x.min()) / 2 * right + (y.max() + y.min()) / 2 * up + look
            look = centre / np.linalg.norm(centre)
        across, tall = x.max() - x.min(), y.max() - y.min()
        width, height = (size, max(16, round(size * tall / across))) if across > tall \
            else (max(16, round(size * across / tall)), size)
        half_tangent = margin * max(across, tall * width / height) / 2
    sensor = 0.025
    look_words = " ".join(f"{v:.6f}" for v in look)
    camera = (f"camera eye {eye[0]} {eye[1]} {eye[2]} look {look_words} up 0 1 0 "
              f"focal {sensor / 2 / half_tangent:.6f} sensor {sensor}")
    lines = []
    for line in scene_file.read_text().splitlines():
        words = line.split()
        if words[:1] == ["camera"]:
            line = camera
        elif words[:1] == ["mesh"]:
            written = next(m for m in scene.meshes if m.written_path == words[1])
            line = " ".join(["mesh", str(written.path), *words[2:]])
        lines.append(line)
    out = folder / f"close_up_{name}.scene"
    out.write_text("\n".join(lines) + "\n")
    return out, width, height


def close_up_difference(chapter: str, tmp_path, scene_file: Path, name: str, size: int,
                        spp: int, mitsuba_spp: int, mesh_folders=(), extra=()):
    """One object in a close-up (close_up), rendered by the chapter at `spp` and by
    Mitsuba 3 at `mitsuba_spp`, `size` pixels across: (our brightness over the object / Mitsuba's
    - 1, its standard error, the pixels, our image, Mitsuba's, the close-up's file).
    RGB averaged; the error is the spread of ours - ratio x theirs, which a picture only
    too dark or too bright (ours = ratio x theirs) does not widen."""
    pytest.importorskip("mitsuba")
    from python_prototypes import scene_io
    folders = [str(f) for f in mesh_folders]
    close, width, height = close_up(scene_file, name, tmp_path, size, mesh_folders)
    ours = path_trace(chapter, tmp_path, f"close_up_{name}", "--scene", close, "--width",
                      width, "--height", height, "--spp", spp, *extra)
    scene = scene_io.load_scene(str(close), folders)
    theirs = kept_mitsuba(scene, width, height, mitsuba_spp, 6, seed=0).astype(np.float64)
    mask = mitsuba_cache.kept_region_masks(scene, width, height)[name]
    relative, error = brightness_difference(ours[mask], theirs[mask])
    print(f"{name}: {relative:+.2%} (standard error {error:.2%}, {mask.sum()} pixels, "
          f"{spp} spp against {mitsuba_spp})")
    return relative, error, int(mask.sum()), ours, theirs, close


def mitsuba_regions(scene_file: Path, spp: int, size: int, mesh_folders=()):
    """Mitsuba 3's render of a scene file (size x size, depth 6, seed 0) and its regions:
    (image (size, size, 3), {region: mask}, scene_file), what assert_regions_within_two_percent
    compares a chapter's render with."""
    pytest.importorskip("mitsuba")
    from python_prototypes import scene_io
    scene = scene_io.load_scene(str(scene_file), [str(f) for f in mesh_folders])
    image = kept_mitsuba(scene, size, size, spp, 6, seed=0)
    return image, mitsuba_cache.kept_region_masks(scene, size, size), scene_file


def assert_regions_within_two_percent(ours: np.ndarray, reference, mesh_folders=()):
    """Every region within SIGMAS standard errors (conftest.regions_agreeing), and its
    brightness within 2% of Mitsuba's, or SIGMAS of its standard errors where the region
    is noisier than that (glass holds caustics: a few very bright pixels). Returns the
    regions compared."""
    theirs, masks, scene_file = reference
    compared = regions_agreeing(ours, theirs, scene_file, SIGMAS, mesh_folders)
    for region, mask in masks.items():
        if mask.sum() < 20:
            continue
        relative, error = brightness_difference(ours[mask], theirs[mask])
        print(f"{region}: {relative:+.2%} (standard error {error:.2%})")
        assert abs(relative) < max(0.02, SIGMAS * error), (region, relative, error)
    return compared


def brightness_difference(ours: np.ndarray, theirs: np.ndarray):
    """Two renders' pixels of one region (N x 3): (our brightness over theirs - 1, its
    standard error), RGB averaged. The error is the spread of ours - ratio x theirs,
    which a picture only too dark or too bright (ours = ratio x theirs) does not widen."""
    a, b = ours.mean(axis=-1), theirs.mean(axis=-1)
    ratio = a.mean() / b.mean()
    error = np.std(a - ratio * b, ddof=1) / math.sqrt(len(a)) / b.mean()
    return ratio - 1, error


def named_region(image: np.ndarray, scene_file: Path, name: str):
    """(the pixels that see only the shape called `name`, the scene), at the image's size."""
    from python_prototypes import scene_io
    scene = scene_io.load_scene(str(scene_file), [])
    return mitsuba_cache.kept_region_masks(scene, image.shape[1], image.shape[0])[name], scene


def render_with_stats(chapter: str, tmp_path, name: str, *args,
                      env=None) -> tuple[np.ndarray, dict]:
    """Renders a PFM headless; returns the linear image and the --json statistics."""
    out = tmp_path / f"{name}.pfm"
    result = run_chapter(chapter, "--headless", "--out", out, "--json", *map(str, args),
                         env=env)
    assert result.returncode == 0, result.stderr
    return read_pfm(out)[..., :3], json.loads(result.stdout.strip().splitlines()[-1])


def render_stats(chapter: str, tmp_path, *args) -> dict:
    """The chapter's --json statistics for one headless render with args."""
    result = run_chapter(chapter, "--headless", "--out", tmp_path / "stats.pfm", "--json",
                         *map(str, args))
    assert result.returncode == 0, result.stderr
    return json.loads(result.stdout.strip().splitlines()[-1])


def shaders_with_bug(chapter: str, destination: Path, bug=None, extra=()) -> Path:
    """A copy of a chapter's shader folder (conftest.copy_shaders, with the `extra` files
    beside them), where bug = (file, the right text, the wrong one) plants one mistake;
    the right text must stand exactly once, so a planted bug cannot silently miss."""
    folder = copy_shaders(chapter, destination)
    for path in extra:
        shutil.copy(path, folder / Path(path).name)
    if bug is not None:
        name, right, wrong = bug
        text = (folder / name).read_text()
        assert text.count(right) == 1, f"the planted bug's line is gone from {name}"
        (folder / name).write_text(text.replace(right, wrong))
    return folder


def run_bsdf_probe(probe_shader: str, shader_dir: Path, queries: np.ndarray,
                   tmp_path: Path, buffers: dict | None = None) -> np.ndarray:
    """Runs a probe shader (in shader_dir, beside the chapter's BSDF code) on (N, 20)
    float32 queries through tests/cpp/bsdf_probe.cpp; returns the (N, 24) answers.
    `buffers` maps a storage-buffer binding to a file of floats bound there too (an
    environment map's texels and tables, as the chapter binds them)."""
    assert BSDF_PROBE.exists(), \
        f"{BSDF_PROBE} is not built (cmake --build build --target bsdf_probe)"
    queries_file, answers_file = tmp_path / "queries.f32", tmp_path / "answers.f32"
    np.ascontiguousarray(queries, dtype=np.float32).tofile(queries_file)
    extra = [str(word) for binding, path in (buffers or {}).items()
             for word in ("--buffer", binding, path)]
    result = subprocess.run([BSDF_PROBE, shader_dir, shader_dir / probe_shader,
                             queries_file, answers_file, *extra], capture_output=True,
                            text=True, timeout=300)
    assert result.returncode == 0, result.stderr
    return np.fromfile(answers_file, dtype=np.float32).reshape(-1, 24).astype(np.float64)


# Two ways of computing the same picture (chapters 19 and 20): the same random numbers
# for each pixel, so the same pixels, except that a compiler may fold constants in
# another order than it computes a buffer's values, which changes the last bits of a few
# pixels and, through a bounce that goes the other way, a pixel entirely. Mesa 22's
# llvmpipe gives identical pixels.
MOST_DIFFERING_PIXELS = 0.003  # 3 in 1000: last-bit changes that sent a bounce elsewhere
MEAN_TOLERANCE = 1e-5


def assert_same_picture(image: np.ndarray, reference: np.ndarray, what: str):
    """The same picture within float rounding: at most MOST_DIFFERING_PIXELS of the
    pixels differ by more than 1e-5 (relative), and the mean by MEAN_TOLERANCE."""
    differs = np.abs(image - reference) > 1e-5 * np.maximum(np.abs(reference), 1e-3)
    share = differs.any(axis=-1).mean()
    assert share <= MOST_DIFFERING_PIXELS, f"{what}: {share:.2%} of the pixels differ"
    relative = abs(image.mean() / reference.mean() - 1)
    assert relative <= MEAN_TOLERANCE, f"{what}: the mean differs by {relative:.2e}"


def spheres_scene(path, count: int):
    """`count` small spheres in rows above the Cornell room's floor, every fifth one
    glowing, the rest alternately white and red: a scene of count + 6 shapes."""
    lines = ["camera eye 0 0 3.9 look 0 0 -1 up 0 1 0 focal 0.035 sensor 0.025",
             "material white albedo 0.8 0.8 0.8", "material red albedo 0.8 0.1 0.1",
             "material lamp albedo 0.8 0.8 0.8 emission 4 4 4",
             "quad -1 -1 1 2 0 0 0 0 -2 white", "quad -1 1 -1 2 0 0 0 0 2 white",
             "quad -1 -1 -1 2 0 0 0 2 0 white", "quad -1 -1 1 0 0 -2 0 2 0 red",
             "quad 1 -1 -1 0 0 2 0 2 0 white",
             "quad -0.25 0.99 -0.25 0.5 0 0 0 0 0.5 lamp"]
    side = int(np.ceil(np.sqrt(count)))
    for i in range(count):
        x, z = -0.9 + 1.8 * (i % side + 0.5) / side, -0.9 + 1.8 * (i // side + 0.5) / side
        material = "lamp" if i % 5 == 0 else ("white", "red")[i % 2]
        lines.append(f"sphere {x:.4f} {-0.9 + 0.05 * (i % 3):.4f} {z:.4f} "
                     f"{0.6 / side:.4f} {material}")
    path.write_text("\n".join(lines) + "\n")
    return path
