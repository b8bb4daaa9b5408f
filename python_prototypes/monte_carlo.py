"""Monte Carlo integration in numpy: the estimator chapter 11's path tracer runs on the GPU.

To estimate F = ∫ f(x) dx, draw N samples x_i with a density p(x) and average
f(x_i) / p(x_i). Its expected value is F (it is unbiased) for any p that is non-zero
wherever f is; its standard error falls as σ / √N, σ² the variance of one sample
f(x)/p(x). A p shaped like f makes σ small: importance sampling. Three examples:

* ∫₀^π sin x dx = 2, with uniform samples and with a tent-shaped density.
* Irradiance under a constant sky, E = ∫ L cos θ dω = π L, with uniform directions on
  the hemisphere (pdf 1/2π) and cosine-weighted ones (Malley's method, pdf cos θ / π).
* Irradiance on the floor from a square area light, with points picked uniformly on the
  light (pdf 1/A per m²); the Jacobian dω = cos θ_light dA / d² turns them into
  directions. The exact answer is Lambert's formula for a polygonal light.

    python python_prototypes/monte_carlo.py --figure convergence.png --which convergence
    python python_prototypes/monte_carlo.py --figure hemisphere.png --which hemisphere
    python python_prototypes/monte_carlo.py --figure light.png --which light --seed 2
"""

import argparse
from dataclasses import dataclass

import numpy as np

from python_prototypes.figure_file import save_figure_file


SINE_INTEGRAL = 2.0  # ∫₀^π sin x dx
SKY_RADIANCE = 1.0  # L of the constant sky; its irradiance is π L
FLOOR_POINT = np.array([0.0, 0.0, 0.0])
FLOOR_NORMAL = np.array([0.0, 0.0, 1.0])


def mean_and_standard_error(samples):
    """The estimate (the mean of the samples) and its standard error √(s² / N)."""
    return samples.mean(), np.sqrt(samples.var(ddof=1) / len(samples))


def normalize(vectors):
    return vectors / np.linalg.norm(vectors, axis=-1, keepdims=True)


# ---------------------------------------------------------------------------------------
# 1D: ∫₀^π sin x dx = 2. Each function returns N samples of f(x) / p(x).
# ---------------------------------------------------------------------------------------

# --8<-- [start:uniform]
def sine_uniform_samples(rng, count):
    """x uniform on [0, π]: p = 1/π, so each sample is π sin x."""
    x = rng.uniform(0.0, np.pi, count)
    return np.sin(x) / (1.0 / np.pi)
# --8<-- [end:uniform]


def tent_pdf(x):
    """A triangle on [0, π] peaking at π/2, of area 1: roughly the shape of sin x."""
    return (4.0 / np.pi**2) * np.minimum(x, np.pi - x)


def sample_tent(rng, count):
    """Invert the tent's CDF. On the left half the CDF is 2x²/π², so x = π √(u/2);
    the right half is the mirror image."""
    u = rng.random(count)
    left = np.pi * np.sqrt(u / 2.0)
    right = np.pi - np.pi * np.sqrt((1.0 - u) / 2.0)
    return np.where(u < 0.5, left, right)


# --8<-- [start:importance]
def sine_importance_samples(rng, count):
    """x from the tent: f/p stays between π/2 and π²/4, so the samples vary little."""
    x = sample_tent(rng, count)
    return np.sin(x) / tent_pdf(x)
# --8<-- [end:importance]


# ---------------------------------------------------------------------------------------
# 2D: the hemisphere around the normal z. Irradiance E = ∫ L cos θ dω = π L.
# ---------------------------------------------------------------------------------------

def uniform_hemisphere(rng, count):
    """Directions uniform over the hemisphere z > 0, pdf 1/(2π) per steradian.
    (Archimedes: on the sphere, z = cos θ is uniform, so draw it uniform.)"""
    cos_theta = rng.random(count)
    sin_theta = np.sqrt(1.0 - cos_theta**2)
    phi = 2.0 * np.pi * rng.random(count)
    directions = np.stack([sin_theta * np.cos(phi), sin_theta * np.sin(phi), cos_theta],
                          axis=-1)
    return directions, np.full(count, 1.0 / (2.0 * np.pi))


# --8<-- [start:cosine]
def cosine_hemisphere(rng, count):
    """Malley's method: a uniform point on the unit disk, lifted straight up onto the
    hemisphere. The directions' pdf is cos θ / π."""
    radius = np.sqrt(rng.random(count))  # √: uniform over the disk's area, not its radius
    phi = 2.0 * np.pi * rng.random(count)
    x, y = radius * np.cos(phi), radius * np.sin(phi)
    z = np.sqrt(np.maximum(0.0, 1.0 - x**2 - y**2))  # max: rounding could dip below 0
    return np.stack([x, y, z], axis=-1), z / np.pi
# --8<-- [end:cosine]


def sky_irradiance_samples(directions, pdf, sky_radiance=SKY_RADIANCE):
    """One sample of E per direction: L cos θ / p(ω)."""
    return sky_radiance * directions[:, 2] / pdf


def sky_uniform_samples(rng, count):
    return sky_irradiance_samples(*uniform_hemisphere(rng, count))


def sky_cosine_samples(rng, count):
    """L cos θ / (cos θ / π) = π L for every direction: zero variance."""
    return sky_irradiance_samples(*cosine_hemisphere(rng, count))


# ---------------------------------------------------------------------------------------
# Area light: from "per m² of the light" to "per steradian seen from the floor"
# ---------------------------------------------------------------------------------------

@dataclass
class RectangleLight:
    """A one-sided Lambertian rectangle of radiance L: the points corner + s edge_a +
    t edge_b, s and t in [0, 1]. It shines towards cross(edge_a, edge_b)."""
    corner: np.ndarray
    edge_a: np.ndarray
    edge_b: np.ndarray
    radiance: float = 1.0

    def area(self):
        return np.linalg.norm(np.cross(self.edge_a, self.edge_b))

    def normal(self):
        return normalize(np.cross(self.edge_a, self.edge_b))

    def center(self):
        return self.corner + 0.5 * (self.edge_a + self.edge_b)

    def corners(self):
        """Counter-clockwise seen from the lit side (right-hand rule around normal())."""
        a, b = self.edge_a, self.edge_b
        return np.array([self.corner, self.corner + a, self.corner + a + b,
                         self.corner + b])


def square_light(center, side, tilt_degrees=0.0, radiance=1.0):
    """A side x side square centred at center, facing down (-z), turned by tilt_degrees
    about the x axis."""
    tilt = np.radians(tilt_degrees)
    edge_a = side * np.array([1.0, 0.0, 0.0])
    edge_b = side * np.array([0.0, -np.cos(tilt), -np.sin(tilt)])  # a x b: (0, sin, -cos)
    corner = np.asarray(center, dtype=np.float64) - 0.5 * (edge_a + edge_b)
    return RectangleLight(corner, edge_a, edge_b, radiance)


FIGURE_LIGHT = square_light(center=(0.5, 0.0, 1.5), side=1.0)


def polygon_irradiance(light, point=FLOOR_POINT, normal=FLOOR_NORMAL):
    """Lambert's exact formula for a polygonal light of uniform radiance L:
        E = L/2 Σ_i angle_i · (normal · normalize(v_{i+1} x v_i)),
    v_i the unit vectors from the point to the corners, angle_i the angle between v_i
    and v_{i+1}. Valid when the whole light is above the point's horizon."""
    to_corners = normalize(light.corners() - point)
    if np.any(to_corners @ normal <= 0.0):
        raise ValueError("the light crosses the horizon: Lambert's formula needs clipping")
    total = 0.0
    for i in range(len(to_corners)):
        v, v_next = to_corners[i], to_corners[(i + 1) % len(to_corners)]
        angle = np.arccos(np.clip(np.dot(v, v_next), -1.0, 1.0))
        # Seen from the point the corners go counter-clockwise, so v_next x v (not
        # v x v_next) is the normal of the edge's great circle towards the light's inside.
        total += angle * np.dot(normal, normalize(np.cross(v_next, v)))
    return max(0.0, 0.5 * light.radiance * total)  # 0 behind the one-sided light


def sample_light_geometry(rng, count, light, point, normal):
    """Pick points uniformly on the light; for each: cos θ at the floor, cos θ at the
    light, and the squared distance d² between them."""
    s, t = rng.random(count), rng.random(count)
    on_light = light.corner + s[:, None] * light.edge_a + t[:, None] * light.edge_b
    offset = on_light - point
    distance_squared = np.sum(offset**2, axis=-1)
    direction = offset / np.sqrt(distance_squared)[:, None]
    cos_floor = np.maximum(0.0, direction @ normal)
    cos_light = np.maximum(0.0, -(direction @ light.normal()))  # 0: seen from behind
    return cos_floor, cos_light, distance_squared


# --8<-- [start:light]
def light_area_samples(rng, count, light=FIGURE_LIGHT, point=FLOOR_POINT,
                       normal=FLOOR_NORMAL):
    """One sample of E per point picked uniformly on the light (pdf 1/A per m²):
    L cos θ_floor · (cos θ_light / d²) / (1/A). The factor in brackets is the Jacobian
    dω/dA, which turns "per m² of light" into "per steradian seen from the point"."""
    cos_floor, cos_light, d2 = sample_light_geometry(rng, count, light, point, normal)
    return light.radiance * cos_floor * (cos_light / d2) * light.area()
# --8<-- [end:light]


def light_area_samples_forgot_jacobian(rng, count, light=FIGURE_LIGHT, point=FLOOR_POINT,
                                       normal=FLOOR_NORMAL):
    """The classic bug: the same points and pdf, but no cos θ_light / d². Its mean is
    L ∫ cos θ_floor dA, radiance times m² rather than an irradiance: wrong."""
    cos_floor, _, _ = sample_light_geometry(rng, count, light, point, normal)
    return light.radiance * cos_floor * light.area()


# ---------------------------------------------------------------------------------------
# Convergence: the error against the number of samples N
# ---------------------------------------------------------------------------------------

def rms_errors(sampler, exact, counts, runs, rng):
    """For each N in counts, the root-mean-square error of `runs` independent estimates
    made of N samples each."""
    errors = []
    for count in counts:
        estimates = np.array([sampler(rng, count).mean() for _ in range(runs)])
        errors.append(np.sqrt(np.mean((estimates - exact) ** 2)))
    return np.array(errors)


def log_log_slope(counts, errors):
    """Slope of the straight line through (log N, log error): -1/2 for σ/√N."""
    return np.polyfit(np.log(counts), np.log(errors), 1)[0]


def running_estimates(samples):
    """Estimate and standard error after the first 1, 2, ..., N samples."""
    n = np.arange(1, len(samples) + 1)
    mean = np.cumsum(samples) / n
    mean_of_squares = np.cumsum(samples**2) / n
    # n / (n - 1): the sample variance; max(0, ...): rounding when the variance is 0.
    variance = np.maximum(0.0, mean_of_squares - mean**2) * n / np.maximum(n - 1, 1)
    return mean, np.sqrt(variance / n)


# ---------------------------------------------------------------------------------------
# Figures
# ---------------------------------------------------------------------------------------

def label_axes(axes, xlabel, ylabel, title, legend_place="best"):
    axes.set_xlabel(xlabel)
    axes.set_ylabel(ylabel)
    axes.set_title(title, fontsize=11)
    axes.grid(True, which="both", alpha=0.3)
    axes.legend(fontsize=9.5, loc=legend_place)

def draw_convergence(axes, rng, runs=64):
    counts = np.unique(np.round(np.logspace(1, 5, 17)).astype(int))
    methods = [("uniform, p = 1/π", sine_uniform_samples, "tab:blue"),
               ("importance, p = tent", sine_importance_samples, "tab:orange")]
    errors = {}
    for label, sampler, color in methods:
        errors[label] = rms_errors(sampler, SINE_INTEGRAL, counts, runs, rng)
        slope = log_log_slope(counts, errors[label])
        axes.loglog(counts, errors[label], "o-", color=color, markersize=4,
                    label=f"{label}: fitted slope {slope:.2f}")
    axes.loglog(counts, 3.0 / np.sqrt(counts), "--", color="0.4",
                label="3 / √N (slope -0.5), for reference")
    ratio = np.mean(errors[methods[0][0]] / errors[methods[1][0]])
    axes.text(0.03, 0.04, f"importance sampling: about {ratio:.1f}x smaller error at "
              f"every N,\nthe same error with {ratio**2:.0f}x fewer samples",
              transform=axes.transAxes, fontsize=10)
    label_axes(axes, "samples per estimate, N", f"RMS error over {runs} runs",
               r"$\int_0^\pi \sin x \, dx = 2$: the error falls as $1/\sqrt{N}$")


def draw_disk(axes, directions, title, color):
    """Directions seen from straight above: (x, y), on the unit disk."""
    from matplotlib.patches import Circle
    axes.add_patch(Circle((0, 0), 1.0, fill=False, color="0.5"))  # the horizon
    axes.plot(directions[:, 0], directions[:, 1], ".", color=color, markersize=3)
    axes.set_aspect("equal")
    axes.set_xlim(-1.05, 1.05)
    axes.set_ylim(-1.05, 1.05)
    axes.set_xticks([])
    axes.set_yticks([])
    axes.set_title(title, fontsize=10)


def plot_running_estimate(axes, samples, label, color, first=2, linewidth=1.5):
    """The estimate after N = first, ..., len(samples) samples, in a ±2 standard-error
    band (from N = 2 at least: one sample says nothing about the variance)."""
    mean, error = running_estimates(samples)
    n = np.arange(1, len(samples) + 1)[first - 1:]
    mean, error = mean[first - 1:], error[first - 1:]
    axes.fill_between(n, mean - 2 * error, mean + 2 * error, color=color, alpha=0.2)
    axes.plot(n, mean, color=color, linewidth=linewidth,
              label=f"{label} (band: ±2 standard errors)")
    return mean[-1]


def draw_hemisphere(figure, rng, count=100_000, shown=400):
    grid = figure.add_gridspec(2, 2, width_ratios=(1, 2.2))
    draw_disk(figure.add_subplot(grid[0, 0]), uniform_hemisphere(rng, shown)[0],
              f"uniform, pdf 1/2π\n({shown} directions, seen from above)", "tab:blue")
    draw_disk(figure.add_subplot(grid[1, 0]), cosine_hemisphere(rng, shown)[0],
              "cosine (Malley), pdf cos θ/π\n= uniform on the disk", "tab:orange")
    axes = figure.add_subplot(grid[:, 1])
    plot_running_estimate(axes, sky_uniform_samples(rng, count), "uniform", "tab:blue")
    plot_running_estimate(axes, sky_cosine_samples(rng, count), "cosine-weighted",
                          "tab:orange", first=1, linewidth=3)
    axes.axhline(np.pi * SKY_RADIANCE, color="black", linestyle="--", linewidth=1,
                 label="exact: π L")
    axes.set_xscale("log")
    axes.set_ylim(np.pi - 1.5, np.pi + 1.5)
    label_axes(axes, "samples N", "estimate of E (L = 1)",
               "Irradiance under a constant sky: cosine sampling is exact at N = 1",
               "upper right")


def draw_light(axes, rng, count=100_000, light=FIGURE_LIGHT):
    right = light_area_samples(rng, count, light)
    wrong = light_area_samples_forgot_jacobian(rng, count, light)
    plot_running_estimate(axes, right, r"with the Jacobian $\cos\theta_\mathrm{light}/d^2$",
                          "tab:green", first=10)
    wrong_limit = plot_running_estimate(axes, wrong, "forgot the Jacobian", "tab:red",
                                        first=10)
    axes.text(count, wrong_limit - 0.03,
              r"converges, but to $L \int \cos\theta_\mathrm{floor} \, dA$:" "\n"
              "radiance times m², not an irradiance", ha="right", va="top",
              color="tab:red", fontsize=10)
    exact = polygon_irradiance(light)
    axes.axhline(exact, color="black", linestyle="--", linewidth=1,
                 label=f"exact (Lambert's formula): {exact:.4f}")
    axes.set_xscale("log")
    axes.set_ylim(0.0, None)
    x, y, z = light.center()
    label_axes(axes, "points picked on the light, N",
               "estimate of E at the floor point (L = 1)",
               f"Floor point (0, 0, 0) under a {np.sqrt(light.area()):g} m square light "
               f"centred at ({x:g}, {y:g}, {z:g}), facing down", "center right")


def save_figure(which, path, seed):
    """Draw one figure and write it atomically: to a temporary file in the same
    folder, then renamed, so nobody ever reads half a PNG."""
    import matplotlib
    matplotlib.use("Agg")  # no window: we only write a file
    import matplotlib.pyplot as plt

    rng = np.random.default_rng(seed)
    figure = plt.figure(figsize=(8, 5) if which != "hemisphere" else (9, 5.2), dpi=100)
    if which == "convergence":
        draw_convergence(figure.add_subplot(), rng)
    elif which == "hemisphere":
        draw_hemisphere(figure, rng)
    else:
        draw_light(figure.add_subplot(), rng)
    save_figure_file(figure, path)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--figure", required=True, help="write the figure (PNG) here")
    parser.add_argument("--which", choices=("convergence", "hemisphere", "light"),
                        default="convergence", help="which figure (default convergence)")
    parser.add_argument("--seed", type=int, default=1, help="random seed (default 1)")
    args = parser.parse_args(argv)
    save_figure(args.which, args.figure, args.seed)
    print(f"wrote {args.figure}")


if __name__ == "__main__":
    main()
