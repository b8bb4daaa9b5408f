// The scene: spheres, quads and triangles in storage buffers, each with a material
// and, if it glows, its place in the emitter list; the triangles' corners, normals and
// texture coordinates in three more (textures.glsl). A ray tests every sphere and quad
// (a scene has a few dozen) and finds its triangles (a mesh may have millions) through
// the bounding volume hierarchy: bvh_traversal.glsl.

layout(std430, binding = SPHERES_BINDING) readonly buffer Spheres { Sphere spheres[]; };
layout(std430, binding = QUADS_BINDING) readonly buffer Quads { Quad quads[]; };
layout(std430, binding = TRIANGLES_BINDING) readonly buffer Triangles {
    Triangle triangles[];
};
layout(std430, binding = POSITIONS_BINDING) readonly buffer Positions { vec4 positions[]; };
layout(std430, binding = NORMALS_BINDING) readonly buffer Normals { vec4 normals[]; };
layout(std430, binding = MATERIALS_BINDING) readonly buffer Materials {
    Material materials[];
};
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
    return hitTriangle(ray, cornersOf(triangles[index]), tMin, tMax, t, uv);
}
#include "bvh_traversal.glsl"

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

// --8<-- [start:nearest]
// The nearest surface along the ray, between tMin and tMax.
bool nearestHit(Ray ray, float tMin, float tMax, out Hit hit) {
    int kind = -1, index = 0;
    float t;
    vec2 barycentric, hitBarycentric, ab, hitAb;
    for (int i = 0; i < spheres.length(); ++i)
        if (hitSphere(ray, spheres[i], tMin, tMax, t)) {
            tMax = t; kind = SHAPE_SPHERE; index = i;
        }
    for (int i = 0; i < quads.length(); ++i)
        if (hitQuad(ray, quads[i], tMin, tMax, t, ab)) {
            tMax = t; kind = SHAPE_QUAD; index = i; hitAb = ab;
        }
    // The triangles: the tree finds the nearest one nearer than tMax (the nearest
    // sphere or quad so far), or brute force tries them all.
    if (bruteForce != 0u) {
        for (int i = 0; i < triangles.length(); ++i)
            if (hitTriangle(ray, uint(i), tMin, tMax, t, barycentric)) {
                tMax = t; kind = SHAPE_TRIANGLE; index = i; hitBarycentric = barycentric;
            }
        bvhLoopIterations += uint(triangles.length());  // for --view cost
    } else {
        uint triangle;
        if (bvhNearestHit(ray, tMin, tMax, triangle, t, barycentric)) {
            tMax = t; kind = SHAPE_TRIANGLE; index = int(triangle); hitBarycentric = barycentric;
        }
    }
    // Normals only for the one shape that was hit.
    if (kind == SHAPE_SPHERE) {
        Sphere s = spheres[index];
        hit = makeHit(ray, tMax, ray.origin + tMax * ray.direction - s.center, s.material,
                      s.emitter, vec2(0.0));  // no texture on spheres
    } else if (kind == SHAPE_QUAD) {
        Quad q = quads[index];
        hit = makeHit(ray, tMax, cross(q.edge1, q.edge2), q.material, q.emitter, hitAb);
    } else if (kind == SHAPE_TRIANGLE) {
        hit = triangleHit(ray, tMax, hitBarycentric, triangles[index]);
    }
    return kind >= 0;
}
// --8<-- [end:nearest]

// Is anything in the way between tMin and tMax? Any hit will do (a shadow ray).
bool anyHit(Ray ray, float tMin, float tMax) {
    float t;
    vec2 barycentric, ab;
    for (int i = 0; i < spheres.length(); ++i)
        if (hitSphere(ray, spheres[i], tMin, tMax, t)) return true;
    for (int i = 0; i < quads.length(); ++i)
        if (hitQuad(ray, quads[i], tMin, tMax, t, ab)) return true;
    if (bruteForce == 0u) return bvhAnyHit(ray, tMin, tMax);
    for (int i = 0; i < triangles.length(); ++i)
        if (hitTriangle(ray, uint(i), tMin, tMax, t, barycentric)) return true;
    return false;
}
