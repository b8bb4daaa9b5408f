"""Chapter 29's catalogue: blends graded by the 'denoised' kind (the submission's
blended, denoised frames against the solution's: tools/course_tools/grading/
denoised_grading.py). Correct ones find the history or judge the surface another valid
way and must score at least 90%; plausible wrong ones, each in code the student writes
(temporal.comp's projection, same-surface tests and blend), must score at most half.
Registered in CATALOGUE as denoising.py's chapter is (grading_catalogue/__init__.py
imports this module)."""

from __future__ import annotations

from grading_catalogue.catalogue import CATALOGUE
from grading_catalogue.variant import Edit, Variant

T = "29_temporal"
BLEND = "shaders/temporal.comp"
FROM_EYE = "    vec3 fromEye = position - c.eye;\n"
ON_SENSOR = """    vec2 onSensor = vec2(dot(fromEye, c.right) / c.sensorWidth,
                         -dot(fromEye, c.up) / sensorHeight) * (c.focalLength / ahead);
    point = (onSensor + 0.5) * vec2(temporalSize);
"""
PLANE = "    if (offPlane > allowed) return false;\n"
NORMALS = "    if (agreement < normalAgreement) return false;\n"
ROWS = "-dot(fromEye, c.up) / sensorHeight) * (c.focalLength / ahead);\n"
SHARE = "        a = max(minimumBlend, k / (k + 1.0 / history.emitted.w));\n"
WEIGHTS_SQUARED = "        s = (1.0 - a) * (1.0 - a) * history.emitted.w + a * a / k;\n"
TOLERANCE = "    float allowed = max(planeTolerance * then.albedoDepth.w,"

CHAPTER_29 = [
    Variant(T, "the point projected through the focus plane's pixel grid", True, (
        Edit(BLEND, ON_SENSOR,
             "    vec2 pixelsPerMetre = vec2(temporalSize) /\n"
             "                          vec2(c.sensorWidth, sensorHeight);\n"
             "    vec2 onPlane = vec2(dot(fromEye, c.right), -dot(fromEye, c.up)) *\n"
             "                   (c.focalLength / ahead);\n"
             "    point = onPlane * pixelsPerMetre + 0.5 * vec2(temporalSize);\n"),)),
    Variant(T, "the normals' agreement at 0.8", True, (
        Edit(BLEND, NORMALS, "    if (agreement < 0.8) return false;\n"),)),
    Variant(T, "the plane's tolerance half again as wide", True, (
        Edit(BLEND, TOLERANCE,
             "    float allowed = max(1.5 * planeTolerance * then.albedoDepth.w,"),)),

    Variant(T, "the point projected with this frame's camera", False, (
        Edit(BLEND, FROM_EYE, "    c = camera;  // the camera as it is now\n" + FROM_EYE),),
        explanation=("The history is read where the pixel is now, not where the last frame "
                     "saw it: motion smears."),
        section="Where the last frame saw it"),
    Variant(T, "the plane test left out", False, (
        Edit(BLEND, PLANE, ""),),
        explanation=("Without the plane test, a surface uncovered by the motion takes the "
                     "history of what hid it: a ghost."),
        section="The same surface"),
    Variant(T, "the picture's rows counted upwards", False, (
        Edit(BLEND, ROWS,
             "dot(fromEye, c.up) / sensorHeight) * (c.focalLength / ahead);\n"),),
        explanation=("Row 0 is the picture's top: counted upwards, the history is read "
                     "upside down, and most of it is lost."),
        section="Where the last frame saw it"),
    Variant(T, "the history's share given to the frame", False, (
        Edit(BLEND, SHARE,
             "        a = max(minimumBlend, (1.0 / history.emitted.w) /\n"
             "                              (k + 1.0 / history.emitted.w));\n"),),
        explanation=("The frame's share is k / (k + n): given n / (k + n), the newest "
                     "samples outweigh the rest."),
        section="Weighing the history"),
    Variant(T, "s not carried: every blend one frame's worth", False, (
        Edit(BLEND, WEIGHTS_SQUARED, "        s = 1.0 / k;\n"),),
        explanation=("s says what the blend is worth in samples: kept at one frame's, "
                     "every blend is half frame, and noise stays."),
        section="Weighing the history"),
]

CATALOGUE["29"] = CHAPTER_29
