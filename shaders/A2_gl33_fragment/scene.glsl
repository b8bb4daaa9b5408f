// The scene: spheres, quads and triangles in a buffer texture, each with a material
// and, if it glows, its place in the emitter list (materials and emitters are in the
// uniform block of shared.h); the triangles' corners and normals in the same texture,
// as in chapter 09. Every ray tests every shape (chapter 13's BVH does better); the
// Cornell scenes have a few dozen shapes, the gems ~200.

// --8<-- [start:fetch]
// GL 3.3 shaders cannot read storage buffers, but they can read a buffer as a texture:
// texelFetch(primitives, i) is the i-th RGBA32F texel, any i, no filtering.
uniform samplerBuffer primitives;

// The shapes as chapter 12's shaders see them, built here from their texels.
struct Sphere {
    vec3 center;
    float radius;
    uint material;
    uint emitter;  // index into the emitter list, or NO_EMITTER
};
struct Quad {
    vec3 origin;
    vec3 edge1;
    vec3 edge2;
    uint material;
    uint emitter;
};
struct Triangle {  // chapter 12's: the front is where the corners run counter-clockwise
    uvec3 corners;        // indices into the positions
    uint material;
    uvec3 cornerNormals;  // indices into the normals, in the corners' order
    uint emitter;
};

vec4 texel(uint index) { return texelFetch(primitives, int(index)); }

// Indices are stored as floats (shared.h): a sphere's or quad's last texel holds the
// material and the emitter, -1 when the shape does not glow.
uint materialOf(vec4 indices) { return uint(indices.x); }
uint emitterOf(float index) { return index < 0.0 ? NO_EMITTER : uint(index); }

Sphere sphereAt(uint i) {
    uint first = firstSphereTexel + i * uint(SPHERE_TEXELS);
    vec4 centerRadius = texel(first), indices = texel(first + 1u);
    return Sphere(centerRadius.xyz, centerRadius.w, materialOf(indices),
                  emitterOf(indices.y));
}
Quad quadAt(uint i) {
    // BEGIN SOLUTION quad i's four texels: origin, edge1, edge2, then its indices
    uint first = firstQuadTexel + i * uint(QUAD_TEXELS);
    vec3 origin = texel(first).xyz, edge1 = texel(first + 1u).xyz;
    vec3 edge2 = texel(first + 2u).xyz;
    vec4 indices = texel(first + 3u);
    return Quad(origin, edge1, edge2, materialOf(indices), emitterOf(indices.y));
    // STUB: return Quad(vec3(0.0), vec3(0.0), vec3(0.0), 0u, NO_EMITTER);
    // END SOLUTION
}
Triangle triangleAt(uint i) {
    // BEGIN SOLUTION triangle i's texels: corners and material, then normals and emitter
    uint first = firstTriangleTexel + i * uint(TRIANGLE_TEXELS);
    vec4 corners = texel(first), normals = texel(first + 1u);
    return Triangle(uvec3(corners.xyz), uint(corners.w), uvec3(normals.xyz),
                    emitterOf(normals.w));
    // STUB: return Triangle(uvec3(0u), 0u, uvec3(0u), NO_EMITTER);
    // END SOLUTION
}
// Chapter 12's positions[i] and normals[i]: the triangles' corners and their normals.
vec4 positionAt(uint i) { return texel(firstPositionTexel + i); }
vec4 normalAt(uint i) { return texel(firstNormalTexel + i); }
// --8<-- [end:fetch]

// What a ray found.
struct Hit {
    float t;
    vec3 position;
    vec3 normal;           // unit, on the front side: to shade with (smooth on a mesh)
    vec3 geometricNormal;  // unit, on the front side: the surface's own, flat
    bool front;            // did the ray arrive at the front of the surface itself?
    uint material;
    uint emitter;          // index into the emitter list, or NO_EMITTER
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

// Where the ray meets the quad's plane, if the point is inside the parallelogram.
bool hitQuad(Ray ray, Quad quad, float tMin, float tMax, out float t) {
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
    return a >= 0.0 && a <= 1.0 && b >= 0.0 && b <= 1.0;
}

// Chapter 09's triangles: hitTriangle, smoothNormal, triangleHit.
#include "triangle.glsl"

// Fills in a hit on a sphere or a quad from its front normal, material and emitter:
// the same normal to shade with and to tell the sides apart.
Hit makeHit(Ray ray, float t, vec3 frontNormal, uint material, uint emitter) {
    vec3 normal = normalize(frontNormal);
    return Hit(t, ray.origin + t * ray.direction, normal, normal,
               dot(normal, ray.direction) < 0.0, material, emitter);
}

// --8<-- [start:nearest]
// The nearest surface along the ray, between tMin and tMax.
bool nearestHit(Ray ray, float tMin, float tMax, out Hit hit) {
    int kind = -1;
    uint index = 0u;
    float t;
    vec2 barycentric, hitBarycentric;
    for (uint i = 0u; i < sphereCount; ++i)
        if (hitSphere(ray, sphereAt(i), tMin, tMax, t)) {
            tMax = t; kind = SHAPE_SPHERE; index = i;
        }
    for (uint i = 0u; i < quadCount; ++i)
        if (hitQuad(ray, quadAt(i), tMin, tMax, t)) {
            tMax = t; kind = SHAPE_QUAD; index = i;
        }
    for (uint i = 0u; i < triangleCount; ++i)
        if (hitTriangle(ray, cornersOf(triangleAt(i)), tMin, tMax, t, barycentric)) {
            tMax = t; kind = SHAPE_TRIANGLE; index = i; hitBarycentric = barycentric;
        }
    // Normals only for the one shape that was hit.
    if (kind == SHAPE_SPHERE) {
        Sphere s = sphereAt(index);
        hit = makeHit(ray, tMax, ray.origin + tMax * ray.direction - s.center, s.material,
                      s.emitter);
    } else if (kind == SHAPE_QUAD) {
        Quad q = quadAt(index);
        hit = makeHit(ray, tMax, cross(q.edge1, q.edge2), q.material, q.emitter);
    } else if (kind == SHAPE_TRIANGLE) {
        hit = triangleHit(ray, tMax, hitBarycentric, triangleAt(index));
    }
    return kind >= 0;
}
// --8<-- [end:nearest]

// Is anything in the way between tMin and tMax? Any hit will do (a shadow ray).
bool anyHit(Ray ray, float tMin, float tMax) {
    float t;
    vec2 barycentric;
    for (uint i = 0u; i < sphereCount; ++i)
        if (hitSphere(ray, sphereAt(i), tMin, tMax, t)) return true;
    for (uint i = 0u; i < quadCount; ++i)
        if (hitQuad(ray, quadAt(i), tMin, tMax, t)) return true;
    for (uint i = 0u; i < triangleCount; ++i)
        if (hitTriangle(ray, cornersOf(triangleAt(i)), tMin, tMax, t, barycentric)) return true;
    return false;
}
