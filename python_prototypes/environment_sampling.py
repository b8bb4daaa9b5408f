"""Importance sampling of a latitude-longitude environment map: the tables the C++ host
builds and the lookups the shader makes, in numpy.

The map (sky.py's orientation: u = atan2(x, -z) / 2π, v = acos(y) / π, pixel (r, c) the
patch u in [c, c+1]/W, v in [r, r+1]/H) is a piecewise-constant radiance. Pick a pixel
with probability P(r, c) ∝ luminance(r, c) · sin θ_r, then a point uniformly inside its
(u, v) patch: the density over the unit square is p(u, v) = W H P(r, c). A patch of
du dv covers dω = 2π² sin θ du dv of the sphere, so per steradian

    pdf(ω) = p(u, v) / (2π² sin θ) = W H P(r, c) / (2π² sin θ).

The sin θ in the weight matches the pixels' true sizes: rows near the poles are thin
slivers of the sphere. Forget it in the weight and the sampler still works, only worse,
as long as the pdf is computed from the table it used; forget it in the pdf (the
classic bug) and every estimate is wrong.

Tables, as the C++ host will build them: the marginal CDF over rows (H + 1 numbers,
from 0 to 1) and one conditional CDF per row over its columns (H x (W + 1)). One number
u1 picks the row by binary search in the marginal CDF, and where it falls inside that
row's step places the point inside the pixel vertically; u2 does the same within the row.

    python python_prototypes/environment_sampling.py --figure sampling.png
    python python_prototypes/environment_sampling.py --map sky.pfm --figure sky_sampling.png
"""

import argparse
import math
from dataclasses import dataclass

import numpy as np


from python_prototypes.chi_square import chi_square_p_value, pool_small_cells
from python_prototypes.figure_file import save_figure_file
from python_prototypes import sky

UP = np.array([0.0, 1.0, 0.0])  # the map's zenith, v = 0


# ---------------------------------------------------------------------------------------
# Tables
# ---------------------------------------------------------------------------------------

def pixel_weights(image, sin_theta_weighting=True):
    """Luminance x sin θ of each pixel's centre (height, width): proportional to the
    pixel's share of the map's light. sin_theta_weighting=False: luminance alone."""
    height = image.shape[0]
    weights = sky.luminance(image)
    if sin_theta_weighting:
        weights = weights * np.sin(np.pi * (np.arange(height) + 0.5) / height)[:, None]
    return np.maximum(weights, 0.0)


def cumulative_distribution(weights):
    """CDF along the last axis with a leading 0 and a last entry of exactly 1. A row of
    zero total gets a uniform CDF (the marginal never picks it, but the table must be
    valid)."""
    steps = weights.shape[-1]
    sums = np.cumsum(weights, axis=-1)
    totals = sums[..., -1:]
    uniform = np.arange(1, steps + 1) / steps
    cdf = np.where(totals > 0, sums / np.where(totals > 0, totals, 1.0), uniform)
    cdf[..., -1] = 1.0  # rounding must not leave a gap above the last step
    zeros = np.zeros(weights.shape[:-1] + (1,))
    return np.concatenate([zeros, cdf], axis=-1)


# --8<-- [start:sampler]
@dataclass
class EnvironmentSampler:
    """The map and its sampling tables: marginal_cdf (H + 1,) over rows,
    conditional_cdf (H, W + 1) over the columns of each row, and pixel_probability
    (H, W) = P(r, c), which the pdf needs."""
    image: np.ndarray
    marginal_cdf: np.ndarray
    conditional_cdf: np.ndarray
    pixel_probability: np.ndarray

    @classmethod
    def from_image(cls, image, sin_theta_weighting=True):
        image = np.asarray(image, dtype=np.float64)
        weights = pixel_weights(image, sin_theta_weighting)
        if weights.sum() <= 0:
            weights = np.ones_like(weights)  # a black map: uniform, never divide by 0
        row_sums = weights.sum(axis=1)
        probability = weights / weights.sum()
        return cls(image, cumulative_distribution(row_sums),
                   cumulative_distribution(weights), probability)

    @property
    def height(self):
        return self.image.shape[0]

    @property
    def width(self):
        return self.image.shape[1]

    def sample(self, u1, u2):
        """Directions (N, 3), their pdf per steradian (N,) and pixels (rows, columns)
        for uniform numbers u1, u2 in [0, 1). A pdf of 0 (a direction exactly at a
        pole, sin θ = 0) means: discard the sample."""
        u1, u2 = np.asarray(u1, dtype=np.float64), np.asarray(u2, dtype=np.float64)
        row, v_inside = invert_cdf(self.marginal_cdf, u1)
        column, u_inside = invert_cdf(self.conditional_cdf, u2, which=row)
        u = (column + u_inside) / self.width
        v = (row + v_inside) / self.height
        directions = sky.uv_to_direction(u, v)
        return directions, self.pdf_of_pixel(row, column, np.sin(np.pi * v)), (row, column)

    def pdf_of_pixel(self, row, column, sin_theta):
        """W H P(r, c) / (2π² sin θ); 0 where sin θ = 0."""
        density_uv = self.width * self.height * self.pixel_probability[row, column]
        safe = np.where(sin_theta > 0, sin_theta, 1.0)
        return np.where(sin_theta > 0, density_uv / (2.0 * np.pi**2 * safe), 0.0)

    def pdf(self, directions):
        """The pdf per steradian with which sample() returns these unit directions."""
        directions = np.asarray(directions, dtype=np.float64)
        row, column = sky.pixel_of_direction(directions, self.width, self.height)
        sin_theta = np.hypot(directions[..., 0], directions[..., 2])
        return self.pdf_of_pixel(row, column, sin_theta)

    def radiance(self, directions):
        """RGB (..., 3) of the pixel each direction falls in: the nearest-pixel lookup
        that the piecewise-constant sampling assumes."""
        row, column = sky.pixel_of_direction(directions, self.width, self.height)
        return self.image[row, column]
# --8<-- [end:sampler]


def invert_cdf(table, u, which=None):
    """For each u in [0, 1): the step i of its CDF with cdf[i] <= u < cdf[i + 1] (so a
    step of zero width is never chosen) and where u falls inside that step, in [0, 1).
    table: one CDF (n + 1,), or CDFs (rows, n + 1) with which (N,) the row of each u.
    A binary search, at most ⌈log2 n⌉ halvings for every u, as the shader will do it."""
    table = np.asarray(table)
    if table.ndim == 1:
        table, which = table[None, :], np.zeros(len(u), dtype=np.int64)
    low = np.zeros(len(u), dtype=np.int64)  # table[which, low] <= u, always
    high = np.full(len(u), table.shape[1] - 1)  # table[which, high] > u: the last is 1
    while np.any(high - low > 1):
        middle = (low + high) // 2
        right = table[which, middle] <= u
        low = np.where(right, middle, low)
        high = np.where(right, high, middle)
    start, end = table[which, low], table[which, low + 1]
    inside = (u - start) / np.where(end > start, end - start, 1.0)
    return low, np.clip(inside, 0.0, np.nextafter(1.0, 0.0))


def pdf_forgot_sin_theta(sampler, directions):
    """The classic bug: the pdf over (u, v) taken for the pdf per steradian without the
    Jacobian 1 / sin θ, W H P(r, c) / (2π²). Estimates divided by it are biased."""
    return sampler.pdf(directions) * np.hypot(directions[..., 0], directions[..., 2])


# ---------------------------------------------------------------------------------------
# Checks: probabilities per pixel, irradiance, chi-square
# ---------------------------------------------------------------------------------------

def pixel_probabilities_from_pdf(pdf, width, height, subdivisions=4):
    """∫ pdf dω over each pixel (height, width), by the midpoint rule on a
    subdivisions² grid in (u, v) with dω = 2π² sin θ du dv. A pdf ∝ 1/sin θ inside a
    pixel (ours) is integrated exactly."""
    offsets = (np.arange(subdivisions) + 0.5) / subdivisions
    u = ((np.arange(width)[:, None] + offsets).ravel()) / width
    v = ((np.arange(height)[:, None] + offsets).ravel()) / height
    grid_u, grid_v = np.meshgrid(u, v)
    sin_theta = np.sin(np.pi * grid_v)
    area = 2.0 * np.pi**2 * sin_theta / (width * height * subdivisions**2)
    values = pdf(sky.uv_to_direction(grid_u, grid_v)) * area
    return values.reshape(height, subdivisions, width, subdivisions).sum(axis=(1, 3))


def sample_counts(rows, columns, width, height):
    return np.bincount(rows * width + columns, minlength=width * height).reshape(height,
                                                                               width)


def irradiance_samples(sampler, rng, count, pdf=None):
    """Samples (count, 3) of the irradiance on an upward-facing (+y) point:
    L(ω) max(cos θ, 0) / pdf(ω) with ω from sampler.sample. pdf: another function of
    the directions to divide by (to show a wrong one); samples of pdf 0 count 0."""
    directions, sample_pdf, _ = sampler.sample(rng.random(count), rng.random(count))
    if pdf is not None:
        sample_pdf = pdf(sampler, directions)
    cosine = np.maximum(directions @ UP, 0.0)
    usable = sample_pdf > 0
    weight = np.where(usable, cosine / np.where(usable, sample_pdf, 1.0), 0.0)
    return sampler.radiance(directions) * weight[:, None]


def mean_and_standard_error(samples):
    """Per column: the mean and its standard error √(s² / N)."""
    return samples.mean(axis=0), samples.std(axis=0, ddof=1) / math.sqrt(len(samples))


def chi_square_test(observed, expected, min_expected=5.0):
    """Pearson's test of counts against expected counts (same total), bins expecting
    fewer than min_expected pooled as chi_square.py pools them. Samples where the pdf
    says none count against the sampler. Returns (statistic, dof, p-value)."""
    observed, expected = pool_small_cells(np.ravel(observed).astype(np.float64),
                                          np.ravel(expected).astype(np.float64), min_expected)
    if np.any((expected <= 0) & (observed > 0)):  # samples where none were expected
        return math.inf, len(expected) - 1, 0.0
    keep = expected > 0
    statistic = float(np.sum((observed[keep] - expected[keep]) ** 2 / expected[keep]))
    dof = int(keep.sum()) - 1
    if dof < 1:  # one bin: the totals agree by construction, nothing to test
        return statistic, 0, 1.0
    return statistic, dof, chi_square_p_value(statistic, dof)


def sampler_chi_square(sampler, reference, rng, count, subdivisions=1):
    """Samples `count` directions from sampler and tests them, binned per pixel (each
    pixel split into subdivisions² cells), against the probabilities reference.pdf
    gives the cells. Returns (statistic, dof, p-value)."""
    fine_width, fine_height = sampler.width * subdivisions, sampler.height * subdivisions
    directions, _, _ = sampler.sample(rng.random(count), rng.random(count))
    rows, columns = sky.pixel_of_direction(directions, fine_width, fine_height)
    observed = sample_counts(rows, columns, fine_width, fine_height)
    expected = count * pixel_probabilities_from_pdf(reference.pdf, fine_width, fine_height)
    return chi_square_test(observed, expected)


# ---------------------------------------------------------------------------------------
# Figure
# ---------------------------------------------------------------------------------------

def draw_samples_on_map(axes, sampler, rng, count):
    """log10 of the luminance (a sky's sun and a test map's spots and background all
    show), with sampled directions over it."""
    log_luminance = np.log10(np.maximum(sky.luminance(sampler.image), 1e-6))
    # Up to the 99.9th percentile: a sun of one pixel would leave the sky all black.
    picture = axes.imshow(log_luminance, extent=(0, 360, -90, 90), cmap="gray",
                          vmax=np.percentile(log_luminance, 99.9), interpolation="nearest")
    axes.figure.colorbar(picture, ax=axes, shrink=0.8, label="log10 luminance")
    directions, _, _ = sampler.sample(rng.random(count), rng.random(count))
    u, v = sky.direction_to_uv(directions)
    axes.plot(360 * u, 90 - 180 * v, ".", color="tab:orange", markersize=2.5)
    axes.set_xticks(range(0, 361, 45))
    axes.set_yticks(range(-90, 91, 30))
    axes.set_xlabel("azimuth (degrees, 360 u)")
    axes.set_ylabel("elevation (degrees)")
    axes.set_title(f"The map and {count} directions drawn from it (pixel ∝ luminance "
                   "x sin θ, uniform inside the pixel)", fontsize=10)


def draw_row_histogram(axes, sampler, wrong, rng, count):
    """Samples per row against the pdf's expectation, for the right sampler and for
    one built without sin θ."""
    height, width = sampler.height, sampler.width
    expected = count * pixel_probabilities_from_pdf(sampler.pdf, width, height).sum(axis=1)
    elevation = 90 - 180 * (np.arange(height) + 0.5) / height
    axes.step(elevation, expected, where="mid", color="black", linewidth=1.2,
              label="expected from pdf(ω)")
    for candidate, label, color in [(sampler, "sampled, weight L sin θ", "tab:green"),
                                    (wrong, "sampled, weight L (no sin θ)", "tab:red")]:
        _, _, (rows, _) = candidate.sample(rng.random(count), rng.random(count))
        axes.plot(elevation, np.bincount(rows, minlength=height), "o", color=color,
                  markersize=3.5, label=label)
    axes.set_yscale("log")
    axes.set_xlabel("elevation of the row (degrees)")
    axes.set_ylabel(f"samples per row (of {count})")
    axes.set_title("Per row: the sin θ weighting matters most near the poles", fontsize=10)
    axes.grid(True, which="both", alpha=0.3)
    axes.legend(fontsize=8.5)


def draw_ratio(axes, sampler, wrong, rng, count):
    """Observed / expected count per pixel for the right sampler, with both p-values."""
    height, width = sampler.height, sampler.width
    directions, _, (rows, columns) = sampler.sample(rng.random(count), rng.random(count))
    observed = sample_counts(rows, columns, width, height)
    expected = count * pixel_probabilities_from_pdf(sampler.pdf, width, height)
    picture = axes.imshow(observed / expected, extent=(0, 360, -90, 90), cmap="coolwarm",
                          vmin=0.8, vmax=1.2, interpolation="nearest")
    axes.figure.colorbar(picture, ax=axes, shrink=0.8, label="observed / expected")
    _, dof, p_right = chi_square_test(observed, expected)
    _, _, p_wrong = sampler_chi_square(wrong, sampler, rng, count)
    axes.set_xticks(range(0, 361, 90))
    axes.set_yticks(range(-90, 91, 45))
    axes.set_title(f"{count:,} samples, counted per pixel, against pdf(ω):\n"
                   f"χ² p = {p_right:.3f} ({dof} dof); built without sin θ: p = "
                   f"{p_wrong:.2g}", fontsize=10)


def save_figure(path, image, seed):
    import matplotlib
    matplotlib.use("Agg")  # no window: we only write a file
    import matplotlib.pyplot as plt

    rng = np.random.default_rng(seed)
    sampler = EnvironmentSampler.from_image(image)
    wrong = EnvironmentSampler.from_image(image, sin_theta_weighting=False)
    figure = plt.figure(figsize=(10, 8.4), dpi=100)
    grid = figure.add_gridspec(2, 2, height_ratios=(1.15, 1))
    draw_samples_on_map(figure.add_subplot(grid[0, :]), sampler, rng, 2000)
    draw_row_histogram(figure.add_subplot(grid[1, 0]), sampler, wrong, rng, 200_000)
    draw_ratio(figure.add_subplot(grid[1, 1]), sampler, wrong, rng, 1_000_000)
    save_figure_file(figure, path)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--map", help="a lat-long PFM (default: sky.py's spots test map)")
    parser.add_argument("--figure", help="write the figure (PNG) here")
    parser.add_argument("--samples", type=int, default=1_000_000,
                        help="samples for the printed checks (default 1 000 000)")
    parser.add_argument("--seed", type=int, default=1, help="random seed (default 1)")
    args = parser.parse_args(argv)
    image = sky.read_pfm(args.map) if args.map else sky.spots_map()
    rng = np.random.default_rng(args.seed)
    sampler = EnvironmentSampler.from_image(image)
    samples = irradiance_samples(sampler, rng, args.samples)
    estimate, error = mean_and_standard_error(samples)
    exact = sky.upward_irradiance(image)
    print(f"upward irradiance, {args.samples} samples: "
          + ", ".join(f"{e:.5g} ± {s:.2g} (exact {x:.5g})"
                      for e, s, x in zip(estimate, error, exact)))
    if args.figure:
        save_figure(args.figure, image, args.seed)
        print(f"wrote {args.figure}")


if __name__ == "__main__":
    main()
