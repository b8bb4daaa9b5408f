"""Chapter 15's figures, drawn from the numpy prototype (microfacet.py):

    python python_prototypes/metal_figures.py --figure fresnel.png --which fresnel
    python python_prototypes/metal_figures.py --figure ggx.png --which ggx
    python python_prototypes/metal_figures.py --figure vndf.png --which vndf

fresnel: the reflectance of gold, copper and aluminium against the angle of incidence,
  per channel (Mitsuba 3.9.1's RGB eta and k, as in assets/scenes/);
ggx: the GGX density of normals D(θm) cos θm for several roughnesses, and the white
  furnace albedo single scattering keeps;
vndf: visible normals drawn for one direction of incidence, in the plane of incidence:
  the normals facing the viewer come up, the ones turned away never do."""

from __future__ import annotations

import argparse

import numpy as np

from python_prototypes import microfacet as mf
from python_prototypes.figure_file import new_figure, save_figure_file

# Mitsuba 3.9.1's RGB variants, mi.traverse(mi.load_dict({"type": "conductor",
# "material": NAME})): eta and k at a red, a green and a blue wavelength.
METALS = {
    "gold (Au)": ([0.143036, 0.375307, 1.44205], [3.983, 2.38556, 1.60336]),
    "copper (Cu)": ([0.201005, 0.92375, 1.10222], [3.91326, 2.45305, 2.14209]),
    "aluminium (Al)": ([1.6575, 0.880405, 0.521244], [9.22381, 6.2695, 4.837]),
}
CHANNELS = (("red", "#c0392b"), ("green", "#27ae60"), ("blue", "#2e6fd8"))


def draw_fresnel(figure):
    angles = np.linspace(0.0, 90.0, 181)
    cosines = np.cos(np.radians(angles))
    for index, (name, (eta, k)) in enumerate(METALS.items()):
        axes = figure.add_subplot(1, 3, index + 1)
        reflectance = mf.fresnel_conductor(cosines, eta, k)
        for channel, (label, colour) in enumerate(CHANNELS):
            axes.plot(angles, reflectance[:, channel], color=colour, label=label)
        axes.set_title(name)
        axes.set_xlabel("angle of incidence θ (degrees)")
        axes.set_ylim(0.0, 1.02)
        axes.set_xlim(0, 90)
        axes.grid(alpha=0.3)
        if index == 0:
            axes.set_ylabel("reflected fraction F(θ)")
            axes.legend(loc="lower left")


def draw_ggx(figure):
    alphas = (0.05, 0.1, 0.2, 0.5, 1.0)
    density = figure.add_subplot(1, 2, 1)
    theta = np.radians(np.linspace(0.0, 89.5, 400))
    normals = np.stack([np.sin(theta), 0 * theta, np.cos(theta)], axis=-1)
    for alpha in alphas:
        # D cos θm sin θm 2π: the share of projected microfacet area per radian of θm.
        share = mf.ggx_d(normals, alpha) * np.cos(theta) * np.sin(theta) * 2 * np.pi
        density.plot(np.degrees(theta), share, label=f"α = {alpha:g}")
    density.set_yscale("log")
    density.set_ylim(1e-3, 50)
    density.set_xlabel("microfacet normal's angle θm (degrees)")
    density.set_ylabel("2π D(θm) cos θm sin θm (per radian)")
    density.set_title("GGX: where the microfacets point")
    density.legend()
    density.grid(alpha=0.3)

    albedo = figure.add_subplot(1, 2, 2)
    angles = np.arange(0.0, 90.0, 5.0)
    for alpha in (0.1, 0.3, 0.5, 1.0):
        values = [mf.furnace_albedo(a, alpha, count=40_000, seed=1)[0] for a in angles]
        albedo.plot(angles, values, marker=".", label=f"α = {alpha:g}")
    albedo.set_ylim(0.0, 1.02)
    albedo.set_xlabel("angle of incidence θi (degrees)")
    albedo.set_ylabel("light kept (F = 1)")
    albedo.set_title("single scattering loses light")
    albedo.legend(loc="lower left")
    albedo.grid(alpha=0.3)


def draw_vndf(figure):
    rng = np.random.default_rng(1)
    for index, (angle, alpha) in enumerate(((0.0, 0.5), (60.0, 0.5), (80.0, 0.5))):
        axes = figure.add_subplot(1, 3, index + 1)
        theta = np.radians(angle)
        wi = np.array([np.sin(theta), 0.0, np.cos(theta)])
        count = 3000
        m = mf.sample_visible_normal(np.tile(wi, (count, 1)), alpha, rng.random(count),
                                     rng.random(count))
        # The normals' angles in the plane of incidence (x, z), as a histogram.
        angles = np.degrees(np.arctan2(m[:, 0], m[:, 2]))
        axes.hist(angles, bins=60, range=(-90, 90), density=True, color="#888888",
                  label="visible normals drawn")
        axes.axvline(angle, color="#c0392b", linestyle="--", label="towards the viewer")
        axes.set_title(f"θi = {angle:g}°, α = {alpha:g}")
        # Short labels: three panels share 11 inches.
        axes.set_xlabel("normal's angle θm (degrees)")
        if index == 0:
            axes.set_ylabel("density (per degree)")
            axes.legend(loc="upper left", fontsize=8)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--figure", required=True, help="write the figure (PNG) here")
    parser.add_argument("--which", choices=("fresnel", "ggx", "vndf"), default="fresnel")
    args = parser.parse_args(argv)
    figure = new_figure(figsize=(11, 3.8) if args.which != "ggx" else (11, 4.2), dpi=100)
    {"fresnel": draw_fresnel, "ggx": draw_ggx, "vndf": draw_vndf}[args.which](figure)
    save_figure_file(figure, args.figure)
    print(f"wrote {args.figure}")


if __name__ == "__main__":
    main()
