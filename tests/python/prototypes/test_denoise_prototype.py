"""python_prototypes/denoise.py on its still life, whose true picture is known: the
weights sum to one (a flat picture stays flat), the albedo comes back exactly, edges in
the features and in the light are kept, five a-trous passes reach 63 pixels across, and
the filtered picture at 8 samples a pixel is closer to the truth than the raw one at 64.
The luminance weight's darkening is measured and shrinks as 1/spp. Each check is shown
to fail on a planted mistake (weights not normalised, the albedo not put back, the
step not doubled, no luminance weight)."""

from __future__ import annotations

import numpy as np
import pytest

from python_prototypes import denoise

SEEDS = range(4)


@pytest.fixture(scope="module")
def scene():
    return denoise.still_life()


def renders(scene, spp):
    return [denoise.noisy_render(scene, spp, np.random.default_rng(seed)) for seed in SEEDS]


def flat_features(height=40, width=48):
    return denoise.Features(np.full((height, width, 3), 0.5),
                            np.tile([0.0, 0.0, 1.0], (height, width, 1)),
                            np.full((height, width), 3.0))


def test_a_flat_picture_stays_flat_only_when_the_weights_are_normalised(scene):
    features = scene.features
    grey = np.full(features.albedo.shape, 0.3)
    for image in (denoise.box_blur(grey, 3), denoise.gaussian_blur(grey, 2.0)):
        assert np.allclose(image, grey, rtol=1e-12)
    # Flat light on the chequered wall: the features' filters keep it (and the texture).
    flat = denoise.remodulate(np.full(features.albedo.shape, 0.7), features.albedo)
    variance = np.full(features.depth.shape, 0.01)
    assert np.allclose(denoise.atrous(flat, variance, features), flat, rtol=1e-12)
    bilateral = denoise.cross_bilateral(denoise.demodulate(flat, features.albedo), features,
                                        4, 2.0)
    assert np.allclose(bilateral, 0.7, rtol=1e-12)
    wrong = denoise.atrous(flat, variance, features, normalise=False)
    assert not np.allclose(wrong, flat, rtol=0.05)  # the weights' sum left in


def test_the_albedo_comes_back_exactly(scene):
    colour = scene.colour
    round_trip = denoise.remodulate(denoise.demodulate(colour, scene.features.albedo),
                                    scene.features.albedo)
    assert np.allclose(round_trip, colour, rtol=1e-12)
    noisy, variance = renders(scene, 8)[0]
    kept = denoise.atrous(noisy, variance, scene.features)
    lost = denoise.atrous(noisy, variance, scene.features, put_albedo_back=False)
    assert denoise.relative_mse(kept, colour) < 0.02
    assert denoise.relative_mse(lost, colour) > 0.5  # the chequer gone, light as colour


def test_edge_weights_stop_at_silhouettes_and_creases_not_on_a_surface(scene):
    features = scene.features
    h, w = features.depth.shape
    sigmas = denoise.Sigmas()
    right = denoise.edge_weights(features, 0, 1, sigmas)
    down = denoise.edge_weights(features, 1, 0, sigmas)
    row, wall_x = int(0.5 * h), w // 4
    box_left = int(np.argmax(features.depth[row] < 3.0))  # the box's first column
    assert right[row, wall_x] == pytest.approx(1.0)  # the wall, flat and facing us
    assert right[row, box_left - 1] < 1e-6        # wall, then box: depth jumps
    crease = int(np.argmax(features.normal[:, wall_x, 1] > 0.5))  # the first floor row
    assert down[crease - 1, wall_x] < 1e-6          # wall, then floor: normals part
    floor = (crease + h) // 2
    # The floor comes nearer row by row, and a tap on its plane counts fully in every
    # direction (compared with the change's size alone, as SVGF does, a tap straight
    # down would count exp(-1) and one along the row 1: the weights would streak).
    for dy, dx in ((1, 0), (4, 0), (4, 3), (0, 5)):
        assert denoise.edge_weights(features, dy, dx, sigmas)[floor, wall_x] > 0.999


def test_five_passes_reach_63_pixels_across_only_with_the_step_doubled():
    """An impulse on flat features, with the luminance weight off: each pass reaches
    2 steps each way, so 2 (1 + 2 + 4 + 8 + 16) = 62."""
    width, middle = 321, 160  # wide enough that no tap that matters leaves the row
    features = flat_features(height=1, width=width)
    impulse = np.zeros((1, width, 3))
    impulse[0, middle] = 1.0
    variance = np.ones((1, width))
    no_light_weight = denoise.Sigmas(luminance=np.inf)
    spread = denoise.atrous(impulse, variance, features, passes=5,
                           sigmas=no_light_weight)[0, :, 0]
    reached = np.flatnonzero(spread > 0.0)
    assert (reached.min(), reached.max()) == (middle - 62, middle + 62)
    assert spread.sum() == pytest.approx(1.0, rel=1e-12)  # the light stays
    narrow = denoise.atrous(impulse, variance, features, passes=5,
                            sigmas=no_light_weight, double_step=False)[0, :, 0]
    assert np.flatnonzero(narrow > 0.0).max() == middle + 10


def test_eight_samples_filtered_beat_sixty_four_raw(scene):
    truth = scene.colour
    filtered = np.mean([denoise.relative_mse(denoise.atrous(c, v, scene.features), truth)
                        for c, v in renders(scene, 8)])
    raw_8 = np.mean([denoise.relative_mse(c, truth) for c, _ in renders(scene, 8)])
    raw_64 = np.mean([denoise.relative_mse(c, truth) for c, _ in renders(scene, 64)])
    blurred = np.mean([denoise.relative_mse(denoise.gaussian_blur(c, 2.0), truth)
                       for c, _ in renders(scene, 8)])
    # measured: raw 8 spp 0.21, Gaussian 0.096, a-trous 0.0044, raw 64 spp 0.026
    assert filtered < raw_64 < blurred < raw_8
    assert filtered < 0.4 * raw_64


def test_the_shadow_edge_is_kept_only_with_the_luminance_weight(scene):
    """The box's shadow on the floor is in the light alone: the features cannot see it.
    Two pixels on either side of its far edge, the filtered picture keeps the step."""
    truth = scene.colour
    h, w = truth.shape[:2]
    rows = slice(int(0.8 * h), int(0.95 * h))
    edge = int(0.98 * w - 0.5)  # the last shadowed column
    inside, outside = edge - 2, edge + 2

    def step_kept(sigmas):
        ratios = []
        for colour, variance in renders(scene, 8):
            image = denoise.luminance(denoise.atrous(colour, variance, scene.features,
                                                     sigmas=sigmas))
            ratios.append(image[rows, inside].mean() / image[rows, outside].mean())
        return np.mean(ratios)

    true_ratio = denoise.luminance(truth)[rows, inside].mean() / \
        denoise.luminance(truth)[rows, outside].mean()
    assert true_ratio == pytest.approx(0.25, rel=0.05)
    assert step_kept(denoise.Sigmas()) < 0.45
    assert step_kept(denoise.Sigmas(luminance=np.inf)) > 0.6  # the light leaks in


def test_the_luminance_weight_keeps_the_light_only_with_both_pixels_noise(scene):
    """Judged by the pixel's own noise alone (SVGF's form), a bright outlier averages its
    dim neighbours but they turn it away: some of its light is lost, a bias that shrinks
    like the noise's variance, 1/spp (measured: -4.2% of the whole picture at 8 spp,
    -1.0% at 32). Judged by the noise of the difference, both pixels' variances
    together, the weight is the same from either side and the light stays (measured
    +0.75% at 8 spp). The features alone (no luminance weight) lose nothing."""
    truth_mean = scene.colour.mean()

    def darkening(spp, sigmas):
        means = [denoise.atrous(c, v, scene.features, sigmas=sigmas).mean()
                 for c, v in renders(scene, spp)]
        return 1.0 - np.mean(means) / truth_mean

    own_noise = denoise.Sigmas(both_noises=False)
    at_8, at_32 = darkening(8, own_noise), darkening(32, own_noise)
    assert 0.02 < at_8 < 0.07
    assert at_32 == pytest.approx(at_8 / 4, rel=0.5)
    assert abs(darkening(8, denoise.Sigmas())) < 0.012
    features_only = darkening(8, denoise.Sigmas(luminance=np.inf))
    assert abs(features_only) < 0.01


def test_a_lone_spike_is_shared_with_its_neighbours_and_no_light_is_lost():
    """One pixel 50 times its flat, slightly noisy neighbours: its colour above the cap
    goes, a ninth to each of the 3 x 3 pixels around it (itself included); the picture's
    light is the same to float rounding, and a picture without spikes is unchanged."""
    rng = np.random.default_rng(4)
    illumination = 1.0 + 0.01 * rng.standard_normal((9, 9, 1)).repeat(3, axis=2)
    albedo = np.full((9, 9, 3), 0.5)
    assert np.allclose(denoise.share_spikes(illumination, albedo), illumination, rtol=1e-12)
    spiky = illumination.copy()
    spiky[4, 4] = 50.0
    shared = denoise.share_spikes(spiky, albedo)
    assert (shared * albedo).sum() == pytest.approx((spiky * albedo).sum(), rel=1e-12)
    gained = (shared - illumination)[3:6, 3:6, 0]
    assert shared[4, 4, 0] < 0.15 * 50.0  # the dot: its cap and its own ninth
    around = np.delete(gained.ravel(), 4)
    assert np.allclose(around, around[0], rtol=0.05) and around[0] > 5.0  # shared evenly
    assert shared[4, 4, 0] == pytest.approx(50.0 - 8.0 * around[0], rel=0.01)  # 8 ninths
    assert np.allclose(shared[:2], illumination[:2])  # far away: untouched


def lamp_seen_by(coverage, samples, rng, light=14.4):
    """The light a row of pixels sees directly when each sees a lamp of `light` with a
    share `coverage` of its area: each of `samples` samples on the lamp or not (rgb)."""
    hits = rng.binomial(samples, np.broadcast_to(coverage, (64,) + coverage.shape))
    return (light * hits / samples)[..., None].repeat(3, axis=-1)


def test_an_emitters_rim_is_filtered_and_a_sharp_edge_kept():
    """A lamp the lens blurs: coverage rises from 0 to 1 over 6 pixels, each pixel's
    8 samples on it or not. Filtered, the rim's error against the true coverage falls by
    more than a fifth (measured: to 66%), its light stays (the mean within 2%) and the
    pixels all on the lamp keep their light exactly; filtering every pixel instead (a
    planted mistake) pulls them down towards the rim. A sharp edge (every pixel all on
    the lamp or all off) is left exactly as it is, and so is a sky seen directly (no
    darkness near: its texture is no coverage noise)."""
    rng = np.random.default_rng(7)
    ramp = np.clip((np.arange(40) - 17) / 6.0, 0.0, 1.0)
    seen = lamp_seen_by(ramp, 8, rng)
    truth = 14.4 * ramp[None, :, None]
    filtered = denoise.emitted_filtered(seen, 8)
    raw_error = np.mean((seen - truth) ** 2)
    assert np.mean((filtered - truth) ** 2) < 0.75 * raw_error
    assert filtered.mean() == pytest.approx(truth.mean(), rel=0.02)
    on_the_lamp = seen[..., 0] == 14.4
    assert np.array_equal(filtered[on_the_lamp], seen[on_the_lamp])
    every_pixel = denoise.emitted_filtered(seen, 8, rim_only=False)
    assert np.abs(every_pixel - seen)[on_the_lamp].max() > 1.0
    sharp = lamp_seen_by((np.arange(40) >= 20).astype(float), 8, rng)
    assert np.array_equal(denoise.emitted_filtered(sharp, 8), sharp)
    sky = 1.0 + 0.5 * rng.random((16, 16, 3))
    assert np.array_equal(denoise.emitted_filtered(sky, 8), sky)
