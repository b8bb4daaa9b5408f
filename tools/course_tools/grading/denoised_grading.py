"""Grading a denoiser: the autograder's 'denoised' kind (chapter 28).

A denoised picture is a filter of a random picture: random too, and the filter moves
its expectation a little (light spread a few pixels across an edge), so it is graded
against the solution's own filter, run as the submission is (the same path tracer, the
same samples, `runs` seeds each), not against the path tracer's expectation:

1. Light: each region's mean (the whole image, its 2 x 2 and 4 x 4 blocks, each colour
   channel; no finer, since a filter's reach is several pixels) over the submission's
   runs against the solution's. A correct filter written another way (another kernel,
   another falloff of the same weights) moves a region's light by less than
   LIGHT_ALLOWANCE of it; beyond that, the difference is tested against the noise of
   the two means (each estimated from the spread of the region's mean between runs,
   since a filter's pixels are not independent), with Holm's correction over the
   regions at grading_statistics.FAMILY_ALPHA. A filter that darkens, brightens, loses
   the texture or smears one wall's colour over another fails here.
2. Noise: the typical pixel's variance between runs (grading_statistics.noise) at most
   NOISE_MOST times the solution's filter's. A filter that keeps the light but reaches
   less far (a step not doubled from pass to pass) leaves more of the noise it is for.
3. The guards of every random picture: no NaN, infinite or negative pixel, and runs
   that differ although their seeds do (grading_statistics).

Measured on the Cornell box at 96 x 96 and at 123 x 77, 8 samples, 16 runs a side
(2026-12-06; book/docs/instructors.md keeps the catalogue's table): the solution at
three sets of seeds and three correct variants at most 2.5 standard errors beyond the
allowance (a region fails from 4.1) and 0.91 to 1.09 times the solution's noise; the
wrong ones 6.6 to 1 200 standard errors beyond it, or 1.8 and 2.1 times its noise."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from course_tools.grading import grading_statistics as statistics
from course_tools.grading.blocks import block_sizes, block_sums

LEVELS = (1, 2, 4)          # the image cut into n x n blocks, for each n
LIGHT_ALLOWANCE = 0.01      # of a region's light: a correct filter written another way
NOISE_MOST = 1.4            # the submission's noise at most this times the solution's


def region_means(runs: np.ndarray, level: int) -> tuple[np.ndarray, np.ndarray]:
    """For runs (K, H, W, C): the regions' means over the runs, and the variance of
    those means from their spread between runs."""
    per_run = block_sums(runs, level) / block_sizes(runs.shape[1], runs.shape[2], level)
    return per_run.mean(axis=0), per_run.var(axis=0, ddof=1) / runs.shape[0]


def compare(runs: np.ndarray, solution_runs: np.ndarray) -> statistics.Comparison:
    """The submission's denoised runs against the solution's, region by region (both
    (K, H, W, 3), linear). z is each difference beyond the allowance in standard errors
    (0 within it)."""
    height, width = runs.shape[1:3]
    levels = [n for n in statistics.block_levels(height, width) if n in LEVELS]
    regions, means, solution_means, errors = [], [], [], []
    for level in levels:
        mine, my_variance = region_means(runs, level)
        theirs, their_variance = region_means(solution_runs, level)
        for row in range(level):
            for column in range(level):
                for channel in range(runs.shape[3]):
                    regions.append(statistics.Region(level, row, column, channel))
                    means.append(mine[row, column, channel])
                    solution_means.append(theirs[row, column, channel])
                    errors.append(my_variance[row, column, channel] +
                                  their_variance[row, column, channel])
    means, solution_means = np.array(means), np.array(solution_means)
    floor = statistics.FLOOR_RELATIVE * np.abs(solution_means) + statistics.FLOOR_ABSOLUTE
    error = np.sqrt(np.array(errors) + floor ** 2)
    beyond = np.maximum(np.abs(means - solution_means) -
                        LIGHT_ALLOWANCE * np.abs(solution_means), 0.0)
    z = np.sign(means - solution_means) * beyond / error
    p = statistics.normal_two_sided_p(z)
    mine, theirs = statistics.noise(runs), statistics.noise(solution_runs)
    ratio = mine / theirs if theirs > 0 else (1.0 if mine == 0 else np.inf)
    alike = bool(np.all(runs == runs[0])) and theirs > 0
    return statistics.Comparison(
        regions, means, solution_means, error, z, p,
        statistics.holm(p, statistics.FAMILY_ALPHA),
        statistics.normal_quantile_two_sided(statistics.FAMILY_ALPHA / len(p)),
        float(ratio), alike)


def grade_test(test, outcome, workdir: Path, report_dir: Path, run, references, describe,
               first_seed: int = statistics.SUBMISSION_SEED):
    """Fills in outcome for a 'denoised' test (grading_statistics.grade_test's
    arguments): the submission's `runs` runs against the solution's
    `reference_runs`, each of `spp` samples denoised."""
    found = statistics.read_runs(test, outcome, workdir, run, references, describe,
                                 first_seed)
    if found is None:
        return outcome
    return judge(test, outcome, report_dir, np.stack(found[0]), np.stack(found[1]),
                 first_seed)


def judge(test, outcome, report_dir: Path, runs: np.ndarray, solution_runs: np.ndarray,
          first_seed: int = statistics.SUBMISSION_SEED):
    """The submission's denoised runs against the solution's (both (K, H, W, 3)):
    outcome's score, output, measurement and report images."""
    if statistics.broken_pixels(runs, outcome, "statistical"):
        return outcome
    result = compare(runs, solution_runs)
    sampling = test.sampling
    outcome.measurement = statistics.diagnosis_measurement(runs)
    levels = sorted({r.level for r in result.regions})
    lines = [f"{len(result.regions)} region means ({', '.join(f'{n}x{n}' for n in levels)} "
             f"blocks, each channel) of {sampling.runs} denoised runs of {sampling.spp} "
             f"samples (seeds {first_seed}..{first_seed + sampling.runs - 1}) against the "
             f"solution's filter's {sampling.reference_runs}; a region fails from |z| > "
             f"{result.threshold_z:.2f} beyond {LIGHT_ALLOWANCE:.0%} of its light (Holm, "
             f"family-wise alpha {statistics.FAMILY_ALPHA:g})",
             f"largest |z| beyond the allowance: {np.abs(result.z).max():.2f}; noise "
             f"{result.variance_ratio:.2f} x the solution's filter's (at most "
             f"{NOISE_MOST:g})"]
    if result.runs_alike:
        lines.append("every run gave the same picture, although their seeds differ: "
                     "the program ignores --seed, or its picture is not random")
    too_noisy = result.variance_ratio > NOISE_MOST
    passed = result.passed and not too_noisy and not result.runs_alike
    if passed:
        lines.insert(0, "passed: the solution's light in every region, and no more noise")
    else:
        why = []
        if not result.passed:
            why.append(f"{int(result.rejected.sum())} of {len(result.regions)} regions "
                       "hold other light than the solution's filter leaves there")
        if too_noisy:
            why.append(f"{result.variance_ratio:.1f} x the noise the solution's filter "
                       f"leaves (at most {NOISE_MOST:g}): the filter does not reach as far")
        if result.runs_alike:
            why.append("the runs do not change with the seed")
        lines.insert(0, "failed: " + "; ".join(why))
        for index in np.argsort(-np.abs(result.z))[:5]:
            if not result.rejected[index]:
                break
            lines.append(f"  {result.regions[index].describe(runs.shape[1:])}: "
                         f"{result.submission[index]:.5g}, the solution's "
                         f"{result.reference[index]:.5g} +- "
                         f"{result.standard_error[index]:.2g} (z = {result.z[index]:+.1f} "
                         f"beyond {LIGHT_ALLOWANCE:.0%})")
    outcome.score = test.max_score if passed else 0.0
    outcome.output = "\n".join(lines)
    statistics.save_report_images(test.slug, report_dir, runs.mean(axis=0),
                                  solution_runs.mean(axis=0),
                                  statistics.finest_z_map(result, runs.shape[1:]), outcome)
    return outcome
