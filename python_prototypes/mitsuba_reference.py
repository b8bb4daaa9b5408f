"""Chapter 11's yardstick: the same scene rendered by Mitsuba 3, and the image split into
regions (each wall, each sphere, the light) so that any two renderers can be compared
region by region.

The Mitsuba scene is built from our own scene file (scene_io.py), never from numbers
copied here, so the two renderers cannot drift apart:

    quad        -> Mitsuba `rectangle`; to_world maps its [-1, 1]^2 square onto the quad:
                   columns edge1 / 2, edge2 / 2, the unit normal, the quad's centre
    sphere      -> `sphere` (center, radius)
    triangle    -> the triangles of one material, written to a small OBJ file
    mesh        -> `obj` with to_world = worldFromMesh (scale, rotate_y, translate)
                   and flip_tex_coords false: Mitsuba's uv is then the file's vt
    material    -> `diffuse` with the albedo as RGB reflectance; an emitting material
                   also gets an `area` emitter with its radiance (front side only, as
                   in our format). The other kinds: mitsuba_bsdf()
    albedo texture T -> `diffuse` with T as its reflectance:
      image     -> `bitmap`, filter_type bilinear, wrap_mode repeat, raw when `linear`,
                   and to_uv (u, v) -> (u, 1 - v): Mitsuba's bitmap puts v = 0 on the
                   image's top row, ours (and OBJ's) on its bottom row
      checker   -> `checkerboard`, color0 / color1, to_uv a scale by S
                   With these, Mitsuba's uv is textures.py's everywhere: a rectangle's
                   is (a, b) along edge1 and edge2 as ours, and an OBJ's is its vt.
                   (Mitsuba's default flip_tex_coords would turn its checkerboard
                   upside down on meshes only.)
    camera      -> `perspective` with fov_axis "x" and fov = 2 atan(sensor / 2 focal):
                   our sensor width is horizontal whatever the image's shape, so the
                   horizontal field of view is what matches. (mitsuba.cornell_box()
                   uses fov_axis "smaller", the same thing for square images only.)
                   With a lens of radius > 0: `thinlens` (thin_lens.py's
                   mitsuba_thinlens_dict), aperture_radius = the lens radius,
                   focus_distance = focus. The regions below stay the pinhole's.
    film        -> `hdrfilm` with a box filter: each sample counts for the pixel it
                   falls in, as our jittered samples do (Mitsuba's default is Gaussian)
    environment -> `envmap` with the PFM's filename, scale S, and to_world a turn about
                   [0, 1, 0] by +DEGREES: Mitsuba looks d up at to_world⁻¹ d, our
                   mapFromWorld, in the same lat-long frame (sky.py), so a spot the
                   file shows along +x is seen along -z at 90 in both. Mitsuba reads
                   the map bilinearly with its first and last rows on the poles, we by
                   nearest pixel: the same file differs in detail, not in orientation
                   (sky.py's docstring measures the difference)

Path depth: our --depth N counts the surfaces a path may bounce off (N = 1 is direct
lighting only, what --direct renders). Mitsuba's max_depth counts path segments, so
that max_depth 1 shows only the emitters and 2 is direct lighting: max_depth = N + 1.
Mitsuba starts Russian roulette at depth 5 (rr_depth), which changes the noise but not
the expected image.

Mitsuba's `diffuse` reflects from its front side only; every surface in the Cornell
scenes is seen from its front, except the top of the light quad, 1 cm under the ceiling.

Regions: a primary-ray ID render of our scene in numpy (camera_rays.py's convention,
4 x 4 rays spread over each pixel), each shape's ID mapped to its name in the scene
file (shapes sharing a name share a region). A pixel counts for a region only if all
its rays see that region, and the masks are eroded by a pixel more, so that edge
pixels, whose samples mix two regions, do not count.

    python python_prototypes/mitsuba_reference.py --scene assets/scenes/cornell_spheres.scene \\
        --width 256 --height 256 --spp 256 --depth 6 --out reference.pfm --json stats.json
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from python_prototypes import camera_rays
from python_prototypes import obj_io
from python_prototypes import scene_io
from python_prototypes.scene_cast import sphere_t

VARIANTS = ("scalar_rgb", "llvm_ad_rgb")
# Debian bookworm's LLVM (apt-get install libllvm19); Dr.Jit's llvm_* variants need it
# (bookworm's default libLLVM-15, which Mesa uses, fails to compile Mitsuba's kernels).
DEFAULT_LIBLLVM = "/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1"
MISS = -1  # the ID of a pixel whose ray leaves the scene
MIXED = -2  # the ID of a pixel that sees more than one shape (primary_ids' subsamples)


# ---------------------------------------------------------------------------------------
# Mitsuba
# ---------------------------------------------------------------------------------------

def import_mitsuba(variant: str):
    """Imports mitsuba and selects the variant; for llvm_* points Dr.Jit at LLVM 19."""
    if variant.startswith("llvm") and "DRJIT_LIBLLVM_PATH" not in os.environ \
            and Path(DEFAULT_LIBLLVM).exists():
        os.environ["DRJIT_LIBLLVM_PATH"] = DEFAULT_LIBLLVM
    import mitsuba as mi
    mi.set_variant(variant)
    return mi


def mitsuba_max_depth(bounces: int) -> int:
    """Our depth (surface bounces) as Mitsuba's max_depth (path segments)."""
    return bounces + 1


def quad_to_world(quad: scene_io.Quad) -> np.ndarray:
    """The 4x4 matrix taking Mitsuba's rectangle ([-1, 1]^2 at z = 0, normal +z) to the quad."""
    origin, edge1, edge2 = (np.asarray(v, dtype=np.float64)
                            for v in (quad.origin, quad.edge1, quad.edge2))
    matrix = np.eye(4)
    matrix[:3, 0] = edge1 / 2
    matrix[:3, 1] = edge2 / 2
    matrix[:3, 2] = quad.normal()
    matrix[:3, 3] = origin + (edge1 + edge2) / 2
    return matrix


def write_triangles_obj(path: Path, triangles) -> None:
    lines = []
    for n, triangle in enumerate(triangles):
        for point in (triangle.p0, triangle.p1, triangle.p2):
            lines.append("v {:.9g} {:.9g} {:.9g}".format(*point))
        lines.append(f"f {3 * n + 1} {3 * n + 2} {3 * n + 3}")
    path.write_text("\n".join(lines) + "\n")


def rgb(values) -> dict:
    return {"type": "rgb", "value": list(values)}


def mitsuba_texture(texture: scene_io.Texture) -> dict:
    """A scene texture in Mitsuba 3's words, looked up as textures.py does (Mitsuba
    must be imported, a variant set: to_uv is one of its transforms)."""
    import mitsuba as mi
    if texture.kind == "checker":
        return {"type": "checkerboard", "color0": rgb(texture.color0),
                "color1": rgb(texture.color1),
                "to_uv": mi.ScalarAffineTransform3f().scale([texture.scale] * 2)}
    # Mitsuba's bitmap has v = 0 at the top row; ours at the bottom: v -> 1 - v.
    flip_v = mi.ScalarAffineTransform3f(mi.ScalarMatrix3f([[1, 0, 0], [0, -1, 1],
                                                           [0, 0, 1]]))
    return {"type": "bitmap", "filename": str(texture.path), "filter_type": "bilinear",
            "wrap_mode": "repeat", "raw": texture.linear, "to_uv": flip_v}


def mitsuba_bsdf(material: scene_io.Material, textures: dict | None = None) -> dict:
    """The scene format's materials in Mitsuba 3's words (common/course/scene_file.h):
    albedo -> diffuse (its reflectance the texture of `textures`, the scene's, if it
    names one); mirror -> conductor, material none, specular_reflectance;
    conductor -> conductor or roughconductor (GGX, visible normals) with eta and k;
    dielectric -> dielectric or roughdielectric, int_ior N, ext_ior 1."""
    if material.kind == "albedo" and material.texture is not None:
        return {"type": "diffuse", "reflectance": mitsuba_texture(textures[material.texture])}
    if material.kind == "albedo":
        return {"type": "diffuse", "reflectance": rgb(material.albedo)}
    if material.kind == "mirror":
        return {"type": "conductor", "material": "none",
                "specular_reflectance": rgb(material.reflectance)}
    if material.kind == "boundary":
        return {"type": "null"}
    rough = {"distribution": "ggx", "alpha": material.roughness, "sample_visible": True}
    if material.kind == "conductor":
        bsdf = {"eta": rgb(material.eta), "k": rgb(material.k)}
        return {"type": "roughconductor", **rough, **bsdf} if material.roughness > 0 \
            else {"type": "conductor", **bsdf}
    bsdf = {"int_ior": material.ior, "ext_ior": 1.0}
    return {"type": "roughdielectric", **rough, **bsdf} if material.roughness > 0 \
        else {"type": "dielectric", **bsdf}


def mitsuba_medium(medium: scene_io.Medium) -> dict:
    """A medium in Mitsuba 3's words, with an `hg` phase. Homogeneous: sigma_t = sigma_a
    + sigma_s and the albedo sigma_s / sigma_t (any value where sigma_t is 0). A grid:
    `heterogeneous`, its sigma_t the same .vol file over the box the file gives
    (use_grid_bbox) times the scale, its albedo constant."""
    if medium.kind == "grid":
        return {"type": "heterogeneous",
                "sigma_t": {"type": "gridvolume", "filename": str(medium.path),
                            "use_grid_bbox": True},
                "albedo": {"type": "constvolume", "value": rgb(list(medium.albedo))},
                "scale": medium.scale, "phase": {"type": "hg", "g": medium.g}}
    sigma_t = np.add(medium.sigma_a, medium.sigma_s)
    albedo = np.divide(medium.sigma_s, sigma_t, out=np.zeros(3), where=sigma_t > 0)
    # Mitsuba reads an RGB value as a reflectance, in [0, 1]: sigma_t goes in as its
    # largest channel (`scale`) times a colour.
    scale = float(sigma_t.max()) or 1.0
    return {"type": "homogeneous", "sigma_t": rgb((sigma_t / scale).tolist()),
            "albedo": rgb(albedo.tolist()), "scale": scale,
            "phase": {"type": "hg", "g": medium.g}}


def mitsuba_envmap(mi, environment: scene_io.Environment) -> dict:
    """The scene's environment as Mitsuba 3's envmap: the same file, scale and turn."""
    return {"type": "envmap", "filename": str(environment.path),
            "scale": environment.scale,
            "to_world": mi.ScalarTransform4f().rotate([0, 1, 0],
                                                      environment.rotate_y_degrees)}


def mitsuba_scene_dict(mi, scene: scene_io.Scene, width: int, height: int, bounces: int,
                       spp: int = 16, work_folder: Path | None = None) -> dict:
    """A Mitsuba scene dictionary for our scene. Triangles are written as OBJ files into
    work_folder (needed only when the scene has `triangle` lines). Mitsuba 3 draws
    stills: a scene whose instances move is drawn at an instant (Scene.at_instant), and
    a blurred picture is the mean of stills over the shutter."""
    if scene.moves():
        raise ValueError(f"{scene.path}: instances move; Mitsuba draws a still: "
                         "scene.at_instant(s)")
    T = mi.ScalarTransform4f
    camera = scene.camera
    eye = np.asarray(camera.eye, dtype=np.float64)
    sensor = {
        "type": "perspective",
        "fov_axis": "x",
        "fov": camera.horizontal_fov_degrees(),
        "to_world": T().look_at(origin=eye.tolist(),
                                target=(eye + np.asarray(camera.look)).tolist(),
                                up=list(camera.up)),
    }
    if camera.lens_radius > 0:
        from python_prototypes import thin_lens
        sensor = thin_lens.mitsuba_thinlens_dict(camera.as_thin_lens_camera(), width,
                                                 height, spp)
    sensor.update({
        "near_clip": 1e-3,
        "far_clip": 1e4,
        "sampler": {"type": "independent", "sample_count": spp},
        "film": {"type": "hdrfilm", "width": width, "height": height,
                 "rfilter": {"type": "box"}, "pixel_format": "rgb",
                 "component_format": "float32"},
    })
    # Media need the volumetric path tracer; its depth counts as `path`'s does, with a
    # medium's scattering a bounce and a null (boundary) surface none.
    integrator = "volpath" if scene.media else "path"
    result = {
        "type": "scene",
        "integrator": {"type": integrator, "max_depth": mitsuba_max_depth(bounces)},
        "sensor": sensor,
    }
    for name, medium in scene.media.items():
        result[f"medium_{name}"] = mitsuba_medium(medium)
    if scene.camera.medium is not None:
        sensor["medium"] = {"type": "ref", "id": f"medium_{scene.camera.medium}"}
    for name, material in scene.materials.items():
        result[f"material_{name}"] = mitsuba_bsdf(material, scene.textures)

    def surface(shape_dict, material_name, interior=None):
        shape_dict["bsdf"] = {"type": "ref", "id": f"material_{material_name}"}
        material = scene.materials[material_name]
        # A surface light passes through has its interior behind it and the camera's
        # medium in front (common/course/scene_file.h); opaque ones change no medium.
        if material.kind in ("boundary", "dielectric"):
            if interior is not None:
                shape_dict["interior"] = {"type": "ref", "id": f"medium_{interior}"}
            if scene.camera.medium is not None:
                shape_dict["exterior"] = {"type": "ref", "id": f"medium_{scene.camera.medium}"}
        if material.emits:
            shape_dict["emitter"] = {"type": "area",
                                     "radiance": {"type": "rgb",
                                                  "value": list(material.emission)}}
        return shape_dict

    def add_shapes(into: dict, holder, prefix: str = ""):
        """The spheres, quads, meshes and lone triangles of the scene or of an object."""
        for index, quad in enumerate(holder.quads):
            into[f"{prefix}quad_{index}"] = surface(
                {"type": "rectangle", "to_world": T(quad_to_world(quad))}, quad.material)
        for index, sphere in enumerate(holder.spheres):
            into[f"{prefix}sphere_{index}"] = surface(
                {"type": "sphere", "center": list(sphere.center), "radius": sphere.radius},
                sphere.material, sphere.interior)
        for index, mesh in enumerate(holder.meshes):
            into[f"{prefix}mesh_{index}"] = surface(
                {"type": "obj", "filename": str(mesh.path), "flip_tex_coords": False,
                 "to_world": T(mesh.world_from_mesh())}, mesh.material, mesh.interior)
        if holder.triangles:
            if work_folder is None:
                raise ValueError("the scene has triangles: pass a work_folder for their OBJ "
                                 "files")
            for material in sorted({t.material for t in holder.triangles}):
                path = Path(work_folder) / f"{prefix}triangles_{material}.obj"
                write_triangles_obj(path, [t for t in holder.triangles
                                           if t.material == material])
                into[f"{prefix}triangles_{material}"] = surface(
                    {"type": "obj", "filename": str(path), "face_normals": True}, material)

    add_shapes(result, scene)
    if scene.environment is not None:
        result["environment"] = mitsuba_envmap(mi, scene.environment)
    # Objects are Mitsuba's shape groups, drawn only through its instances, whose
    # to_world is the placement (each step multiplying from the left, as ours).
    for name, scene_object in scene.objects.items():
        group = {"type": "shapegroup"}
        add_shapes(group, scene_object, prefix=f"{name}_")
        result[f"object_{name}"] = group
    for index, instance in enumerate(scene.instances):
        result[f"instance_{index}"] = {
            "type": "instance", "shapegroup": {"type": "ref", "id": f"object_{instance.object}"},
            "to_world": T(instance.world_from_object())}
    return result


def render_mitsuba(scene: scene_io.Scene, width: int, height: int, spp: int, bounces: int,
                   seed: int = 0, variant: str = "scalar_rgb"):
    """Renders with Mitsuba's path tracer: (linear RGB float32 (height, width, 3), stats).
    Row 0 is the top of the image. stats["seconds"] times mitsuba.render() alone."""
    mi = import_mitsuba(variant)
    with tempfile.TemporaryDirectory() as work_folder:
        loaded = mi.load_dict(mitsuba_scene_dict(mi, scene, width, height, bounces, spp,
                                                 Path(work_folder)))
        start = time.perf_counter()
        image = np.array(mi.render(loaded, spp=spp, seed=seed), dtype=np.float32)
        seconds = time.perf_counter() - start
    samples = width * height * spp
    return image[:, :, :3], {
        "renderer": f"mitsuba {mi.__version__} {variant}", "variant": variant,
        "width": width, "height": height, "spp": spp, "seed": seed,
        "depth": bounces, "mitsuba_max_depth": mitsuba_max_depth(bounces),
        "seconds": seconds, "samples_per_second": samples / seconds,
        "threads": os.cpu_count()}


# ---------------------------------------------------------------------------------------
# Files
# ---------------------------------------------------------------------------------------

from python_prototypes.pfm import read_pfm, write_pfm  # noqa: F401  (others read PFMs through here)


# ---------------------------------------------------------------------------------------
# Regions: which shape each pixel centre sees
# ---------------------------------------------------------------------------------------

def quad_distances(origin, directions, quad):
    """Distance along each ray to the quad (either side), inf where it misses."""
    o, e1, e2 = (np.asarray(v, dtype=np.float64) for v in (quad.origin, quad.edge1,
                                                          quad.edge2))
    normal = np.cross(e1, e2)
    facing = directions @ normal
    with np.errstate(divide="ignore", invalid="ignore"):  # rays parallel to the quad
        t = ((o - origin) @ normal) / facing
        offset = origin + t[..., np.newaxis] * directions - o
        # Coordinates along e1 and e2 from the dual basis: a = (p-o).(e2 x n) / e1.(e2 x n).
        across1, across2 = np.cross(e2, normal), np.cross(normal, e1)
        a = offset @ across1 / (e1 @ across1)
        b = offset @ across2 / (e2 @ across2)
    hit = (np.abs(facing) > 1e-12) & (t > 1e-9) & (a >= 0) & (a <= 1) & (b >= 0) & (b <= 1)
    return np.where(hit, t, np.inf)


def rays_into_box(origin, directions, low, high) -> np.ndarray:
    """Which rays (from one origin) meet the box [low, high] ahead of it: the slab test,
    a little widened so that no ray grazing a face is lost."""
    pad = 1e-6 * (1.0 + np.abs(high - low).max())
    with np.errstate(divide="ignore", invalid="ignore"):
        t0 = (low - pad - origin) / directions
        t1 = (high + pad - origin) / directions
    t0, t1 = np.nan_to_num(t0, nan=-np.inf), np.nan_to_num(t1, nan=np.inf)
    near = np.minimum(t0, t1).max(axis=-1)
    far = np.maximum(t0, t1).min(axis=-1)
    return (near <= far) & (far > 0)


def triangle_distances(origin, directions, corners):
    """Nearest distance to any of the triangles (T, 3, 3), either side; inf where none.
    Only the rays that meet the triangles' bounding box are tested (a mesh covers a part
    of the picture: the region masks of a 6 320-triangle teapot at 256² take seconds,
    not minutes)."""
    corners = np.asarray(corners, dtype=np.float64)
    best = np.full(directions.shape[:-1], np.inf)
    if len(corners) == 0:
        return best
    inside = rays_into_box(origin, directions, corners.reshape(-1, 3).min(axis=0),
                           corners.reshape(-1, 3).max(axis=0))
    best[inside] = triangles_distances_all(origin, directions[inside], corners)
    return best


def triangles_distances_all(origin, directions, corners):
    """triangle_distances for every ray given, without the box test."""
    best = np.full(directions.shape[:-1], np.inf)
    for p0, p1, p2 in corners:
        edge1, edge2 = p1 - p0, p2 - p0
        pvec = np.cross(directions, edge2)
        determinant = pvec @ edge1
        with np.errstate(divide="ignore", invalid="ignore"):
            inverse = 1.0 / determinant
            tvec = origin - p0
            u = (pvec @ tvec) * inverse
            qvec = np.cross(tvec, edge1)
            v = (directions @ qvec) * inverse
            t = (qvec @ edge2) * inverse
            hit = (np.abs(determinant) > 1e-12) & (u >= 0) & (v >= 0) & (u + v <= 1) \
                & (t > 1e-9)
        best = np.where(hit & (t < best), t, best)
    return best


def mesh_corners(mesh: scene_io.Mesh) -> np.ndarray:
    """The mesh's triangles in world space, (T, 3, 3)."""
    positions, _, triangles, _ = obj_io.read_obj(mesh.path)
    matrix = mesh.world_from_mesh()
    world = positions @ matrix[:3, :3].T + matrix[:3, 3]
    return world[np.asarray(triangles)]


def instance_distances(scene: scene_io.Scene, instance: scene_io.Instance, eye,
                       directions) -> np.ndarray:
    """Nearest distance to any shape of the instance's object: its triangles, quads and
    meshes placed in the world (an affine map takes a triangle to a triangle), its
    spheres in the object's space (a sphere unevenly scaled is an ellipsoid), where the
    rays' directions keep the length the map gives them, so t is the world's."""
    scene_object = scene.objects[instance.object]
    world = instance.world_from_object()
    place = lambda corners: corners @ world[:3, :3].T + world[:3, 3]  # noqa: E731
    best = np.full(directions.shape[:-1], np.inf)
    corners = [np.array([[t.p0, t.p1, t.p2] for t in scene_object.triangles]).reshape(-1, 3, 3)]
    for quad in scene_object.quads:
        o, e1, e2 = (np.asarray(v, dtype=np.float64) for v in (quad.origin, quad.edge1,
                                                              quad.edge2))
        corners.append(np.array([[o, o + e1, o + e1 + e2], [o, o + e1 + e2, o + e2]]))
    corners += [mesh_corners(mesh) for mesh in scene_object.meshes]
    best = np.minimum(best, triangle_distances(eye, directions, place(np.concatenate(corners))))
    object_from_world = np.linalg.inv(world)
    local_eye = object_from_world[:3, :3] @ eye + object_from_world[:3, 3]
    local_directions = directions @ object_from_world[:3, :3].T
    for sphere in scene_object.spheres:
        best = np.minimum(best, sphere_t(sphere.center, sphere.radius, local_eye,
                                         local_directions))
    return best


def ray_directions(camera: scene_io.SceneCamera, width: int, height: int,
                   subsamples: int = 1) -> np.ndarray:
    """Unit directions (height * n, width * n, 3) of n x n rays per pixel: through the
    pixel centre for n = 1 (camera_rays.py's rays), else evenly from one edge of the
    pixel to the other, both edges included (so that a shape's edge cannot slip
    between the rays)."""
    forward, right, true_up = camera_rays.camera_basis(camera.look, camera.up)
    offsets = np.array([0.5]) if subsamples == 1 else np.linspace(0.0, 1.0, subsamples)
    across = ((np.arange(width)[:, None] + offsets).ravel() / width - 0.5)
    down_to_up = 0.5 - (np.arange(height)[:, None] + offsets).ravel() / height
    sensor_height = camera.sensor_width * height / width  # square pixels
    points = (forward * camera.focal_length
              + right * (across * camera.sensor_width)[None, :, None]
              + true_up * (down_to_up * sensor_height)[:, None, None])
    return points / np.linalg.norm(points, axis=-1, keepdims=True)


def primary_ids(scene: scene_io.Scene, width: int, height: int, subsamples: int = 1):
    """Which shape each pixel sees: (ids (height, width) int, names [region name of each
    id]); MISS where the ray leaves the scene. With subsamples = n, n x n rays spread
    over each pixel, its edges and corners included; a pixel whose rays do not all see
    one shape gets MIXED."""
    eye = np.asarray(scene.camera.eye, dtype=np.float64)
    directions = ray_directions(scene.camera, width, height, subsamples)
    distances, names = [], []
    for kind, index, shape in scene.shapes():
        if kind == "quad":
            t = quad_distances(eye, directions, shape)
        elif kind == "sphere":
            t = sphere_t(shape.center, shape.radius, eye, directions)
        elif kind == "triangle":
            t = triangle_distances(eye, directions, [[shape.p0, shape.p1, shape.p2]])
        else:
            t = triangle_distances(eye, directions, mesh_corners(shape))
        distances.append(t)
        names.append(scene.region_name(kind, index, shape))
    for index, instance in enumerate(scene.instances):
        distances.append(instance_distances(scene, instance, eye, directions))
        names.append(instance.name or f"instance_{index}")
    if not distances:  # only an environment: every ray leaves the scene
        return np.full((height, width), MISS), names
    distances = np.stack(distances)
    fine = np.where(np.isfinite(distances.min(axis=0)), distances.argmin(axis=0), MISS)
    blocks = fine.reshape(height, subsamples, width, subsamples).transpose(0, 2, 1, 3)
    blocks = blocks.reshape(height, width, subsamples * subsamples)
    pure = np.all(blocks == blocks[..., :1], axis=-1)
    return np.where(pure, blocks[..., 0], MIXED), names


def erode(mask: np.ndarray, pixels: int) -> np.ndarray:
    """Keeps the pixels whose whole (2 * pixels + 1)^2 neighbourhood is in the mask; the
    image border does not erode (outside counts as inside)."""
    if pixels <= 0:
        return mask.copy()
    padded = np.pad(mask, pixels, mode="edge")
    height, width = mask.shape
    result = np.ones_like(mask)
    for dy in range(2 * pixels + 1):
        for dx in range(2 * pixels + 1):
            result &= padded[dy:dy + height, dx:dx + width]
    return result


def region_masks(scene: scene_io.Scene, width: int, height: int, erode_pixels: int = 1,
                 subsamples: int = 4) -> dict:
    """{region name: bool mask (height, width)}: the pixels wholly inside one region (all
    subsamples x subsamples rays see it), then eroded by erode_pixels more, for
    renderers whose pixel filter reaches past the pixel. Shapes that share a name form
    one region. Pixels of a box-filtered render inside a mask take samples from that
    region only."""
    ids, names = primary_ids(scene, width, height, subsamples)
    region_of_id = np.array(names + ["", ""], dtype=object)  # MIXED (-2), MISS (-1) -> ""
    labels = region_of_id[ids]
    masks = {}
    for name in dict.fromkeys(names):  # file order, each name once
        masks[name] = erode(labels == name, erode_pixels)
    return masks


def region_means(image: np.ndarray, masks: dict) -> dict:
    """{region name: mean linear RGB (3,)} over each mask's pixels (NaN if empty)."""
    pixels = np.asarray(image, dtype=np.float64).reshape(-1, image.shape[-1])
    return {name: pixels[mask.ravel()].mean(axis=0) if mask.any()
            else np.full(image.shape[-1], np.nan) for name, mask in masks.items()}


def region_standard_errors(image_a: np.ndarray, image_b: np.ndarray, masks: dict) -> dict:
    """{region: standard error (3,) of the mean of image_a - image_b}: for two renders
    with independent noise, how far apart their region means may be by chance."""
    difference = (np.asarray(image_a, dtype=np.float64) - image_b).reshape(-1, 3)
    return {name: difference[mask.ravel()].std(axis=0) / math.sqrt(max(mask.sum(), 1))
            for name, mask in masks.items()}


# ---------------------------------------------------------------------------------------
# Command line
# ---------------------------------------------------------------------------------------

def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--scene", required=True, help="a .scene file (assets/scenes/)")
    parser.add_argument("--mesh-folder", action="append", default=None,
                        help="where mesh paths are looked up after the scene's folder "
                             "(default: build/assets, where the build writes meshes/)")
    parser.add_argument("--width", type=int, default=256)
    parser.add_argument("--height", type=int, default=256)
    parser.add_argument("--spp", type=int, default=64)
    parser.add_argument("--depth", type=int, default=6,
                        help="surface bounces, ours (Mitsuba's max_depth is one more)")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--variant", choices=VARIANTS, default="scalar_rgb")
    parser.add_argument("--out", help="write the image as linear PFM")
    parser.add_argument("--json", help="write the timing and region means as JSON")
    parser.add_argument("--regions", action="store_true", help="print region means")
    args = parser.parse_args(argv)
    folders = args.mesh_folder if args.mesh_folder is not None \
        else scene_io.default_mesh_folders()
    try:
        scene = scene_io.load_scene(args.scene, folders)
    except scene_io.SceneError as error:
        sys.exit(f"mitsuba_reference.py: {error}")

    image, stats = render_mitsuba(scene, args.width, args.height, args.spp, args.depth,
                                  args.seed, args.variant)
    masks = region_masks(scene, args.width, args.height)
    means = region_means(image, masks)
    stats["scene"] = str(scene.path)
    stats["region_means"] = {name: [float(v) for v in mean] for name, mean in means.items()}
    stats["region_pixels"] = {name: int(mask.sum()) for name, mask in masks.items()}
    if args.out:
        write_pfm(args.out, image)
    if args.json:
        partial = Path(args.json + ".partial")
        partial.write_text(json.dumps(stats, indent=2) + "\n")
        os.replace(partial, args.json)
    print(f"{stats['renderer']}: {args.width} x {args.height}, {args.spp} spp, depth "
          f"{args.depth}: {stats['seconds']:.2f} s, "
          f"{stats['samples_per_second'] / 1e6:.3f} M samples/s")
    if args.regions:
        for name, mean in means.items():
            print(f"  {name:<14} {stats['region_pixels'][name]:7d} px  "
                  + " ".join(f"{v:9.5f}" for v in mean))


if __name__ == "__main__":
    main()
