// The scene: a triangle mesh in storage buffers, positions, normals and indices, the
// search for the surface a ray sees, and the question whether anything is in the way.

layout(std430, binding = TRIANGLES_BINDING) readonly buffer Triangles {
    Triangle triangles[];
};
layout(std430, binding = POSITIONS_BINDING) readonly buffer Positions { vec4 positions[]; };
layout(std430, binding = NORMALS_BINDING) readonly buffer Normals { vec4 normals[]; };

// What a ray found.
struct Hit {
    float t;
    vec3 position;
    vec3 normal;           // unit, facing the ray: to shade with (smooth on a mesh)
    vec3 geometricNormal;  // unit, facing the ray: the triangle's own, flat
    vec3 albedo;           // the share of red, green and blue light it reflects
};

// The albedo of each material: the share of red, green and blue light it reflects.
const vec3 ALBEDO[2] = vec3[2](vec3(0.9, 0.55, 0.25),  // MATERIAL_MESH: terracotta
                               vec3(0.7, 0.7, 0.7));   // MATERIAL_FLOOR: light grey

// Chapter 08's triangles: hitTriangle, smoothNormal, triangleHit.
#include "triangle.glsl"

// --8<-- [start:nearest]
// The nearest surface along the ray, between tMin and tMax.
bool nearestHit(Ray ray, float tMin, float tMax, out Hit hit) {
    bool found = false;
    hit.t = tMax;  // only hits nearer than this count; it shrinks with each hit found
    for (int i = 0; i < triangles.length(); ++i) {
        float t;
        vec2 barycentric;
        if (hitTriangle(ray, cornersOf(triangles[i]), tMin, hit.t, t, barycentric)) {
            hit = triangleHit(ray, t, barycentric, triangles[i]);
            found = true;
        }
    }
    return found;
}
// --8<-- [end:nearest]

// --8<-- [start:any_hit]
// Is anything in the way between tMin and tMax? For a shadow ray any hit will do, so
// the search stops at the first one: what was a bug for camera rays is right here.
bool anyHit(Ray ray, float tMin, float tMax) {
    float t;
    vec2 barycentric;
    for (int i = 0; i < triangles.length(); ++i)
        if (hitTriangle(ray, cornersOf(triangles[i]), tMin, tMax, t, barycentric))
            return true;
    return false;
}
// --8<-- [end:any_hit]
