// The scene: spheres, quads and triangles, each with a material and, if it glows, its
// place in the emitter list, read along the path scene_code.glsl chose
// (scene_memory.glsl); the triangles' normals and texture coordinates in storage
// buffers (textures.glsl). A ray tests every sphere and quad (a scene has a few dozen)
// and finds its triangles (a mesh may have millions) through the bounding volume
// hierarchy: bvh_traversal.glsl, compiled in only for a scene with triangles.
//
// The counts are numbers in the shader (scene_code.glsl): the compiler knows every
// loop's length, unrolls the short ones and drops a loop that never runs.

#include "scene_memory.glsl"
layout(std430, binding = NORMALS_BINDING) readonly buffer Normals { vec4 normals[]; };
// The meshes' texture coordinates, the textures and their texels: albedoAt.
#include "textures.glsl"

// What a ray found.
struct Hit {
    float t;
    vec3 position;
    vec3 normal;           // unit, on the front side: to shade with (smooth on a mesh)
    vec3 geometricNormal;  // unit, on the front side: the surface's own, flat
    bool front;            // did the ray arrive at the front of the surface itself?
    uint material;
    uint emitter;          // index into the emitter list, or NO_EMITTER
    vec2 uv;               // texture coordinates: a quad's (a, b), a mesh's from its vt
};

// The nearer root of |origin + t direction - centre|^2 = r^2 inside (tMin, tMax).
bool hitSphere(Ray ray, Sphere sphere, float tMin, float tMax, out float t) {
    vec3 toOrigin = ray.origin - sphere.center;
    float halfB = dot(toOrigin, ray.direction);
    float c = dot(toOrigin, toOrigin) - sphere.radius * sphere.radius;
    float discriminant = halfB * halfB - c;
    if (discriminant < 0.0) return false;
    float root = sqrt(discriminant);
    // -b - sqrt(...) loses digits when b is large and negative: q / a is exact there.
    float q = -halfB - (halfB >= 0.0 ? root : -root);
    if (q == 0.0) return false;  // the origin on the sphere, the ray along its tangent
    float t1 = q, t2 = c / q;
    t = min(t1, t2);
    if (t <= tMin) t = max(t1, t2);
    return t > tMin && t < tMax;
}

// Where the ray meets the quad's plane, if the point is inside the parallelogram; ab is
// the point's place along the edges, the quad's texture coordinates.
bool hitQuad(Ray ray, Quad quad, float tMin, float tMax, out float t, out vec2 ab) {
    vec3 normal = cross(quad.edge1, quad.edge2);
    float facing = dot(normal, ray.direction);
    if (abs(facing) < 1e-20) return false;  // parallel to the plane
    t = dot(normal, quad.origin - ray.origin) / facing;
    if (!(t > tMin && t < tMax)) return false;
    // The point's coordinates along the two edges, each in [0, 1] inside: solve
    // p = origin + a edge1 + b edge2 with the dual vectors of the edges.
    vec3 p = ray.origin + t * ray.direction - quad.origin;
    vec3 w = normal / dot(normal, normal);
    float a = dot(w, cross(p, quad.edge2));
    float b = dot(w, cross(quad.edge1, p));
    ab = vec2(a, b);
    return a >= 0.0 && a <= 1.0 && b >= 0.0 && b <= 1.0;
}

// Chapter 09's triangles: hitTriangle, smoothNormal, triangleHit.
#include "triangle.glsl"

// --8<-- [start:bvh_interface]
// What bvh_traversal.glsl asks for: triangle `index` of the buffer, which the host
// filled in the tree's leaf order, and where on it (uv, for the smooth normal).
bool hitTriangle(Ray ray, uint index, float tMin, float tMax, out float t, out vec2 uv) {
    // Its corners from the copy in leaf order: three reads, no indices to follow.
    Corners corners = Corners(leafCornerAt(3u * index), leafCornerAt(3u * index + 1u),
                              leafCornerAt(3u * index + 2u));
    return hitTriangle(ray, corners, tMin, tMax, t, uv);
}
#if HAS_TRIANGLES
#include "bvh_traversal.glsl"
#else
uint bvhLoopIterations = 0u;  // no tree, no steps (--view cost)
#endif

// --brute-force (bruteForce in the PathParameters block, shared.h): test every
// triangle, as chapter 12 does.
// --8<-- [end:bvh_interface]

// Fills in a hit on a sphere or a quad from its front normal, material, emitter and
// texture coordinates: the same normal to shade with and to tell the sides apart.
Hit makeHit(Ray ray, float t, vec3 frontNormal, uint material, uint emitter, vec2 uv) {
    vec3 normal = normalize(frontNormal);
    return Hit(t, ray.origin + t * ray.direction, normal, normal,
               dot(normal, ray.direction) < 0.0, material, emitter, uv);
}

// What a hit needs of the sphere or quad it found, kept as the tests go: a sphere's
// centre or a quad's front normal, its material and emitter. Nothing is then read by an
// index known only at run time, which llvmpipe does one lane at a time.
struct Found {
    vec3 centreOrNormal;
    uint material;
    uint emitter;
};
Found foundSphere(Sphere s) { return Found(s.center, s.material, s.emitter); }
Found foundQuad(Quad q) { return Found(cross(q.edge1, q.edge2), q.material, q.emitter); }

// --8<-- [start:written_out]
// A scene in constants (MEMORY_CONSTANTS) has each shape's test written out, not
// looped: FOR_EACH_QUAD(TEST), from scene_code.glsl, is TEST(0) TEST(1) ... With its
// index a number, each test reads its own shape's constants, and the compiler folds
// what depends on them alone (a quad's normal, its dual vectors) into numbers.
#define NEAREST_SPHERE(i) if (hitSphere(ray, SCENE_SPHERES[i], tMin, tMax, t)) { \
        tMax = t; kind = SHAPE_SPHERE; found = foundSphere(SCENE_SPHERES[i]); }
#define NEAREST_QUAD(i) if (hitQuad(ray, SCENE_QUADS[i], tMin, tMax, t, ab)) { \
        tMax = t; kind = SHAPE_QUAD; found = foundQuad(SCENE_QUADS[i]); hitAb = ab; }
// A shadow ray: no return inside the tests. Each return would put every test after it
// in an else branch, nested as deep as the scene has shapes, and llvmpipe draws wrong
// pictures past some depth; one test after the other, each skipped once blocked, is flat.
#define ANY_SPHERE(i) if (!blocked && hitSphere(ray, SCENE_SPHERES[i], tMin, tMax, t)) \
        blocked = true;
#define ANY_QUAD(i) if (!blocked && hitQuad(ray, SCENE_QUADS[i], tMin, tMax, t, ab)) \
        blocked = true;
// --8<-- [end:written_out]

// --8<-- [start:nearest]
// The nearest surface along the ray, between tMin and tMax.
bool nearestHit(Ray ray, float tMin, float tMax, out Hit hit) {
    int kind = -1, index = 0;  // index: a triangle's
    Found found;
    float t;
    vec2 barycentric, hitBarycentric, ab, hitAb;
#if SCENE_MEMORY == MEMORY_CONSTANTS
    FOR_EACH_SPHERE(NEAREST_SPHERE)
    FOR_EACH_QUAD(NEAREST_QUAD)
#else
    for (int i = 0; i < SPHERE_COUNT; ++i) {
        Sphere s = sphereAt(i);
        if (hitSphere(ray, s, tMin, tMax, t)) {
            tMax = t; kind = SHAPE_SPHERE; found = foundSphere(s);
        }
    }
    for (int i = 0; i < QUAD_COUNT; ++i) {
        Quad q = quadAt(i);
        if (hitQuad(ray, q, tMin, tMax, t, ab)) {
            tMax = t; kind = SHAPE_QUAD; found = foundQuad(q); hitAb = ab;
        }
    }
#endif
    // The triangles: the tree finds the nearest one nearer than tMax (the nearest
    // sphere or quad so far), or brute force tries them all.
#if HAS_TRIANGLES
    if (bruteForce != 0u) {
        for (int i = 0; i < TRIANGLE_COUNT; ++i)
            if (hitTriangle(ray, uint(i), tMin, tMax, t, barycentric)) {
                tMax = t; kind = SHAPE_TRIANGLE; index = i; hitBarycentric = barycentric;
            }
        bvhLoopIterations += uint(TRIANGLE_COUNT);  // for --view cost
    } else {
        uint triangle;
        if (bvhNearestHit(ray, tMin, tMax, triangle, t, barycentric)) {
            tMax = t; kind = SHAPE_TRIANGLE; index = int(triangle); hitBarycentric = barycentric;
        }
    }
#endif
    // Normals only for the one shape that was hit.
    if (kind == SHAPE_SPHERE) {
        hit = makeHit(ray, tMax, ray.origin + tMax * ray.direction - found.centreOrNormal,
                      found.material, found.emitter, vec2(0.0));  // no texture on spheres
    } else if (kind == SHAPE_QUAD) {
        hit = makeHit(ray, tMax, found.centreOrNormal, found.material, found.emitter, hitAb);
    } else if (kind == SHAPE_TRIANGLE) {
        hit = triangleHit(ray, tMax, hitBarycentric, triangleAt(uint(index)));
    }
    return kind >= 0;
}
// --8<-- [end:nearest]

// Is anything in the way between tMin and tMax? Any hit will do (a shadow ray).
bool anyHit(Ray ray, float tMin, float tMax) {
    float t;
    vec2 barycentric, ab;
#if SCENE_MEMORY == MEMORY_CONSTANTS
    bool blocked = false;
    FOR_EACH_SPHERE(ANY_SPHERE)
    FOR_EACH_QUAD(ANY_QUAD)
    if (blocked) return true;
#else
    for (int i = 0; i < SPHERE_COUNT; ++i)
        if (hitSphere(ray, sphereAt(i), tMin, tMax, t)) return true;
    for (int i = 0; i < QUAD_COUNT; ++i)
        if (hitQuad(ray, quadAt(i), tMin, tMax, t, ab)) return true;
#endif
#if HAS_TRIANGLES
    if (bruteForce == 0u) return bvhAnyHit(ray, tMin, tMax);
    for (int i = 0; i < TRIANGLE_COUNT; ++i)
        if (hitTriangle(ray, uint(i), tMin, tMax, t, barycentric)) return true;
#endif
    return false;
}
