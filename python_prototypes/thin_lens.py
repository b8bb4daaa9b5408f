"""A thin-lens camera: depth of field for the course's pinhole camera, and how blurred a
point is at each distance (the circle of confusion).

The pinhole camera (camera_rays.py) sends the ray of pixel (x, y) from the eye through
its point on the sensor, focal_length F in front of the eye and sensor_width S wide. The
thin lens keeps that ray's direction d and its field of view, 2 atan(S / 2F), and
replaces the eye by a disk of diameter A (the aperture) across right and true_up:

    lens point  L = eye + (A / 2)(a · right + b · true_up),  (a, b) = concentric(u1, u2)
    focus point P = eye + d · focus / (d · forward)    the pinhole ray meets the plane
                                                       `focus` metres in front of the lens
    ray         from L towards P

Every ray of the pixel passes through P, so whatever lies on the focus plane is sharp.
A point Q at depth D (measured along forward) is seen from lens point L by the pixel
whose focus point is where the line L -> Q crosses the focus plane; projected back
through the eye onto the sensor that pixel is at x = F Q_side / D + F ℓ (1/focus - 1/D),
ℓ the lens point's offset. As ℓ runs over the disk of radius A/2, the images of Q fill
a disk on the sensor of diameter

    c(D) = A · F · |D - focus| / (D · focus)            (on the sensor, metres)
    c_pixels(D) = c(D) · width_in_pixels / S

A real lens of focal length f focused at f_d has its sensor at f f_d / (f_d - f), not at
f, and the textbook formula c = A |D - f_d| / D · f / (f_d - f) measures the blur there.
Relative to the sensor's distance both are A |D - f_d| / (D f_d): in pixels they agree
whenever the two sensors span the same field of view. Our camera fixes the field of
view by F and S alone, focused anywhere (a real lens "breathes", its view narrowing a
little as it focuses closer).

Mitsuba 3's `thinlens` sensor is this camera: fov = 2 atan(S / 2F) with fov_axis "x",
aperture_radius = A / 2 (in scene units, metres here: a 35 mm lens at f/2.8 has
A = 12.5 mm, aperture_radius 0.00625), focus_distance = focus, measured along the view
axis to a plane as here. Its lens x axis points to the image's left (its camera frame
is x = up x forward), so its aperture sample (1 - u1, u2) gives our lens point for
(u1, u2); its ray starts near_clip further along. See mitsuba_thinlens_dict().

    python python_prototypes/thin_lens.py --figure coc.png
    python python_prototypes/thin_lens.py --figure coc.png --focus 2 --f-numbers 1.4 4 16
"""

import argparse
import math
import sys
from dataclasses import dataclass

import numpy as np


from python_prototypes.figure_file import save_figure_file
from python_prototypes import camera_rays


@dataclass
class ThinLensCamera(camera_rays.Camera):
    """camera_rays.Camera plus an aperture (diameter, metres; 0 is the pinhole) and the
    distance of the plane in focus (metres, along forward)."""
    aperture_diameter: float = 0.035 / 2.8  # the 35 mm lens at f/2.8
    focus_distance: float = 4.0


def basis(camera):
    return camera_rays.camera_basis(camera.look_direction, camera.up)


# --8<-- [start:concentric]
def concentric_disk(u1, u2):
    """Shirley and Chiu's map from the unit square onto the unit disk (N, 2): squares
    round the centre go to rings, so areas keep their proportions and neighbours stay
    neighbours (better for stratified samples than r = √u)."""
    a = 2.0 * np.asarray(u1, dtype=np.float64) - 1.0
    b = 2.0 * np.asarray(u2, dtype=np.float64) - 1.0
    wider = np.abs(a) > np.abs(b)
    radius = np.where(wider, a, b)
    safe_a = np.where(a == 0, 1.0, a)
    safe_b = np.where(b == 0, 1.0, b)
    angle = np.where(wider, (np.pi / 4) * b / safe_a, np.pi / 2 - (np.pi / 4) * a / safe_b)
    angle = np.where((a == 0) & (b == 0), 0.0, angle)  # the centre: any angle, radius 0
    return np.stack([radius * np.cos(angle), radius * np.sin(angle)], axis=-1)
# --8<-- [end:concentric]


def sensor_offsets(camera, width, height, pixel_x, pixel_y):
    """(across, up) on the sensor, metres from its centre, of the continuous pixel
    coordinates pixel_x (from the image's left edge) and pixel_y (from its top edge):
    the pixel centre of (px, py) is (px + 0.5, py + 0.5), as in camera_rays.py."""
    sensor_height = camera.sensor_width * height / width  # square pixels
    across = (np.asarray(pixel_x, dtype=np.float64) / width - 0.5) * camera.sensor_width
    up = (0.5 - np.asarray(pixel_y, dtype=np.float64) / height) * sensor_height
    return across, up


def pinhole_directions(camera, width, height, pixel_x, pixel_y):
    """Unit directions (N, 3) of the pinhole rays through those sensor points."""
    forward, right, true_up = basis(camera)
    across, up = sensor_offsets(camera, width, height, pixel_x, pixel_y)
    to_sensor = (forward * camera.focal_length + right * across[:, None]
                 + true_up * up[:, None])
    return to_sensor / np.linalg.norm(to_sensor, axis=-1, keepdims=True)


def lens_points(camera, u1, u2):
    """Points (N, 3) on the aperture disk for uniform numbers u1, u2."""
    _, right, true_up = basis(camera)
    disk = concentric_disk(u1, u2) * (0.5 * camera.aperture_diameter)
    return np.asarray(camera.eye, dtype=np.float64) + disk[:, :1] * right \
        + disk[:, 1:] * true_up


# --8<-- [start:thin_lens]
def thin_lens_rays(camera, width, height, pixel_x, pixel_y, u1, u2):
    """Origins and unit directions (N, 3) of the thin-lens rays of these continuous
    pixel coordinates, with (u1, u2) choosing the point on the lens."""
    forward, _, _ = basis(camera)
    eye = np.asarray(camera.eye, dtype=np.float64)
    pinhole = pinhole_directions(camera, width, height, pixel_x, pixel_y)
    # Where the pinhole ray meets the focus plane: every ray of this pixel goes there.
    focus_points = eye + pinhole * (camera.focus_distance / (pinhole @ forward))[:, None]
    origins = lens_points(camera, u1, u2)
    directions = focus_points - origins
    return origins, directions / np.linalg.norm(directions, axis=-1, keepdims=True)
# --8<-- [end:thin_lens]


def depth(camera, points):
    """Distance in front of the lens, along forward (what `focus` measures)."""
    forward, _, _ = basis(camera)
    return (np.asarray(points, dtype=np.float64) - np.asarray(camera.eye)) @ forward


def image_positions(camera, width, height, points, lens):
    """The continuous pixel coordinates (pixel_x, pixel_y) whose ray from lens point
    `lens` passes through `points` (both (N, 3), points in front of the lens): the line
    lens -> point crosses the focus plane somewhere; the pinhole ray through that
    crossing comes from the pixel sought."""
    forward, right, true_up = basis(camera)
    eye = np.asarray(camera.eye, dtype=np.float64)
    points, lens = np.asarray(points, dtype=np.float64), np.asarray(lens, dtype=np.float64)
    # The lens is at depth 0, so depth grows linearly from 0 at the lens to D at the point.
    on_focus_plane = lens + (points - lens) * (camera.focus_distance
                                               / depth(camera, points))[:, None]
    on_sensor = (on_focus_plane - eye) * (camera.focal_length / camera.focus_distance)
    sensor_height = camera.sensor_width * height / width
    pixel_x = (on_sensor @ right / camera.sensor_width + 0.5) * width
    pixel_y = (0.5 - on_sensor @ true_up / sensor_height) * height
    return pixel_x, pixel_y


# ---------------------------------------------------------------------------------------
# The circle of confusion
# ---------------------------------------------------------------------------------------

def circle_of_confusion(distance, aperture_diameter, focal_length, focus_distance):
    """Diameter (metres) of a point's blur on our camera's sensor (at focal_length in
    front of the eye): A F |D - focus| / (D focus), D the point's depth, written as
    A F |1/focus - 1/D| so that D = inf works."""
    distance = np.asarray(distance, dtype=np.float64)
    return aperture_diameter * focal_length * np.abs(1.0 / focus_distance - 1.0 / distance)


def physical_circle_of_confusion(distance, aperture_diameter, focal_length,
                                 focus_distance):
    """The textbook blur on a real lens's sensor, at f f_d / (f_d - f) behind it:
    A |D - f_d| / D · f / (f_d - f)."""
    distance = np.asarray(distance, dtype=np.float64)
    return (aperture_diameter * np.abs(1.0 - focus_distance / distance)
            * focal_length / (focus_distance - focal_length))


def circle_of_confusion_pixels(camera, distance, width):
    """Blur diameter in pixels of an image `width` pixels wide."""
    return circle_of_confusion(distance, camera.aperture_diameter, camera.focal_length,
                               camera.focus_distance) * width / camera.sensor_width


def measured_blur_diameter(camera, width, height, point, samples, rng):
    """The blur of one point measured as the renderer would see it: its images for
    `samples` random lens points; the diameter is twice the largest distance from
    the pinhole's image (the disk's centre), in pixels."""
    lens = lens_points(camera, rng.random(samples), rng.random(samples))
    points = np.broadcast_to(np.asarray(point, dtype=np.float64), lens.shape)
    x, y = image_positions(camera, width, height, points, lens)
    centre_x, centre_y = image_positions(camera, width, height, points[:1],
                                         np.asarray(camera.eye, dtype=np.float64)[None])
    return 2.0 * np.max(np.hypot(x - centre_x, y - centre_y))


def f_number_aperture(focal_length, f_number):
    """Aperture diameter A = F / N."""
    return focal_length / f_number


def mitsuba_thinlens_dict(camera, width, height, spp=16):
    """The same camera as a Mitsuba 3 `thinlens` sensor (a dictionary for load_dict)."""
    import mitsuba as mi
    eye = np.asarray(camera.eye, dtype=np.float64)
    return {
        "type": "thinlens",
        "fov_axis": "x",
        "fov": math.degrees(2 * math.atan(camera.sensor_width / (2 * camera.focal_length))),
        "aperture_radius": camera.aperture_diameter / 2.0,
        "focus_distance": camera.focus_distance,
        "to_world": mi.ScalarTransform4f().look_at(
            origin=eye.tolist(), target=(eye + np.asarray(camera.look_direction)).tolist(),
            up=list(camera.up)),
        "sampler": {"type": "independent", "sample_count": spp},
        "film": {"type": "hdrfilm", "width": width, "height": height,
                 "rfilter": {"type": "box"}},
    }


# ---------------------------------------------------------------------------------------
# Figure
# ---------------------------------------------------------------------------------------

def draw_circle_of_confusion(axes, camera, width, f_numbers, rng):
    """Blur in pixels against depth for a few apertures; the dots are measured from lens
    samples (measured_blur_diameter), the lines are c(D)."""
    height = width  # the blur does not depend on the image's height
    distances = np.geomspace(0.25, 100.0, 400)
    measured_at = np.geomspace(0.3, 60.0, 9)
    forward, _, _ = basis(camera)
    for f_number, color in zip(f_numbers, ["tab:blue", "tab:orange", "tab:green",
                                           "tab:red", "tab:purple"]):
        lens = ThinLensCamera(**{**camera.__dict__,
                                 "aperture_diameter": f_number_aperture(
                                     camera.focal_length, f_number)})
        axes.loglog(distances, circle_of_confusion_pixels(lens, distances, width),
                    color=color,
                    label=f"f/{f_number:g}: A = {lens.aperture_diameter * 1000:.3g} mm")
        measured = [measured_blur_diameter(lens, width, height,
                                           np.asarray(lens.eye) + forward * d, 4000, rng)
                    for d in measured_at]
        axes.loglog(measured_at, measured, "o", color=color, markersize=4)
    axes.axvline(camera.focus_distance, color="black", linestyle="--", linewidth=1)
    axes.text(camera.focus_distance * 1.05, 100, f"focus {camera.focus_distance:g} m",
              fontsize=9, va="top")
    axes.axhline(1.0, color="0.5", linewidth=1)
    axes.text(0.27, 1.1, "one pixel", fontsize=9, color="0.4")
    axes.set_ylim(0.01, 200)
    axes.set_xlabel("depth of the point D (m)")
    axes.set_ylabel(f"blur diameter (pixels, image {width} px wide)")
    axes.set_title(f"Circle of confusion: {camera.focal_length * 1000:g} mm lens, "
                   f"{camera.sensor_width * 1000:g} mm sensor; "
                   r"$c = A F |D - f_d| / (D f_d)$" "\n"
                   "lines: the formula; dots: measured from 4000 lens samples",
                   fontsize=10)
    axes.grid(True, which="both", alpha=0.3)
    axes.legend(fontsize=9, loc="upper right")


def save_figure(path, camera, width, f_numbers, seed):
    import matplotlib
    matplotlib.use("Agg")  # no window: we only write a file
    import matplotlib.pyplot as plt

    figure = plt.figure(figsize=(8, 5.2), dpi=100)
    draw_circle_of_confusion(figure.add_subplot(), camera, width, f_numbers,
                             np.random.default_rng(seed))
    save_figure_file(figure, path)


def main(argv=None):
    defaults = ThinLensCamera()
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--figure", help="write the circle-of-confusion figure (PNG) here")
    parser.add_argument("--focus", type=float, default=2.0, help="metres (default 2)")
    parser.add_argument("--focal-length", type=float, default=defaults.focal_length,
                        help="metres (default 0.035)")
    parser.add_argument("--sensor-width", type=float, default=defaults.sensor_width,
                        help="metres (default 0.036)")
    parser.add_argument("--width", type=int, default=256, help="image width in pixels")
    parser.add_argument("--f-numbers", type=float, nargs="+", default=[1.4, 4.0, 16.0],
                        help="apertures as f-numbers N, A = F / N (default 1.4 4 16)")
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args(argv)
    if args.focus <= args.focal_length:
        sys.exit("thin_lens.py: --focus must be further than the focal length")
    camera = ThinLensCamera(focal_length=args.focal_length, sensor_width=args.sensor_width,
                            focus_distance=args.focus)
    fov = math.degrees(2 * math.atan(args.sensor_width / (2 * args.focal_length)))
    print(f"Mitsuba thinlens: fov {fov:.4f} (fov_axis x), focus_distance {args.focus:g}")
    for f_number in args.f_numbers:
        aperture = f_number_aperture(args.focal_length, f_number)
        camera.aperture_diameter = aperture
        near = args.focus / 4
        print(f"  f/{f_number:g}: aperture_radius {aperture / 2:.6g} m; blur at infinity "
              f"{circle_of_confusion_pixels(camera, math.inf, args.width):.3g} px, at "
              f"{near:g} m {circle_of_confusion_pixels(camera, near, args.width):.3g} px "
              f"({args.width} px wide)")
    if args.figure:
        save_figure(args.figure, camera, args.width, args.f_numbers, args.seed)
        print(f"wrote {args.figure}")


if __name__ == "__main__":
    main()
