"""The media chapter's figures, drawn from the numpy prototype (media.py):

    python python_prototypes/media_figures.py --figure beer.png --which beer
    python python_prototypes/media_figures.py --figure phase.png --which phase
    python python_prototypes/media_figures.py --figure tracking.png --which tracking

beer: transmittance against distance for a medium thin in red and dense in blue (the
  light that gets through turns red), and free flights drawn against their density;
phase: the Henyey-Greenstein lobe for several g, as a polar plot about the direction of
  travel, and the cosines drawn by its sampler against the density;
tracking: a piecewise-constant density along a ray, its transmittance, and where delta
  tracking's real collisions fall (a histogram against sigma_t T)."""

from __future__ import annotations

import argparse

import numpy as np

from python_prototypes import media
from python_prototypes.figure_file import new_figure, save_figure_file

CHANNELS = (("red", "#c0392b"), ("green", "#27ae60"), ("blue", "#2e6fd8"))
RED_SMOKE = np.array([0.2, 1.0, 3.0])  # sigma_t per channel, per metre
SMOKE = media.PiecewiseDensity([0.0, 1.0, 1.5, 2.5, 4.0], [0.3, 2.0, 0.0, 0.8])
SAMPLES = 200_000


def draw_beer(figure):
    distance = np.linspace(0.0, 3.0, 301)
    curves = figure.add_subplot(1, 2, 1)
    for channel, (label, colour) in enumerate(CHANNELS):
        curves.plot(distance, media.transmittance(RED_SMOKE[channel], distance),
                    color=colour, label=f"{label}: σt = {RED_SMOKE[channel]:g} / m")
    curves.set_xlabel("distance through the medium (m)")
    curves.set_ylabel("transmittance T = exp(−σt d)")
    curves.set_ylim(0.0, 1.02)
    curves.grid(alpha=0.3)
    curves.legend()
    flights = figure.add_subplot(1, 2, 2)
    rng = np.random.default_rng(1)
    t = media.sample_free_flight(1.0, rng.random(SAMPLES))
    flights.hist(t, bins=80, range=(0.0, 6.0), density=True, color="#888888",
                 label="free flights drawn (σt = 1 / m)")
    grid = np.linspace(0.0, 6.0, 301)
    flights.plot(grid, media.free_flight_pdf(1.0, grid), color="#c0392b",
                 label="σt exp(−σt t)")
    flights.set_xlabel("distance to the next collision t (m)")
    flights.set_ylabel("density (per metre)")
    flights.legend()


def draw_phase(figure):
    polar = figure.add_subplot(1, 2, 1, projection="polar")
    angles = np.linspace(0.0, 2.0 * np.pi, 721)
    for g in (-0.5, 0.0, 0.3, 0.7):
        polar.plot(angles, media.henyey_greenstein(np.cos(angles), g), label=f"g = {g:g}")
    polar.set_rscale("log")
    polar.set_title("p(θ) per steradian, travel towards 0°", fontsize=10)
    polar.legend(loc="lower left", fontsize=8, bbox_to_anchor=(-0.15, -0.15))
    drawn = figure.add_subplot(1, 2, 2)
    rng = np.random.default_rng(2)
    g = 0.7
    cosines = media.sample_henyey_greenstein_cosine(g, rng.random(SAMPLES))
    drawn.hist(cosines, bins=80, range=(-1.0, 1.0), density=True, color="#888888",
               label=f"cos θ drawn, g = {g:g}")
    grid = np.linspace(-1.0, 1.0, 401)
    drawn.plot(grid, 2.0 * np.pi * media.henyey_greenstein(grid, g), color="#c0392b",
               label="2π p(cos θ)")
    drawn.set_yscale("log")
    drawn.set_xlabel("cos θ between the directions of travel")
    drawn.set_ylabel("density (per unit of cos θ)")
    drawn.legend(loc="upper left")


def draw_tracking(figure):
    t = np.linspace(0.0, 4.0, 801)
    profile = figure.add_subplot(1, 2, 1)
    profile.step(t, SMOKE.sigma_t(t), where="post", color="#2e6fd8", label="σt(t) (per metre)")
    profile.axhline(SMOKE.majorant(), color="#888888", linestyle="--",
                    label="majorant σ̄")
    profile.plot(t, np.exp(-SMOKE.optical_depth(t)), color="#c0392b",
                 label="transmittance T(t)")
    profile.set_xlabel("distance along the ray t (m)")
    profile.legend()
    profile.grid(alpha=0.3)
    collisions = figure.add_subplot(1, 2, 2)
    rng = np.random.default_rng(3)
    distances, _ = media.delta_tracking(SMOKE, 4.0, rng, SAMPLES)
    collisions.hist(distances[np.isfinite(distances)], bins=80, range=(0.0, 4.0),
                    weights=np.full(np.isfinite(distances).sum(), 80 / 4.0 / SAMPLES),
                    color="#888888", label="real collisions (delta tracking)")
    collisions.plot(t, SMOKE.sigma_t(t) * np.exp(-SMOKE.optical_depth(t)), color="#c0392b",
                    label="σt(t) T(t)")
    collisions.set_xlabel("distance along the ray t (m)")
    collisions.set_ylabel("density (per metre)")
    collisions.legend()


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--figure", required=True, help="write the figure (PNG) here")
    parser.add_argument("--which", choices=("beer", "phase", "tracking"), default="beer")
    args = parser.parse_args(argv)
    figure = new_figure(figsize=(11, 4.2), dpi=100)
    {"beer": draw_beer, "phase": draw_phase, "tracking": draw_tracking}[args.which](figure)
    save_figure_file(figure, args.figure)
    print(f"wrote {args.figure}")


if __name__ == "__main__":
    main()
