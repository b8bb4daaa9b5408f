"""The Monte Carlo prototype of chapter 11 (python_prototypes/monte_carlo.py), against
closed forms and statistics: every estimator's mean converges to its exact value, the
error falls as 1/√N, importance and cosine sampling lower the variance, Lambert's formula
for a polygonal light agrees with brute-force quadrature, and forgetting the Jacobian
dω/dA is caught by the same z-test that passes the right estimator."""

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[3]

from python_prototypes import monte_carlo as mc

SEEDS = [1, 2, 3]
LARGE_N = 200_000
PI = np.pi

# A few lights above the floor point (0, 0, 0), normal +z; all fully above its horizon.
LIGHTS = {
    "centred above": mc.square_light(center=(0.0, 0.0, 1.0), side=1.0),
    "offset": mc.square_light(center=(0.8, -0.3, 1.2), side=0.6, radiance=2.5),
    "tilted 35°": mc.square_light(center=(0.2, 0.4, 1.0), side=0.8, tilt_degrees=35.0),
    "figure's": mc.FIGURE_LIGHT,
}


def light_sampler(sampler, light):
    return lambda rng, count: sampler(rng, count, light)


ESTIMATORS = {
    "sine, uniform": (mc.sine_uniform_samples, 2.0),
    "sine, tent importance": (mc.sine_importance_samples, 2.0),
    "sky, uniform hemisphere": (mc.sky_uniform_samples, PI * mc.SKY_RADIANCE),
    "sky, cosine-weighted": (mc.sky_cosine_samples, PI * mc.SKY_RADIANCE),
    **{f"light area sampling, {name}": (light_sampler(mc.light_area_samples, light),
                                        mc.polygon_irradiance(light))
       for name, light in LIGHTS.items()},
}


def passes_z_test(samples, exact, standard_errors=4.0):
    """|estimate - exact| within a few standard errors. The tiny absolute slack is for
    zero-variance estimators, whose standard error is 0 up to rounding."""
    estimate, standard_error = mc.mean_and_standard_error(samples)
    return abs(estimate - exact) <= standard_errors * standard_error + 1e-12 * abs(exact)


# ---------------------------------------------------------------------------------------
# Unbiased, and the error falls as 1/√N
# ---------------------------------------------------------------------------------------

@pytest.mark.parametrize("seed", SEEDS)
@pytest.mark.parametrize("name", ESTIMATORS)
def test_estimate_converges_to_the_closed_form(name, seed):
    sampler, exact = ESTIMATORS[name]
    samples = sampler(np.random.default_rng(seed), LARGE_N)
    estimate, standard_error = mc.mean_and_standard_error(samples)
    assert passes_z_test(samples, exact), (
        f"{name}: {estimate:.6f} ± {standard_error:.2g}, exact {exact:.6f}")


@pytest.mark.parametrize("name", ["sine, uniform", "sine, tent importance",
                                  "sky, uniform hemisphere",
                                  "light area sampling, offset"])
def test_rms_error_falls_as_one_over_root_n(name):
    sampler, exact = ESTIMATORS[name]
    counts = np.array([16, 64, 256, 1024, 4096])
    errors = mc.rms_errors(sampler, exact, counts, runs=256, rng=np.random.default_rng(7))
    slope = mc.log_log_slope(counts, errors)
    assert abs(slope + 0.5) <= 0.08, f"{name}: slope {slope:.3f}"


def test_log_log_slope_of_an_exact_power_law():
    counts = np.array([10, 100, 1000])
    assert mc.log_log_slope(counts, 3.0 / np.sqrt(counts)) == pytest.approx(-0.5)


def test_running_estimates_match_the_direct_ones():
    samples = np.random.default_rng(3).normal(5.0, 2.0, 1000)
    mean, error = mc.running_estimates(samples)
    for n in [2, 10, 1000]:
        direct_mean, direct_error = mc.mean_and_standard_error(samples[:n])
        assert mean[n - 1] == pytest.approx(direct_mean, rel=1e-12)
        assert error[n - 1] == pytest.approx(direct_error, rel=1e-9)


# ---------------------------------------------------------------------------------------
# Variance: importance sampling and cosine-weighted sampling
# ---------------------------------------------------------------------------------------

def midpoint_integral(function, low, high, steps=2_000_000):
    x = low + (np.arange(steps) + 0.5) * (high - low) / steps
    return np.sum(function(x)) * (high - low) / steps


def test_tent_is_a_density_and_sample_tent_follows_it():
    assert midpoint_integral(mc.tent_pdf, 0.0, PI) == pytest.approx(1.0, rel=1e-9)
    x = mc.sample_tent(np.random.default_rng(5), LARGE_N)
    assert np.all((x >= 0.0) & (x <= PI))
    counts, edges = np.histogram(x, bins=20, range=(0.0, PI))
    expected = LARGE_N * np.array([midpoint_integral(mc.tent_pdf, a, b, 1000)
                                   for a, b in zip(edges[:-1], edges[1:])])
    assert np.all(np.abs(counts - expected) <= 5.0 * np.sqrt(expected))


def test_importance_sampling_has_lower_variance_than_uniform():
    rng = np.random.default_rng(11)
    uniform = mc.sine_uniform_samples(rng, LARGE_N).var(ddof=1)
    importance = mc.sine_importance_samples(rng, LARGE_N).var(ddof=1)
    # Exact variances: E[(f/p)²] - 2² = ∫ f²/p dx - 4.
    assert uniform == pytest.approx(PI**2 / 2 - 4, rel=0.02)  # 0.9348
    exact_importance = midpoint_integral(lambda x: np.sin(x)**2 / mc.tent_pdf(x),
                                         0.0, PI) - 4.0
    assert exact_importance == pytest.approx(0.06696, abs=1e-4)
    assert importance == pytest.approx(exact_importance, rel=0.03)
    assert importance < uniform / 10  # about 14 times lower


def test_cosine_sampling_has_zero_variance_under_a_constant_sky():
    rng = np.random.default_rng(13)
    cosine = mc.sky_cosine_samples(rng, LARGE_N)
    uniform = mc.sky_uniform_samples(rng, LARGE_N)
    np.testing.assert_allclose(cosine, PI * mc.SKY_RADIANCE, rtol=1e-12, atol=0)
    # Uniform: 2π L cos θ with cos θ uniform, so the variance is (2π)²/3 - π² = π²/3.
    assert uniform.var(ddof=1) == pytest.approx(PI**2 / 3, rel=0.02)


@pytest.mark.parametrize("sample", [mc.uniform_hemisphere, mc.cosine_hemisphere])
def test_hemisphere_directions_are_unit_upward_with_their_pdf(sample):
    directions, pdf = sample(np.random.default_rng(17), LARGE_N)
    np.testing.assert_allclose(np.linalg.norm(directions, axis=-1), 1.0, rtol=1e-12)
    assert np.all(directions[:, 2] >= 0.0)
    cos_theta = directions[:, 2]
    if sample is mc.uniform_hemisphere:
        np.testing.assert_allclose(pdf, 1.0 / (2.0 * PI))
        expected_mean_cos = 0.5  # ∫ cos θ dω / 2π
    else:
        np.testing.assert_allclose(pdf, cos_theta / PI)
        expected_mean_cos = 2.0 / 3.0  # ∫ cos² θ dω / π
    assert passes_z_test(cos_theta, expected_mean_cos)


# ---------------------------------------------------------------------------------------
# Lambert's formula against brute-force quadrature over the light
# ---------------------------------------------------------------------------------------

def quadrature_irradiance(light, point, normal, steps=1000):
    """E = ∫ L cos θ_point cos θ_light / d² dA on a steps x steps midpoint grid."""
    s = (np.arange(steps) + 0.5) / steps
    s, t = [grid.ravel() for grid in np.meshgrid(s, s)]
    on_light = light.corner + s[:, None] * light.edge_a + t[:, None] * light.edge_b
    offset = on_light - point
    distance = np.linalg.norm(offset, axis=-1)
    cos_point = np.maximum(0.0, offset @ normal / distance)
    light_normal = np.cross(light.edge_a, light.edge_b)
    light_normal /= np.linalg.norm(light_normal)
    cos_light = np.maximum(0.0, -(offset @ light_normal) / distance)
    cell_area = np.linalg.norm(np.cross(light.edge_a, light.edge_b)) / steps**2
    return light.radiance * np.sum(cos_point * cos_light / distance**2) * cell_area


RECEIVERS = {
    "floor": (np.zeros(3), np.array([0.0, 0.0, 1.0])),
    "tilted receiver": (np.array([0.1, -0.2, 0.0]),
                        np.array([0.3, -0.2, 1.0]) / np.linalg.norm([0.3, -0.2, 1.0])),
}


@pytest.mark.parametrize("receiver", RECEIVERS)
@pytest.mark.parametrize("name", LIGHTS)
def test_lambert_formula_agrees_with_quadrature(name, receiver):
    point, normal = RECEIVERS[receiver]
    light = LIGHTS[name]
    exact = mc.polygon_irradiance(light, point, normal)
    assert exact > 0.0
    assert exact == pytest.approx(quadrature_irradiance(light, point, normal), rel=1e-4)


def test_lambert_formula_for_a_small_light_is_the_point_light_limit():
    light = mc.square_light(center=(0.6, 0.0, 0.8), side=1e-3)
    distance = 1.0  # cos θ_floor = 0.8, cos θ_light = 0.8
    point_light = light.area() * 0.8 * 0.8 / distance**2
    assert mc.polygon_irradiance(light) == pytest.approx(point_light, rel=1e-5)


def test_lambert_formula_behind_the_light_and_below_the_horizon():
    facing_up = mc.square_light(center=(0.0, 0.0, 1.0), side=1.0, tilt_degrees=180.0)
    assert mc.polygon_irradiance(facing_up) == 0.0  # one-sided: the floor sees its back
    across_horizon = mc.square_light(center=(0.0, 0.0, 0.2), side=1.0, tilt_degrees=90.0)
    with pytest.raises(ValueError):
        mc.polygon_irradiance(across_horizon)


# ---------------------------------------------------------------------------------------
# The Jacobian dω/dA: the z-test passes the right estimator and rejects the wrong one
# ---------------------------------------------------------------------------------------

@pytest.mark.parametrize("seed", SEEDS)
@pytest.mark.parametrize("name", ["centred above", "offset", "figure's"])
def test_forgetting_the_jacobian_is_caught(name, seed):
    light = LIGHTS[name]
    exact = mc.polygon_irradiance(light)
    rng = np.random.default_rng(seed)
    right = mc.light_area_samples(rng, LARGE_N, light)
    wrong = mc.light_area_samples_forgot_jacobian(rng, LARGE_N, light)
    assert passes_z_test(right, exact)
    assert not passes_z_test(wrong, exact)


# ---------------------------------------------------------------------------------------
# The command line writes each figure
# ---------------------------------------------------------------------------------------

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


@pytest.mark.parametrize("which", ["convergence", "hemisphere", "light"])
def test_cli_writes_each_figure_as_a_png(tmp_path, which):
    out = tmp_path / f"10_mc_{which}.png"
    result = subprocess.run(
        [sys.executable, str(REPO / "python_prototypes" / "monte_carlo.py"),
         "--which", which, "--seed", "1", "--figure", str(out)],
        capture_output=True, text=True, timeout=120, cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    data = out.read_bytes()
    assert data[:8] == PNG_SIGNATURE and data[12:16] == b"IHDR"
    width = int.from_bytes(data[16:20], "big")
    height = int.from_bytes(data[20:24], "big")
    assert 600 <= width <= 2000 and 300 <= height <= 1500, (width, height)
    assert len(data) > 20_000  # a real plot, not an empty canvas
    assert [p.name for p in tmp_path.iterdir()] == [out.name]  # no partial file left
