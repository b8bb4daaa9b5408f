"""Chapter 28's catalogue: filters graded by the 'denoised' kind (the submission's
denoised pictures against the solution's filter: tools/course_tools/grading/
denoised_grading.py). Correct ones filter another valid way (another kernel, another
falloff, a gentler normal weight) and must score at least 90%; plausible wrong ones,
each in code the student writes, must score at most half. Registered in CATALOGUE as
catalogue.py's chapters are (grading_catalogue/__init__.py imports this module)."""

from __future__ import annotations

from grading_catalogue.catalogue import CATALOGUE
from grading_catalogue.variant import Edit, Variant

D = "28_denoising"
FILTER = "shaders/denoise.comp"
KERNEL = "float[5](1.0 / 16.0, 1.0 / 4.0, 3.0 / 8.0, 1.0 / 4.0, 1.0 / 16.0)"
LUMINANCE_WEIGHT = "        weight *= exp(-lightApart / (luminanceSigma * noise + EPSILON));\n"
NORMAL_WEIGHT = "    weight *= pow(clamp(agreement, 0.0, 1.0), normalPower);\n"
NOISE_OF_BOTH = "    float noise = sqrt(lightVariance + tap.w);\n"
MEAN_OF_TAPS = "    return vec4(sum / weights, variance / (weights * weights));\n"
VARIANCE_OF_TAP = "            variance += w * w * tap.w;\n"
STEP = "        dispatch(STAGE_FILTER, samples, 1u << pass);\n"

CHAPTER_28 = [
    Variant(D, "a sampled Gaussian kernel for the B3 spline", True, (
        Edit(FILTER, KERNEL, "float[5](0.054, 0.244, 0.403, 0.244, 0.054)"),)),
    Variant(D, "the luminance weight falling off as a Gaussian", True, (
        Edit(FILTER, LUMINANCE_WEIGHT,
             "        weight *= exp(-0.5 * lightApart * lightApart / (luminanceSigma * "
             "luminanceSigma * (lightVariance + tap.w) + EPSILON));\n"),)),
    Variant(D, "a gentler normal weight (half the power)", True, (
        Edit(FILTER, NORMAL_WEIGHT,
             "    weight *= pow(clamp(agreement, 0.0, 1.0), 0.5 * normalPower);\n"),)),

    Variant(D, "the weights' sum not divided out", False, (
        Edit(FILTER, MEAN_OF_TAPS, "    return vec4(sum, variance);\n"),),
        explanation=("A weighted mean divides by the sum of its weights: without it the "
                     "picture is far too bright."),
        section="Blurs: the noise goes, and the edges with it"),
    Variant(D, "the mean's variance through the weights, not their squares", False, (
        Edit(FILTER, VARIANCE_OF_TAP, "            variance += w * tap.w;\n"),
        Edit(FILTER, MEAN_OF_TAPS,
             "    return vec4(sum / weights, variance / weights);\n")),
        explanation=("A weighted mean's variance takes the weights squared: without them the "
                     "next passes blur across edges."),
        section="The light's own edges"),
    Variant(D, "the difference judged by the pixel's noise alone", False, (
        Edit(FILTER, NOISE_OF_BOTH, "    float noise = sqrt(lightVariance);\n"),),
        explanation=("Judged by one pixel's noise, a bright pixel turns its neighbours away: "
                     "its light is lost."),
        section="The light's own edges"),
    Variant(D, "the step not doubled from pass to pass", False, (
        Edit("chapters/denoiser.cpp", STEP,
             "        dispatch(STAGE_FILTER, samples, 1u);\n"),),
        explanation=("Each pass's taps lie twice as far apart as the last's, or the filter "
                     "reaches too few pixels."),
        section="À-trous: wide with 25 taps"),
    Variant(D, "the normal weight left out", False, (
        Edit(FILTER, NORMAL_WEIGHT, ""),),
        explanation=("Without the normal weight, walls meeting at a crease share their "
                     "light."),
        section="Weights from the features"),
]

CATALOGUE["28"] = CHAPTER_28
