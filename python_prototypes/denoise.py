"""Denoising in numpy: a clean picture from a few samples a pixel, by a filter that
knows where the edges are. The prototype of the denoising chapter, in float64, on a
still life in two dimensions whose true picture is known exactly.

A path tracer's picture at a few samples a pixel is the true picture plus noise that
has no mean: averaging neighbours removes noise, and the art is to average only
neighbours that should look alike. The steps, each one's picture in the page:

- a box blur and a Gaussian blur average every neighbour: the noise goes, and so does
  every edge (box_blur, gaussian_blur);
- the path tracer also writes what the first hit saw, exactly and without noise: the
  surface's albedo, its normal and its depth (Features). A *cross-bilateral* filter
  weighs each neighbour by how alike those are (edge_weights), so it does not average
  across a silhouette or a crease (cross_bilateral);
- the texture would be smeared all the same, since albedo changes from texel to texel:
  the filter works on the *illumination*, the colour divided by the albedo, and
  multiplies the albedo back in afterwards (demodulate, remodulate);
- a wide filter is slow, (2r + 1)^2 taps a pixel. The edge-avoiding a-trous wavelet
  filter (Dammertz et al. 2010) runs a 5 x 5 kernel several times, its taps 1, 2, 4,
  8, 16 pixels apart: 25 taps a pass reach 63 pixels across in five (atrous);
- a shadow's edge is in the illumination, not in the features: the last weight is the
  illumination's luminance, compared in units of its noise (the variance the path
  tracer measured, filtered along with the picture: SVGF, Schied et al. 2017).

Every filter divides by the sum of its weights (a filter moves noise, not light): a
flat picture stays flat, and block means stay the true picture's (checked).

    python python_prototypes/denoise.py          # the still life's errors, raw and filtered
"""

from __future__ import annotations

import argparse
import functools
from dataclasses import dataclass

import numpy as np

B3 = np.array([1.0, 4.0, 6.0, 4.0, 1.0]) / 16.0  # the a-trous kernel: a B3 spline's taps
GAUSS3 = (0.25, 0.5, 0.25)  # a 3-tap Gaussian, for the noise's own estimate
LUMINANCE = np.array([0.2126, 0.7152, 0.0722])  # Rec. 709, linear RGB
ALBEDO_FLOOR = 0.01  # black albedo has no illumination to speak of: divide by this instead
EPSILON = 1e-10
SPIKE_SIGMAS = 8.0  # a spike: above its neighbours' mean by this many of their spreads
EMITTED_REACH = 3  # how far an emitter's rim looks for its brightest light and its peers


@dataclass
class Features:
    """What the first hit of each pixel's samples saw, without noise, as means over the
    pixel's samples: (H, W, 3) albedo and normal (a unit vector where every sample met
    one surface, shorter where they met two), (H, W) depth along the view, and the
    spread of the samples' depths (zero where they met one plane face on; None: zero)."""
    albedo: np.ndarray
    normal: np.ndarray
    depth: np.ndarray
    spread: np.ndarray | None = None

    @functools.cached_property
    def depth_gradient(self) -> tuple[np.ndarray, np.ndarray]:
        """How depth changes from a pixel to the next along x and along y on the same
        surface (a floor seen at a grazing angle changes depth quickly without any
        edge): of the differences to the two neighbours on an axis, the smaller, since
        at a silhouette one of them is the jump; at the picture's border, the one there
        is."""
        def along(axis):
            z = np.moveaxis(self.depth, axis, 0)
            if len(z) < 2:  # one row (or column): no change along it
                return np.zeros_like(self.depth)
            step = z[1:] - z[:-1]
            ahead = np.concatenate([step, step[-1:]])   # the last: only the one behind
            behind = np.concatenate([step[:1], step])   # the first: only the one ahead
            return np.moveaxis(np.where(np.abs(ahead) < np.abs(behind), ahead, behind),
                               0, axis)
        return along(1), along(0)

@dataclass(frozen=True)
class Sigmas:
    """How quickly each weight falls off: depth off the pixel's plane in units of the
    plane's change across the tap's distance (plus the pixel's own spread), the
    normals' agreement raised to a power (SVGF's 128 turns away a curved surface's
    neighbours: cos 10 degrees to the 128th is 0.14; 4 measured best at 8 spp on all four
    of the chapter's scenes, and a crease at 90 degrees still gets 0), luminance in
    standard deviations of the noise of the difference (SVGF's 4 is for one pixel's
    noise and a picture that time has cleaned; with both pixels' noise, 1.5 measured
    best at 8 spp, keeping the caustics' edges)."""
    depth: float = 1.0
    normal: float = 4.0
    luminance: float = 1.5
    both_noises: bool = True  # False: the pixel's own noise alone, as SVGF (it darkens)


def luminance(rgb: np.ndarray) -> np.ndarray:
    return rgb @ LUMINANCE


def shifted(image: np.ndarray, dy: int, dx: int) -> tuple[np.ndarray, np.ndarray]:
    """image[y + dy, x + dx] for every pixel (edge pixels repeated outside), and where
    that tap lies inside the picture: taps outside get no weight."""
    h, w = image.shape[:2]
    ys = np.clip(np.arange(h) + dy, 0, h - 1)
    xs = np.clip(np.arange(w) + dx, 0, w - 1)
    inside = ((np.arange(h) + dy >= 0) & (np.arange(h) + dy < h))[:, None] & \
        ((np.arange(w) + dx >= 0) & (np.arange(w) + dx < w))[None, :]
    return image[ys][:, xs], inside


def weighted_sum(image: np.ndarray, taps) -> np.ndarray:
    """sum of w image(q) / sum of w over the taps (dy, dx, weight), outside taps left out."""
    total = np.zeros(image.shape, dtype=np.float64)
    weights = np.zeros(image.shape[:2], dtype=np.float64)
    for dy, dx, weight in taps:
        value, inside = shifted(image, dy, dx)
        w = weight * inside
        total += (w[..., None] if image.ndim == 3 else w) * value
        weights += w
    return total / (weights[..., None] if image.ndim == 3 else weights)


def box_blur(image: np.ndarray, radius: int) -> np.ndarray:
    offsets = range(-radius, radius + 1)
    return weighted_sum(image, [(dy, dx, 1.0) for dy in offsets for dx in offsets])


def gaussian_blur(image: np.ndarray, sigma: float) -> np.ndarray:
    radius = int(np.ceil(3.0 * sigma))
    offsets = range(-radius, radius + 1)
    return weighted_sum(image, [(dy, dx, np.exp(-(dy * dy + dx * dx) / (2 * sigma ** 2)))
                                for dy in offsets for dx in offsets])


def demodulate(colour: np.ndarray, albedo: np.ndarray) -> np.ndarray:
    """The illumination: what the surface received, the texture divided out."""
    return colour / np.maximum(albedo, ALBEDO_FLOOR)


def remodulate(illumination: np.ndarray, albedo: np.ndarray) -> np.ndarray:
    return illumination * np.maximum(albedo, ALBEDO_FLOOR)


def edge_weights(features: Features, dy: int, dx: int, sigmas: Sigmas,
                 light: np.ndarray | None = None, light_variance: np.ndarray | None = None,
                 taps: np.ndarray | None = None, taps_variance: np.ndarray | None = None
                 ) -> np.ndarray:
    """How much the tap (dy, dx) away may count, from 0 to 1, per pixel:
    - depth: the tap's against the pixel's plane (the gradient's prediction; SVGF
      compares the change with the prediction's size instead, which gives a tap on the
      same plane exp(-1) unless the plane is level along the offset, so its weights
      streak along slopes), in units of the plane's change over the tap's distance plus
      the spread of the pixel's own depths (a pixel whose samples meet two surfaces is on
      neither's plane);
    - normal: the tap's normal against the pixel's mean normal, as well as the pixel's
      own samples agree with it (|mean|^2, 1 where they all agree);
    - luminance, where given: the pixel's `light` (a blur of it: its own is noisy)
      against the tap's (`taps`, the illumination's luminance), in units of the noise of
      the difference, both variances together: the same weight from either side, so a
      pixel lifted by a lucky sample spreads its light rather than losing it."""
    depth_q, _ = shifted(features.depth, dy, dx)
    along_x, along_y = features.depth_gradient
    off_plane = np.abs(depth_q - features.depth - (along_x * dx + along_y * dy))
    spread = 0.0 if features.spread is None else features.spread
    scale = sigmas.depth * (np.hypot(along_x, along_y) * np.hypot(dx, dy) + spread)
    weight = np.exp(-off_plane / (scale + EPSILON))
    normal_q, _ = shifted(features.normal, dy, dx)
    mean = features.normal
    agreement = np.sum(mean * normal_q, axis=-1) / np.maximum(
        np.sum(mean * mean, axis=-1) * np.linalg.norm(normal_q, axis=-1), EPSILON)
    weight = weight * np.clip(agreement, 0.0, 1.0) ** sigmas.normal
    if light is not None:
        light_q, _ = shifted(taps, dy, dx)
        variance_q, _ = shifted(taps_variance, dy, dx)
        noise = np.sqrt(light_variance + (variance_q if sigmas.both_noises else 0.0))
        weight = weight * np.exp(-np.abs(light - light_q) /
                                 (sigmas.luminance * noise + EPSILON))
    return weight


def cross_bilateral(illumination: np.ndarray, features: Features, radius: int,
                    sigma: float, sigmas: Sigmas = Sigmas()) -> np.ndarray:
    """A Gaussian of `sigma` pixels whose taps are weighed by the features alone:
    (2 radius + 1)^2 taps a pixel."""
    offsets = range(-radius, radius + 1)
    return weighted_sum(illumination, [
        (dy, dx, np.exp(-(dy * dy + dx * dx) / (2 * sigma ** 2)) *
         edge_weights(features, dy, dx, sigmas)) for dy in offsets for dx in offsets])


def share_spikes(illumination: np.ndarray, albedo: np.ndarray,
                 sigmas: float = SPIKE_SIGMAS) -> np.ndarray:
    """A lone spike (a lucky caustic) where the features set a pixel apart is spread by no
    tap. Its colour above a cap, its eight neighbours' mean luminance plus `sigmas` of
    their spread, is shared evenly among the pixels around it (the 3 x 3 inside the
    picture), features or not: the chapter's gather stage. No light is lost."""
    light = luminance(illumination)
    sums, squares, counts, sharers = (np.zeros_like(light) for _ in range(4))
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            value, inside = shifted(light, dy, dx)
            sharers += inside
            if (dy, dx) != (0, 0):
                sums += value * inside
                squares += value * value * inside
                counts += inside
    mean = sums / counts
    cap = mean + sigmas * np.sqrt(np.maximum(squares / counts - mean * mean, 0.0))
    kept = np.where(light > cap, cap / np.maximum(light, EPSILON), 1.0)
    floored = np.maximum(albedo, ALBEDO_FLOOR)
    excess = illumination * (1.0 - kept)[..., None] * floored
    colour = illumination * floored - excess
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):  # what each neighbour q = p + (dy, dx) gives away, a share
            given, inside = shifted(excess / sharers[..., None], dy, dx)
            colour += given * inside[..., None]
    return colour / floored


def emitted_filtered(emitted: np.ndarray, samples: int, reach: int = EMITTED_REACH,
                     rim_only: bool = True) -> np.ndarray:
    """The light the camera sees directly, (H, W, 3), exact where a pixel's samples agree;
    at an emitter's rim (a lamp the lens blurs) a pixel sees it with a share f of its
    `samples`, and f is chance. With L the brightest light within `reach` pixels, the
    pixel shows f L with a coverage's variance f (1 - f) L^2 / n, if a pixel within
    `reach` sees no emitted light (a sky seen directly is no rim). Such a pixel becomes a
    Gaussian mean (sigma reach / 2) of the (2 reach + 1)^2 pixels around it, each weighed
    by how well its light agrees with the pixel's in units of the two's noise; a pixel
    with all or none of its samples on the emitter keeps its own: the chapter's finish.
    `rim_only` False plants a mistake: every pixel filtered, a sharp edge too."""
    light = luminance(emitted)
    darkest, brightest = light.copy(), light.copy()
    offsets = [(dy, dx) for dy in range(-reach, reach + 1) for dx in range(-reach, reach + 1)]
    for dy, dx in offsets:
        value, inside = shifted(light, dy, dx)
        darkest = np.where(inside, np.minimum(darkest, value), darkest)
        brightest = np.where(inside, np.maximum(brightest, value), brightest)

    def coverage_variance(value):
        return np.maximum(value * (brightest - value), 0.0) / samples
    variance = coverage_variance(light)
    total, weights = np.zeros_like(emitted), np.zeros_like(light)
    for dy, dx in offsets:
        value, inside = shifted(emitted, dy, dx)
        tap = luminance(value)
        noise = np.sqrt(variance + coverage_variance(tap))
        w = inside * np.exp(-(dy * dy + dx * dx) / (2 * (reach / 2) ** 2) -
                            np.abs(light - tap) / (noise + EPSILON))
        total += w[..., None] * value
        weights += w
    rim = (variance > 0.0) & (darkest <= 0.0) if rim_only else np.ones_like(light, bool)
    return np.where(rim[..., None], total / weights[..., None], emitted)


def around(image: np.ndarray) -> np.ndarray:
    """A 3 x 3 Gaussian of the image, taps outside the picture left out."""
    return weighted_sum(image, [(dy, dx, GAUSS3[dy + 1] * GAUSS3[dx + 1])
                                for dy in (-1, 0, 1) for dx in (-1, 0, 1)])


def atrous_pass(illumination: np.ndarray, variance: np.ndarray, features: Features,
                step: int, sigmas: Sigmas = Sigmas(), normalise: bool = True
                ) -> tuple[np.ndarray, np.ndarray]:
    """One pass of the edge-avoiding a-trous filter: the 5 x 5 B3 kernel with its taps
    `step` pixels apart, each weighed by edge_weights. The pixel's luminance and its
    variance are 3 x 3 Gaussians of theirs around it (one pixel's own are noisy). The
    variance of the luminance goes through the same pass with the weights squared (the
    variance of a weighted mean), so the next pass knows how much noise is left."""
    taps = luminance(illumination)
    light, light_variance = around(taps), around(variance)
    total = np.zeros_like(illumination)
    total_variance = np.zeros_like(variance)
    weights = np.zeros_like(variance)
    for i in range(-2, 3):
        for j in range(-2, 3):
            dy, dx = i * step, j * step
            value, inside = shifted(illumination, dy, dx)
            value_variance, _ = shifted(variance, dy, dx)
            w = B3[i + 2] * B3[j + 2] * inside
            if (dy, dx) != (0, 0):  # the pixel is like itself (its luminance blurred or not)
                w = w * edge_weights(features, dy, dx, sigmas, light, light_variance, taps,
                                     variance)
            total += w[..., None] * value
            total_variance += w * w * value_variance
            weights += w
    if not normalise:  # a planted mistake: the weights' sum left in
        return total, total_variance
    return total / weights[..., None], total_variance / (weights * weights)


def atrous(colour: np.ndarray, variance: np.ndarray, features: Features, passes: int = 3,
           sigmas: Sigmas = Sigmas(), double_step: bool = True, put_albedo_back: bool = True,
           normalise: bool = True, emitted: np.ndarray | None = None,
           illumination: np.ndarray | None = None, samples: int | None = None
           ) -> np.ndarray:
    """The whole filter: the illumination filtered `passes` times, the taps 1, 2, 4, ...
    pixels apart, the albedo multiplied back in and the light the camera sees directly
    (`emitted`, from `samples` a pixel: a lamp's, filtered only at its rim) added.
    `variance` is the variance of the noisy illumination's luminance, per pixel (of the
    pixel's mean, not of a sample). The illumination is the colour over the albedo, or
    given (the chapter's own, which divides the mean reflected light by the mean
    albedo). The three flags plant the checks' mistakes."""
    if illumination is None:
        illumination = demodulate(colour, features.albedo)
    for level in range(passes):
        step = 2 ** level if double_step else 1
        illumination, variance = atrous_pass(illumination, variance, features, step,
                                             sigmas, normalise)
    picture = remodulate(illumination, features.albedo) if put_albedo_back else illumination
    if emitted is None:
        return picture
    if samples is None:  # the rim's coverage noise depends on it: no default guess
        raise ValueError("emitted light needs the samples a pixel it is the mean of")
    return picture + emitted_filtered(emitted, samples)


def relative_mse(image: np.ndarray, reference: np.ndarray) -> float:
    """The issue's error measure: mean((x - ref)^2 / (ref^2 + 0.01)), bright and dark
    regions counting alike."""
    return float(np.mean((image - reference) ** 2 / (reference ** 2 + 0.01)))


def block_means(image: np.ndarray, block: int) -> np.ndarray:
    h, w = image.shape[0] // block * block, image.shape[1] // block * block
    cut = image[:h, :w]
    return cut.reshape(h // block, block, w // block, block, -1).mean(axis=(1, 3))


# ---------------------------------------------------------------- a still life in 2D

@dataclass
class StillLife:
    """A picture whose truth is known: a chequered back wall, a floor meeting it at a
    crease, a red box standing in front (a silhouette: depth jumps), and a lamp to the
    left whose light falls off smoothly, with the box's hard shadow on the floor (an
    edge that only the illumination has)."""
    features: Features
    illumination: np.ndarray  # (H, W, 3), the truth

    @property
    def colour(self) -> np.ndarray:
        return remodulate(self.illumination, self.features.albedo)


def still_life(width: int = 128, height: int = 96) -> StillLife:
    y, x = np.mgrid[0:height, 0:width]
    u, v = (x + 0.5) / width, (y + 0.5) / height
    floor = v > 0.62
    box = (u > 0.52) & (u < 0.78) & (v > 0.35) & (v < 0.8)
    depth = np.where(floor, 2.0 + 6.0 * (1.0 - v), 4.0)  # the floor comes towards us
    depth = np.where(box, 2.5, depth)
    normal = np.zeros((height, width, 3))
    normal[..., 2] = 1.0
    normal[floor & ~box] = (0.0, 1.0, 0.0)
    chequer = ((x // 8 + y // 8) % 2 == 0)
    albedo = np.where(chequer[..., None], (0.8, 0.75, 0.7), (0.25, 0.3, 0.35))
    albedo = np.where(floor[..., None], (0.5, 0.5, 0.5), albedo)
    albedo = np.where(box[..., None], (0.7, 0.15, 0.12), albedo)
    light = 0.4 + 1.6 * np.exp(-((u - 0.1) ** 2 + (v - 0.3) ** 2) / 0.25)
    shadow = floor & ~box & (u > 0.78) & (u < 0.98) & (v > 0.66)  # cast to the right
    light = np.where(shadow, 0.25 * light, light)
    illumination = np.repeat(light[..., None], 3, axis=2) * (1.0, 0.95, 0.85)
    return StillLife(Features(albedo, normal, depth), illumination)


def noisy_render(scene: StillLife, spp: int, rng: np.random.Generator, noise: float = 2.0
                 ) -> tuple[np.ndarray, np.ndarray]:
    """What a path tracer gives at `spp` samples a pixel: each sample the true
    illumination times a positive random factor of mean 1 and variance `noise` (a
    gamma variable: most samples dim, a few bright, as paths that find the lamp or
    not), the albedo exact. Returns the mean colour and the variance of the mean's
    illumination luminance, estimated from the samples as a renderer does (sum of
    squares)."""
    shape = 1.0 / noise
    factors = rng.gamma(shape, 1.0 / shape, size=(spp, *scene.illumination.shape[:2]))
    samples = factors[..., None] * scene.illumination  # (spp, H, W, 3)
    light = luminance(samples)
    mean = samples.mean(axis=0)
    variance = light.var(axis=0, ddof=1) / spp if spp > 1 else light[0] ** 2 * noise
    return remodulate(mean, scene.features.albedo), variance


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--spp", type=int, default=8)
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()
    scene = still_life()
    rng = np.random.default_rng(args.seed)
    colour, variance = noisy_render(scene, args.spp, rng)
    truth = scene.colour
    print(f"relative MSE at {args.spp} spp against the truth:")
    print(f"  raw                {relative_mse(colour, truth):.5f}")
    print(f"  Gaussian blur      {relative_mse(gaussian_blur(colour, 2.0), truth):.5f}")
    bilateral = remodulate(cross_bilateral(demodulate(colour, scene.features.albedo),
                                           scene.features, 6, 3.0), scene.features.albedo)
    print(f"  cross-bilateral    {relative_mse(bilateral, truth):.5f}")
    print(f"  a-trous, 3 passes  "
          f"{relative_mse(atrous(colour, variance, scene.features), truth):.5f}")
    raw64, _ = noisy_render(scene, 64, rng)
    print(f"  raw at 64 spp      {relative_mse(raw64, truth):.5f}")


if __name__ == "__main__":
    main()
