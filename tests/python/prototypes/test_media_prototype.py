"""python_prototypes/media.py against closed forms and statistics: Beer-Lambert, free
flights, the Henyey-Greenstein phase function (its integral, its mean cosine, and its
sampler by chi-square), delta tracking and ratio tracking on a piecewise-constant
density. Each sampler's check is shown to reject a plausible wrong version too."""

from __future__ import annotations

import math

import numpy as np
import pytest

from python_prototypes import chi_square as cs
from python_prototypes import media

SAMPLES = 200_000
G_VALUES = [-0.7, 0.0, 0.3, 0.9]
SIGMAS = 5.0  # a correct estimate is further off than this by chance 1 in ~1.7 million
# Smoke along a ray: thin, dense, empty, medium (per metre), over 4 metres.
SMOKE = media.PiecewiseDensity([0.0, 1.0, 1.5, 2.5, 4.0], [0.3, 2.0, 0.0, 0.8])


def z_score(estimates, expected):
    """How many standard errors the mean of the estimates is from the expected value."""
    error = np.std(estimates) / math.sqrt(len(estimates))
    return abs(np.mean(estimates) - expected) / max(error, 1e-300)


# ---------------------------------------------------------------- Beer-Lambert

def test_transmittance_is_beer_lambert_per_channel():
    sigma_t = np.array([0.1, 1.0, 10.0])
    assert np.allclose(media.transmittance(sigma_t, 2.0), np.exp(-2.0 * sigma_t))
    assert media.transmittance(0.0, 1e9) == 1.0  # vacuum
    # Two slabs one after the other multiply: exp(-a) exp(-b) = exp(-(a + b)).
    assert math.isclose(media.transmittance(0.5, 1.0) * media.transmittance(0.5, 3.0),
                        media.transmittance(0.5, 4.0))


def test_optical_depth_of_a_piecewise_density_is_its_integral():
    # 0.3 x 1 + 2.0 x 0.5 + 0 x 1 + 0.8 x 1.5 = 2.5, and nothing beyond the medium.
    assert math.isclose(SMOKE.optical_depth(4.0), 2.5)
    assert math.isclose(SMOKE.optical_depth(10.0), 2.5)
    assert math.isclose(SMOKE.optical_depth(1.25), 0.3 + 2.0 * 0.25)
    assert SMOKE.sigma_t(1.2) == 2.0 and SMOKE.sigma_t(2.0) == 0.0
    assert SMOKE.sigma_t(-1.0) == 0.0 and SMOKE.sigma_t(5.0) == 0.0


# ---------------------------------------------------------------- free flights

def kolmogorov_smirnov(samples, cdf) -> float:
    """The largest gap between the samples' empirical CDF and the given one."""
    x = np.sort(samples)
    n = len(x)
    theirs = cdf(x)
    return max(np.max(np.arange(1, n + 1) / n - theirs), np.max(theirs - np.arange(n) / n))


def ks_critical(n: int, level: float = 1e-4) -> float:
    """The KS distance a correct sampler exceeds with probability `level` (asymptotic)."""
    return math.sqrt(-0.5 * math.log(level / 2.0) / n)


@pytest.mark.parametrize("sigma_t", [0.2, 1.0, 7.5])
def test_free_flights_have_the_exponential_distribution(sigma_t):
    rng = np.random.default_rng(1)
    t = media.sample_free_flight(sigma_t, rng.random(SAMPLES))
    distance = kolmogorov_smirnov(t, lambda x: 1.0 - np.exp(-sigma_t * x))
    assert distance < ks_critical(SAMPLES)
    assert z_score(t, 1.0 / sigma_t) < SIGMAS  # the mean free path
    # The density integrates to one (trapezoids out to 40 mean free paths).
    grid = np.linspace(0.0, 40.0 / sigma_t, 200_001)
    pdf = media.free_flight_pdf(sigma_t, grid)
    assert math.isclose(np.sum(0.5 * (pdf[1:] + pdf[:-1]) * np.diff(grid)), 1.0,
                        rel_tol=1e-6)


def test_a_free_flight_without_the_log_is_rejected():
    # 2u / sigma_t: the right mean free path (1 / sigma_t), the wrong distribution.
    rng = np.random.default_rng(1)
    t = 2.0 * rng.random(SAMPLES)  # sigma_t = 1
    distance = kolmogorov_smirnov(t, lambda x: 1.0 - np.exp(-x))
    assert distance > ks_critical(SAMPLES)


# ---------------------------------------------------------------- Henyey-Greenstein

@pytest.mark.parametrize("g", G_VALUES)
def test_henyey_greenstein_integrates_to_one_with_mean_cosine_g(g):
    # Over cos theta in [-1, 1] (Gauss-Legendre; dω = 2 pi d(cos theta)).
    nodes, weights = np.polynomial.legendre.leggauss(400)
    p = media.henyey_greenstein(nodes, g)
    assert math.isclose(2.0 * np.pi * np.sum(weights * p), 1.0, rel_tol=1e-6)
    assert math.isclose(2.0 * np.pi * np.sum(weights * p * nodes), g, abs_tol=1e-6)


def test_henyey_greenstein_at_zero_is_the_uniform_sphere():
    assert np.allclose(media.henyey_greenstein(np.linspace(-1, 1, 9), 0.0), 1.0 / (4 * np.pi))


def phase_chi_square(g, sampler, seed=1):
    """The sampled directions around +z against the phase function's density."""
    travel = np.array([0.0, 0.0, 1.0])

    def sample_directions(rng, count):
        directions = sampler(np.tile(travel, (count, 1)), g, rng.random(count),
                             rng.random(count))
        return directions, np.ones(count, dtype=bool)

    def density(directions):
        return media.henyey_greenstein(directions[..., 2], g)
    return cs.chi_square_test(sample_directions, density, SAMPLES, seed=seed,
                              test_count=len(G_VALUES))


@pytest.mark.parametrize("g", G_VALUES)
def test_henyey_greenstein_sampler_passes_chi_square(g):
    result = phase_chi_square(g, media.sample_henyey_greenstein)
    assert result.accepted, str(result)


def test_a_sampler_with_g_of_the_wrong_sign_is_rejected():
    # The classic slip between the conventions for the incident direction: -g.
    def flipped(direction, g, u1, u2):
        return media.sample_henyey_greenstein(direction, -g, u1, u2)
    result = phase_chi_square(0.3, flipped)
    assert not result.accepted, str(result)


def test_sampled_directions_are_unit_vectors_around_any_direction_of_travel():
    rng = np.random.default_rng(2)
    travel = rng.normal(size=(10_000, 3))
    travel /= np.linalg.norm(travel, axis=1, keepdims=True)
    travel[0] = [0.0, 0.0, -1.0]  # the basis' special case
    out = media.sample_henyey_greenstein(travel, 0.6, rng.random(10_000), rng.random(10_000))
    assert np.allclose(np.linalg.norm(out, axis=1), 1.0)
    cosines = np.sum(out * travel, axis=1)
    assert z_score(cosines, 0.6) < SIGMAS  # the mean cosine is g about every direction


# ---------------------------------------------------------------- delta and ratio tracking

@pytest.mark.parametrize("t_max", [1.25, 2.0, 4.0])
def test_delta_tracking_escapes_with_the_transmittance(t_max):
    rng = np.random.default_rng(3)
    distances, _ = media.delta_tracking(SMOKE, t_max, rng, SAMPLES)
    escaped = np.isinf(distances).astype(float)
    assert z_score(escaped, math.exp(-SMOKE.optical_depth(t_max))) < SIGMAS


def test_delta_tracking_collides_with_density_sigma_t_times_transmittance():
    # The real collisions' distances have the CDF 1 - T(t) (for t inside the medium).
    rng = np.random.default_rng(4)
    distances, _ = media.delta_tracking(SMOKE, 4.0, rng, SAMPLES)
    for t in (0.5, 1.0, 1.25, 2.0, 3.0):
        below = (distances < t).astype(float)
        assert z_score(below, 1.0 - math.exp(-SMOKE.optical_depth(t))) < SIGMAS, t
    # None in the empty stretch between 1.5 and 2.5 metres.
    assert not np.any((distances > 1.5) & (distances < 2.5))


def test_delta_tracking_that_keeps_every_tentative_collision_is_caught():
    # Treating the majorant as the medium: far too many collisions.
    rng = np.random.default_rng(5)
    dense = media.PiecewiseDensity(SMOKE.edges, np.full(4, SMOKE.majorant()))
    distances, _ = media.delta_tracking(dense, 4.0, rng, SAMPLES)
    escaped = np.isinf(distances).astype(float)
    assert z_score(escaped, math.exp(-SMOKE.optical_depth(4.0))) > SIGMAS


@pytest.mark.parametrize("t_max", [1.25, 2.0, 4.0])
def test_ratio_tracking_is_unbiased_for_the_transmittance(t_max):
    rng = np.random.default_rng(6)
    weights = media.ratio_tracking(SMOKE, t_max, rng, SAMPLES)
    assert np.all((weights >= 0.0) & (weights <= 1.0))
    assert z_score(weights, math.exp(-SMOKE.optical_depth(t_max))) < SIGMAS


def test_ratio_tracking_is_less_noisy_than_counting_escapes():
    # The reason shadow rays use it: the same mean, a fraction of the variance.
    rng = np.random.default_rng(7)
    ratio = media.ratio_tracking(SMOKE, 4.0, rng, SAMPLES)
    escaped = np.isinf(media.delta_tracking(SMOKE, 4.0, rng, SAMPLES)[0]).astype(float)
    assert np.var(ratio) < 0.5 * np.var(escaped)


def test_ratio_tracking_with_the_ratio_the_wrong_way_up_is_caught():
    # sigma_t / majorant instead of 1 - sigma_t / majorant: a biased estimate.
    rng = np.random.default_rng(8)
    t_max, majorant = 4.0, SMOKE.majorant()
    t = np.zeros(SAMPLES)
    weight = np.ones(SAMPLES)
    alive = np.ones(SAMPLES, dtype=bool)
    while alive.any():
        t[alive] += media.sample_free_flight(majorant, rng.random(alive.sum()))
        alive &= t < t_max
        weight[alive] *= SMOKE.sigma_t(t[alive]) / majorant
    assert z_score(weight, math.exp(-SMOKE.optical_depth(t_max))) > SIGMAS


# ---------------------------------------------------------------- chromatic media

RED_SMOKE = np.array([0.2, 1.0, 3.0])  # sigma_t per channel: thin in red, dense in blue


@pytest.mark.parametrize("distance", [0.3, 1.0, 2.0])
def test_one_distance_for_three_channels_is_unbiased_in_each(distance):
    rng = np.random.default_rng(9)
    estimates = media.chromatic_escape_estimate(RED_SMOKE, distance, rng, SAMPLES)
    for channel in range(3):
        assert z_score(estimates[:, channel],
                       math.exp(-RED_SMOKE[channel] * distance)) < SIGMAS, channel


def test_one_distance_without_weights_is_caught_and_the_chosen_channel_alone_is_noisy():
    rng = np.random.default_rng(10)
    distance = 1.0
    channel = rng.integers(0, 3, size=SAMPLES)
    t = media.sample_free_flight(RED_SMOKE[channel], rng.random(SAMPLES))
    escaped = (t >= distance)[:, None]
    past = np.exp(-RED_SMOKE * distance)
    # An escape counted as 1 in every channel: the mean of the three transmittances in
    # each, so red comes out too dark and blue too bright (grey smoke).
    grey = np.where(escaped, 1.0, 0.0) * np.ones((SAMPLES, 3))
    assert z_score(grey[:, 0], past[0]) > SIGMAS and z_score(grey[:, 2], past[2]) > SIGMAS
    # Weighted by the picked channel's own chance alone: unbiased, but a blue-picked
    # path that escapes weighs red by exp(3 - 0.2) ~ 16, so red is far noisier than with
    # the mean over the channels.
    alone = np.where(escaped, past / past[channel][:, None], 0.0)
    assert z_score(alone[:, 0], past[0]) < SIGMAS
    mean_weighted = media.chromatic_escape_estimate(RED_SMOKE, distance, rng, SAMPLES)
    assert np.var(alone[:, 0]) > 2.0 * np.var(mean_weighted[:, 0])


# ---------------------------------------------------------------- the furnace

@pytest.mark.parametrize("sigma_s, g", [(0.5, 0.0), (4.0, 0.0), (4.0, 0.8), (4.0, -0.5)])
def test_a_scattering_sphere_in_a_white_furnace_is_white(sigma_s, g):
    # No absorption: light is only moved about, so every ray sees radiance 1 exactly.
    rng = np.random.default_rng(11)
    radiance = media.furnace(sigma_s, 0.0, g, 1.0, rng, 20_000)
    assert np.allclose(radiance, 1.0)


def test_an_absorbing_sphere_is_beer_lambert_along_its_diameter():
    # Each path escapes (1) or is absorbed (0): the mean is the transmittance.
    rng = np.random.default_rng(12)
    radiance = media.furnace(0.0, 0.7, 0.0, 1.0, rng, SAMPLES)
    assert z_score(radiance, math.exp(-0.7 * 2.0)) < SIGMAS


def test_scattering_and_absorbing_lies_between_and_loses_light_with_each_bounce():
    rng = np.random.default_rng(13)
    radiance = media.furnace(2.0, 0.5, 0.3, 1.0, rng, SAMPLES)
    # Above pure absorption along the diameter (scattering can shorten the way out),
    # below 1, and its estimate is a mean of albedo^bounces.
    assert math.exp(-2.5 * 2.0) < radiance.mean() < 1.0
    bounces = np.log(radiance[radiance > 0]) / math.log(2.0 / 2.5)
    assert np.allclose(bounces, np.round(bounces))
