"""The denoising chapter's figures, drawn from the numpy prototype (denoise.py):

    python python_prototypes/denoise_figures.py --figure steps.png --which steps
    python python_prototypes/denoise_figures.py --figure weights.png --which weights
    python python_prototypes/denoise_figures.py --figure passes.png --which passes

steps: the still life true, at 8 samples a pixel, and filtered five ways (box,
  Gaussian, cross-bilateral on the features, a-trous with the luminance weight), each
  with its relative error;
weights: around one pixel of the floor beside the box, how much each neighbour counts:
  by depth, by normal, by light, and all three together;
passes: the error against the number of a-trous passes at 4, 8 and 16 samples a pixel,
  against the raw picture's at 64; and the light the filter keeps against the samples a
  pixel, with the luminance weight judged by the pixel's own noise (SVGF's form, which
  darkens as 1/spp) and by both pixels' noise (the chapter's)."""

from __future__ import annotations

import argparse

import numpy as np

from python_prototypes import denoise, srgb
from python_prototypes.figure_file import new_figure, save_figure_file

SEED = 3


def shown(image: np.ndarray) -> np.ndarray:
    return srgb.encode(np.clip(image, 0.0, 1.0))


def draw_steps(figure):
    scene = denoise.still_life()
    colour, variance = denoise.noisy_render(scene, 8, np.random.default_rng(SEED))
    albedo, features = scene.features.albedo, scene.features
    bilateral = denoise.remodulate(denoise.cross_bilateral(
        denoise.demodulate(colour, albedo), features, 6, 3.0), albedo)
    pictures = [("the truth", scene.colour), ("8 samples a pixel", colour),
                ("box blur, 5 x 5", denoise.box_blur(colour, 2)),
                ("Gaussian, sigma 2", denoise.gaussian_blur(colour, 2.0)),
                ("cross-bilateral on the features", bilateral),
                ("a-trous, 3 passes, light weighed",
                 denoise.atrous(colour, variance, features))]
    for index, (title, image) in enumerate(pictures):
        axes = figure.add_subplot(2, 3, index + 1)
        axes.imshow(shown(image), interpolation="nearest")
        if index > 0:
            title += f"\nrelative MSE {denoise.relative_mse(image, scene.colour):.4f}"
        axes.set_title(title, fontsize=9)
        axes.set_axis_off()


def draw_weights(figure):
    scene = denoise.still_life()
    colour, variance = denoise.noisy_render(scene, 8, np.random.default_rng(SEED))
    features = scene.features
    h, w = features.depth.shape
    centre = (int(0.72 * h), int(0.5 * w))  # the floor, just left of the box
    radius = 12
    taps = denoise.luminance(denoise.demodulate(colour, features.albedo))
    light, light_variance = denoise.around(taps), denoise.around(variance)
    parts = {name: np.zeros((2 * radius + 1, 2 * radius + 1))
             for name in ("depth", "normal", "light", "all")}
    for dy in range(-radius, radius + 1):
        for dx in range(-radius, radius + 1):
            depth_only = denoise.edge_weights(features, dy, dx,
                                              denoise.Sigmas(normal=0.0))[centre]
            both = denoise.edge_weights(features, dy, dx, denoise.Sigmas())[centre]
            all_three = denoise.edge_weights(features, dy, dx, denoise.Sigmas(), light,
                                             light_variance, taps, variance)[centre]
            parts["depth"][dy + radius, dx + radius] = depth_only
            parts["normal"][dy + radius, dx + radius] = both / max(depth_only, 1e-12)
            parts["light"][dy + radius, dx + radius] = all_three / max(both, 1e-12)
            parts["all"][dy + radius, dx + radius] = all_three
    y0, x0 = centre
    crop = shown(colour[y0 - radius:y0 + radius + 1, x0 - radius:x0 + radius + 1])
    panels = [("the noisy picture around it", crop)] + \
        [(f"by {name}" if name != "all" else "all three", parts[name]) for name in parts]
    for index, (title, image) in enumerate(panels):
        axes = figure.add_subplot(1, 5, index + 1)
        axes.imshow(image, cmap=None if image.ndim == 3 else "magma", vmin=0.0, vmax=1.0,
                    interpolation="nearest")
        axes.plot([radius], [radius], marker="+", color="#2e6fd8", markersize=10)
        axes.set_title(title, fontsize=9)
        axes.set_axis_off()


def draw_passes(figure):
    scene = denoise.still_life()
    truth = scene.colour
    errors = figure.add_subplot(1, 2, 1)
    for spp, colour_name in ((4, "#c0392b"), (8, "#27ae60"), (16, "#2e6fd8")):
        colour, variance = denoise.noisy_render(scene, spp, np.random.default_rng(SEED))
        curve = [denoise.relative_mse(colour, truth)]
        illumination = denoise.demodulate(colour, scene.features.albedo)
        for level in range(6):
            illumination, variance = denoise.atrous_pass(illumination, variance,
                                                         scene.features, 2 ** level)
            curve.append(denoise.relative_mse(
                denoise.remodulate(illumination, scene.features.albedo), truth))
        errors.plot(range(7), curve, marker="o", color=colour_name, label=f"{spp} spp")
    raw_64, _ = denoise.noisy_render(scene, 64, np.random.default_rng(SEED))
    errors.axhline(denoise.relative_mse(raw_64, truth), color="#888888", linestyle="--",
                   label="raw, 64 spp")
    errors.set_yscale("log")
    errors.set_xlabel("a-trous passes (taps 1, 2, 4, ... pixels apart)")
    errors.set_ylabel("relative MSE against the truth")
    errors.legend()
    errors.grid(alpha=0.3)
    light = figure.add_subplot(1, 2, 2)
    counts = [4, 8, 16, 32, 64, 128]
    for both, name, colour_name in ((False, "the pixel's own noise (SVGF)", "#c0392b"),
                                    (True, "both pixels' noise (the chapter)", "#27ae60")):
        sigmas = denoise.Sigmas(both_noises=both)
        kept = []
        for spp in counts:
            means = [denoise.atrous(*denoise.noisy_render(scene, spp,
                                                          np.random.default_rng(s)),
                                    scene.features, sigmas=sigmas).mean() for s in range(3)]
            kept.append(100.0 * (np.mean(means) / truth.mean() - 1.0))
        light.plot(counts, kept, marker="o", color=colour_name, label=name)
    light.axhline(0.0, color="#888888", linestyle="--")
    light.set_xscale("log", base=2)
    light.set_xlabel("samples a pixel")
    light.set_ylabel("the filtered picture's light, against the truth (%)")
    light.legend()
    light.grid(alpha=0.3)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--figure", required=True)
    parser.add_argument("--which", choices=("steps", "weights", "passes"), required=True)
    args = parser.parse_args()
    size = {"steps": (11, 6.2), "weights": (13, 3.2), "passes": (11, 4.2)}[args.which]
    figure = new_figure(figsize=size, dpi=80)
    {"steps": draw_steps, "weights": draw_weights, "passes": draw_passes}[args.which](figure)
    save_figure_file(figure, args.figure)


if __name__ == "__main__":
    main()
