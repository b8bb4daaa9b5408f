#version 430
// Runs shaders/13_bvh/bvh_traversal.glsl on the GPU for a list of rays, so that
// tests/cpp/test_bvh_gpu.cpp can compare every answer with the C++ traversal. Loaded
// with the chapter's shader folder as the base, so the includes below resolve there.

// The interface bvh_traversal.glsl expects (see its top), with test bindings.
#define BVH_NODES_BINDING 0
#include "bvh_layout.h"

struct Ray {
    vec3 origin;
    vec3 direction;
};

layout(std430, binding = 1) readonly buffer Positions { vec4 positions[]; };  // xyz
layout(std430, binding = 2) readonly buffer Triangles { uvec4 triangles[]; };  // leaf order

// Moller-Trumbore, as in the chapters' triangle.glsl.
bool hitTriangle(Ray ray, uint triangleIndex, float tMin, float tMax, out float t,
                 out vec2 uv) {
    uvec4 corners = triangles[triangleIndex];
    vec3 p0 = positions[corners.x].xyz;
    vec3 edge1 = positions[corners.y].xyz - p0;
    vec3 edge2 = positions[corners.z].xyz - p0;
    vec3 p = cross(ray.direction, edge2);
    float determinant = dot(edge1, p);
    if (abs(determinant) < 1e-12) return false;
    float inverse = 1.0 / determinant;
    vec3 toOrigin = ray.origin - p0;
    float u = dot(toOrigin, p) * inverse;
    if (u < 0.0 || u > 1.0) return false;
    vec3 q = cross(toOrigin, edge1);
    float v = dot(ray.direction, q) * inverse;
    if (v < 0.0 || u + v > 1.0) return false;
    t = dot(edge2, q) * inverse;
    uv = vec2(u, v);
    return t > tMin && t < tMax;
}

#include "bvh_traversal.glsl"

struct RayQuery {
    vec4 origin;     // xyz
    vec4 direction;  // xyz
    vec4 limits;     // tMin, tMax of the nearest-hit query, tMax of the any-hit query
};
layout(std430, binding = 3) readonly buffer Queries { RayQuery queries[]; };

struct RayResult {
    uint found;         // bvhNearestHit's answer ...
    uint triangle;      // ... its triangle (leaf order) ...
    float t;            // ... distance ...
    uint anyFound;      // bvhAnyHit's answer
    vec2 uv;            // ... and (u, v)
    uint iterations;    // bvhLoopIterations of the nearest-hit query ...
    uint anyIterations; // ... and of the any-hit query
};
layout(std430, binding = 4) writeonly buffer Results { RayResult results[]; };

// Each invocation repeats its queries this often (1 normally): the llvmpipe budget test.
uniform uint repeats;
// How many repetitions really ran: llvmpipe's limit would end the loop early, silently.
layout(std430, binding = 5) writeonly buffer Completed { uint completed[]; };

layout(local_size_x = 64) in;
void main() {
    uint index = gl_GlobalInvocationID.x;
    if (index >= uint(queries.length())) return;
    RayQuery query = queries[index];
    Ray ray = Ray(query.origin.xyz, query.direction.xyz);

    RayResult result;
    uint done = 0u;
    for (uint r = 0u; r < repeats; ++r) {
        bvhLoopIterations = 0u;
        uint triangle;
        float t;
        vec2 uv;
        bool found = bvhNearestHit(ray, query.limits.x, query.limits.y, triangle, t, uv);
        result.found = uint(found);
        result.triangle = triangle;
        result.t = t;
        result.uv = uv;
        result.iterations = bvhLoopIterations;
        bvhLoopIterations = 0u;
        result.anyFound = uint(bvhAnyHit(ray, query.limits.x, query.limits.z));
        result.anyIterations = bvhLoopIterations;
        ++done;
    }
    results[index] = result;
    completed[index] = done;
}
