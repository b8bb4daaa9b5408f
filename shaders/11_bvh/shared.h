// Numbers and structs the C++ host and the GLSL shaders must agree on. Both sides read
// this one file: GLSL sees the structs as they are, C++ sees them in namespace gpu with
// glm's vector types. (C++ files include <glm/glm.hpp> and <cstddef> first: GLSL has no
// such headers; includes are looked for in this folder.)
#ifndef COURSE_SHARED_H
#define COURSE_SHARED_H

// The tree's node, as bvh.cpp writes it and the traversal reads it.
#include "bvh_layout.h"

#define PIXELS_BINDING 0     // the image: the running mean of the samples, linear RGB
#define SPHERES_BINDING 1    // the scene's spheres
#define TRIANGLES_BINDING 2  // its triangles, meshes included, corners stored in place
#define QUADS_BINDING 3      // its parallelograms (walls, lights)
#define RANDOM_BINDING 4     // each pixel's generator state: one uvec4, kept all along
#define MATERIALS_BINDING 5  // albedo and emission, picked by each shape's `material`
#define EMITTERS_BINDING 6   // the shapes that emit: what next-event estimation samples
#define RAY_COUNT_BINDING 7  // rays traced by each pixel so far, for the --json stats
#define BVH_NODES_BINDING 8  // the bounding volume hierarchy over the triangles
#define BOUNCE_START_BINDING 9  // --view bounce: each pixel's first hit, found once

// What the image shows (--view). Everything but the radiance uses one ray through each
// pixel's centre and no randomness, so that two runs can be compared pixel by pixel.
#define VIEW_RADIANCE 0  // the path tracer's estimate of the light (the default)
#define VIEW_NORMALS 1   // the normal of the surface hit, 0.5 + 0.5 n; black for no hit
#define VIEW_DISTANCE 2  // how far along the ray the hit is (PFM: metres); 0 for no hit
#define VIEW_COST 3      // traversal steps for the ray, as a heat map (bvh_traversal.glsl)
#define VIEW_BOUNCE 4    // random diffuse rays from the first hit: the share that travel
                         // over a quarter of the scene (ambient occlusion); a benchmark

// Which estimator of the light arriving at a surface (--estimator).
#define ESTIMATOR_NEE 0   // sample the lights only (next-event estimation)
#define ESTIMATOR_BSDF 1  // sample the BSDF only; light counts when a ray hits it
#define ESTIMATOR_MIS 2   // both, weighted by multiple importance sampling

// What kind of shape an emitter is.
#define SHAPE_SPHERE 0
#define SHAPE_QUAD 1
#define SHAPE_TRIANGLE 2
#define NO_EMITTER 0xFFFFFFFFu  // a shape's `emitter` when its material does not emit

// New rays start RAY_OFFSET * (1 + the hit's largest |coordinate|) off the surface,
// along its normal, so that float32 rounding does not make them find the surface they
// leave (chapter 05). Relative, like float32's precision: 0.2 mm in the 2 m Cornell box.
#define RAY_OFFSET 1e-4

// Russian roulette starts after this many bounces: the first few are cheap and carry
// most of the light, so every path makes them.
#define ROULETTE_AFTER 3

// 8x8 tiles of invocations: neighbouring rays run together (chapter 02).
#define TILE_SIZE 8

#ifdef __cplusplus
namespace gpu {
using uint = glm::uint;
using uvec4 = glm::uvec4;
using vec4 = glm::vec4;
#endif

// --8<-- [start:structs]
// Every struct is built from vec4s and uvec4s: std430 aligns a vec3 to 16 bytes, and
// glm::vec3 is 12 bytes, so a vec3 member would shift everything after it.
struct Sphere {
    vec4 centerRadius;  // xyz the centre, w the radius
    uvec4 info;         // x material, y emitter index or NO_EMITTER; z, w unused
};
struct Quad {           // corners origin, origin + edge1, origin + edge1 + edge2, ...
    vec4 origin;        // w unused
    vec4 edge1;
    vec4 edge2;         // the front is the side cross(edge1, edge2) points to
    uvec4 info;         // as Sphere::info
};
struct Triangle {       // the front is where the corners run counter-clockwise
    vec4 p0;            // w unused
    vec4 p1;
    vec4 p2;
    uvec4 info;         // as Sphere::info
};
struct Material {
    vec4 albedo;    // rgb: the reflected fraction of the light (Lambertian)
    vec4 emission;  // rgb: the radiance it gives out from its front; zero if none
};
struct Emitter {
    uint shape;   // SHAPE_SPHERE, SHAPE_QUAD or SHAPE_TRIANGLE
    uint index;   // into the spheres, quads or triangles
    float area;   // its surface area: uniform sampling has the density 1 / area
    float power;  // unused; room for picking bright lights more often
};
// --8<-- [end:structs]

#ifdef __cplusplus
static_assert(sizeof(Sphere) == 32 && offsetof(Sphere, info) == 16, "std430 Sphere");
static_assert(sizeof(Quad) == 64 && offsetof(Quad, info) == 48, "std430 Quad");
static_assert(sizeof(Triangle) == 64 && offsetof(Triangle, info) == 48, "std430 Triangle");
static_assert(sizeof(Material) == 32 && offsetof(Material, emission) == 16, "std430 Material");
static_assert(sizeof(Emitter) == 16 && offsetof(Emitter, area) == 8, "std430 Emitter");
}  // namespace gpu
#endif

#endif
