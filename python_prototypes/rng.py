"""Chapter 09's random numbers in numpy: the GPU generator, its two seedings, and the
statistics that tell them apart.

The generator is the "hybrid Taus" of GPU Gems 3 (ch. 37): three Tausworthe generators
and a linear congruential generator (LCG), stepped together, their outputs XORed. Each
pixel has its own state of four 32-bit words (z1, z2, z3 Tausworthe; z4 LCG):

    uint tausStep(inout uint z, int s1, int s2, int s3, uint m) {
        uint b = ((z << s1) ^ z) >> s2;
        return z = ((z & m) << s3) ^ b;
    }
    uint lcgStep(inout uint z) { return z = 1664525u * z + 1013904223u; }
    uint nextUint(inout uvec4 z) {
        return tausStep(z.x, 13, 19, 12, 4294967294u) ^ tausStep(z.y, 2, 25, 4, 4294967288u)
             ^ tausStep(z.z, 3, 11, 17, 4294967280u) ^ lcgStep(z.w);
    }
    float nextFloat(inout uvec4 z) { return float(nextUint(z) >> 8) * (1.0 / 16777216.0); }

nextFloat keeps the top 24 bits, which a float holds exactly: the result is exact on
every GPU and in numpy, and lies in [0, 1). (The textbook's `2.3283064365387e-10 * x`
rounds large x up to 1.0 in float32, which a sampling routine does not expect.)

A Tausworthe word must not start below 128: a small state (0 at worst) stays stuck
in its low bits. Both seedings raise such a word by 128 (`z < 128u ? z + 128u : z`).

The four seed words come from --seed on the host: s0 = pcg(seed), s(k+1) = pcg(sk).

- naive seeding, state word k of pixel p:   z_k = s_k + p
- hashed seeding:                           z_k = pcg(s_k + pcg(p))

with p = y * width + x and pcg() the PCG hash (Jarzynski and Olano, JCGT 2020). Wang's
hash is here too, as the alternative the literature names.

Why the naive seeding fails: neighbouring pixels start from states 1 apart. An LCG
step keeps that difference a constant (a^n mod 2^32 after n steps), and a Tausworthe
step is linear in the bits, moving the few low bits that differ up only slowly: the
first number of pixel p + 1 is almost that of pixel p, and rows of nearly equal values
show up as lines (the first sample) and diagonal stripes (the later ones), for as
long as the stream runs (after 1000 numbers, neighbours still correlate with r up to
0.97: throwing the first numbers away does not help). Each pixel's own stream is still
perfectly uniform, so a per-pixel uniformity test passes; what fails are the tests
across neighbouring pixels.

    python python_prototypes/rng.py --report             # the statistics, both seedings
    python python_prototypes/rng.py --figure stripes.png # samples 1, 2: naive / hashed
    python python_prototypes/rng.py --images /tmp/first  # /tmp/first_naive.png, ...
"""

from __future__ import annotations

import argparse
import math
from dataclasses import dataclass

import numpy as np

LCG_MULTIPLIER = 1664525  # Numerical Recipes
LCG_INCREMENT = 1013904223
# (s1, s2, s3, mask) of the three Tausworthe steps (L'Ecuyer 1996, GPU Gems 3 ch. 37).
TAUS_STEPS = ((13, 19, 12, 4294967294), (2, 25, 4, 4294967288), (3, 11, 17, 4294967280))
TAUS_MINIMUM = 128  # a Tausworthe word starting below this gets 128 added
FLOAT_BITS = 24  # nextFloat keeps the top 24 bits

SEEDINGS = ("naive", "hashed", "hashed_wang")

_U32 = np.uint32


def _u32(values) -> np.ndarray:
    """As a uint32 array; Python ints are taken modulo 2^32."""
    if isinstance(values, np.ndarray) and values.dtype == _U32:
        return values
    return np.asarray(np.asarray(values, dtype=np.int64) & 0xFFFFFFFF, dtype=_U32)


# ---------------------------------------------------------------------------------------
# Hashes: one 32-bit word in, one well-mixed 32-bit word out
# ---------------------------------------------------------------------------------------

def pcg_hash(values) -> np.ndarray:
    """The PCG hash: an LCG step, then a PCG output permutation (RXS-M-XS)."""
    x = _u32(values)
    with np.errstate(over="ignore"):
        state = x * _U32(747796405) + _U32(2891336453)
        word = ((state >> ((state >> _U32(28)) + _U32(4))) ^ state) * _U32(277803737)
    return (word >> _U32(22)) ^ word


def wang_hash(values) -> np.ndarray:
    """Thomas Wang's 32-bit integer hash."""
    x = _u32(values)
    with np.errstate(over="ignore"):
        x = (x ^ _U32(61)) ^ (x >> _U32(16))
        x = x * _U32(9)
        x = x ^ (x >> _U32(4))
        x = x * _U32(0x27D4EB2D)
        x = x ^ (x >> _U32(15))
    return x


HASHES = {"hashed": pcg_hash, "hashed_wang": wang_hash}


# ---------------------------------------------------------------------------------------
# Seeding
# ---------------------------------------------------------------------------------------

def seed_words(seed: int) -> np.ndarray:
    """The four uniform seed words the host derives from --seed: a chain of PCG hashes."""
    words = [pcg_hash(seed)]
    for _ in range(3):
        words.append(pcg_hash(words[-1]))
    return np.stack(words)  # shape (4,)


def _raise_small_taus_words(state: np.ndarray) -> np.ndarray:
    taus = state[:3]
    state[:3] = np.where(taus < _U32(TAUS_MINIMUM), taus + _U32(TAUS_MINIMUM), taus)
    return state


def naive_state(seed: int, pixel_index) -> np.ndarray:
    """z_k = s_k + p for each pixel index p: the seeding that shows lines. (4, P)."""
    pixels = _u32(np.atleast_1d(pixel_index))
    with np.errstate(over="ignore"):
        state = seed_words(seed)[:, np.newaxis] + pixels[np.newaxis, :]
    return _raise_small_taus_words(state)


def hashed_state(seed: int, pixel_index, hash_function=pcg_hash) -> np.ndarray:
    """z_k = hash(s_k + hash(p)): neighbouring pixels start far apart. (4, P).

    The inner hash spreads the pixel indices, so that pixel p with seed s and pixel
    p + 1 with seed s - 1 do not start alike (as with hash(s + p)); the outer one makes
    the state a non-linear function of the seed word.
    """
    pixels = _u32(np.atleast_1d(pixel_index))
    with np.errstate(over="ignore"):
        state = hash_function(seed_words(seed)[:, np.newaxis] + hash_function(pixels))
    return _raise_small_taus_words(state)


def initial_state(seeding: str, seed: int, pixel_index) -> np.ndarray:
    """The state of every pixel in pixel_index for a seeding in SEEDINGS: (4, P)."""
    if seeding == "naive":
        return naive_state(seed, pixel_index)
    if seeding in HASHES:
        return hashed_state(seed, pixel_index, HASHES[seeding])
    raise ValueError(f"unknown seeding {seeding!r}; the seedings are {', '.join(SEEDINGS)}")


# ---------------------------------------------------------------------------------------
# The generator
# ---------------------------------------------------------------------------------------

def taus_step(z: np.ndarray, s1: int, s2: int, s3: int, mask: int) -> np.ndarray:
    b = ((z << _U32(s1)) ^ z) >> _U32(s2)
    return ((z & _U32(mask)) << _U32(s3)) ^ b


def lcg_step(z: np.ndarray) -> np.ndarray:
    with np.errstate(over="ignore"):
        return z * _U32(LCG_MULTIPLIER) + _U32(LCG_INCREMENT)


def next_uint(state: np.ndarray) -> np.ndarray:
    """Steps every pixel's state in place (4, P); returns the P outputs, uint32."""
    for k, (s1, s2, s3, mask) in enumerate(TAUS_STEPS):
        state[k] = taus_step(state[k], s1, s2, s3, mask)
    state[3] = lcg_step(state[3])
    return state[0] ^ state[1] ^ state[2] ^ state[3]


def generate(state: np.ndarray, count: int) -> np.ndarray:
    """The next `count` outputs of every stream: uint32 (count, P). Advances state."""
    return np.stack([next_uint(state) for _ in range(count)])


def to_unit_float(bits: np.ndarray) -> np.ndarray:
    """nextFloat: the top 24 bits as a float32 in [0, 1), exact."""
    return ((bits >> _U32(32 - FLOAT_BITS)).astype(np.float32)
            * np.float32(1.0 / (1 << FLOAT_BITS)))


def pixel_streams(seeding: str, seed: int, width: int, height: int,
                  count: int) -> np.ndarray:
    """The first `count` numbers of every pixel as uint32 (count, height, width), pixel
    index y * width + x, row 0 at the top: what a GPU read-back is compared with."""
    state = initial_state(seeding, seed, np.arange(width * height, dtype=np.int64))
    return generate(state, count).reshape(count, height, width)


def pixel_floats(seeding: str, seed: int, width: int, height: int,
                 count: int) -> np.ndarray:
    """pixel_streams() as nextFloat values, float64 (count, height, width)."""
    bits = pixel_streams(seeding, seed, width, height, count)
    return to_unit_float(bits).astype(np.float64)


def first_sample_image(seeding: str, seed: int = 1, width: int = 256,
                       height: int = 256) -> np.ndarray:
    """Every pixel's first random number, as a grey image (height, width) in [0, 1)."""
    return pixel_floats(seeding, seed, width, height, 1)[0]


# ---------------------------------------------------------------------------------------
# Statistics. Each test takes samples u of shape (count, height, width) in [0, 1).
# ---------------------------------------------------------------------------------------

@dataclass
class TestResult:
    name: str
    statistic: float  # the number compared with the limit
    limit: float      # passes when statistic < limit
    detail: str

    @property
    def passed(self) -> bool:
        return self.statistic < self.limit

    def __str__(self):
        verdict = "pass" if self.passed else "FAIL"
        return f"{self.name:<28} {self.statistic:12.3f} (< {self.limit:g}) {verdict}  " \
               f"{self.detail}"


def normal_tail(z: float) -> float:
    """P(Z > z) for a standard normal Z."""
    return 0.5 * math.erfc(z / math.sqrt(2.0))


def chi_square_p_value(chi2, dof: int):
    """P(X > chi2) for X ~ chi-square(dof), by Wilson and Hilferty's cube-root normal
    approximation (good to about 1e-3 in p from 10 degrees of freedom up; numpy only)."""
    chi2 = np.asarray(chi2, dtype=np.float64)
    scale = 2.0 / (9.0 * dof)
    z = (np.cbrt(chi2 / dof) - (1.0 - scale)) / np.sqrt(scale)
    return 0.5 * np.vectorize(math.erfc)(z / math.sqrt(2.0))


def bin_counts(u: np.ndarray, bins: int, axis: int) -> np.ndarray:
    """Histogram of u along `axis` into `bins` equal bins of [0, 1)."""
    index = np.minimum((u * bins).astype(np.int64), bins - 1)
    return np.stack([(index == b).sum(axis=axis) for b in range(bins)], axis=-1)


def stream_uniformity_test(u: np.ndarray, bins: int = 16, alpha: float = 0.01) -> TestResult:
    """Chi-square uniformity of each pixel's own stream (its `count` numbers in `bins`
    bins). A good generator fails at level alpha in a fraction alpha of the pixels; the
    statistic is how many binomial standard deviations the failures are above that."""
    count = u.shape[0]
    pixels = u.reshape(count, -1)
    expected = count / bins
    chi2 = ((bin_counts(pixels, bins, axis=0) - expected) ** 2 / expected).sum(axis=-1)
    failed = int(np.sum(chi_square_p_value(chi2, bins - 1) < alpha))
    total = chi2.size
    excess = (failed - alpha * total) / math.sqrt(total * alpha * (1 - alpha))
    return TestResult("per-pixel uniformity", excess, 5.0,
                      f"{failed} of {total} pixels fail at p < {alpha} "
                      f"(expected {alpha * total:.0f}); mean chi2 {chi2.mean():.2f}, "
                      f"dof {bins - 1}")


def _pearson(a: np.ndarray, b: np.ndarray, axis: int) -> np.ndarray:
    a = a - a.mean(axis=axis, keepdims=True)
    b = b - b.mean(axis=axis, keepdims=True)
    return (a * b).sum(axis=axis) / np.sqrt((a * a).sum(axis=axis) * (b * b).sum(axis=axis))


def neighbour_pairs(u: np.ndarray, direction: str):
    """(left, right) or (upper, lower) neighbours, as disjoint pairs: columns 0-1, 2-3,
    ... (or rows), so that no pixel is in two pairs and the pairs are independent."""
    if direction == "x":
        width = u.shape[2] - u.shape[2] % 2
        return u[:, :, 0:width:2], u[:, :, 1:width:2]
    height = u.shape[1] - u.shape[1] % 2
    return u[:, 0:height:2, :], u[:, 1:height:2, :]


def neighbour_correlation(u: np.ndarray, direction: str = "x") -> np.ndarray:
    """For each sample index n: Pearson r, across the image, between the n-th number
    of each pixel and the n-th number of its right (or lower) neighbour. (count,)"""
    first, second = neighbour_pairs(u, direction)
    count = u.shape[0]
    return _pearson(first.reshape(count, -1), second.reshape(count, -1), axis=1)


def neighbour_correlation_test(u: np.ndarray, direction: str = "x") -> TestResult:
    """The numbers that neighbouring pixels draw at the same moment must be unrelated.
    Uncorrelated, r * sqrt(pairs) is about standard normal; the statistic is the largest
    |r| * sqrt(pairs) over the sample indices (below 5 for a good generator, with room
    for taking the largest of a few hundred)."""
    r = neighbour_correlation(u, direction)
    pairs = neighbour_pairs(u, direction)[0][0].size
    worst = int(np.argmax(np.abs(r)))
    return TestResult(f"neighbour correlation ({direction})",
                      float(np.abs(r[worst]) * math.sqrt(pairs)), 5.0,
                      f"largest |r| = {abs(r[worst]):.4f} at sample {worst} over "
                      f"{pairs} pairs; mean |r| {np.abs(r).mean():.4f}")


def stream_correlation_test(u: np.ndarray) -> TestResult:
    """Mean over pixel pairs (p, p + 1) of Pearson r between their whole streams. Each
    r is about normal(0, 1/sqrt(count)); the statistic is |mean r| in standard errors.
    A weak test: the naive seeding fails it for most seeds but not all (it passes with
    --seed 2024), because what relates two naive streams is not a linear trend in time.
    neighbour_correlation_test, which compares numbers drawn at the same moment, never
    misses."""
    first, second = neighbour_pairs(u, "x")
    count = u.shape[0]
    r = _pearson(first.reshape(count, -1), second.reshape(count, -1), axis=0)
    z = abs(r.mean()) / (r.std() / math.sqrt(r.size))
    return TestResult("stream correlation (x)", float(z), 5.0,
                      f"mean r {r.mean():+.5f} over {r.size} pairs of {count}-number "
                      f"streams (standard error {r.std() / math.sqrt(r.size):.5f})")


def neighbour_pair_uniformity_test(u: np.ndarray, bins: int = 8,
                                   direction: str = "x") -> TestResult:
    """Chi-square test that (u_n(p), u_n(neighbour of p)) is uniform on the unit square,
    pooled over sample indices n and pairs: catches any dependence, not only a linear
    one. The statistic is the chi-square in standard deviations above its mean."""
    first, second = neighbour_pairs(u, direction)
    cells = (np.minimum((first * bins).astype(np.int64), bins - 1) * bins
             + np.minimum((second * bins).astype(np.int64), bins - 1))
    counts = np.bincount(cells.ravel(), minlength=bins * bins)
    expected = cells.size / (bins * bins)
    chi2 = float(((counts - expected) ** 2 / expected).sum())
    dof = bins * bins - 1
    return TestResult(f"neighbour pair chi-square ({direction})",
                      (chi2 - dof) / math.sqrt(2 * dof), 5.0,
                      f"chi2 {chi2:.1f} with {dof} dof over {cells.size} pairs")


def all_tests(u: np.ndarray) -> list[TestResult]:
    return [stream_uniformity_test(u), neighbour_correlation_test(u, "x"),
            neighbour_correlation_test(u, "y"), stream_correlation_test(u),
            neighbour_pair_uniformity_test(u, direction="x"),
            neighbour_pair_uniformity_test(u, direction="y")]


# ---------------------------------------------------------------------------------------
# Command line
# ---------------------------------------------------------------------------------------

def save_figure(path: str, seed: int, width: int, height: int):
    """First and second samples, naive seeding above and hashed seeding below."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    figure, axes = plt.subplots(2, 2, figsize=(8, 8.4), dpi=100)
    for row, seeding in enumerate(["naive", "hashed"]):
        samples = pixel_floats(seeding, seed, width, height, 2)
        for column in range(2):
            axis = axes[row][column]
            axis.imshow(samples[column], cmap="gray", vmin=0, vmax=1,
                        interpolation="nearest")
            axis.set_title(f"{seeding} seeding, sample {column + 1}")
            axis.set_xticks([])
            axis.set_yticks([])
    figure.suptitle(f"Each pixel's random numbers, {width} x {height}, --seed {seed}")
    figure.tight_layout()
    figure.savefig(path)
    plt.close(figure)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--width", type=int, default=256)
    parser.add_argument("--height", type=int, default=256)
    parser.add_argument("--count", type=int, default=64, help="numbers per pixel")
    parser.add_argument("--report", action="store_true", help="print the statistics")
    parser.add_argument("--figure", help="write the first-sample figure (PNG)")
    parser.add_argument("--images", metavar="PREFIX",
                        help="write PREFIX_naive.png and PREFIX_hashed.png: each pixel's "
                             "first number as an 8-bit grey level")
    args = parser.parse_args(argv)
    if args.report or not (args.figure or args.images):
        for seeding in SEEDINGS:
            u = pixel_floats(seeding, args.seed, args.width, args.height, args.count)
            print(f"{seeding} seeding, {args.width} x {args.height} pixels, "
                  f"{args.count} numbers each:")
            for result in all_tests(u):
                print("  " + str(result))
    if args.figure:
        save_figure(args.figure, args.seed, args.width, args.height)
        print(f"wrote {args.figure}")
    if args.images:
        from PIL import Image
        for seeding in ["naive", "hashed"]:
            image = first_sample_image(seeding, args.seed, args.width, args.height)
            path = f"{args.images}_{seeding}.png"
            Image.fromarray((image * 256).astype(np.uint8)).save(path)
            print(f"wrote {path}")


if __name__ == "__main__":
    main()
