"""Chapter 16's figures, drawn from the numpy prototype (microfacet.py):

    python python_prototypes/glass_figures.py --figure fresnel.png --which fresnel
    python python_prototypes/glass_figures.py --figure refraction.png --which refraction

fresnel: the reflectance of the gems' indices against the angle of incidence, from
  outside (air into the stone) and from inside (the stone into air), where it reaches
  1 at the critical angle: total internal reflection;
refraction: rays of light meeting a flat surface of glass, bent by Snell's law, from
  outside and from inside; from inside, past the critical angle, none gets out."""

from __future__ import annotations

import argparse

import numpy as np

from python_prototypes import microfacet as mf
from python_prototypes.figure_file import new_figure, save_figure_file

# The stones of assets/scenes/cornell_gem_glass.scene: their indices of refraction.
GEMS = {
    "diamond, 2.42": (2.42, "#555555"),
    "ruby, sapphire, 1.77": (1.77, "#c0392b"),
    "emerald, 1.57": (1.57, "#27ae60"),
    "glass, 1.5": (1.5, "#2e6fd8"),
}


def critical_angle(eta):
    """The angle of incidence inside beyond which sin θt would exceed 1."""
    return np.degrees(np.arcsin(1.0 / eta))


def draw_fresnel(figure):
    angles = np.linspace(0.0, 90.0, 901)
    cosines = np.cos(np.radians(angles))
    outside, inside = figure.add_subplot(1, 2, 1), figure.add_subplot(1, 2, 2)
    for name, (eta, colour) in GEMS.items():
        outside.plot(angles, mf.fresnel_dielectric(cosines, eta)[0], color=colour,
                     label=name)
        # From inside, cos θi is negative in the prototype's convention.
        inside.plot(angles, mf.fresnel_dielectric(-cosines, eta)[0], color=colour,
                    label=f"{name}: critical {critical_angle(eta):.1f}°")
    outside.set_title("from outside: air into the stone")
    inside.set_title("from inside: the stone into air")
    for axes in (outside, inside):
        axes.set_xlabel("angle of incidence θ (degrees)")
        axes.set_xlim(0, 90)
        axes.set_ylim(0.0, 1.02)
        axes.grid(alpha=0.3)
    outside.set_ylabel("reflected fraction F(θ)")
    outside.legend(loc="upper left")
    inside.legend(loc="lower right", fontsize=8)


def draw_rays(axes, eta, from_inside):
    """Rays arriving at the origin from above (z > 0) at several angles: the surface is
    z = 0, the medium on the arriving side is air (outside) or the stone (inside)."""
    normal = np.array([0.0, 0.0, 1.0])
    angles = (10, 30, 50, 70, 85) if not from_inside else (10, 20, 30, 40, 50, 70)
    cosine_sign = -1.0 if from_inside else 1.0
    for angle in angles:
        theta = np.radians(angle)
        wi = np.array([-np.sin(theta), 0.0, np.cos(theta)])  # towards where light came from
        F, cos_t, _, eta_ti = mf.fresnel_dielectric(cosine_sign * wi[2], eta)
        axes.plot([wi[0], 0.0], [wi[2], 0.0], color="#d4a017", lw=1.5)
        reflected = mf.reflect(wi, normal)
        axes.plot([0.0, reflected[0]], [0.0, reflected[2]], color="#d4a017",
                  alpha=0.25 + 0.75 * float(F), lw=1.5, linestyle=":")
        if F < 1.0:  # a refracted ray exists: Snell's law, on the far side
            refracted = mf.refract(wi, normal, -abs(cos_t), eta_ti)
            axes.plot([0.0, refracted[0]], [0.0, refracted[2]], color="#2e6fd8", lw=1.5)
    axes.axhline(0.0, color="black", lw=1)
    glass = (0.0, 1.1) if from_inside else (-1.1, 0.0)  # the stone's side, shaded
    axes.fill_between([-1.1, 1.1], *glass, color="#cfe3f7", alpha=0.6, zorder=0)
    axes.text(-1.05, 1.0, "glass" if from_inside else "air", va="top")
    axes.text(-1.05, -1.0, "air" if from_inside else "glass", va="bottom")
    axes.text(0.98, 0.98, "solid: arriving, refracted\ndotted: reflected (darker: more)",
              transform=axes.transAxes, ha="right", va="top", fontsize=8)
    critical = critical_angle(eta)
    axes.set_title(f"from inside (η = {eta:g}): critical angle {critical:.1f}°" if from_inside
                   else f"from outside (η = {eta:g})")
    axes.set_xlim(-1.1, 1.1)
    axes.set_ylim(-1.1, 1.1)
    axes.set_aspect("equal")
    axes.set_xticks([])
    axes.set_yticks([])


def draw_refraction(figure):
    draw_rays(figure.add_subplot(1, 2, 1), 1.5, from_inside=False)
    draw_rays(figure.add_subplot(1, 2, 2), 1.5, from_inside=True)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--figure", required=True, help="write the figure (PNG) here")
    parser.add_argument("--which", choices=("fresnel", "refraction"), default="fresnel")
    args = parser.parse_args(argv)
    figure = new_figure(figsize=(11, 4.2) if args.which == "fresnel" else (10, 5), dpi=100)
    {"fresnel": draw_fresnel, "refraction": draw_refraction}[args.which](figure)
    save_figure_file(figure, args.figure)
    print(f"wrote {args.figure}")


if __name__ == "__main__":
    main()
