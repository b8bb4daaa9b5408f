"""A clear sky with a sun as a latitude-longitude radiance map: the environment light.

The map is made here, at build time, from a physically based model (nothing is
downloaded) and written as a float32 RGB PFM that Mitsuba 3's `envmap` and our renderer
both read.

Orientation: Mitsuba 3's `envmap` at identity to_world (checked against Mitsuba itself
in tests/python/prototypes/test_environment_prototypes.py). +y is up; a direction d has

    u = atan2(d.x, -d.z) / 2π   (wrapped into [0, 1)),   v = acos(d.y) / π
    d = (sin φ sin θ, cos θ, -cos φ sin θ),   φ = 2π u,   θ = π v

so u = 0 looks along -z, u = 1/4 along +x, u = 1/2 along +z, u = 3/4 along -x; v = 0 is
the zenith (the image's top row), v = 1/2 the horizon. Our renderer reads pixel
(row r, column c) as the constant radiance of the patch u in [c, c+1]/W, v in [r, r+1]/H
(nearest pixel, what importance sampling assumes), and every pixel here holds the mean
radiance over that patch. Mitsuba interpolates bilinearly with column c centred at
u = (c + 1/2)/W, as we do, but row r at v = r/(H - 1): its first and last rows sit on
the poles. The two readings of one file differ by at most half a row in elevation
(0.35° for a 512 x 256 map); mitsuba_envmap_eval() is Mitsuba's reading in numpy. On a
horizontal plane under the default 512 x 256 sky, Mitsuba's reading gives 0.3 to 0.5%
more light than ours (mitsuba_upward_irradiance() against upward_irradiance(); Mitsuba's
own render agrees with the former); the gap halves with each doubling of the width.

The sky: Preetham, Shirley and Smits, "A Practical Analytic Model for Daylight"
(SIGGRAPH 1999). Luminance Y and chromaticity x, y each follow Perez et al.'s
distribution, F(θ, γ) = (1 + A e^(B / cos θ)) (1 + C e^(D γ) + E cos² γ), θ the view
direction's zenith angle and γ its angle to the sun, scaled so the zenith gets the
paper's zenith values: Y = Y_z F(θ, γ) / F(0, θ_s). The coefficients A..E are linear in
the turbidity T, Y_z (in kcd/m²) and x_z, y_z are the paper's fits in T and the sun's
zenith angle θ_s (appendix A.2). xyY -> XYZ -> linear sRGB (Rec. 709 primaries, D65).
Negative components are clipped to 0: the sky has none once the sun is a degree or two
up (with the sun on the horizon and T < 3 a few pixels go out of gamut, a known weakness
of the fit), and a sun low in hazy air loses its blue altogether.

The sun: a uniform disk 0.53° across (no limb darkening) of spectral radiance
    L_sun(λ) = B(λ, 5778 K) · τ_Rayleigh(λ) · τ_aerosol(λ),
a black body at the sun's effective temperature (which by definition has the solar
disk's mean radiance) seen through the paper's own transmittances with the same T:
τ_R = exp(-0.008735 λ^-4.08 m), τ_a = exp(-β λ^-1.3 m), β = 0.04608 T - 0.04586
(λ in μm), air mass m = 1 / (cos θ_s + 0.15 (93.885 - θ_s in degrees)^-1.253). The
paper's ozone, mixed-gas and water-vapour absorption (a few per cent in the visible)
are left out, which makes the sun a few per cent too bright. L_sun(λ) -> XYZ with
Wyman, Sloan and Shirley's analytic fit of the CIE 1931 matching functions (2013),
683 lm/W, then the same matrix to sRGB. The sun's pixels get its radiance times the
fraction of their solid angle it covers, normalised so its total is exactly L_sun Ω_sun.

Units: the map's luminance (0.2126 R + 0.7152 G + 0.0722 B) is in kcd/m² (1 = 1000
cd/m²), the paper's unit; --scale multiplies everything.

Below the horizon: a Lambertian ground of constant albedo ρ (default 0.2, grey) lit by
this map's sky and sun without shadows: L_ground = ρ E / π, E the map's irradiance on a
horizontal plane. --ground-albedo 0 gives a black ground.

--spots writes instead a small test map: a dim uniform background and three bright
disks of known angular radius and radiance (SPOTS), one near the zenith, one low, one
below the horizon.

    python python_prototypes/sky.py --out sky.pfm --width 512 --sun-elevation 30 \\
        --sun-azimuth 120 --turbidity 3 --figure sky.png
    python python_prototypes/sky.py --spots --out spots.pfm --figure spots.png
"""

import argparse
import math
import sys
import time
from dataclasses import dataclass

import numpy as np

from python_prototypes.figure_file import save_figure_file
from python_prototypes import srgb
from python_prototypes.pfm import read_pfm, write_pfm  # noqa: F401  (the maps are PFM files)


SUN_ANGULAR_DIAMETER_DEGREES = 0.53
SUN_TEMPERATURE_KELVIN = 5778.0
SUN_HALF_ANGLE = math.radians(SUN_ANGULAR_DIAMETER_DEGREES / 2)
SUN_SOLID_ANGLE = 2.0 * math.pi * (1.0 - math.cos(SUN_HALF_ANGLE))  # about 6.7e-5 sr
LUMINOUS_EFFICACY = 683.0  # lm/W at 555 nm: radiometric -> photometric
DEFAULT_GROUND_ALBEDO = 0.2
REC709_LUMINANCE = np.array([0.2126, 0.7152, 0.0722])  # Y of linear sRGB

# XYZ -> linear sRGB (Rec. 709 primaries, D65 white). The inverse's middle row (Y from
# RGB) is REC709_LUMINANCE to four digits, so the map's luminance is the model's Y.
XYZ_TO_LINEAR_SRGB = np.array([[3.2404542, -1.5371385, -0.4985314],
                               [-0.9692660, 1.8760108, 0.0415560],
                               [0.0556434, -0.2040259, 1.0572252]])

# Preetham et al. 1999, appendix A.2: each Perez coefficient A..E is slope * T + offset.
PEREZ_LUMINANCE = np.array([[0.1787, -1.4630], [-0.3554, 0.4275], [-0.0227, 5.3251],
                            [0.1206, -2.5771], [-0.0670, 0.3703]])
PEREZ_X = np.array([[-0.0193, -0.2592], [-0.0665, 0.0008], [-0.0004, 0.2125],
                    [-0.0641, -0.8989], [-0.0033, 0.0452]])
PEREZ_Y = np.array([[-0.0167, -0.2608], [-0.0950, 0.0092], [-0.0079, 0.2102],
                    [-0.0441, -1.6537], [-0.0109, 0.0529]])
# Zenith chromaticity: [T², T, 1] @ matrix @ [θ_s³, θ_s², θ_s, 1], θ_s in radians.
ZENITH_X = np.array([[0.00166, -0.00375, 0.00209, 0.0],
                     [-0.02903, 0.06377, -0.03202, 0.00394],
                     [0.11693, -0.21196, 0.06052, 0.25886]])
ZENITH_Y = np.array([[0.00275, -0.00610, 0.00317, 0.0],
                     [-0.04214, 0.08970, -0.04153, 0.00516],
                     [0.15346, -0.26756, 0.06670, 0.26688]])
TURBIDITY_RANGE = (1.7, 10.0)  # clear to hazy; further out the fits only extrapolate


# ---------------------------------------------------------------------------------------
# Directions and pixels: Mitsuba 3's envmap orientation
# ---------------------------------------------------------------------------------------

# --8<-- [start:orientation]
def direction_to_uv(directions):
    """(u, v) in [0, 1) x [0, 1] of unit directions (..., 3), Mitsuba's envmap mapping:
    u = atan2(x, -z) / 2π wrapped into [0, 1), v = acos(y) / π."""
    d = np.asarray(directions, dtype=np.float64)
    u = np.arctan2(d[..., 0], -d[..., 2]) / (2.0 * np.pi)
    u = u - np.floor(u)  # atan2 gives (-π, π]: fold the negative half onto [1/2, 1)
    v = np.arccos(np.clip(d[..., 1], -1.0, 1.0)) / np.pi
    return u, v


def uv_to_direction(u, v):
    """Unit directions (..., 3) of (u, v): φ = 2π u, θ = π v,
    d = (sin φ sin θ, cos θ, -cos φ sin θ)."""
    phi = 2.0 * np.pi * np.asarray(u, dtype=np.float64)
    theta = np.pi * np.asarray(v, dtype=np.float64)
    sin_theta = np.sin(theta)
    return np.stack([np.sin(phi) * sin_theta, np.cos(theta), -np.cos(phi) * sin_theta],
                    axis=-1)
# --8<-- [end:orientation]


def pixel_of_direction(directions, width, height):
    """(row, column) of the pixel whose patch holds each direction (nearest pixel)."""
    u, v = direction_to_uv(directions)
    column = np.minimum((u * width).astype(np.int64), width - 1)
    row = np.minimum((v * height).astype(np.int64), height - 1)  # v = 1: the last row
    return row, column


def pixel_center_uv(width, height):
    """(u, v), each (height, width), of every pixel's centre."""
    u = (np.arange(width) + 0.5) / width
    v = (np.arange(height) + 0.5) / height
    return np.meshgrid(u, v)


def pixel_center_directions(width, height):
    return uv_to_direction(*pixel_center_uv(width, height))


def row_solid_angles(width, height):
    """Solid angle (height,) of one pixel in each row:
    (2π / W)(cos θ_top - cos θ_bottom). The rows near the poles are thin slivers,
    which is why the sampler weights by sin θ."""
    theta_edges = np.pi * np.arange(height + 1) / height
    return (2.0 * np.pi / width) * (np.cos(theta_edges[:-1]) - np.cos(theta_edges[1:]))


def row_cosine_integrals(width, height):
    """∫ max(cos θ, 0) dω (height,) over one pixel of each row: the weight of a pixel in
    the irradiance of an upward-facing (+y) point. Over a row above the horizon it is
    (2π / W)(sin² θ_bottom - sin² θ_top) / 2."""
    theta_edges = np.minimum(np.pi * np.arange(height + 1) / height, np.pi / 2)
    sin_squared = np.sin(theta_edges) ** 2
    return (2.0 * np.pi / width) * 0.5 * (sin_squared[1:] - sin_squared[:-1])


def upward_irradiance(image):
    """Irradiance (3,) on an upward-facing (+y) point under the map, each pixel a patch
    of constant radiance: Σ L_pixel ∫_pixel max(cos θ, 0) dω, exact."""
    height, width = image.shape[:2]
    weights = row_cosine_integrals(width, height)
    return np.einsum("hwc,h->c", np.asarray(image, dtype=np.float64), weights)


def mitsuba_envmap_eval(image, directions):
    """What Mitsuba 3's envmap (scalar_rgb, scale 1, identity to_world) returns for
    these directions: bilinear, columns centred at u = (c + 1/2)/W and wrapping round,
    row r at v = r / (H - 1), so the first and last rows lie on the poles."""
    image = np.asarray(image, dtype=np.float64)
    height, width = image.shape[:2]
    wrapped = np.concatenate([image, image[:, :1]], axis=1)  # Mitsuba's extra column
    u, v = direction_to_uv(directions)
    u = u - 0.5 / width
    u = u - np.floor(u)
    x, y = u * width, v * (height - 1)
    column = np.minimum(x.astype(np.int64), width - 1)
    row = np.minimum(y.astype(np.int64), height - 2)
    wx, wy = (x - column)[..., None], (y - row)[..., None]
    top = (1 - wx) * wrapped[row, column] + wx * wrapped[row, column + 1]
    bottom = (1 - wx) * wrapped[row + 1, column] + wx * wrapped[row + 1, column + 1]
    return (1 - wy) * top + wy * bottom


def mitsuba_upward_irradiance(image, steps=200_000):
    """Upward (+y) irradiance (3,) under the map as Mitsuba reads it (bilinear, rows on
    the poles). Linear interpolation round each row keeps the row's mean, so only the
    rows' weights ∫ hat_r(v) max(cos θ, 0) sin θ dv need integrating (midpoint rule);
    compare with upward_irradiance(), our reading."""
    image = np.asarray(image, dtype=np.float64)
    height, width = image.shape[:2]
    v = (np.arange(steps) + 0.5) / steps
    theta = np.pi * v
    # dω = 2π² sin θ du dv; the row mean already holds the ∫ du (= mean over columns).
    weight = 2.0 * np.pi**2 * np.maximum(np.cos(theta), 0.0) * np.sin(theta) / steps
    position = v * (height - 1)
    row = np.minimum(position.astype(np.int64), height - 2)
    above = position - row
    row_weights = (np.bincount(row, weight * (1 - above), minlength=height)
                   + np.bincount(row + 1, weight * above, minlength=height))
    return row_weights @ image.mean(axis=1)


def elevation_azimuth_to_direction(elevation_degrees, azimuth_degrees):
    """Elevation above the horizon; azimuth is the map's φ = 2π u, from -z towards +x,
    so a sun at azimuth α shows at u = α / 360 across the map."""
    return uv_to_direction(np.asarray(azimuth_degrees) / 360.0,
                           (90.0 - np.asarray(elevation_degrees)) / 180.0)


def luminance(rgb):
    return np.asarray(rgb, dtype=np.float64) @ REC709_LUMINANCE


# ---------------------------------------------------------------------------------------
# Disks on the sphere: the sun and the test spots, averaged over each pixel
# ---------------------------------------------------------------------------------------

def disk_coverage(width, height, center, angular_radius, subsamples=16):
    """Fraction (height, width) of each pixel's solid angle inside the disk (spherical
    cap) of angular_radius (radians) around the unit direction center, by a
    subsamples x subsamples grid in (u, v) weighted by sin θ. Only pixels that can
    reach the disk are subsampled, so a tiny sun on a big map costs little."""
    center = np.asarray(center, dtype=np.float64)
    center = center / np.linalg.norm(center)
    # No point of a pixel lies further from its centre than half its height plus half
    # its widest width (go along the meridian, then along the circle of latitude).
    reach = np.pi / (2 * height) + np.pi / width
    centers = pixel_center_directions(width, height)
    distance = np.arccos(np.clip(centers @ center, -1.0, 1.0))
    rows, columns = np.nonzero(distance <= angular_radius + reach)
    offsets = (np.arange(subsamples) + 0.5) / subsamples
    sub_u = (columns[:, None, None] + offsets[None, None, :]) / width
    sub_v = (rows[:, None, None] + offsets[None, :, None]) / height
    sub_u, sub_v = np.broadcast_arrays(sub_u, sub_v)
    inside = uv_to_direction(sub_u, sub_v) @ center >= math.cos(angular_radius)
    weight = np.sin(np.pi * sub_v)  # solid angle of each subsample ∝ sin θ
    coverage = np.zeros((height, width))
    coverage[rows, columns] = (inside * weight).sum(axis=(1, 2)) / weight.sum(axis=(1, 2))
    return coverage


def add_disk(image, center, angular_radius, radiance, exact_total=True, subsamples=16):
    """Adds a uniform disk of the given RGB radiance to the map, each pixel getting the
    radiance times the fraction of its solid angle the disk covers. exact_total: rescale
    the fractions so the disk's Σ coverage x pixel solid angle is exactly its solid
    angle 2π (1 - cos r), so that its light on the scene is exact."""
    height, width = image.shape[:2]
    coverage = disk_coverage(width, height, center, angular_radius, subsamples)
    if exact_total:
        covered = coverage.sum(axis=1) @ row_solid_angles(width, height)
        coverage *= 2.0 * np.pi * (1.0 - math.cos(angular_radius)) / covered
    image += coverage[..., None] * np.asarray(radiance, dtype=np.float64)
    return coverage


# ---------------------------------------------------------------------------------------
# The sky: Preetham et al. 1999
# ---------------------------------------------------------------------------------------

def perez_coefficients(turbidity):
    """Perez coefficients A..E for Y, x and y: three arrays (5,)."""
    return tuple(table[:, 0] * turbidity + table[:, 1]
                 for table in (PEREZ_LUMINANCE, PEREZ_X, PEREZ_Y))


# --8<-- [start:perez]
def perez(theta, gamma, coefficients):
    """Perez et al.'s sky distribution F(θ, γ) = (1 + A e^(B / cos θ)) (1 + C e^(D γ) +
    E cos² γ): θ the zenith angle (< π/2), γ the angle to the sun."""
    a, b, c, d, e = coefficients
    cos_theta = np.maximum(np.cos(theta), 1e-6)  # at the horizon e^(B / cos θ) -> 0
    return (1.0 + a * np.exp(b / cos_theta)) * (1.0 + c * np.exp(d * gamma)
                                                + e * np.cos(gamma) ** 2)
# --8<-- [end:perez]


def zenith_luminance(turbidity, sun_zenith):
    """Y_z in kcd/m²: (4.0453 T - 4.9710) tan χ - 0.2155 T + 2.4192,
    χ = (4/9 - T/120)(π - 2 θ_s)."""
    chi = (4.0 / 9.0 - turbidity / 120.0) * (np.pi - 2.0 * sun_zenith)
    return (4.0453 * turbidity - 4.9710) * np.tan(chi) - 0.2155 * turbidity + 2.4192


def zenith_chromaticity(turbidity, sun_zenith):
    """(x_z, y_z) = [T², T, 1] M [θ_s³, θ_s², θ_s, 1]ᵀ (the paper's matrices M)."""
    powers_of_t = np.array([turbidity**2, turbidity, 1.0])
    powers_of_sun = np.array([sun_zenith**3, sun_zenith**2, sun_zenith, 1.0])
    return (powers_of_t @ ZENITH_X @ powers_of_sun,
            powers_of_t @ ZENITH_Y @ powers_of_sun)


def sky_xyY(directions, sun_direction, turbidity):
    """(x, y, Y) of the clear sky, Y in kcd/m², for directions above the horizon."""
    directions = np.asarray(directions, dtype=np.float64)
    sun_direction = np.asarray(sun_direction, dtype=np.float64)
    sun_zenith = math.acos(np.clip(sun_direction[1], -1.0, 1.0))
    theta = np.arccos(np.clip(directions[..., 1], -1.0, 1.0))
    gamma = np.arccos(np.clip(directions @ sun_direction, -1.0, 1.0))
    x_z, y_z = zenith_chromaticity(turbidity, sun_zenith)
    zenith_values = (zenith_luminance(turbidity, sun_zenith), x_z, y_z)
    luminance_c, x_c, y_c = perez_coefficients(turbidity)
    # F(0, θ_s): the distribution at the zenith, whose γ is the sun's zenith angle.
    values = [zenith * perez(theta, gamma, c) / perez(0.0, sun_zenith, c)
              for zenith, c in zip(zenith_values, (luminance_c, x_c, y_c))]
    big_y, x, y = values
    return x, y, big_y


def xyY_to_linear_srgb(x, y, big_y):
    """Chromaticity and luminance -> XYZ (X = x Y / y, Z = (1 - x - y) Y / y) -> linear
    sRGB; (..., 3)."""
    xyz = np.stack([x * big_y / y, big_y, (1.0 - x - y) * big_y / y], axis=-1)
    return xyz @ XYZ_TO_LINEAR_SRGB.T


def sky_radiance(directions, sun_direction, turbidity):
    """Linear sRGB (..., 3) of the sky alone (no sun disk), luminance in kcd/m²; zero at
    and below the horizon. Out-of-gamut negatives are clipped to 0."""
    rgb = xyY_to_linear_srgb(*sky_xyY(directions, sun_direction, turbidity))
    above = np.asarray(directions)[..., 1] > 0.0
    return np.where(above[..., None], np.maximum(rgb, 0.0), 0.0)


# ---------------------------------------------------------------------------------------
# The sun: a black body through Preetham's Rayleigh and aerosol transmittances
# ---------------------------------------------------------------------------------------

def relative_air_mass(sun_zenith):
    """Kasten's (1966) fit, the one the paper uses:
    m = 1 / (cos θ + 0.15 (93.885 - θ in degrees)^-1.253)."""
    degrees = math.degrees(sun_zenith)
    return 1.0 / (math.cos(sun_zenith) + 0.15 * (93.885 - degrees) ** -1.253)


def sun_transmittance(wavelength_nm, sun_zenith, turbidity):
    """Rayleigh x aerosol (Ångström, α = 1.3) transmittance along the sun's path."""
    micrometres = np.asarray(wavelength_nm, dtype=np.float64) / 1000.0
    air_mass = relative_air_mass(sun_zenith)
    beta = 0.04608365822050 * turbidity - 0.04586025928522
    rayleigh = np.exp(-0.008735 * micrometres**-4.08 * air_mass)
    aerosol = np.exp(-beta * micrometres**-1.3 * air_mass)
    return rayleigh * aerosol


def planck_radiance(wavelength_nm, temperature):
    """Black-body spectral radiance in W / (m² sr nm)."""
    h, c, k = 6.62607015e-34, 2.99792458e8, 1.380649e-23
    metres = np.asarray(wavelength_nm, dtype=np.float64) * 1e-9
    per_metre = 2.0 * h * c**2 / metres**5 / np.expm1(h * c / (metres * k * temperature))
    return per_metre * 1e-9


def cie_1931_matching(wavelength_nm):
    """x̄, ȳ, z̄ (..., 3): Wyman, Sloan and Shirley's multi-lobe Gaussian fit (2013)."""
    lam = np.asarray(wavelength_nm, dtype=np.float64)

    def lobe(mean, sigma_below, sigma_above):
        sigma = np.where(lam < mean, sigma_below, sigma_above)
        return np.exp(-0.5 * ((lam - mean) / sigma) ** 2)

    x_bar = (1.056 * lobe(599.8, 37.9, 31.0) + 0.362 * lobe(442.0, 16.0, 26.7)
             - 0.065 * lobe(501.1, 20.4, 26.2))
    y_bar = 0.821 * lobe(568.8, 46.9, 40.5) + 0.286 * lobe(530.9, 16.3, 31.1)
    z_bar = 1.217 * lobe(437.0, 11.8, 36.0) + 0.681 * lobe(459.0, 26.0, 13.8)
    return np.stack([x_bar, y_bar, z_bar], axis=-1)


def spectrum_to_linear_srgb(wavelength_nm, spectral_radiance):
    """Linear sRGB whose luminance is 683 ∫ L(λ) ȳ(λ) dλ, in kcd/m² (L in
    W / (m² sr nm))."""
    step = wavelength_nm[1] - wavelength_nm[0]  # an even grid: a plain sum integrates
    xyz = LUMINOUS_EFFICACY * step * (spectral_radiance @ cie_1931_matching(wavelength_nm))
    return (xyz / 1000.0) @ XYZ_TO_LINEAR_SRGB.T


def sun_radiance(sun_zenith, turbidity):
    """Linear sRGB (3,) of the sun's disk, kcd/m², seen through the atmosphere."""
    wavelengths = np.arange(360.0, 831.0, 1.0)
    spectrum = (planck_radiance(wavelengths, SUN_TEMPERATURE_KELVIN)
                * sun_transmittance(wavelengths, sun_zenith, turbidity))
    return np.maximum(spectrum_to_linear_srgb(wavelengths, spectrum), 0.0)


# ---------------------------------------------------------------------------------------
# The maps
# ---------------------------------------------------------------------------------------

def check_sky_arguments(width, sun_elevation, turbidity):
    if width < 4 or width % 2:
        raise ValueError(f"width {width}: must be even and at least 4 (height = width / 2)")
    if not 0.0 <= sun_elevation <= 90.0:
        raise ValueError(f"sun elevation {sun_elevation}: the model needs 0 to 90 degrees")
    low, high = TURBIDITY_RANGE
    if not low <= turbidity <= high:
        raise ValueError(f"turbidity {turbidity}: the model was fitted for {low} to {high}")


def sky_map(width=512, sun_elevation=30.0, sun_azimuth=120.0, turbidity=3.0,
            ground_albedo=DEFAULT_GROUND_ALBEDO, scale=1.0):
    """The sky-and-sun map: float32 (width / 2, width, 3), linear sRGB, kcd/m² x scale."""
    check_sky_arguments(width, sun_elevation, turbidity)
    height = width // 2
    sun_direction = elevation_azimuth_to_direction(sun_elevation, sun_azimuth)
    sun_zenith = math.radians(90.0 - sun_elevation)
    image = sky_radiance(pixel_center_directions(width, height), sun_direction, turbidity)
    # The sun is far smaller than a pixel (0.53° against 0.7° for 512 wide): each pixel
    # gets its share of the disk, exact in total; the part below the horizon is ground.
    add_disk(image, sun_direction, SUN_HALF_ANGLE, sun_radiance(sun_zenith, turbidity))
    below = np.arange(height) >= height // 2  # the horizon is the border of two rows
    image[below] = 0.0
    ground = np.asarray(ground_albedo, dtype=np.float64) * upward_irradiance(image) / np.pi
    image[below] = ground
    return (image * scale).astype(np.float32)


@dataclass(frozen=True)
class Spot:
    """A uniform disk on the sphere: centre (elevation, azimuth in the map's sense) and
    angular radius, in degrees, and its RGB radiance."""
    elevation: float
    azimuth: float
    angular_radius: float
    radiance: tuple

    def direction(self):
        return elevation_azimuth_to_direction(self.elevation, self.azimuth)


SPOTS = (
    Spot(elevation=72.0, azimuth=45.0, angular_radius=10.0, radiance=(40.0, 36.0, 30.0)),
    Spot(elevation=15.0, azimuth=200.0, angular_radius=7.0, radiance=(10.0, 20.0, 60.0)),
    Spot(elevation=-35.0, azimuth=300.0, angular_radius=12.0, radiance=(30.0, 12.0, 6.0)),
)
SPOTS_BACKGROUND = (0.05, 0.05, 0.05)


def spots_map(width=64, height=32, spots=SPOTS, background=SPOTS_BACKGROUND):
    """The test map: a uniform background plus the spots, each pixel the mean over its
    patch (spots partly covering a pixel give it that share of their radiance)."""
    image = np.empty((height, width, 3))
    image[...] = background
    for spot in spots:  # the spot replaces the background where it covers it
        extra = np.asarray(spot.radiance) - np.asarray(background)
        add_disk(image, spot.direction(), math.radians(spot.angular_radius), extra,
                 exact_total=False, subsamples=32)
    return image.astype(np.float32)


def spots_irradiance(spots=SPOTS, background=SPOTS_BACKGROUND):
    """Upward (+y) irradiance (3,) under the spots map's disks themselves, in closed
    form for a cap wholly above or below the horizon: a cap of radius r around
    elevation e gives π sin² r sin e (the Nusselt analogue), and the background π L."""
    total = np.pi * np.asarray(background, dtype=np.float64)
    for spot in spots:
        if abs(spot.elevation) < spot.angular_radius:
            raise ValueError("a spot crossing the horizon has no simple closed form")
        if spot.elevation > 0:
            # The cap's cos-weighted solid angle: π sin² r times its centre's cos θ.
            extra = np.asarray(spot.radiance) - np.asarray(background)
            total = total + np.pi * math.sin(math.radians(spot.angular_radius)) ** 2 \
                * math.sin(math.radians(spot.elevation)) * extra
    return total


# ---------------------------------------------------------------------------------------
# PFM files (mitsuba_reference.py's conventions: little-endian, bottom row first)
# ---------------------------------------------------------------------------------------


# ---------------------------------------------------------------------------------------
# Figure
# ---------------------------------------------------------------------------------------

def tone_map(image, exposure):
    """Reinhard x / (1 + x), then the sRGB curve: for looking at, not for measuring."""
    x = np.maximum(np.asarray(image, dtype=np.float64) * exposure, 0.0)
    x = x / (1.0 + x)
    return srgb.encode(x)


def cap_outline(center, angular_radius, points=181):
    """(azimuth, elevation) in degrees of points round the edge of a disk on the sphere,
    for drawing it on the map; NaN breaks the line where it wraps round the seam."""
    center = np.asarray(center, dtype=np.float64)
    helper = np.array([1.0, 0.0, 0.0]) if abs(center[0]) < 0.9 else np.array([0, 0, 1.0])
    first = np.cross(center, helper)
    first /= np.linalg.norm(first)
    second = np.cross(center, first)
    angle = np.linspace(0.0, 2.0 * np.pi, points)[:, None]
    edge = (math.cos(angular_radius) * center + math.sin(angular_radius)
            * (np.cos(angle) * first + np.sin(angle) * second))
    u, v = direction_to_uv(edge)
    azimuth, elevation = 360.0 * u, 90.0 - 180.0 * v
    jumps = np.nonzero(np.abs(np.diff(azimuth)) > 180.0)[0] + 1
    return np.insert(azimuth, jumps, np.nan), np.insert(elevation, jumps, np.nan)


def draw_map(axes, image, title, exposure, marks=()):
    """The map, tone-mapped, with azimuth and elevation on its axes. marks: (direction,
    angular radius in radians, label) of disks to outline."""
    axes.imshow(tone_map(image, exposure), extent=(0, 360, -90, 90), aspect="equal",
                interpolation="nearest")
    for direction, radius, label in marks:
        azimuth, elevation = cap_outline(direction, radius)
        axes.plot(azimuth, elevation, color="tab:red", linewidth=1)
        u, v = direction_to_uv(direction)
        axes.annotate(label, (np.nanmax(azimuth), 90.0 - 180.0 * v), xytext=(4, 0),
                      textcoords="offset points", ha="left", va="center",
                      color="tab:red", fontsize=8.5)  # to the right of the disk
    axes.set_xticks(range(0, 361, 45))
    axes.set_yticks(range(-90, 91, 30))
    axes.set_xlabel("azimuth φ = 360° u  (0: -z, 90: +x, 180: +z, 270: -x)")
    axes.set_ylabel("elevation = 90° - 180° v")
    axes.set_title(title, fontsize=10)


def draw_profile(axes, image, sun_azimuth):
    """Luminance along the great circle through the sun and the zenith: elevation from
    the ground under the sun up over the zenith and down the opposite side."""
    height, width = image.shape[:2]
    elevation = 90.0 - 180.0 * (np.arange(height) + 0.5) / height
    sun_column = int(sun_azimuth / 360.0 * width) % width
    opposite_column = (sun_column + width // 2) % width
    lum = luminance(image)
    axes.semilogy(elevation, lum[:, sun_column], color="tab:orange",
                  label=f"towards the sun (azimuth {sun_azimuth:g}°)")
    axes.semilogy(180.0 - elevation, lum[:, opposite_column], color="tab:blue",
                  label="away from the sun (over the zenith)")
    axes.axvline(90.0, color="0.5", linewidth=0.8)
    axes.axvline(0.0, color="0.5", linewidth=0.8, linestyle=":")
    axes.axvline(180.0, color="0.5", linewidth=0.8, linestyle=":")
    axes.text(91, lum.min() * 1.5, "zenith", fontsize=8, color="0.4")
    axes.text(1, lum.min() * 1.5, "horizon", fontsize=8, color="0.4")
    axes.set_xlim(-90, 270)
    axes.set_xticks(range(-90, 271, 45))
    axes.set_xlabel("angle along the circle (elevation on the sun's side; past 90° the "
                    "far side)")
    axes.set_ylabel("luminance of the pixel (kcd/m²)")
    axes.grid(True, which="both", alpha=0.3)
    axes.legend(fontsize=9)


def save_figure(path, image, title, exposure, marks=(), sun_azimuth=None):
    """The map (and, for the sky, a luminance profile), written atomically."""
    import matplotlib
    matplotlib.use("Agg")  # no window: we only write a file
    import matplotlib.pyplot as plt

    rows = 1 if sun_azimuth is None else 2
    figure = plt.figure(figsize=(9, 4.6 if rows == 1 else 8.2), dpi=100)
    draw_map(figure.add_subplot(rows, 1, 1), image, title, exposure, marks)
    if sun_azimuth is not None:
        draw_profile(figure.add_subplot(rows, 1, 2), image, sun_azimuth)
    save_figure_file(figure, path)


# ---------------------------------------------------------------------------------------
# Command line
# ---------------------------------------------------------------------------------------

def parse_args(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--out", required=True, help="write the map here (PFM)")
    parser.add_argument("--spots", action="store_true",
                        help="write the small test map with three bright spots instead")
    parser.add_argument("--width", type=int, default=None,
                        help="map width in pixels, height = width / 2 (default 512, "
                             "64 with --spots)")
    parser.add_argument("--sun-elevation", type=float, default=30.0, help="degrees")
    parser.add_argument("--sun-azimuth", type=float, default=120.0,
                        help="degrees from -z towards +x: the sun shows at u = azimuth/360")
    parser.add_argument("--turbidity", type=float, default=3.0,
                        help="2 very clear, 3 clear, 6 hazy (default 3)")
    parser.add_argument("--ground-albedo", type=float, default=DEFAULT_GROUND_ALBEDO,
                        help="albedo of the ground below the horizon (0: black)")
    parser.add_argument("--scale", type=float, default=1.0,
                        help="multiply the map (default 1: luminance in kcd/m²)")
    parser.add_argument("--figure", help="also write a preview (PNG) here")
    return parser.parse_args(argv)


def main(argv=None):
    args = parse_args(argv)
    start = time.perf_counter()
    if args.spots:
        width = args.width or 64
        image = spots_map(width, width // 2) * np.float32(args.scale)
        title = (f"Test map {width} x {width // 2}: background {SPOTS_BACKGROUND[0]:g}, "
                 f"{len(SPOTS)} spots")
        marks = [(s.direction(), math.radians(s.angular_radius),
                  f"r = {s.angular_radius:g}°\nL = {s.radiance}") for s in SPOTS]
        exposure = 4.0 / luminance(image).max()  # the spots in colour, the background dark
        sun_azimuth = None
    else:
        width = args.width or 512
        try:
            image = sky_map(width, args.sun_elevation, args.sun_azimuth, args.turbidity,
                            args.ground_albedo, args.scale)
        except ValueError as error:
            sys.exit(f"sky.py: {error}")
        title = (f"Preetham sky, T = {args.turbidity:g}, sun at elevation "
                 f"{args.sun_elevation:g}°, azimuth {args.sun_azimuth:g}° ({width} x "
                 f"{width // 2}, tone-mapped)")
        sun = elevation_azimuth_to_direction(args.sun_elevation, args.sun_azimuth)
        marks = [(sun, math.radians(3.0), "sun (circle 3°; the disk is 0.27°)")]
        sky_luminance = luminance(image[: image.shape[0] // 2])
        exposure = 0.6 / np.median(sky_luminance)  # the median sky -> 0.6, then Reinhard
        sun_azimuth = args.sun_azimuth
    seconds = time.perf_counter() - start
    write_pfm(args.out, image)
    irradiance = upward_irradiance(image)
    print(f"wrote {args.out}: {image.shape[1]} x {image.shape[0]} in {seconds:.2f} s; "
          f"upward irradiance (RGB) {np.array2string(irradiance, precision=4)}, "
          f"max pixel luminance {luminance(image).max():.4g}")
    if args.figure:
        save_figure(args.figure, image, title, exposure, marks, sun_azimuth)
        print(f"wrote {args.figure}")


if __name__ == "__main__":
    main()
