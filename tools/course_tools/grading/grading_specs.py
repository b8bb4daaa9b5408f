"""What the autograder runs for each chapter: named tests with points, the chapter's
command-line arguments, and whether students see the result before the deadline
('visible') or only after it ('after_due_date', Gradescope's hidden tests).

kind 'image': the submission's PNG is compared with the solution's for the same args
  (for deterministic pictures: the same arguments give one right picture).
kind 'check': the program checks itself; it must exit 0 and print `expect`.
kind 'statistical': for random pictures. The submission renders the args several times
  at its own seeds (`sampling`); each region's mean must agree with the solution's
  many-sample render in a z-test with the submission's own noise
  (tools/course_tools/grading/grading_statistics.py), so any correct estimator passes, whatever its noise.
kind 'traversal': chapter 13's tree: the solution's nearest hits, and about its work.
kind 'denoised': a denoiser (chapter 28): the submission renders the args several times
  at its own seeds, denoised; each region's light must be the solution's filter's (run
  as many times, at other seeds) within an allowance and the noise of the two means, and
  the noise it leaves at most a little more than the solution's
  (tools/course_tools/grading/denoised_grading.py).

Points: a plausible wrong implementation should lose at least half, a correct one
nothing, so each chapter's tests weigh what they catch
(tests/python/tools/test_grading_statistics.py grades catalogues of both)."""

from __future__ import annotations

import re
from dataclasses import dataclass, field


@dataclass(frozen=True)
class Sampling:
    """How a 'statistical' test samples: the submission's `runs` renders of `spp`
    samples each (at seeds 1, 2, ...) against the solution's `reference_runs` renders
    of `reference_spp` (at other seeds, made once and kept)."""
    runs: int = 8
    spp: int = 64
    reference_runs: int = 4
    reference_spp: int = 1024


@dataclass
class GradeTest:
    name: str
    max_score: float
    args: list[str] = field(default_factory=list)
    kind: str = "image"
    visibility: str = "visible"
    expect: str = ""
    sampling: Sampling | None = None  # kinds 'statistical' and 'denoised'
    # Files the arguments name, from the build's generated assets (build/assets): the
    # grader puts a copy of each in the folder the program runs in, the submission's
    # and the reference's alike, so that `--obj gem_octahedron.obj` finds it there.
    inputs: tuple[str, ...] = ()

    @property
    def slug(self) -> str:
        return re.sub(r"[^a-z0-9]+", "_", self.name.lower()).strip("_")


SMALL = ["--width", "96", "--height", "72"]
ODD = ["--width", "123", "--height", "77"]  # not a multiple of any work-group size
TINY = ["--width", "32", "--height", "32"]  # statistical tests: many small runs
WAVEFRONT = ["--kernel", "wavefront"]  # chapter 23: the kernels over queues
TWO_LIGHTS = ["--scene", "cornell_two_lights"]  # assets/scenes: lights of two sizes
PLATES = ["--scene", "glossy_plates"]  # assets/scenes: four rough metals, four lamps
# Samples of the statistical tests (tools/course_tools/grading/grading_statistics.py): the submission's 8
# runs at its own seeds against the solution's 4 runs of many samples (and 8 of the
# submission's samples, for its noise). A path tracer's references take 8 times the
# submission's samples in all, which leaves them an eighth of its variance: a z-score 6%
# below an exact reference's. (At 4 times, 11%: a wrong chapter-15 variant, Smith's
# Lambda with alpha for alpha squared, then passed; measured 2026-12-02.) The other
# pictures' references take 4 times: their wrong variants still fail, and references are
# most of the time a chapter's first grading takes.
PATH_SAMPLING = Sampling(runs=8, spp=64, reference_runs=4, reference_spp=1024)
# Chapter 09 traces every triangle for every ray: its anti-aliased picture is of the
# build's octahedral gem (8 triangles; the teapot has 552, and took 40 times as long),
# framed as the teapot is, whose silhouette, facets and shadow edges slope every way a
# wrong jitter shows on. Cheap, it takes the path tracers' samples: more than the
# teapot's 8 x 32 (its wrong variants fail by a wider margin, book/docs/instructors.md).
GEM = ["--obj", "gem_octahedron.obj"]
GEM_INPUTS = ("meshes/gem_octahedron.obj",)
GEM_SAMPLING = Sampling(runs=8, spp=64, reference_runs=4, reference_spp=1024)
PREVIEW_SAMPLING = Sampling(runs=8, spp=32, reference_runs=4, reference_spp=256)
# Chapter 13's picture tells a right tree from a wrong one by whole missing triangles:
# few samples do. It is the gems' (220 facets), not the teapot's: a tree that loses or
# misplaces triangles shows it there as well, the teapot's deep tree is graded exactly
# by the traversal tests, and a submission whose box test enters every box then takes
# seconds a run instead of the teapot's minutes (its catalogue entry: 393 s in all).
TREE_SAMPLING = Sampling(runs=8, spp=16, reference_runs=4, reference_spp=128)
# The appendix's gems test every triangle for every ray in a fragment shader.
GEMS_SAMPLING = Sampling(runs=8, spp=32, reference_runs=4, reference_spp=256)
# Chapter 28's denoiser: 16 runs of 8 samples a pixel, denoised, against the solution's
# filter's 16 (another 16 seeds), on the Cornell box at 96 x 96, where a 4 x 4 block (24
# pixels a side) is wider than the filter's reach. With 8 runs a side the solution's
# noise at other seeds came out 0.87 to 1.14 times its own, too near the step-not-doubled
# mistake's 1.56 at 64 x 64 (denoised_grading.py has the 16 runs' figures). A run takes
# about a second.
DENOISE_SAMPLING = Sampling(runs=16, spp=8, reference_runs=16, reference_spp=8)
DENOISED = ["--denoise", "atrous"]
# Chapter 29's blend: 16 runs a side of 4 frames, 1 sample each; the last frame, blended
# and denoised, is graded as chapter 28's denoised picture is, against the solution's
# own. Moving, the camera steps 20 cm right, 10 cm up and 30 cm forward a frame and the
# history fades slowly (--blend 0.05): the strips each step uncovers beside the boxes
# are wide, and a ghost left there lasts, while the box still fills four fifths of the
# picture (the noise is compared over the typical pixel: half the picture black outside
# the box made it 0). At 5 cm a frame, a blend without the plane test moved no 4 x 4
# block's light by more than 2%, within the noise: it scored full marks. Standing still,
# 4 frames blend into the mean of 4 samples. A run takes about a second.
TEMPORAL_SAMPLING = Sampling(runs=16, spp=1, reference_runs=16, reference_spp=1)
MOVING = ["--move-frames", "4", "--move", "0.2,0.1,-0.3", "--blend", "0.05", *DENOISED]
STILL = ["--move-frames", "4", *DENOISED]
# Chapter 04's three front spheres in front of the big one, close up with a long lens:
# where the nearest hit matters, filling the frame.
OVERLAP_CLOSE_UP = ["--camera-look", "-0.15,-0.6,-3.3", "--focal-length", "0.1"]

SPECS: dict[str, list[GradeTest]] = {
    "01": [
        GradeTest("sums of 1000 floats", 3, ["--count", "1000"], "check", expect="all correct"),
        GradeTest("one element", 2, ["--count", "1"], "check", expect="all correct"),
        GradeTest("33 elements: a partial work group", 3, ["--count", "33"], "check",
                  expect="all correct"),
        GradeTest("a million elements", 2, ["--count", "1000000"], "check",
                  "after_due_date", expect="all correct"),
    ],
    "02": [
        GradeTest("pattern, 1D dispatch", 4, ["--width", "96", "--height", "64",
                                               "--dispatch", "1d"]),
        GradeTest("pattern, 2D dispatch", 3, ["--width", "96", "--height", "64",
                                               "--dispatch", "2d"]),
        GradeTest("odd size, 1D dispatch", 3, ["--width", "203", "--height", "157",
                                                "--dispatch", "1d"], visibility="after_due_date"),
    ],
    "03": [
        GradeTest("default camera", 4, SMALL),
        GradeTest("moved and tilted camera", 3, [*SMALL, "--camera-eye", "1.5,2,3",
                                                 "--camera-look", "-0.4,-0.5,-1",
                                                 "--camera-up", "0.2,1,0"]),
        GradeTest("wide lens, odd size", 3, [*ODD, "--focal-length", "0.02"],
                  visibility="after_due_date"),
    ],
    "04": [
        GradeTest("one sphere", 3, [*SMALL, "--scene", "single"]),
        GradeTest("four spheres", 3, SMALL),
        GradeTest("overlapping spheres, close up", 2, [*SMALL, *OVERLAP_CLOSE_UP]),
        GradeTest("four spheres, odd size", 2, ODD, visibility="after_due_date"),
    ],
    "05": [
        GradeTest("one sphere, lit", 3, [*SMALL, "--scene", "single"]),
        GradeTest("spheres with shadows", 4, SMALL),
        GradeTest("low camera, shadows on the floor", 3,
                  [*ODD, "--camera-eye", "0.1,1.1,4"], visibility="after_due_date"),
    ],
    "06": [
        GradeTest("pyramid", 4, [*SMALL, "--scene", "pyramid"]),
        GradeTest("spheres on a triangle floor", 3, SMALL),
        GradeTest("pyramid, odd size", 3, [*ODD, "--scene", "pyramid"],
                  visibility="after_due_date"),
    ],
    "07": [
        GradeTest("teapot, flat shaded", 4, SMALL),
        GradeTest("teapot, wider picture", 3, ["--width", "128", "--height", "64"]),
        GradeTest("teapot, odd size", 3, ODD, visibility="after_due_date"),
    ],
    "08": [
        GradeTest("smooth teapot", 4, SMALL),
        GradeTest("smooth teapot, wider picture", 3, ["--width", "128", "--height", "64"]),
        GradeTest("smooth teapot, odd size", 3, ODD, visibility="after_due_date"),
    ],
    # Chapter 09: the generator is the lesson, and it is deterministic: the hybrid Taus
    # of GPU Gems 3, bit for bit as python_prototypes/rng.py, so the first number of each
    # pixel (--view noise) must be the solution's exactly, at a fixed seed. (Another
    # good generator is another lesson: it loses these five points, by design.) What the
    # numbers are used for is random: the anti-aliased picture averages rays through
    # random points of each pixel, and any uniform point is right (the two numbers in
    # either order, shifted and wrapped), so it is graded by statistics. The two halves
    # weigh the same, so that a wrong generator and a wrong jitter each lose half.
    # (--view ao is not graded: its picture barely depends on the jitter, and its
    # points would tip that balance; test_09_random_numbers.py checks it.)
    "09": [
        GradeTest("first random numbers, hashed seeding", 3,
                  [*SMALL, "--view", "noise", "--seed", "3"]),
        GradeTest("first random numbers, naive seeding", 2,
                  [*SMALL, "--view", "noise", "--seeding", "naive", "--seed", "3"]),
        GradeTest("anti-aliased gem", 3, ["--width", "32", "--height", "32", *GEM],
                  "statistical", sampling=GEM_SAMPLING, inputs=GEM_INPUTS),
        GradeTest("anti-aliased gem, wider picture", 2,
                  ["--width", "48", "--height", "24", *GEM], "statistical",
                  "after_due_date", sampling=GEM_SAMPLING, inputs=GEM_INPUTS),
    ],
    # Chapter 10: the preview is random too (a random point in each pixel, ambient
    # occlusion by random rays): graded by expectation. Surfaces alone (no occlusion
    # within reach) probe the quad and sphere tests and the materials; the preview
    # probes the occlusion; the gems probe triangles from a mesh file.
    "10": [
        GradeTest("Cornell spheres, surfaces and materials", 4,
                  [*TINY, "--ao-distance", "1e-7"], "statistical", sampling=PREVIEW_SAMPLING),
        GradeTest("Cornell spheres, ambient occlusion preview", 3, TINY, "statistical",
                  sampling=PREVIEW_SAMPLING),
        GradeTest("gems, ambient occlusion preview", 3, [*TINY, "--scene", "cornell_gems"],
                  "statistical", "after_due_date", sampling=PREVIEW_SAMPLING),
    ],
    # Chapter 11: a path-traced picture is random, and any correct sampler of the same
    # directions may draw its numbers in another order or map them another valid way:
    # graded by its expectation (tools/course_tools/grading/grading_statistics.py), never by reproducing the
    # solution's noise. Each test probes other code: direct light (the first bounce's
    # direction and weight), a path's length (two bounces: one too many or too few shows
    # through BSDF sampling's noise; at four, a fifth bounce's light would not), the
    # whole series, and a room lit by two lights of different sizes.
    "11": [
        GradeTest("Cornell box, direct light", 2.5, [*TINY, "--direct"], "statistical",
                  sampling=PATH_SAMPLING),
        GradeTest("Cornell box, two bounces", 2.5, [*TINY, "--depth", "2"], "statistical",
                  sampling=PATH_SAMPLING),
        GradeTest("Cornell box, global illumination", 2.5, TINY, "statistical",
                  sampling=PATH_SAMPLING),
        GradeTest("two lights, global illumination", 2.5, [*TINY, *TWO_LIGHTS],
                  "statistical", "after_due_date", sampling=PATH_SAMPLING),
    ],
    # Chapter 12: as chapter 11, graded by expectation. Each test probes other code:
    # direct light (light sampling and MIS against BSDF sampling at the first bounce), a
    # path's length (four bounces), Russian roulette (from the third bounce on), light
    # sampling without MIS. Three of them light the room with two lights of different
    # sizes (assets/scenes/cornell_two_lights.scene): every other scene the chapter ships
    # has one light, where a density not divided by the number of lights goes unseen.
    "12": [
        GradeTest("two lights, direct light", 2.5, [*TINY, *TWO_LIGHTS, "--direct"],
                  "statistical", sampling=PATH_SAMPLING),
        GradeTest("two lights, four bounces", 2.5, [*TINY, *TWO_LIGHTS, "--depth", "4"],
                  "statistical", sampling=PATH_SAMPLING),
        GradeTest("Cornell box, global illumination", 2.5, TINY, "statistical",
                  sampling=PATH_SAMPLING),
        GradeTest("two lights, light sampling only", 2.5,
                  [*TINY, *TWO_LIGHTS, "--estimator", "nee"], "statistical",
                  "after_due_date", sampling=PATH_SAMPLING),
    ],
    "13": [
        # The tree must give the pictures of brute force (a slab test that enters every
        # box does too, only slowly) and do about the solution's work, but need not be
        # the solution's slab test: another valid one (the planes ordered by min and max
        # instead of by the direction's signs) may differ in the last bit. So the
        # path-traced picture is graded by
        # statistics, and the traversal by its nearest hits (--view distance, exact: one
        # ray through each pixel's centre) and its work (--view cost, each pixel's steps):
        # within +-25% of the solution's mean where rays enter the tree, and no more
        # pixels at the heat map's top (60 steps; entering every box takes thousands).
        # The starter's box test misses every box: the room without the gems or the teapot.
        GradeTest("gems in the Cornell box, six bounces", 4,
                  [*TINY, "--scene", "cornell_gems"], "statistical", sampling=TREE_SAMPLING),
        GradeTest("nearest hits and traversal work", 4, ["--width", "64", "--height", "64"],
                  "traversal"),
        GradeTest("gems, nearest hits and traversal work", 2,
                  ["--scene", "cornell_gems", "--width", "64", "--height", "64"],
                  "traversal", visibility="after_due_date"),
    ],
    # Chapter 14: the SAH. The picture does not depend on the tree's quality (any valid
    # tree finds the same hits), so what is graded is the work: the same traversal tests
    # as chapter 13's, whose +-25% band around the solution's steps a valid SAH (another
    # bin count, the cost divided by the node's area) meets and a wrong cost does not
    # (the starter's, a node's price alone, picks the first plane: a peeling tree, many
    # times the steps). Chapter 13's tests check the pictures.
    "14": [
        GradeTest("nearest hits and traversal work", 6, ["--width", "64", "--height", "64"],
                  "traversal"),
        GradeTest("gems, nearest hits and traversal work", 4,
                  ["--scene", "cornell_gems", "--width", "64", "--height", "64"],
                  "traversal", visibility="after_due_date"),
    ],
    # Chapter 15: mirrors and metals, graded by expectation as chapter 12. Each test
    # probes other code: direct light (NEE through the rough gold's eval: D, G and the
    # conductor's Fresnel; copper's Fresnel seen in the light's reflection), the whole
    # picture (every material, light after a mirror), and the glossy plates by BSDF
    # sampling alone (the visible normals and their density at four roughnesses).
    "15": [
        GradeTest("metals, direct light", 3, [*TINY, "--direct"], "statistical",
                  sampling=PATH_SAMPLING),
        GradeTest("metals, global illumination", 3, TINY, "statistical",
                  sampling=PATH_SAMPLING),
        GradeTest("glossy plates, BSDF sampling only", 2,
                  [*TINY, *PLATES, "--estimator", "bsdf"], "statistical",
                  sampling=PATH_SAMPLING),
        GradeTest("glossy plates", 2, [*TINY, *PLATES], "statistical", "after_due_date",
                  sampling=PATH_SAMPLING),
    ],
    # Chapter 16: glass, graded by expectation as chapter 15. What a student writes is
    # the dielectric's Fresnel equations and Snell's law; each test sees them in other
    # light: the two glass spheres (smooth: the delta's choice between reflection and
    # refraction; rough: the same at every microfacet, through NEE and MIS), the gems
    # (total internal reflection, four indices, triangles) and the showcase's field of
    # glass among the other materials.
    "16": [
        GradeTest("glass spheres", 4, TINY, "statistical", sampling=PATH_SAMPLING),
        GradeTest("glass gems", 3, [*TINY, "--scene", "cornell_gem_glass"], "statistical",
                  sampling=PATH_SAMPLING),
        GradeTest("showcase", 3, [*TINY, "--scene", "showcase"], "statistical",
                  "after_due_date", sampling=PATH_SAMPLING),
    ],
    # Chapter 17: a thin lens and textures, graded by expectation as chapter 16. What a
    # student writes is the concentric map onto the aperture, bilinear filtering and the
    # sRGB curve's inverse. The bokeh wall shows all three in every test: lamps far out
    # of focus are seen as the aperture itself (a square, or a disk crowded at its
    # centre, is another picture), the test pattern in focus shows each texel (nearest
    # texels, an image upside down or not decoded); the chapter's scene, all of it.
    "17": [
        GradeTest("bokeh and an image, direct light", 4,
                  [*TINY, "--scene", "bokeh_wall", "--direct"], "statistical",
                  sampling=PATH_SAMPLING),
        GradeTest("bokeh and an image", 3, [*TINY, "--scene", "bokeh_wall"], "statistical",
                  sampling=PATH_SAMPLING),
        GradeTest("textured teapot through the lens", 3, TINY, "statistical",
                  "after_due_date", sampling=PATH_SAMPLING),
    ],
    # Chapter 18's exercises are the environment's pdf (pixelPdf) and its table search
    # (findStep): either wrong biases every surface the map lights. The spots map and a
    # lamp (both sampled by next-event estimation) show it most clearly, direct light
    # first; the showcase under the sky, with its sun, after the due date.
    "18": [
        GradeTest("spots and a lamp, direct light", 4,
                  [*TINY, "--scene", "environment_spots", "--direct"], "statistical",
                  sampling=PATH_SAMPLING),
        GradeTest("spots and a lamp", 3, [*TINY, "--scene", "environment_spots"],
                  "statistical", sampling=PATH_SAMPLING),
        GradeTest("the sky showcase", 3, TINY, "statistical", "after_due_date",
                  sampling=PATH_SAMPLING),
    ],
    # Chapter 19's exercise writes a quad out as a GLSL constant (scene_code.cpp). What
    # it writes is all in the views that trace one ray through each pixel's centre
    # without random numbers: deterministic pictures, so compared with the solution's as
    # images. The room's quads, written wrong, lose every wall; the showcase's quad, its
    # floor; the room's albedos, after the due date.
    "19": [
        GradeTest("the room's quads written into the shader", 5,
                  [*SMALL, "--scene", "cornell_box", "--view", "normals"]),
        GradeTest("the showcase written out", 3,
                  [*SMALL, "--scene-memory", "constants", "--view", "normals"]),
        GradeTest("the room's albedos", 2,
                  [*SMALL, "--scene", "cornell_box", "--view", "albedo"], "image",
                  "after_due_date"),
    ],
    # Chapter 20's exercises read a quad and a tree node back out of a buffer texture's
    # texels (scene_memory.glsl). What they read is all in the views that trace one ray
    # through each pixel's centre without random numbers: deterministic pictures, so
    # compared with the solution's as images. The room's quads, read wrong, lose every
    # wall; the teapot's tree, every triangle; the showcase's albedos, after the due date.
    "20": [
        GradeTest("the room's quads from a buffer texture", 5,
                  [*SMALL, "--scene", "cornell_box", "--scene-memory", "texture",
                   "--view", "normals"]),
        GradeTest("the teapot's tree from a buffer texture", 3,
                  [*SMALL, "--scene", "cornell_teapot", "--bvh-memory", "texture",
                   "--view", "normals"]),
        GradeTest("the showcase's albedos", 2, [*SMALL, "--view", "albedo"], "image",
                  "after_due_date"),
    ],
    # Chapter 21's exercise takes the next child off the walk's stack
    # (bvh_traversal.glsl). Any walk that finds the nearest hit finds the same one, so
    # the views of one ray through each pixel's centre are compared as images: a wrong
    # pop leaves holes in the meshes, or finds a farther triangle than the nearest. The
    # teapot, the textured teapot behind a lens, and the gems (a few triangles each)
    # after the due date.
    "21": [
        GradeTest("the teapot's nearest hits", 5,
                  [*SMALL, "--scene", "cornell_teapot", "--view", "normals"]),
        GradeTest("the textured teapot through the lens", 3,
                  [*SMALL, "--scene", "lens_textures", "--view", "albedo"]),
        GradeTest("the gems' nearest hits", 2,
                  [*SMALL, "--scene", "cornell_gems", "--view", "normals"], "image",
                  "after_due_date"),
    ],
    # Chapter 22's exercise adds a finished path to the pixel's running mean and starts
    # the pixel's next path in the same lane (path.comp). Wrong, it carries light or
    # throughput from one path into the next, or counts the samples wrong: the picture
    # brightens, darkens or keeps too few samples, judged by statistics as the path
    # tracer's pictures are. The room (up to 64 samples a dispatch), smooth and rough
    # glass, the sky showcase after the due date.
    "22": [
        GradeTest("the Cornell box, many samples a dispatch", 4,
                  [*TINY, "--scene", "cornell_box"], "statistical", sampling=PATH_SAMPLING),
        GradeTest("smooth and rough glass", 3, [*TINY, "--scene", "cornell_glass"],
                  "statistical", sampling=PATH_SAMPLING),
        GradeTest("the sky showcase", 3, TINY, "statistical", "after_due_date",
                  sampling=PATH_SAMPLING),
    ],
    # Chapter 23's exercises are the wavefront's queue: a push (an atomic place for each
    # pixel) and the dispatch commands (enough work groups for every item). Either wrong
    # loses paths or traces the wrong ones, and the picture darkens or scrambles: judged
    # by statistics, as the megakernel's pictures are. The room by direct light first
    # (one kind of material), smooth and rough glass (a queue per kind), the sky showcase
    # after the due date.
    "23": [
        GradeTest("the room by direct light, through the wavefront", 4,
                  [*TINY, "--scene", "cornell_box", "--direct", *WAVEFRONT], "statistical",
                  sampling=PATH_SAMPLING),
        GradeTest("smooth and rough glass, through the wavefront", 3,
                  [*TINY, "--scene", "cornell_glass", *WAVEFRONT], "statistical",
                  sampling=PATH_SAMPLING),
        GradeTest("the sky showcase, through the wavefront", 3, [*TINY, *WAVEFRONT],
                  "statistical", "after_due_date", sampling=PATH_SAMPLING),
    ],
    # Chapter 24's exercises are the free flight (where a ray in a medium scatters, and
    # its weight) and the Henyey-Greenstein sampler. The smoke ball shows both: its
    # direct light (one scattering, the free flight alone), then the whole path (the
    # phase function's direction at every scattering); the fog, after the due date.
    "24": [
        GradeTest("the smoke ball, direct light", 4,
                  [*TINY, "--scene", "cornell_smoke", "--direct"], "statistical",
                  sampling=PATH_SAMPLING),
        GradeTest("the smoke ball", 3, [*TINY, "--scene", "cornell_smoke"], "statistical",
                  sampling=PATH_SAMPLING),
        GradeTest("the fog", 3, TINY, "statistical", "after_due_date",
                  sampling=PATH_SAMPLING),
    ],
    # Chapter 25's exercises are the trilinear lookup, delta tracking (where a ray in a
    # grid scatters) and ratio tracking (what a shadow ray through it keeps). A coarse
    # checkerboard of density seen close up shows all three in its direct light (its
    # cells' blurred edges, camera rays tracked to their first scattering, shadow rays
    # to the lamp); the cloud's whole path; the checkerboard's after the due date.
    "25": [
        GradeTest("the checkered grid, direct light", 4,
                  [*TINY, "--scene", "grid_checker", "--direct"], "statistical",
                  sampling=PATH_SAMPLING),
        GradeTest("the cloud", 3, TINY, "statistical", sampling=PATH_SAMPLING),
        GradeTest("the checkered grid", 3, [*TINY, "--scene", "grid_checker"],
                  "statistical", "after_due_date", sampling=PATH_SAMPLING),
    ],
    # Chapter 26's exercises take a ray into an instance's object space and its normal
    # back to the world. Wrong, instances stand where their objects are, at the wrong
    # distance, or shaded with tilted normals: judged by statistics, as the path tracer's
    # pictures are (direct light first, then the whole path), and the normals one ray
    # through each pixel's centre sees after the due date.
    "26": [
        GradeTest("the instances, direct light", 4, [*TINY, "--direct"], "statistical",
                  sampling=PATH_SAMPLING),
        GradeTest("the instances", 3, TINY, "statistical", sampling=PATH_SAMPLING),
        GradeTest("the instances' normals", 3, [*SMALL, "--view", "normals"], "image",
                  "after_due_date"),
    ],
    # Chapter 27's exercises give each path its own instant of the shutter and move the
    # object's space back by that share of the instance's motion. Wrong, the moving
    # instances stand still, go the wrong way or too far: the blurred room judged by
    # statistics (direct light, then the whole path), and after the due date the smear
    # itself, the albedo one ray through each pixel's centre sees at random instants.
    "27": [
        GradeTest("the moving balls, direct light", 4, [*TINY, "--direct"], "statistical",
                  sampling=PATH_SAMPLING),
        GradeTest("the moving balls", 3, TINY, "statistical", sampling=PATH_SAMPLING),
        GradeTest("the smears", 3, [*TINY, "--view", "albedo"], "statistical",
                  "after_due_date", sampling=PATH_SAMPLING),
    ],
    # Chapter 28: the filter's passes (denoise.comp) and their steps (denoiser.cpp). The
    # odd size has tiles that overhang the picture, and taps beyond its edges.
    "28": [
        GradeTest("Cornell box, denoised", 6, ["--width", "96", "--height", "96",
                                              "--scene", "cornell_box", *DENOISED],
                  "denoised", sampling=DENOISE_SAMPLING),
        GradeTest("Cornell box, denoised, odd size", 4, [*ODD, "--scene", "cornell_box",
                                                         *DENOISED],
                  "denoised", "after_due_date", sampling=DENOISE_SAMPLING),
    ],
    # Chapter 29: the projection into the last frame's camera, the same-surface tests and
    # the blend (temporal.comp). The camera moving, then standing still (the blend must
    # be the plain mean: every frame weighed by the samples it holds).
    "29": [
        GradeTest("Cornell box, the camera moving fast", 5, ["--width", "96", "--height",
                                                             "96", "--scene", "cornell_box",
                                                             *MOVING],
                  "denoised", sampling=TEMPORAL_SAMPLING),
        GradeTest("Cornell box, the camera still", 5, [*ODD, "--scene", "cornell_box",
                                                       *STILL],
                  "denoised", "after_due_date", sampling=TEMPORAL_SAMPLING),
    ],
    # Appendix A1: chapter 12's path tracer in fragment-shader passes. What a student
    # writes is the pass's end: the pixel's state from the previous pass's textures,
    # one more sample, the new state to this pass's outputs. Graded by statistics, as
    # chapter 12: a generator that restarts every pass is caught by its noise.
    "A1": [
        GradeTest("Cornell box, direct light", 3, [*TINY, "--direct"], "statistical",
                  sampling=PATH_SAMPLING),
        GradeTest("Cornell box, global illumination", 4, TINY, "statistical",
                  sampling=PATH_SAMPLING),
        GradeTest("two lights, global illumination", 3, [*TINY, *TWO_LIGHTS],
                  "statistical", "after_due_date", sampling=PATH_SAMPLING),
    ],
    # Appendix A2: the path tracer of chapter 12 on OpenGL 3.3. What a student writes is
    # what GL 3.3 changes: reading the quads and the triangles out of the buffer
    # texture. Graded by statistics, as chapter 12. Every scene has quads (the room);
    # the gems' two tests carry half the points, so that a wrong triangle loses half.
    "A2": [
        GradeTest("Cornell box, direct light", 2.5, [*TINY, "--direct"], "statistical",
                  sampling=PATH_SAMPLING),
        GradeTest("gems, direct light", 3, [*TINY, "--scene", "cornell_gems", "--direct"],
                  "statistical", sampling=GEMS_SAMPLING),
        GradeTest("gems, global illumination", 2, [*TINY, "--scene", "cornell_gems"],
                  "statistical", sampling=GEMS_SAMPLING),
        GradeTest("two lights, global illumination", 2.5, [*TINY, *TWO_LIGHTS],
                  "statistical", "after_due_date", sampling=PATH_SAMPLING),
    ],
}
