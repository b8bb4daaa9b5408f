"""A small, strict reader for the course's scene files (assets/scenes/*.scene), the
Python twin of common/scene_file.cpp. The format is described in
common/course/scene_file.h and in assets/scenes/README.md:

    camera eye X Y Z look X Y Z up X Y Z focal F sensor S [lens RADIUS focus DISTANCE]
    texture NAME image PATH [linear]
    texture NAME checker R G B R G B [scale S]
    material NAME albedo R G B [emission R G B]
    material NAME albedo texture TEXTURE [emission R G B]
    material NAME mirror [reflectance R G B]
    material NAME conductor eta R G B k R G B [roughness A]
    material NAME dielectric ior N [roughness A]
    sphere CX CY CZ RADIUS MATERIAL [name NAME]
    quad OX OY OZ EX EY EZ FX FY FZ MATERIAL [name NAME]
    triangle AX AY AZ BX BY BZ CX CY CZ MATERIAL [name NAME]
    mesh PATH MATERIAL [scale S] [rotate_y DEGREES] [translate X Y Z] [name NAME]
    environment PATH [scale S] [rotate_y DEGREES]
    object NAME begin ... end
    instance OBJECT [scale S | scale X Y Z] [rotate X Y Z DEGREES] [rotate_y DEGREES]
             [translate X Y Z] [moving X Y Z] [name NAME]

load_scene(path, mesh_folders) -> Scene. Any problem raises SceneError("file:line: ...");
line 0 means the file as a whole. Image paths are found as mesh paths are; what a
texture does with its values is textures.py's (the numpy reference). So are
environment maps (PFM only, at most one line), which light the scene from infinitely
far: a scene with one needs no emitter; environment_map.py looks its radiance up.
"""

from __future__ import annotations

import dataclasses
import math
import os
import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from python_prototypes import camera_rays
from python_prototypes import environment_map
from python_prototypes import pfm
from python_prototypes import textures

CONTROL_BYTES = re.compile(r"[\x00-\x08\x0b\x0c\x0e-\x1f\x7f]")  # all but \t \n \r
NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_-]*\Z")
FLOAT_MAX = float(np.finfo(np.float32).max)


def absolute(path) -> Path:
    """Absolute, without '.' or '..' (as the C++ reader shows paths)."""
    return Path(os.path.abspath(path))


class SceneError(ValueError):
    """A problem in a scene file; the message starts with 'file:line: '."""


@dataclass
class SceneCamera:
    eye: tuple
    look: tuple
    up: tuple
    focal_length: float
    sensor_width: float
    lens_radius: float = 0.0     # the aperture's radius (metres); 0 is the pinhole
    focus_distance: float = 0.0  # with a lens: the sharp plane, metres along look
    medium: str | None = None    # the medium around the camera (`medium MEDIUM`)
    shutter_open: float = 0.0    # seconds (`shutter OPEN CLOSE`); both 0 when not written
    shutter_close: float = 0.0

    def as_camera(self) -> camera_rays.Camera:
        return camera_rays.Camera(self.eye, self.look, self.up, self.focal_length,
                                  self.sensor_width)

    def as_thin_lens_camera(self):
        """thin_lens.py's camera, which takes the aperture's diameter, not its radius."""
        from python_prototypes import thin_lens
        return thin_lens.ThinLensCamera(self.eye, self.look, self.up, self.focal_length,
                                        self.sensor_width, 2.0 * self.lens_radius,
                                        self.focus_distance)

    def horizontal_fov_degrees(self) -> float:
        """The angle the sensor's width spans seen from the eye."""
        return math.degrees(2.0 * math.atan(self.sensor_width / (2.0 * self.focal_length)))


@dataclass
class Texture:
    """texture NAME image PATH [linear] | NAME checker R G B R G B [scale S]"""
    name: str
    kind: str                          # "image" or "checker"
    path: Path | None = None           # image: absolute, where the file was found
    written_path: str = ""             # image: as the scene file writes it
    linear: bool = False               # image: values already linear, not sRGB
    color0: tuple = (0.0, 0.0, 0.0)    # checker: the two colours
    color1: tuple = (1.0, 1.0, 1.0)
    scale: float = 1.0                 # checker: squares of each colour per unit of u, v
    line: int = 0


@dataclass
class Material:
    name: str
    albedo: tuple = (0.0, 0.0, 0.0)    # albedo: the reflected fraction per channel
    texture: str | None = None         # albedo: a texture's name, used instead of albedo
    emission: tuple = (0.0, 0.0, 0.0)  # albedo only: the emitted radiance
    kind: str = "albedo"               # "albedo", "mirror", "conductor", "dielectric", "boundary"
    reflectance: tuple = (1.0, 1.0, 1.0)  # mirror
    eta: tuple = (1.0, 1.0, 1.0)       # conductor: the complex index eta + i k
    k: tuple = (0.0, 0.0, 0.0)
    ior: float = 1.5                   # dielectric: the index inside (outside: 1)
    roughness: float = 0.0             # conductor, dielectric: GGX alpha; 0 is smooth

    @property
    def emits(self) -> bool:
        return any(value > 0 for value in self.emission)


@dataclass
class Medium:
    """medium NAME homogeneous sigma_a R G B sigma_s R G B [g G] |
    NAME grid PATH albedo R G B [scale S] [g G]"""
    name: str
    kind: str                             # "homogeneous" or "grid"
    sigma_a: tuple = (0.0, 0.0, 0.0)      # homogeneous: per metre, per channel
    sigma_s: tuple = (0.0, 0.0, 0.0)
    path: Path | None = None              # grid: absolute, where the .vol file was found
    written_path: str = ""
    albedo: tuple = (0.0, 0.0, 0.0)       # grid: sigma_s / sigma_t
    scale: float = 1.0                    # grid: sigma_t per metre at density 1
    g: float = 0.0                        # Henyey-Greenstein's mean cosine
    line: int = 0


@dataclass
class Sphere:
    center: tuple
    radius: float
    material: str
    name: str = ""
    interior: str | None = None  # the medium inside


@dataclass
class Quad:
    origin: tuple
    edge1: tuple
    edge2: tuple
    material: str
    name: str = ""

    def corners(self) -> np.ndarray:
        o, e, f = (np.asarray(v, dtype=np.float64) for v in (self.origin, self.edge1,
                                                             self.edge2))
        return np.stack([o, o + e, o + e + f, o + f])

    def normal(self) -> np.ndarray:
        n = np.cross(self.edge1, self.edge2)
        return n / np.linalg.norm(n)


@dataclass
class Triangle:
    p0: tuple
    p1: tuple
    p2: tuple
    material: str
    name: str = ""


@dataclass
class Mesh:
    path: Path  # absolute: where the file was found
    written_path: str
    material: str
    scale: float = 1.0
    rotation_y_degrees: float = 0.0
    translation: tuple = (0.0, 0.0, 0.0)
    name: str = ""
    line: int = 0
    interior: str | None = None  # the medium inside (a closed mesh)

    def world_from_mesh(self) -> np.ndarray:
        """4x4: scale, then turn about y (counter-clockwise seen from above), then move."""
        angle = math.radians(self.rotation_y_degrees)
        c, s = math.cos(angle), math.sin(angle)
        matrix = np.eye(4)
        matrix[:3, :3] = np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]]) * self.scale
        matrix[:3, 3] = self.translation
        return matrix


def rotation_matrix(axis, degrees) -> np.ndarray:
    """3 x 3: a turn by `degrees` about `axis` (any length), counter-clockwise seen from
    the axis's tip (Rodrigues' formula; glm::rotate and Mitsuba's rotate with a unit axis)."""
    x, y, z = np.asarray(axis, dtype=np.float64) / np.linalg.norm(axis)
    c, s = math.cos(math.radians(degrees)), math.sin(math.radians(degrees))
    cross = np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])
    return c * np.eye(3) + s * cross + (1.0 - c) * np.outer((x, y, z), (x, y, z))


@dataclass
class SceneObject:
    """object NAME begin ... end: shapes drawn only where instances place them."""
    name: str
    line: int = 0
    spheres: list = field(default_factory=list)
    quads: list = field(default_factory=list)
    triangles: list = field(default_factory=list)
    meshes: list = field(default_factory=list)

    def is_empty(self) -> bool:
        return not (self.spheres or self.quads or self.triangles or self.meshes)


@dataclass
class Instance:
    """instance OBJECT [steps] [moving X Y Z] [name NAME]: `steps` as written, each
    (kind, numbers): ("scale", (x, y, z)), ("rotate", (x, y, z, degrees)),
    ("rotate_y", (degrees,)), ("translate", (x, y, z))."""
    object: str
    steps: list = field(default_factory=list)
    motion: tuple = (0.0, 0.0, 0.0)
    name: str = ""
    line: int = 0

    def world_from_object(self) -> np.ndarray:
        """4x4, where the instance is when the shutter opens: each step multiplies from
        the left, so the first written applies to the object first."""
        world = np.eye(4)
        for kind, values in self.steps:
            step = np.eye(4)
            if kind == "scale":
                step[:3, :3] = np.diag(values)
            elif kind == "rotate":
                step[:3, :3] = rotation_matrix(values[:3], values[3])
            elif kind == "rotate_y":
                step[:3, :3] = rotation_matrix((0.0, 1.0, 0.0), values[0])
            else:
                step[:3, 3] = values
            world = step @ world
        return world


@dataclass
class Environment:
    """environment PATH [scale S] [rotate_y DEGREES]: a latitude-longitude radiance map
    (PFM) lighting the scene from infinitely far; environment_map.py reads it."""
    path: Path                      # absolute: where the file was found
    written_path: str               # as the scene file writes it
    scale: float = 1.0              # multiplies the radiance
    rotate_y_degrees: float = 0.0   # turns the map about y, counter-clockwise from above
    line: int = 0


@dataclass
class Scene:
    path: Path
    camera: SceneCamera
    textures: dict = field(default_factory=dict)   # name -> Texture, in file order
    materials: dict = field(default_factory=dict)  # name -> Material, in file order
    spheres: list = field(default_factory=list)
    quads: list = field(default_factory=list)
    triangles: list = field(default_factory=list)
    meshes: list = field(default_factory=list)
    environment: Environment | None = None  # the `environment` line, if there is one
    media: dict = field(default_factory=dict)  # name -> Medium, in file order
    objects: dict = field(default_factory=dict)  # name -> SceneObject, in file order
    instances: list = field(default_factory=list)

    def shapes(self):
        """(kind, index, shape) for every shape: spheres, quads, triangles, meshes."""
        for kind, shapes in [("sphere", self.spheres), ("quad", self.quads),
                             ("triangle", self.triangles), ("mesh", self.meshes)]:
            for index, shape in enumerate(shapes):
                yield kind, index, shape

    def region_name(self, kind, index, shape) -> str:
        """The shape's name, or kind_index for a shape without one."""
        return shape.name or f"{kind}_{index}"

    def emitters(self):
        return [shape for _, _, shape in self.shapes() if self.materials[shape.material].emits]

    def moves(self) -> bool:
        """Whether an instance moves while the shutter is open (`moving X Y Z`)."""
        return any(any(instance.motion) for instance in self.instances)

    def at_instant(self, instant: float) -> "Scene":
        """The scene at one instant of the shutter (0: it opens, 1: it closes), as a
        renderer without motion blur draws it: each moving instance gets the step
        `translate` by that share of its motion (the last step: a move in the world) and
        moves no more; the camera's shutter is taken out."""
        still = dataclasses.replace(
            self, camera=dataclasses.replace(self.camera, shutter_open=0.0, shutter_close=0.0),
            instances=[dataclasses.replace(
                instance, motion=(0.0, 0.0, 0.0),
                steps=instance.steps + ([("translate", tuple(instant * m for m in instance.motion))]
                                        if any(instance.motion) else []))
                for instance in self.instances])
        return still


# ---------------------------------------------------------------------------------------
# Parsing
# ---------------------------------------------------------------------------------------

def number(word: str) -> float:
    try:
        value = float(word)
    except ValueError:
        raise SceneError(f"'{word}' is not a number") from None
    if not math.isfinite(value):
        raise SceneError(f"'{word}' is not a finite number")
    if abs(value) > FLOAT_MAX:
        raise SceneError(f"'{word}' is too large for a float")
    return value


def vector(words, first: int) -> tuple:
    return tuple(number(word) for word in words[first:first + 3])


def expect_label(words, index, label, statement):
    if words[index] != label:
        raise SceneError(f"'{statement}' expects '{label}' here, got '{words[index]}'")


def shape_name(word: str) -> str:
    if not NAME.match(word):
        raise SceneError(f"shape name '{word}': use letters, digits, '_' and '-', "
                         "starting with a letter or '_'")
    return word


def shape_fields(keyword, words, count, fields):
    """The first `count` fields, then an optional `name NAME`: (fields, name)."""
    if len(words) == count + 2:
        expect_label(words, count, "name", keyword)
        return words[:count], shape_name(words[count + 1])
    if len(words) != count:
        raise SceneError(f"'{keyword}' needs {count} fields ({fields}), then optionally "
                         f"name NAME; got {len(words)}")
    return words, ""


def read_sphere(words) -> Sphere:
    """sphere CX CY CZ RADIUS MATERIAL [interior MEDIUM] [name NAME]"""
    if len(words) < 5:
        raise SceneError("'sphere' needs 5 fields (CX CY CZ RADIUS MATERIAL), then optionally "
                         f"interior MEDIUM and name NAME; got {len(words)}")
    sphere = Sphere(vector(words, 0), number(words[3]), words[4])
    seen = set()
    for i in range(5, len(words), 2):
        option = words[i]
        if option not in ("interior", "name") or option in seen or i + 1 >= len(words):
            raise SceneError("'sphere' takes after its 5 fields only interior MEDIUM and name "
                             f"NAME, each once; got '{option}'")
        seen.add(option)
        if option == "interior":
            sphere.interior = words[i + 1]
        else:
            sphere.name = shape_name(words[i + 1])
    if not sphere.radius > 0:
        raise SceneError(f"the sphere's radius must be positive, got '{words[3]}'")
    return sphere


def is_degenerate(edge1, edge2) -> bool:
    edge1, edge2 = np.asarray(edge1, dtype=np.float64), np.asarray(edge2, dtype=np.float64)
    area = np.linalg.norm(np.cross(edge1, edge2))
    return area <= 1e-7 * np.linalg.norm(edge1) * np.linalg.norm(edge2)


def looks_like_number(word: str) -> bool:
    """Where a step's numbers end: the next word that starts as no number does."""
    return word[0].isdigit() or word[0] in "-+."


def read_camera(words) -> SceneCamera:
    shutter = None  # shutter OPEN CLOSE, anywhere after the sensor, is taken out first
    for i in range(16, len(words)):
        if words[i] != "shutter":
            continue
        if i + 2 >= len(words) or not looks_like_number(words[i + 1]) or \
                not looks_like_number(words[i + 2]):
            raise SceneError("the camera's shutter needs two numbers, OPEN CLOSE (seconds), "
                             "once")
        shutter = (number(words[i + 1]), number(words[i + 2]))
        if not (shutter[0] >= 0 and shutter[1] >= shutter[0]):
            raise SceneError(f"the camera's shutter '{words[i + 1]}' '{words[i + 2]}' must "
                             "open at 0 or later and close no earlier than it opens")
        if "shutter" in words[i + 3:]:
            raise SceneError("the camera's shutter needs two numbers, OPEN CLOSE (seconds), "
                             "once")
        words = words[:i] + words[i + 3:]
        break
    camera = read_camera_fields(words)
    if shutter is not None:
        camera.shutter_open, camera.shutter_close = shutter
    return camera


def read_camera_fields(words) -> SceneCamera:
    if len(words) < 16 or len(words) > 22 or len(words) % 2:
        raise SceneError("'camera' needs 16 fields (eye X Y Z look X Y Z up X Y Z focal F "
                         "sensor S, then optionally lens RADIUS focus DISTANCE and medium "
                         f"MEDIUM), got {len(words)}")
    for index, label in [(0, "eye"), (4, "look"), (8, "up"), (12, "focal"), (14, "sensor")]:
        expect_label(words, index, label, "camera")
    camera = SceneCamera(vector(words, 1), vector(words, 5), vector(words, 9),
                         number(words[13]), number(words[15]))
    look, up = np.array(camera.look), np.array(camera.up)
    if not look.any():
        raise SceneError("the camera's look direction must not be zero")
    if not up.any():
        raise SceneError("the camera's up direction must not be zero")
    if np.linalg.norm(np.cross(look, up)) <= 1e-6 * np.linalg.norm(look) * np.linalg.norm(up):
        raise SceneError("the camera's up must not be parallel to its look direction")
    if not (camera.focal_length > 0 and camera.sensor_width > 0):
        raise SceneError("the camera's focal length and sensor width must be positive")
    i, seen = 16, set()
    while i < len(words):
        option = words[i]
        if option == "lens" and option not in seen and i + 4 <= len(words):
            expect_label(words, i + 2, "focus", "camera")
            camera.lens_radius, camera.focus_distance = number(words[i + 1]), number(words[i + 3])
            if not camera.lens_radius >= 0:
                raise SceneError(f"the lens radius '{words[i + 1]}' must be 0 or more")
            if not camera.focus_distance > 0:
                raise SceneError(f"the focus distance '{words[i + 3]}' must be positive")
            i += 4
        elif option == "medium" and option not in seen:
            camera.medium = words[i + 1]
            i += 2
        else:
            raise SceneError(f"unexpected '{option}' in 'camera' (after the sensor: lens "
                             "RADIUS focus DISTANCE, medium MEDIUM, shutter OPEN CLOSE, each "
                             "once)")
        seen.add(option)
    return camera


def read_medium(words, scene_path, mesh_folders, line) -> Medium:
    if len(words) < 2:
        raise SceneError("'medium' needs a name and a kind (NAME homogeneous sigma_a R G B "
                         "sigma_s R G B, NAME grid PATH albedo R G B)")
    name, kind = words[0], words[1]
    if not NAME.match(name):
        raise SceneError(f"medium name '{name}': use letters, digits, '_' and '-', "
                         "starting with a letter or '_'")
    medium = Medium(name, kind, line=line)
    if kind == "homogeneous":
        if len(words) < 10:
            raise SceneError("'medium NAME homogeneous' needs sigma_a R G B sigma_s R G B")
        expect_label(words, 2, "sigma_a", "medium")
        medium.sigma_a = read_non_negative(words, 3, "sigma_a")
        expect_label(words, 6, "sigma_s", "medium")
        medium.sigma_s = read_non_negative(words, 7, "sigma_s")
        at = 10
    elif kind == "grid":
        if len(words) < 7:
            raise SceneError("'medium NAME grid' needs PATH albedo R G B")
        medium.written_path = words[2]
        medium.path = find_file(words[2], scene_path, mesh_folders, "grid file")
        expect_label(words, 3, "albedo", "medium")
        medium.albedo = read_fraction(words, 4, "albedo")
        at = 7
    else:
        raise SceneError(f"unknown medium kind '{kind}' (expected homogeneous or grid)")
    seen = set()
    while at < len(words):
        option = words[at]
        scale = option == "scale" and kind == "grid"
        if (option != "g" and not scale) or option in seen:
            after = "after the albedo: scale S, g G" if kind == "grid" else "after sigma_s: g G"
            raise SceneError(f"unexpected '{option}' in medium '{name}' ({after})")
        if at + 1 >= len(words):
            raise SceneError(f"'{option}' needs a number")
        value = number(words[at + 1])
        if scale and not value > 0:
            raise SceneError(f"the grid's scale '{words[at + 1]}' must be positive")
        if not scale and not -1 < value < 1:
            raise SceneError(f"g '{words[at + 1]}' must lie strictly between -1 and 1 (the "
                             "phase function's mean cosine)")
        if scale:
            medium.scale = value
        else:
            medium.g = value
        seen.add(option)
        at += 2
    return medium


def read_fraction(words, first: int, what: str) -> tuple:
    values = read_non_negative(words, first, what)
    for word, value in zip(words[first:first + 3], values):
        if value > 1:
            raise SceneError(f"{what} '{word}' is outside [0, 1]: a surface cannot reflect "
                             "more light than reaches it")
    return values


def read_non_negative(words, first: int, what: str) -> tuple:
    if first + 3 > len(words):
        raise SceneError(f"{what} needs three numbers R G B")
    values = vector(words, first)
    for word, value in zip(words[first:first + 3], values):
        if value < 0:
            raise SceneError(f"{what} '{word}' is negative")
    return values


def read_material(words, textures) -> Material:
    """material NAME albedo R G B [emission R G B] | NAME albedo texture TEX [emission
    R G B] | NAME mirror [reflectance R G B] | NAME conductor eta R G B k R G B
    [roughness A] | NAME dielectric ior N [roughness A]. `textures` are those defined on
    earlier lines: unlike a material, a texture comes before its use."""
    if len(words) < 2:
        raise SceneError("'material' needs a name and a kind (NAME albedo R G B, NAME "
                         "mirror, NAME conductor eta R G B k R G B, NAME dielectric ior N)")
    name, kind = words[0], words[1]
    if not NAME.match(name):
        raise SceneError(f"material name '{name}': use letters, digits, '_' and '-', "
                         "starting with a letter or '_'")
    material = Material(name, kind=kind)
    at = 2  # the first word after the kind
    if kind == "albedo" and len(words) > at and words[at] == "texture":
        if len(words) < at + 2:
            raise SceneError("'albedo texture' needs the name of a texture")
        if words[at + 1] not in textures:
            raise SceneError(f"texture '{words[at + 1]}' is not defined on an earlier line")
        material.texture = words[at + 1]
        at += 2
    elif kind == "albedo":
        material.albedo = read_fraction(words, at, "albedo")
        at += 3
    elif kind == "mirror":
        pass
    elif kind == "conductor":
        if len(words) < at + 8:
            raise SceneError("'material' conductor eta R G B k R G B: too few fields")
        expect_label(words, at, "eta", "material")
        material.eta = vector(words, at + 1)
        expect_label(words, at + 4, "k", "material")
        material.k = vector(words, at + 5)
        for index in range(3):
            if not material.eta[index] > 0:
                raise SceneError(f"eta '{words[at + 1 + index]}' must be above 0")
            if material.k[index] < 0:
                raise SceneError(f"k '{words[at + 5 + index]}' is negative")
        at += 8
    elif kind == "boundary":
        pass
    elif kind == "dielectric":
        if len(words) < at + 2:
            raise SceneError("'material' dielectric ior N: too few fields")
        expect_label(words, at, "ior", "material")
        material.ior = number(words[at + 1])
        if not material.ior > 0:
            raise SceneError(f"ior '{words[at + 1]}' must be above 0")
        at += 2
    else:
        raise SceneError(f"unknown material kind '{kind}' (expected albedo, mirror, "
                         "conductor, dielectric or boundary)")
    described = f"material '{name}' ({kind})"
    seen = set()
    while at < len(words):
        option = words[at]
        if option == "emission" and kind != "albedo":
            raise SceneError(f"only an 'albedo' material may have an emission, not {described}")
        if option in seen or (option, kind) not in {
                ("emission", "albedo"), ("reflectance", "mirror"),
                ("roughness", "conductor"), ("roughness", "dielectric")}:
            raise SceneError(f"unexpected '{option}' in {described}")
        seen.add(option)
        if option == "emission":
            material.emission = read_non_negative(words, at + 1, "emission")
            at += 4
        elif option == "reflectance":
            material.reflectance = read_fraction(words, at + 1, "reflectance")
            at += 4
        else:
            if at + 1 >= len(words):
                raise SceneError("roughness needs a number, the GGX alpha")
            material.roughness = number(words[at + 1])
            if material.roughness < 0:
                raise SceneError(f"roughness '{words[at + 1]}' is negative")
            at += 2
    return material


def find_file(written: str, scene_path: Path, mesh_folders, what="mesh file") -> Path:
    """A mesh's or an image's PATH: the scene file's folder first, then mesh_folders."""
    candidates = [Path(written)] if Path(written).is_absolute() else \
        [scene_path.parent / written] + [Path(folder) / written for folder in mesh_folders]
    for candidate in candidates:
        if candidate.is_file():
            return absolute(candidate)
    tried = ", ".join(str(absolute(c)) for c in candidates)
    raise SceneError(f"{what} '{written}' not found (looked for {tried})")


def read_texture(words, scene_path, mesh_folders, line) -> Texture:
    """texture NAME image PATH [linear] | NAME checker R G B R G B [scale S]"""
    if len(words) < 2:
        raise SceneError("'texture' needs a name and a kind (NAME image PATH [linear], "
                         "NAME checker R G B R G B [scale S])")
    name, kind = words[0], words[1]
    if not NAME.match(name):
        raise SceneError(f"texture name '{name}': use letters, digits, '_' and '-', "
                         "starting with a letter or '_'")
    texture = Texture(name, kind, line=line)
    if kind == "image":
        linear = len(words) == 4 and words[3] == "linear"
        if len(words) != 3 and not linear:
            raise SceneError("'texture NAME image PATH' takes only the word 'linear' "
                             "after PATH")
        texture.written_path, texture.linear = words[2], linear
        texture.path = find_file(words[2], scene_path, mesh_folders, "image file")
        problem = textures.image_problem(texture.path)
        if problem:
            raise SceneError(f"image '{words[2]}' ({texture.path}) is {problem}")
    elif kind == "checker":
        texture.color0 = read_fraction(words, 2, "checker colour")
        texture.color1 = read_fraction(words, 5, "checker colour")
        if len(words) == 10:
            expect_label(words, 8, "scale", "texture")
            texture.scale = number(words[9])
            if not texture.scale > 0:
                raise SceneError(f"the checker's scale '{words[9]}' must be positive")
        elif len(words) != 8:
            raise SceneError("'texture NAME checker' needs two colours R G B R G B, then "
                             "optionally scale S")
    else:
        raise SceneError(f"unknown texture kind '{kind}' (expected image or checker)")
    return texture


def read_mesh(words, scene_path, mesh_folders, line) -> Mesh:
    if len(words) < 2:
        raise SceneError("'mesh' needs a PATH and a MATERIAL, then optionally scale S, "
                         "rotate_y DEGREES, translate X Y Z, name NAME")
    mesh = Mesh(find_file(words[0], scene_path, mesh_folders), words[0], words[1],
                line=line)
    seen = set()
    i = 2
    while i < len(words):
        option = words[i]
        counts = {"scale": 1, "rotate_y": 1, "translate": 3, "name": 1, "interior": 1}
        if option not in counts:
            raise SceneError(f"unknown mesh option '{option}' "
                             "(expected scale, rotate_y, translate, interior or name)")
        if option in seen:
            raise SceneError(f"'{option}' is given twice")
        seen.add(option)
        count = counts[option]
        if len(words) - (i + 1) < count:
            what = "name" if option in ("name", "interior") else "number" if count == 1 \
                else "numbers"
            raise SceneError(f"'{option}' needs {count} {what}")
        if option == "scale":
            mesh.scale = number(words[i + 1])
            if not mesh.scale > 0:
                raise SceneError(f"the mesh's scale must be positive, got '{words[i + 1]}'")
        elif option == "rotate_y":
            mesh.rotation_y_degrees = number(words[i + 1])
        elif option == "translate":
            mesh.translation = vector(words, i + 1)
        elif option == "interior":
            mesh.interior = words[i + 1]
        else:
            mesh.name = shape_name(words[i + 1])
        i += 1 + count
    return mesh


def read_environment(words, scene_path, mesh_folders, line) -> Environment:
    """environment PATH [scale S] [rotate_y DEGREES]: the file is found as a mesh's is,
    then the options are read, then the whole map is read and checked."""
    if not words:
        raise SceneError("'environment' needs a PATH, then optionally scale S, "
                         "rotate_y DEGREES")
    environment = Environment(find_file(words[0], scene_path, mesh_folders,
                                        "environment file"), words[0], line=line)
    seen = set()
    i = 1
    while i < len(words):
        option = words[i]
        if option not in ("scale", "rotate_y"):
            raise SceneError(f"unknown environment option '{option}' "
                             "(expected scale or rotate_y)")
        if option in seen:
            raise SceneError(f"'{option}' is given twice")
        seen.add(option)
        if i + 1 >= len(words):
            raise SceneError(f"'{option}' needs 1 number")
        if option == "scale":
            environment.scale = number(words[i + 1])
            if not environment.scale > 0:
                raise SceneError("the environment's scale must be positive, got "
                                 f"'{words[i + 1]}'")
        else:
            environment.rotate_y_degrees = number(words[i + 1])
        i += 2
    try:
        image = environment_map.read_map(environment.path)
    except pfm.PfmError as error:
        raise SceneError(f"environment '{words[0]}' ({environment.path}) is "
                         f"{error}") from None
    bad = environment_map.first_bad_texel(image)
    if bad is not None:
        row, column, what = bad
        raise SceneError(f"environment '{words[0]}': texel (row {row}, column {column}) "
                         f"is {what}: a radiance map holds finite values >= 0")
    return environment


INSTANCE_FORMS = {"scale": (1, 3), "rotate": (4,), "rotate_y": (1,), "translate": (3,),
                  "moving": (3,)}
INSTANCE_NEEDS = {"scale": "1 number (S) or 3 (X Y Z)", "rotate": "4 numbers (axis X Y Z, "
                  "DEGREES)", "rotate_y": "1 number (DEGREES)", "translate": "3 numbers (X Y Z)",
                  "moving": "3 numbers (X Y Z)"}


def read_instance(words, line=0) -> Instance:
    """instance OBJECT [scale S | scale X Y Z] [rotate X Y Z DEGREES] [rotate_y DEGREES]
    [translate X Y Z] [moving X Y Z] [name NAME]"""
    if not words:
        raise SceneError("'instance' needs the name of an object, then its placement")
    if not NAME.match(words[0]):
        raise SceneError(f"object name '{words[0]}': use letters, digits, '_' and '-', "
                         "starting with a letter or '_'")
    instance, seen, i = Instance(words[0], line=line), set(), 1
    while i < len(words):
        step = words[i]
        count = 0
        while i + 1 + count < len(words) and looks_like_number(words[i + 1 + count]):
            count += 1
        if step == "name" and "name" not in seen and i + 1 < len(words):
            instance.name = shape_name(words[i + 1])
            seen.add("name")
            i += 2
            continue
        if step not in INSTANCE_FORMS or (step == "moving" and "moving" in seen):
            raise SceneError(f"unexpected '{step}' in 'instance' (expected scale, rotate, "
                             "rotate_y, translate, and moving X Y Z and name NAME once each)")
        if count not in INSTANCE_FORMS[step]:
            raise SceneError(f"'{step}' needs {INSTANCE_NEEDS[step]}, got {count} "
                             f"number{'' if count == 1 else 's'}")
        values = tuple(number(word) for word in words[i + 1:i + 1 + count])
        if step == "scale":
            values = values * 3 if count == 1 else values
            if 0.0 in values:
                raise SceneError("scale by 0 squashes the object flat")
        if step == "rotate" and not any(values[:3]):
            raise SceneError("rotate needs an axis that is not 0 0 0")
        if step == "moving":
            instance.motion = values
            seen.add("moving")
        else:
            instance.steps.append((step, values))
        i += 1 + count
    determinant = float(np.linalg.det(instance.world_from_object()[:3, :3]))
    if not (math.isfinite(determinant) and abs(determinant) > 1e-24):
        raise SceneError("the placement squashes the object flat or blows it up (the "
                         f"determinant of its matrix is {determinant:.3g})")
    return instance


def parse_scene(text: str, path, mesh_folders=()) -> Scene:
    """Parses scene text; `path` names it in messages and anchors relative mesh paths."""
    path = absolute(path)
    camera, camera_line = None, 0
    materials, material_lines, uses = {}, {}, []  # uses: (line, material, shape kind)
    interiors = []  # (line, shape) for each sphere or mesh with an interior medium
    scene = Scene(path, None)
    open_object = None  # the object between its `begin` and `end`
    emitting_uses = []  # (line, material, object name) for the shapes of objects

    def shapes():
        return scene if open_object is None else open_object

    def fail(line, message):
        raise SceneError(f"{path}:{line}: {message}")

    if not text:
        fail(0, "empty file")
    text = text.removeprefix("\ufeff")
    for line_number, line in enumerate(text.split("\n"), start=1):
        try:
            if CONTROL_BYTES.search(line):
                raise SceneError("binary data (a control byte) in what should be a text file")
            words = line.split("#", 1)[0].split()
            if not words:
                continue
            keyword, words = words[0], words[1:]
            if open_object is not None and keyword not in ("sphere", "quad", "triangle",
                                                            "mesh", "end"):
                where = f"object '{open_object.name}' (line {open_object.line})"
                if keyword == "instance" and words and words[0] == open_object.name:
                    raise SceneError(f"object '{open_object.name}' is used inside itself")
                if keyword in ("instance", "object"):
                    raise SceneError(f"'{keyword}' inside {where}: objects hold shapes, not "
                                     "objects or instances; 'end' it first")
                raise SceneError(f"'{keyword}' inside {where}: only sphere, quad, triangle "
                                 "and mesh statements stand between its begin and end")
            if open_object is not None and keyword in ("sphere", "quad", "triangle", "mesh"):
                emitting_uses.append((line_number, None, open_object.name))
            if keyword == "camera":
                if camera is not None:
                    raise SceneError(f"a second camera (the first is on line {camera_line})")
                camera, camera_line = read_camera(words), line_number
            elif keyword == "texture":
                texture = read_texture(words, path, mesh_folders, line_number)
                if texture.name in scene.textures:
                    raise SceneError(f"texture '{texture.name}' is already defined on "
                                     f"line {scene.textures[texture.name].line}")
                scene.textures[texture.name] = texture
            elif keyword == "material":
                material = read_material(words, scene.textures)
                if material.name in materials:
                    raise SceneError(f"material '{material.name}' is already defined on "
                                     f"line {material_lines[material.name]}")
                materials[material.name] = material
                material_lines[material.name] = line_number
            elif keyword == "sphere":
                sphere = read_sphere(words)
                uses.append((line_number, sphere.material, "sphere"))
                if sphere.interior is not None and open_object is not None:
                    raise SceneError(f"object '{open_object.name}': an object's shapes hold "
                                     "no medium (interior)")
                shapes().spheres.append(sphere)
                if sphere.interior is not None:
                    interiors.append((line_number, sphere))
            elif keyword == "medium":
                medium = read_medium(words, path, mesh_folders, line_number)
                if medium.name in scene.media:
                    raise SceneError(f"medium '{medium.name}' is already defined on line "
                                     f"{scene.media[medium.name].line}")
                scene.media[medium.name] = medium
            elif keyword == "quad":
                fields, name = shape_fields("quad", words, 10,
                                            "OX OY OZ EX EY EZ FX FY FZ MATERIAL")
                quad = Quad(vector(fields, 0), vector(fields, 3), vector(fields, 6),
                            fields[9], name)
                if is_degenerate(quad.edge1, quad.edge2):
                    raise SceneError("the quad has zero area: an edge is zero or the two "
                                     "edges are parallel")
                uses.append((line_number, quad.material, "quad"))
                shapes().quads.append(quad)
            elif keyword == "triangle":
                fields, name = shape_fields("triangle", words, 10,
                                            "AX AY AZ BX BY BZ CX CY CZ MATERIAL")
                triangle = Triangle(vector(fields, 0), vector(fields, 3), vector(fields, 6),
                                    fields[9], name)
                a, b, c = (np.array(p) for p in (triangle.p0, triangle.p1, triangle.p2))
                if is_degenerate(b - a, c - a):
                    raise SceneError("the triangle has zero area: its corners are on one line")
                uses.append((line_number, triangle.material, "triangle"))
                shapes().triangles.append(triangle)
            elif keyword == "mesh":
                mesh = read_mesh(words, path, mesh_folders, line_number)
                uses.append((line_number, mesh.material, "mesh"))
                if mesh.interior is not None and open_object is not None:
                    raise SceneError(f"object '{open_object.name}': an object's shapes hold "
                                     "no medium (interior)")
                shapes().meshes.append(mesh)
                if mesh.interior is not None:
                    interiors.append((line_number, mesh))
            elif keyword == "environment":
                if scene.environment is not None:
                    raise SceneError("a second environment (the first is on line "
                                     f"{scene.environment.line})")
                scene.environment = read_environment(words, path, mesh_folders,
                                                     line_number)
            elif keyword == "object":
                if len(words) != 2 or words[1] != "begin":
                    raise SceneError("'object' needs a name and the word begin: object NAME "
                                     "begin")
                if not NAME.match(words[0]):
                    raise SceneError(f"object name '{words[0]}': use letters, digits, '_' "
                                     "and '-', starting with a letter or '_'")
                if words[0] in scene.objects:
                    raise SceneError(f"object '{words[0]}' is already defined on line "
                                     f"{scene.objects[words[0]].line}")
                open_object = scene.objects[words[0]] = SceneObject(words[0], line_number)
            elif keyword == "end":
                if open_object is None:
                    raise SceneError("'end' without an 'object NAME begin' before it")
                if words:
                    raise SceneError(f"'end' takes nothing after it, got '{words[0]}'")
                if open_object.is_empty():
                    error = SceneError(f"object '{open_object.name}' is empty: put shapes "
                                       "between its begin and end")
                    error.line = open_object.line  # named at its `object` line
                    raise error
                open_object = None
            elif keyword == "instance":
                scene.instances.append(read_instance(words, line_number))
            else:
                raise SceneError(f"unknown keyword '{keyword}' (expected camera, texture, "
                                 "material, medium, sphere, quad, triangle, mesh, "
                                 "environment, object, end or instance)")
        except SceneError as error:
            fail(getattr(error, "line", line_number), str(error))

    if open_object is not None:
        fail(open_object.line, f"object '{open_object.name}' has no 'end'")
    object_shape_lines = {line: name for line, _, name in emitting_uses}

    for line_number, material, kind in uses:
        if material not in materials:
            fail(line_number, f"material '{material}' is not defined")
        if line_number in object_shape_lines and materials[material].emits:
            fail(line_number, f"object '{object_shape_lines[line_number]}': material "
                              f"'{material}' emits, and an object's shapes may not (a light "
                              "is placed as it is, not through instances)")
        # A sphere or a triangle line has no (u, v) to look a texture up with.
        if materials[material].texture is not None and kind not in ("quad", "mesh"):
            fail(line_number, f"material '{material}' is textured, and this shape has no "
                              "texture coordinates: textures apply to quads and meshes")
    for instance in scene.instances:
        if instance.object not in scene.objects:
            fail(instance.line, f"object '{instance.object}' is not defined")
    media_uses = [(line, shape.interior, shape) for line, shape in interiors]
    if camera is not None and camera.medium is not None:
        media_uses.insert(0, (camera_line, camera.medium, None))
    for line_number, medium, shape in sorted(media_uses, key=lambda use: use[0]):
        if medium not in scene.media:
            fail(line_number, f"medium '{medium}' is not defined")
        kind = materials[shape.material].kind if shape is not None else None
        if shape is not None and kind not in ("boundary", "dielectric"):
            fail(line_number, "an interior medium needs a surface light passes through, a "
                              f"'boundary' or 'dielectric' material; '{shape.material}' is "
                              f"{kind}")
    if camera is None:
        fail(0, "no camera: a scene needs one 'camera' line")
    scene.camera = camera
    scene.materials = materials
    if not scene.emitters() and scene.environment is None:  # an environment is a light
        fail(0, "no emitter: no shape uses a material with an emission")
    return scene


def load_scene(path, mesh_folders=()) -> Scene:
    """Reads a scene file; mesh_folders are searched for mesh paths after its folder."""
    path = absolute(path)
    try:
        data = path.read_bytes()
    except OSError as error:
        raise SceneError(f"{path}: cannot open ({error.strerror})") from None
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError:
        raise SceneError(f"{path}:0: not a text file (not UTF-8)") from None
    return parse_scene(text, path, mesh_folders)


def default_mesh_folders():
    """The build's generated assets (cmake/Assets.cmake): meshes/, textures/ and
    environments/."""
    return [Path(__file__).resolve().parents[1] / "build" / "assets"]
