"""The catalogues of submissions for the deterministic chapters, graded by comparing
pictures (kind 'image' in tools/course_tools/grading/grading_specs.py): correct ones
that draw the solution's picture another way (another form of the quadratic, another
camera basis, another triangle test), which must each score at least 90%, and plausible
wrong ones, which must each score at most half, each changing the pictures in its own
way so that the grader's diagnosis can name it. Registered in CATALOGUE as catalogue.py's
chapters are (grading_catalogue/__init__.py imports this module)."""

from __future__ import annotations

from grading_catalogue.catalogue import CATALOGUE
from grading_catalogue.variant import Edit, Variant

# ---------------------------------------------------------------- chapter 03

C = "03_camera_rays"
CAMERA = "shaders/camera.glsl"
BASIS = "chapters/camera.cpp"
HEIGHT = ("    float sensorHeight = camera.sensorWidth * float(imageSize.y) / "
          "float(imageSize.x);\n")
CENTRE = "    vec2 centre = (vec2(pixel) + 0.5) / vec2(imageSize);\n"
ACROSS_UP = """    float across = centre.x - 0.5;
    float upwards = 0.5 - centre.y;
"""
EYE_TO_PIXEL = """    vec3 eyeToPixel = camera.forward * camera.focalLength
                    + camera.right * (across * camera.sensorWidth)
                    + camera.up * (upwards * sensorHeight);
"""
RAY = "    return Ray(camera.eye, normalize(eyeToPixel));\n"
SIDE = "    glm::vec3 side = glm::cross(forward, up);\n"
TRUE_UP = "    glm::vec3 trueUp = glm::cross(right, forward);\n"

CHAPTER_03 = [
    Variant(C, "true up by Gram-Schmidt: up less its forward part", True, (
        Edit(BASIS, TRUE_UP,
             "    glm::vec3 trueUp = "
             "glm::normalize(up - glm::dot(up, forward) * forward);\n"),)),
    Variant(C, "right from the look direction before it is normalised", True, (
        Edit(BASIS, SIDE, "    glm::vec3 side = glm::cross(look, up);\n"),)),
    Variant(C, "pixel centre measured in pixels from the image's middle", True, (
        Edit(CAMERA, CENTRE + ACROSS_UP,
             "    vec2 middle = 0.5 * vec2(imageSize);\n"
             "    float across = (float(pixel.x) + 0.5 - middle.x) / float(imageSize.x);\n"
             "    float upwards = (middle.y - float(pixel.y) - 0.5) / float(imageSize.y);\n"
             ),)),
    Variant(C, "sensor offsets divided by the focal length (a sensor 1 m away)", True, (
        Edit(CAMERA, EYE_TO_PIXEL, """    vec3 eyeToPixel = camera.forward
                    + camera.right * (across * camera.sensorWidth / camera.focalLength)
                    + camera.up * (upwards * sensorHeight / camera.focalLength);
"""),)),
    Variant(C, "square pixels by the pixel's size in metres", True, (
        Edit(CAMERA, EYE_TO_PIXEL, """\
    float pixelSize = camera.sensorWidth / float(imageSize.x);
    vec2 offset = (vec2(pixel) + 0.5 - 0.5 * vec2(imageSize)) * pixelSize;
    vec3 eyeToPixel = camera.forward * camera.focalLength
                    + camera.right * offset.x - camera.up * offset.y;
"""),)),

    Variant(C, "image rows taken as counting upwards", False, (
        Edit(CAMERA, ACROSS_UP, ACROSS_UP.replace("0.5 - centre.y", "centre.y - 0.5")),),
        explanation="Row 0 is the top of the image, but the ray of row 0 looks down: "
                    "the picture is upside down.",
        section="Two classic mistakes"),
    Variant(C, "image columns taken as counting leftwards", False, (
        Edit(CAMERA, ACROSS_UP, ACROSS_UP.replace("centre.x - 0.5", "0.5 - centre.x")),),
        explanation="Column 0 is the left of the image, but its ray looks right: "
                    "the picture is mirrored left to right.",
        section="One ray per pixel"),
    Variant(C, "sensor as tall as it is wide", False, (
        Edit(CAMERA, HEIGHT, "    float sensorHeight = camera.sensorWidth;\n"),),
        explanation="The sensor's height ignores the image's shape: a wide picture is "
                    "squashed, circles become ellipses.",
        section="Two classic mistakes"),
    Variant(C, "sensor height from the aspect ratio upside down", False, (
        Edit(CAMERA, HEIGHT, HEIGHT.replace("float(imageSize.y) / float(imageSize.x)",
                                            "float(imageSize.x) / float(imageSize.y)")),),
        explanation="The sensor's height is its width times width / height instead of "
                    "height / width: the picture is squashed.",
        section="One ray per pixel"),
    Variant(C, "right as cross(up, forward)", False, (
        Edit(BASIS, SIDE, "    glm::vec3 side = glm::cross(up, forward);\n"),),
        explanation="cross(up, forward) points left, and the up built from it points "
                    "down: the picture is turned by 180 degrees.",
        section="The camera's basis"),
    Variant(C, "the given up used without making it perpendicular", False, (
        Edit(BASIS, TRUE_UP, "    glm::vec3 trueUp = up;\n"),),
        explanation="The up passed in is not perpendicular to forward when the camera "
                    "tilts: the picture is sheared vertically.",
        section="The camera's basis"),
    Variant(C, "ray direction not normalised", False, (
        Edit(CAMERA, RAY, "    return Ray(camera.eye, eyeToPixel);\n"),),
        explanation="The direction keeps the length of eye-to-sensor (centimetres): its "
                    "colours all end up near grey.",
        section="Directions as colours"),
    Variant(C, "pixel divided by the image size in integers", False, (
        Edit(CAMERA, CENTRE, "    vec2 centre = vec2(pixel / imageSize) + 0.5;\n"),),
        explanation="pixel / imageSize divides unsigned integers, which gives 0: every "
                    "pixel gets the same ray and one colour.",
        section="One ray per pixel"),
]

CATALOGUE["03"] = CHAPTER_03


# ---------------------------------------------------------------- chapter 04

S = "04_spheres"
SPHERE = "shaders/sphere.glsl"
# The geometric intersection of chapters 04 to 06, from its first line to its return.
GEOMETRIC = """\
    // 1. Project the centre onto the ray: tClosest is where the ray passes closest.
    vec3 toCenter = sphere.center - ray.origin;
    float tClosest = dot(toCenter, ray.direction);
    // 2. How close it passes: the vector from that point to the centre. (Computed as a
    //    vector, not as |toCenter|^2 - tClosest^2, which cancels badly when far away.)
    vec3 closestToCenter = toCenter - tClosest * ray.direction;
    float missBySquared = dot(closestToCenter, closestToCenter);
    float radiusSquared = sphere.radius * sphere.radius;
    if (missBySquared > radiusSquared) return false;  // passes outside the sphere
    // 3. Pythagoras: the ray is inside the sphere for halfChord either side of it.
    float halfChord = sqrt(radiusSquared - missBySquared);
    t = tClosest - halfChord;                      // where the ray enters ...
    if (t <= tMin) t = tClosest + halfChord;       // ... or leaves, if it starts inside
    return t > tMin && t < tMax;
"""
ENTRY = """    t = tClosest - halfChord;                      // where the ray enters ...
    if (t <= tMin) t = tClosest + halfChord;       // ... or leaves, if it starts inside
"""
HALF_B = """    vec3 fromCenter = ray.origin - sphere.center;
    float b = dot(fromCenter, ray.direction);
    float c = dot(fromCenter, fromCenter) - sphere.radius * sphere.radius;
    float discriminant = b * b - c;
    if (discriminant < 0.0) return false;
    float root = sqrt(discriminant);
    t = -b - root;
    if (t <= tMin) t = -b + root;
    return t > tMin && t < tMax;
"""
TEXTBOOK = """    vec3 fromCenter = ray.origin - sphere.center;
    float a = dot(ray.direction, ray.direction);
    float b = 2.0 * dot(fromCenter, ray.direction);
    float c = dot(fromCenter, fromCenter) - sphere.radius * sphere.radius;
    float discriminant = b * b - 4.0 * a * c;
    if (discriminant < 0.0) return false;
    float root = sqrt(discriminant);
    t = (-b - root) / (2.0 * a);
    if (t <= tMin) t = (-b + root) / (2.0 * a);
    return t > tMin && t < tMax;
"""
STABLE = """    vec3 fromCenter = ray.origin - sphere.center;
    float b = dot(fromCenter, ray.direction);
    float c = dot(fromCenter, fromCenter) - sphere.radius * sphere.radius;
    float discriminant = b * b - c;
    if (discriminant < 0.0) return false;
    // The root that adds magnitudes, and the other from the product of the roots, c.
    float q = b < 0.0 ? -b + sqrt(discriminant) : -b - sqrt(discriminant);
    float t0 = min(q, c / q), t1 = max(q, c / q);
    t = t0 > tMin ? t0 : t1;
    return t > tMin && t < tMax;
"""
MISS_BY = """    vec3 closestToCenter = toCenter - tClosest * ray.direction;
    float missBySquared = dot(closestToCenter, closestToCenter);
"""
SPHERE_NORMAL = "(position - sphere.center) / sphere.radius"

CHAPTER_04 = [
    Variant(S, "quadratic formula with the half b", True, (
        Edit(SPHERE, GEOMETRIC, HALF_B),)),
    Variant(S, "textbook quadratic formula with a, b and c", True, (
        Edit(SPHERE, GEOMETRIC, TEXTBOOK),)),
    Variant(S, "quadratic solved without cancellation (the product of the roots)", True, (
        Edit(SPHERE, GEOMETRIC, STABLE),)),
    Variant(S, "miss distance by Pythagoras on lengths", True, (
        Edit(SPHERE, MISS_BY, "    float missBySquared = dot(toCenter, toCenter) - "
                              "tClosest * tClosest;\n"),)),
    Variant(S, "normal normalised instead of divided by the radius", True, (
        Edit(SPHERE, SPHERE_NORMAL, "normalize(position - sphere.center)"),)),

    Variant(S, "the far root instead of the near one", False, (
        Edit(SPHERE, ENTRY, "    t = tClosest + halfChord;  // the larger root\n"),),
        explanation="t is where the ray leaves the sphere, not where it enters: each sphere "
                    "shows its far side's normals.",
        section="Where a ray meets a sphere"),
    Variant(S, "centre minus origin the wrong way round", False, (
        Edit(SPHERE, "    vec3 toCenter = sphere.center - ray.origin;\n",
             "    vec3 toCenter = ray.origin - sphere.center;\n"),),
        explanation="toCenter points from the centre to the eye: every sphere is looked for "
                    "behind the camera and none is seen.",
        section="Where a ray meets a sphere"),
    Variant(S, "radius where its square belongs", False, (
        Edit(SPHERE, "    float radiusSquared = sphere.radius * sphere.radius;\n",
             "    float radiusSquared = sphere.radius;\n"),),
        explanation="The radius is compared with squared distances: spheres smaller than 1 "
                    "grow, their normals too long.",
        section="Where a ray meets a sphere"),
    Variant(S, "discriminant without its 4", False, (
        Edit(SPHERE, GEOMETRIC, TEXTBOOK.replace("b * b - 4.0 * a * c", "b * b - a * c")),),
        explanation="The discriminant is b^2 - ac, not b^2 - 4ac: rays that pass the "
                    "spheres by meet them, filling the picture.",
        section="Geometric or quadratic?"),
    Variant(S, "roots of the quadratic not divided by 2a", False, (
        Edit(SPHERE, GEOMETRIC, TEXTBOOK.replace("(-b - root) / (2.0 * a)", "-b - root")
             .replace("(-b + root) / (2.0 * a)", "-b + root")),),
        explanation="The roots are not divided by 2a: each hit lies twice as far, behind "
                    "the sphere, with wrong normals.",
        section="Geometric or quadratic?"),
    Variant(S, "normal pointing into the sphere", False, (
        Edit(SPHERE, SPHERE_NORMAL, "(sphere.center - position) / sphere.radius"),),
        explanation="The normal points from the surface to the centre: every sphere's "
                    "colours are inverted.",
        section="The nearest hit"),
    Variant(S, "normal not divided by the radius", False, (
        Edit(SPHERE, SPHERE_NORMAL, "(position - sphere.center)"),),
        explanation="position - center is as long as the radius, not of unit length: "
                    "small spheres' colours fade to grey.",
        section="Normals as colours, and a sky"),
]

CATALOGUE["04"] = CHAPTER_04


# ---------------------------------------------------------------- chapter 05

L = "05_shading_shadows"
SHADING = "shaders/shading.glsl"
SHADOW_ORIGIN = "    vec3 shadowOrigin = hit.position + hit.normal * shadowOffset;\n"
TO_LIGHT = "    vec3 toLight = lightPosition - shadowOrigin;\n"
SHADOW_RAY = "    Ray shadowRay = Ray(shadowOrigin, toLight / lightDistance);\n"
VISIBLE = "    float visible = anyHit(shadowRay, 0.0, lightDistance) ? 0.0 : 1.0;\n"
COSINE = "    float cosine = max(0.0, dot(hit.normal, shadowRay.direction));\n"
LAMBERT = "    return hit.albedo * (AMBIENT + (1.0 - AMBIENT) * visible * cosine);\n"
PLANE_T = "    t = (plane.offset - dot(plane.normal, ray.origin)) / approach;\n"

CHAPTER_05 = [
    Variant(L, "Lambert's cosine towards the light from the hit point itself", True, (
        Edit(SHADING, COSINE, "    float cosine = max(0.0, dot(hit.normal, "
                              "normalize(lightPosition - hit.position)));\n"),)),
    Variant(L, "ambient and direct light blended with mix()", True, (
        Edit(SHADING, LAMBERT,
             "    return hit.albedo * mix(visible * cosine, 1.0, AMBIENT);\n"),)),
    Variant(L, "no shadow ray where the surface faces away from the light", True, (
        Edit(SHADING, SHADOW_RAY, SHADOW_RAY + "    if (dot(hit.normal, shadowRay.direction)"
                                               " <= 0.0) return hit.albedo * AMBIENT;\n"),)),
    Variant(L, "shadow ray asked for its nearest hit", True, (
        Edit(SHADING, VISIBLE,
             "    Hit blocker;\n"
             "    float visible = nearestHit(shadowRay, 0.0, lightDistance, blocker) "
             "? 0.0 : 1.0;\n"),)),
    Variant(L, "plane met through its point nearest the origin", True, (
        Edit("shaders/plane.glsl", PLANE_T,
             "    t = dot(plane.normal * plane.offset - ray.origin, plane.normal) "
             "/ approach;\n"),)),
    Variant(L, "shadow ray from the hit point with tMin as the offset", True, (
        Edit(SHADING, SHADOW_ORIGIN, "    vec3 shadowOrigin = hit.position;\n"),
        Edit(SHADING, VISIBLE, VISIBLE.replace("0.0, lightDistance", "shadowOffset, "
                                                                     "lightDistance")))),

    Variant(L, "no shadow rays", False, (
        Edit(SHADING, VISIBLE, "    float visible = 1.0;\n"),),
        explanation="Nothing is ever in the light's way: there are no shadows, every "
                    "surface facing the light is lit.",
        section="Shadow rays"),
    Variant(L, "shadow rays start on the surface", False, (
        Edit(SHADING, SHADOW_ORIGIN, "    vec3 shadowOrigin = hit.position;\n"),),
        explanation="Shadow rays start exactly at the rounded hit point, often inside the "
                    "surface: lit sides get dark speckles.",
        section="The famous bug: shadow acne"),
    Variant(L, "direction to the light the wrong way round", False, (
        Edit(SHADING, TO_LIGHT, "    vec3 toLight = shadowOrigin - lightPosition;\n"),),
        explanation="toLight points away from the light: every shadow ray is blocked, "
                    "and only the ambient light is left.",
        section="Lambert's cosine law"),
    Variant(L, "shadow ray direction not normalised", False, (
        Edit(SHADING, SHADOW_RAY, "    Ray shadowRay = Ray(shadowOrigin, toLight);\n"),),
        explanation="The direction to the light keeps its length of metres: the cosine "
                    "is far above 1 and the lit parts burn white.",
        section="Lambert's cosine law"),
    Variant(L, "no ambient light", False, (
        Edit(SHADING, LAMBERT, "    return hit.albedo * visible * cosine;\n"),),
        explanation="The ambient term is left out: shadows and sides facing away from the "
                    "light are pitch black.",
        section="Lambert's cosine law"),
    Variant(L, "ambient light added on top of the full direct light", False, (
        Edit(SHADING, LAMBERT, "    return hit.albedo * (AMBIENT + visible * cosine);\n"),),
        explanation="Direct light is not scaled by 1 - ambient: every lit surface is up to "
                    "a tenth of its albedo too bright.",
        section="Lambert's cosine law"),
    Variant(L, "plane equation with the wrong sign", False, (
        Edit("shaders/plane.glsl", PLANE_T,
             "    t = (dot(plane.normal, ray.origin) - plane.offset) / approach;\n"),),
        explanation="t has the wrong sign: the floor is met behind rays that look down, "
                    "so rays that look up see it instead.",
        section="A floor: the infinite plane"),
]

CATALOGUE["05"] = CHAPTER_05


# ---------------------------------------------------------------- chapter 06

T = "06_triangles"
TRIANGLE = "shaders/triangle.glsl"
# Moller-Trumbore as chapter 06 writes it, from its first line to its return.
MOLLER_TRUMBORE = """    vec3 edge1 = triangle.p1 - triangle.p0;
    vec3 edge2 = triangle.p2 - triangle.p0;
    // Cramer's rule on the 3x3 system [-direction, edge1, edge2] (t, u, v) = toOrigin,
    // each determinant written as a scalar triple product, sharing two cross products.
    vec3 p = cross(ray.direction, edge2);
    float determinant = dot(edge1, p);
    // Zero: the ray runs parallel to the triangle's plane. Negative: it comes from the
    // back; both sides count, so only the size is tested.
    if (abs(determinant) < 1e-12) return false;
    float inverse = 1.0 / determinant;
    vec3 toOrigin = ray.origin - triangle.p0;
    float u = dot(toOrigin, p) * inverse;
    if (u < 0.0 || u > 1.0) return false;  // outside the edge opposite p1
    vec3 q = cross(toOrigin, edge1);
    float v = dot(ray.direction, q) * inverse;
    if (v < 0.0 || u + v > 1.0) return false;  // outside the other two edges
    t = dot(edge2, q) * inverse;
    barycentric = vec2(u, v);
    return t > tMin && t < tMax;
"""
# The same solve with the triangle's normal as one of the cross products (as in
# Inigo Quilez's well-known shader).
NORMAL_FORM = """    vec3 edge1 = triangle.p1 - triangle.p0;
    vec3 edge2 = triangle.p2 - triangle.p0;
    vec3 toOrigin = ray.origin - triangle.p0;
    vec3 n = cross(edge1, edge2);
    vec3 q = cross(toOrigin, ray.direction);
    float facing = dot(ray.direction, n);
    if (abs(facing) < 1e-12) return false;
    float d = 1.0 / facing;
    float u = d * dot(-q, edge2);
    float v = d * dot(q, edge1);
    t = d * dot(-n, toOrigin);
    if (u < 0.0 || v < 0.0 || u + v > 1.0) return false;
    barycentric = vec2(u, v);
    return t > tMin && t < tMax;
"""
# The reference's way: the plane first, then the point's barycentric coordinates.
EDGE_FUNCTIONS = """    vec3 edge1 = triangle.p1 - triangle.p0;
    vec3 edge2 = triangle.p2 - triangle.p0;
    vec3 n = cross(edge1, edge2);
    float approach = dot(n, ray.direction);
    if (abs(approach) < 1e-12) return false;
    t = dot(n, triangle.p0 - ray.origin) / approach;
    vec3 fromP0 = ray.origin + t * ray.direction - triangle.p0;
    float area = dot(n, n);
    float u = dot(cross(fromP0, edge2), n) / area;
    float v = dot(cross(edge1, fromP0), n) / area;
    if (u < 0.0 || v < 0.0 || u + v > 1.0) return false;
    barycentric = vec2(u, v);
    return t > tMin && t < tMax;
"""
U_TEST = "    if (u < 0.0 || u > 1.0) return false;  // outside the edge opposite p1\n"
UV_TEST = "    if (v < 0.0 || u + v > 1.0) return false;  // outside the other two edges\n"
DETERMINANT = "    if (abs(determinant) < 1e-12) return false;\n"
FLIP = "    if (flipNormals && dot(normal, ray.direction) > 0.0) normal = -normal;\n"
TRIANGLE_NORMAL = "    vec3 normal = normalize(cross(edge1, edge2));\n"

CHAPTER_06 = [
    Variant(T, "Moller-Trumbore around the triangle's normal", True, (
        Edit(TRIANGLE, MOLLER_TRUMBORE, NORMAL_FORM),)),
    Variant(T, "the plane first, then barycentric coordinates by areas", True, (
        Edit(TRIANGLE, MOLLER_TRUMBORE, EDGE_FUNCTIONS),)),
    Variant(T, "all three barycentric tests at the end", True, (
        Edit(TRIANGLE, U_TEST, ""),
        Edit(TRIANGLE, UV_TEST, "    if (u < 0.0 || v < 0.0 || u + v > 1.0) return false;\n"))),
    Variant(T, "normal turned with faceforward()", True, (
        Edit(TRIANGLE, FLIP,
             "    if (flipNormals) normal = faceforward(normal, ray.direction, normal);\n"),)),
    Variant(T, "normal from the edges in the other order", True, (
        Edit(TRIANGLE, TRIANGLE_NORMAL,
             "    vec3 normal = normalize(cross(edge2, edge1));\n"),)),

    Variant(T, "u + v > 1 accepted", False, (
        Edit(TRIANGLE, UV_TEST, "    if (v < 0.0 || v > 1.0) return false;\n"),),
        explanation="Only u and v are tested, each on its own, not u + v <= 1: every "
                    "triangle becomes a parallelogram.",
        section="Where a ray meets a triangle: Möller–Trumbore"),
    Variant(T, "back faces culled", False, (
        Edit(TRIANGLE, DETERMINANT, "    if (determinant < 1e-12) return false;\n"),),
        explanation="The determinant's test has no abs(): triangles seen from behind, "
                    "the floor among them, disappear.",
        section="Where a ray meets a triangle: Möller–Trumbore"),
    Variant(T, "front faces culled", False, (
        Edit(TRIANGLE, DETERMINANT, "    if (determinant > -1e-12) return false;\n"),),
        explanation="Triangles seen from the front are skipped: the pyramid shows the "
                    "unlit inside of its far faces.",
        section="Where a ray meets a triangle: Möller–Trumbore"),
    Variant(T, "ray origin minus p0 the wrong way round", False, (
        Edit(TRIANGLE, "    vec3 toOrigin = ray.origin - triangle.p0;\n",
             "    vec3 toOrigin = triangle.p0 - ray.origin;\n"),),
        explanation="toOrigin points from the ray to p0: u, v and t change sign and the "
                    "triangles are met behind the camera.",
        section="Where a ray meets a triangle: Möller–Trumbore"),
    Variant(T, "t not divided by the determinant", False, (
        Edit(TRIANGLE, "    t = dot(edge2, q) * inverse;\n", "    t = dot(edge2, q);\n"),),
        explanation="t is not scaled by 1 / determinant: triangles seen from behind vanish, "
                    "the others are met at wrong distances.",
        section="Where a ray meets a triangle: Möller–Trumbore"),
    Variant(T, "second edge from p1 instead of p0", False, (
        Edit(TRIANGLE, "    vec3 edge2 = triangle.p2 - triangle.p0;\n    // Cramer's",
             "    vec3 edge2 = triangle.p2 - triangle.p1;\n    // Cramer's"),),
        explanation="edge2 runs from p1, not p0, to p2: each triangle is met as another one, "
                    "with a corner moved.",
        section="Where a ray meets a triangle: Möller–Trumbore"),
    Variant(T, "v from the origin's vector instead of the direction", False, (
        Edit(TRIANGLE, "    float v = dot(ray.direction, q) * inverse;\n",
             "    float v = dot(toOrigin, q) * inverse;\n"),),
        explanation="v is dot(toOrigin, q), which is always 0: triangles become endless "
                    "bands between two parallel lines.",
        section="Where a ray meets a triangle: Möller–Trumbore"),
    Variant(T, "normals not turned towards the ray", False, (
        Edit(TRIANGLE, FLIP, ""),),
        explanation="The normal keeps the corners' winding: the floor, seen from behind, "
                    "faces away from the light and is dark.",
        section="Which way is up? Two-sided triangles"),
    Variant(T, "normals turned away from the ray", False, (
        Edit(TRIANGLE, FLIP, FLIP.replace("> 0.0", "< 0.0")),),
        explanation="The flip's test is backwards: every triangle faces away from the "
                    "camera and shows only ambient light.",
        section="Which way is up? Two-sided triangles"),
]

CATALOGUE["06"] = CHAPTER_06


# ---------------------------------------------------------------- chapter 07

M = "07_obj_teapot"
FRAMING = "chapters/scene.cpp"
DISTANCE = "    float distance = radius / std::sin(halfFov);\n"
RESOLVED = ("        const long long resolved = index > 0 ? index - 1 : "
            "(long long)count + index;\n")
CORNERS = """\
    return Corners(positions[triangle.corners.x].xyz, positions[triangle.corners.y].xyz,
                   positions[triangle.corners.z].xyz);
"""

CHAPTER_07 = [
    Variant(M, "distance by Pythagoras from the tangent's adjacent side", True, (
        Edit(FRAMING, DISTANCE,
             "    float distance = std::hypot(radius, radius / std::tan(halfFov));\n"),)),
    Variant(M, "negative OBJ indices tested first", True, (
        Edit("chapters/obj_loader.cpp", RESOLVED,
             "        const long long resolved = index < 0 ? (long long)count + index "
             ": index - 1;\n"),)),
    Variant(M, "corner indices read once as a uvec3", True, (
        Edit("shaders/scene.glsl", CORNERS, """    uvec3 index = triangle.corners;
    return Corners(positions[index[0]].xyz, positions[index[1]].xyz,
                   positions[index[2]].xyz);
"""),)),

    Variant(M, "framing distance by the tangent", False, (
        Edit(FRAMING, DISTANCE, "    float distance = radius / std::tan(halfFov);\n"),),
        explanation="tan(halfFov) stands where sin(halfFov) belongs: the camera stands "
                    "too close and the teapot looks too big.",
        section="Framing any mesh"),
    Variant(M, "framing by the whole angle of view", False, (
        Edit(FRAMING, DISTANCE, "    float distance = radius / std::sin(2.0f * halfFov);\n"),),
        explanation="The whole angle of view stands where its half belongs: the camera "
                    "is far too close, the teapot huge.",
        section="Framing any mesh"),
    Variant(M, "framing by the wider angle of view", False, (
        Edit(FRAMING, "std::min(kSensorWidth, sensorHeight)",
             "std::max(kSensorWidth, sensorHeight)"),),
        explanation="The distance fits the wider angle of view, not the narrower one: the "
                    "teapot is framed too tightly.",
        section="Framing any mesh"),
    Variant(M, "one corner looked up twice", False, (
        Edit("shaders/scene.glsl", CORNERS, CORNERS.replace("corners.z", "corners.y")),),
        explanation="The third corner is looked up with the second's index: each triangle "
                    "collapses to a line, nothing is drawn.",
        section="The mesh on the GPU"),
    Variant(M, "indices made 0-based twice", False, (
        Edit("shaders/scene.glsl", CORNERS, """\
    return Corners(positions[triangle.corners.x - 1u].xyz,
                   positions[triangle.corners.y - 1u].xyz,
                   positions[triangle.corners.z - 1u].xyz);
"""),),
        explanation="The reader already made the indices 0-based; subtracting 1 again "
                    "takes each corner's neighbour: broken faces.",
        section="The off-by-one"),
    Variant(M, "positions uploaded as packed vec3", False, (
        Edit("chapters/main.cpp", "        if (packedVec3Bug)",
             "        if (!packedVec3Bug)"),),
        explanation="12-byte glm::vec3s are read 16 bytes apart: vertices come from the "
                    "wrong bytes, the teapot is scrambled.",
        section="vec3 in std430: the bug in the picture"),
    Variant(M, "light not scaled with the mesh", False, (
        Edit(FRAMING, "    scene.lightPosition = center + radius * kLightOffset;\n",
             "    scene.lightPosition = center + kLightOffset;\n"),),
        explanation="The light's offset is not multiplied by the radius: the light is too "
                    "close, and the shading and shadow change.",
        section="Framing any mesh"),
    Variant(M, "floor through the mesh's centre", False, (
        Edit(FRAMING, "y = bounds.lo.y;", "y = center.y;"),),
        explanation="The floor is at the centre's height, not the lowest point's: it cuts "
                    "the teapot in half.",
        section="Framing any mesh"),
]

CATALOGUE["07"] = CHAPTER_07


# ---------------------------------------------------------------- chapter 08

N = "08_phong_normals"
BLEND = "    vec3 blended = (1.0 - u - v) * normals.n0 + u * normals.n1 + v * normals.n2;\n"
SMOOTH_RETURN = "    return length(blended) > 1e-12 ? normalize(blended) : flatNormal;\n"
SIDE_FLIP = """    if (flipNormals && dot(geometricNormal, ray.direction) > 0.0) {
        geometricNormal = -geometricNormal;
        normal = -normal;
    }
"""

CHAPTER_08 = [
    Variant(N, "normals blended by a matrix", True, (
        Edit(TRIANGLE, BLEND, "    vec3 blended = mat3(normals.n0, normals.n1, normals.n2) "
                              "* vec3(1.0 - u - v, u, v);\n"),)),
    Variant(N, "corner normals normalised before blending", True, (
        Edit(TRIANGLE, BLEND, BLEND.replace("normals.n0", "normalize(normals.n0)")
             .replace("normals.n1", "normalize(normals.n1)")
             .replace("normals.n2", "normalize(normals.n2)")),)),
    Variant(N, "both normals turned by one sign", True, (
        Edit(TRIANGLE, SIDE_FLIP, """\
    float side = flipNormals && dot(geometricNormal, ray.direction) > 0.0 ? -1.0 : 1.0;
    geometricNormal *= side;
    normal *= side;
"""),)),
    Variant(N, "cancelling normals tested by the squared length", True, (
        Edit(TRIANGLE, SMOOTH_RETURN, "    return dot(blended, blended) > 1e-24 ? "
                                      "normalize(blended) : flatNormal;\n"),)),

    Variant(N, "barycentric weights on the wrong corners", False, (
        Edit(TRIANGLE, BLEND, "    vec3 blended = u * normals.n0 + v * normals.n1 + "
                              "(1.0 - u - v) * normals.n2;\n"),),
        explanation="Each corner's normal gets another corner's weight: the shading jumps "
                    "at every edge, in a pattern of facets.",
        section="Blending normals with barycentric coordinates"),
    Variant(N, "u and v swapped in the blend", False, (
        Edit(TRIANGLE, BLEND, "    vec3 blended = (1.0 - u - v) * normals.n0 + "
                              "v * normals.n1 + u * normals.n2;\n"),),
        explanation="u weighs p1's normal and v p2's, not the other way round: the shading "
                    "is creased along the triangles.",
        section="Blending normals with barycentric coordinates"),
    Variant(N, "blended normal not normalised", False, (
        Edit(TRIANGLE, SMOOTH_RETURN, "    return blended;\n"),),
        explanation="A blend of unit normals is shorter than 1 inside a triangle: the "
                    "teapot darkens towards triangles' middles.",
        section="Blending normals with barycentric coordinates"),
    Variant(N, "flat normals only", False, (
        Edit(TRIANGLE, SMOOTH_RETURN, "    return flatNormal;\n"),),
        explanation="The corners' normals are not used: the teapot is shaded flat, "
                    "triangle by triangle, as in chapter 07.",
        section="Normals at the corners"),
    Variant(N, "only the flat normal turned to face the ray", False, (
        Edit(TRIANGLE, SIDE_FLIP, SIDE_FLIP.replace("        normal = -normal;\n", "")),),
        explanation="The smooth normal is not turned with the flat one: surfaces seen from "
                    "behind, the floor among them, go dark.",
        section="Which side? Ask the flat triangle"),
]

CATALOGUE["08"] = CHAPTER_08
