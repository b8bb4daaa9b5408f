"""Participating media in numpy: the pieces the media chapter's shaders are checked
against, each small enough to read beside its formula.

Light crossing a medium is absorbed (coefficient sigma_a, per metre) and scattered
(sigma_s); together they extinguish it, sigma_t = sigma_a + sigma_s. Along a ray,

    transmittance  T(t) = exp(-tau(t)),   optical depth  tau(t) = integral_0^t sigma_t(s) ds

(Beer-Lambert). In a homogeneous medium tau(t) = sigma_t t.

- Free-flight sampling draws the distance to the next collision with density
  p(t) = sigma_t exp(-sigma_t t), by inverting its CDF 1 - exp(-sigma_t t).
- The Henyey-Greenstein phase function says where scattered light goes: a lobe around
  the direction of travel whose mean cosine is g (g > 0 forwards, g < 0 backwards,
  g = 0 the same in every direction). It is sampled exactly by inverting its CDF.
- Where sigma_t varies (smoke, clouds), a majorant sigma_bar >= sigma_t everywhere on
  the ray fills the medium up with fictitious particles to a homogeneous one: delta
  tracking samples collisions with sigma_bar and keeps one as real with probability
  sigma_t(x) / sigma_bar (the distance it returns has the density sigma_t(t) T(t)), and
  ratio tracking multiplies (1 - sigma_t(x) / sigma_bar) over the tentative collisions,
  an unbiased estimate of T for shadow rays.
- A chromatic medium (sigma_t per channel) still draws one distance per path: picked
  with one channel, weighted per channel over the mean of the channels' densities.

Conventions: a direction is the one light travels in; cos_theta is the cosine between
the direction of travel before and after scattering (pbrt-v4 and Mitsuba 3 write the
same function with their own sign conventions for the incident direction).
"""

from __future__ import annotations

import numpy as np

FOUR_PI = 4.0 * np.pi
# Below this |g| the phase function is drawn as the uniform one: the exact inversion
# divides by g.
ISOTROPIC_G = 1e-3


# ---------------------------------------------------------------------------------------
# Transmittance (Beer-Lambert)
# ---------------------------------------------------------------------------------------

def transmittance(sigma_t, distance):
    """exp(-sigma_t distance): the share of light left after `distance` metres of a
    homogeneous medium (per channel when sigma_t is an RGB triple)."""
    return np.exp(-np.asarray(sigma_t, dtype=float) * np.asarray(distance, dtype=float))


class PiecewiseDensity:
    """sigma_t along a ray, constant between breakpoints: sigma_t = values[i] on
    [edges[i], edges[i + 1]), zero beyond the last edge (the ray has left the medium)."""

    def __init__(self, edges, values):
        self.edges = np.asarray(edges, dtype=float)
        self.values = np.asarray(values, dtype=float)
        assert len(self.edges) == len(self.values) + 1 and np.all(np.diff(self.edges) > 0)
        assert np.all(self.values >= 0)

    def sigma_t(self, t):
        t = np.asarray(t, dtype=float)
        index = np.searchsorted(self.edges, t, side="right") - 1
        inside = (index >= 0) & (index < len(self.values))
        return np.where(inside, self.values[np.clip(index, 0, len(self.values) - 1)], 0.0)

    def optical_depth(self, t):
        """tau(t): the integral of sigma_t from 0 to t, exactly (a sum of rectangles)."""
        t = np.asarray(t, dtype=float)
        lengths = np.clip(t[..., None] - self.edges[:-1], 0.0, np.diff(self.edges))
        return (lengths * self.values).sum(axis=-1)

    def majorant(self):
        return float(self.values.max())


# ---------------------------------------------------------------------------------------
# Free flights
# ---------------------------------------------------------------------------------------

def sample_free_flight(sigma_t, u):
    """The distance to the next collision in a homogeneous medium, for u uniform in
    [0, 1): -log(1 - u) / sigma_t (1 - u, so that u = 0 gives 0, never log 0)."""
    return -np.log1p(-np.asarray(u, dtype=float)) / sigma_t


def free_flight_pdf(sigma_t, t):
    """sigma_t exp(-sigma_t t): the density of sample_free_flight's distances."""
    return sigma_t * np.exp(-sigma_t * np.asarray(t, dtype=float))


# ---------------------------------------------------------------------------------------
# Henyey-Greenstein
# ---------------------------------------------------------------------------------------

def henyey_greenstein(cos_theta, g):
    """The phase function's value per steradian: (1 - g^2) / (4 pi (1 + g^2 - 2 g cos)^1.5).
    It integrates to 1 over the sphere, and its mean cosine is g."""
    cos_theta = np.asarray(cos_theta, dtype=float)
    denominator = 1.0 + g * g - 2.0 * g * cos_theta
    return (1.0 - g * g) / (FOUR_PI * denominator * np.sqrt(denominator))


def sample_henyey_greenstein_cosine(g, u):
    """cos_theta with the density of the phase function (over cos_theta: 2 pi p), by
    inverting its CDF; the uniform sphere's 1 - 2u when g is nearly 0."""
    u = np.asarray(u, dtype=float)
    if abs(g) < ISOTROPIC_G:
        return 1.0 - 2.0 * u
    square = (1.0 - g * g) / (1.0 - g + 2.0 * g * u)
    return np.clip((1.0 + g * g - square * square) / (2.0 * g), -1.0, 1.0)


def orthonormal_basis(direction):
    """Two unit vectors at right angles to each other and to `direction` (..., 3),
    without a branch on the sign of z (Duff et al. 2017)."""
    x, y, z = direction[..., 0], direction[..., 1], direction[..., 2]
    sign = np.where(z >= 0.0, 1.0, -1.0)
    a = -1.0 / (sign + z)
    b = x * y * a
    tangent = np.stack([1.0 + sign * x * x * a, sign * b, -sign * x], axis=-1)
    bitangent = np.stack([b, sign + y * y * a, -y], axis=-1)
    return tangent, bitangent


def sample_henyey_greenstein(direction, g, u1, u2):
    """A new direction of travel for light scattered from `direction` (unit, (..., 3)):
    the cosine from sample_henyey_greenstein_cosine, the angle around it uniform."""
    cos_theta = sample_henyey_greenstein_cosine(g, u1)[..., None]
    sin_theta = np.sqrt(np.maximum(0.0, 1.0 - cos_theta * cos_theta))
    phi = (2.0 * np.pi * np.asarray(u2, dtype=float))[..., None]
    tangent, bitangent = orthonormal_basis(direction)
    return (sin_theta * (np.cos(phi) * tangent + np.sin(phi) * bitangent)
            + cos_theta * direction)


# ---------------------------------------------------------------------------------------
# Heterogeneous media: delta tracking and ratio tracking
# ---------------------------------------------------------------------------------------

def delta_tracking(density: PiecewiseDensity, t_max, rng, count):
    """The distance of the first real collision along each of `count` rays, or inf where
    the ray leaves [0, t_max] without one. Tentative collisions come at the majorant's
    rate; each is real with probability sigma_t(x) / majorant. Returns (distances,
    tentative collisions per ray)."""
    majorant = density.majorant()
    t = np.zeros(count)
    alive = np.ones(count, dtype=bool)
    steps = np.zeros(count, dtype=int)
    result = np.full(count, np.inf)
    while alive.any():
        t[alive] += sample_free_flight(majorant, rng.random(alive.sum()))
        left = alive & (t >= t_max)
        alive &= ~left
        steps[alive] += 1
        real = alive.copy()
        real[alive] = rng.random(alive.sum()) < density.sigma_t(t[alive]) / majorant
        result[real] = t[real]
        alive &= ~real
    return result, steps


def ratio_tracking(density: PiecewiseDensity, t_max, rng, count):
    """An unbiased estimate of T(t_max) per ray: the product of (1 - sigma_t(x) /
    majorant) over the tentative collisions before t_max. Its mean is exp(-tau(t_max))."""
    majorant = density.majorant()
    t = np.zeros(count)
    weight = np.ones(count)
    alive = np.ones(count, dtype=bool)
    while alive.any():
        t[alive] += sample_free_flight(majorant, rng.random(alive.sum()))
        alive &= t < t_max
        weight[alive] *= 1.0 - density.sigma_t(t[alive]) / majorant
    return weight


# ---------------------------------------------------------------------------------------
# Chromatic media: one distance for three channels
# ---------------------------------------------------------------------------------------

def chromatic_escape_estimate(sigma_t_rgb, distance, rng, count):
    """Transmittance through a homogeneous slab whose sigma_t differs per channel, with
    one free flight per path for all three channels, as Mitsuba's volpath does: the
    distance is drawn with a channel picked uniformly, so its density is the mean of
    the three channels' densities, and each channel's estimate is weighted by its own
    probability over that mean (a one-sample multiple importance estimate, balance
    heuristic). Returns (count, 3) estimates whose mean is exp(-sigma_t d) per channel."""
    sigma = np.asarray(sigma_t_rgb, dtype=float)
    channel = rng.integers(0, 3, size=count)
    t = sample_free_flight(sigma[channel], rng.random(count))
    escaped = (t >= distance)[:, None]
    # The chance of flying past `distance` in each channel, and its mean over channels.
    past = np.exp(-sigma * distance)
    return np.where(escaped, past / past.mean(), 0.0) * np.ones((count, 3))


# ---------------------------------------------------------------------------------------
# A furnace: a volumetric path tracer for one sphere of medium
# ---------------------------------------------------------------------------------------

def sphere_exit_distance(origin, direction, radius):
    """How far a ray from inside a sphere about the origin travels before it leaves."""
    b = np.sum(origin * direction, axis=-1)
    c = np.sum(origin * origin, axis=-1) - radius * radius
    return -b + np.sqrt(np.maximum(b * b - c, 0.0))


def furnace(sigma_s, sigma_a, g, radius, rng, count, max_bounces=1000):
    """Radiance seen along `count` rays that enter a sphere of homogeneous medium through
    its centre, lit by a uniform environment of radiance 1 and nothing else: each path
    flies (free flights with sigma_t), scatters (Henyey-Greenstein) until it leaves,
    weighted by the albedo sigma_s / sigma_t at each scattering, and then sees the
    environment. With no absorption the answer is exactly 1 whatever sigma_s and g (the
    medium only moves light about); with no scattering it is exp(-sigma_a 2 radius)."""
    sigma_t = sigma_s + sigma_a
    albedo = sigma_s / sigma_t if sigma_t > 0 else 0.0
    position = np.tile([0.0, 0.0, -radius], (count, 1))
    direction = np.tile([0.0, 0.0, 1.0], (count, 1))
    weight = np.ones(count)
    radiance = np.zeros(count)
    alive = np.ones(count, dtype=bool)
    for _ in range(max_bounces):
        if not alive.any():
            break
        exit_distance = sphere_exit_distance(position[alive], direction[alive], radius)
        flight = (sample_free_flight(sigma_t, rng.random(alive.sum())) if sigma_t > 0
                  else np.full(alive.sum(), np.inf))
        leaves = flight >= exit_distance
        index = np.flatnonzero(alive)
        radiance[index[leaves]] = weight[index[leaves]]  # the environment's radiance is 1
        alive[index[leaves]] = False
        scatter = index[~leaves]
        position[scatter] += flight[~leaves, None] * direction[scatter]
        weight[scatter] *= albedo
        direction[scatter] = sample_henyey_greenstein(direction[scatter], g,
                                                      rng.random(len(scatter)),
                                                      rng.random(len(scatter)))
    return radiance
