"""Microfacet materials in numpy: the prototype of the chapter's mirror, conductor and
dielectric, in Mitsuba 3's meanings. The GLSL is checked against these functions, and
they against closed forms, statistics and Mitsuba itself
(tests/python/prototypes/test_microfacet_prototype.py).

Conventions, all Mitsuba's, which the GLSL copies:

* Directions are unit vectors in the local shading frame, the normal along +z, so a
  direction's cos θ is its z. Arrays of directions have shape (..., 3); cosines, pdfs
  and a dielectric's values (...); a conductor's values have a channel axis, (..., 3)
  for RGB eta and k.
* wi points away from the surface towards where the path came from (the camera's
  side); wo is the direction sampled next. Radiance flows from wo to wi.
* `*_eval(wi, wo)` returns f(wi, wo) |cos θo|: the BSDF already times the cosine, as
  Mitsuba's BSDF::eval does. The path tracer multiplies by L and divides by the pdf.
* `*_sample(...)` returns (wo, weight, pdf) with weight = eval / pdf; a failed sample
  (the reflected direction went below the surface, ...) has weight 0 and pdf 0.
* eta = int_ior / ext_ior (1.5 for glass in air) as seen from outside (wi.z > 0); a ray
  from inside (wi.z < 0) sees 1 / eta. For a conductor eta + i k is complex.
* Transmission multiplies radiance by (η_i / η_t)²: the same radiance squeezed into a
  smaller solid angle is brighter (Mitsuba's TransportMode::Radiance).
* Masking-shadowing is Mitsuba 3's separable G1(wi) G1(wo), not the height-correlated
  form, which is here too (ggx_g2) and loses less energy; the tests measure both.
* Visible normals are sampled with Mitsuba's mapping of (u1, u2): the same random
  numbers give Mitsuba's microfacet normal, so the GLSL can be compared sample by sample.
"""

import numpy as np

# Mitsuba's `conductor` with `material none`: eta 0, k 1, a perfect mirror (F = 1).
MIRROR_ETA, MIRROR_K = 0.0, 1.0


# ---------------------------------------------------------------------------------------
# Vectors in the shading frame
# ---------------------------------------------------------------------------------------

def dot(a, b):
    return np.sum(a * b, axis=-1)


def normalize(v):
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def vector(x, y, z):
    """Stacks three arrays of coordinates into one array of vectors."""
    return np.stack(np.broadcast_arrays(x, y, z), axis=-1)


def column(values):
    """(...) -> (..., 1), to scale an array of vectors by an array of numbers."""
    return np.asarray(values)[..., None]


def reflect(wi, m):
    """wi mirrored about the (micro)normal m."""
    return column(2.0 * dot(wi, m)) * m - wi


def refract(wi, m, cos_t, eta_ti):
    """Snell's law about the normal m: the part of wi along the surface shrinks by
    eta_ti = η_i / η_t and changes sign; the part along m becomes cos_t, the signed
    cosine fresnel_dielectric returns (on the far side of the surface from wi)."""
    along_surface = wi - column(dot(wi, m)) * m
    return column(cos_t) * m - column(eta_ti) * along_surface


# ---------------------------------------------------------------------------------------
# Fresnel: the fraction of light a smooth interface reflects
# ---------------------------------------------------------------------------------------

# --8<-- [start:fresnel_dielectric]
def fresnel_dielectric(cos_i, eta):
    """Unpolarised Fresnel reflectance between two dielectrics, as Mitsuba's fresnel().

    cos_i: cosine of the incident direction with the normal; negative from inside.
    eta:   η_inside / η_outside. Returns (F, cos_t, eta_it, eta_ti):
      F       reflectance, 1 under total internal reflection
      cos_t   cosine of the refracted direction, of the opposite sign to cos_i (0 under TIR)
      eta_it  η_t / η_i in the direction of travel (eta from outside, 1/eta from inside)
      eta_ti  its reciprocal, the factor the refracted direction's x and y are scaled by
    """
    cos_i = np.asarray(cos_i, dtype=float)
    from_outside = cos_i >= 0.0
    eta_it = np.where(from_outside, eta, 1.0 / eta)
    eta_ti = 1.0 / eta_it

    # Snell: sin θt = (η_i / η_t) sin θi. Beyond 1 no refracted ray exists.
    sin_t_squared = eta_ti**2 * (1.0 - cos_i**2)
    total_internal_reflection = sin_t_squared >= 1.0
    cos_i_abs = np.abs(cos_i)
    cos_t_abs = np.sqrt(np.maximum(0.0, 1.0 - sin_t_squared))

    # Amplitudes of the two polarisations; unpolarised light reflects their mean power.
    with np.errstate(divide="ignore", invalid="ignore"):  # 0/0 at grazing TIR: F = 1
        r_s = (cos_i_abs - eta_it * cos_t_abs) / (cos_i_abs + eta_it * cos_t_abs)
        r_p = (eta_it * cos_i_abs - cos_t_abs) / (eta_it * cos_i_abs + cos_t_abs)
    F = 0.5 * (r_s**2 + r_p**2)
    F = np.where(total_internal_reflection | (cos_i_abs == 0.0), 1.0, F)
    F = np.where(eta == 1.0, 0.0, F)  # no interface at all: nothing reflects

    cos_t = np.where(from_outside, -cos_t_abs, cos_t_abs)
    return F, cos_t, eta_it, eta_ti
# --8<-- [end:fresnel_dielectric]


# --8<-- [start:fresnel_conductor]
def fresnel_conductor(cos_i, eta, k):
    """Unpolarised Fresnel reflectance of a conductor, complex index n = eta + i k, for
    light arriving from outside (0 <= cos_i <= 1). eta and k are numbers or RGB triples;
    the result has a channel axis: shape cos_i.shape + (1,) or + (3,).

    The dielectric formulas hold with a complex n; n cos θt = sqrt(n² - sin² θi) by
    Snell's law (the principal root: the wave decays into the metal)."""
    n = np.atleast_1d(eta) + 1j * np.atleast_1d(k)
    cos_i = column(np.asarray(cos_i, dtype=float))  # one value per channel
    n_cos_t = np.sqrt(n**2 - (1.0 - cos_i**2))
    r_s = (cos_i - n_cos_t) / (cos_i + n_cos_t)
    r_p = (n**2 * cos_i - n_cos_t) / (n**2 * cos_i + n_cos_t)
    return 0.5 * (np.abs(r_s)**2 + np.abs(r_p)**2)
# --8<-- [end:fresnel_conductor]


# ---------------------------------------------------------------------------------------
# GGX (Trowbridge-Reitz) microfacets, isotropic roughness alpha
# ---------------------------------------------------------------------------------------

# --8<-- [start:ggx]
def ggx_d(m, alpha):
    """Density of microfacet normals m per unit solid angle, normalised so that the
    microfacets' areas projected on the surface add up to its own: ∫ D cos θm dω = 1."""
    x, y, z = m[..., 0], m[..., 1], m[..., 2]
    D = 1.0 / (np.pi * alpha**2 * ((x**2 + y**2) / alpha**2 + z**2)**2)
    return np.where(z > 0.0, D, 0.0)  # every microfacet faces up


def ggx_lambda(v, alpha):
    """Smith's Λ: the microfacet area hidden from direction v, relative to the visible
    area. 0 straight above, infinite at the horizon."""
    tan_squared = (v[..., 0]**2 + v[..., 1]**2) / v[..., 2]**2
    return 0.5 * (np.sqrt(1.0 + alpha**2 * tan_squared) - 1.0)


def facing(v, m):
    """Whether v can see microfacet m: v·m must have the sign of cos θv. From above, v
    sees the microfacets' fronts; from inside a dielectric, their backs, as it sees the
    surface's back. A microfacet turned away from v is hidden from it."""
    return dot(v, m) * v[..., 2] > 0.0


def ggx_g1(v, m, alpha):
    """Smith masking: the fraction of microfacets with normal m that v sees."""
    with np.errstate(divide="ignore"):  # v at the horizon: Λ = ∞, G1 = 0
        G1 = 1.0 / (1.0 + ggx_lambda(v, alpha))
    return np.where(facing(v, m), G1, 0.0)


def ggx_g2(wi, wo, m, alpha):
    """Height-correlated masking-shadowing (for reflection): a microfacet seen from wi
    is more likely lit from wo when both see it, because both favour high microfacets."""
    with np.errstate(divide="ignore"):
        G2 = 1.0 / (1.0 + ggx_lambda(wi, alpha) + ggx_lambda(wo, alpha))
    return np.where(facing(wi, m) & facing(wo, m), G2, 0.0)


def ggx_g2_separable(wi, wo, m, alpha):
    """Masking and shadowing as independent events: Mitsuba 3's choice, and the BSDFs'."""
    return ggx_g1(wi, m, alpha) * ggx_g1(wo, m, alpha)
# --8<-- [end:ggx]


# ---------------------------------------------------------------------------------------
# Sampling the visible normals (Heitz 2018, JCGT 7(4))
# ---------------------------------------------------------------------------------------

def square_to_disk_concentric(u1, u2):
    """Shirley and Chiu's area-preserving map of the unit square onto the unit disk, as
    Mitsuba's warp: the same (u1, u2) gives Mitsuba's direction, sample for sample."""
    x, y = 2.0 * np.asarray(u1) - 1.0, 2.0 * np.asarray(u2) - 1.0
    radius_is_x = np.abs(x) >= np.abs(y)  # squares' rings onto the disk's circles
    r = np.where(radius_is_x, x, y)
    with np.errstate(divide="ignore", invalid="ignore"):
        phi = np.where(radius_is_x, (np.pi / 4) * (y / x),
                       np.pi / 2 - (np.pi / 4) * (x / y))
    phi = np.where((x == 0.0) & (y == 0.0), 0.0, phi)
    return r * np.cos(phi), r * np.sin(phi)


# --8<-- [start:visible_normals]
def sample_visible_normal(wi, alpha, u1, u2):
    """A microfacet normal m drawn with the density of the normals wi sees (wi.z > 0):
    visible_normal_pdf(wi, m, alpha)."""
    # GGX of roughness alpha is the distribution of the normals of an ellipsoid with
    # radii (1/alpha, 1/alpha, 1). Stretching it into a sphere turns wi into wi_h, and
    # the visible normals of a hemisphere are simple: they are its points, uniformly
    # distributed in the area they project to along wi_h.
    wi_h = normalize(vector(alpha * wi[..., 0], alpha * wi[..., 1], wi[..., 2]))

    # A frame around wi_h: t1 = wi_h × z across the plane of incidence, t2 in it.
    # Straight above there is no plane of incidence; any t1 would do, Mitsuba's is -y.
    across = vector(wi_h[..., 1], -wi_h[..., 0], 0.0)
    length = np.hypot(wi_h[..., 0], wi_h[..., 1])
    with np.errstate(divide="ignore", invalid="ignore"):
        t1 = np.where(column(length > 0.0), across / column(length), [0.0, -1.0, 0.0])
    t2 = np.cross(t1, wi_h)

    # Seen from wi_h, the hemisphere projects to half a disk and half an ellipse of
    # height cos θ. Each chord of the unit disk across t2, from -√(1-x²) to √(1-x²),
    # is squeezed linearly onto the chord of that shape, from -cos θ √(1-x²) to √(1-x²):
    # every chord shrinks by the same factor s, so uniform points stay uniform.
    x, y = square_to_disk_concentric(u1, u2)
    s = 0.5 * (1.0 + wi_h[..., 2])
    y = (1.0 - s) * np.sqrt(1.0 - x**2) + s * y

    # Lift the point along wi_h onto the hemisphere: that point is the normal there.
    height = np.sqrt(np.maximum(0.0, 1.0 - x**2 - y**2))
    n_h = column(x) * t1 + column(y) * t2 + column(height) * wi_h

    # Back to the ellipsoid: normals transform with the inverse transpose of the
    # stretch, which scales x and y by alpha.
    return normalize(vector(alpha * n_h[..., 0], alpha * n_h[..., 1],
                            np.maximum(0.0, n_h[..., 2])))


def visible_normal_pdf(wi, m, alpha):
    """Density (per solid angle of m) of sample_visible_normal: the microfacets with
    normal m that wi sees, weighted by the area they show it, over the surface's own:
    G1(wi, m) max(0, wi·m) D(m) / cos θi."""
    return ggx_g1(wi, m, alpha) * np.maximum(0.0, dot(wi, m)) * ggx_d(m, alpha) / wi[..., 2]
# --8<-- [end:visible_normals]


# --8<-- [start:jacobians]
def reflection_jacobian(wo, m):
    """dω_m / dω_o for wo = reflect(wi, m) (Walter et al. 2007, eq. 14). m is wi + wo
    normalised, and |wi + wo| = 2 |wo·m|: the patch dω_o around the tip of wi + wo,
    seen along m (times |wo·m|) from the distance |wi + wo| (over its square), covers
    dω_m = dω_o |wo·m| / (2 wo·m)² = dω_o / (4 |wo·m|)."""
    return 1.0 / (4.0 * np.abs(dot(wo, m)))


def transmission_jacobian(wi, wo, m, eta_it):
    """dω_m / dω_o for wo = refract(wi, m) (Walter et al. 2007, eq. 17): the same
    construction with m along wi + η wo, so the patch is η² dω_o."""
    return eta_it**2 * np.abs(dot(wo, m)) / (dot(wi, m) + eta_it * dot(wo, m))**2
# --8<-- [end:jacobians]


# ---------------------------------------------------------------------------------------
# Smooth materials: one direction each (a delta), so only sampling makes sense
# ---------------------------------------------------------------------------------------

def smooth_conductor_sample(wi, eta, k):
    """Mirror reflection (Mitsuba's `conductor`); wi.z > 0. Returns (wo, weight): the
    weight is F per channel (1 for MIRROR_ETA, MIRROR_K)."""
    wo = vector(-wi[..., 0], -wi[..., 1], wi[..., 2])
    weight = fresnel_conductor(wi[..., 2], eta, k)
    return wo, np.where(column(wi[..., 2] > 0.0), weight, 0.0)


# --8<-- [start:smooth_dielectric]
def smooth_dielectric_sample(wi, eta, u):
    """Mitsuba's `dielectric`: reflect with probability F (u <= F), else refract.
    Reflection's weight F / F is 1; refraction's is (1 - F) / (1 - F) times the
    radiance scale eta_ti². Returns (wo, weight)."""
    F, cos_t, eta_it, eta_ti = fresnel_dielectric(wi[..., 2], eta)
    chose_reflection = np.asarray(u) <= F
    reflected = vector(-wi[..., 0], -wi[..., 1], wi[..., 2])
    refracted = vector(-eta_ti * wi[..., 0], -eta_ti * wi[..., 1], cos_t)
    wo = np.where(column(chose_reflection), reflected, refracted)
    weight = np.where(chose_reflection, 1.0, eta_ti**2)
    return wo, weight
# --8<-- [end:smooth_dielectric]


# ---------------------------------------------------------------------------------------
# Rough conductor (Mitsuba's `roughconductor`, GGX, sample_visible true)
# ---------------------------------------------------------------------------------------

# --8<-- [start:rough_conductor]
def rough_conductor_eval(wi, wo, alpha, eta, k, g2=ggx_g2_separable):
    """f(wi, wo) cos θo = F D G2 / (4 cos θi), per channel. Both above the surface."""
    m = normalize(wi + wo)  # the only microfacet normal that reflects wi into wo
    F = fresnel_conductor(dot(wi, m), eta, k)
    with np.errstate(divide="ignore", invalid="ignore"):
        value = ggx_d(m, alpha) * g2(wi, wo, m, alpha) / (4.0 * wi[..., 2])
    above = (wi[..., 2] > 0.0) & (wo[..., 2] > 0.0)
    return np.where(column(above), F * column(value), 0.0)


def rough_conductor_pdf(wi, wo, alpha):
    """Density of rough_conductor_sample's wo: the visible normal's density times the
    Jacobian of the reflection."""
    m = normalize(wi + wo)
    with np.errstate(divide="ignore", invalid="ignore"):
        pdf = visible_normal_pdf(wi, m, alpha) * reflection_jacobian(wo, m)
    valid = (wi[..., 2] > 0.0) & (wo[..., 2] > 0.0) & (dot(wo, m) > 0.0)
    return np.where(valid, pdf, 0.0)


def rough_conductor_sample(wi, alpha, eta, k, u1, u2, g2=ggx_g2_separable):
    """Draws a visible normal m and reflects wi about it. Returns (wo, weight, pdf):
    eval / pdf = F G2 / G1(wi), which is F G1(wo) for separable masking."""
    m = sample_visible_normal(wi, alpha, u1, u2)
    wo = reflect(wi, m)
    with np.errstate(divide="ignore", invalid="ignore"):
        pdf = visible_normal_pdf(wi, m, alpha) * reflection_jacobian(wo, m)
        shadowing = g2(wi, wo, m, alpha) / ggx_g1(wi, m, alpha)
    valid = (wi[..., 2] > 0.0) & (wo[..., 2] > 0.0) & (pdf > 0.0)
    weight = fresnel_conductor(dot(wi, m), eta, k) * column(shadowing)
    return wo, np.where(column(valid), weight, 0.0), np.where(valid, pdf, 0.0)
# --8<-- [end:rough_conductor]


# ---------------------------------------------------------------------------------------
# Rough dielectric (Mitsuba's `roughdielectric`: Walter et al. 2007, VNDF sampling)
# ---------------------------------------------------------------------------------------

# --8<-- [start:rough_dielectric]
def eta_beyond(wi, eta):
    """η on the far side of the surface over η on wi's side: eta from outside, 1/eta
    from inside."""
    return np.where(wi[..., 2] > 0.0, eta, 1.0 / eta)


def generalized_half_vector(wi, wo, eta):
    """The microfacet normal that scatters wi into wo, turned to face up: wi + wo for a
    reflection, wi + η wo for a refraction (η = η_o / η_i, Walter et al. eq. 16)."""
    is_reflection = wi[..., 2] * wo[..., 2] > 0.0
    scale = np.where(is_reflection, 1.0, eta_beyond(wi, eta))
    m = normalize(wi + column(scale) * wo)
    return np.where(column(m[..., 2] < 0.0), -m, m), is_reflection


def rough_dielectric_eval(wi, wo, alpha, eta, g2=ggx_g2_separable):
    """f(wi, wo) |cos θo| of a rough interface, wi and wo on either side."""
    m, is_reflection = generalized_half_vector(wi, wo, eta)
    eta_io = eta_beyond(wi, eta)
    F = fresnel_dielectric(dot(wi, m), eta)[0]
    D_G = ggx_d(m, alpha) * g2(wi, wo, m, alpha)
    cos_i = wi[..., 2]
    with np.errstate(divide="ignore", invalid="ignore"):
        reflection = F * D_G / (4.0 * np.abs(cos_i))
        # Walter's BTDF (its η_o² and denominator are the transmission Jacobian) times
        # the radiance scale 1/η_io²; the two cancel, but each has its reason.
        radiance_scale = 1.0 / eta_io**2
        transmission = np.abs(radiance_scale * (1.0 - F) * D_G * eta_io**2
                              * dot(wi, m) * dot(wo, m)
                              / (cos_i * (dot(wi, m) + eta_io * dot(wo, m))**2))
    value = np.where(is_reflection, reflection, transmission)
    return np.where((cos_i != 0.0) & (D_G > 0.0), value, 0.0)


def rough_dielectric_pdf(wi, wo, alpha, eta):
    """Density of rough_dielectric_sample's wo over the whole sphere."""
    m, is_reflection = generalized_half_vector(wi, wo, eta)
    eta_io = eta_beyond(wi, eta)
    F = fresnel_dielectric(dot(wi, m), eta)[0]
    wi_above = wi * column(np.where(wi[..., 2] < 0.0, -1.0, 1.0))  # sampled from above
    with np.errstate(divide="ignore", invalid="ignore"):
        jacobian = np.where(is_reflection, reflection_jacobian(wo, m),
                            transmission_jacobian(wi, wo, m, eta_io))
        lobe_probability = np.where(is_reflection, F, 1.0 - F)
        pdf = visible_normal_pdf(wi_above, m, alpha) * lobe_probability * jacobian
    valid = facing(wi, m) & facing(wo, m) & (wi[..., 2] != 0.0)
    return np.where(valid, pdf, 0.0)


def rough_dielectric_sample(wi, alpha, eta, u, u1, u2, g2=ggx_g2_separable):
    """Draws a normal m that wi sees, then reflects about it with probability F (u <= F)
    or refracts. Returns (wo, weight, pdf); weight = G2 / G1(wi), times eta_ti² for a
    refraction (F and 1 - F cancel with the lobe's probability)."""
    # From inside, wi sees the same microfacets upside down: sample them for wi's mirror
    # image above the surface.
    wi_above = wi * column(np.where(wi[..., 2] < 0.0, -1.0, 1.0))
    m = sample_visible_normal(wi_above, alpha, u1, u2)
    F, cos_t, eta_it, eta_ti = fresnel_dielectric(dot(wi, m), eta)
    chose_reflection = np.asarray(u) <= F

    wo = np.where(column(chose_reflection), reflect(wi, m), refract(wi, m, cos_t, eta_ti))
    with np.errstate(divide="ignore", invalid="ignore"):
        jacobian = np.where(chose_reflection, reflection_jacobian(wo, m),
                            transmission_jacobian(wi, wo, m, eta_it))
        pdf = (visible_normal_pdf(wi_above, m, alpha)
               * np.where(chose_reflection, F, 1.0 - F) * jacobian)
        weight = (g2(wi, wo, m, alpha) / ggx_g1(wi, m, alpha)
                  * np.where(chose_reflection, 1.0, eta_ti**2))

    # A reflection must stay on wi's side of the surface, a refraction cross it.
    on_correct_side = np.where(chose_reflection, wi[..., 2] * wo[..., 2] > 0.0,
                               wi[..., 2] * wo[..., 2] < 0.0)
    valid = on_correct_side & (wi[..., 2] != 0.0) & (pdf > 0.0)
    return wo, np.where(valid, weight, 0.0), np.where(valid, pdf, 0.0)
# --8<-- [end:rough_dielectric]


# ---------------------------------------------------------------------------------------
# The white furnace: how much light does a perfect reflector (F = 1) keep?
# ---------------------------------------------------------------------------------------

def furnace_albedo(theta_i_degrees, alpha, count=400_000, seed=0, g2=ggx_g2_separable):
    """∫ f cos θo dωo for F = 1 at incidence θi, estimated as the mean sample weight.
    Single scattering: light that would hit a second microfacet is lost (the rougher
    the surface, the more), and so is light reflected below the surface by GGX's long
    tail of steep microfacets."""
    rng = np.random.default_rng(seed)
    theta = np.radians(theta_i_degrees)
    wi = np.tile([np.sin(theta), 0.0, np.cos(theta)], (count, 1))
    _, weight, _ = rough_conductor_sample(wi, alpha, MIRROR_ETA, MIRROR_K,
                                          rng.random(count), rng.random(count), g2=g2)
    return weight.mean(), weight.std(ddof=1) / np.sqrt(count)


if __name__ == "__main__":
    print("white furnace albedo (F = 1), separable / height-correlated masking")
    for alpha in (0.05, 0.1, 0.3, 0.5, 0.8, 1.0):
        row = [f"{furnace_albedo(theta, alpha)[0]:.4f}/"
               f"{furnace_albedo(theta, alpha, g2=ggx_g2)[0]:.4f}"
               for theta in (0, 45, 75, 85)]
        print(f"alpha {alpha:4}, θi 0 45 75 85°: " + "  ".join(row))
