"""Grading pictures that are random, and work that may differ: the autograder's
'statistical' and 'traversal' test kinds (tools/course_tools/grading/grader.py dispatches them here;
a denoiser's pictures, kind 'denoised', are read here and judged in denoised_grading.py).

A path-traced picture at a fixed seed is one draw of a random image: a submission that
draws its random numbers in another order, or maps them to directions another valid way,
gives other noise around the same expectation. So a random picture is graded on its
expectation, not on its noise:

1. The submission renders the test's arguments `runs` times, at seeds 1, 2, ...,
   `spp` samples each, as PFM (linear radiance, not 8-bit sRGB). The solution renders
   them `reference_runs` times at seeds 1000001, 1000002, ... with `reference_spp`
   samples each, and `runs` times with `spp` samples at seeds 2000001, ...; the grader
   renders those once and keeps them in build/grading/NN/.
2. The regions: the whole image, its 2 x 2, 4 x 4 and 8 x 8 blocks (as many of those
   levels as leave at least MIN_REGION_PIXELS pixels a block), each colour channel
   apart. Coarse regions see a small bias spread over the picture (a bounce too few),
   fine ones a large bias in one place (a light's cosine).
3. Per region, the mean of the submission's runs is compared with the reference's in
   a z-test. The variance of each mean is estimated two ways and the larger taken: from
   the per-pixel spread between runs, pooled over the region's pixels (many degrees of
   freedom, right when pixels are independent, as the course's hashed per-pixel streams
   are), and from the spread of the region's mean between runs (few degrees of freedom,
   right even when pixels are correlated). The submission's own variance counts (so a
   noisier but correct estimator is not punished), but never less than the solution's
   with as many samples: eight runs of a path tracer may all miss its rare bright
   samples and look both darker and surer than they are. The reference's variance is
   added, and a tiny floor (FLOOR_RELATIVE of the reference's mean, plus
   FLOOR_ABSOLUTE) stands for float rounding, so that a region with no noise at all
   (the sky) needs no bit-exact match.
4. p-values from the normal distribution, and Holm's correction over all regions and
   channels (family-wise significance FAMILY_ALPHA): the test passes when no region is
   rejected. Holm and Bonferroni reject the first hypothesis at the same threshold, so
   pass or fail is Bonferroni's; Holm counts the rejected regions for the report.
   (Mitsuba 3's render tests do a per-pixel z-test with Sidak's correction against a
   reference's variance; here the regions pool pixels, because eight runs estimate one
   pixel's variance too roughly for a z-test at these significances.)
5. Guards: any NaN, infinite or negative pixel fails (radiance is neither); a
   submission more than MAX_VARIANCE_RATIO times as noisy as the solution (the median
   pixel's variance between runs, with as many samples) fails, or adding noise would
   pass any z-test; a picture whose runs are all alike where the solution's differ is
   named in the report (it ignores --seed, or is not random).

Scores are all or nothing: the test asks "is this estimator's expectation the
solution's?", and the size of a bias says nothing about how wrong the code is (a
missing 1/pi and a bounce too few are both wrong estimators), while the number of
regions that reject it grows with the samples taken. Partial credit comes from a
chapter's several tests, each probing other code.

The 'traversal' kind grades chapter 13's tree by what it does, not by equality with the
solution's tree (another valid SAH, another bin count, another slab test give another
tree with other per-pixel costs): the nearest hits must be the solution's (--view
distance, deterministic: one ray through each pixel's centre) and the work (--view cost,
decoded from its heat map) must be within WORK_BAND of the solution's mean over the
pixels whose rays enter the tree, and may not hit the heat map's top (COST_SCALE steps;
a traversal that enters every box does thousands) on more than SATURATED_EXTRA more of
the pixels than the solution's does.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from course_tools.grading import diagnosis
from course_tools.grading.blocks import block_sizes, block_sums, edges
from course_tools.grading.submission_files import submitted_file
from python_prototypes import srgb
from python_prototypes.pfm import parse_pfm, read_pfm  # noqa: F401  (the grader reads through here)

# The kinds whose runs and references this module names (reference_arguments) and
# reads (read_runs): 'denoised' is judged in denoised_grading.py.
KINDS = ("statistical", "traversal", "denoised")
RANDOM_KINDS = ("statistical", "denoised")  # pictures that change with the seed

FAMILY_ALPHA = 1e-4         # the chance that a correct submission fails one test
MIN_REGION_PIXELS = 16      # the finest blocks: enough pixels to pool their variances
BLOCK_LEVELS = (1, 2, 4, 8)  # the image cut into n x n blocks, for each n
FLOOR_RELATIVE = 1e-4       # float rounding: no region needs agreement closer than this
FLOOR_ABSOLUTE = 1e-5
MAX_VARIANCE_RATIO = 4.0    # a correct estimator may be noisier, but not this much
SUBMISSION_SEED = 1         # the submission's runs: seeds 1, 2, ...
REFERENCE_SEED = 1_000_001  # the solution's many-sample runs: far from the submission's
NOISE_SEED = 2_000_001      # the solution's runs at the submission's budget

# Chapter 13's --view cost: path.comp's heat(steps / COST_SCALE), blue to red.
COST_SCALE = 60.0
HEAT_COLOURS = np.array([[0.0, 0.0, 0.4], [0.0, 0.7, 1.0], [1.0, 0.9, 0.0],
                         [0.9, 0.0, 0.0]])
WORK_BAND = 0.25            # the submission's mean work within +-25% of the solution's
SATURATED_EXTRA = 0.01      # at most 1% more of the pixels at the heat map's top
HITS_AGREEING = 0.995       # pixels whose nearest hit must be the solution's
DISTANCE_TOLERANCE = 1e-4   # relative


# ---------------------------------------------------------------- what is run

def run_arguments(test, seed: int, spp: int) -> list[str]:
    return [*test.args, "--spp", str(spp), "--seed", str(seed)]


def reference_arguments(test) -> list[list[str]]:
    """The solution's runs a test compares with (the grader renders each once, as PFM,
    and keeps it): for a statistical test, `reference_runs` runs of many samples (the
    expected picture), then `runs` runs of the submission's samples (the solution's
    noise at the submission's budget, for the noise guard)."""
    if test.kind == "traversal":
        return [[*test.args, "--view", "distance"], [*test.args, "--view", "cost"]]
    sampling = test.sampling
    if test.kind == "denoised":  # the solution's filter, at the submission's budget
        return [run_arguments(test, REFERENCE_SEED + j, sampling.reference_spp)
                for j in range(sampling.reference_runs)]
    return ([run_arguments(test, REFERENCE_SEED + j, sampling.reference_spp)
             for j in range(sampling.reference_runs)] +
            [run_arguments(test, NOISE_SEED + k, sampling.spp) for k in range(sampling.runs)])


def submission_arguments(test, first_seed: int = SUBMISSION_SEED) -> list[list[str]]:
    """A submission's runs: at seeds 1, 2, ...; the diagnosis grades the catalogued
    mistakes at other seeds (diagnosis.FOLD_SEEDS)."""
    if test.kind == "traversal":
        return reference_arguments(test)
    sampling = test.sampling
    return [run_arguments(test, first_seed + k, sampling.spp)
            for k in range(sampling.runs)]


# ---------------------------------------------------------------- reading

def read_output(path: Path) -> bytes:
    """The bytes of a file the submission wrote, read by the grader's own reader (never
    through a link the submission left there, never from a FIFO or device, within the
    sandbox's file size limit). Raises ValueError saying what is wrong."""
    data, problem = submitted_file(path)
    if data is None:
        raise ValueError(problem)
    return data


# ---------------------------------------------------------------- the z-test

@dataclass
class Region:
    level: int      # the image cut into level x level blocks
    row: int
    column: int
    channel: int

    def describe(self, shape) -> str:
        colour = "RGB"[self.channel]
        if self.level == 1:
            return f"the whole image ({colour})"
        return (f"block ({self.row}, {self.column}) of {self.level}x{self.level} "
                f"({colour}, rows {edges(shape[0], self.level)[self.row]}..., "
                f"columns {edges(shape[1], self.level)[self.column]}...)")


@dataclass
class Comparison:
    regions: list[Region]
    submission: np.ndarray       # region means
    reference: np.ndarray
    standard_error: np.ndarray   # of the difference
    z: np.ndarray
    p: np.ndarray
    rejected: np.ndarray         # bool, Holm at FAMILY_ALPHA
    threshold_z: float           # the |z| the first (Bonferroni) step rejects from
    variance_ratio: float        # submission's noise / the solution's, same samples
    runs_alike: bool             # every run of the submission the same picture

    @property
    def passed(self) -> bool:
        return not self.rejected.any()


def block_levels(height: int, width: int) -> list[int]:
    """The block grids that keep at least MIN_REGION_PIXELS pixels a block (and the
    whole image, however small)."""
    return [n for n in BLOCK_LEVELS if n == 1 or n <= min(height, width) and
            (height // n) * (width // n) >= MIN_REGION_PIXELS]


def region_statistics(runs: np.ndarray, levels: list[int]):
    """For runs (K, H, W, C): per level, (region means, variance of those means). The
    variance is the larger of the pooled per-pixel estimate and the between-run one."""
    count = runs.shape[0]
    mean = runs.mean(axis=0)
    pixel_variance = runs.var(axis=0, ddof=1) / count  # of each pixel's mean
    result = []
    for level in levels:
        sizes = block_sizes(runs.shape[1], runs.shape[2], level)
        means = block_sums(mean, level) / sizes
        pooled = block_sums(pixel_variance, level) / sizes ** 2
        between = (block_sums(runs, level) / sizes).var(axis=0, ddof=1) / count
        result.append((means, np.maximum(pooled, between)))
    return result


def normal_two_sided_p(z: np.ndarray) -> np.ndarray:
    return np.vectorize(lambda x: math.erfc(abs(x) / math.sqrt(2.0)))(z)


def normal_quantile_two_sided(p: float) -> float:
    """The |z| whose two-sided p-value is p (bisection on erfc; no scipy in the grading
    layer)."""
    low, high = 0.0, 40.0
    for _ in range(200):
        middle = 0.5 * (low + high)
        if math.erfc(middle / math.sqrt(2.0)) > p:
            low = middle
        else:
            high = middle
    return 0.5 * (low + high)


def holm(p: np.ndarray, alpha: float) -> np.ndarray:
    """Holm's step-down: which hypotheses are rejected at family-wise level alpha."""
    order = np.argsort(p)
    rejected = np.zeros(p.shape, dtype=bool)
    m = len(p)
    for rank, index in enumerate(order):
        if p[index] > alpha / (m - rank):
            break
        rejected[index] = True
    return rejected


def noise(runs: np.ndarray) -> float:
    """A picture's typical noise: the median over pixels of the variance between runs
    (channels summed). The median, because a path tracer's rare bright samples make a
    mean over so few runs jump by orders of magnitude; the mean where most pixels have
    none."""
    variance = runs.var(axis=0, ddof=1).sum(axis=-1)
    median = float(np.median(variance))
    return median if median > 0 else float(variance.mean())


def compare(runs: np.ndarray, reference_runs: np.ndarray,
            noise_runs: np.ndarray | None = None) -> Comparison:
    """The submission's runs against the solution's, region by region (all (K, H, W, 3),
    linear): reference_runs have many samples, noise_runs (if given) the submission's
    samples, for comparing the noise."""
    height, width = runs.shape[1:3]
    levels = block_levels(height, width)
    mine = region_statistics(runs, levels)
    theirs = region_statistics(reference_runs, levels)
    # The solution's noise at the submission's budget: the least the submission's own
    # may count as (its runs may just have missed the rare bright samples).
    fair = region_statistics(noise_runs, levels) if noise_runs is not None else mine
    regions, means, reference_means, variances = [], [], [], []
    for level, (m, v), (r, w), (_, f) in zip(levels, mine, theirs, fair):
        own = np.maximum(v, f)
        for row in range(level):
            for column in range(level):
                for channel in range(runs.shape[3]):
                    regions.append(Region(level, row, column, channel))
                    means.append(m[row, column, channel])
                    reference_means.append(r[row, column, channel])
                    variances.append(own[row, column, channel] + w[row, column, channel])
    means, reference_means = np.array(means), np.array(reference_means)
    floor = FLOOR_RELATIVE * np.abs(reference_means) + FLOOR_ABSOLUTE
    error = np.sqrt(np.array(variances) + floor ** 2)
    z = (means - reference_means) / error
    p = normal_two_sided_p(z)
    mine_noise = noise(runs)
    their_noise = noise(noise_runs) if noise_runs is not None else mine_noise
    ratio = mine_noise / their_noise if their_noise > 0 else (1.0 if mine_noise == 0
                                                               else math.inf)
    alike = bool(np.all(runs == runs[0])) and their_noise > 0
    return Comparison(regions, means, reference_means, error, z, p,
                      holm(p, FAMILY_ALPHA), normal_quantile_two_sided(FAMILY_ALPHA / len(p)),
                      ratio, alike)


def diagnosis_measurement(runs: np.ndarray) -> dict:
    """What the diagnosis compares with the catalogued mistakes (diagnosis.py): the
    finest blocks' means and their variances, the noise, and the runs themselves (for
    the calibration's splits; never written out)."""
    level = block_levels(runs.shape[1], runs.shape[2])[-1:]
    means, variances = region_statistics(runs, level)[0]
    return diagnosis.statistical_measurement(means, variances, noise(runs), runs)


# ---------------------------------------------------------------- --view cost

def decode_cost(image: np.ndarray) -> tuple[np.ndarray, float]:
    """Traversal steps per pixel from --view cost's heat map (linear PFM), and how far
    the worst pixel is from the map's colours (0 for a heat map)."""
    best_steps = np.zeros(image.shape[:2])
    best_distance = np.full(image.shape[:2], np.inf)
    for segment in range(3):
        a, b = HEAT_COLOURS[segment], HEAT_COLOURS[segment + 1]
        direction = b - a
        t = np.clip(((image - a) @ direction) / (direction @ direction), 0.0, 1.0)
        distance = np.linalg.norm(image - (a + t[..., None] * direction), axis=-1)
        better = distance < best_distance
        best_distance = np.where(better, distance, best_distance)
        best_steps = np.where(better, (segment + t) / 3.0 * COST_SCALE, best_steps)
    return best_steps, float(best_distance.max())


# ---------------------------------------------------------------- report images

def _save_png(rgb: np.ndarray, path: Path):
    from PIL import Image
    Image.fromarray(srgb.encode_8bit(rgb).astype(np.uint8)).save(path)


def _save_heat(values: np.ndarray, path: Path, scale: int = 8):
    """values in [0, 1] (1: the worst), enlarged for the report."""
    from matplotlib import colormaps
    from PIL import Image
    coloured = colormaps["inferno"](np.clip(np.nan_to_num(values), 0.0, 1.0))[..., :3]
    picture = Image.fromarray((coloured * 255).astype(np.uint8))
    picture.resize((values.shape[1] * scale, values.shape[0] * scale),
                   Image.NEAREST).save(path)


def finest_z_map(comparison: Comparison, shape) -> np.ndarray:
    """|z| / the rejection threshold on the finest blocks, worst channel, per pixel."""
    level = max(r.level for r in comparison.regions)
    picture = np.zeros(shape[:2])
    rows, columns = edges(shape[0], level), edges(shape[1], level)
    for region, z in zip(comparison.regions, comparison.z):
        if region.level == level:
            block = picture[rows[region.row]:rows[region.row + 1],
                            columns[region.column]:columns[region.column + 1]]
            np.maximum(block, abs(z) / comparison.threshold_z, out=block)
    return picture


# ---------------------------------------------------------------- grading

def read_runs(test, outcome, workdir: Path, run, references, describe,
              first_seed: int = SUBMISSION_SEED):
    """The submission's runs (run(args, out) runs it headless with args writing out,
    returning (exit code, output)) and the solution's references (references(): its
    PFMs for reference_arguments(test)), as lists of pictures; or None, with outcome's
    output saying why (a run that failed or wrote no picture, another size).
    describe(code) says what an exit code means."""
    images = []
    outcome.measurement = diagnosis.stopped(test.kind, "failed")
    for number, arguments in enumerate(submission_arguments(test, first_seed)):
        out = workdir / f"{test.slug}-{number}.pfm"
        code, output = run(arguments, out)
        what = " ".join(arguments[len(test.args):])
        try:
            data = read_output(out) if code == 0 else None
        except ValueError as error:
            outcome.output = f"run {number + 1} ({what}) exited 0 but {error}"
            return None
        if data is None:
            outcome.output = (f"run {number + 1} ({what}): the program {describe(code)}, "
                              f"no image:\n{output.strip()}")
            return None
        try:
            images.append(parse_pfm(data, out.name))
        except ValueError as error:
            outcome.output = f"run {number + 1} ({what}): {error}"
            return None
    reference = [read_pfm(path) for path in references()]
    shapes = {image.shape for image in images}
    if shapes != {reference[0].shape}:
        shape = images[0].shape
        outcome.output = (f"image is {shape[1]}x{shape[0]}, expected "
                          f"{reference[0].shape[1]}x{reference[0].shape[0]}")
        return None
    return images, reference


def grade_test(test, outcome, workdir: Path, report_dir: Path, run, references,
               describe, first_seed: int = SUBMISSION_SEED):
    """Fills in outcome (score, output, images, measurement) for a statistical or
    traversal test (read_runs says what the arguments are)."""
    found = read_runs(test, outcome, workdir, run, references, describe, first_seed)
    if found is None:
        return outcome
    images, reference = found
    if test.kind == "traversal":
        return _grade_traversal(test, outcome, report_dir, images, reference)
    return _grade_statistical(test, outcome, report_dir, np.stack(images),
                              np.stack(reference[:test.sampling.reference_runs]),
                              np.stack(reference[test.sampling.reference_runs:]),
                              first_seed)


def broken_pixels(runs: np.ndarray, outcome, kind: str) -> bool:
    """NaN, infinite or negative pixels in any run: the outcome says so (and is
    measured as that stop), and the test scores nothing."""
    bad = ~np.isfinite(runs)
    if bad.any():
        outcome.measurement = diagnosis.stopped(kind, "nan")
        outcome.output = (f"{int(bad.any(axis=(0, 3)).sum())} pixels are NaN or infinite "
                          "in some run (a division by zero, or 0 * inf?)")
        return True
    if (runs < 0).any():
        outcome.measurement = diagnosis.stopped(kind, "negative")
        outcome.output = (f"{int((runs < 0).any(axis=(0, 3)).sum())} pixels are negative: "
                          "light is never negative (a sign, or a negative cosine used?)")
        return True
    return False


def save_report_images(slug: str, report_dir: Path, submission: np.ndarray,
                       reference: np.ndarray, error: np.ndarray, outcome):
    """The report's three pictures: the submission's mean, the solution's, and a heat
    map of where they differ (error: 0 to 1, 1 the worst)."""
    _save_png(submission, report_dir / f"{slug}_submission.png")
    _save_png(reference, report_dir / f"{slug}_reference.png")
    _save_heat(error, report_dir / f"{slug}_error.png")
    outcome.images = {kind: f"{slug}_{kind}.png"
                      for kind in ("submission", "reference", "error")}


def _grade_statistical(test, outcome, report_dir, runs, reference_runs, noise_runs,
                       first_seed: int = SUBMISSION_SEED):
    sampling = test.sampling
    if broken_pixels(runs, outcome, "statistical"):
        return outcome
    result = compare(runs, reference_runs, noise_runs)
    shape = runs.shape[1:]
    levels = sorted({r.level for r in result.regions})
    outcome.measurement = diagnosis_measurement(runs)
    lines = [f"{len(result.regions)} region means ({', '.join(f'{n}x{n}' for n in levels)} "
             f"blocks, each channel) of {sampling.runs} runs of {sampling.spp} samples "
             f"(seeds {first_seed}..{first_seed + sampling.runs - 1}) against the "
             f"solution's {sampling.reference_runs} x {sampling.reference_spp} samples; "
             f"a region fails from |z| > {result.threshold_z:.2f} (Holm, family-wise "
             f"alpha {FAMILY_ALPHA:g})",
             f"largest |z|: {np.abs(result.z).max():.2f}; noise {result.variance_ratio:.2f} x "
             f"the solution's with as many samples (at most {MAX_VARIANCE_RATIO:g})"]
    if result.runs_alike:
        lines.append("every run gave the same picture, although their seeds differ: "
                     "the program ignores --seed, or its picture is not random")
    too_noisy = result.variance_ratio > MAX_VARIANCE_RATIO
    passed = result.passed and not too_noisy
    if passed:
        lines.insert(0, "passed: the same expected picture as the solution's")
    else:
        why = []
        if not result.passed:
            why.append(f"{int(result.rejected.sum())} of {len(result.regions)} region "
                       "means differ from the solution's")
        if too_noisy:
            why.append(f"the picture is {result.variance_ratio:.1f} x as noisy as the "
                       f"solution's with as many samples (at most {MAX_VARIANCE_RATIO:g})")
        lines.insert(0, "failed: " + "; ".join(why))
        worst = np.argsort(-np.abs(result.z))[:5]
        for index in worst:
            if not result.rejected[index]:
                break
            lines.append(f"  {result.regions[index].describe(shape)}: "
                         f"{result.submission[index]:.5g}, the solution "
                         f"{result.reference[index]:.5g} +- "
                         f"{result.standard_error[index]:.2g} (z = {result.z[index]:+.1f})")
    outcome.score = test.max_score if passed else 0.0
    outcome.output = "\n".join(lines)
    save_report_images(test.slug, report_dir, runs.mean(axis=0), reference_runs.mean(axis=0),
                       finest_z_map(result, shape), outcome)
    return outcome


def _grade_traversal(test, outcome, report_dir, images, reference):
    distance, cost = images
    reference_distance, reference_cost = reference
    lines = []
    # 1. The nearest hits: the same distances as the solution's, whatever the tree.
    if not np.isfinite(distance).all():
        outcome.measurement = diagnosis.stopped("traversal", "nan")
        outcome.output = "the distance view has NaN or infinite pixels"
        return outcome
    close = np.abs(distance - reference_distance) <= \
        DISTANCE_TOLERANCE * np.maximum(1.0, np.abs(reference_distance))
    hits_agree = float(np.mean(np.all(close, axis=-1)))
    hits_ok = hits_agree >= HITS_AGREEING
    lines.append(f"nearest hits (--view distance): {hits_agree:.2%} of pixels as the "
                 f"solution's (at least {HITS_AGREEING:.1%})")
    # 2. The work: decoded from the heat map, compared where rays enter the tree.
    steps, off_map = decode_cost(cost)
    reference_steps, _ = decode_cost(reference_cost)
    if off_map > 0.01:
        outcome.output = "\n".join(lines + ["--view cost is not path.comp's heat map "
                                            f"(a pixel {off_map:.2f} off its colours)"])
        return outcome
    working = reference_steps > reference_steps.min() + 0.5
    if not working.any():
        working = np.ones_like(working)
    mean, reference_mean = float(steps[working].mean()), float(reference_steps[working].mean())
    ratio = mean / reference_mean
    work_ok = abs(ratio - 1.0) <= WORK_BAND
    lines.append(f"work (--view cost) where rays enter the tree ({int(working.sum())} "
                 f"pixels): {mean:.1f} steps a ray, the solution's {reference_mean:.1f} "
                 f"({ratio:.2f} x; within {1 - WORK_BAND:.2f}..{1 + WORK_BAND:.2f})")
    top = COST_SCALE - 0.5
    saturated = float(np.mean(steps >= top))
    reference_saturated = float(np.mean(reference_steps >= top))
    bound_ok = saturated <= reference_saturated + SATURATED_EXTRA
    lines.append(f"pixels at the heat map's top ({COST_SCALE:.0f} steps or more; a "
                 f"traversal entering every box does thousands): {saturated:.1%}, the "
                 f"solution's {reference_saturated:.1%} (at most "
                 f"{SATURATED_EXTRA:.0%} more)")
    passed = hits_ok and work_ok and bound_ok
    outcome.measurement = diagnosis.traversal_measurement(
        ~np.all(close, axis=-1), (steps - reference_steps) / COST_SCALE)
    lines.insert(0, "passed" if passed else "failed: " + ", ".join(
        what for what, ok in (("not the solution's nearest hits", hits_ok),
                              ("work outside the band", work_ok),
                              ("too many pixels at the top", bound_ok)) if not ok))
    outcome.score = test.max_score if passed else 0.0
    outcome.output = "\n".join(lines)
    save_report_images(test.slug, report_dir, cost, reference_cost,
                       np.abs(steps - reference_steps) / COST_SCALE + (~np.all(close, axis=-1)),
                       outcome)
    return outcome
