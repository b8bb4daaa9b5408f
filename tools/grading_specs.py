"""What the autograder runs for each chapter: named tests with points, the chapter's
command-line arguments, and whether students see the result before the deadline
('visible') or only after it ('after_due_date', Gradescope's hidden tests).

kind 'image': the submission's PNG is compared with the solution's for the same args.
kind 'check': the program checks itself; it must exit 0 and print `expect`."""

from __future__ import annotations

import re
from dataclasses import dataclass, field


@dataclass
class GradeTest:
    name: str
    max_score: float
    args: list[str] = field(default_factory=list)
    kind: str = "image"
    visibility: str = "visible"
    expect: str = ""

    @property
    def slug(self) -> str:
        return re.sub(r"[^a-z0-9]+", "_", self.name.lower()).strip("_")


SMALL = ["--width", "96", "--height", "72"]
ODD = ["--width", "123", "--height", "77"]  # not a multiple of any work-group size
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
    # Chapter 09 draws random numbers: every run uses a fixed --seed, so the solution's
    # picture is reproduced bit for bit, and few samples keep the runs short.
    "09": [
        GradeTest("first random numbers, hashed seeding", 3,
                  [*SMALL, "--view", "noise", "--seed", "3"]),
        GradeTest("first random numbers, naive seeding", 2,
                  [*SMALL, "--view", "noise", "--seeding", "naive", "--seed", "3"]),
        GradeTest("anti-aliased teapot, 4 samples", 3,
                  ["--width", "64", "--height", "48", "--spp", "4", "--seed", "5"]),
        GradeTest("ambient occlusion, 2 samples", 2,
                  ["--width", "64", "--height", "48", "--view", "ao", "--spp", "2",
                   "--seed", "7"], visibility="after_due_date"),
    ],
    "10": [
        # A fixed seed makes a path-traced image deterministic: the submission must
        # reproduce the solution's estimate, noise and all, at the same seed.
        GradeTest("Cornell box, direct light", 3,
                  ["--width", "48", "--height", "48", "--spp", "4", "--seed", "7", "--direct"]),
        GradeTest("Cornell box, global illumination", 4,
                  ["--width", "48", "--height", "48", "--spp", "4", "--seed", "7"]),
        GradeTest("light sampling only", 3, ["--width", "48", "--height", "48", "--spp", "4",
                                              "--seed", "3", "--estimator", "nee"],
                  visibility="after_due_date"),
    ],
    "11": [
        # The tree must give the same pictures as brute force (a slab test that enters
        # every box does too, only slowly, or cut short on a GL with a loop limit) and
        # do the same work: --view cost shows each pixel's traversal steps, which depend
        # on the SAH's tree and the box test. The starter's box test misses every box.
        GradeTest("teapot in the Cornell box, six bounces", 4,
                  ["--width", "32", "--height", "32", "--spp", "2", "--seed", "7"]),
        GradeTest("traversal work per pixel (--view cost)", 4,
                  ["--width", "64", "--height", "64", "--spp", "1", "--view", "cost"]),
        GradeTest("gems, traversal work per pixel", 2,
                  ["--scene", "cornell_gems", "--width", "64", "--height", "64", "--spp",
                   "1", "--view", "cost"], visibility="after_due_date"),
    ],
}
