"""Does a sampler draw directions with the density its pdf says? Pearson's chi-square
goodness-of-fit test, in the manner of Mitsuba's chi2 module.

1. Cut the sphere of directions into cells: equal steps in θ and in φ. Cells are
   smaller near the poles, where the sharp peaks of a smooth surface lit from above
   sit, so the quadrature of step 3 resolves them.
2. Draw N directions with the sampler and count how many land in each cell (the
   observed counts). Samples the sampler gives up on (below the surface, ...) are
   counted as one more category, "no direction".
3. Integrate the pdf over each cell (Gauss-Legendre in θ and φ, dω = sin θ dθ dφ) and
   multiply by N: the expected counts. A Gauss-Legendre rule is very accurate for a
   smooth integrand and poor across a jump, so cells are split at the angles θ where
   the pdf is known to jump (the horizon; for a rough dielectric, where the microfacet
   joining wi and wo turns vertical). "No direction" expects N (1 - the pdf's total).
4. Pool the cells expecting fewer than 5 samples into one: the chi-square statistic
   is only chi-square distributed when every category expects a handful.
5. X² = Σ (observed - expected)² / expected, with (categories - 1) degrees of freedom.
   Its p-value is the chance that a correct sampler deviates at least this much.
6. Reject when the p-value is below the significance level. Running many tests, one
   of them fails by chance with probability up to (number of tests) x level, so each
   test uses 0.01 / (number of tests) (Bonferroni's correction).

Samples in a cell whose pdf is zero (directions the pdf calls impossible) fall into the
pooled category, where they expect next to nothing and raise X² a lot.
"""

import math
from dataclasses import dataclass

import numpy as np

MINIMUM_EXPECTED = 5.0


@dataclass
class ChiSquareResult:
    statistic: float
    degrees_of_freedom: int
    p_value: float
    significance: float
    observed: np.ndarray  # per category, after pooling
    expected: np.ndarray

    @property
    def accepted(self):
        return self.p_value >= self.significance

    def __str__(self):
        decision = "accepted" if self.accepted else "REJECTED"
        return (f"X² = {self.statistic:.1f}, {self.degrees_of_freedom} degrees of freedom, "
                f"p = {self.p_value:.3g} (level {self.significance:.2g}): {decision}")


# ---------------------------------------------------------------------------------------
# Cells on the sphere
# ---------------------------------------------------------------------------------------

def cell_index(directions, theta_cells, phi_cells):
    """The cell of each unit direction, numbered theta_index * phi_cells + phi_index."""
    theta = np.arccos(np.clip(directions[..., 2], -1.0, 1.0))  # in [0, π]
    phi = np.arctan2(directions[..., 1], directions[..., 0])  # in [-π, π]
    i = np.floor(theta / np.pi * theta_cells).astype(int)
    j = np.floor((phi + np.pi) / (2.0 * np.pi) * phi_cells).astype(int)
    return np.clip(i, 0, theta_cells - 1) * phi_cells + np.clip(j, 0, phi_cells - 1)


def observed_counts(directions, valid, theta_cells, phi_cells):
    """Samples per cell, then the number of failed samples as the last category."""
    cells = cell_index(directions[valid], theta_cells, phi_cells)
    counts = np.bincount(cells, minlength=theta_cells * phi_cells)
    return np.append(counts, np.count_nonzero(~valid)).astype(float)


def gauss_legendre(edges, order):
    """Nodes and weights of an order-point Gauss-Legendre rule on each interval between
    consecutive edges, all in one flat array (interval by interval)."""
    nodes, weights = np.polynomial.legendre.leggauss(order)  # on [-1, 1]
    edges = np.asarray(edges, dtype=float)
    half_width = 0.5 * (edges[1:] - edges[:-1])[:, None]
    middle = 0.5 * (edges[1:] + edges[:-1])[:, None]
    return (middle + half_width * nodes).ravel(), (half_width * weights).ravel()


def cell_probabilities(pdf, theta_cells, phi_cells, order=6, theta_breaks=()):
    """∫ pdf dω over each cell, then 1 - their sum (the chance of no direction) last.
    pdf: a function of an array of directions (..., 3) returning densities (...).
    theta_breaks: angles where the pdf jumps; no quadrature interval straddles them."""
    cell_edges = np.linspace(0.0, np.pi, theta_cells + 1)
    breaks = [b for b in list(theta_breaks) + [np.pi / 2] if 0.0 < b < np.pi]
    theta_edges = np.unique(np.concatenate([cell_edges, breaks]))
    theta, theta_weights = gauss_legendre(theta_edges, order)
    theta_cell = np.minimum((theta / np.pi * theta_cells).astype(int), theta_cells - 1)
    phi, phi_weights = gauss_legendre(np.linspace(-np.pi, np.pi, phi_cells + 1), order)

    theta, phi = theta[:, None], phi[None, :]
    directions = np.stack(np.broadcast_arrays(np.sin(theta) * np.cos(phi),
                                              np.sin(theta) * np.sin(phi), np.cos(theta)),
                          axis=-1)
    # dω = sin θ dθ dφ
    weights = (theta_weights * np.sin(theta[:, 0]))[:, None] * phi_weights[None, :]
    integrand = pdf(directions) * weights  # (θ nodes, φ nodes)
    per_phi_cell = integrand.reshape(len(theta), phi_cells, order).sum(axis=-1)
    probabilities = np.zeros((theta_cells, phi_cells))
    np.add.at(probabilities, theta_cell, per_phi_cell)  # θ nodes into their cells
    probabilities = probabilities.ravel()
    return np.append(probabilities, 1.0 - probabilities.sum())


# ---------------------------------------------------------------------------------------
# The statistic and its p-value
# ---------------------------------------------------------------------------------------

def pool_small_cells(observed, expected, minimum=MINIMUM_EXPECTED):
    """Merges the categories expecting fewer than `minimum` samples into one. If even
    that one expects too few, it joins the smallest of the others."""
    small = expected < minimum
    kept_observed, kept_expected = list(observed[~small]), list(expected[~small])
    pooled_observed, pooled_expected = observed[small].sum(), expected[small].sum()
    if pooled_expected >= minimum or not kept_expected:
        kept_observed.append(pooled_observed)
        kept_expected.append(pooled_expected)
    elif pooled_observed > 0 or pooled_expected > 0:
        smallest = int(np.argmin(kept_expected))
        kept_observed[smallest] += pooled_observed
        kept_expected[smallest] += pooled_expected
    return np.array(kept_observed), np.array(kept_expected)


def regularized_upper_gamma(a, x):
    """Q(a, x) = Γ(a, x) / Γ(a), for a > 0, x >= 0 (Numerical Recipes, section 6.2):
    a power series for P = 1 - Q when x < a + 1, else a continued fraction for Q."""
    if x <= 0.0:
        return 1.0
    # x^a e^-x / Γ(a), the factor in front of both expansions
    prefactor = math.exp(a * math.log(x) - x - math.lgamma(a))
    if x < a + 1.0:
        term = total = 1.0 / a
        n = 0
        while abs(term) > abs(total) * 1e-16 and n < 10_000:
            n += 1
            term *= x / (a + n)
            total += term
        return max(0.0, 1.0 - prefactor * total)
    # Lentz's evaluation of the continued fraction 1/(x+1-a- 1(1-a)/(x+3-a- 2(2-a)/...))
    tiny = 1e-300
    b = x + 1.0 - a
    c, d = 1.0 / tiny, 1.0 / b
    fraction = d
    for i in range(1, 10_000):
        an = -i * (i - a)
        b += 2.0
        d = an * d + b
        d = tiny if abs(d) < tiny else d
        c = b + an / c
        c = tiny if abs(c) < tiny else c
        d = 1.0 / d
        fraction *= d * c
        if abs(d * c - 1.0) < 1e-16:
            break
    return prefactor * fraction


def chi_square_p_value(statistic, degrees_of_freedom):
    """P(X² >= statistic) for a chi-square variable: Q(k/2, x/2)."""
    return regularized_upper_gamma(0.5 * degrees_of_freedom, 0.5 * statistic)


def chi_square_test(sample_directions, pdf, sample_count, seed=0, theta_cells=60,
                    phi_cells=120, order=6, theta_breaks=(), significance=0.01,
                    test_count=1):
    """Tests sample_directions(rng, count) -> (directions (count, 3), valid (count,))
    against pdf(directions) -> densities, over the whole sphere."""
    directions, valid = sample_directions(np.random.default_rng(seed), sample_count)
    observed = observed_counts(directions, valid, theta_cells, phi_cells)
    expected = sample_count * cell_probabilities(pdf, theta_cells, phi_cells, order,
                                                 theta_breaks)
    level = significance / test_count
    observed, expected = pool_small_cells(observed, np.maximum(expected, 0.0))
    statistic = float(np.sum((observed - expected)**2 / expected))
    dof = len(observed) - 1
    return ChiSquareResult(statistic, dof, chi_square_p_value(statistic, dof), level,
                           observed, expected)
